//! # rvlife
//!
//! Accuracy-life prediction of RV reducers and cycloid drives: the cycloid disc profile
//! ([`geometry`]), the loaded contact between disc and pins ([`contact`]), Archard wear over
//! working hours with profile updates ([`wear`]), static and loaded transmission error and lost
//! motion ([`te`]), and the study that strings them together ([`study`]) up to the accuracy
//! life ([`life`]), for one reducer or a toleranced batch ([`montecarlo`]), calibrated against
//! measurements ([`calibration`]), configured by TOML
//! ([`config`]) and reported as JSON, CSV, DXF and plots ([`report`], [`export`], [`plot`]).
//!
//! SI units inside; engineering units only in config keys and output columns. The method follows
//! Tao et al., Machines 2024, 12(8), 511 (the "paper"), documented with every other model in `docs/model.md`, with
//! true gaps from geometry and wear with profile updates as the defaults.

#![warn(missing_docs)]

pub mod api;
pub mod budget;
pub mod calibration;
pub mod config;
pub mod contact;
pub mod dynamics;
pub mod error;
pub mod fem;
pub mod geometry;
pub mod life;
pub mod montecarlo;
pub mod output;
pub mod quantities;
pub mod reducer;
pub mod statics;
pub mod study;
pub mod te;
pub mod units;
pub mod wear;

pub use error::{Error, Result};
