fn main() {
    let mut model = rvlife::config::Config::example().validate().unwrap();
    model.stage_hours = vec![2500.0];
    let h = rvlife::wear::integrate(&model, &|_, _| {}).unwrap();
    let m = &h.maps[0];
    for i in 60..90 { println!("{:.1} h {:.2} nm  d2 {:.2} nm", i as f64*0.5, m[i]*1e9, (m[i+1]-2.0*m[i]+m[i-1])*1e9); }
}
