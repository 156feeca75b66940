fn main() {
    let mut model = rvlife::config::Config::example().validate().unwrap();
    let prof = model.profile(None).unwrap();
    let w0 = rvlife::wear::wear_per_mesh_cycle(&prof, &model, 412.0).unwrap();
    model.stage_hours = vec![500.0];
    let h = rvlife::wear::integrate(&model, &|_, _| {}).unwrap();
    let map = rvlife::geometry::WearMap::new(h.maps[0].clone()).unwrap();
    let prof1 = model.profile(Some(map)).unwrap();
    let w1 = rvlife::wear::wear_per_mesh_cycle(&prof1, &model, 412.0).unwrap();
    for m in (60..140).step_by(2) { println!("{:.1} {:.4e} {:.4e} h {:.3}", m as f64*0.5, w0[m], w1[m], h.maps[0][m]*1e6); }
}
