fn main() {
    let mut model = rvlife::config::Config::example().validate().unwrap();
    model.stage_hours = vec![2500.0];
    let h = rvlife::wear::integrate(&model, &|_, _| {}).unwrap();
    let map = rvlife::geometry::WearMap::new(h.maps[0].clone()).unwrap();
    for (name, prof) in [("worn", model.profile(Some(map.clone())).unwrap()), ("unworn", model.profile(None).unwrap()), ("uniform", model.profile(Some(rvlife::geometry::WearMap::uniform(720, 10e-6).unwrap())).unwrap())] {
        let t0 = std::time::Instant::now();
        for k in 0..180 { let phi = std::f64::consts::TAU * k as f64 / 7200.0; rvlife::contact::pin_geometries(&prof, phi, 0.0).unwrap(); }
        let tp = t0.elapsed() / 7200;
        let t0 = std::time::Instant::now();
        for k in 0..18 { let phi = std::f64::consts::TAU * k as f64 / 720.0; rvlife::contact::solve(&prof, &model.contact, phi, 226.6).unwrap(); }
        println!("dents {:?}", prof.dent_zones().iter().map(|d| (d.0.to_degrees(), d.1.to_degrees())).collect::<Vec<_>>());
        println!("{name}: projection {:?}, solve {:?}", tp, t0.elapsed() / 18);
    }
}
#[allow(dead_code)]
fn x() {}
