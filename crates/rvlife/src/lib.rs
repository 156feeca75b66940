//! # rvlife
//!
//! Accuracy-life prediction of RV reducers and cycloid drives: the cycloid disc profile
//! ([`geometry`]), the line contact of pins and disc ([`contact`]), the reducer's parts
//! ([`reducer`]) and its static and dynamic analyses ([`statics`], [`dynamics`], with the
//! finite-element disc of [`fem`]), Archard wear over working hours with profile updates
//! ([`wear`]), transmission error and the catalogue accuracy quantities ([`te`]), and the study
//! that strings them together ([`study`]) up to the accuracy life ([`life`]), for one reducer or
//! a toleranced batch ([`montecarlo`]), calibrated against measurements ([`calibration`]),
//! configured by TOML ([`config`]), every reported quantity declared once ([`quantities`]) and
//! written as JSON, CSV, DXF, plots and an HTML report ([`output`]); [`api`] holds the commands
//! that the command line and the Python package call.
//!
//! SI units inside; engineering units only in config keys and output columns ([`units`]). The
//! method follows Tao et al., Machines 2024, 12(8), 511 (the "paper"), documented with every
//! other model in `docs/model.md`, with true gaps from geometry and wear with profile updates
//! as the defaults; `docs/architecture.md` describes the layers of these modules.

#![warn(missing_docs)]

pub mod api;
pub mod budget;
pub mod calibration;
pub mod config;
pub mod contact;
pub mod dynamics;
pub mod efficiency;
pub mod error;
pub mod fem;
pub mod geometry;
pub mod input;
pub mod life;
pub mod montecarlo;
pub mod optimize;
pub mod output;
pub mod quantities;
pub mod reducer;
pub mod sensitivity;
pub mod statics;
pub mod study;
pub mod sweep;
pub mod te;
pub mod tribology;
pub mod units;
pub mod wear;

pub use error::{Error, Result};

#[cfg(test)]
mod tests;
