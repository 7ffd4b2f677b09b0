#![doc = include_str!("../README.md")]
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
