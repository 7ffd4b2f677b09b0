#![doc = include_str!("../README.md")]
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
