fn main() {
    let model = rvlife::config::Config::example().validate().unwrap();
    let prof = model.profile(None).unwrap();
    for b in [0.0, 1e-5, 2e-5, 4e-5, -2e-5] {
        let g = rvlife::contact::pin_geometry(&prof, 0, 0.0, b).unwrap();
        let g1 = rvlife::contact::pin_geometry(&prof, 1, 0.0, b).unwrap();
        println!(
            "beta {b:e}: pin0 gap {:e} t {:e} l {:e} | pin1 gap {:e}",
            g.gap, g.t, g.lever_arm, g1.gap
        );
    }
}
