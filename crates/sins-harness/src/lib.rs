//! The navigation harness of sinsbench, free of file formats and viewers:
//!
//! - [`replay_setup`]: one place that turns a parameter set and replay options into a
//!   [`sins_replay::Replay`] (the CLI's `navigate`, `report` and `diagnose` share it);
//! - [`pipeline`]: simulate-and-calibrate and simulate-and-replay in memory, and
//!   [`pipeline::MultiReplay`], which replays one stream of samples under several parameter sets
//!   at once (datasets read elsewhere feed it the same way);
//! - [`segments`]: per-segment maxima over contiguous stretches of a label;
//! - [`summary`]: the machine-readable results (`summary.json`) in the layout of the paper's
//!   Table 5;
//! - [`reference`](mod@reference): the paper's Table 5 rows;
//! - [`config`]: the report configuration;
//! - [`gate`]: thresholds, their evaluation and JUnit XML for CI systems; [`baseline`]: the
//!   gate of a candidate release against a baseline over noise seeds, and [`gate_power`]: how
//!   well that gate works on a release's own run-to-run spread;
//! - [`parallel`]: the deterministic work pool (results in job order whatever the thread count).
//!
//! Nothing here reads or writes files or parses TOML / JSON: `sins-config` loads the report
//! configuration, the thresholds and Table 5 into these types and writes and reads
//! `summary.json`.
//!
//! Units: SI inside (m, s, rad); nautical miles (1852 m) and hours only in summaries.

#![warn(missing_docs)]

pub mod baseline;
pub mod config;
mod error;
pub mod gate;
pub mod gate_power;
pub mod parallel;
pub mod pipeline;
pub mod reference;
pub mod replay_setup;
pub mod segments;
pub mod shift;
pub mod summary;

pub use error::HarnessError;
pub use sins_replay::ErrorPoint;
