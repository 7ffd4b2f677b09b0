#![doc = include_str!("../README.md")]
//!
//! ## Design choices
//!
//! - **Closed loop** ([`filter`]): navigation errors are corrected in the strapdown solution and
//!   coefficient errors added to the running estimate after every update; the estimate
//!   compensates the following raw samples exactly (eqs 3-5), so the error states are zero before
//!   each propagation and the first-order model of eq (6) stays valid.
//! - **Discretisation** (module `moments`): over an update interval (default 1 s) the
//!   navigation block `F_nn` is constant on a turntable, while `C_b^n` turns at 9 deg/s; the
//!   coefficient block `Φ_np = Σ Fⁿ M_n` is built from per-sample moment sums of `C_b^n` times
//!   the increments, so the rotation is followed sample by sample at ~350 multiply-adds per
//!   sample.
//! - **Structure** (module `covariance`): `Φ = [[Φ_nn, Φ_np], [0, D]]` touches only the 9
//!   navigation rows, `O(9 n²)` per propagation; Joseph-form update of the 6 measurements.
//! - **Noise**: white gyro/accelerometer noise into φ/δV; bias instability as Gauss-Markov
//!   nuisance states beside eq (8) ([`FilterNoise`]); a tiny numerical floor
//!   ([`ARW_FLOOR_RAD_PER_SQRT_S`]) keeps noise-free runs regular.
//! - **Followers** ([`CalibrationFilter::following`]): filters fed the same run with small
//!   perturbations (the diagnosis's finite differences) can apply a leading filter's gains to
//!   their own innovations instead of keeping 42-state covariances; their estimates differ from
//!   their own filters' by the gains' difference (first order in the perturbation) times the
//!   innovations.
//! - **Navigation**: free vertical channel, two-sample increments with the second-order
//!   rotation term (`sins_nav::mechanization`), which removes a 0.02 ppm scale-factor bias the classical
//!   algorithm leaves under the scheme's turns.

#![warn(missing_docs)]

pub mod config;
mod covariance;
#[cfg(test)]
mod dynamics;
mod engine;
pub mod error;
pub mod filter;
mod moments;
pub mod report;
pub mod states;

pub use config::{CalibrationConfig, FilterNoise, InitialSigmas, MeasurementNoise, MotionCheck};
pub use engine::{ARW_FLOOR_RAD_PER_SQRT_S, SharedGain, VRW_FLOOR_MPS_PER_SQRT_S};
pub use error::CalibrationError;
pub use filter::CalibrationFilter;
pub use report::{
    CalibrationResult, ObservabilityReport, Snapshot, StandardizedInnovation, StateObservability,
};
pub use states::{STATE_NAMES, STATE_UNITS, n_params, params_from_vec, params_to_vec};
