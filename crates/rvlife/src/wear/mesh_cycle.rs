//! Wear of one mesh cycle of the default model (docs/model.md sections 7.2, 7.11 and 7.12):
//! the disc's depth per pass from the static solutions over the cycle, the pins' (and, for pins
//! that turn, their grooves') wear map, and the Hertz band spreading of both.

use std::f64::consts::TAU;

use rayon::prelude::*;

use super::{resample_periodic, WearInputs};
use crate::contact::gap::GapField;
use crate::contact::pin_turning::{self, PinTurning};
use crate::error::Result;
#[cfg(test)]
use crate::geometry::WearMap;
use crate::geometry::{band_shape, rotate, Profile, Vec2};
use crate::reducer::{contact_direction, PIN_MAP_POINTS};
use crate::statics::{DiscLoad, StaticAnalysis, StaticSolution};

/// Mesh cycles of the output revolution whose wear is averaged for a reducer with part errors
/// or a single-stage drive (spread evenly over the revolution; the nominal RV reducer needs
/// one).
pub(crate) const REVOLUTION_POSITIONS: usize = 8;

/// The mesh cycles a wear rate of `reducer` is averaged over: [`REVOLUTION_POSITIONS`] with
/// part errors or for a single-stage drive (every mesh cycle differs), 1 otherwise.
pub(crate) fn revolution_positions(reducer: &crate::reducer::Reducer) -> usize {
    let differs =
        !reducer.errors.is_zero() || matches!(reducer.drive, crate::reducer::Drive::SingleStage(_));
    if differs {
        REVOLUTION_POSITIONS
    } else {
        1
    }
}

/// Every pin contact's kinematics of `disc` per unit crank angle (ground frame, pins at rest):
/// `(w, v_d)`, the disc material's speed along the pin's counter-clockwise tangent, `w = v . t`
/// with `v = dO/dphi + dpsi/dphi x (x - O)`, `dpsi/dphi = -1/Zc`, and the contact's speed along
/// the flank `v_d` (docs/model.md section 7.2); `(0, 0)` for an unloaded pin. One entry per
/// pin.
pub(crate) fn contact_kinematics(profile: &Profile, disc: &DiscLoad) -> Vec<(f64, f64)> {
    let zc = profile.geometry().disc_teeth() as f64;
    let (centre, psi) = (disc.pose.centre, disc.pose.angle);
    disc.pins
        .iter()
        .map(|p| {
            if p.force <= 0.0 {
                return (0.0, 0.0);
            }
            let pt = profile.point(p.profile_parameter);
            let r = rotate(&pt.p, psi);
            let v = Vec2::new(-centre.y, centre.x) + Vec2::new(-r.y, r.x) * (-1.0 / zc);
            let tangent = rotate(&(pt.dp / pt.dp.norm()), psi);
            // The pin's outward direction at the contact is minus the flank's outward normal;
            // its counter-clockwise tangent is that turned a quarter turn, along the flank's
            // tangent one way or the other.
            let n = -rotate(&p.normal, psi);
            let sense = tangent.dot(&Vec2::new(-n.y, n.x)).signum();
            (v.dot(&tangent) * sense, pt.dp.norm())
        })
        .collect()
}

/// The entrainment (mean rolling) speed of a fixed pin's contact per unit crank angle, m/rad:
/// half the sum of the two surfaces' speeds relative to the contact point, the disc's `v_d`
/// along its flank and the pin's `r_p |d beta/d phi|` round the pin
/// ([`contact_direction`]), whose difference is the sliding speed `|w|`; along the common
/// tangent, `|u_1 + u_2| = sqrt(2 u_1^2 + 2 u_2^2 - (u_1 - u_2)^2)` (docs/model.md section
/// 18.2). `crank` the disc's crank angle, rad.
pub(crate) fn entrainment_speed(
    geo: &crate::geometry::CycloidGeometry,
    pin: usize,
    crank: f64,
    w: f64,
    v_disc: f64,
) -> f64 {
    let u_pin = geo.pin_radius * contact_direction(geo, pin, crank).1.abs();
    0.5 * (2.0 * v_disc * v_disc + 2.0 * u_pin * u_pin - w * w)
        .max(0.0)
        .sqrt()
}

/// Wear of one mesh cycle ([`wear_per_mesh_cycle`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MeshCycleWear {
    /// Disc: depth per mesh cycle (one sweep of every tooth point), m, on the wear-map grid.
    pub disc: Vec<f64>,
    /// Pins: depth per sweep of the pin (one revolution of the eccentric), m, on the pin map's
    /// grid ([`PIN_MAP_POINTS`] around the pin); empty when the pins do not wear.
    pub pin: Vec<f64>,
    /// Archard's sliding integral of the cycle, `sum F |v_s| dphi` over the contacts, N m
    /// (the mean over the positions and discs averaged, like the depths).
    pub sliding: f64,
}

/// Wear of one mesh cycle for the output torque `torque` (N m), on the actual profile
/// `profile` (default model, see the module docs), for the disc and, when they wear, the pins
/// (docs/model.md section 7.11).
///
/// # Errors
/// Propagates contact-solver failures.
#[cfg(test)]
pub(crate) fn wear_per_mesh_cycle(
    profile: &Profile,
    inputs: &WearInputs,
    torque: f64,
) -> Result<MeshCycleWear> {
    Ok(wear_per_mesh_cycle_from(profile, inputs, torque, 0.0, None, None)?.0)
}

/// [`wear_per_mesh_cycle`] with each static solve started from `warm`, the solutions of the
/// cycle's crank angles on a slightly less worn profile (the previous evaluation of a wear
/// integration: the disc moves by the wear step between them, far less than between
/// neighbouring crank angles), every crank angle then solved on its own; without them (or
/// with another count of them) each run of consecutive crank angles is solved in order, each
/// solve from its predecessor ([`StaticAnalysis::solve_sequence`]). Returns the wear and the
/// solutions (position-major, crank angle within), the next evaluation's `warm`. `field`: the
/// contact geometry of `profile` when already built (else built here, as
/// [`StaticAnalysis::new`] builds it).
///
/// # Errors
/// Propagates contact-solver failures.
pub(crate) fn wear_per_mesh_cycle_from(
    profile: &Profile,
    inputs: &WearInputs,
    torque: f64,
    speed_rpm: f64,
    warm: Option<&[StaticSolution]>,
    field: Option<&GapField>,
) -> Result<(MeshCycleWear, Vec<StaticSolution>)> {
    let n = inputs.grid_points();
    let pins_wear = inputs.wear.pin_archard > 0.0;
    let n_pin = if pins_wear { PIN_MAP_POINTS } else { 0 };
    if torque == 0.0 {
        let none = MeshCycleWear {
            disc: vec![0.0; n],
            pin: vec![0.0; n_pin],
            sliding: 0.0,
        };
        return Ok((none, Vec::new()));
    }
    let geo = profile.geometry();
    let zp = geo.pins as f64;
    let zc = geo.disc_teeth() as f64;
    let steps = inputs.wear.crank_steps;
    let dphi = TAU / (zp * steps as f64);
    let slide_scale = 1.0 - inputs.wear.pin_rolling_fraction;
    let sa = match field {
        Some(f) => StaticAnalysis::with_field(inputs.reducer, profile, f.clone()),
        None => StaticAnalysis::new(inputs.reducer, profile)?,
    };
    let phis: Vec<f64> = (0..steps)
        .map(|k| TAU * k as f64 / (zp * steps as f64))
        .collect();
    // The nominal reducer repeats every mesh cycle and its discs wear alike (disc 2 meets the
    // same crank angles half a crank revolution later): disc 1 over one mesh cycle. With part
    // errors every mesh cycle differs while every tooth meets every pin: the mean over
    // `REVOLUTION_POSITIONS` mesh cycles spread over the output revolution, and over the discs.
    // A single-stage drive repeats only where the output pins' pattern does (and its discs
    // may be unevenly phased): it is averaged like a reducer with errors.
    let positions = revolution_positions(inputs.reducer);
    let errors = positions > 1;
    let cycles = (zp * zc) as usize;
    let at: Vec<Vec<f64>> = (0..positions)
        .map(|r| {
            let c = (r * cycles / positions) as f64;
            phis.iter().map(|p| p + c * TAU / zp).collect()
        })
        .collect();
    let solutions = match warm.filter(|w| w.len() == positions * steps) {
        Some(warm) => at
            .concat()
            .par_iter()
            .zip(warm)
            .map(|(&phi, near)| {
                let psi0 = sa.first_contact(phi, torque)?;
                sa.solve_near(phi, torque, psi0, Some(near))
            })
            .collect::<Result<Vec<_>>>()?,
        None => {
            let mut solutions = Vec::with_capacity(positions * steps);
            for at in &at {
                solutions.extend(sa.solve_sequence(at, torque)?);
            }
            solutions
        }
    };
    let discs = if errors { solutions[0].discs.len() } else { 1 };
    let weight = 1.0 / (positions * discs) as f64;
    let balance = match inputs.wear.pin_turning {
        PinTurning::Fixed => None,
        PinTurning::Balance {
            pin_friction,
            groove_friction,
        } => Some((pin_friction, groove_friction)),
    };
    let contact_modulus = inputs.reducer.contact.materials.contact_modulus();
    // The wear coefficient's factor from the contact's film (docs/model.md section 18.6): the
    // crank speed in the pins' frame, `Zc` times the output's, sets the entrainment.
    let lub = &inputs.lubrication;
    let crank_speed = speed_rpm.abs() * TAU / 60.0 / inputs.reducer.ratio.abs() * zc;
    let film_factor = |p: &crate::statics::PinLoad, crank: f64, w: f64, v_disc: f64| -> f64 {
        if !lub.wear_follows_film() {
            return 1.0;
        }
        let u = entrainment_speed(geo, p.pin, crank, w, v_disc) * crank_speed;
        let (_, lambda) = lub.contact_film(p.half_width, p.max_pressure, contact_modulus, u);
        lub.wear_factor(lambda)
    };
    // Per solution and disc: the disc's samples (mesh angle, depth, half-width, sliding
    // integral F |v_s| dphi) and the pins' (section 7.11; with turning pins, 7.12).
    let per_step: Vec<Vec<(Vec<DiscSample>, Vec<PinSample>)>> = solutions
        .par_iter()
        .map(|sol| {
            // Every loaded contact's kinematics per unit crank angle, once
            // ([`contact_kinematics`]): for the discs whose wear is sampled, and with turning
            // pins for every disc (a pin's balance takes them all).
            let kinematic_discs = if balance.is_some() {
                sol.discs.len()
            } else {
                discs
            };
            let kinematics: Vec<Vec<(f64, f64)>> = sol.discs[..kinematic_discs]
                .iter()
                .map(|disc| contact_kinematics(profile, disc))
                .collect();
            // Each pin's balance over the contacts of every disc (a pin is one body).
            let turning: Vec<Option<pin_turning::PinBalance>> = match balance {
                None => vec![None; geo.pins],
                Some((mu_d, mu_g)) => (0..geo.pins)
                    .map(|j| {
                        let contacts: Vec<pin_turning::PinContact> = sol
                            .discs
                            .iter()
                            .zip(&kinematics)
                            .filter(|(d, _)| d.pins[j].force > 0.0)
                            .map(|(d, k)| pin_turning::PinContact {
                                force: d.pins[j].force,
                                surface_speed: k[j].0,
                            })
                            .collect();
                        Some(pin_turning::balance(&contacts, mu_d, mu_g))
                    })
                    .collect(),
            };
            (0..discs)
                .map(|d| {
                    let disc = &sol.discs[d];
                    let mut disc_out = Vec::with_capacity(disc.pins.len());
                    let mut pin_out = Vec::new();
                    for p in &disc.pins {
                        if p.force <= 0.0 {
                            disc_out.push((p.mesh_angle, 0.0, 0.0, 0.0));
                            continue;
                        }
                        let (w, v_disc) = kinematics[d][p.pin];
                        // The sliding speed that wears the contact, per unit crank angle, and
                        // the pin's surface speed (0: it stands still).
                        let (v_slide, u) = match &turning[p.pin] {
                            None => ((w * slide_scale).abs(), 0.0),
                            Some(b) => {
                                // This contact's place among the pin's contacts (discs in
                                // order, loaded ones only).
                                let k = sol.discs[..d]
                                    .iter()
                                    .filter(|x| x.pins[p.pin].force > 0.0)
                                    .count();
                                let u = b.surface_speed;
                                let slide = match (balance, b.rolling_traction[k]) {
                                    (Some((mu_d, _)), Some(f)) => pin_turning::micro_slip_speed(
                                        f,
                                        p.force,
                                        mu_d,
                                        p.max_pressure,
                                        contact_modulus,
                                        v_disc,
                                    ),
                                    _ => (w - u).abs(),
                                };
                                (slide, u)
                            }
                        };
                        // The film's share of the load wears nothing (docs/model.md section
                        // 18.3; 1 with constant coefficients).
                        let film = film_factor(p, disc.pose.crank_angle, w, v_disc);
                        let dh = film * weight * inputs.wear.archard * p.force * v_slide
                            / (geo.width * v_disc);
                        let sliding = weight * p.force * v_slide * dphi;
                        disc_out.push((p.mesh_angle, dh, p.half_width, sliding));
                        if !pins_wear {
                            continue;
                        }
                        // Where on the pin and how fast the contact moves round it: the pitch
                        // point's kinematics (the coordinate the static analysis reads the map
                        // at).
                        let (beta, dbeta) = contact_direction(geo, p.pin, disc.pose.crank_angle);
                        let turns = u != 0.0 || slide_scale < 1.0;
                        pin_out.push(PinSample {
                            beta,
                            dbeta,
                            sliding: film * sliding,
                            half_width: p.half_width,
                            even: turns,
                        });
                        if u != 0.0 {
                            // The turning pin slides in its groove under this disc's load: the
                            // groove wears where the load presses (opposite the contact, so
                            // its depth opens this contact's gap as the pin's own wear would,
                            // read at the same angle) and the pin all round.
                            let groove = film * weight * p.force * u.abs() * dphi;
                            for even in [false, true] {
                                pin_out.push(PinSample {
                                    beta,
                                    dbeta,
                                    sliding: groove,
                                    half_width: p.half_width,
                                    even,
                                });
                            }
                        }
                    }
                    (disc_out, pin_out)
                })
                .collect()
        })
        .collect();
    // Flattened position-major, then disc, as the solutions.
    let per_step: Vec<(Vec<DiscSample>, Vec<PinSample>)> = per_step.into_iter().flatten().collect();
    // Each (position, disc) is resampled on the grid on its own and the grids summed (their
    // weights make the mean).
    let group = steps;
    let mut depth = vec![0.0; n];
    let mut half_width = vec![0.0; n];
    let groups = positions * discs;
    for g in 0..groups {
        // Rows of one position and disc: steps solutions (position-major), disc `g % discs`.
        let rows: Vec<&Vec<DiscSample>> = (0..group)
            .map(|k| &per_step[((g / discs) * group + k) * discs + g % discs].0)
            .collect();
        let samples: Vec<&DiscSample> = rows.into_iter().flatten().collect();
        let d = resample_periodic(samples.iter().map(|s| (s.0, s.1)).collect(), n);
        let h = resample_periodic(samples.iter().map(|s| (s.0, s.2)).collect(), n);
        for m in 0..n {
            depth[m] += d[m];
            half_width[m] += h[m] / groups as f64;
        }
    }
    let sliding: f64 = per_step.iter().flat_map(|s| &s.0).map(|s| s.3).sum();
    let pin = if pins_wear {
        pin_deposit(
            per_step.iter().flat_map(|s| &s.1),
            geo.pin_radius,
            inputs.wear.pin_archard / geo.width,
            dphi,
        )
    } else {
        Vec::new()
    };
    let wear = MeshCycleWear {
        disc: spread_over_band(profile, &depth, &half_width),
        pin,
        sliding,
    };
    Ok((wear, solutions))
}

/// One pass of a contact over the pin (or, for a turning pin, of the pin in its groove) for
/// [`pin_deposit`].
#[derive(Debug, Clone, Copy)]
struct PinSample {
    /// Angle of the contact round the pin from its inward radial direction, rad.
    beta: f64,
    /// `d beta / d phi` (per unit crank angle).
    dbeta: f64,
    /// Archard's sliding integral `F |v_s| dphi` of the step, N m.
    sliding: f64,
    /// Hertz half-width, m.
    half_width: f64,
    /// The area goes all round the pin (a pin that turns) rather than where the contact is.
    even: bool,
}

/// A disc sample of one contact: mesh angle (rad), depth (m), Hertz half-width (m), Archard's
/// sliding integral `F |v_s| dphi` (N m).
type DiscSample = (f64, f64, f64, f64);

/// The pins' wear of one sweep (docs/model.md sections 7.11 and 7.12), m on
/// [`PIN_MAP_POINTS`] around the pin, from the contacts of one mesh cycle (every pin's,
/// together the whole path of one pin over a revolution of the eccentric). Each contact
/// removes the area `k/B F |v_s| dphi` (`k_per_width` = `k/B`, 1/Pa/m) from the arc `r dbeta`
/// its contact point sweeps during its crank step `dphi` (uniformly: Archard's depth
/// `k F |v_s|/(B v_p)` with `v_p = r |d beta/d phi|`), and the result is spread over the Hertz
/// band (`+-b/r` around the pin, semi-elliptic, area conserving); the area of a sample marked
/// `even` (a pin that turns) is spread over the whole circumference.
fn pin_deposit<'s>(
    contacts: impl Iterator<Item = &'s PinSample>,
    pin_radius: f64,
    k_per_width: f64,
    dphi: f64,
) -> Vec<f64> {
    let n = PIN_MAP_POINTS;
    let cell = TAU / n as f64;
    let mut depth = vec![0.0; n];
    let mut even = 0.0;
    let (mut band, mut total) = (0.0, 0.0);
    for s in contacts {
        let PinSample {
            beta,
            dbeta,
            sliding,
            half_width: b,
            even: spread,
        } = *s;
        if sliding <= 0.0 {
            continue;
        }
        let area = k_per_width * sliding;
        if spread {
            even += area / (TAU * pin_radius);
            continue;
        }
        band += area * b;
        total += area;
        // The arc swept during the step, in cells; at least one cell wide (where the contact
        // stands still on the pin the band spreads it).
        let half = (dbeta.abs() * dphi / 2.0).max(cell / 2.0);
        let (lo, hi) = ((beta - half) / cell, (beta + half) / cell);
        let per_cell = area / (pin_radius * (hi - lo) * cell);
        let mut x = lo;
        while x < hi {
            let k = x.floor();
            let next = (k + 1.0).min(hi);
            depth[(k as i64).rem_euclid(n as i64) as usize] += per_cell * (next - x);
            x = next;
        }
    }
    if total <= 0.0 {
        return depth.into_iter().map(|d| d + even).collect();
    }
    // The Hertz band: semi-elliptic weights over +-b/r, periodic, normalised (area kept).
    let b = band / total / pin_radius;
    let reach = (b / cell).floor() as i64;
    let weights: Vec<f64> = (-reach..=reach)
        .map(|k| (1.0 - (k as f64 * cell / b).powi(2)).max(0.0).sqrt())
        .collect();
    let norm: f64 = weights.iter().sum();
    (0..n as i64)
        .map(|m| {
            (-reach..=reach)
                .zip(&weights)
                .map(|(k, w)| w * depth[(m + k).rem_euclid(n as i64) as usize])
                .sum::<f64>()
                / norm
                + even
        })
        .collect()
}

/// Spreads the wear of each contact position over its Hertz band: a pass deposits the wear of
/// its centre position over `+-b` of arc length with the semi-elliptic weight of the Hertz
/// pressure, conserving the worn area. Features narrower than the contact band cannot be worn
/// into the flank (Flodin and Andersson's point model integrated over the band).
fn spread_over_band(profile: &Profile, depth: &[f64], half_width: &[f64]) -> Vec<f64> {
    let n = depth.len();
    // Arc length per grid step at every node.
    let ds = profile.arc_steps(n);
    let mut out = vec![0.0; n];
    for src in 0..n {
        if depth[src] == 0.0 {
            continue;
        }
        let weights = band_shape(&ds, src, half_width[src]);
        // Conserve the worn area: sum_m h_m ds_m = depth_src ds_src.
        let norm: f64 = weights.iter().map(|(m, w)| w * ds[*m]).sum();
        let scale = depth[src] * ds[src] / norm;
        for (m, w) in &weights {
            out[*m] += scale * w;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The wear of a mesh cycle whose static solves start from the solutions of a less worn
    /// profile (the previous evaluation of a wear integration, each crank angle on its own)
    /// equals the one solved in runs from the neighbouring crank angle
    /// ([`StaticAnalysis::solve_sequence`]): the equilibria are unique, so only the solves'
    /// residual tolerance separates them: within 1e-7 of the largest depth (1.8e-8 seen with the
    /// pins in their grooves, 1.6e-11 with rigid pins). On the example's new
    /// and 2500 h discs, with the pins wearing, and with a pin-circle offset (every mesh cycle
    /// differs: 8 positions over the revolution and both discs).
    #[test]
    fn warm_started_wear_equals_the_cold() {
        let mut cfg = crate::config::Config::example();
        cfg.dynamics.enabled = false;
        cfg.fem.enabled = false;
        cfg.wear.pin_archard_coefficient_mm3_per_n_m = 5e-9;
        let model = cfg.validate().unwrap();
        let mut worn = model.clone();
        worn.wear.stage_hours = vec![2500.0];
        let hist = crate::wear::integrate(&worn.wear_inputs(), &|_, _| {}).unwrap();
        let map = hist.maps[0].clone();
        let mut offset = model.clone();
        offset.reducer.errors.pin_circle_offset = Vec2::new(2e-6, -1e-6);
        let torque = model.rating.rated_torque;
        for (name, m) in [("nominal", &model), ("pin-circle offset", &offset)] {
            let inputs = m.wear_inputs();
            for depth in [0.0_f64, 1.0] {
                let at = |f: f64| {
                    let w = (depth > 0.0)
                        .then(|| WearMap::new(map.iter().map(|h| f * h).collect()).unwrap());
                    m.cycloid.profile(w).unwrap()
                };
                // The previous evaluation: 1 % less wear (a couple of profile updates).
                let before = at(0.99);
                let (_, prev) =
                    wear_per_mesh_cycle_from(&before, &inputs, torque, 0.0, None, None).unwrap();
                let profile = at(1.0);
                let (cold, cold_sol) =
                    wear_per_mesh_cycle_from(&profile, &inputs, torque, 0.0, None, None).unwrap();
                let (warm, warm_sol) =
                    wear_per_mesh_cycle_from(&profile, &inputs, torque, 0.0, Some(&prev), None)
                        .unwrap();
                assert_eq!(cold_sol.len(), warm_sol.len(), "{name}");
                // Each map within 1e-7 of its largest value.
                for (a, b) in [(&cold.disc, &warm.disc), (&cold.pin, &warm.pin)] {
                    let largest = a.iter().copied().fold(0.0, f64::max);
                    assert!(largest > 0.0, "{name}");
                    for (x, y) in a.iter().zip(b) {
                        assert!(
                            (x - y).abs() <= 1e-7 * largest,
                            "{name} {depth}: {x:e} {y:e}"
                        );
                    }
                }
                assert!(
                    (cold.sliding - warm.sliding).abs() <= 1e-9 * cold.sliding,
                    "{name} {depth}"
                );
            }
        }
    }

    #[test]
    fn band_spreading_conserves_area_and_spreads() {
        let model = crate::config::Config::paper().validate().unwrap();
        let profile = model.profile().unwrap();
        let n = model.wear_inputs().grid_points();
        let mut depth = vec![0.0; n];
        depth[90] = 1e-6;
        let b = vec![30e-6; n];
        let out = spread_over_band(&profile, &depth, &b);
        let dt = TAU / n as f64;
        let ds: Vec<f64> = (0..n)
            .map(|m| profile.point(m as f64 * dt).dp.norm() * dt)
            .collect();
        let before = depth[90] * ds[90];
        let after: f64 = out.iter().zip(&ds).map(|(h, s)| h * s).sum();
        assert!((before - after).abs() < 1e-12 * before, "{before} {after}");
        let spread = out.iter().filter(|h| **h > 0.0).count();
        eprintln!("spread over {spread} nodes: {:?}", &out[80..100]);
        assert!(spread >= 5, "{spread}");
    }
}
