//! Archard wear of the disc flanks over working hours (docs/model.md section 7).
//!
//! Default model (`flodin`): over one mesh cycle every point of a tooth is swept once by the
//! contact band of whichever pin passes it. A point at mesh angle `t` loses, per pass,
//! `dh = k p s` with mean pressure `p = F/(2 b B)` (paper eq 19) and sliding distance
//! `s = 2 b |v_s| / v_d` (Flodin and Andersson, Wear 207, 1997): `v_s` the sliding speed at the
//! contact (disc material against a pin that does not turn in its groove, scaled by
//! `1 - pin_rolling_fraction`; for pins that turn by their friction balance, [`PinTurning`],
//! the sliding the balance leaves), `v_d` the speed of the contact point along the disc flank. The
//! half-width cancels: `dh = k F |v_s| / (B v_d)`. Forces come from the loaded-contact solution
//! on the actual (worn) profile at `crank_steps_per_mesh_cycle` crank angles; each pin of each
//! solve samples `dh` at its actual contact mesh angle, and the samples are interpolated onto the
//! wear-map grid. Mesh cycles per hour are `60 n_in Zp / i_H` (one per crank revolution relative
//! to the carrier, docs/model.md section 1). The wear rate is recomputed from the worn profile
//! every `profile_update_hours` (explicit Euler in hours), so wear feeds back into the load
//! sharing.
//!
//! Paper model (`paper`): eqs 11-20 as printed, with Li's closed-form forces (eqs 5, 9, 10) on the
//! unworn profile, sliding `S = 2 a_H |1 - u1 cos(alpha)/u2|` with `u1 = omega r_i` (`r_i` the
//! contact radius), `u2 = omega l_i / i_H` read with `i_H = Zp/Zc` as in the profile equations,
//! `alpha` from eq 1, total distance `X = S n1 t eps_a` (eq 19, input revolutions times the
//! overlap ratio), `h = k X P` (eq 20); no profile update.

//!
//! The crank bearings' wear, as growth of their radial clearance: [`bearings`].

mod bearings;
pub(crate) mod mesh_cycle;
mod worn;

pub use crate::contact::pin_turning::PinTurning;
pub use bearings::{bearing_wear_rates, clearance_growth, BearingWearParams, BearingWearRates};
#[cfg(test)]
pub(crate) use mesh_cycle::wear_per_mesh_cycle;
pub(crate) use mesh_cycle::{
    contact_kinematics, entrainment_speed, revolution_positions, MeshCycleWear,
};
pub use worn::{profile_maps, WornState};

use std::f64::consts::TAU;

use serde::Serialize;

use crate::budget::{self, Budget};
use crate::contact::gap::GapField;
use crate::contact::li_load_distribution;
use crate::error::{Error, Result};
use crate::geometry::{band_shape, mesh_angle, CycloidParams, Profile, WearMap};
use crate::reducer::{Reducer, PIN_MAP_POINTS};

/// Wear model choice (`wear.model`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub enum WearModelKind {
    /// Archard with sliding distance `2 b |v_d - v_p| / v_d` from the real kinematics
    /// (Flodin and Andersson 1997), contact from true gaps, profile updates.
    Flodin,
    /// The paper's eqs 11-20 as printed.
    Paper,
}

/// One level of the load spectrum (`[load]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LoadLevel {
    /// Output torque, N m (negative loads the other flank).
    pub torque: f64,
    /// Input speed, rpm.
    pub speed_rpm: f64,
    /// Share of the working time, 0..1 (the levels sum to 1).
    pub fraction: f64,
}

/// `[wear]` checked, SI (docs/model.md section 7).
#[derive(Debug, Clone, PartialEq)]
pub struct WearParams {
    /// The wear model.
    pub model: WearModelKind,
    /// Archard coefficient `k = K/H`, m^2/N.
    pub archard: f64,
    /// The key that sets the Archard coefficient, as the user wrote it (for messages).
    pub archard_key: &'static str,
    /// Working-hour stages at which results are reported, h (ascending, at least one).
    pub stage_hours: Vec<f64>,
    /// Profile update step, h (0: the wear rate of the new profile throughout).
    pub update_hours: f64,
    /// Largest wear increment between profile updates, m.
    pub max_wear_step: f64,
    /// Crank angles solved per mesh cycle (the wear grid has `Zp` times as many points).
    pub crank_steps: usize,
    /// Fraction of the sliding taken up by pins turning in their grooves, 0..1.
    pub pin_rolling_fraction: f64,
    /// How the pins turn in their grooves (docs/model.md section 7.12).
    pub pin_turning: PinTurning,
    /// Archard coefficient of the pins, m^2/N (0: the pins do not wear; docs/model.md section
    /// 7.11).
    pub pin_archard: f64,
    /// Overlap ratio of the paper's model.
    pub overlap_ratio: f64,
    /// The crank bearings' wear ([`bearings`]).
    pub bearings: BearingWearParams,
    /// Running-in of the disc's coefficient.
    pub running_in: RunningIn,
}

/// Running-in of the disc's Archard coefficient (docs/model.md section 7.10): `k(t) = k_ss
/// (1 + (r - 1) exp(-t/tau))`, falling from `r k_ss` when new to the steady `k_ss` over the
/// time constant `tau` (the exponential approach to steady wear; Blau, *On the nature of
/// running-in*, Tribology International 39, 2006). The wear rate is `k` times a function of
/// the worn profile, so the wear after `t` hours is the steady wear after the equivalent hours
/// `H(t) = t + (r - 1) tau (1 - exp(-t/tau))`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunningIn {
    /// `r = k(0)/k_ss` (1: no running-in).
    pub factor: f64,
    /// `tau`, h.
    pub hours: f64,
}

impl RunningIn {
    /// Equivalent steady hours `H(t)` of `t` working hours.
    pub fn equivalent_hours(&self, t: f64) -> f64 {
        if self.factor <= 1.0 {
            return t;
        }
        t + (self.factor - 1.0) * self.hours * (-(-t / self.hours).exp_m1())
    }

    /// `k(t)/k_ss` at `t` working hours.
    pub fn factor_at(&self, t: f64) -> f64 {
        1.0 + (self.factor - 1.0) * (-t / self.hours).exp()
    }
}

impl WearParams {
    /// Wear-rate evaluations the profile-update step asks for up to the last stage
    /// ([`budget::scheduled_updates`]).
    pub(crate) fn scheduled_updates(&self) -> f64 {
        let last = self.stage_hours.last().copied().unwrap_or(0.0);
        budget::scheduled_updates(self.model == WearModelKind::Paper, last, self.update_hours)
    }

    /// Static solves of one wear-rate evaluation over `levels` load levels
    /// ([`budget::per_rate_evaluation`]).
    pub(crate) fn rate_evaluation_solves(&self, levels: usize, positions: usize) -> f64 {
        budget::per_rate_evaluation(
            self.model == WearModelKind::Paper,
            levels,
            self.crank_steps * positions,
        )
    }
}

/// What the wear integration reads: the reducer's mechanical model, the disc the profiles are
/// built from, the wear settings, the load spectrum, the torque of the band filter, the work
/// budget ([`crate::config::Model::wear_inputs`]).
#[derive(Debug, Clone, Copy)]
pub struct WearInputs<'a> {
    /// The reducer's mechanical model.
    pub reducer: &'a Reducer,
    /// The disc: every worn profile is built from it.
    pub disc: &'a CycloidParams,
    /// The wear settings.
    pub wear: &'a WearParams,
    /// The load spectrum.
    pub load: &'a [LoadLevel],
    /// Output torque whose Li peak force sets the band of the wear map's filter (the
    /// loaded-TE torque), N m.
    pub band_torque: f64,
    /// The work budget and the stages' analyses' cost.
    pub budget: Budget,
    /// Clearance growth of the crank bearings, m/h: the wear rate at hour `t` is that of the
    /// reducer with its bearings opened by `t` times these ([`bearing_wear_rates`]; zero: the
    /// assembly clearances throughout).
    pub bearing_rates: BearingWearRates,
    /// The oil and surfaces: with [`crate::tribology::WearFilm::Lambda`] each contact's
    /// coefficient is scaled by the asperities' share of its load (docs/model.md section 18.6).
    pub lubrication: crate::tribology::Lubrication,
}

impl WearInputs<'_> {
    /// Number of wear-map grid points per tooth: `Zp x crank_steps_per_mesh_cycle`.
    pub(crate) fn grid_points(&self) -> usize {
        self.disc.geometry.pins * self.wear.crank_steps
    }
}

/// Periodic linear interpolation of samples `(angle, value)` (angles in rad, any order) onto
/// `n` uniform grid points over `[0, 2 pi)`.
fn resample_periodic(mut samples: Vec<(f64, f64)>, n: usize) -> Vec<f64> {
    samples.sort_by(|a, b| a.0.total_cmp(&b.0));
    let m = samples.len();
    let mut out = vec![0.0; n];
    let mut i = 0; // samples[i] is the last sample with angle <= grid angle
    for (g, o) in out.iter_mut().enumerate() {
        let t = TAU * g as f64 / n as f64;
        while i + 1 < m && samples[i + 1].0 <= t {
            i += 1;
        }
        let (lo, hi) = if samples[0].0 > t {
            // before the first sample: wrap from the last
            let (a, va) = samples[m - 1];
            ((a - TAU, va), samples[0])
        } else if i + 1 < m {
            (samples[i], samples[i + 1])
        } else {
            let (b, vb) = samples[0];
            (samples[m - 1], (b + TAU, vb))
        };
        let w = if hi.0 > lo.0 {
            (t - lo.0) / (hi.0 - lo.0)
        } else {
            0.0
        };
        *o = lo.1 + w * (hi.1 - lo.1);
    }
    out
}

/// Wear rates of the disc and the pins, m/h ([`wear_rate`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct WearRate {
    /// The disc's, on the wear-map grid.
    pub disc: Vec<f64>,
    /// The pins', on the pin map's grid (empty when the pins do not wear).
    pub pin: Vec<f64>,
}

/// Wear rates (m/h) of the disc (on the grid) and the pins (around the pin) for the model's
/// load spectrum on the actual profile. The pins are swept once per revolution of the
/// eccentric, `Zc/Zp` times per mesh cycle of the disc (docs/model.md section 7.11).
///
/// # Errors
/// Propagates contact-solver failures.
pub(crate) fn wear_rate(profile: &Profile, inputs: &WearInputs) -> Result<WearRate> {
    wear_rate_from(profile, inputs, &mut WearWarm::default())
}

/// How many times the eccentricity the unworn disc's mean wear rate must wear by the hours
/// asked for before they are refused as far beyond the wear model's validity
/// ([`far_beyond_validity`]).
pub(crate) const VALIDITY_MARGIN: f64 = 3.0;

/// Whether `hours` (h) lie far beyond the validity of the wear model of `inputs` (the wear
/// depth reaching the eccentricity `a`, section 7.8 of docs/model.md), from the unworn disc
/// alone: the mean of its steady wear rates over the mesh-angle grid, times the equivalent
/// hours of running-in, reaches [`VALIDITY_MARGIN`] times `a`. Returns that depth (m) and the
/// rate (m/h) where it does. The deepest point of the worn flank stays above 0.9 times the
/// mean rate's depth on every preset up to 1e6 h, where they approach the limit (1.65 at
/// 1e4 h, 0.90 at 1e6 h: the flank conforms and spreads its wear, but its deepest point keeps
/// most of the mean), so a request refused by this test would leave the validity by a factor
/// of 3 x 0.9 at least; running-in only adds wear early (the equivalent hours exceed the
/// hours), and a disc that runs in wears less later than its unworn rate, which the margin
/// covers. One wear-rate evaluation of the unworn disc. (Measured with the presets' own
/// wear integrations to 1e4, 1e5, 3e5 and 1e6 h; the paper's reducer, whose disc alone
/// wears at 4.7 times the example's rate, leaves the validity at 1.67e5 h with the ratio at
/// 1.40 at 1e5 h.)
///
/// # Errors
/// Those of the wear-rate evaluation.
pub(crate) fn far_beyond_validity(inputs: &WearInputs, hours: f64) -> Result<Option<(f64, f64)>> {
    let rate = wear_rate(&inputs.disc.profile(None)?, inputs)?;
    let mean = rate.disc.iter().sum::<f64>() / rate.disc.len().max(1) as f64;
    let depth = mean * inputs.wear.running_in.equivalent_hours(hours);
    let a = inputs.reducer.geometry.eccentricity;
    Ok((depth >= VALIDITY_MARGIN * a).then_some((depth, mean)))
}

/// What a wear-rate evaluation leaves for the next one of a wear integration: the static
/// solutions per load level and the worn profile with its contact geometry.
#[derive(Debug, Clone, Default)]
pub(crate) struct WearWarm {
    /// Per load level, the solutions of [`mesh_cycle::wear_per_mesh_cycle_from`].
    solutions: Vec<Vec<crate::statics::StaticSolution>>,
    /// The profile evaluated and its gap field ([`GapField::new_after`]).
    gap: Option<(Profile, GapField)>,
}

/// [`wear_rate`] with the static solves of each load level started from `warm`'s (the
/// solutions of the previous evaluation of a wear integration, per level;
/// [`mesh_cycle::wear_per_mesh_cycle_from`]) and the contact geometry built from its
/// ([`GapField::new_after`]; once for every level), which it replaces with this evaluation's.
///
/// # Errors
/// As [`wear_rate`].
fn wear_rate_from(profile: &Profile, inputs: &WearInputs, warm: &mut WearWarm) -> Result<WearRate> {
    warm.solutions.resize(inputs.load.len(), Vec::new());
    let mut field: Option<GapField> = None;
    let n = inputs.grid_points();
    let geo = profile.geometry();
    let sweeps_per_cycle = geo.disc_teeth() as f64 / geo.pins as f64;
    let n_pin = if inputs.wear.pin_archard > 0.0 {
        PIN_MAP_POINTS
    } else {
        0
    };
    let mut rate = WearRate {
        disc: vec![0.0; n],
        pin: vec![0.0; n_pin],
    };
    for (level, solved) in inputs.load.iter().zip(warm.solutions.iter_mut()) {
        let per_cycle = match inputs.wear.model {
            WearModelKind::Flodin => {
                let near = (!solved.is_empty()).then_some(&solved[..]);
                if field.is_none() && level.torque != 0.0 {
                    field = Some(GapField::new_after(
                        profile,
                        inputs.reducer.gap_points,
                        Some(inputs.reducer.contact_band()),
                        warm.gap.as_ref().map(|(p, f)| (f, p)),
                    )?);
                }
                let (w, solutions) = mesh_cycle::wear_per_mesh_cycle_from(
                    profile,
                    inputs,
                    level.torque,
                    level.speed_rpm,
                    near,
                    field.as_ref(),
                )?;
                *solved = solutions;
                w
            }
            WearModelKind::Paper => MeshCycleWear {
                disc: paper_wear_per_input_rev(profile, inputs, level.torque)?,
                pin: Vec::new(),
                sliding: 0.0,
            },
        };
        let cycles = match inputs.wear.model {
            WearModelKind::Flodin => inputs.reducer.mesh_cycles_per_hour(level.speed_rpm),
            // X = S n1 t eps_a, n1 the input speed.
            WearModelKind::Paper => 60.0 * level.speed_rpm * inputs.wear.overlap_ratio,
        };
        for (r, d) in rate.disc.iter_mut().zip(&per_cycle.disc) {
            *r += level.fraction * cycles * d;
        }
        for (r, d) in rate.pin.iter_mut().zip(&per_cycle.pin) {
            *r += level.fraction * cycles * sweeps_per_cycle * d;
        }
    }
    if let Some(f) = field {
        warm.gap = Some((profile.clone(), f));
    }
    Ok(rate)
}

/// The paper's wear per input revolution and unit overlap (eqs 11-20 as printed), m, on the grid.
fn paper_wear_per_input_rev(
    profile: &Profile,
    inputs: &WearInputs,
    torque: f64,
) -> Result<Vec<f64>> {
    let n = inputs.grid_points();
    if torque == 0.0 {
        return Ok(vec![0.0; n]);
    }
    let geo = profile.geometry();
    let zp = geo.pins as f64;
    let zc = geo.disc_teeth() as f64;
    let k1 = geo.k1();
    let steps = inputs.wear.crank_steps;
    let mut samples = Vec::with_capacity(n);
    for k in 0..steps {
        let phi = TAU * k as f64 / (zp * steps as f64);
        let forces = li_load_distribution(geo, phi, inputs.reducer.equivalent_disc_torque(torque));
        for (j, &f) in forces.iter().enumerate() {
            let t = mesh_angle(TAU * j as f64 / zp - phi);
            if f == 0.0 {
                samples.push((t, 0.0));
                continue;
            }
            let f = f.abs();
            let sq = (1.0 + k1 * k1 - 2.0 * k1 * t.cos()).sqrt();
            let lever = (geo.disc_pitch_radius() * t.sin() / sq).abs();
            let pt = profile.point(t);
            let r_i = pt.p.norm();
            // Eq 1: contact force angle.
            let alpha = (k1 * t.sin()).atan2(1.0 - k1 * t.cos()).abs();
            let ratio = r_i * alpha.cos() * (zp / zc) / lever;
            let hz = inputs.reducer.contact.hertz(f, pt.curvature);
            let s = 2.0 * hz.half_width * (1.0 - ratio).abs();
            samples.push((t, inputs.wear.archard * s * hz.mean_pressure));
        }
    }
    Ok(resample_periodic(samples, n))
}

/// Filters a wear map at the scale of the Hertz band. The flank a pin meets is the worn flank
/// averaged over the contact band: waviness shorter than the band (grid-scale noise of the
/// sampled wear) is flattened elastically and does not steer the load, and left in the geometry
/// it feeds back into the load sharing and grows. Each node becomes the semi-elliptic average
/// over `+-b` of arc length, `b` the Hertz half-width of Li's peak force at the loaded-TE torque
/// on the unworn flank there.
struct BandSmoother {
    /// For every node: (neighbour index, weight), weights summing to 1.
    weights: Vec<Vec<(usize, f64)>>,
}

impl BandSmoother {
    fn new(inputs: &WearInputs) -> Result<Self> {
        let n = inputs.grid_points();
        let profile = inputs.disc.profile(None)?;
        let geo = &inputs.disc.geometry;
        let f_peak = 4.0
            * inputs
                .reducer
                .equivalent_disc_torque(inputs.band_torque.abs().max(1e-9))
            / (geo.eccentricity * (geo.disc_teeth() * geo.pins) as f64);
        let dt = TAU / n as f64;
        let pts: Vec<_> = (0..n).map(|m| profile.point(m as f64 * dt)).collect();
        let ds: Vec<f64> = pts.iter().map(|p| p.dp.norm() * dt).collect();
        let weights = (0..n)
            .map(|m| {
                let b = inputs
                    .reducer
                    .contact
                    .hertz(f_peak, pts[m].curvature)
                    .half_width;
                let w = band_shape(&ds, m, b);
                let total: f64 = w.iter().map(|&(i, x)| x * ds[i]).sum();
                w.iter().map(|&(i, x)| (i, x * ds[i] / total)).collect()
            })
            .collect();
        Ok(BandSmoother { weights })
    }

    fn apply(&self, h: &[f64]) -> Vec<f64> {
        let pass = |h: &[f64]| -> Vec<f64> {
            self.weights
                .iter()
                .map(|w| w.iter().map(|&(i, x)| x * h[i]).sum())
                .collect()
        };
        pass(&pass(h))
    }
}

/// Where the wear model leaves its validity: the worn profile can no longer be analysed (the
/// contact leaves the range of the line-contact law or of the static analysis, or the worn
/// flank folds over itself).
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct ValidityLimit {
    /// Working hours at which the worn profile could not be analysed, h.
    pub hours: f64,
    /// Largest wear depth of that profile, um.
    pub max_wear_um: f64,
    /// Which limit: the analysis' own message.
    pub reason: String,
}

/// Wear maps at the model's stages.
#[derive(Debug, Clone, Serialize)]
pub struct WearHistory {
    /// Stage working hours, h: the model's stages up to the validity limit.
    pub hours: Vec<f64>,
    /// Wear depth on the grid at each stage, m (`maps[s][m]` at mesh angle `2 pi m / n`),
    /// filtered at the Hertz band scale (the flank the pins meet).
    pub maps: Vec<Vec<f64>>,
    /// Pin wear around the pin at each stage, m ([`crate::reducer::PinWear::depth`]; empty
    /// maps when the pins do not wear).
    pub pin_maps: Vec<Vec<f64>>,
    /// Working hours at which the wear rate was evaluated (the profile-update schedule), h;
    /// starts with 0. Pass it to `integrate_on_schedule` to repeat the same schedule.
    pub update_hours: Vec<f64>,
    /// Set when the integration stopped before the last stage because the worn profile left
    /// the model's validity; `hours` and `maps` then hold the stages before it.
    pub limit: Option<ValidityLimit>,
    /// The crank bearings' clearance growth the integration ran with, m/h
    /// ([`WearInputs::bearing_rates`]): the worn states at its hours grow them so.
    #[serde(skip)]
    pub bearing_rates: BearingWearRates,
    /// The unfiltered wear state at each profile update and the rates held until the next
    /// ([`WearHistory::replay`]).
    #[serde(skip)]
    pub(crate) segments: Vec<WearSegment>,
    /// What the last wear-rate evaluation leaves for the next: where a continued
    /// integration's evaluations start ([`WearHistory::continued`]), as the next evaluation's
    /// would have.
    #[serde(skip)]
    pub(crate) warm: WearWarm,
}

/// One profile update of a wear integration: the unfiltered wear depths at its start and the
/// rates (m per steady-equivalent hour) held until the next update.
#[derive(Debug, Clone)]
pub(crate) struct WearSegment {
    /// Working hours of the update, h.
    start_h: f64,
    /// Disc wear on the grid, m, unfiltered.
    disc: Vec<f64>,
    /// Pin wear round the pin, m.
    pin: Vec<f64>,
    /// Disc wear rate, m per hour (steady coefficient).
    disc_rate: Vec<f64>,
    /// Pin wear rate, m per hour (steady coefficient).
    pin_rate: Vec<f64>,
}

impl WearSegment {
    /// The unfiltered disc and pin wear (m) at `hours` (h, at or after this update), the
    /// rates held from it: the integration's own explicit step ([`advance_depths`]).
    fn state_at(&self, run_in: RunningIn, hours: f64) -> (Vec<f64>, Vec<f64>) {
        let (mut disc, mut pin) = (self.disc.clone(), self.pin.clone());
        advance_depths(&mut disc, &self.disc_rate, run_in, self.start_h, hours);
        advance_depths(&mut pin, &self.pin_rate, run_in, self.start_h, hours);
        (disc, pin)
    }
}

impl WearHistory {
    /// Number of wear-rate evaluations (profile updates + 1): `update_hours.len()`.
    pub(crate) fn rate_evaluations(&self) -> usize {
        self.update_hours.len()
    }
    /// Mesh angles of the grid, rad.
    pub fn angles(&self) -> Vec<f64> {
        let n = self.maps.first().map_or(0, Vec::len);
        (0..n).map(|m| TAU * m as f64 / n as f64).collect()
    }
    /// The wear after `hours` of the same integration, without evaluating a wear rate: the
    /// state at the last profile update at or before `hours` advanced with the rate held from
    /// it, as the integration itself advances it (exact for an integration on the same
    /// schedule to those hours, up to round-off). Returns the filtered disc map and the pin
    /// map (m), or `None` beyond the last stage integrated (or before 0).
    ///
    /// `inputs` must be those of the integration.
    ///
    /// # Errors
    /// The wear depth reaching the eccentricity (section 7.8 of docs/model.md) is a numerical
    /// error naming the hours.
    pub(crate) fn replay(
        &self,
        inputs: &WearInputs,
        hours: f64,
    ) -> Result<Option<(Vec<f64>, Vec<f64>)>> {
        let end = self.hours.last().copied().unwrap_or(0.0);
        if self.limit.is_some() || !(0.0..=end).contains(&hours) {
            return Ok(None);
        }
        let Some(seg) = self.segments.iter().rev().find(|s| s.start_h <= hours) else {
            return Ok(None);
        };
        let (disc, pin) = seg.state_at(inputs.wear.running_in, hours);
        let map = BandSmoother::new(inputs)?.apply(&disc);
        if let Some(l) = depth_limit(inputs, hours, &map) {
            return Err(Error::numerical("wear integration", l.reason));
        }
        Ok(Some((map, pin)))
    }
    /// Maximum wear depth at each stage, m.
    pub(crate) fn max_depths(&self) -> Vec<f64> {
        self.maps
            .iter()
            .map(|m| m.iter().copied().fold(0.0, f64::max))
            .collect()
    }
}

/// Integrates Archard wear over the working hours with profile updates (see module docs).
/// `progress(done, total)` is called after each wear-rate evaluation.
///
/// Where the worn profile leaves the model's validity (the wear rate of a worn profile cannot
/// be evaluated: the contact leaves the range of the contact law or the static analysis, or the
/// flank folds over itself), the integration stops there and reports the stages before it with
/// [`WearHistory::limit`] set.
///
/// # Errors
/// Propagates solver failures on the unworn profile; [`Error::Invalid`] naming the key that
/// drives the work when the profile updates that `wear.max_wear_step_um` asks for exceed the
/// work budget ([`crate::budget`]).
pub fn integrate(
    inputs: &WearInputs,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<WearHistory> {
    integrate_from(inputs, None, None, progress, &|_| {})
}

/// [`integrate`], telling `on_stage` each stage's wear as soon as it is known (what the
/// history will hold at that index): a stage can be analysed while the integration goes on
/// to the next.
///
/// # Errors
/// As [`integrate`].
pub fn integrate_with_stages(
    inputs: &WearInputs,
    progress: &(dyn Fn(usize, usize) + Sync),
    on_stage: &dyn Fn(StageWearRef),
) -> Result<WearHistory> {
    integrate_from(inputs, None, None, progress, on_stage)
}

/// One stage's wear as [`integrate_with_stages`] finds it.
#[derive(Debug, Clone, Copy)]
pub struct StageWearRef<'a> {
    /// The stage's index (in `wear.stage_hours`).
    pub index: usize,
    /// Working hours, h.
    pub hours: f64,
    /// The disc's wear depth on the grid, m (filtered at the Hertz band scale).
    pub map: &'a [f64],
    /// The pins' wear round the pin, m (empty when the pins do not wear).
    pub pin_map: &'a [f64],
}

/// [`integrate`] with the profile updates at the given working hours (h, ascending; values
/// outside `(0, last stage)` are ignored) instead of the model's `profile_update_hours` and
/// `max_wear_step_um` rule. With the schedule fixed, the wear depth is a smooth, increasing
/// function of the Archard coefficient, which calibration needs: the adaptive rule moves the
/// update times with the coefficient and makes the depth jitter by a few 0.1 %.
///
/// # Errors
/// As [`integrate`].
pub(crate) fn integrate_on_schedule(
    inputs: &WearInputs,
    update_hours: &[f64],
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<WearHistory> {
    integrate_from(inputs, Some(update_hours), None, progress, &|_| {})
}

impl WearHistory {
    /// This integration of `inputs` (by the model's rule, [`integrate`]) continued from its
    /// last stage to `hours` (h), which becomes its last stage: the unfiltered state there
    /// ([`WearHistory::replay`]'s) is the start, a wear rate is evaluated there and the
    /// profile updates follow the same rule (the multiples of `wear.profile_update_hours`,
    /// capped by `wear.max_wear_step_um`). It differs from an integration from zero to `hours`
    /// only by that one extra profile update at the old last stage (within the integration's
    /// own step error), and costs the hours added instead of all of them; the accuracy life's
    /// search beyond the stages steps on this way and replays its trials in between.
    ///
    /// # Errors
    /// As [`integrate`]; [`Error::Invalid`] naming `hours` if it is not beyond the last stage
    /// or this history ended at a validity limit. A history that meets the validity limit on
    /// the way is returned with [`WearHistory::limit`] set, as [`integrate`] returns it.
    pub(crate) fn continued(&self, inputs: &WearInputs, hours: f64) -> Result<WearHistory> {
        let end = self.hours.last().copied().unwrap_or(0.0);
        if self.limit.is_some() || self.segments.is_empty() || hours.is_nan() || hours <= end {
            return Err(Error::invalid(
                "hours",
                format!("{hours}"),
                format!("beyond the last stage integrated ({end} h), without a validity limit"),
            ));
        }
        let seg = self.segments.last().expect("checked: not empty");
        let run_in = inputs.wear.running_in;
        if update_step(inputs.wear).is_infinite() {
            // One rate held throughout: the last segment runs on.
            let (disc, pin) = seg.state_at(run_in, hours);
            let map = BandSmoother::new(inputs)?.apply(&disc);
            let mut next = self.clone();
            next.limit = depth_limit(inputs, hours, &map);
            if next.limit.is_none() {
                next.hours.push(hours);
                next.maps.push(map);
                next.pin_maps.push(pin);
            }
            return Ok(next);
        }
        let (disc, pin) = seg.state_at(run_in, end);
        let mut wear = inputs.wear.clone();
        wear.stage_hours = self.hours.clone();
        wear.stage_hours.push(hours);
        let start = Start {
            hours: end,
            disc,
            pin,
            history: self,
        };
        integrate_from(
            &WearInputs {
                wear: &wear,
                ..*inputs
            },
            None,
            Some(start),
            &|_, _| {},
            &|_| {},
        )
    }
}

/// Hours between profile updates, h: infinite for the paper's model and without updates (one
/// rate, of the unworn profile, held throughout).
fn update_step(w: &WearParams) -> f64 {
    if w.model == WearModelKind::Paper || w.update_hours <= 0.0 {
        f64::INFINITY
    } else {
        w.update_hours
    }
}

/// The state an integration continues from ([`WearHistory::continued`]): the unfiltered disc
/// and pin wear (m) at `hours` (h), the last stage of `history`.
struct Start<'a> {
    hours: f64,
    disc: Vec<f64>,
    pin: Vec<f64>,
    history: &'a WearHistory,
}

/// The integration loop of [`integrate`], from zero or from `start` (whose history's stages
/// are the first of `inputs.wear.stage_hours`), telling `on_stage` each new stage.
fn integrate_from(
    inputs: &WearInputs,
    schedule: Option<&[f64]>,
    start: Option<Start>,
    progress: &(dyn Fn(usize, usize) + Sync),
    on_stage: &dyn Fn(StageWearRef),
) -> Result<WearHistory> {
    let w = inputs.wear;
    let n = inputs.grid_points();
    let last = *w.stage_hours.last().expect("validated: at least one stage");
    let step = update_step(w);
    // Expected number of rate evaluations, for the progress report.
    let total = match schedule {
        Some(sch) => 1 + sch.iter().filter(|&&x| x > 0.0 && x < last).count(),
        None if step.is_finite() => (last / step).ceil().max(1.0) as usize,
        None => 1,
    };
    let mut update_hours = Vec::new();
    let mut segments = Vec::new();
    let stages = &w.stage_hours;
    // Round-off tolerance of the hour arithmetic, relative to the horizon: an update step is
    // never shorter than horizon / budget (checked below), far above it.
    let eps = 1e-12 * last;
    let mut limit = None;
    let mut budget_checked = false;
    let smoother = BandSmoother::new(inputs)?;
    let mut h = vec![0.0; n];
    let n_pin = if w.pin_archard > 0.0 {
        PIN_MAP_POINTS
    } else {
        0
    };
    let mut hp = vec![0.0; n_pin];
    // What the last rate evaluation leaves for the next.
    let mut warm = WearWarm::default();
    let mut t = 0.0;
    let mut maps = Vec::with_capacity(stages.len());
    let mut pin_maps = Vec::with_capacity(stages.len());
    let mut si = 0;
    if let Some(st) = start {
        h = st.disc;
        hp = st.pin;
        t = st.hours;
        maps.extend(st.history.maps.iter().cloned());
        pin_maps.extend(st.history.pin_maps.iter().cloned());
        si = maps.len();
        update_hours.extend(st.history.update_hours.iter().copied());
        segments.extend(st.history.segments.iter().cloned());
        warm.clone_from(&st.history.warm);
        // The budget was checked for the history's own horizon; the rate at the start is
        // checked against the new one below.
    }
    let told = |si: usize, maps: &[Vec<f64>], pin_maps: &[Vec<f64>]| {
        on_stage(StageWearRef {
            index: si,
            hours: stages[si],
            map: &maps[si],
            pin_map: &pin_maps[si],
        })
    };
    while si < stages.len() {
        if stages[si] <= t + eps {
            maps.push(smoother.apply(&h));
            pin_maps.push(hp.clone());
            told(si, &maps, &pin_maps);
            si += 1;
            continue;
        }
        // Rate from the current worn profile (on the bearings and pins worn to this hour),
        // held until the next update.
        let grown = WornState::parts(inputs.bearing_rates, t, &hp);
        let grown = grown.reducer(inputs.reducer);
        let at_hours = WearInputs {
            reducer: &grown,
            ..*inputs
        };
        let worn = h.iter().any(|&x| x > 0.0);
        let rate = if worn {
            let smoothed = smoother.apply(&h);
            if let Some(l) = depth_limit(inputs, t, &smoothed) {
                limit = Some(l);
                break;
            }
            let evaluated = WearMap::new(smoothed.clone())
                .and_then(|m| inputs.disc.profile(Some(m)))
                .and_then(|p| wear_rate_from(&p, &at_hours, &mut warm));
            match evaluated {
                Ok(r) => r,
                Err(e) => {
                    limit = Some(ValidityLimit {
                        hours: t,
                        max_wear_um: smoothed.iter().copied().fold(0.0, f64::max) * 1e6,
                        reason: e.to_string(),
                    });
                    break;
                }
            }
        } else {
            wear_rate_from(&inputs.disc.profile(None)?, &at_hours, &mut warm)?
        };
        if rate.disc.iter().chain(&rate.pin).any(|r| !r.is_finite()) {
            return Err(Error::numerical("wear integration", "non-finite wear rate"));
        }
        let max_rate = rate
            .disc
            .iter()
            .chain(&rate.pin)
            .copied()
            .fold(0.0, f64::max);
        if schedule.is_none() {
            // The estimate from the first rate, and again whenever the updates run past twice
            // the scheduled count (the rate grows as the flank wears).
            let sched = (last / step).ceil();
            if !budget_checked || (update_hours.len() as f64) > 2.0 * sched.max(1.0) {
                check_updates(inputs, last, max_rate)?;
                budget_checked = true;
            }
        }
        update_hours.push(t);
        segments.push(WearSegment {
            start_h: t,
            disc: h.clone(),
            pin: hp.clone(),
            disc_rate: rate.disc.clone(),
            pin_rate: rate.pin.clone(),
        });
        progress(update_hours.len().min(total), total);
        let seg_end = if let Some(sch) = schedule {
            sch.iter()
                .copied()
                .find(|&x| x > t + eps && x < last)
                .unwrap_or(last)
        } else {
            let mut seg_end = if step.is_finite() {
                (((t / step + eps).floor() + 1.0) * step).min(last)
            } else {
                last
            };
            // Explicit Euler in hours is stable only while no point wears much more than the
            // contact approach between updates: cap the largest increment.
            if step.is_finite() && max_rate > 0.0 {
                seg_end = seg_end.min(t + w.max_wear_step / (max_rate * w.running_in.factor_at(t)));
            }
            // Every update advances the hours (the budget check bounds the count of them).
            seg_end.max(t + 4.0 * eps)
        };
        // The rate is the steady coefficient's; running-in scales the hours.
        let run_in = w.running_in;
        let advance = |h: &mut Vec<f64>, hp: &mut Vec<f64>, to: f64, t: &mut f64| {
            advance_depths(h, &rate.disc, run_in, *t, to);
            advance_depths(hp, &rate.pin, run_in, *t, to);
            *t = to;
        };
        while si < stages.len() && stages[si] <= seg_end + eps {
            advance(&mut h, &mut hp, stages[si], &mut t);
            let map = smoother.apply(&h);
            if let Some(l) = depth_limit(inputs, t, &map) {
                limit = Some(l);
                break;
            }
            maps.push(map);
            pin_maps.push(hp.clone());
            told(si, &maps, &pin_maps);
            si += 1;
        }
        if limit.is_some() {
            break;
        }
        if t < seg_end - eps {
            advance(&mut h, &mut hp, seg_end, &mut t);
        }
        if h.iter().chain(&hp).any(|x| !x.is_finite()) {
            return Err(Error::numerical(
                "wear integration",
                "non-finite wear depth",
            ));
        }
    }
    Ok(WearHistory {
        hours: w.stage_hours[..maps.len()].to_vec(),
        maps,
        pin_maps,
        update_hours,
        limit,
        bearing_rates: inputs.bearing_rates,
        segments,
        warm,
    })
}

/// Advances the wear depths `depth` (m) at the held rates `rate` (m per hour of the steady
/// coefficient) from `from` to `to` working hours, running-in scaling the hours
/// ([`RunningIn::equivalent_hours`]): the explicit Euler step of the integration between
/// profile updates, and its replay.
fn advance_depths(depth: &mut [f64], rate: &[f64], run_in: RunningIn, from: f64, to: f64) {
    let dh = run_in.equivalent_hours(to) - run_in.equivalent_hours(from);
    for (x, r) in depth.iter_mut().zip(rate) {
        *x += r * dh;
    }
}

/// The validity limit at `hours` where the wear map `map` (m) reaches the eccentricity, half
/// the teeth's height (the profile spans `2a` from root to tip): past it the cycloid mesh the
/// model describes is gone, whether or not its analyses still converge (docs/model.md section
/// 7.8). `None` below it.
fn depth_limit(inputs: &WearInputs, hours: f64, map: &[f64]) -> Option<ValidityLimit> {
    let deepest = map.iter().copied().fold(0.0, f64::max);
    let a = inputs.reducer.geometry.eccentricity;
    (deepest >= a).then(|| ValidityLimit {
        hours,
        max_wear_um: deepest * 1e6,
        reason: format!(
            "the wear depth {:.0} um reaches the eccentricity {:.0} um, half the teeth's height",
            deepest * 1e6,
            a * 1e6
        ),
    })
}

/// Checks, once the largest wear rate `max_rate` (m/h) of the unworn profile is known, the
/// profile updates that `wear.max_wear_step_um` asks for over `horizon` hours against the work
/// budget ([`crate::budget`]).
///
/// # Errors
/// [`Error::Invalid`] naming `wear.max_wear_step_um` if it is below its default of 1 um,
/// otherwise the Archard coefficient key, with the estimate and the budget.
pub(crate) fn check_updates(inputs: &WearInputs, horizon: f64, max_rate: f64) -> Result<()> {
    let w = inputs.wear;
    if w.model == WearModelKind::Paper || w.update_hours <= 0.0 {
        return Ok(());
    }
    let updates = (w.running_in.equivalent_hours(horizon) * max_rate / w.max_wear_step)
        .ceil()
        .max(w.scheduled_updates());
    let positions = revolution_positions(inputs.reducer);
    let total = updates * w.rate_evaluation_solves(inputs.load.len(), positions)
        + w.stage_hours.len() as f64 * inputs.budget.per_stage;
    if total <= inputs.budget.solves {
        return Ok(());
    }
    let (key, value) = if w.max_wear_step < 0.999e-6 {
        (
            "wear.max_wear_step_um".to_string(),
            format!("{}", w.max_wear_step * 1e6),
        )
    } else if w.archard_key.ends_with("m2_per_n") {
        (w.archard_key.to_string(), format!("{:.4e}", w.archard))
    } else {
        (
            w.archard_key.to_string(),
            format!("{:.4e}", w.archard * 1e9),
        )
    };
    Err(Error::invalid(
        key,
        value,
        format!(
            "the largest wear rate, {:.3e} um/h on the unworn disc, needs about {updates:.2e} \
             profile updates of at most wear.max_wear_step_um = {} um over {horizon} h: about \
             {total:.2e} contact solves (~{:.1} min), more than the work budget of {:.1} min \
             (--work-budget-min)",
            max_rate * 1e6,
            w.max_wear_step * 1e6,
            budget::minutes(total),
            budget::minutes(inputs.budget.solves),
        ),
    ))
}

/// Finds the Archard coefficient (m^2/N) that makes the maximum wear at the last stage equal
/// `target_depth` (m) within 0.1 %. Returns the coefficient and the maximum depth it gives.
///
/// Two phases of the fixed-point iteration `k <- k target / h_max(k)` (wear depth is
/// proportional to `k` without profile updates and nearly so with them): first with the model's
/// adaptive update rule until within 2 %, then with that run's update schedule held fixed
/// (`integrate_on_schedule`), on which the depth is an increasing function of `k`, so the
/// iteration cannot chatter between neighbouring schedules. The returned depth is on the fixed
/// schedule; `rvlife run` with the returned coefficient uses the adaptive rule again and lands
/// within the rule's own jitter (a few 0.1 %) of it.
///
/// # Errors
/// [`Error::Invalid`] if the target is not in `(0, 2a]` (`a` the eccentricity: the tooth
/// height), the last stage is at 0 h, the model gives no wear, or the wear model leaves its
/// validity before the target depth; [`Error::Numerical`] if the fixed-schedule phase does not
/// reach 0.1 % in 20 iterations.
pub fn calibrate(inputs: &WearInputs, target_depth: f64) -> Result<(f64, f64)> {
    let tooth = 2.0 * inputs.disc.geometry.eccentricity;
    if !(target_depth.is_finite() && target_depth > 0.0 && target_depth <= tooth) {
        return Err(Error::invalid(
            "--target-wear-um",
            target_depth * 1e6,
            format!(
                "must be a finite number in (0, {:.1}] um (the tooth height, twice \
                 cycloid.eccentricity_mm)",
                tooth * 1e6
            ),
        ));
    }
    let last = inputs.wear.stage_hours.last().copied().unwrap_or(0.0);
    if last <= 0.0 {
        return Err(Error::invalid(
            "wear.stage_hours",
            format!("{:?}", inputs.wear.stage_hours),
            "the last stage is at 0 h, where there is no wear to calibrate; list a later stage",
        ));
    }
    let mut w = inputs.wear.clone();
    let max_depth = |hist: &WearHistory| -> Result<f64> {
        if let Some(l) = &hist.limit {
            return Err(Error::invalid(
                "--target-wear-um",
                target_depth * 1e6,
                format!(
                    "the wear model leaves its validity at {:.0} h with {:.2} um of wear, before \
                     the last stage ({last} h) reaches the target: {}; aim lower",
                    l.hours, l.max_wear_um, l.reason
                ),
            ));
        }
        let achieved = *hist.max_depths().last().unwrap_or(&0.0);
        if achieved > 0.0 {
            Ok(achieved)
        } else {
            Err(Error::invalid(
                "load",
                "no wear",
                "the load spectrum (load.kind and its torques) produces no wear; nothing to \
                 calibrate",
            ))
        }
    };
    // Phase 1: adaptive schedule, coarse.
    let mut schedule = Vec::new();
    for _ in 0..20 {
        let hist = integrate(
            &WearInputs {
                wear: &w,
                ..*inputs
            },
            &|_, _| {},
        )?;
        if let Some(l) = &hist.limit {
            if l.max_wear_um * 1e-6 > target_depth && l.hours > 0.0 {
                // Past the target before the limit: a smaller coefficient reaches the target
                // at the last stage (depth about proportional to k times hours).
                w.archard *= 0.5 * target_depth / (l.max_wear_um * 1e-6) * (l.hours / last);
                continue;
            }
        }
        let achieved = max_depth(&hist)?;
        schedule = hist.update_hours;
        if (achieved / target_depth - 1.0).abs() < 0.02 {
            break;
        }
        w.archard *= target_depth / achieved;
    }
    // Phase 2: fixed schedule, fine.
    for _ in 0..20 {
        let fixed = WearInputs {
            wear: &w,
            ..*inputs
        };
        let achieved = max_depth(&integrate_on_schedule(&fixed, &schedule, &|_, _| {})?)?;
        if (achieved / target_depth - 1.0).abs() < 1e-3 {
            return Ok((w.archard, achieved));
        }
        w.archard *= target_depth / achieved;
    }
    Err(Error::numerical(
        "calibration",
        "the maximum wear did not reach the target within 0.1 % in 20 iterations",
    ))
}
