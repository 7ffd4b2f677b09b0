//! The sim-to-real gap on files (`sinsbench diagnose`, `sinsbench blind`):
//!
//! - [`DatasetSource`]: any dataset in the project's format as a re-readable sample source of
//!   the diagnosis (read from disk in bounded batches on every pass);
//! - [`diagnose_datasets`]: replay each dataset with the calibrated parameter set, then run
//!   `sins_diag::diagnose` against the twin (identified model + noise model);
//! - [`write_diagnosis`]: `report.md`, `diagnosis.json`, PNG plots of the gap against the twin's
//!   3-sigma envelope, one Rerun recording, written atomically;
//! - [`noise_report`]: the report of `sinsbench noise` (terms, stretches, motion, warnings,
//!   Allan plot) written as a directory `diagnose --noise-from` reads;
//! - [`blind`]: the blind validation suite (cases with hidden effects, sealed manifests whose
//!   hashes are fixed before the diagnosis runs, grading with the confusion table).

#![warn(missing_docs)]

pub mod blind;
mod error;
mod markdown;
mod markdown_events;
mod markdown_rivals;
mod noise;
pub mod noise_report;
mod run;
mod source;
pub mod still;
mod write;

pub use error::GapError;
pub use markdown::render_markdown;
pub use noise::{identify_datasets, identify_datasets_with};
pub use run::{DiagnoseRequest, DiagnosisOutcome, diagnose_datasets};
pub use source::DatasetSource;
pub use write::write_diagnosis;
