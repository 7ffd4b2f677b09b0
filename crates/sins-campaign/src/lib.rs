#![doc = include_str!("../README.md")]
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
