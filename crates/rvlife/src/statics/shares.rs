//! Where the elastic twist goes: the share of the twist under a torque that each part of the
//! reducer takes (docs/model.md section 5.9).
//!
//! A part's share is the elastic twist that goes when that part alone is made rigid, over the
//! whole elastic twist: `(psi_e - psi_e')/psi_e`, with `psi_e = psi(T) - psi(0+)` (the twist
//! beyond the no-load point, so that clearances count as play, not as compliance) and `psi_e'`
//! the same with the part rigid. Means over the crank angles given. The parts are nonlinear
//! (rollers, Hertz contacts), so the shares add to 100 % only nearly.

use rayon::prelude::*;
use serde::Serialize;

use super::StaticAnalysis;
use crate::contact::ApproachLaw;
use crate::error::{Error, Result};
use crate::geometry::Profile;
use crate::reducer::structure::SeriesCompliances;
use crate::reducer::{BearingLaw, Drive, Reducer};

/// A stiffness that stands for a rigid bearing or mesh, N/m (1e13: about 4e3 times the
/// stiffest part of an RV-40E-class reducer, its carrier seats).
const RIGID: f64 = 1e13;

/// A stiffness that stands for a rigid disc-pin contact, N/m (1e12: about 1e3 times a loaded
/// contact's; stiffer would raise the round-off floor of the contact forces, `4 eps Rp sum
/// k_j`, to 10 N on 20 pins).
const RIGID_CONTACT: f64 = 1e12;

/// One part's share of the elastic twist (docs/model.md section 5.9).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TwistShare {
    /// The part: `"crank bearings"`, `"crank bending"` (both eccentrics' terms), `"disc
    /// body"`, `"disc bores"` (their ovalisation), `"carrier"`, `"housing"`, `"structure"` (the structure compliance), `"input shaft"`, `"first
    /// stage"` (the sun-planet meshes with the cranks' torsion in series), `"disc-pin
    /// contacts"` (with the pins' housing grooves) or, for a single-stage drive, `"eccentric
    /// bearings"`, `"output pins"`.
    pub part: &'static str,
    /// Its share of the elastic twist, 0..1.
    pub share: f64,
    /// The elastic twist it takes, rad (mean over the crank angles).
    pub twist: f64,
}

/// The parts of `red` that have a compliance, each with the reducer that has it rigid.
fn rigid_variants(red: &Reducer) -> Vec<(&'static str, Reducer)> {
    let mut out = Vec::new();
    let mut with = |part: &'static str, f: &dyn Fn(&mut Reducer)| {
        let mut r = red.clone();
        f(&mut r);
        if r != *red {
            out.push((part, r));
        }
    };
    let single = matches!(red.drive, Drive::SingleStage(_));
    with(
        if single {
            "eccentric bearings"
        } else {
            "crank bearings"
        },
        &|r| {
            r.bearings.disc.law = BearingLaw::Linear { stiffness: RIGID };
            if !single {
                r.bearings.carrier.law = BearingLaw::Linear { stiffness: RIGID };
            }
        },
    );
    if !single {
        // A part in series taken out of the sums it is in (the bearings' and the meshes'
        // series stiffness): what the reducer would be with it rigid.
        let without = |r: &mut Reducer, c: &dyn Fn(&mut SeriesCompliances)| {
            let mut s = r.series;
            c(&mut s);
            r.set_series(s);
        };
        with("crank bending", &|r| {
            without(r, &|s| {
                s.crank_bending_own = 0.0;
                s.crank_bending_shared = 0.0;
            });
            // A bending stiffness of a linear model's key, not in the parts.
            if r.series.disc_side() == 0.0 {
                r.bearings.disc.series_stiffness = f64::INFINITY;
            }
        });
        with("disc body", &|r| without(r, &|s| s.disc_body = 0.0));
        with("disc bores", &|r| without(r, &|s| s.disc_bores = 0.0));
        with("carrier", &|r| without(r, &|s| s.carrier = 0.0));
        with("housing", &|r| without(r, &|s| s.housing = 0.0));
        with("structure", &|r| without(r, &|s| s.structure = 0.0));
        with("input shaft", &|r| without(r, &|s| s.input_shaft = 0.0));
        with("first stage", &|r| {
            without(r, &|s| s.crank_torsion = 0.0);
            r.mesh.stiffness = 1.0 / (1.0 / RIGID + r.series.mesh_side());
        });
    }
    with("disc-pin contacts", &|r| {
        r.contact.law = ApproachLaw::Linear {
            stiffness: RIGID_CONTACT,
        };
        r.contact.groove = None;
    });
    if let Drive::SingleStage(w) = red.drive {
        with("output pins", &|r| {
            let mut w = w;
            w.stiffness = RIGID;
            r.drive = Drive::SingleStage(w);
        });
    }
    out
}

/// The elastic twist (rad) of `red` on `profile` under `torque` (N m), mean over
/// `crank_angles` (rad).
fn elastic_twist(
    red: &Reducer,
    profile: &Profile,
    crank_angles: &[f64],
    torque: f64,
) -> Result<f64> {
    let sa = StaticAnalysis::new(red, profile)?;
    let s = torque.signum();
    let twists = crank_angles
        .par_iter()
        .map(|&phi| Ok(sa.solve(phi, torque)?.twist - sa.no_load_twist(phi, s)?))
        .collect::<Result<Vec<f64>>>()?;
    Ok(twists.iter().sum::<f64>() / twists.len().max(1) as f64)
}

/// Each part's share of the elastic twist of `red` on `profile` under `torque` (N m, usually
/// the rated torque), mean over `crank_angles` (rad): one entry per part that has a
/// compliance, in the order of [`TwistShare::part`]'s list (docs/model.md section 5.9).
/// Bearings-supported discs only (empty for the paper's rigid support).
///
/// # Errors
/// [`Error::Invalid`] for a torque that is not positive or a reducer that does not twist
/// under it; failures of the static analysis of `red` or of a variant with a part made rigid.
pub fn twist_shares(
    red: &Reducer,
    profile: &Profile,
    crank_angles: &[f64],
    torque: f64,
) -> Result<Vec<TwistShare>> {
    if red.support != crate::reducer::Support::Bearings {
        return Ok(Vec::new());
    }
    if torque.is_nan() || torque <= 0.0 {
        return Err(Error::invalid("torque", torque, "must be positive"));
    }
    let whole = elastic_twist(red, profile, crank_angles, torque)?;
    if whole.is_nan() || whole <= 0.0 {
        return Err(Error::invalid(
            "torque",
            torque,
            "twists the reducer by no elastic angle: no shares to give",
        ));
    }
    rigid_variants(red)
        .into_iter()
        .map(|(part, r)| {
            let twist = whole - elastic_twist(&r, profile, crank_angles, torque)?;
            Ok(TwistShare {
                part,
                share: twist / whole,
                twist,
            })
        })
        .collect()
}
