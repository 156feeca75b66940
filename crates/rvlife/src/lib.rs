//! rvlife: accuracy-life prediction of RV reducers and cycloid drives.
pub mod contact;
pub mod error;
pub mod geometry;

pub use error::{Error, Result};
