//! Dynamic transmission error (DTE): a planar rigid multibody model of the whole RV reducer with
//! impact contact between the discs and the pins (paper section 3.2 and Table 3;
//! docs/model.md section 8).
//!
//! The model ([`system`]) has the input shaft with the sun, 2 or 3 crankshafts with their planets
//! (each on crank-carrier bearings), the output carrier, and two discs on the cranks' eccentrics
//! (crank-disc bearings), 180 degrees apart, against the fixed pin ring. Every disc-pin gap comes
//! from the actual (modified or worn) profile through a tabulated field of exact projections
//! (`gap`); the force is MSC Adams IMPACT. The input is driven by a `STEP` speed ramp or a
//! motor torque; the output carries no load, a constant, a sinusoidal or a tabulated torque
//! ([`params`]).
//!
//! State: the input angle and speed, and for every other coordinate its *deviation* from the
//! nominal rigid kinematics driven by the input (`theta_o = theta_s / i_H`, cranks, eccentrics).
//! The deviations are microns and microradians, so the integrator's error control acts on what
//! matters (the TE itself is the output deviation) rather than on angles that grow to hundreds of
//! radians.
//!
//! Integration ([`ode`]), from `diffsol` with error control: by default the L-stable ESDIRK
//! 3(4) pair, whose steps follow the accuracy wanted rather than the stiff (about 10 kHz)
//! contact and bearing modes, with a forward-difference Jacobian whose columns recompute only
//! the contacts their state moves; or the explicit Tsitouras 5(4) pair, which resolves those
//! modes at steps of a few microseconds (`dynamics.integrator`; docs/model.md section 8).

pub mod ode;
pub mod params;
pub mod system;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::fem::modal::ModalDisc;
use crate::fem::{DiscSet, FemParams, Mount};
use crate::geometry::Profile;
use crate::reducer::Reducer;
use crate::units::ARCMIN_PER_RAD;

pub use crate::contact::gap::{Band, GapField};
pub use crate::fem::modal::ModalSettings;
use params::Method;
pub use params::{Damping, DynamicsParams};
pub use system::{PinForce, System};

/// One sample of the time series (engineering units, as written to `dynamics.csv`).
#[derive(Debug, Clone, Serialize)]
pub struct Sample {
    /// Time, s.
    pub time_s: f64,
    /// Input shaft angle, deg.
    pub input_angle_deg: f64,
    /// Output shaft angle, deg.
    pub output_angle_deg: f64,
    /// Input speed, deg/s.
    pub input_speed_deg_s: f64,
    /// Output speed, deg/s.
    pub output_speed_deg_s: f64,
    /// Transmission error `theta_out - theta_in / i_H`, arcmin (paper eq 21).
    pub te_arcmin: f64,
    /// Output load torque, N m.
    pub load_nm: f64,
    /// Pins in contact on disc 1 and disc 2.
    pub pins_in_contact: [usize; 2],
    /// Largest pin force, N.
    pub max_pin_force_n: f64,
}

/// Summary of one simulation over the TE window.
#[derive(Debug, Clone, Serialize)]
#[cfg_attr(feature = "ts", derive(ts_rs::TS))]
pub struct DynamicsSummary {
    /// Largest wear depth of the disc profile simulated, um.
    pub max_wear_um: f64,
    /// Window start, s.
    pub window_start_s: f64,
    /// Window end, s.
    pub window_end_s: f64,
    /// Mean TE, arcmin.
    pub te_mean_arcmin: f64,
    /// Peak-to-peak TE, arcmin.
    pub te_peak_to_peak_arcmin: f64,
    /// RMS of the TE (about zero), arcmin.
    pub te_rms_arcmin: f64,
    /// Smallest TE, arcmin.
    pub te_min_arcmin: f64,
    /// Largest TE, arcmin.
    pub te_max_arcmin: f64,
    /// Mean output speed over the window, deg/s.
    pub output_speed_deg_s: f64,
    /// Mean input speed over the window divided by `i_H`, deg/s.
    pub nominal_output_speed_deg_s: f64,
    /// Largest pin force in the window, N.
    pub max_pin_force_n: f64,
    /// Accepted integrator steps.
    pub steps: usize,
    /// Full right-hand-side evaluations.
    pub rhs_evaluations: usize,
    /// Finite-difference Jacobian columns, each evaluating only the contacts its state moves
    /// (ESDIRK34; 0 for Tsit45).
    pub jacobian_columns: usize,
    /// Elastic modes per disc (0: rigid discs).
    pub disc_modes: usize,
    /// Natural frequencies of the flexible disc's modes (bores held), Hz.
    pub disc_mode_frequencies_hz: Vec<f64>,
    /// The integrator that produced the result: `"esdirk34"` or `"tsit45"`.
    pub integrator: String,
    /// Why the configured integrator was replaced, when it was: ESDIRK34's Newton iteration
    /// can stall at a non-smooth contact event (its step size then falls below 1e-13 s); the
    /// run is then repeated with Tsitouras 5(4) at the same tolerance.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "ts", ts(optional))]
    pub integrator_fallback: Option<String>,
}

/// Result of one simulation.
#[derive(Debug, Clone)]
pub struct DynamicsResult {
    /// Time series at the output interval.
    pub samples: Vec<Sample>,
    /// Pin forces per sample (`2 x Zp` per row, N, disc-major), if asked for.
    pub pin_forces: Option<Vec<Vec<f64>>>,
    /// Deviations of every coordinate from the nominal kinematics per sample, with the pin
    /// forces (one row of `crate::reducer::Layout::dofs` entries: m for positions, rad for
    /// angles; the layout of [`crate::statics::StaticSolution::deviations`]).
    pub deviations: Option<Vec<Vec<f64>>>,
    /// Summary over the window.
    pub summary: DynamicsSummary,
}

/// Simulates the reducer with the disc profile `profile` (both discs alike) and returns the
/// time series and the TE summary. With `pin_forces`, also every pin force and the deviations
/// of every coordinate at every sample.
///
/// # Errors
/// [`Error::Numerical`] if the gap table cannot be built, the integrator fails (step size
/// underflow) or a state becomes non-finite.
pub fn simulate(
    profile: &Profile,
    reducer: &Reducer,
    params: &DynamicsParams,
    pin_forces: bool,
) -> Result<DynamicsResult> {
    simulate_with(profile, reducer, params, None, pin_forces)
}

/// Flexible discs of the multibody model: the modal FE disc and how each of the two discs sits
/// on it ([`Mount`]: disc 2 of an RV reducer is disc 1's part turned by pi).
#[derive(Debug, Clone, Copy)]
pub struct FlexibleDiscs<'a> {
    /// The modal reduction of the discs' FE model.
    pub modal: &'a ModalDisc<'a>,
    /// Per disc, its mount on the model.
    pub mounts: [Mount; 2],
}

impl<'a> FlexibleDiscs<'a> {
    /// Both discs of `discs` on `modal` (the reduction of `discs.models[0]`).
    ///
    /// # Errors
    /// [`Error::Invalid`] (key `dynamics.disc`) if a disc needs a model of its own (its turn
    /// is no symmetry of the holes of `[fem]`): the multibody model carries one modal disc.
    pub fn new(modal: &'a ModalDisc<'a>, discs: &DiscSet) -> Result<FlexibleDiscs<'a>> {
        if discs.mounts.len() != 2 || discs.mounts.iter().any(|m| m.model != 0) {
            return Err(crate::error::Error::invalid(
                "dynamics.disc",
                "\"flexible\"",
                "needs the discs to be one part turned by the eccentric phase onto itself: the \
                 crank bores and holes of [fem] must map onto themselves under that turn (an \
                 even number of cranks and an odd tooth count do); use \"rigid\" discs, or the \
                 quasi-static flexible disc of [fem], which models each disc",
            ));
        }
        Ok(FlexibleDiscs {
            modal,
            mounts: [discs.mounts[0], discs.mounts[1]],
        })
    }
}

/// [`simulate_with`] with the discs that `params.flexible` asks for: rigid, or the FE disc of
/// `fem` (mesh and holes of `[fem]`) on `profile`, modally reduced ([`ModalDisc::build`]).
/// `discs` reuses the FE discs already built on `profile` with `fem`.
///
/// # Errors
/// As [`simulate_with`], and the FE model's and the modal reduction's errors;
/// [`FlexibleDiscs::new`]'s.
pub fn simulate_discs(
    profile: &Profile,
    reducer: &Reducer,
    params: &DynamicsParams,
    fem: &FemParams,
    discs: Option<&DiscSet>,
    pin_forces: bool,
) -> Result<DynamicsResult> {
    let Some(settings) = &params.flexible else {
        return simulate_with(profile, reducer, params, None, pin_forces);
    };
    let built;
    let discs = match discs {
        Some(d) => d,
        None => {
            built = DiscSet::build(profile, fem, reducer)?;
            &built
        }
    };
    let modal = ModalDisc::build(&discs.models[0], settings)?;
    let flexible = FlexibleDiscs::new(&modal, discs)?;
    // The FE disc is the disc's body: not again in series with the bearings.
    simulate_with(
        profile,
        &reducer.without_disc_body(),
        params,
        Some(flexible),
        pin_forces,
    )
}

/// [`simulate`] with rigid discs (`flexible` = `None`) or with flexible discs: each disc the
/// modal FE disc (fixed-interface modes and residual flexibility at the load stations,
/// [`crate::fem::modal`]) of the same profile, at its own contact parameters mapped by its
/// mount.
///
/// # Errors
/// As [`simulate`]; [`Error::Invalid`] if the disc inertia is below the modes' effective mass;
/// [`Error::Numerical`] also if a flexible contact problem fails to converge.
pub fn simulate_with(
    profile: &Profile,
    reducer: &Reducer,
    params: &DynamicsParams,
    flexible: Option<FlexibleDiscs>,
    pin_forces: bool,
) -> Result<DynamicsResult> {
    let field = params.gap_field(profile, reducer)?;
    let sys = match flexible {
        Some(fd) => System::flexible(params, reducer, [&field, &field], fd)?,
        None => System::new(params, reducer, [&field, &field]),
    };
    let zp = reducer.geometry.pins;
    let n_out = (params.end_time / params.output_interval).round() as usize;
    let times: Vec<f64> = (0..=n_out)
        .map(|i| (i as f64 * params.output_interval).min(params.end_time))
        .collect();
    let dofs = sys.layout().dofs();
    let mut dz = vec![0.0; sys.states()];
    let mut pins = vec![PinForce::default(); 2 * zp];
    let mut samples = Vec::with_capacity(times.len());
    let mut forces_out = pin_forces.then(|| Vec::with_capacity(times.len()));
    let mut deviations_out = pin_forces.then(|| Vec::with_capacity(times.len()));
    let mut method = params.integrator;
    let mut fallback = None;
    let stats = loop {
        samples.clear();
        forces_out.iter_mut().for_each(|v| v.clear());
        deviations_out.iter_mut().for_each(|v| v.clear());
        sys.reset_caches();
        let run = ode::integrate(
            &sys,
            method,
            params.rtol,
            pin_forces,
            params.end_time,
            &times,
            |t, z| {
                pins.iter_mut().for_each(|p| *p = PinForce::default());
                sys.rhs(t, z, &mut dz, Some(&mut pins));
                let [th_i, th_o, w_i, w_o] = sys.shafts(t, z);
                let te = sys.transmission_error(z) * ARCMIN_PER_RAD;
                let count = |d: usize| {
                    pins[d * zp..(d + 1) * zp]
                        .iter()
                        .filter(|p| p.normal > 0.0)
                        .count()
                };
                samples.push(Sample {
                    time_s: t,
                    input_angle_deg: th_i.to_degrees(),
                    output_angle_deg: th_o.to_degrees(),
                    input_speed_deg_s: w_i.to_degrees(),
                    output_speed_deg_s: w_o.to_degrees(),
                    te_arcmin: te,
                    load_nm: params.load.torque(t),
                    pins_in_contact: [count(0), count(1)],
                    max_pin_force_n: pins.iter().map(|p| p.normal).fold(0.0, f64::max),
                });
                if let Some(f) = forces_out.as_mut() {
                    f.push(pins.iter().map(|p| p.normal).collect());
                }
                if let Some(d) = deviations_out.as_mut() {
                    d.push(z[..dofs].to_vec());
                }
                if te.is_finite() {
                    Ok(())
                } else {
                    Err(Error::numerical(
                        "dynamics",
                        format!("the state became non-finite at t = {t:.6} s"),
                    ))
                }
            },
        );
        match run {
            Err(Error::Numerical { message, .. }) if method == Method::Esdirk34 => {
                fallback = Some(message);
                method = Method::Tsit45;
            }
            other => break other?,
        }
    };
    let mut summary = summarize(&samples, params, reducer.ratio, stats);
    summary.integrator = match method {
        Method::Esdirk34 => "esdirk34",
        Method::Tsit45 => "tsit45",
    }
    .into();
    summary.integrator_fallback = fallback;
    summary.max_wear_um = profile.wear().map_or(0.0, |w| w.max_depth()) * 1e6;
    summary.disc_modes = sys.modes();
    if let Some(fd) = flexible {
        summary.disc_mode_frequencies_hz = fd
            .modal
            .omega
            .iter()
            .map(|w| w / std::f64::consts::TAU)
            .collect();
    }
    Ok(DynamicsResult {
        samples,
        pin_forces: forces_out,
        deviations: deviations_out,
        summary,
    })
}

fn summarize(
    samples: &[Sample],
    p: &DynamicsParams,
    ratio: f64,
    stats: ode::Stats,
) -> DynamicsSummary {
    let (w0, w1) = p.window;
    let eps = 1e-9 * p.end_time;
    let win: Vec<&Sample> = samples
        .iter()
        .filter(|s| s.time_s >= w0 - eps && s.time_s <= w1 + eps)
        .collect();
    let te: Vec<f64> = win.iter().map(|s| s.te_arcmin).collect();
    let n = te.len().max(1) as f64;
    let mean = te.iter().sum::<f64>() / n;
    let rms = (te.iter().map(|x| x * x).sum::<f64>() / n).sqrt();
    let min = te.iter().copied().fold(f64::INFINITY, f64::min);
    let max = te.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (first, last) = (win.first(), win.last());
    let (speed, nominal) = match (first, last) {
        (Some(a), Some(b)) if b.time_s > a.time_s => {
            let dt = b.time_s - a.time_s;
            (
                (b.output_angle_deg - a.output_angle_deg) / dt,
                (b.input_angle_deg - a.input_angle_deg) / dt / ratio,
            )
        }
        _ => (0.0, 0.0),
    };
    DynamicsSummary {
        max_wear_um: 0.0,
        window_start_s: w0,
        window_end_s: w1,
        te_mean_arcmin: mean,
        te_peak_to_peak_arcmin: if te.is_empty() { 0.0 } else { max - min },
        te_rms_arcmin: rms,
        te_min_arcmin: if te.is_empty() { 0.0 } else { min },
        te_max_arcmin: if te.is_empty() { 0.0 } else { max },
        output_speed_deg_s: speed,
        nominal_output_speed_deg_s: nominal,
        max_pin_force_n: win.iter().map(|s| s.max_pin_force_n).fold(0.0, f64::max),
        steps: stats.steps,
        rhs_evaluations: stats.rhs_evaluations,
        jacobian_columns: stats.jacobian_columns,
        disc_modes: 0,
        disc_mode_frequencies_hz: Vec::new(),
        integrator: String::new(),
        integrator_fallback: None,
    }
}
