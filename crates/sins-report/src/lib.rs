//! The navigation report of sinsbench (`sinsbench report`): run a report configuration
//! ([`run_report`]: calibrate or load the parameter sets, simulate or read the navigation data,
//! replay each experiment under every set) and write `reports/<name>/` atomically
//! ([`write_report`]): `report.md` (the paper's Table 5 layout beside ours, per-segment maxima),
//! `summary.json` (`sins_config::summary_to_json`), one Parquet error track, PNG plots and one
//! Rerun `.rrd` per experiment, and the calibrated parameter sets.
//!
//! This crate and `sins-data` / `sins-viz` are the only ones here that link polars or rerun.

#![warn(missing_docs)]

mod dataset;
mod error;
mod markdown;
mod names;
mod output;
mod plots;
mod prediction;
mod progress;
mod rrd;
mod run;
mod simulate;
mod tracks;
mod uq_config;
mod uq_markdown;
mod uq_write;

pub use dataset::{replay_dataset, require_temperatures};
pub use error::ReportError;
pub use markdown::render_markdown;
pub use output::{
    OUTPUT_MARKER, ReportFiles, check_output_dir, write_bytes, write_dir_atomically, write_report,
};
pub use prediction::prediction_for_report;
pub use progress::Progress;
pub use run::{ReportRun, ResolvedSet, run_report};
pub use simulate::{
    check_output_space, dataset_meta, estimated_dataset_bytes, human_bytes, simulate_to_dataset,
    simulate_to_dataset_with,
};
pub use uq_config::{
    UqStudy, load_base, load_table2, load_uq_study, paper_cells, table2_indices, unit_si,
};
pub use uq_markdown::{render_uq_markdown, uq_table_for_report};
pub use uq_write::{
    intervals_figure, read_sample, sample_path, sensitivity_figure, write_sample, write_uq_outputs,
};
