use rvlife::contact::*;
use rvlife::geometry::*;
fn main() {
    let g = CycloidGeometry { pins: 40, eccentricity: 1.3e-3, pin_circle_radius: 64e-3, pin_radius: 3e-3, width: 8.75e-3 };
    let prof = Profile::new(g.clone(), Modification::default(), None).unwrap();
    let phi = 0.3;
    let mut w = vec![];
    let gs = pin_geometries(&prof, phi, 0.0).unwrap();
    let k1 = g.k1();
    for pg in gs.iter().take(40) {
        let t = std::f64::consts::TAU * pg.pin as f64 / 40.0 - phi;
        let li = g.disc_pitch_radius() * t.sin() / (1.0 + k1 * k1 - 2.0 * k1 * t.cos()).sqrt();
        println!("{} gap {:.3e} lever {:.6e} li {:.6e} mesh {:.3} curv {:.2}", pg.pin, pg.gap, pg.lever_arm, li, mesh_angle(pg.t).to_degrees(), pg.curvature);
    }
    let m = ContactModel { law: ApproachLaw::Paper, materials: Materials { disc_youngs_modulus: 219e9, disc_poisson_ratio: 0.3, pin_youngs_modulus: 219e9, pin_poisson_ratio: 0.3 }, width: 8.75e-3, pin_radius: 3e-3, max_radius: 64e-3 };
    let t0 = std::time::Instant::now();
    let sol = solve(&prof, &m, 0.0, 0.55 * 412.0).unwrap();
    println!("solve {:?}", t0.elapsed());
    println!("beta {:.4} arcmin maxF {:.1} pins {} pmax {:.1} MPa moment {}", sol.disc_rotation.to_degrees()*60.0, sol.max_force(), sol.pins_in_contact(), sol.max_pressure()/1e6, sol.pin_moment());
    let prof2 = Profile::new(g.clone(), Modification { equidistant: 10e-6, ..Default::default() }, None).unwrap();
    let b = first_contact(&prof2, 0.0, 1.0).unwrap();
    let b2 = first_contact(&prof2, 0.0, -1.0).unwrap();
    println!("eq 10um: +{:.5} -{:.5} arcmin expected {:.5}", b.to_degrees()*60.0, b2.to_degrees()*60.0, (10e-6/(1.3e-3*39.0) as f64).to_degrees()*60.0);
    let t0 = std::time::Instant::now();
    let sol = solve(&prof2, &m, 0.0, 0.55 * 412.0).unwrap();
    println!("solve {:?}", t0.elapsed());
    println!("beta {:.4} arcmin maxF {:.1} pins {} pmax {:.1} MPa moment {}", sol.disc_rotation.to_degrees()*60.0, sol.max_force(), sol.pins_in_contact(), sol.max_pressure()/1e6, sol.pin_moment());
    for p in &sol.pins { if p.force > 0.0 { print!("{}:{:.0} ", p.pin, p.force); } }
    println!();
}
