//! The numeric engine of the sim-to-real gap diagnosis: where a real run's navigation error
//! parts from its twin, which unmodelled effect of the catalogue (`sins_imu::EffectKind`)
//! explains it, with what magnitude and evidence, and how far the gap shrinks on withheld data.
//! No file I/O: samples come from a re-readable [`source::SampleSource`].
//!
//! # Method
//! - **Real track** ([`replay::replay_run`], or the CLI's own replay): the run compensated with
//!   the calibrated parameters, self-aligned and navigated exactly as `sinsbench navigate`.
//! - **Twin**: the identified model plus its noise model. Compensation uses the same
//!   parameters, so its mean error is the algorithm's floor (zero unless the caller supplies a
//!   noise-free twin replay); its spread is computed, not sampled.
//! - **Sensitivities** ([`sensitivity::run_sensitivity`], one pass over the samples for all
//!   columns): each column (one component of a candidate effect at 1 SI unit, or one calibration
//!   coefficient) is evaluated by the effect itself on the sample's context (compensated
//!   increments as the motion, recorded temperatures, smoothed temperature rates), resolved in
//!   NED with the real track's attitude carried between its 1 Hz points by the gyro increments,
//!   with a second-order quadrature (`pass`) so that perturbations correlated with the
//!   vibration rectify correctly, and integrated into 1 s bins with three moments. A linear
//!   error model (`model`: φ, δv_NE, δr_NE, vertical held) propagates every column; the
//!   stationary self-alignment is reproduced by a linear replica (`align`: coarse TRIAD
//!   Jacobian at the data's own means, the fine filter's exact gain sequence with feedback), so
//!   what the alignment absorbs (level accelerometer bias, east gyro drift) is absorbed.
//!   Measured against the nonlinear pipeline (simulate with and without the effect, replay,
//!   difference): 0.03 % for constant biases, 0.005-0.6 % for the temperature and vibration
//!   terms, 1.3 % for a 300 s thermal lag (`tests/linear_vs_nonlinear.rs`).
//! - **Twin covariance** ([`noise`]): sensor noise (white angle and velocity random walks,
//!   Gauss-Markov biases in body axes, laser-gyro quantization under vibration) propagated as a
//!   13-state covariance through the same alignment replica and attitude, with the full time
//!   correlation at the fit times; calibration uncertainty (`calib`) as one-sigma responses
//!   common to all runs; a white floor as a tolerance.
//! - **Fit** (`gls`, `problem`, `candidates`, `rank`): generalised least squares of the
//!   decimated gap, runs whitened separately and the shared calibration term by Woodbury;
//!   deterministic candidates by GLS with forward selection of components, random walks as
//!   noise terms with a maximum-likelihood intensity whose smoothed increments must pass a
//!   whiteness test (`walk`: no step-like outlier, no lag-one correlation); evidence = chi-square drop (2 Δ log L),
//!   Bonferroni-corrected tail probability and BIC; chi-square consistency tests with the
//!   null distribution of the quadratic form (Satterthwaite) so that the floor stays a tolerance.
//! - **Nonlinear refinement** (`refine`): the leading deterministic candidates whose linear
//!   residual is inconsistent (and a leading time offset) are refined by Gauss-Newton steps
//!   on the real runs replayed with the fitted effect removed from every raw sample, so that
//!   effects large enough to bend the error dynamics are fitted and tested on the real
//!   pipeline, not on an extrapolation.
//! - **Verdict**: no significant gap / explained by X / partly explained by X / unexplained /
//!   not separable X vs Y (signatures explaining each other in the twin's metric with evidence
//!   within a margin). "Explained" needs a consistent residual and one magnitude for every run
//!   (`constancy`); otherwise the winner only partly explains the gap.
//! - **Localisation** (`localise`): per segment and channel, first exit from the 3-sigma
//!   envelope, time-scale shares (secular, 24 h, Schuler, segment steps).
//! - **Withheld validation** (`validate`): leave one run out (or the second half of a single
//!   run), predict it with twin + effect(θ) (θ × sensitivity, or the refined nonlinear
//!   correction plus the step to the withheld fit), RMS, maximum-horizontal-error and
//!   systematic gaps (√(χ² − E χ²) in the twin's metric: the gap beyond the twin's spread).
//!
//! Entry point: [`diagnose()`] with an [`input::DiagnosisInput`] and an
//! [`input::DiagnoseConfig`], returning a serialisable [`report::Diagnosis`].
//!
//! # Stages (modules in the order the data flow through them)
//! 1. Inputs: `input`, `source` (samples), `replay` (the real track), `temperature`.
//! 2. The twin (`twin`): `sensitivity` (one pass per run: `pass`, `bank`, `columns`, `model`,
//!    `align`), `noise` (twin covariance), `calib`, `absorb` (the calibration run).
//! 3. Fit: `gaps` (gap and fit data per run), `problem`, `gls`, `unresolved` (slow noise an
//!    identification left open), `candidates`, `walk`, `rank`.
//! 4. Refine: `refine`.
//! 5. Time-local effects: `timelocal` over `events`.
//! 6. Verdict, localisation and validation: `constancy`, `localise`, `winner`, `validate`,
//!    `report`.
//!
//! `diagnose` runs them; `runs` and `stats` are shared helpers. Public are the entry point, its
//! input and output types, the sample sources and replay other crates feed it with, and the
//! sensitivity and absorption stages that the tests check against the nonlinear pipeline.

#![warn(missing_docs)]

// 1. Inputs.
pub mod input;
pub mod replay;
pub mod source;
mod temperature;
// 2. Sensitivities and the twin.
pub mod absorb;
mod align;
mod bank;
mod calib;
mod columns;
mod model;
pub mod noise;
mod pass;
pub mod sensitivity;
mod twin;
// 3. Fit.
mod candidates;
mod gaps;
mod gls;
mod problem;
mod rank;
mod unresolved;
mod walk;
// 4. Refine.
mod refine;
// 5. Time-local effects.
mod cal_events;
pub mod events;
mod timelocal;
// 5b. Time-local rivals of a catalogue verdict and the design's confounds.
pub mod confound;
pub mod rival;
mod stacked;
mod whiten;
// 6. Verdict, localisation, validation, and the diagnosis that runs the stages.
mod constancy;
mod diagnose;
mod localise;
pub mod report;
mod validate;
mod winner;
// Shared.
mod error;
mod runs;
mod stats;

pub use columns::param_vector;
pub use diagnose::diagnose;
pub use error::DiagError;
pub use input::{DiagnoseConfig, DiagnosisInput, RunData};
pub use pass::Grid;
pub use report::{Confound, Diagnosis, TimeCourseAlternative, Verdict};
pub use runs::track_at;
pub use stats::{chi2_isf, chi2_sf, normal_cdf};
pub use temperature::TemperatureSeries;
