//! Li Lixing's closed-form load distribution of an unmodified rigid disc with linear springs
//! (docs/model.md section 5; paper eqs 5, 9, 10): the forces of the paper's wear model.

use crate::geometry::CycloidGeometry;

/// Li Lixing's closed-form load distribution (docs/model.md section 5, paper eqs 5, 9, 10) for
/// an unmodified rigid disc with linear springs: `l_j = a Zc sin(t_j) / S(t_j)` with mesh angle
/// `t_j = 2 pi j / Zp - phi`, `F_j = T_disc l_j / sum l^2` over the pins with `l_j > 0`.
/// Returns `Zp` forces, N (zero on the unloaded flank); negative torques load the other flank.
pub(crate) fn li_load_distribution(geo: &CycloidGeometry, phi: f64, disc_torque: f64) -> Vec<f64> {
    let zp = geo.pins as f64;
    let k1 = geo.k1();
    let s = disc_torque.signum();
    let levers: Vec<f64> = (0..geo.pins)
        .map(|j| {
            let t = std::f64::consts::TAU * j as f64 / zp - phi;
            let sq = (1.0 + k1 * k1 - 2.0 * k1 * t.cos()).sqrt();
            geo.disc_pitch_radius() * t.sin() / sq
        })
        .collect();
    let sum2: f64 = levers.iter().filter(|l| s * **l > 0.0).map(|l| l * l).sum();
    levers
        .iter()
        .map(|l| {
            if s * l > 0.0 {
                disc_torque * l / sum2
            } else {
                0.0
            }
        })
        .collect()
}
