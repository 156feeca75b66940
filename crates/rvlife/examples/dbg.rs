fn main() {
    let mut model = rvlife::config::Config::example().validate().unwrap();
    model.stage_hours = vec![1250.0];
    let h = rvlife::wear::integrate(&model, &|_, _| {}).unwrap();
    let map = rvlife::geometry::WearMap::new(h.maps[0].clone()).unwrap();
    let prof = model.profile(Some(map)).unwrap();
    let mut v = vec![];
    for k in 0..18 {
        let phi = std::f64::consts::TAU * k as f64 / 720.0;
        let sol = rvlife::contact::solve(&prof, &model.contact, phi, 226.6).unwrap();
        for p in &sol.pins { let d = p.mesh_angle.to_degrees(); if d > 55.0 && d < 65.0 { v.push((d, p.force, p.half_width*1e6, p.gap*1e6, k)); } }
    }
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    for x in v { println!("{:.3} F {:.1} b {:.1} gap {:.3} k {}", x.0, x.1, x.2, x.3, x.4); }
}
