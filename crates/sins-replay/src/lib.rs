//! Replay of IMU samples: compensation with a parameter set (eqs 3-5), stationary
//! self-alignment or a known start, pure-inertial strapdown navigation, and the horizontal error
//! track against the fixed turntable site, with per-segment maxima. No file I/O: callers feed
//! samples in batches from any source.

mod metrics;
mod replay;

pub use metrics::{ErrorPoint, ReplaySummary, SegmentSummary};
pub use replay::{Replay, ReplayConfig, ReplayError, Start};
