#![doc = include_str!("../README.md")]

mod metrics;
mod replay;
pub mod setup;

pub use metrics::{ErrorPoint, ReplaySummary, SegmentSummary};
pub use replay::{Replay, ReplayConfig, ReplayError, Start};
