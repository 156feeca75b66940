fn main() {
    let model = rvlife::config::Config::example().validate().unwrap();
    let t0 = std::time::Instant::now();
    let h = rvlife::wear::integrate(&model, &|_, _| {}).unwrap();
    println!("integrate {:?} evals {}", t0.elapsed(), h.rate_evaluations);
    for (i, map) in h.maps.iter().enumerate() {
        let prof = model.profile(if i == 0 { None } else { Some(rvlife::geometry::WearMap::new(map.clone()).unwrap()) }).unwrap();
        let t0 = std::time::Instant::now();
        let _ = rvlife::study::analyse_profile(&model, &prof, 0.0).unwrap();
        let t1 = t0.elapsed();
        let t0 = std::time::Instant::now();
        for k in 0..18 { let phi = std::f64::consts::TAU * k as f64 / 720.0; rvlife::contact::solve(&prof, &model.contact, phi, 226.6).unwrap(); }
        println!("stage {i}: analyse {:?}, solve {:?} dents {}", t1, t0.elapsed() / 18, prof.dent_zones().len());
    }
}
