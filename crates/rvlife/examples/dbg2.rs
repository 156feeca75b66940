fn main() {
    let mut model = rvlife::config::Config::example().validate().unwrap();
    model.stage_hours = vec![7500.0];
    let h = rvlife::wear::integrate(&model, &|_, _| {}).unwrap();
    let prof = model.profile(Some(rvlife::geometry::WearMap::new(h.maps[0].clone()).unwrap())).unwrap();
    std::env::set_var("RVD", "1");
    rvlife::contact::solve(&prof, &model.contact, 0.01, 226.6).unwrap();
}
