//! Friction, losses and lubrication (docs/model.md section 18): the Coulomb loop of one contact
//! against its closed form, the friction's work over a quasi-static cycle against the contacts'
//! dissipation along the path, the pins' friction-moment balance against its closed form, the
//! losses' limits and linearity, and the wear's dependence on the film.

use crate::config::{Config, Model, EXAMPLE_TOML};
use crate::efficiency::efficiency_map;
use crate::statics::{DiscLoad, PinLoad, StaticSolution};
use crate::te::{mesh_cycle_angles, FrictionTorques, TwistTable};
use crate::tribology::pin_dissipation;
use crate::wear::PinTurning;

/// The built-in example with `edits` (`from`, `to`) made to its text, validated.
fn example_with(edits: &[(&str, &str)]) -> Model {
    let mut t = EXAMPLE_TOML.to_string();
    for (from, to) in edits {
        assert!(t.contains(from), "the example has no `{from}`");
        t = t.replacen(from, to, 1);
    }
    Config::from_toml_str(&t, "test")
        .unwrap()
        .validate()
        .unwrap()
}

/// One spring `k` (N m/rad) behind one Coulomb contact of friction torque `F`, preloaded (no
/// play, the friction acts at zero torque too), swept between `+-T_r`: rigid-plastic Coulomb
/// friction in series with a linear spring gives the parallelogram loop `psi = (T -+ F)/k`
/// with vertical steps of `2F` at the turning points, whose area is `4 F (T_r - F)/k`; its
/// width at zero torque is `2F/k`; its midpoints are the spring's; the twist stands still
/// while the torque falls from `T_r` by `2F` (stick).
#[test]
fn one_coulomb_contact_against_the_closed_form() {
    let (k, rated, f) = (2.0e5, 100.0, 5.0);
    let fractions: Vec<f64> = [0.0, 0.03]
        .into_iter()
        .chain((1..=10).map(|i| i as f64 / 10.0))
        .collect();
    let twist: Vec<f64> = fractions.iter().map(|x| x * rated / k).collect();
    let table = TwistTable {
        fractions: fractions.clone(),
        rated_torque: rated,
        measuring_fraction: 0.03,
        positive: twist.clone(),
        negative: twist.iter().map(|x| -x).collect(),
        friction: Some(FrictionTorques {
            positive: vec![f; fractions.len()],
            negative: vec![f; fractions.len()],
            positive_twist: vec![f / k; fractions.len()],
            negative_twist: vec![f / k; fractions.len()],
        }),
    };
    let area = 4.0 * f * (rated - f) / k;
    assert!(
        (table.friction_work() - area).abs() < 1e-12 * area,
        "{} {area}",
        table.friction_work()
    );
    let acc = table.accuracy();
    assert!((acc.hysteresis_loss - 2.0 * f / k).abs() < 1e-15);
    assert!((acc.lost_motion - 2.0 * 0.03 * rated / k).abs() < 1e-15);
    assert!((acc.torsional_stiffness - k).abs() < 1e-6 * k);
    // Stick at the top: 100 N m and 90 N m (= T_r - 2F) on the way down share the twist of
    // the rising branch at the rated torque, (T_r - F)/k; slip resumes below.
    let c = table.curve();
    let n = fractions.len();
    let down = &c.twist[n..2 * n];
    assert!((down[0] - (rated - f) / k).abs() < 1e-15);
    assert!((down[1] - (rated - f) / k).abs() < 1e-15);
    assert!((down[2] - (80.0 + f) / k).abs() < 1e-15);
    // Frictionless, the loop has no area and the quantities are the spring's.
    let bare = TwistTable {
        friction: None,
        ..table.clone()
    };
    assert_eq!(bare.friction_work(), 0.0);
    assert_eq!(bare.accuracy().hysteresis_loss, 0.0);
}

/// The catalogue's points of a hysteresis curve (`TwistTable::catalogue_points`) are those
/// its quantities are read between: on a table whose two senses differ (a stiffer negative
/// side, an offset), with and without friction, the midpoints' twists differ by the lost
/// motion and sit at `+-T_m`, each the mean of the curve's twists at its torque on the loop
/// (the first loading left out); the secant's torque over twist is the torsional stiffness
/// `b/a`, from the loading branch at `+T_m` to `+T_r`.
#[test]
fn catalogue_points_give_the_catalogue_quantities() {
    let (k, rated, f) = (2.0e5, 100.0, 5.0);
    let fractions: Vec<f64> = [0.0, 0.03]
        .into_iter()
        .chain((1..=10).map(|i| i as f64 / 10.0))
        .collect();
    let n = fractions.len();
    let positive: Vec<f64> = fractions.iter().map(|x| 1e-4 + x * rated / k).collect();
    let negative: Vec<f64> = fractions
        .iter()
        .map(|x| -2e-4 - x * rated / (1.5 * k))
        .collect();
    let bare = TwistTable {
        fractions: fractions.clone(),
        rated_torque: rated,
        measuring_fraction: 0.03,
        positive,
        negative,
        friction: None,
    };
    let rubbing = TwistTable {
        friction: Some(FrictionTorques {
            positive: vec![f; n],
            negative: vec![f; n],
            positive_twist: vec![f / k; n],
            negative_twist: vec![f / k; n],
        }),
        ..bare.clone()
    };
    for table in [&bare, &rubbing] {
        let acc = table.accuracy();
        let p = table.catalogue_points();
        let [[tn, psi_n], [tp, psi_p]] = p.lost_motion;
        assert_eq!((tn, tp), (-0.03 * rated, 0.03 * rated));
        assert!((psi_p - psi_n - acc.lost_motion).abs() < 1e-15 * acc.lost_motion.abs().max(1e-3));
        // Each midpoint: the mean of the loop's twists at its torque.
        let c = table.curve();
        let mean_at = |t: f64| {
            let at: Vec<f64> = (n - 1..c.torque.len())
                .filter(|&i| (c.torque[i] - t).abs() < 1e-12)
                .map(|i| c.twist[i])
                .collect();
            at.iter().sum::<f64>() / at.len() as f64
        };
        assert!(
            (mean_at(tp) - psi_p).abs() < 1e-15,
            "{} {psi_p}",
            mean_at(tp)
        );
        assert!(
            (mean_at(tn) - psi_n).abs() < 1e-15,
            "{} {psi_n}",
            mean_at(tn)
        );
        let [[t0, psi0], [t1, psi1]] = p.torsional_stiffness;
        assert_eq!((t0, t1), (0.03 * rated, rated));
        let secant = (t1 - t0) / (psi1 - psi0);
        assert!((secant - acc.torsional_stiffness).abs() < 1e-9 * acc.torsional_stiffness);
        // The secant starts on the loading branch: the last loading's twist at +T_m.
        let last = c
            .torque
            .iter()
            .rposition(|&t| (t - t0).abs() < 1e-12)
            .unwrap();
        assert!((c.twist[last] - psi0).abs() < 1e-15);
    }
}

/// The friction's work over the sweep `+T_r -> -T_r -> +T_r` (the loop's area, from the two
/// branches at the grid's torques) equals the work the contacts' and bearings' friction does
/// along the path swept, `oint T_f |dpsi|` (each level's friction torque from its contacts'
/// creep, the trapezoid rule over the branches' twists), at 8 crank angles of a mesh cycle of
/// the built-in example, within 1.5 % (measured: at most 0.8 %). Not to round-off: the
/// friction is first order (it does not move the loads), so the branches are the
/// frictionless twists moved by `T_f / k`, and the two sums differ by the second-order terms
/// and the grid's discretisation. The frictionless path (without the stick at the turning
/// points) overstates the work.
#[test]
fn friction_work_of_a_cycle_is_the_contacts_dissipation() {
    let m = example_with(&[]);
    assert!(m.reducer.friction.is_some());
    let profile = m.profile().unwrap();
    let phis = mesh_cycle_angles(m.reducer.geometry.pins, 8);
    let (tables, _) =
        crate::te::hysteresis(&m.reducer, &profile, &phis, m.rating.rated_torque, 0.03, 40)
            .unwrap();
    let mut worst: f64 = 0.0;
    for t in &tables {
        let f = t.friction.as_ref().unwrap();
        // `2 integral T_f dpsi` over each side by the trapezoid rule, the rising and falling
        // branches both (each side swept twice, once each way).
        let side = |psi: &[f64], tf: &[f64]| -> f64 {
            (1..psi.len())
                .map(|i| (tf[i] + tf[i - 1]) * (psi[i] - psi[i - 1]).abs())
                .sum::<f64>()
        };
        let path = side(&t.positive, &f.positive) + side(&t.negative, &f.negative);
        // Along the branches actually swept (their twists, the stick at the turning points).
        let c = t.curve();
        let n = t.fractions.len();
        let tf_at = |torque: f64| -> f64 {
            let r = t.rated_torque;
            let i = t
                .fractions
                .iter()
                .position(|x| (x * r - torque.abs()).abs() < 1e-9)
                .unwrap();
            if torque >= 0.0 {
                f.positive[i]
            } else {
                f.negative[i]
            }
        };
        let swept: f64 = (n..c.twist.len())
            .map(|i| {
                0.5 * (tf_at(c.torque[i]) + tf_at(c.torque[i - 1]))
                    * (c.twist[i] - c.twist[i - 1]).abs()
            })
            .sum();
        let work = t.friction_work();
        worst = worst.max((work - swept).abs() / swept);
        assert!(work > 0.0 && path > swept);
        assert!(
            (work - swept).abs() < 0.015 * swept,
            "loop {work:e} J, contacts {swept:e} J"
        );
    }
    eprintln!(
        "loop against the contacts' work: at most {:.2} % apart",
        100.0 * worst
    );
}

/// A pin under one disc contact (force `Q`, the disc's material sliding past at `w`): held, it
/// loses `mu Q |w|` at the contact; free to turn with `mu_d > mu_g` it rolls on the contact
/// (which carries the groove's `mu_g Q` as traction, Carter's creep its only loss there) and
/// slides in its groove, losing `mu_g Q |w|` there; with `mu_d < mu_g` it stands still and
/// the contact slides: the balance of the friction moments takes the cheaper interface.
#[test]
fn pin_friction_moment_balance_against_the_closed_form() {
    let (q, w, v_d, p0, e_star) = (1000.0, 0.02, 0.05, 1.0e9, 1.154e11);
    let pin = |force: f64| PinLoad {
        pin: 0,
        profile_parameter: 0.0,
        mesh_angle: 0.0,
        gap: 0.0,
        force,
        lever_arm: 0.0,
        half_width: 1e-4,
        max_pressure: p0,
        curvature: 0.0,
        stiffness: 0.0,
        point: Default::default(),
        normal: Default::default(),
    };
    let sol = StaticSolution {
        crank_angle: 0.0,
        output_torque: 1.0,
        twist: 0.0,
        first_contact_twist: 0.0,
        stiffness: 1.0,
        discs: vec![DiscLoad {
            pose: crate::contact::DiscPose::default(),
            translation: Default::default(),
            rotation: 0.0,
            torque: 0.0,
            pins: vec![pin(q)],
        }],
        residual: 0.0,
        roundoff_floor: 0.0,
        deviations: Vec::new(),
        twist_direction: Vec::new(),
    };
    let speeds = vec![vec![(w, v_d)]];
    let mu = 0.08;
    let (c, g) = pin_dissipation(&sol, &speeds, &[vec![mu]], &PinTurning::Fixed, 0.0, e_star);
    assert!((c - mu * q * w).abs() < 1e-15 && g == 0.0);
    // A quarter of the sliding taken by the groove at the contact's coefficient.
    let (c, g) = pin_dissipation(&sol, &speeds, &[vec![mu]], &PinTurning::Fixed, 0.25, e_star);
    assert!((c - 0.75 * mu * q * w).abs() < 1e-15 && (g - 0.25 * mu * q * w).abs() < 1e-15);
    // Rolling: the groove slides at w under Q; the contact creeps under the traction mu_g Q.
    let rolls = PinTurning::Balance {
        pin_friction: 0.1,
        groove_friction: 0.05,
    };
    let (c, g) = pin_dissipation(&sol, &speeds, &[vec![mu]], &rolls, 0.0, e_star);
    assert!((g - 0.05 * q * w).abs() < 1e-15, "{g}");
    // Carter: xi = (mu_d b/R)(1 - sqrt(1 - F/(mu_d Q))), b/R = 2 p0/E*; loss F xi v_d.
    let xi = 0.1 * 2.0 * p0 / e_star * (1.0 - (1.0 - 0.5f64).sqrt());
    assert!((c - 0.05 * q * xi * v_d).abs() < 1e-12 * c, "{c}");
    assert!(c < 1e-2 * g);
    // Standing still: the contact slides at its own coefficient, the groove loses nothing.
    let still = PinTurning::Balance {
        pin_friction: 0.05,
        groove_friction: 0.1,
    };
    let (c, g) = pin_dissipation(&sol, &speeds, &[vec![mu]], &still, 0.0, e_star);
    assert!((c - mu * q * w).abs() < 1e-15 && g == 0.0);
}

/// The losses' limits and linearity on the built-in example: with a constant disc-pin
/// coefficient and no bearing or mesh friction, the first-order disc-pin loss (on the
/// frictionless loads) is proportional to the coefficient and the only loss; with the friction
/// in the equilibrium it departs from that by the second order (the pins' tangential forces
/// act on the discs with the pin circle's lever, several times the normal forces' lever arms,
/// so the departure is 8 % of the loss at `mu = 0.05`, and a tenth of that at a tenth of the
/// coefficient); without any friction but the meshes' the efficiency is the meshes'; every loss is
/// non-negative, the input power exceeds the output's by the losses within 1e-3 of the input
/// (the rest is the paper law's own work over the cycle, see
/// [`energy_balance_of_a_running_cycle`], and the friction's work on the elastic motion), and the efficiency rises with the film where the coefficient follows it (the oil's
/// viscosity at 20 deg C against 80 deg C).
#[test]
fn losses_limits_and_linearity() {
    let m = example_with(&[
        ("bearing_f0 = 6.0", "bearing_f0 = 0.0"),
        ("bearing_f1 = 0.0005", "bearing_f1 = 0.0"),
    ]);
    let profile = m.profile().unwrap();
    let rated = m.rating.rated_torque;
    let sa = crate::statics::StaticAnalysis::new(&m.reducer, &profile).unwrap();
    let loads = crate::efficiency::mesh_cycle_loads(&sa, rated, 12).unwrap();
    let mut lub = m.lubrication;
    let first_order = |lub: &crate::tribology::Lubrication| {
        crate::efficiency::operating_point(&sa, &profile, lub, &m.wear, &loads, 15.0)
    };
    let run = |lub: &crate::tribology::Lubrication, t: f64| {
        efficiency_map(
            &m.reducer,
            &profile,
            lub,
            &m.wear,
            &[rated],
            &[15.0],
            &[t],
            12,
        )
        .unwrap()[0]
    };
    let mut at = |mu: f64| {
        lub.friction = crate::tribology::FrictionModel::Constant(mu);
        (run(&lub, 40.0), first_order(&lub))
    };
    let (small, small1) = at(0.005);
    let (a, a1) = at(0.05);
    let (b, b1) = at(0.10);
    assert!(a.loss_crank_bearings_w == 0.0 && a.loss_pin_grooves_w == 0.0);
    assert!((b1.loss_disc_pins_w / a1.loss_disc_pins_w - 2.0).abs() < 1e-12);
    // The equilibrium's departure from the first order is of the second order in the
    // coefficient: relative to the loss, of the first, so a tenth of the coefficient leaves
    // about a tenth of it.
    let departure = |x: &crate::efficiency::OperatingPoint,
                     x1: &crate::efficiency::OperatingPoint| {
        x.loss_disc_pins_w / x1.loss_disc_pins_w - 1.0
    };
    let (d_small, d_a, d_b) = (
        departure(&small, &small1),
        departure(&a, &a1),
        departure(&b, &b1),
    );
    eprintln!(
        "equilibrium against first order at mu 0.005, 0.05, 0.1: {d_small:.3e} {d_a:.3e} {d_b:.3e}"
    );
    assert!(d_small.abs() < 0.15 * d_a.abs() && d_a.abs() < 0.6 * d_b.abs());
    lub.friction = crate::tribology::FrictionModel::Constant(0.0);
    let z = run(&lub, 40.0);
    assert_eq!(z.loss_disc_pins_w, 0.0);
    for p in [a, b, z] {
        let rest = p.input_power_w - p.output_power_w - p.loss_w();
        eprintln!(
            "input - output - losses: {:.3e} of the input",
            rest / p.input_power_w
        );
        assert!(rest.abs() < 1e-3 * p.input_power_w);
        assert!(p.loss_disc_pins_w >= 0.0 && p.loss_gear_meshes_w > 0.0);
    }
    // The mixed-lubrication coefficient: a thicker film (cold oil) slides more easily.
    let cold = run(&m.lubrication, 20.0);
    let hot = run(&m.lubrication, 80.0);
    assert!(cold.lambda_mean > hot.lambda_mean);
    assert!(cold.pin_friction_coefficient < hot.pin_friction_coefficient);
}

/// The wear that follows the film: each contact's depth is scaled by the asperities' share of
/// its load (at most 1), so a mesh cycle wears less than with constant coefficients, less
/// the faster the input turns, and as much where the film vanishes (a thin oil crawling).
#[test]
fn wear_follows_the_film() {
    let constant = example_with(&[]);
    let film = example_with(&[("wear = \"constant\"", "wear = \"lambda\"")]);
    let profile = constant.profile().unwrap();
    let t = constant.rating.rated_torque;
    let depth = |m: &Model, rpm: f64| {
        let (w, _) = crate::wear::mesh_cycle::wear_per_mesh_cycle_from(
            &profile,
            &m.wear_inputs(),
            t,
            rpm,
            None,
            None,
        )
        .unwrap();
        w.disc.iter().copied().fold(0.0, f64::max)
    };
    let full = depth(&constant, 1500.0);
    let at_1500 = depth(&film, 1500.0);
    let at_3000 = depth(&film, 3000.0);
    assert!(
        at_1500 < full && at_3000 < at_1500,
        "{full:e} {at_1500:e} {at_3000:e}"
    );
    let crawling = depth(&film, 1e-6);
    assert!(
        (crawling / full - 1.0).abs() < 1e-3,
        "{crawling:e} {full:e}"
    );
}

/// The work of one quasi-static running cycle of `m` at its rated torque and 15 rpm output with
/// the friction in the equilibrium, over `samples` crank angles of a mesh cycle (and back to
/// the first), each state's terms by the trapezoid rule along the solved path: `(W_in, W_out,
/// dU, D, losses)`, J: the input's work, the output's (`-T dtheta_out`), the elastic energy's
/// change, the friction forces' work along the path (`-Q_f . dq`), and the operating point's
/// losses (along the nominal motion) over the cycle's time. Without friction (`friction`
/// false) the equilibria are the frictionless ones and `D` is 0.
fn running_cycle(m: &Model, samples: usize, friction: bool) -> [f64; 5] {
    let red = &m.reducer;
    let profile = m.profile().unwrap();
    let sa = crate::statics::StaticAnalysis::new(red, &profile).unwrap();
    let torque = m.rating.rated_torque;
    let speed_rpm = 15.0;
    let run = crate::efficiency::Running::new(red, &profile, torque, speed_rpm);
    let mut phis: Vec<f64> = mesh_cycle_angles(red.geometry.pins, samples);
    phis.push(phis[0] + (phis[1] - phis[0]) * samples as f64);
    // In the sense the input turns.
    if run.omega_in * red.kappa() < 0.0 {
        phis.reverse();
    }
    let loads = sa.solve_sequence(&phis, torque).unwrap();
    let states: Vec<_> = loads
        .iter()
        .map(|sol| {
            let (s, held) = if friction {
                crate::efficiency::running_equilibrium(
                    &sa,
                    &profile,
                    &m.lubrication,
                    &m.wear,
                    sol,
                    run,
                )
                .unwrap()
            } else {
                (sol.clone(), crate::statics::ContactFriction::default())
            };
            (
                sa.positions_of(&s),
                sa.input_torque(&s, &held),
                sa.applied_forces(&s, &held),
                sa.elastic_energy_of(&s).unwrap(),
            )
        })
        .collect();
    let (mut w_in, mut dissipated) = (0.0, 0.0);
    for pair in states.windows(2) {
        let ((qa, ta, aa, _), (qb, tb, ab, _)) = (&pair[0], &pair[1]);
        w_in += 0.5 * (ta + tb) * (qb[0] - qa[0]);
        dissipated -= (0..qa.len())
            .map(|i| 0.5 * (aa[i] + ab[i]) * (qb[i] - qa[i]))
            .sum::<f64>();
    }
    let (first, last) = (&states[0], &states[states.len() - 1]);
    let w_out = -torque * (last.0[1] - first.0[1]);
    let stored = last.3 - first.3;
    let cycle = crate::efficiency::MeshCycleLoads {
        torque,
        bearing_forces: loads[..samples]
            .iter()
            .map(|s| sa.bearing_forces(s))
            .collect(),
        solutions: loads[..samples].to_vec(),
    };
    let point = if friction {
        crate::efficiency::running_point(&sa, &profile, &m.lubrication, &m.wear, &cycle, speed_rpm)
            .unwrap()
    } else {
        crate::efficiency::operating_point(
            &sa,
            &profile,
            &m.lubrication,
            &m.wear,
            &cycle,
            speed_rpm,
        )
    };
    let time = (first.0[0] - last.0[0]).abs() / run.omega_in.abs();
    [w_in, w_out, stored, dissipated, point.loss_w() * time]
}

/// The energy balance of the running reducer with the friction in its equilibrium, over a
/// quasi-static mesh cycle of the built-in example at its rated torque with every friction on
/// (the film's at the disc-pin contacts, the pins turning in their grooves, Palmgren's in the
/// crank bearings, the meshes'): the input's work is the output's, the elastic energy's change
/// and the friction forces' work along the solved path, `W_in = W_out + dU + D` (the virtual
/// work of the equilibria), within 1e-6 of the input's work with a contact law of the approach
/// alone (`law = "linear"`: measured 7e-8 over 96 crank angles; the same without friction,
/// where `D = 0`). The friction dissipates, and `D` is the operating point's losses (along the
/// nominal motion) over the cycle's time within 0.5 % (measured 0.2 %). The paper's law, whose
/// approach also depends on the flank's curvature at the contact point (which moves along the
/// flank), is not conservative: its elastic forces do work over the cycle, measured 1.6e-4 of
/// the input's without friction and with it; asserted below 3e-4 (docs/model.md section 18.8).
#[test]
fn energy_balance_of_a_running_cycle() {
    let linear = example_with(&[(
        "law = \"paper\"",
        "law = \"linear\"\nlinear_stiffness_n_per_um = 500.0",
    )]);
    for friction in [true, false] {
        let [w_in, w_out, stored, dissipated, losses] = running_cycle(&linear, 96, friction);
        let imbalance = (w_in - (w_out + stored + dissipated)) / w_in;
        eprintln!(
            "linear law, friction {friction}: W_in {w_in:.9e} J, W_out {w_out:.9e} J, dU \
             {stored:.3e} J, D {dissipated:.6e} J, losses {losses:.6e} J, imbalance \
             {imbalance:.3e}"
        );
        assert!(w_in > 0.0 && w_out > 0.0);
        assert!(imbalance.abs() < 1e-6, "{imbalance:.3e}");
        if friction {
            assert!(dissipated > 0.0 && (losses / dissipated - 1.0).abs() < 5e-3);
        } else {
            assert_eq!(dissipated, 0.0);
        }
    }
    let paper = example_with(&[]);
    for friction in [true, false] {
        let [w_in, w_out, stored, dissipated, _] = running_cycle(&paper, 48, friction);
        let imbalance = (w_in - (w_out + stored + dissipated)) / w_in;
        eprintln!("paper's law, friction {friction}: imbalance {imbalance:.3e}");
        assert!(imbalance.abs() < 3e-4, "{imbalance:.3e}");
    }
}

/// The hysteresis curve's branches with the friction in the equilibrium against the first-order
/// branches (the frictionless twist `-+ T_f/k`) on the built-in example, at 8 crank angles of a
/// mesh cycle. At 30 % and all of the rated torque the loading branch lies inside the
/// frictionless twist and the unloading one outside it; their distance, `2 T_f/k` to first
/// order, agrees within 3 % (measured 0.6 and 1 %); their midpoint stays within a tenth of that
/// distance of the frictionless twist (measured 5-6 %). At the lost-motion points (+-3 %), where
/// the friction torque is a fifth of the torque and the discs sit in their bearings' play, the
/// first order does not hold: the branches are about half as far apart and their midpoints move
/// inwards by about half the distance, so the lost motion between the midpoints is smaller than
/// the frictionless one; asserted within 5 % of it (docs/model.md section 18.3 quotes the
/// measured figures).
#[test]
fn hysteresis_branches_in_the_equilibrium_against_first_order() {
    let m = example_with(&[]);
    let red = &m.reducer;
    let f = red.friction.expect("the example has friction");
    let profile = m.profile().unwrap();
    let sa = crate::statics::StaticAnalysis::new(red, &profile).unwrap();
    let rated = m.rating.rated_torque;
    let fmt = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.4}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    // Per crank angle: the frictionless twist, the branches' midpoint and their distance over
    // the first order's.
    let branches = |phi: f64, torque: f64| {
        let sol = sa.solve(phi, torque).unwrap();
        let loading = crate::te::friction_branch(&sa, &f, &sol, true).unwrap();
        let unloading = crate::te::friction_branch(&sa, &f, &sol, false).unwrap();
        let first = crate::te::friction_torques(&sa, &f, std::slice::from_ref(&sol))[0];
        let s = torque.signum();
        assert!((loading.twist - sol.twist) * s < 0.0);
        let width = (unloading.twist - loading.twist) * s;
        let mid = 0.5 * (unloading.twist + loading.twist);
        (sol.twist, mid, width / (2.0 * first / sol.stiffness), width)
    };
    let phis = mesh_cycle_angles(red.geometry.pins, 8);
    for fraction in [0.3, 1.0] {
        let (mut widths, mut shifts) = (Vec::new(), Vec::new());
        for &phi in &phis {
            let (twist, mid, ratio, width) = branches(phi, fraction * rated);
            widths.push(ratio);
            shifts.push((mid - twist) / width);
        }
        eprintln!(
            "{fraction} T_r: width / first order {}; midpoint shift / width {}",
            fmt(&widths),
            fmt(&shifts)
        );
        assert!(widths.iter().all(|w| (w - 1.0).abs() < 0.03));
        assert!(shifts.iter().all(|s| s.abs() < 0.1));
    }
    let (mut frictionless, mut with_friction, mut widths) = (Vec::new(), Vec::new(), Vec::new());
    for &phi in &phis {
        let (tp, mp, wp, _) = branches(phi, 0.03 * rated);
        let (tn, mn, wn, _) = branches(phi, -0.03 * rated);
        frictionless.push((tp - tn) * crate::units::ARCMIN_PER_RAD);
        with_friction.push((mp - mn) * crate::units::ARCMIN_PER_RAD);
        widths.extend([wp, wn]);
    }
    let change: Vec<f64> = with_friction
        .iter()
        .zip(&frictionless)
        .map(|(a, b)| a / b - 1.0)
        .collect();
    eprintln!(
        "+-3 %: width / first order {}; lost motion frictionless {} arcmin, with friction {} \
         arcmin, change {}",
        fmt(&widths),
        fmt(&frictionless),
        fmt(&with_friction),
        fmt(&change)
    );
    assert!(change.iter().all(|c| *c < 0.0 && c.abs() < 0.05));
}

/// With rigid support (the paper's one disc on a fixed centre: no coordinates for the friction
/// forces) the efficiency is the first-order one, its disc-pin loss that of the contacts'
/// kinematics: positive, and the efficiency between the meshes' alone and 50 %.
#[test]
fn rigid_support_efficiency_is_first_order() {
    let m = example_with(&[(
        "support = \"bearings\"",
        "support = \"rigid\"\nload_share = 0.55",
    )]);
    let profile = m.profile().unwrap();
    let p = efficiency_map(
        &m.reducer,
        &profile,
        &m.lubrication,
        &m.wear,
        &[m.rating.rated_torque],
        &[15.0],
        &[40.0],
        12,
    )
    .unwrap()[0];
    eprintln!("rigid support: {p:?}");
    assert!(p.loss_disc_pins_w > 0.0 && p.efficiency > 0.5 && p.efficiency < 1.0);
    assert!((p.input_power_w - p.output_power_w - p.loss_w()).abs() < 1e-9 * p.input_power_w);
}
