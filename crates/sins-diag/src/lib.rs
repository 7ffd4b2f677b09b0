#![doc = include_str!("../README.md")]
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
mod recalibration;
pub mod sensitivity;
mod twin;
// 3. Fit.
mod candidates;
mod catalogue;
mod context;
mod dense;
mod gaps;
mod gls;
mod problem;
mod rank;
mod unresolved;
mod walk;
// 4. Refine.
mod refine;
mod refinement;
// 5. Time-local effects.
mod cal_events;
pub mod events;
mod timelocal;
// 5b. Time-local rivals of a catalogue verdict and the design's confounds.
pub mod confound;
pub mod rival;
mod stacked;
mod whiten;
// 6. Verdict, its check against the calibration run, localisation, validation, and the
// diagnosis that runs the stages.
pub mod cal_innovations;
mod constancy;
mod diagnose;
mod judge;
mod localise;
pub mod report;
mod validate;
mod winner;
// Shared.
mod error;
mod parallel;
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
