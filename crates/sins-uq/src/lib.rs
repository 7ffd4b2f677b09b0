//! The replica of Wang et al. 2021 Table 5 as a validated prediction, free of file formats:
//!
//! - [`assumptions`]: every input the paper does not fix, as a named assumption with a
//!   distribution (SI) and a justification; candidate explanations of the replica-vs-paper gap
//!   as overrides of those assumptions and extra effects;
//! - [`draw`]: deterministic draws (one ChaCha8 stream per sample index, whatever the thread
//!   count or sharding);
//! - [`apply`]: a draw turned into the concrete calibration and navigation scenarios;
//! - [`sample`]: one Monte Carlo sample end to end (simulate, calibrate 30 and 42 states,
//!   simulate and replay the navigation runs), and a parallel runner;
//! - [`stats`]: quantiles, bootstrap errors, first-order Sobol indices from given data;
//! - [`sobol`]: grouped first-order and total Sobol indices by the pick-freeze design;
//! - [`vv`]: the ASME V&V 20 comparison per Table 5 cell;
//! - [`gap`]: the likelihood of the paper's cells under each candidate, the choice on some cells
//!   and the shrinkage on the withheld ones;
//! - [`summary`]: everything above as one serialisable summary.
//!
//! Units: SI inside (m, s, rad, m/s^2, degC); nautical miles only in [`summary`].

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
