#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

pub mod baseline;
pub mod config;
mod error;
pub mod feed;
pub mod gate;
pub mod gate_power;
pub mod parallel;
pub mod pipeline;
pub mod reference;
pub mod segments;
pub mod shift;
pub mod summary;

pub use error::HarnessError;
pub use sins_replay::ErrorPoint;
