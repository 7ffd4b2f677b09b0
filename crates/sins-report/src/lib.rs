#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

mod dataset;
mod error;
pub mod frames;
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
