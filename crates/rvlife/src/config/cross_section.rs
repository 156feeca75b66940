//! The rules that span sections, applied after every section has been checked on its own:
//! sizes outside `[cycloid]` defaulted from the stage, the mechanical model assembled from
//! `[reducer]`, `[contact]`, `[materials]` and `[errors]` (with the contact band's default from
//! the rating), the measured profile fitted on the wear grid of `[wear]`, and what a key left
//! out defaults to, for the messages. The physical checks of the unworn stage, the last rule,
//! are in [`super::physical`].

use std::path::Path;

use super::contact::ContactParams;
use super::reducer::ReducerParts;
use crate::error::Result;
use crate::geometry::{fit, read_points, CycloidGeometry, MeasuredProfile, Profile};
use crate::reducer::errors::PartErrors;
use crate::reducer::{Drive, Reducer};

/// The reducer's mechanical model: the drive, meshes and bearings of `parts`, the stage
/// `geometry`, the contact law and support of `contact` (its band force by default Li's largest
/// pin force at the rated torque on one disc, docs/model.md section 5), the gap table's
/// resolution `gap_points` (mesh angles per tooth) and the part errors.
pub(super) fn reducer(
    parts: &ReducerParts,
    geometry: &CycloidGeometry,
    contact: &ContactParams,
    gap_points: usize,
    errors: PartErrors,
) -> Reducer {
    let mut reducer = Reducer {
        geometry: geometry.clone(),
        ratio: parts.ratio,
        cranks: parts.cranks,
        crank_circle_radius: parts.crank_circle_radius,
        mesh: parts.mesh,
        bearings: parts.bearings,
        contact: contact.law,
        support: contact.support,
        contact_band_force: 0.0,
        contact_envelope: contact.envelope,
        gap_points,
        errors,
        drive: parts.drive,
        disc_phases: parts.disc_phases.clone(),
        pin_wear: Default::default(),
        series: parts.series,
        friction: None,
    };
    reducer.contact_band_force = match contact.band_force {
        Some(f) => f,
        // Li's largest pin force at the rated torque on one disc (docs/model.md section 5).
        None => {
            4.0 * 0.5 * parts.rating.rated_torque * reducer.twist_factor()
                / (geometry.disc_pitch_radius() * geometry.pins as f64)
        }
    };
    reducer
}

/// The RV reducer whose multibody and FE data a single-stage drive carries (the same stage on
/// a 1:3 first stage with two cranks on the output pin circle, nominal parts): never read by
/// an analysis, since both are refused for a single-stage drive, but checked like an RV's.
pub(super) fn rv_twin(parts: &ReducerParts, reducer: &Reducer) -> Reducer {
    Reducer {
        drive: Drive::Rv,
        cranks: 2,
        crank_circle_radius: parts.rv_mesh.sun_pitch_radius + parts.rv_mesh.planet_pitch_radius,
        mesh: parts.rv_mesh,
        disc_phases: vec![0.0, std::f64::consts::PI],
        errors: Default::default(),
        ..reducer.clone()
    }
}

/// The measured profile of `cycloid.measured_profile` (the file at `path`), fitted as a normal
/// deviation map over the described `profile` on the wear grid of `grid` points per tooth
/// (docs/model.md section 14).
///
/// # Errors
/// Those of [`read_points`] and [`fit`], naming the key.
pub(super) fn measured(profile: &Profile, path: &Path, grid: usize) -> Result<MeasuredProfile> {
    let points = read_points(path)?;
    fit(profile, &points, grid, path)
}

/// What the default of a key not set in the user's file depends on.
pub(super) fn default_source(key: &str) -> &'static str {
    match key {
        "fem.crank_bore_diameter_mm" => {
            "its default is 2 x dynamics.inertia.crank_bore_radius_mm; set it in [fem]"
        }
        "dynamics.inertia.crank_bore_radius_mm"
        | "fem.output_pin_hole_diameter_mm"
        | "fem.centre_hole_diameter_mm"
        | "reducer.gears.planet_pitch_radius_mm" => {
            "its default scales the paper's reducer with the disc's root radius Rp - rrp - a \
             of [cycloid]; set it to change it"
        }
        "fem.crank_circle_radius_mm" => {
            "its default is the crank circle, sun + planet pitch radius from [reducer.gears] \
             and the tooth numbers; set it in [fem]"
        }
        "fem.output_pin_circle_radius_mm" => {
            "its default is the crank circle radius; set it in [fem]"
        }
        "fem.output_pin_hole_phase_deg" => {
            "its default is 180 / fem.output_pin_holes; set it in [fem]"
        }
        "contact.band_force_n" => {
            "its default is Li's largest pin force at reducer.rated_torque_nm; set it in [contact]"
        }
        "te.loaded_torque_nm"
        | "load.torque_nm"
        | "load.amplitude_nm"
        | "dynamics.load.torque_nm"
        | "dynamics.load.amplitude_nm" => "its default is reducer.rated_torque_nm",
        _ => "a built-in default; set the key to change it",
    }
}
