//! The disc's body and its crank bores as compliances in series with the crank-disc bearings,
//! for the static analysis (docs/model.md section 5.13).
//!
//! The static analysis holds the disc rigid beyond the contact law's depth term. Two parts of
//! its elastic twist are then missing: the disc's body between the pins' contacts and the
//! bores (the flexible disc of [`super::flex`] has it, but only for its own results), and the
//! bores' ovalisation under the needles' pressure (nowhere: the FE disc holds its bores with
//! rigid spiders). Both are found here from the strain energy of the disc with the holes of
//! `[fem]`, on a coarser mesh ([`COARSE_FLANK_PER_PITCH`]), under the pins' loads of the static
//! analysis at the rated torque, and each is given as the compliance
//! `s` of a spring in series with each crank-disc bearing that stores the same energy under
//! the bearings' forces, `s = W / sum_k |F_k|^2` (`W = f . u`, twice the strain energy):
//!
//! - **body**, `s_b`: the disc with its bores held by rigid spiders (translations held, turning
//!   free, as in the FE disc), loaded by the pins' forces as elliptic pressure patches of
//!   half-width `w` (as the FE disc loads them); minus, per contact, the law's own disc term
//!   from `w` down to its reference depth (`ContactModel::disc_depth_compliance`), which the
//!   patch's mean displacement holds again. That energy holds the pins' loads fixed and so
//!   overstates the body; `s_b` is then scaled until the static analysis gives the flexible
//!   discs' mean twist ([`series_compliances`]). The flexible analyses run without it (the FE
//!   disc is the body: [`crate::reducer::Reducer::without_disc_body`]).
//! - **bores**, `s_o`: the same disc free, held only against rigid motion (three node
//!   components), loaded by the pins' forces and, on each bore, the bearing's force as the
//!   classic cosine pressure over the loaded half (`p = 2|F|/(pi R B) cos theta`, Stribeck's
//!   zero-clearance distribution; Harris & Kotzalas, *Rolling Bearing Analysis*, 5th ed.,
//!   section 7.2), the bores' forces balancing the pins' force and moment (the pins' resultant
//!   shared equally, their moment as equal tangential forces); minus the body's energy. For
//!   balanced loads `f . u` does not depend on how the body is held.
//!
//! Means over crank angles of a crank revolution of disc 1 (the loads move once round the
//! disc relative to its bores). The pins' loads are those of the static analysis without
//! these two parts; they change with them by a few per cent, which changes `s` by less.

use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use super::flex::solve_flexible_bearings;
use super::mesh::{LoopKind, Mesh};
use super::plane::{FeModel, NodeBc};
use super::{DiscModel, DiscSet, FemParams};
use crate::error::{Error, Result};
use crate::geometry::{Profile, Vec2};
use crate::reducer::structure::SeriesCompliances;
use crate::reducer::Reducer;
use crate::statics::{PinLoad, StaticAnalysis};

/// Crank angles over one crank revolution at which the disc's energy is taken.
pub const CRANK_ANGLES: usize = 8;

/// The disc's compliances in series with each crank-disc bearing, m/N.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DiscCompliance {
    /// The disc's body beyond the contact law's depth term, `s_b`.
    pub body: f64,
    /// The bores' ovalisation, `s_o`.
    pub bores: f64,
}

/// The disc's energies under one set of pin loads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Energies {
    /// `f . u` with the bores held by rigid spiders, J.
    pub held: f64,
    /// `f . u` with the bores loaded by the bearings' cosine pressures, J.
    pub free: f64,
    /// The contact law's disc term from the patch down to its depth, `sum F^2 c_d`, J.
    pub law: f64,
    /// `sum_k |F_k|^2` of the bores' forces, N^2.
    pub bore_forces: f64,
}

/// The disc of an FE disc model as two FE models: its bores held by the model's rigid
/// spiders (the model itself), and free.
pub(crate) struct DiscBody<'a> {
    model: &'a DiscModel,
    free: FeModel,
}

impl<'a> DiscBody<'a> {
    /// The free disc on `model`'s mesh, held along `axis` (0: x, 1: y; [`hold`]), factorised.
    ///
    /// # Errors
    /// Solver failures (`Error::Numerical`).
    pub(crate) fn new(model: &'a DiscModel, axis: usize) -> Result<DiscBody<'a>> {
        let mesh = &model.fe.mesh;
        let free = FeModel::new(
            mesh.clone(),
            model.params.material,
            &hold(mesh, axis),
            Vec::new(),
        )?;
        Ok(DiscBody { model, free })
    }

    /// The mesh (both models share it).
    fn mesh(&self) -> &Mesh {
        &self.model.fe.mesh
    }

    /// The disc's energies under the pins' loads `pins` (the profile frame of the disc of
    /// `params`; forces into the disc along `-normal`), with the contact law `law`.
    pub(crate) fn energies(
        &self,
        pins: &[PinLoad],
        law: &crate::contact::ContactModel,
    ) -> Energies {
        let mesh = self.mesh();
        let n = mesh.nodes.len();
        let params = &self.model.params;
        let w = params.patch;
        let thickness = params.material.thickness;
        let mut load = vec![0.0; 2 * n];
        let mut law_energy = 0.0;
        for p in pins.iter().filter(|p| p.force > 0.0) {
            let unit = self.model.patch_load(&p.point, &(-p.normal));
            for (i, v) in unit {
                load[i] += p.force * v;
            }
            law_energy += p.force * p.force * law.disc_depth_compliance(p.curvature, w);
        }
        let work = |u: &[f64], f: &[f64]| u.iter().zip(f).map(|(a, b)| a * b).sum::<f64>();
        let held = work(&self.model.fe.solve(&load), &load);
        // The bores' forces: the pins' resultant shared equally, their moment about the disc
        // centre as equal tangential forces.
        let (mut resultant, mut moment) = (Vec2::zeros(), 0.0);
        for i in 0..n {
            let f = Vec2::new(load[2 * i], load[2 * i + 1]);
            resultant += f;
            moment += cross(&mesh.nodes[i], &f);
        }
        let bores = &params.bores;
        let m = bores.len() as f64;
        let mean_centre = bores.iter().map(|b| b.centre).sum::<Vec2>() / m;
        let radii: f64 = bores.iter().map(|b| b.centre.norm()).sum();
        let tangential = (-moment + cross(&mean_centre, &resultant)) / radii;
        let mut bore_forces = 0.0;
        for (k, b) in bores.iter().enumerate() {
            let c = b.centre;
            let t = Vec2::new(-c.y, c.x) / c.norm();
            let f = -resultant / m + t * tangential;
            bore_forces += f.norm_squared();
            for (i, v) in bore_pressure(mesh, k, b.centre, b.radius, thickness, &f) {
                load[i] += v;
            }
        }
        let free = work(&self.free.solve(&load), &load);
        Energies {
            held,
            free,
            law: law_energy,
            bore_forces,
        }
    }
}

/// `a x b` (z component).
fn cross(a: &Vec2, b: &Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Boundary conditions that hold the free disc against rigid motion only: the node furthest
/// in `-x` (`axis` 0; `-y` for 1) held in both components, the node furthest in `+x` (`+y`)
/// across that axis.
fn hold(mesh: &Mesh, axis: usize) -> Vec<NodeBc> {
    let mut bc = vec![NodeBc::Free; mesh.nodes.len()];
    let along = |i: usize| mesh.nodes[i][axis.min(1)];
    let order = |a: &usize, b: &usize| along(*a).total_cmp(&along(*b));
    let lo = (0..mesh.nodes.len()).min_by(order).unwrap_or(0);
    let hi = (0..mesh.nodes.len()).max_by(order).unwrap_or(0);
    bc[lo] = NodeBc::Fixed(Some(0.0), Some(0.0));
    bc[hi] = if axis == 0 {
        NodeBc::Fixed(None, Some(0.0))
    } else {
        NodeBc::Fixed(Some(0.0), None)
    };
    bc
}

/// Nodal loads (`(node dof, N)`) of the force `force` (N) that a bearing's rollers press on
/// bore `k` (centre `centre`, radius `radius`, m): the cosine pressure
/// `p0 cos theta` normal to the bore over the half facing `force`, scaled so that its
/// resultant along `force` is exactly `|force|`.
fn bore_pressure(
    mesh: &Mesh,
    k: usize,
    centre: Vec2,
    radius: f64,
    thickness: f64,
    force: &Vec2,
) -> Vec<(usize, f64)> {
    let size = force.norm();
    if size <= 0.0 {
        return Vec::new();
    }
    let dir = force / size;
    let edges =
        (0..mesh.boundary.len()).filter(|&e| mesh.boundary[e].kind == LoopKind::CrankBore(k));
    let p0 = 2.0 * size / (PI * radius * thickness);
    let mut load = super::plane::traction_load(mesh, thickness, edges, |x| {
        let n = (x - centre) / (x - centre).norm();
        let c = n.dot(&dir);
        (c > 0.0).then(|| n * (p0 * c))
    });
    super::plane::scale_to_resultant(&mut load, &dir, size);
    load
}

/// The FE disc of `params` made coarser for the body's compliances, which need one number
/// per disc, not the load stations' detail: at least [`COARSE_FLANK_PER_PITCH`] of the pins'
/// pitch `2 pi Rp/Zp` along the outline (0.72 mm on the example), load patches at least twice
/// that half-width, at most 8 stations per flank (the same holes, material and largest
/// element). On the example its `b/a` equals the one of `[fem]`'s mesh (0.25 mm) to 0.1 N
/// m/arcmin.
fn coarse(params: &FemParams, pitch: f64) -> FemParams {
    let flank = params.flank_size.max(COARSE_FLANK_PER_PITCH * pitch);
    FemParams {
        flank_size: flank,
        max_size: params.max_size.max(flank),
        patch: params.patch.max(2.0 * flank),
        stations_per_flank: params.stations_per_flank.min(8),
        ..params.clone()
    }
}

/// Outline element of the body's FE disc per pin pitch ([`coarse`]).
pub const COARSE_FLANK_PER_PITCH: f64 = 1.0 / 14.0;

/// The disc's compliances in series with each crank-disc bearing of `reducer` (an RV reducer
/// on bearings, without either part) with the disc `profile` of `params`, under `torque`
/// (N m, the rated torque), from [`CRANK_ANGLES`] crank angles of a revolution:
///
/// - the bores' part from disc 1's energies, `s_o = sum (free - held) / sum |F_k|^2`;
/// - the body's part such that the static analysis with it (and `s_o`) gives the mean
///   elastic twist of the flexible discs on their bearings ([`super::flex`], with `s_o`):
///   starting from the energy estimate `sum (held - law) / sum |F_k|^2`, which holds the pins'
///   loads fixed and so overstates it (the flexible body shares the load out over more pins),
///   scaled by the ratio of the flexible discs' extra twist to the one it gives, twice.
///
/// Each at least 0, rounded to three significant digits ([`significant`]).
///
/// # Errors
/// The static and flexible analyses' and the FE models' failures; [`Error::Numerical`] for a
/// non-finite compliance.
pub fn series_compliances(
    reducer: &Reducer,
    profile: &Profile,
    params: &FemParams,
    torque: f64,
) -> Result<DiscCompliance> {
    let geometry = &reducer.geometry;
    let params = &coarse(
        params,
        TAU * geometry.pin_circle_radius / geometry.pins as f64,
    );
    let discs = DiscSet::build(profile, params, reducer)?;
    let (model, mount) = discs.disc(0);
    if mount.teeth != 0 || mount.rotation != 0.0 {
        return Err(Error::numerical(
            "disc body",
            "disc 1 is not the FE model's own disc (its profile is turned against its holes)",
        ));
    }
    let body = DiscBody::new(model, 0)?;
    let sa = StaticAnalysis::new(reducer, profile)?;
    let phis: Vec<f64> = (0..CRANK_ANGLES)
        .map(|i| TAU * i as f64 / CRANK_ANGLES as f64)
        .collect();
    let (mut body_sum, mut bore_sum, mut forces) = (0.0, 0.0, 0.0);
    for &phi in &phis {
        let sol = sa.solve(phi, torque)?;
        let e = body.energies(&sol.discs[0].pins, &reducer.contact);
        body_sum += e.held - e.law;
        bore_sum += e.free - e.held;
        forces += e.bore_forces;
    }
    let bores = (bore_sum / forces).max(0.0);
    let with = |body: f64| {
        let mut r = reducer.clone();
        r.set_series(SeriesCompliances {
            disc_body: body,
            disc_bores: bores,
            ..reducer.series
        });
        r
    };
    let base = with(0.0);
    let sa = StaticAnalysis::new(&base, profile)?;
    let twists = |sa: &StaticAnalysis| -> Result<Vec<f64>> {
        phis.par_iter()
            .map(|&phi| Ok(sa.solve(phi, torque)?.twist))
            .collect()
    };
    let rigid = twists(&sa)?;
    let flexible: f64 = phis
        .par_iter()
        .map(|&phi| {
            let start = sa.solve(phi, torque)?;
            Ok(solve_flexible_bearings(&sa, &base, &discs, start)?.0.twist)
        })
        .collect::<Result<Vec<f64>>>()?
        .iter()
        .zip(&rigid)
        .map(|(f, r)| f - r)
        .sum();
    let mut compliance = (body_sum / forces).max(0.0);
    for _ in 0..2 {
        if compliance <= 0.0 || flexible <= 0.0 {
            break;
        }
        let red = with(compliance);
        let extra: f64 = twists(&StaticAnalysis::new(&red, profile)?)?
            .iter()
            .zip(&rigid)
            .map(|(t, r)| t - r)
            .sum();
        if extra <= 0.0 {
            break;
        }
        compliance *= flexible / extra;
    }
    let out = DiscCompliance {
        body: significant(if flexible > 0.0 { compliance } else { 0.0 }),
        bores: significant(bores),
    };
    if !(out.body.is_finite() && out.bores.is_finite()) {
        return Err(Error::numerical(
            "disc body",
            format!(
                "its compliance is not finite ({:e}, {:e} m/N)",
                out.body, out.bores
            ),
        ));
    }
    Ok(out)
}

/// `x` rounded to [`SIGNIFICANT_DIGITS`] significant digits (by the decimal formatting of Rust's
/// core library, the same on every platform): the body's compliance comes from iterative
/// flexible solves whose last bits follow the platform's maths library (1e-5 relative between
/// the native build and the web page's WebAssembly); rounded, both give the same model.
fn significant(x: f64) -> f64 {
    format!("{:.*e}", SIGNIFICANT_DIGITS - 1, x)
        .parse()
        .unwrap_or(x)
}

/// Significant digits of the disc's compliances ([`significant`]): 0.5 % of a compliance at
/// most, 0.02 % of the example's twist.
const SIGNIFICANT_DIGITS: usize = 3;

/// [`series_compliances`] remembered for the last [`MEMO_SIZE`] distinct inputs of this
/// process (keyed by a hash of their debug form): the web page validates its config at every
/// edit, and most edits (a switch, the wear schedule, the spec) leave the disc's inputs as
/// they were. A pure function's results: the same inputs give the same compliances either way.
///
/// # Errors
/// As [`series_compliances`].
pub fn series_compliances_memoised(
    reducer: &Reducer,
    profile: &Profile,
    params: &FemParams,
    torque: f64,
) -> Result<DiscCompliance> {
    use std::hash::{Hash, Hasher};
    use std::sync::{Mutex, OnceLock};
    static MEMO: OnceLock<Mutex<Vec<(u64, DiscCompliance)>>> = OnceLock::new();
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!(
        "{reducer:?}{:?}{:?}{params:?}{torque:e}",
        profile.geometry(),
        profile.modification()
    )
    .hash(&mut h);
    let key = h.finish();
    let memo = MEMO.get_or_init(|| Mutex::new(Vec::new()));
    if let Some(&(_, c)) = memo
        .lock()
        .ok()
        .and_then(|m| m.iter().find(|(k, _)| *k == key).copied())
        .as_ref()
    {
        return Ok(c);
    }
    let c = series_compliances(reducer, profile, params, torque)?;
    if let Ok(mut m) = memo.lock() {
        if m.len() >= MEMO_SIZE {
            m.remove(0);
        }
        m.push((key, c));
    }
    Ok(c)
}

/// Inputs [`series_compliances_memoised`] remembers.
const MEMO_SIZE: usize = 16;
