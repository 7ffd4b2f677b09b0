//! Calibration study of sinsbench (issue 3), as a library: the paper's Table 1 simulation over
//! a Monte Carlo of seeds with the 42-state filter (consistency, NEES, observability, the count
//! against the paper's residuals), the 30-state filter on the same data (the temperature effect
//! left in its constants), and the four-temperature least-squares baseline against the proposed
//! 42-state method on the Table 3 truth. The simulator streams straight into the filter; no
//! files besides the experiment definitions and the paper's tables (`experiments/reference/`).
//!
//! Entry points: [`StudyConfig::paper`] → [`run_study`] → [`Study`] (serde-serialisable) and
//! [`render_markdown`]. Deterministic: every field of a [`Study`] except
//! [`Study::timing`] is bit-identical for any thread count (jobs are collected by index).
#![warn(missing_docs)]

pub mod baseline;
pub mod error;
mod format;
pub mod lsfit;
mod markdown;
mod markdown_ls;
pub mod montecarlo;
pub mod noise;
pub mod reference;
pub mod run;
pub mod stats;
pub mod study;
pub mod table1mc;
pub mod table3;
pub mod thirty;
pub mod units;

pub use baseline::{LsCoefficient, LsPoint, LsStudy};
pub use error::StudyError;
pub use lsfit::{LineFit, fit_line};
pub use markdown::{render_markdown, render_table1_markdown};
pub use montecarlo::{
    McRunOutcome, ObservabilityEntry, SeedOutcome, Table1Entry, Table1Study, mc_seeds,
};
pub use noise::filter_noise_from_experiment;
pub use reference::{
    ReferenceError, Table1, Table1Row, Table3, Table3Row, load_table1, load_table3, parse_table1,
    parse_table3,
};
pub use run::{CalibrationRun, calibrate_scenario, config_for_scenario, truncate_motion};
pub use study::{NoiseFigures, Study, StudyConfig, StudySettings, Timing, run_study};
pub use table1mc::{Table1MonteCarlo, noise_free_run};
pub use table3::{Table3Entry, Table3Study};
pub use thirty::{GyroLeakEntry, LeakEntry, ThirtyStateStudy};
