//! The cycloid disc as a finite-element body (paper section 3.3, the rigid-flexible model;
//! docs/model.md section 9): a 2D plane-stress model of the actual (worn) disc with its crank
//! bearing bores, output-pin holes and centre hole, meshed by constrained Delaunay refinement
//! ([`mesh`]), solved with quadratic triangles and a sparse Cholesky factor ([`plane`]), and
//! condensed onto the loaded tooth flanks as a compliance matrix between *load stations*
//! ([`DiscModel`]). [`flex`] solves the loaded contact with body and Hertz compliance together.
//!
//! Conventions: the disc frame of [`crate::geometry`]; crank bore `k` is centred at angle
//! `2 pi k / cranks` on the crank circle; output-pin hole `k` at `phase + 2 pi k / holes`. Each
//! bore is tied to its crank centre by a rigid spider whose translations are held and whose
//! rotation is free (the bearing lets the disc turn on the eccentric; the paper's rigid point at
//! the bore nodes with the z rotation released). The disc's rigid rotation is the contact
//! solver's `beta`, so the FE displacements are the elastic part relative to the bores.
//!
//! **Load stations.** A pin load is applied as a Hertz-shaped (elliptic) pressure of fixed
//! half-width `w` (`load_patch_half_width_mm`) on the outline, and the matching displacement is
//! the work-conjugate mean of the normal displacement under it, so the compliance converges
//! under mesh refinement (a point load's does not, in 2D). The local contact compliance inside
//! the patch comes from the Hertz law instead, with the disc's depth term cut at `w`
//! ([`flex::FlexibleLaw`]). Stations sit at equal arc length along the driving flank
//! (`0 < mesh angle < pi`)
//! and on the other flank of every tooth (so that both senses of torque, backlash and lost
//! motion have a flexible disc); compliances between arbitrary contact points are Catmull-Rom
//! interpolated between the stations of the flank they lie on (diagonal terms along the
//! diagonal). The compliance `C = B K^-1 B^T` is condensed with forward solves that visit only
//! the elimination-tree reach of each station's load, `C = Y^T Y` (`plane::Factor::condense`:
//! 0.2 s for the example's 1092 stations on 39 530 equations, where full solves took 1.5 s).
//!
//! **Worn stages.** A study meshes the unworn disc once and moves that mesh onto each worn
//! outline (`morph_mesh`, `DiscSet::build_morphed`): the same elements and sparsity pattern
//! (the symbolic factorisation is shared), and results that change smoothly with the wear,
//! where a fresh refinement of a profile that differs by picometres can add or drop nodes.

pub mod body;
pub mod flex;
pub mod mesh;
pub mod modal;
pub mod plane;

use std::f64::consts::{PI, TAU};

use rayon::prelude::*;

use crate::error::Result;
use crate::geometry::{Profile, Vec2};
use mesh::{BoundaryLoop, LoopKind, Mesh, MeshSpec};
use plane::{FeModel, NodeBc, PlaneStress, Spider};

/// A circular hole of the disc, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hole {
    /// Centre in the disc frame, m.
    pub centre: Vec2,
    /// Radius, m.
    pub radius: f64,
}

/// Checked SI parameters of the disc model.
#[derive(Debug, Clone, PartialEq)]
pub struct FemParams {
    /// Crank bores (tied to the cranks by rigid spiders).
    pub bores: Vec<Hole>,
    /// Traction-free holes (output pins, centre).
    pub holes: Vec<Hole>,
    /// Disc material and thickness (the disc width).
    pub material: PlaneStress,
    /// Element size on the outline, m.
    pub flank_size: f64,
    /// Largest element size, m.
    pub max_size: f64,
    /// Load patch half-width, m.
    pub patch: f64,
    /// Stations per flank.
    pub stations_per_flank: usize,
    /// Crank angles per revolution.
    pub crank_angles: usize,
    /// STE measuring torque fraction of the rated torque.
    pub ste_torque_fraction: f64,
    /// Memory limit, bytes.
    pub max_memory: f64,
}

/// Memory of a disc model per mesh node, bytes: an upper bound of the peak resident size of the
/// process building the built-in disc (4 to 16 kB per node measured for 20 000 to 49 000 nodes:
/// assembly triplets, the Cholesky factor, one batch of station solutions). Used to refuse
/// meshes that would not fit before they are built.
pub(crate) const BYTES_PER_NODE: f64 = 10_000.0;

/// Smallest and largest radius of the profile outline, m.
pub(crate) fn outline_radii(profile: &Profile) -> (f64, f64) {
    profile
        .sample(256)
        .iter()
        .map(|p| p.norm())
        .fold((f64::INFINITY, 0.0), |(lo, hi), r| (lo.min(r), hi.max(r)))
}

impl FemParams {
    /// Estimated number of mesh nodes (corner and mid-edge) for `profile`: a graded band along
    /// the outline (about 11 nodes per outline element) and the interior at the largest size
    /// (2 nodes per equilateral element area); a fit to meshes of the built-in disc with flank
    /// sizes 0.1-0.5 mm and largest sizes 2-4 mm, within about 20 %.
    pub(crate) fn estimated_nodes(&self, profile: &Profile) -> f64 {
        let boundary = outline_length(profile) / self.flank_size;
        let (root, _) = outline_radii(profile);
        let interior = PI * root * root / (0.433 * self.max_size * self.max_size);
        11.0 * boundary + 2.0 * interior
    }
}

/// Length of the profile outline, m.
pub(crate) fn outline_length(profile: &Profile) -> f64 {
    let pts = profile.sample(512);
    (0..pts.len())
        .map(|i| (pts[(i + 1) % pts.len()] - pts[i]).norm())
        .sum()
}

/// Parameters `t` in `[0, 2 pi)` that split one tooth of the profile into pieces of equal arc
/// length, about `size` (m) long; and the arc length at `t` as a table `(t, s)` over the tooth.
fn arc_table(profile: &Profile, fine: usize) -> (Vec<f64>, Vec<f64>) {
    let mut ts = Vec::with_capacity(fine + 1);
    let mut ss = Vec::with_capacity(fine + 1);
    let mut s = 0.0;
    let mut prev = profile.position(0.0);
    ts.push(0.0);
    ss.push(0.0);
    for k in 1..=fine {
        let t = TAU * k as f64 / fine as f64;
        let p = profile.position(t);
        s += (p - prev).norm();
        prev = p;
        ts.push(t);
        ss.push(s);
    }
    (ts, ss)
}

/// Linear interpolation in a monotone table.
fn interp(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let i = xs.partition_point(|v| *v < x).clamp(1, xs.len() - 1);
    let (x0, x1) = (xs[i - 1], xs[i]);
    let w = if x1 > x0 { (x - x0) / (x1 - x0) } else { 0.0 };
    ys[i - 1] + w.clamp(0.0, 1.0) * (ys[i] - ys[i - 1])
}

/// The disc condensed onto its driving flanks: the FE model and the compliance matrix between
/// the load stations.
#[derive(Debug)]
pub struct DiscModel {
    /// The assembled, factorised FE model.
    pub fe: FeModel,
    /// Parameters.
    pub params: FemParams,
    /// Profile parameters `t` of the stations of tooth 0: `stations_per_flank` on the driving
    /// flank (`[0, pi]`), then as many on the other flank (`[pi, 2 pi]`), each at equal arc
    /// length.
    pub station_t: Vec<f64>,
    /// Compliance between stations, m/N: `(tooth a, flank f, station i) x (tooth b, flank g,
    /// station k)`, row-major over `2 Zc stations_per_flank` entries (global station index
    /// `(2 tooth + flank) stations_per_flank + station`).
    pub compliance: Vec<f64>,
    /// Reduced loads of the stations (`(equation, N)` pairs of a unit pin force), in the
    /// order of the compliance matrix's rows.
    pub station_loads: Vec<Vec<(usize, f64)>>,
    /// Arc-length table of one tooth: `t` and `s` (m) over `[0, 2 pi]`.
    arc_t: Vec<f64>,
    arc_s: Vec<f64>,
    teeth: usize,
    /// Start and length in arc length (m) of the two flanks of the tooth ([`flank_span`]).
    flank_spans: [(f64, f64); 2],
    /// Outline boundary-edge indices.
    outline_edges: Vec<usize>,
    /// Wall time of meshing, assembly with factorisation, and condensation, s (0 in a
    /// browser's WebAssembly).
    pub timings: [f64; 3],
}

impl DiscModel {
    /// Meshes the actual `profile` with the holes of `params`, assembles and factorises the
    /// plane-stress stiffness and computes the station compliances.
    ///
    /// # Errors
    /// Meshing or solver failures (`Error::Numerical`).
    pub fn build(profile: &Profile, params: &FemParams) -> Result<DiscModel> {
        Self::build_on(profile, params, None)
    }

    /// [`DiscModel::build`] for `profile` on the mesh of `base` (a model of the same modified
    /// profile with another wear map and the same `params`) moved onto `profile`'s outline
    /// ([`morph_mesh`]), reusing `base`'s symbolic factorisation (ordering and elimination
    /// tree: the sparsity pattern is the same); meshed afresh where the morph is refused.
    ///
    /// # Errors
    /// As [`DiscModel::build`].
    pub(crate) fn build_morphed(
        profile: &Profile,
        params: &FemParams,
        base: &DiscModel,
        base_profile: &Profile,
    ) -> Result<DiscModel> {
        Self::build_on(profile, params, Some((base, base_profile)))
    }

    fn build_on(
        profile: &Profile,
        params: &FemParams,
        base: Option<(&DiscModel, &Profile)>,
    ) -> Result<DiscModel> {
        let t0 = clock();
        let (ts, ss) = arc_table(profile, 4000);
        let morphed = base.and_then(|(b, bp)| morph_mesh(b, bp, profile).map(|mesh| (mesh, &b.fe)));
        let (mesh, reuse) = match morphed {
            Some((mesh, fe)) => (mesh, Some(fe)),
            None => (mesh_with_arc_table(profile, params, &ts, &ss)?, None),
        };
        let t1 = clock();
        let spiders: Vec<Spider> = params
            .bores
            .iter()
            .map(|b| Spider {
                centre: b.centre,
                fixed: [Some(0.0), Some(0.0), None],
            })
            .collect();
        let bc: Vec<NodeBc> = node_bcs(&mesh);
        let outline_edges: Vec<usize> = (0..mesh.boundary.len())
            .filter(|&e| mesh.boundary[e].kind == LoopKind::Outline)
            .collect();
        let fe = FeModel::new_reusing(mesh, params.material, &bc, spiders, reuse)?;
        let t2 = clock();
        let teeth = profile.geometry().disc_teeth();
        let m = params.stations_per_flank;
        let (arc_t, arc_s) = (ts.clone(), ss.clone());
        let station_t: Vec<f64> = (0..2)
            .flat_map(|flank| {
                let (s0, len) = flank_span(&arc_t, &arc_s, flank);
                let (arc_t, arc_s) = (&arc_t, &arc_s);
                (0..m).map(move |i| {
                    // Stations from 2 % to 98 % of each flank: the very root and tip carry no
                    // load.
                    let s = s0 + len * (0.02 + 0.96 * i as f64 / (m - 1) as f64);
                    interp(arc_s, arc_t, s)
                })
            })
            .collect();
        let mut model = DiscModel {
            fe,
            params: params.clone(),
            station_t,
            compliance: Vec::new(),
            station_loads: Vec::new(),
            flank_spans: [0, 1].map(|f| flank_span(&arc_t, &arc_s, f)),
            arc_t,
            arc_s,
            teeth,
            outline_edges,
            timings: [0.0; 3],
        };
        let loads: Vec<Vec<(usize, f64)>> = (0..2 * teeth * m)
            .into_par_iter()
            .map(|g| {
                let t = model.station_t[g % (2 * m)] + TAU * (g / (2 * m)) as f64;
                let pp = profile.point(t);
                model
                    .fe
                    .reduce_sparse(&model.patch_load(&pp.p, &(-pp.normal)))
            })
            .collect();
        model.compliance = model.fe.condense(&loads);
        model.station_loads = loads;
        let t3 = clock();
        model.timings = [elapsed(t0, t1), elapsed(t1, t2), elapsed(t2, t3)];
        Ok(model)
    }

    /// Nodal loads (`(node dof, N)`) of a unit pin force at `point` (m, on the outline) in the
    /// direction `dir` (unit): an elliptic pressure of half-width `w` on the outline edges within
    /// `w` of the point, scaled so that its resultant along `dir` is exactly 1 N.
    pub(crate) fn patch_load(&self, point: &Vec2, dir: &Vec2) -> Vec<(usize, f64)> {
        let w = self.params.patch;
        let mesh = &self.fe.mesh;
        let near = self.outline_edges.iter().copied().filter(|&e| {
            let nd = mesh.boundary[e].nodes;
            let (a, b) = (mesh.nodes[nd[0]], mesh.nodes[nd[1]]);
            (a - point).norm().min((b - point).norm()) < w + (b - a).norm()
        });
        let thickness = self.params.material.thickness;
        let mut load = plane::traction_load(mesh, thickness, near, |x| {
            let r = (x - point).norm() / w;
            (r < 1.0).then(|| dir * (2.0 / (PI * w * thickness) * (1.0 - r * r).sqrt()))
        });
        plane::scale_to_resultant(&mut load, dir, 1.0);
        load
    }

    /// Station index and Catmull-Rom weights of a contact at profile parameter `t` (rad): up to
    /// four `(global station, weight)` pairs on the flank the parameter lies on (driving:
    /// local `t` in `[0, pi]`; the other flank otherwise). Parameters within 2 % of a flank's
    /// ends take the end station's compliance.
    pub(crate) fn weights(&self, t: f64) -> [(usize, f64); 4] {
        let m = self.params.stations_per_flank;
        let tooth = (t / TAU).floor().rem_euclid(self.teeth as f64) as usize;
        let local = t.rem_euclid(TAU);
        let flank = usize::from(local > PI);
        let (s0, flank_len) = self.flank_spans[flank];
        // The arc table's parameters are uniform over the tooth: index it directly.
        let fine = self.arc_t.len() - 1;
        let x = local / TAU * fine as f64;
        let k = (x.floor() as usize).min(fine - 1);
        let f = (x - k as f64).clamp(0.0, 1.0);
        let s = self.arc_s[k] + f * (self.arc_s[k + 1] - self.arc_s[k]) - s0;
        let u = ((s / flank_len - 0.02) / 0.96 * (m - 1) as f64).clamp(0.0, (m - 1) as f64);
        let i = (u.floor() as usize).min(m - 2);
        let f = u - i as f64;
        // Catmull-Rom basis.
        let w = [
            0.5 * (-f + 2.0 * f * f - f * f * f),
            0.5 * (2.0 - 5.0 * f * f + 3.0 * f * f * f),
            0.5 * (f + 4.0 * f * f - 3.0 * f * f * f),
            0.5 * (-f * f + f * f * f),
        ];
        let idx = |d: isize| -> usize {
            let k = (i as isize + d).clamp(0, m as isize - 1) as usize;
            (2 * tooth + flank) * m + k
        };
        [
            (idx(-1), w[0]),
            (idx(0), w[1]),
            (idx(1), w[2]),
            (idx(2), w[3]),
        ]
    }

    /// Compliance matrix (m/N, `n x n`, row-major) between contacts at the profile parameters
    /// `ts` (rad): the normal approach of contact `a` under a unit normal force at contact `b`.
    /// Diagonal terms are interpolated along the station diagonal.
    pub(crate) fn compliance_at(&self, ts: &[f64]) -> Vec<f64> {
        let n = ts.len();
        let ns = self.stations();
        let ws: Vec<[(usize, f64); 4]> = ts.iter().map(|&t| self.weights(t)).collect();
        let mut c = vec![0.0; n * n];
        for a in 0..n {
            c[a * n + a] = ws[a]
                .iter()
                .map(|&(i, wi)| wi * self.compliance[i * ns + i])
                .sum();
            // The interpolation of a symmetric kernel with the same weights is symmetric: one
            // triangle is computed and mirrored.
            for b in 0..a {
                let mut v = 0.0;
                for &(i, wi) in &ws[a] {
                    let row = &self.compliance[i * ns..(i + 1) * ns];
                    for &(k, wk) in &ws[b] {
                        v += wi * wk * row[k];
                    }
                }
                c[a * n + b] = v;
                c[b * n + a] = v;
            }
        }
        c
    }

    /// Number of stations in all (both flanks of every tooth).
    pub(crate) fn stations(&self) -> usize {
        2 * self.teeth * self.params.stations_per_flank
    }
}

/// The wall clock where it exists: `None` in a browser's WebAssembly, where
/// `std::time::Instant` panics (the models' timings are then 0).
fn clock() -> Option<std::time::Instant> {
    #[cfg(all(target_arch = "wasm32", target_os = "unknown"))]
    {
        None
    }
    #[cfg(not(all(target_arch = "wasm32", target_os = "unknown")))]
    {
        Some(std::time::Instant::now())
    }
}

/// Seconds from `a` to `b` ([`clock`]; 0 without a clock).
fn elapsed(a: Option<std::time::Instant>, b: Option<std::time::Instant>) -> f64 {
    match (a, b) {
        (Some(a), Some(b)) => (b - a).as_secs_f64(),
        _ => 0.0,
    }
}

/// Start (m) and length (m) in arc length of flank `flank` (0: `t` in `[0, pi]`, 1: `[pi, 2 pi]`)
/// of the one-tooth table `(ts, ss)`.
fn flank_span(ts: &[f64], ss: &[f64], flank: usize) -> (f64, f64) {
    let mid = interp(ts, ss, PI);
    let end = *ss.last().expect("table");
    if flank == 0 {
        (0.0, mid)
    } else {
        (mid, end - mid)
    }
}

/// Node boundary conditions: nodes on crank bore `k` tied to spider `k`.
fn node_bcs(mesh: &Mesh) -> Vec<NodeBc> {
    let mut bc = vec![NodeBc::Free; mesh.nodes.len()];
    for e in &mesh.boundary {
        if let LoopKind::CrankBore(k) = e.kind {
            for &n in &e.nodes {
                bc[n] = NodeBc::Spider(k);
            }
        }
    }
    bc
}

/// How disc `d` of the reducer sits on an FE disc model. The discs of a reducer are one part
/// mounted turned by their eccentric phase (RV: disc 2 is disc 1 turned by pi, which for an
/// odd tooth count puts its teeth half a pitch round, `crate::reducer::Reducer::profile_turn`):
/// disc `d`'s profile is turned by `turn_d` against its crank bores and holes. When a rotation
/// `alpha = -turn_d + 2 pi k / Zc` maps the bores and holes of `[fem]` onto themselves, disc `d`
/// is the FE model of an unturned profile rotated by `alpha`: its contact at profile parameter
/// `t` is the model's at `t - 2 pi k` (`P(t + 2 pi) = R(-2 pi / Zc) P(t)`), and a vector in its
/// profile frame is `R(2 pi k / Zc)` of the vector in the model's frame. Otherwise it gets a
/// model of its own, meshed with the holes turned by `-turn_d` ([`DiscSet::build`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mount {
    /// Index of the disc's model in [`DiscSet::models`].
    pub model: usize,
    /// Whole teeth added to the disc's profile parameters to give the model's.
    pub teeth: isize,
    /// Rotation (rad) from the disc's profile frame to the model's.
    pub rotation: f64,
}

impl Mount {
    /// The model's profile parameter (rad) of the disc's contact at `t` (rad).
    pub fn parameter(&self, t: f64) -> f64 {
        t + TAU * self.teeth as f64
    }

    /// A disc-frame vector in the model's frame.
    pub(crate) fn model_frame(&self, v: &Vec2) -> Vec2 {
        crate::geometry::rotate(v, self.rotation)
    }
}

/// The whole-tooth rotation that carries a disc whose profile is turned by `turn` (rad) against
/// its holes onto the FE model of `params` (profile unturned): `Some(k)` for the rotation
/// `alpha = -turn + 2 pi k / Zc` (the smallest `k` in `0..Zc`) that maps every crank bore and
/// hole onto one of the same kind and radius (within 1 nm), `None` if none does.
pub(crate) fn mount_teeth(zc: usize, turn: f64, params: &FemParams) -> Option<usize> {
    let same = |a: &[Hole], alpha: f64| {
        a.iter().all(|h| {
            let c = crate::geometry::rotate(&h.centre, alpha);
            a.iter()
                .any(|g| (g.centre - c).norm() < 1e-9 && (g.radius - h.radius).abs() < 1e-9)
        })
    };
    (0..zc).find(|&k| {
        let alpha = -turn + TAU * k as f64 / zc as f64;
        same(&params.bores, alpha) && same(&params.holes, alpha)
    })
}

/// The FE models of the reducer's discs and how each disc sits on one ([`Mount`]): one model
/// when every disc is the first one's part turned by a symmetry of its holes (RV reducers with
/// an even number of cranks and an odd tooth count), otherwise one more per disc that is not.
#[derive(Debug)]
pub struct DiscSet {
    /// The models; the first is the unturned profile with the holes of `[fem]`.
    pub models: Vec<DiscModel>,
    /// Per disc of the reducer, its model and mount.
    pub mounts: Vec<Mount>,
}

impl DiscSet {
    /// Builds the FE model of `profile` with `params` and, for every disc of `reducer` that
    /// cannot sit on it (`mount_teeth`), a model with the holes turned by `-turn_d`.
    ///
    /// # Errors
    /// As [`DiscModel::build`].
    pub fn build(
        profile: &Profile,
        params: &FemParams,
        reducer: &crate::reducer::Reducer,
    ) -> Result<DiscSet> {
        Self::build_on(profile, params, reducer, None)
    }

    /// [`DiscSet::build`] for `profile` with each model on the mesh of `base`'s model moved onto
    /// `profile`'s outline ([`DiscModel::build_morphed`]); `base` was built for `base_profile`,
    /// the same modified profile with another wear map, with the same `params` and `reducer`.
    ///
    /// # Errors
    /// As [`DiscModel::build`].
    pub(crate) fn build_morphed(
        profile: &Profile,
        params: &FemParams,
        reducer: &crate::reducer::Reducer,
        base: &DiscSet,
        base_profile: &Profile,
    ) -> Result<DiscSet> {
        Self::build_on(profile, params, reducer, Some((base, base_profile)))
    }

    fn build_on(
        profile: &Profile,
        params: &FemParams,
        reducer: &crate::reducer::Reducer,
        base: Option<(&DiscSet, &Profile)>,
    ) -> Result<DiscSet> {
        let zc = profile.geometry().disc_teeth();
        let model = |k: usize, p: &FemParams| match base
            .and_then(|(b, bp)| b.models.get(k).map(|m| (m, bp)))
        {
            Some((m, bp)) => DiscModel::build_morphed(profile, p, m, bp),
            None => DiscModel::build(profile, p),
        };
        let mut models = vec![model(0, params)?];
        let mut mounts = Vec::new();
        for d in 0..reducer.discs() {
            let turn = reducer.profile_turn(d);
            let mount = match mount_teeth(zc, turn, params) {
                Some(k) => Mount {
                    model: 0,
                    teeth: -(k as isize),
                    rotation: TAU * k as f64 / zc as f64,
                },
                None => {
                    let mut p = params.clone();
                    for h in p.bores.iter_mut().chain(p.holes.iter_mut()) {
                        h.centre = crate::geometry::rotate_by(
                            &h.centre,
                            crate::geometry::portable::sin_cos(-turn),
                        );
                    }
                    models.push(model(models.len(), &p)?);
                    Mount {
                        model: models.len() - 1,
                        teeth: 0,
                        rotation: 0.0,
                    }
                }
            };
            mounts.push(mount);
        }
        Ok(DiscSet { models, mounts })
    }

    /// Disc `d`'s model and mount.
    pub fn disc(&self, d: usize) -> (&DiscModel, Mount) {
        let m = self.mounts[d];
        (&self.models[m.model], m)
    }

    /// Compliance (m/N, row-major) between disc `d`'s contacts at its profile parameters `ts`
    /// ([`DiscModel::compliance_at`] at the model's parameters).
    pub(crate) fn compliance_at(&self, d: usize, ts: &[f64]) -> Vec<f64> {
        let (model, mount) = self.disc(d);
        let t: Vec<f64> = ts.iter().map(|&t| mount.parameter(t)).collect();
        model.compliance_at(&t)
    }

    /// The parameters of the models (the same for all but the holes' turn).
    pub fn params(&self) -> &FemParams {
        &self.models[0].params
    }
}

/// The FE mesh of the disc `profile` for `params` (its outline sampled at the flank element
/// size, the holes, graded inside), with the arc-length table of one tooth (`t`, `s`) already
/// computed.
fn mesh_with_arc_table(
    profile: &Profile,
    params: &FemParams,
    ts: &[f64],
    ss: &[f64],
) -> Result<Mesh> {
    let outline: Vec<Vec2> = outline_parameters(profile, params, ts, ss)
        .iter()
        .map(|&t| profile.position(t))
        .collect();
    let mut loops = vec![BoundaryLoop {
        points: outline,
        kind: LoopKind::Outline,
        circle: None,
    }];
    let segs = |r: f64| ((TAU * r / (params.max_size / 3.0)).ceil() as usize).max(32);
    for (k, b) in params.bores.iter().enumerate() {
        loops.push(BoundaryLoop::circle(
            b.centre,
            b.radius,
            segs(b.radius),
            LoopKind::CrankBore(k),
        ));
    }
    for (k, h) in params.holes.iter().enumerate() {
        loops.push(BoundaryLoop::circle(
            h.centre,
            h.radius,
            segs(h.radius),
            LoopKind::Hole(k),
        ));
    }
    let est = params.estimated_nodes(profile);
    let spec = MeshSpec {
        max_area: 0.433 * params.max_size * params.max_size,
        min_angle_deg: 25.0,
        max_added_vertices: (2.0 * est) as usize + 10_000,
    };
    mesh::triangulate(&loops, &spec)
}

/// Profile parameters (rad, ascending over all teeth) of the outline polygon that
/// [`DiscModel::build`] meshes: each tooth split into pieces of equal arc length about
/// `flank_size` long (at least 8), from the one-tooth arc table `(ts, ss)`.
fn outline_parameters(profile: &Profile, params: &FemParams, ts: &[f64], ss: &[f64]) -> Vec<f64> {
    let teeth = profile.geometry().disc_teeth();
    let tooth_len = *ss.last().expect("table");
    let per_tooth = (tooth_len / params.flank_size).ceil().max(8.0) as usize;
    let local: Vec<f64> = (0..per_tooth)
        .map(|k| interp(ss, ts, tooth_len * k as f64 / per_tooth as f64))
        .collect();
    (0..teeth)
        .flat_map(|tooth| local.iter().map(move |t| t + TAU * tooth as f64))
        .collect()
}

/// Reach of a mesh morph (`morph_mesh`) in element sizes on the outline: nodes further than
/// this from the outline (along mesh edges) keep their place.
pub(crate) const MORPH_REACH_ELEMENTS: f64 = 4.0;

/// Smallest ratio of a morphed triangle's corner area to its area before the morph that
/// `morph_mesh` accepts (otherwise the worn disc is meshed afresh).
pub(crate) const MORPH_MIN_AREA_RATIO: f64 = 0.5;

/// The mesh of `base`, the model of the disc with profile `from`, moved onto the outline of
/// `to`, the same modified profile with another wear map: the same
/// nodes, elements and boundary, so the stiffness keeps its sparsity pattern and the results
/// change smoothly with wear (a fresh Delaunay refinement of a profile that differs by
/// picometres can add or drop nodes, and node-averaged stress maxima then move by per cent).
///
/// Every outline node sits on the outline polygon of `from` at profile parameter `t`
/// (interpolated along its segment) and moves by `P_to(t) - P_from(t)` (the wear difference
/// along the normal). Every other node within [`MORPH_REACH_ELEMENTS`] outline element sizes
/// of the outline (distance along mesh edges, multi-source Dijkstra) moves with its nearest
/// outline node, scaled by the smoothstep `(1 - s)^2 (1 + 2 s)` of its distance `s` in reach
/// units; the rest stay. `None` when the outline polygon is not star-shaped about the centre,
/// an outline node is off it, or a triangle's corner area falls below
/// [`MORPH_MIN_AREA_RATIO`] of its own (the caller meshes `to` afresh).
pub(crate) fn morph_mesh(base: &DiscModel, from: &Profile, to: &Profile) -> Option<Mesh> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    // The outline polygon `base` was meshed on (its arc table is `from`'s).
    let params = &base.params;
    let tp = outline_parameters(from, params, &base.arc_t, &base.arc_s);
    let base = &base.fe.mesh;
    let m = tp.len();
    let poly: Vec<Vec2> = tp.iter().map(|&t| from.position(t)).collect();
    // Polar angles along the polygon, unwrapped; strictly monotone for a star-shaped outline.
    let mut ang = Vec::with_capacity(m + 1);
    let mut prev = poly[0].y.atan2(poly[0].x);
    ang.push(prev);
    for p in poly.iter().skip(1).chain(std::iter::once(&poly[0])) {
        let a = p.y.atan2(p.x);
        let a = prev + (a - prev + PI).rem_euclid(TAU) - PI;
        ang.push(a);
        prev = a;
    }
    let sign = (ang[m] - ang[0]).signum();
    if ang.windows(2).any(|w| (w[1] - w[0]) * sign <= 0.0) || (ang[m] - ang[0]).abs() < PI {
        return None;
    }
    let period = TAU * from.geometry().disc_teeth() as f64;
    let nodes = &base.nodes;
    let n = nodes.len();
    // Outline nodes: their parameter on the polygon and displacement.
    let mut disp = vec![Vec2::zeros(); n];
    let mut dist = vec![f64::INFINITY; n];
    let mut src = vec![usize::MAX; n];
    let mut heap = BinaryHeap::new();
    for e in &base.boundary {
        if e.kind != LoopKind::Outline {
            continue;
        }
        for &i in &e.nodes {
            if src[i] != usize::MAX {
                continue;
            }
            let x = nodes[i];
            let a = ang[0] + ((x.y.atan2(x.x) - ang[0]) * sign).rem_euclid(TAU) * sign;
            let k = if sign > 0.0 {
                ang.partition_point(|&v| v <= a)
            } else {
                ang.partition_point(|&v| v >= a)
            }
            .clamp(1, m)
                - 1;
            let (p0, p1) = (poly[k], poly[(k + 1) % m]);
            let d = p1 - p0;
            let lam = ((x - p0).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            if (p0 + d * lam - x).norm() > 1e-9 {
                return None;
            }
            let t1 = if k + 1 == m {
                tp[0] + period
            } else {
                tp[k + 1]
            };
            let t = tp[k] + lam * (t1 - tp[k]);
            disp[i] = to.position(t) - from.position(t);
            dist[i] = 0.0;
            src[i] = i;
            heap.push(Reverse((0u64, i)));
        }
    }
    // Mesh-edge graph (all node pairs of each element) and the distance to the outline.
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
    for t in &base.triangles {
        for a in 0..6 {
            for b in 0..6 {
                if a != b && !adj[t[a]].contains(&t[b]) {
                    adj[t[a]].push(t[b]);
                }
            }
        }
    }
    let reach = MORPH_REACH_ELEMENTS * params.flank_size;
    while let Some(Reverse((bits, i))) = heap.pop() {
        let di = f64::from_bits(bits);
        if di > dist[i] || di > reach {
            continue;
        }
        for &j in &adj[i] {
            let dj = di + (nodes[j] - nodes[i]).norm();
            if dj < dist[j] && dj <= reach {
                dist[j] = dj;
                src[j] = src[i];
                // Non-negative floats order as their bit patterns.
                heap.push(Reverse((dj.to_bits(), j)));
            }
        }
    }
    let moved: Vec<Vec2> = (0..n)
        .map(|i| {
            if src[i] == usize::MAX {
                return nodes[i];
            }
            let s = (dist[i] / reach).clamp(0.0, 1.0);
            nodes[i] + disp[src[i]] * ((1.0 - s) * (1.0 - s) * (1.0 + 2.0 * s))
        })
        .collect();
    let area = |p: &[Vec2], t: &[usize; 6]| 0.5 * (p[t[1]] - p[t[0]]).perp(&(p[t[2]] - p[t[0]]));
    if base
        .triangles
        .iter()
        .any(|t| area(&moved, t) < MORPH_MIN_AREA_RATIO * area(nodes, t))
    {
        return None;
    }
    Some(Mesh {
        nodes: moved,
        ..base.clone()
    })
}
