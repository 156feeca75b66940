//! Checks of the flexible disc that can fail: patch test, Lame ring,
//! mesh convergence of the disc compliance, rigid limit, bad input.

use std::f64::consts::{PI, TAU};

use crate::config::{Config, Model};
use crate::fem::flex::{
    analyse_stage, faces_driving_flank, faces_loaded_flank, solve_flexible,
    solve_flexible_bearings, FlexibleLaw, FLEX_OFFSET_TOLERANCE,
};
use crate::fem::mesh::{triangulate, BoundaryLoop, LoopKind, MeshSpec};
use crate::fem::plane::{traction_load, FeModel, NodeBc, PlaneStress};
use crate::fem::{DiscModel, DiscSet};
use crate::geometry::{Vec2, WearMap};
use crate::units::ARCMIN_PER_RAD;

fn model_with(edit: impl FnOnce(&mut Config)) -> Model {
    let mut c = Config::paper();
    edit(&mut c);
    c.validate().unwrap()
}

/// The profile of `m` worn uniformly by `depth` (m) along the whole flank.
fn uniformly_worn(m: &Model, depth: f64) -> crate::geometry::Profile {
    m.cycloid
        .profile(Some(WearMap::uniform(360, depth).unwrap()))
        .unwrap()
}

const STEEL: PlaneStress = PlaneStress {
    youngs_modulus: 210e9,
    poisson_ratio: 0.3,
    thickness: 0.01,
};

/// Patch test: a square mesh with interior nodes, every boundary node given the displacement of
/// a linear field; the interior nodes must take the same field and the stress must be the
/// constant `D eps` (to round-off), including on the graded, distorted Delaunay mesh.
#[test]
fn plane_stress_passes_the_patch_test() {
    let side = 0.02;
    let square = BoundaryLoop {
        points: (0..40)
            .map(|k| {
                let s = side * (k % 10) as f64 / 10.0;
                match k / 10 {
                    0 => Vec2::new(s, 0.0),
                    1 => Vec2::new(side, s),
                    2 => Vec2::new(side - s, side),
                    _ => Vec2::new(0.0, side - s),
                }
            })
            .collect(),
        kind: LoopKind::Outline,
        circle: None,
    };
    let mesh = triangulate(
        &[square],
        &MeshSpec {
            max_area: 4e-6,
            min_angle_deg: 25.0,
            max_added_vertices: 10_000,
        },
    )
    .unwrap();
    let field = |p: &Vec2| {
        (
            1e-6 + 2e-4 * p.x - 1e-4 * p.y,
            -2e-6 + 0.5e-4 * p.x + 3e-4 * p.y,
        )
    };
    let on_boundary: std::collections::HashSet<usize> =
        mesh.boundary.iter().flat_map(|e| e.nodes).collect();
    let interior = mesh.nodes.len() - on_boundary.len();
    assert!(interior > 20, "the patch needs interior nodes ({interior})");
    let bc: Vec<NodeBc> = mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if on_boundary.contains(&i) {
                let (ux, uy) = field(p);
                NodeBc::Fixed(Some(ux), Some(uy))
            } else {
                NodeBc::Free
            }
        })
        .collect();
    let fe = FeModel::new(mesh, STEEL, &bc, vec![]).unwrap();
    let u = fe.solve(&vec![0.0; 2 * fe.mesh.nodes.len()]);
    let mut worst: f64 = 0.0;
    for (i, p) in fe.mesh.nodes.iter().enumerate() {
        let (ux, uy) = field(p);
        worst = worst
            .max((u[2 * i] - ux).abs())
            .max((u[2 * i + 1] - uy).abs());
    }
    assert!(
        worst < 1e-15,
        "displacement error {worst:e} m (field ~1e-6 m)"
    );
    let d = STEEL.d();
    let (ex, ey, gxy) = (2e-4, 3e-4, -1e-4 + 0.5e-4);
    let exact = [
        d[0][0] * ex + d[0][1] * ey,
        d[1][0] * ex + d[1][1] * ey,
        d[2][2] * gxy,
    ];
    let s = fe.stresses(&u);
    for st in &s.stress {
        for c in 0..3 {
            assert!(
                (st[c] - exact[c]).abs() < 1e-6 * exact[0].abs(),
                "stress {st:?} vs {exact:?}"
            );
        }
    }
}

/// Thick ring (a = 20 mm, b = 50 mm) under internal pressure 100 MPa: the radial displacement at
/// both radii and the hoop stress at the bore match Lame's plane-stress solution within 1 %.
#[test]
fn thick_ring_matches_lame() {
    let (a, b, p) = (0.02, 0.05, 100e6);
    let outer = BoundaryLoop::circle(Vec2::zeros(), b, 96, LoopKind::Outline);
    let inner = BoundaryLoop::circle(Vec2::zeros(), a, 128, LoopKind::Hole(0));
    let mesh = triangulate(
        &[outer, inner],
        &MeshSpec {
            max_area: 0.433 * 2e-3 * 2e-3,
            min_angle_deg: 25.0,
            max_added_vertices: 50_000,
        },
    )
    .unwrap();
    // Rigid-body modes held by three conditions the radial solution satisfies.
    let find = |x: f64, y: f64| {
        mesh.nodes
            .iter()
            .enumerate()
            .min_by(|p, q| {
                let d = |v: &Vec2| (v - Vec2::new(x, y)).norm();
                d(p.1).total_cmp(&d(q.1))
            })
            .unwrap()
            .0
    };
    let (n_a, n_b, n_c) = (find(b, 0.0), find(0.0, b), find(-b, 0.0));
    let mut bc = vec![NodeBc::Free; mesh.nodes.len()];
    bc[n_a] = NodeBc::Fixed(None, Some(0.0));
    bc[n_b] = NodeBc::Fixed(Some(0.0), None);
    bc[n_c] = NodeBc::Fixed(None, Some(0.0));
    let holes: Vec<usize> = (0..mesh.boundary.len())
        .filter(|&e| mesh.boundary[e].kind == LoopKind::Hole(0))
        .collect();
    let load = traction_load(&mesh, STEEL.thickness, holes.into_iter(), |x| {
        Some(x / x.norm() * p)
    });
    let fe = FeModel::new(mesh, STEEL, &bc, vec![]).unwrap();
    let mut f = vec![0.0; 2 * fe.mesh.nodes.len()];
    for (i, v) in load {
        f[i] += v;
    }
    let u = fe.solve(&f);
    let (e, nu) = (STEEL.youngs_modulus, STEEL.poisson_ratio);
    let ca = p * a * a / (b * b - a * a);
    let cb = p * a * a * b * b / (b * b - a * a);
    let ur = |r: f64| ((1.0 - nu) * ca * r + (1.0 + nu) * cb / r) / e;
    let s = fe.stresses(&u);
    let (mut worst_u, mut worst_s): (f64, f64) = (0.0, 0.0);
    let hoop_a = p * (a * a + b * b) / (b * b - a * a);
    for (i, x) in fe.mesh.nodes.iter().enumerate() {
        let r = x.norm();
        let on = |rr: f64| (r - rr).abs() < 1e-9 * rr;
        if on(a) || on(b) {
            let u_r = (u[2 * i] * x.x + u[2 * i + 1] * x.y) / r;
            worst_u = worst_u.max((u_r / ur(r) - 1.0).abs());
        }
        if on(a) {
            let [sx, sy, t] = s.stress[i];
            let (c, sn) = (x.x / r, x.y / r);
            let hoop = sx * sn * sn + sy * c * c - 2.0 * t * sn * c;
            worst_s = worst_s.max((hoop / hoop_a - 1.0).abs());
        }
    }
    eprintln!("Lame: displacement error {worst_u:.2e}, hoop stress error {worst_s:.2e}");
    assert!(worst_u < 0.01, "radial displacement off by {worst_u}");
    assert!(worst_s < 0.01, "hoop stress off by {worst_s}");
}

/// The disc compliance converges: the station compliances of the default mesh (0.25 mm on the
/// flanks) and the fine mesh (0.125 mm) differ by less than 1 % (largest over the stations of
/// the first tooth and their coupling to the next tooth), and the flexible loaded TE by less than
/// 0.5 %.
#[test]
fn disc_compliance_converges_under_refinement() {
    let build = |flank: f64| {
        let m = model_with(|c| {
            c.fem.flank_element_size_mm = flank;
            c.fem.crank_angles = 8;
        });
        let p = uniformly_worn(&m, 10e-6);
        let d = DiscSet::build(&p, &m.fem.params, &m.reducer).unwrap();
        let st = analyse_stage(&p, &m.reducer, &d, m.rating.rated_torque).unwrap();
        let te = st.flexible_loaded_te.iter().sum::<f64>() / 8.0;
        (d.models.into_iter().next().unwrap(), te)
    };
    let (coarse, te_c) = build(0.25);
    let (fine, te_f) = build(0.125);
    let m = coarse.params.stations_per_flank;
    let n = coarse.stations();
    let mut worst: f64 = 0.0;
    // Stations of tooth 0 on both flanks against those of tooth 1 (global index
    // `(2 tooth + flank) m + i`).
    for i in 0..2 * m {
        for k in [i, i + 2 * m] {
            let (a, b) = (coarse.compliance[i * n + k], fine.compliance[i * n + k]);
            let scale = fine.compliance[i * n + i];
            worst = worst.max((a - b).abs() / scale);
        }
    }
    eprintln!(
        "compliance change {worst:.2e}; TE {:.5} vs {:.5} arcmin",
        te_c * ARCMIN_PER_RAD,
        te_f * ARCMIN_PER_RAD
    );
    assert!(worst < 0.01, "compliance changed by {worst}");
    assert!((te_c / te_f - 1.0).abs() < 0.005);
}

/// The example with the disc modulus times `scale` (FE body and Hertz law alike) and 4 crank
/// angles, its profile under 10 um of uniform wear, and the FE disc of that profile.
fn scaled_disc(scale: f64) -> (Model, crate::geometry::Profile, DiscSet) {
    let m = model_with(|c| {
        c.materials.disc.youngs_modulus_gpa *= scale;
        c.fem.crank_angles = 4;
    });
    let p = uniformly_worn(&m, 10e-6);
    let d = DiscSet::build(&p, &m.fem.params, &m.reducer).unwrap();
    (m, p, d)
}

/// The example's reducer with its disc centre fixed on the eccentric, carrying half the output
/// torque (the fixed-centre flexible model).
fn fixed_centre(m: &Model) -> crate::reducer::Reducer {
    let mut red = m.reducer.clone();
    red.support = crate::reducer::Support::Rigid { load_share: 0.5 };
    red
}

/// At a very large Young's modulus of the disc (x 1e4, in the FE body and in the Hertz law
/// alike) the flexible solution approaches the rigid one: the extra rotation from the disc
/// body is under 0.2 % of the contact part of the loaded TE, against about 55 % at the real
/// modulus.
#[test]
fn stiff_disc_approaches_the_rigid_result() {
    let run = |scale: f64| {
        let (m, p, d) = scaled_disc(scale);
        let red = fixed_centre(&m);
        let sa = crate::statics::StaticAnalysis::new(&red, &p).unwrap();
        let phi = 0.3;
        let s = solve_flexible(&sa, d.disc(0).0, phi, m.rating.rated_torque).unwrap();
        let rigid_static = s.first_contact_rotation;
        let moment: f64 = s.pins.iter().map(|q| q.force * q.lever_arm).sum();
        let disc_torque = 0.5 * m.rating.rated_torque * red.twist_factor();
        assert!((moment / disc_torque - 1.0).abs() < 1e-8);
        (
            (s.disc_rotation - s.rigid_rotation) / (s.rigid_rotation - rigid_static),
            s,
        )
    };
    let (real, _) = run(1.0);
    let (stiff, _) = run(1e4);
    eprintln!("body share of the loaded rotation: real {real:.4}, stiff {stiff:.2e}");
    assert!(
        real > 0.05,
        "the real disc body should add to the TE ({real})"
    );
    assert!(stiff.abs() < 2e-3, "stiff disc still differs by {stiff}");
}

/// Flexible discs on their bearings (the default support): at the real modulus the disc body
/// adds to the loaded TE (more than 3 % of the rigid analysis' elastic twist: 4.8 % with the
/// structure of section 5.9) and every loaded pin closes (gap plus body offset equals minus the
/// local approach) to the fixed point's stopping rule, [`FLEX_OFFSET_TOLERANCE`] of the largest
/// offset (the closure is the pin's last offset change); at a modulus x 1e4 (FE body and Hertz law alike) the extra twist over
/// the rigid-disc static analysis is under 0.2 % of its elastic twist.
#[test]
fn flexible_discs_on_bearings_tend_to_the_rigid_static_analysis() {
    let run = |scale: f64| {
        let (m, p, d) = scaled_disc(scale);
        let sa = crate::statics::StaticAnalysis::new(&m.reducer, &p).unwrap();
        let phi = 0.3;
        let psi0 = sa.first_contact(phi, 1.0).unwrap();
        let rigid = sa.solve_from(phi, m.rating.rated_torque, psi0).unwrap();
        let rigid_twist = rigid.twist;
        let (flex, offsets) = solve_flexible_bearings(&sa, &m.reducer, &d, rigid).unwrap();
        let law = FlexibleLaw {
            model: m.reducer.contact,
            patch: m.fem.params.patch,
        };
        // Flexible closure of every loaded pin: rigid gap + body deflection + local approach
        // = 0, the body deflection from the compliance between the pins facing the flank.
        let zp = m.cycloid.geometry.pins;
        let largest = offsets.iter().fold(0.0_f64, |a, o| a.max(o.abs()));
        for (k, disc) in flex.discs.iter().enumerate() {
            let facing: Vec<_> = disc
                .pins
                .iter()
                .filter(|q| q.force > 0.0 || faces_driving_flank(q.profile_parameter))
                .collect();
            let ts: Vec<f64> = facing.iter().map(|q| q.profile_parameter).collect();
            let c = d.compliance_at(k, &ts);
            let n = facing.len();
            for (a, q) in facing.iter().enumerate().filter(|(_, q)| q.force > 0.0) {
                let body: f64 = (0..n).map(|b| c[a * n + b] * facing[b].force).sum();
                let rigid_gap = q.gap - offsets[k * zp + q.pin];
                let closure = rigid_gap + body + law.approach(q.force, q.curvature).0;
                assert!(
                    closure.abs() < 1.01 * FLEX_OFFSET_TOLERANCE * largest,
                    "disc {k} pin {} closure {closure:e}",
                    q.pin
                );
            }
        }
        (flex.twist - rigid_twist) / (rigid_twist - psi0)
    };
    let real = run(1.0);
    let stiff = run(1e4);
    eprintln!("body share of the loaded twist on bearings: real {real:.4}, stiff {stiff:.2e}");
    assert!(
        real > 0.03,
        "the real disc body should add to the TE ({real})"
    );
    assert!(stiff.abs() < 2e-3, "stiff discs still differ by {stiff}");
}

/// With the body compliance in, the flexible contact still satisfies complementarity: every
/// loaded pin closes (total approach = overlap) and no unloaded pin penetrates.
#[test]
fn flexible_contact_is_complementary() {
    let m = model_with(|c| c.fem.crank_angles = 4);
    let p = uniformly_worn(&m, 20e-6);
    let d = DiscModel::build(&p, &m.fem.params).unwrap();
    let red = fixed_centre(&m);
    let sa = crate::statics::StaticAnalysis::new(&red, &p).unwrap();
    let s = solve_flexible(&sa, &d, 0.1, m.rating.rated_torque).unwrap();
    assert!(s.pins.len() >= 3);
    let law = crate::fem::flex::FlexibleLaw {
        model: m.reducer.contact,
        patch: m.fem.params.patch,
    };
    for q in &s.pins {
        let g = crate::contact::pin_geometry(&p, q.pin, 0.1, s.disc_rotation).unwrap();
        let (w, _) = law.approach(q.force, g.curvature);
        let closure = w + q.body_deflection + g.gap;
        assert!(closure.abs() < 1e-11, "pin {} closure {closure:e}", q.pin);
    }
    let loaded: Vec<usize> = s.pins.iter().map(|q| q.pin).collect();
    let ts: Vec<f64> = s.pins.iter().map(|q| q.profile_parameter).collect();
    for j in 0..m.cycloid.geometry.pins {
        if loaded.contains(&j) {
            continue;
        }
        let g = crate::contact::pin_geometry(&p, j, 0.1, s.disc_rotation).unwrap();
        if g.t.rem_euclid(TAU) > PI {
            continue;
        }
        let mut all = ts.clone();
        all.push(g.t);
        let c = d.compliance_at(&all);
        let n = all.len();
        let body: f64 = s
            .pins
            .iter()
            .enumerate()
            .map(|(k, q)| c[(n - 1) * n + k] * q.force)
            .sum();
        assert!(g.gap + body > -1e-11, "open pin {j} penetrates");
    }
}

/// Bad input: holes cutting the teeth or each other, and a mesh too fine for the memory limit,
/// are refused with the key named.
#[test]
fn bad_fem_input_is_refused() {
    let err = |edit: &dyn Fn(&mut Config)| {
        let mut c = Config::paper();
        edit(&mut c);
        c.validate().unwrap_err().to_string()
    };
    let e = err(&|c| c.fem.crank_bore_diameter_mm = Some(40.0));
    assert!(
        e.contains("fem.crank_bore_diameter_mm") && e.contains("cuts the teeth"),
        "{e}"
    );
    let e = err(&|c| c.fem.output_pin_hole_diameter_mm = Some(40.0));
    assert!(
        e.contains("fem.output_pin_hole_diameter_mm") && e.contains("cuts the teeth"),
        "{e}"
    );
    let e = err(&|c| c.fem.output_pin_hole_phase_deg = Some(10.0));
    assert!(e.contains("fem.") && e.contains("cut each other"), "{e}");
    let e = err(&|c| c.fem.centre_hole_diameter_mm = Some(60.0));
    assert!(e.contains("cut each other"), "{e}");
    let e = err(&|c| {
        c.fem.flank_element_size_mm = 0.01;
        c.fem.load_patch_half_width_mm = 0.02;
    });
    assert!(
        e.contains("fem.flank_element_size_mm") && e.contains("GB"),
        "{e}"
    );
    let e = err(&|c| c.fem.load_patch_half_width_mm = 0.1);
    assert!(e.contains("fem.load_patch_half_width_mm"), "{e}");
}

/// Both flanks carry stations: on the new disc the flexible TE in the reverse sense mirrors the
/// forward one (means over a crank revolution at the measuring and the rated torque within
/// 1 %; the disc with its holes is not exactly mirror-symmetric at each crank angle); the
/// flexible backlash equals the rigid play of the same crank angles; the flexible lost motion
/// exceeds the rigid one (the body adds twist on both sides) and the flexible torsional
/// stiffness is below the rigid one, on the new disc and at 7500 h; the flexible hysteresis
/// curve rises with the torque; every loaded pin of a reverse solution closes (to the fixed
/// point's stopping rule, as in `flexible_discs_on_bearings_tend_to_the_rigid_static_analysis`).
#[test]
fn flexible_disc_has_both_senses() {
    for hours in [0.0, 7500.0] {
        let mut m = model_with(|c| c.fem.crank_angles = 12);
        let profile = if hours == 0.0 {
            m.profile().unwrap()
        } else {
            m.wear.stage_hours = vec![hours];
            let hist = crate::wear::integrate(&m.wear_inputs(), &|_, _| {}).unwrap();
            m.cycloid
                .profile(Some(WearMap::new(hist.maps[0].clone()).unwrap()))
                .unwrap()
        };
        let d = DiscSet::build(&profile, &m.fem.params, &m.reducer).unwrap();
        let st = analyse_stage(&profile, &m.reducer, &d, m.rating.rated_torque).unwrap();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64 * ARCMIN_PER_RAD;
        let (ste, ste_r) = (mean(&st.flexible_ste), mean(&st.flexible_ste_reverse));
        let (te, te_r) = (
            mean(&st.flexible_loaded_te),
            mean(&st.flexible_loaded_te_reverse),
        );
        let backlash = mean(&st.rigid_ste) - mean(&st.rigid_ste_reverse);
        let lost = ste - ste_r;
        // The rigid model's catalogue quantities at the same crank angles.
        let sa = crate::statics::StaticAnalysis::new(&m.reducer, &profile).unwrap();
        let (mut rigid_lost, mut rigid_a) = (0.0, 0.0);
        let t_m = st.ste_torque;
        for &phi in &st.crank_angle {
            let f0 = sa.first_contact(phi, 1.0).unwrap();
            let r0 = sa.first_contact(phi, -1.0).unwrap();
            let twist = |t: f64, psi0: f64| sa.solve_from(phi, t, psi0).unwrap().twist;
            let (mp, mn) = (twist(t_m, f0), twist(-t_m, r0));
            let (rp, rn) = (
                twist(m.rating.rated_torque, f0),
                twist(-m.rating.rated_torque, r0),
            );
            rigid_lost += (mp - mn) * ARCMIN_PER_RAD;
            rigid_a += 0.5 * ((rp - mp) + (mn - rn)) * ARCMIN_PER_RAD;
        }
        let k = st.crank_angle.len() as f64;
        let (rigid_lost, rigid_stiffness) = (
            rigid_lost / k,
            (m.rating.rated_torque - t_m) / (rigid_a / k),
        );
        let stiffness = st.torsional_stiffness / ARCMIN_PER_RAD;
        eprintln!(
            "{hours} h: flexible STE {ste:.4} / {ste_r:.4}, loaded TE {te:.4} / {te_r:.4} arcmin; \
             backlash {backlash:.4}; lost motion flexible {lost:.4}, rigid {rigid_lost:.4}; \
             stiffness flexible {stiffness:.1}, rigid {rigid_stiffness:.1} N m/arcmin"
        );
        if hours == 0.0 {
            assert!((ste + ste_r).abs() < 0.01 * ste, "STE {ste} vs {ste_r}");
            assert!((te + te_r).abs() < 0.01 * te, "loaded TE {te} vs {te_r}");
            assert!(backlash.abs() < 1e-6, "new disc backlash {backlash}");
        }
        assert!(
            lost > rigid_lost,
            "lost motion {lost} vs rigid {rigid_lost}"
        );
        assert!(
            stiffness < rigid_stiffness,
            "stiffness {stiffness} vs rigid {rigid_stiffness}"
        );
        for w in st.hysteresis_twist.windows(2) {
            assert!(
                w[1] > w[0],
                "hysteresis curve not rising: {:?}",
                st.hysteresis_twist
            );
        }
        assert_eq!(st.hysteresis_torque.len(), st.hysteresis_twist.len());
        // A reverse solution closes every loaded pin on the other flank.
        let phi = 0.3;
        let psi0 = sa.first_contact(phi, -1.0).unwrap();
        let rigid = sa.solve_from(phi, -m.rating.rated_torque, psi0).unwrap();
        let (flex, offsets) = solve_flexible_bearings(&sa, &m.reducer, &d, rigid).unwrap();
        assert!(flex.twist < 0.0);
        let law = FlexibleLaw {
            model: m.reducer.contact,
            patch: m.fem.params.patch,
        };
        let zp = m.cycloid.geometry.pins;
        let largest = offsets.iter().fold(0.0_f64, |a, o| a.max(o.abs()));
        for (k, disc) in flex.discs.iter().enumerate() {
            let facing: Vec<_> = disc
                .pins
                .iter()
                .filter(|q| q.force > 0.0 || faces_loaded_flank(q.profile_parameter, -1.0))
                .collect();
            let ts: Vec<f64> = facing.iter().map(|q| q.profile_parameter).collect();
            let c = d.compliance_at(k, &ts);
            let n = facing.len();
            for (a, q) in facing.iter().enumerate().filter(|(_, q)| q.force > 0.0) {
                let body: f64 = (0..n).map(|b| c[a * n + b] * facing[b].force).sum();
                let closure =
                    q.gap - offsets[k * zp + q.pin] + body + law.approach(q.force, q.curvature).0;
                assert!(
                    closure.abs() < 1.01 * FLEX_OFFSET_TOLERANCE * largest,
                    "reverse: disc {k} pin {} closure {closure:e}",
                    q.pin
                );
            }
        }
    }
}

/// Disc 2 of the RV reducer is disc 1's part turned by pi: its contacts sit on disc 1's FE
/// model `(Zc + 1) / 2` teeth round ([`crate::fem::Mount`]). The mapping is the geometry's
/// (the profile point of the model's parameter is the disc's point turned by the mount's
/// rotation, at 40 parameters), and the compliance it gives equals that of a model meshed
/// with the holes turned against the profile as disc 2 has them (the other way of modelling
/// the same part; the meshes differ, so within 0.5 % of the largest entry). Three crank bores
/// have no such symmetry: no mount.
#[test]
fn disc_two_is_disc_one_turned_by_pi() {
    use crate::fem::{mount_teeth, DiscSet};
    let m = model_with(|c| c.fem.crank_angles = 4);
    let p = uniformly_worn(&m, 10e-6);
    let zc = m.cycloid.geometry.disc_teeth();
    let turn = m.reducer.profile_turn(1);
    let set = DiscSet::build(&p, &m.fem.params, &m.reducer).unwrap();
    assert_eq!(set.models.len(), 1, "one model serves both discs");
    let (_, mount) = set.disc(1);
    assert_eq!(mount.teeth.rem_euclid(zc as isize), (zc as isize + 1) / 2);
    assert_eq!(set.disc(0).1.teeth, 0);
    for k in 0..40 {
        let t = TAU * zc as f64 * k as f64 / 40.0 + 0.37;
        let on_model = p.point(mount.parameter(t)).p;
        let turned = mount.model_frame(&p.point(t).p);
        assert!(
            (on_model - turned).norm() < 1e-12,
            "t {t}: {on_model:?} vs {turned:?}"
        );
    }
    // The same part modelled directly: holes turned by -turn against the profile.
    let mut params = m.fem.params.clone();
    for h in params.bores.iter_mut().chain(params.holes.iter_mut()) {
        h.centre = crate::geometry::rotate(&h.centre, -turn);
    }
    let direct = DiscModel::build(&p, &params).unwrap();
    // Contacts on the driving flanks of the teeth a loaded disc 2 touches at crank angle 0.
    let ts: Vec<f64> = (0..12)
        .map(|j| TAU * j as f64 + 0.3 + 0.2 * (j % 3) as f64)
        .collect();
    let a = set.compliance_at(1, &ts);
    let b = direct.compliance_at(&ts);
    let largest = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(&b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!(
        "disc 2 compliance, mounted vs direct: {:.2e} of the largest",
        worst / largest
    );
    assert!(worst < 5e-3 * largest, "{worst:e} of {largest:e}");
    // Disc 1's model read without the mount differs from both by more than that.
    let unmounted = set.models[0].compliance_at(&ts);
    let off = unmounted
        .iter()
        .zip(&b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!(
        "disc 1's model at disc 2's parameters: {:.2e} of the largest",
        off / largest
    );
    // Three crank bores (120 deg apart) are not symmetric under pi.
    let mut three = m.fem.params.clone();
    let r = three.bores[0].centre.norm();
    three.bores = (0..3)
        .map(|k| crate::fem::Hole {
            centre: crate::geometry::Vec2::new(
                r * (TAU * k as f64 / 3.0).cos(),
                r * (TAU * k as f64 / 3.0).sin(),
            ),
            radius: three.bores[0].radius,
        })
        .collect();
    three.holes.clear();
    assert_eq!(mount_teeth(zc, turn, &three), None);
    assert_eq!(mount_teeth(zc, 0.0, &three), Some(0));
}

/// The station compliance condensed over the elimination-tree reach of each load (`C = Y^T Y`)
/// equals `B K^-1 B^T` from full solves of the factor, column by column, to round-off (1e-12 of
/// the largest diagonal term), and is symmetric.
#[test]
fn condensed_compliance_equals_full_solves() {
    let m = model_with(|_| {});
    let p = uniformly_worn(&m, 10e-6);
    let d = DiscModel::build(&p, &m.fem.params).unwrap();
    let n = d.stations();
    let neq = d.fe.equations();
    let scale = (0..n).map(|i| d.compliance[i * n + i]).fold(0.0, f64::max);
    let mut worst: f64 = 0.0;
    // Every 13th station (both flanks, teeth all round) against every station.
    for col in (0..n).step_by(13) {
        let mut rhs = faer::Mat::<f64>::zeros(neq, 1);
        for &(q, v) in &d.station_loads[col] {
            rhs[(q, 0)] += v;
        }
        d.fe.solve_reduced(&mut rhs);
        for i in 0..n {
            let direct: f64 = d.station_loads[i]
                .iter()
                .map(|&(q, v)| v * rhs[(q, 0)])
                .sum();
            worst = worst.max((direct - d.compliance[i * n + col]).abs() / scale);
            assert_eq!(d.compliance[i * n + col], d.compliance[col * n + i]);
        }
    }
    eprintln!("largest difference {worst:.2e} of the largest diagonal term");
    assert!(worst < 1e-12, "condensed compliance off by {worst:e}");
}

/// Profile parameter near the closest point of `profile` to `x` (within a few thousandths of a
/// tooth): the sample of 2000 per tooth with the nearest polar angle (the outline is
/// star-shaped about the centre).
fn parameter_near(profile: &crate::geometry::Profile, x: &Vec2) -> f64 {
    let zc = profile.geometry().disc_teeth();
    let n = 2000 * zc;
    let dt = TAU * zc as f64 / n as f64;
    let a = x.y.atan2(x.x);
    (0..n)
        .map(|k| k as f64 * dt)
        .min_by(|&s, &t| {
            let d = |t: f64| {
                let p = profile.point(t).p;
                let e = p.y.atan2(p.x) - a;
                (e + PI).rem_euclid(TAU) - PI
            };
            d(s).abs().total_cmp(&d(t).abs())
        })
        .unwrap()
}

/// The unworn disc's mesh moved onto a worn outline ([`crate::fem::morph_mesh`]): the same
/// elements; every outline node of two teeth as far from the worn profile as it was from the
/// unworn one (vertices of the outline polygon on the curve, nodes on its chords off it by the
/// chord sag, about 1.6 um, which the wear changes by about 1 % with the radius of curvature:
/// within 10 nm); and station compliances within 2 % of the largest diagonal term (1.1 %
/// measured; the 0.25 and 0.125 mm meshes differ by up to 1 %) and the flexible loaded TE
/// within 0.05 % (2e-5 measured) of a fresh mesh of the worn profile: two discretisations of
/// one disc. The uniform
/// wear of 60 um is the example's largest depth.
#[test]
#[cfg_attr(
    target_family = "wasm",
    ignore = "the flexible (FE) disc is not in the web build's page: run natively"
)]
fn morphed_mesh_matches_a_fresh_mesh_of_the_worn_disc() {
    let m = model_with(|c| c.fem.crank_angles = 8);
    let new = m.profile().unwrap();
    let worn = uniformly_worn(&m, 60e-6);
    let base = DiscSet::build(&new, &m.fem.params, &m.reducer).unwrap();
    let morphed = DiscSet::build_morphed(&worn, &m.fem.params, &m.reducer, &base, &new).unwrap();
    let fresh = DiscSet::build(&worn, &m.fem.params, &m.reducer).unwrap();
    let (mb, mm) = (&base.models[0].fe.mesh, &morphed.models[0].fe.mesh);
    assert_eq!(mb.triangles, mm.triangles, "the morph keeps the elements");
    assert_eq!(mb.nodes.len(), mm.nodes.len());
    let pitch = TAU / new.geometry().disc_teeth() as f64;
    let mut worst: f64 = 0.0;
    let mut count = 0;
    for e in mm.boundary.iter().filter(|e| e.kind == LoopKind::Outline) {
        for &i in &e.nodes {
            let (xb, xm) = (mb.nodes[i], mm.nodes[i]);
            if xb.y.atan2(xb.x).rem_euclid(TAU) > 2.0 * pitch {
                continue;
            }
            let db = new
                .project(&xb, parameter_near(&new, &xb))
                .unwrap()
                .distance;
            let dm = worn
                .project(&xm, parameter_near(&worn, &xm))
                .unwrap()
                .distance;
            worst = worst.max((db - dm).abs());
            count += 1;
        }
    }
    eprintln!("{count} outline nodes: distance to the profile kept within {worst:.2e} m");
    assert!(count > 40);
    assert!(
        worst < 1e-8,
        "an outline node moved off the worn outline by {worst:e} m"
    );
    let (cm, cf) = (&morphed.models[0], &fresh.models[0]);
    let n = cm.stations();
    let mut worst: f64 = 0.0;
    for i in 0..n {
        let scale = cf.compliance[i * n + i];
        for k in [
            i,
            (i + 1) % n,
            (i + 2 * m.fem.params.stations_per_flank) % n,
        ] {
            worst = worst.max((cm.compliance[i * n + k] - cf.compliance[i * n + k]).abs() / scale);
        }
    }
    let te = |d: &DiscSet| {
        let st = analyse_stage(&worn, &m.reducer, d, m.rating.rated_torque).unwrap();
        st.flexible_loaded_te.iter().sum::<f64>() / st.flexible_loaded_te.len() as f64
    };
    let (te_m, te_f) = (te(&morphed), te(&fresh));
    eprintln!(
        "compliance {worst:.2e}; loaded TE {:.6} vs {:.6} arcmin",
        te_m * ARCMIN_PER_RAD,
        te_f * ARCMIN_PER_RAD
    );
    assert!(worst < 0.02, "compliance differs by {worst}");
    assert!((te_m / te_f - 1.0).abs() < 5e-4);
}

/// On the morphed meshes the flexible results follow the wear smoothly and reproducibly: the
/// flexible loaded TE over 7 uniform wear depths from 0 to 12 um (2 um apart) has second
/// differences below a tenth of its first differences; and a wear map 1e-12 m deeper gives the
/// TE its wear slope predicts (2.5e-8 of it; within 1e-7) and the same disc stress (within
/// 1e-6), where a fresh Delaunay refinement of the two
/// profiles may add or drop nodes and move the node-averaged stress maximum by per cent.
#[test]
fn flexible_results_follow_the_wear_smoothly() {
    let m = model_with(|c| c.fem.crank_angles = 8);
    let new = m.profile().unwrap();
    let base = DiscSet::build(&new, &m.fem.params, &m.reducer).unwrap();
    let run = |w: f64| {
        let p = uniformly_worn(&m, w);
        let d = DiscSet::build_morphed(&p, &m.fem.params, &m.reducer, &base, &new).unwrap();
        assert_eq!(
            d.models[0].fe.mesh.triangles,
            base.models[0].fe.mesh.triangles
        );
        let st = analyse_stage(&p, &m.reducer, &d, m.rating.rated_torque).unwrap();
        let te = st.flexible_loaded_te.iter().sum::<f64>() / st.flexible_loaded_te.len() as f64;
        (te, st.stress.max_von_mises)
    };
    let te: Vec<f64> = (0..7).map(|k| run(2e-6 * k as f64 + 1e-9).0).collect();
    let d1: Vec<f64> = te.windows(2).map(|w| w[1] - w[0]).collect();
    let d2 = d1
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0, f64::max);
    let size = d1.iter().map(|x| x.abs()).fold(f64::INFINITY, f64::min);
    eprintln!(
        "loaded TE {:?} arcmin; largest second difference {d2:.3e}, smallest first {size:.3e}",
        te.iter().map(|x| x * ARCMIN_PER_RAD).collect::<Vec<_>>()
    );
    assert!(d2 < 0.1 * size, "loaded TE not smooth in the wear: {te:?}");
    let (a, b) = (run(20e-6), run(20e-6 + 1e-12));
    eprintln!(
        "20 um and 1e-12 m more: TE {:e}, stress {:e} apart",
        a.0 / b.0 - 1.0,
        a.1 / b.1 - 1.0
    );
    assert!((a.0 / b.0 - 1.0).abs() < 1e-7);
    assert!((a.1 / b.1 - 1.0).abs() < 1e-6);
}

/// The built-in disc is meshed alike on every platform, node for node, and its flexible TE
/// agrees to round-off: this test runs natively (`cargo test`) and in the library's WebAssembly
/// build (`scripts/wasm-tests`), against the same recorded figures. The mesh's inputs come from
/// `geometry::portable` (docs/model.md section 9.1); with the platform's own `sin` and `cos` the
/// refinement turned on their last bits (20 100 nodes natively, 20 108 in WebAssembly, the
/// flexible TE 1e-5 apart). The figures change only with the mesh or the flexible model: record
/// them anew then.
#[test]
fn the_disc_is_meshed_alike_on_every_platform() {
    let bits = |v: &[f64]| {
        v.iter().fold(0xcbf2_9ce4_8422_2325_u64, |a, x| {
            (a ^ x.to_bits()).wrapping_mul(0x0100_0000_01b3)
        })
    };
    let mut c = Config::example();
    c.fem.enabled = true;
    let m = c.validate().unwrap();
    let profile = m.profile().unwrap();
    let d = DiscSet::build(&profile, &m.fem.params, &m.reducer).unwrap();
    let nodes: Vec<f64> = d.models[0]
        .fe
        .mesh
        .nodes
        .iter()
        .flat_map(|n| [n.x, n.y])
        .collect();
    assert_eq!(nodes.len() / 2, 20_108, "the example's node count");
    assert_eq!(
        bits(&nodes),
        0xa298_54b4_2337_83ae,
        "the example's node coordinates"
    );
    let st = analyse_stage(&profile, &m.reducer, &d, m.rating.rated_torque).unwrap();
    // Recorded natively; the WebAssembly build gave the same within 3.3e-13.
    let recorded = [
        (st.flexible_ste[0], 1.057_002_217_473_631_3e-4),
        (st.flexible_loaded_te[0], 8.475_158_502_233_097e-4),
        (st.torsional_stiffness, 5.271_183_893_896_517e5),
    ];
    for (got, want) in recorded {
        assert!(
            ((got - want) / want).abs() < 1e-9,
            "{got:e} against the recorded {want:e}"
        );
    }
}
