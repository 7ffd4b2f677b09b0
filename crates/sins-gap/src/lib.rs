#![doc = include_str!("../README.md")]
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
pub use run::{
    DiagnoseRequest, DiagnosisOutcome, diagnose_datasets, diagnose_datasets_identifying,
};
pub use source::DatasetSource;
pub use write::write_diagnosis;
