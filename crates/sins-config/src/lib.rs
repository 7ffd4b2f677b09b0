//! File formats of sinsbench, in human / paper units, and their conversion to the SI types of
//! `sins-imu` and `sins-sim`:
//!
//! - **IMU parameter files** (TOML or JSON): the 30- or 42-state coefficient set of Wang et al.
//!   2021 with keys named after the paper's symbols and units (`B_x_deg_per_h`, `dM_yx_arcsec`,
//!   `TK_z_ppm_per_degc`, ...), optionally with 1-sigma uncertainties. [`load_params`],
//!   [`parse_params_toml`], [`parse_params_json`], [`params_to_toml`], [`params_to_json`] (writing
//!   then reading is bit-exact in SI) and [`coefficient_table`] for reports.
//! - **Experiment files** (TOML): site, sampling, truth IMU and noise, thermal chamber, turntable
//!   motion program and one or more runs; [`load_experiment`] turns each run into a
//!   [`sins_sim::scenario::Scenario`].
//! - **Noise files** (TOML, `kind = "noise"`): an `[imu.noise]` table with its 1-sigma, as
//!   `sinsbench noise` identifies it; [`load_noise`] (also takes an experiment file),
//!   [`noise_to_toml`], [`write_noise`].
//! - **Extra effects** (`[[imu.effect]]` tables of an experiment, or a document of them alone): the
//!   catalogue of `sins_imu::EffectKind`s in paper-style units; [`parse_effects_toml`] and
//!   [`effects_to_toml`] (writing then reading is bit-exact in SI).
//! - **Harness inputs**: the report configuration ([`load_report_config`]), the release-gate
//!   thresholds ([`load_thresholds`], TOML), the paper's Table 5 ([`load_table5`], CSV) and a
//!   report's `summary.json` ([`read_summary`], [`summary_to_json`]), read into (or written from)
//!   the types of `sins-harness`; their errors are `sins_harness::HarnessError`s.
//! - **Markdown tables** for the reports of the crates above this one: [`markdown::Table`].
//!
//! Every error names the file, the key path (`motion.segment[3].duration_s`) and, for TOML, the
//! line. The schema is documented in `experiments/README.md`.

#![warn(missing_docs)]

mod coefficients;
mod csv;
mod ctx;
mod effects;
mod error;
mod exact;
mod experiment;
mod harness;
pub mod markdown;
mod motion;
pub mod names;
mod noise_table;
mod params;
mod params_write;
pub mod plausible;
mod thermal;
mod toml_util;
pub mod units;

pub use coefficients::{Coefficient, coefficient_table};
pub use effects::{effects_to_toml, parse_effects_toml};
pub use error::ConfigError;
pub use experiment::{EXPERIMENT_SCHEMA, Experiment, load_experiment};
pub use harness::{
    load_report_config, load_table5, load_thresholds, read_report_list, read_summary,
    summary_to_json,
};
pub use motion::motion_duration_s;
pub use names::{RUN_NAME_RULE, RunNameError, run_name};
pub use noise_table::{
    NOISE_KIND, NoiseTable, load_noise, noise_to_toml, noise_to_toml_checked, parse_noise_file,
    write_noise,
};
pub use params::{
    ParamFormat, ParamSet, load_params, model_name, parse_params_json, parse_params_toml,
};
pub use params_write::{params_to_json, params_to_toml, write_params};
pub use thermal::chamber_duration_s;
pub use units::PaperUnit;
