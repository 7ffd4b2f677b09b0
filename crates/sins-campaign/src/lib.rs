//! Campaigns: sets of independent runs (the blind suite, the calibration Monte Carlo, the
//! replica's uncertainty study, a list of reports) split into shards by a fixed rule, so that
//! one process, a Slurm array job or a Kubernetes indexed job all give the same bytes.
//!
//! - [`spec`]: the campaign file (`experiments/campaigns/*.toml`): kind, size, seed, jobs per
//!   shard;
//! - [`manifest`]: the plan's manifest (configuration and build hashes, shard count), which
//!   every shard and the reduce check;
//! - [`work`]: what each kind provides (jobs, one job, the reduce); the kinds in `kinds`;
//! - [`run`]: plan, run a shard, list the missing ones, reduce, run all locally;
//! - [`shard`]: a shard's result file, checked against the manifest before use; a damaged one
//!   counts as missing and is kept aside when its shard runs again.
//!
//! Without the default `work` feature only the files are there (campaign file, manifest, shard
//! results and their checks), without the report writers (polars, rerun): what a reader of
//! shard results, such as the fuzz target, needs.
//!
//! A shard `s` holds jobs `s·n .. (s+1)·n` (n = `jobs_per_shard`), whatever the number of
//! workers. Its result is one JSON file written aside and renamed into place; the reduce reads
//! only those files, in shard order, so its `summary.json` and `report.md` are byte-identical
//! however the shards were run.

#![warn(missing_docs)]

mod error;
mod kinds;
pub mod manifest;
#[cfg(feature = "work")]
pub mod run;
pub mod shard;
pub mod spec;
#[cfg(feature = "work")]
pub mod work;

pub use error::CampaignError;
pub use kinds::check_shape;
pub use manifest::{BinaryId, Manifest, array_syntax};
#[cfg(feature = "work")]
pub use run::{Context, Opened, ShardRun, Status, failed_path, open, plan, status};
pub use shard::{SetAside, ShardResult, ShardState, parse_shard, shard_path};
pub use spec::{Campaign, Kind, load_campaign, parse_campaign};
