#![doc = include_str!("../README.md")]
//!
//! ## Method
//!
//! The twin's sensor-noise model identified from the data: the still stretches of real runs
//! (segments labelled `alignment` / `stationary`, or, in a run without labels, the stretches
//! the stillness detector [`still`] finds; motion inside a labelled stretch is found and left
//! out) give the overlapping Allan variance of
//! the three gyros and three accelerometers (IEEE Std 952 / 1554), pooled over stretches and
//! runs, with chi-square intervals from the equivalent degrees of freedom (Howe, Allan and
//! Barnes); a weighted least-squares fit then gives the terms the twin uses, each with its
//! 1-sigma: white noise (gyro angle random walk rad/√s, accelerometer velocity random walk
//! m/s/√s), gyro quantization (rad; read off the increments' lattice when they are quantised;
//! an accelerometer's quantum, m/s, likewise, fitted but not part of the twin: with the
//! remainder carried it bounds the velocity error by one quantum),
//! first-order Gauss-Markov bias (stationary σ and correlation time) and, reported only, a rate
//! random walk. No file I/O; SI throughout.
//!
//! Entry point: [`identify_noise`] with one [`RunStationary`] per run (a re-readable
//! [`sins_diag::source::SampleSource`], its segment labels and site) and a [`NoiseIdConfig`].
//! The result converts to the simulator's [`sins_sim::NoiseModel`] and to the diagnosis's
//! [`sins_diag::noise::NoiseSpec`].
//!
//! Cost: one pass over each run, about 50 bytes of memory per second of stationary data
//! ([`accumulate`]), and a fit of a few hundred small least-squares problems.
//!
//! Modules: [`allan`] (estimator, degrees of freedom, intervals), [`quant`] (quantization of a
//! sensor at rest and the lattice detector), [`model`] (each term's Allan variance), `fit` (the
//! weighted least squares), [`homogeneity`] (do the still stretches agree?), [`turnon`] (a transient from each run's first
//! sample), [`identify`] (the entry point), [`result`].

#![warn(missing_docs)]

pub mod accumulate;
pub mod allan;
pub mod channels;
pub mod config;
pub mod error;
mod fit;
pub mod homogeneity;
pub mod identify;
pub mod model;
pub mod quant;
pub mod result;
mod spectrum;
pub mod steps;
pub mod still;
pub mod turnon;

pub use config::NoiseIdConfig;
pub use error::NoiseIdError;
pub use identify::{CORRELATION_CAP, RunStationary, identify_noise};
pub use result::{
    AllanCurve, ChangeReport, Estimate, IdentifiedNoise, RunUsage, SensorNoise, StretchReport,
};
pub use still::{MotionReport, StillnessConfig};
