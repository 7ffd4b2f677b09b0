#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod apply;
pub mod assumptions;
pub mod cell;
pub mod draw;
mod error;
pub mod gap;
pub mod sample;
pub mod sobol;
pub mod stats;
pub mod summary;
pub mod vv;

pub use error::UqError;

/// One nautical mile (m).
pub const NMI_M: f64 = 1852.0;
