//! Replay set-up shared by every command that navigates: parameter set + options → a ready
//! [`Replay`].

use crate::HarnessError;
use sins_imu::{Compensator, ImuErrorParams};
use sins_nav::alignment::AlignmentConfig;
use sins_nav::reconstruct::ReconstructConfig;
use sins_nav::{ConingOrder, Geodetic, NavState, StrapdownConfig, VerticalChannel};
use sins_replay::{Replay, ReplayConfig, Start};

/// Vertical channel of the replay (turntable runs hold the known height).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VerticalMode {
    /// Height fixed at the site height (default for turntable experiments).
    Hold,
    /// Critically damped loop to the site height with this time constant (s).
    Damped {
        /// Loop time constant (s).
        tau_s: f64,
    },
    /// Pure inertial (unstable over hours).
    Free,
}

/// How navigation starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StartMode {
    /// Stationary self-alignment over the first `duration_s` seconds (the paper: 1200 s).
    Align {
        /// Alignment time (s).
        duration_s: f64,
    },
    /// A known state at rest at the start of the data (e.g. a simulator's truth).
    Known(NavState),
}

/// Options of a replay.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReplayOptions {
    /// Coning / sculling algorithm (default: the look-ahead reconstruction).
    pub coning: ConingOrder,
    /// Vertical channel.
    pub vertical: VerticalMode,
    /// Start mode.
    pub start: StartMode,
    /// Worker threads of the reconstruction (results do not depend on it).
    pub threads: usize,
    /// Interval of the error output (s).
    pub output_interval_s: f64,
}

impl Default for ReplayOptions {
    /// Reconstruction, height hold, 20 min self-alignment, 2 threads, 1 Hz output.
    fn default() -> Self {
        Self {
            coning: ConingOrder::Reconstruct,
            vertical: VerticalMode::Hold,
            start: StartMode::Align { duration_s: 1200.0 },
            threads: 2,
            output_interval_s: 1.0,
        }
    }
}

/// A replay of samples taken every `sample_interval_s` at `site`, compensated with `params`
/// (named `set` in errors).
pub fn build_replay(
    set: &str,
    params: &ImuErrorParams,
    site: Geodetic,
    sample_interval_s: f64,
    options: &ReplayOptions,
) -> Result<Replay, HarnessError> {
    let compensator = Compensator::new(*params).ok_or_else(|| HarnessError::SingularParams {
        set: set.to_string(),
    })?;
    let vertical = match options.vertical {
        VerticalMode::Hold => VerticalChannel::Hold {
            height_m: site.height_m,
        },
        VerticalMode::Damped { tau_s } => VerticalChannel::Damped {
            height_m: site.height_m,
            tau_s,
        },
        VerticalMode::Free => VerticalChannel::Free,
    };
    let start = match options.start {
        StartMode::Align { duration_s } => Start::SelfAlign(AlignmentConfig {
            duration_s,
            ..AlignmentConfig::default()
        }),
        StartMode::Known(state) => Start::Known(state),
    };
    let config = ReplayConfig {
        nav: StrapdownConfig {
            sample_interval_s,
            coning: options.coning,
            vertical,
        },
        start,
        output_interval_s: options.output_interval_s,
    };
    let recon = ReconstructConfig {
        threads: options.threads.max(1),
        ..ReconstructConfig::default()
    };
    Ok(Replay::new(config, compensator, site, 0.0).with_reconstruction(recon))
}
