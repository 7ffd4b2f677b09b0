//! Replay set-up shared by every command that navigates: parameter set + options → a ready
//! [`Replay`]. The one home of "how a run is replayed": `navigate`, `report`, the uncertainty
//! study and the diagnosis's real tracks all build their replays here.

use crate::replay::{Replay, ReplayConfig, ReplayError, Start};
use sins_imu::{Compensator, ImuErrorParams};
use sins_nav::alignment::AlignmentConfig;
use sins_nav::reconstruct::ReconstructConfig;
use sins_nav::{ConingOrder, Geodetic, NavState, StrapdownConfig, VerticalChannel};

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
    /// Stationary self-alignment (the paper: 1200 s, coarse then fine).
    Align(AlignmentConfig),
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
    /// Settings of the reconstruction used with `ConingOrder::Reconstruct` (its worker
    /// threads do not change the results).
    pub reconstruct: ReconstructConfig,
    /// Interval of the error output (s).
    pub output_interval_s: f64,
    /// Integrate each sample over its own recorded interval (the step of `t_s` from the
    /// previous sample) instead of the nominal 1/rate: for datasets whose
    /// `sinsbench.time_base` is `recorded`. The alignment keeps the nominal interval.
    pub stamped_intervals: bool,
    /// Replay only the samples whose interval starts at or after this time (s, the dataset's
    /// own time); `None` replays from the first sample. The alignment then starts there.
    pub start_s: Option<f64>,
}

impl Default for ReplayOptions {
    /// Reconstruction, height hold, 20 min self-alignment, 2 threads, 1 Hz output.
    fn default() -> Self {
        Self {
            coning: ConingOrder::Reconstruct,
            vertical: VerticalMode::Hold,
            start: StartMode::Align(AlignmentConfig::default()),
            reconstruct: ReconstructConfig::default(),
            output_interval_s: 1.0,
            stamped_intervals: false,
            start_s: None,
        }
    }
}

/// A replay of samples taken every `sample_interval_s` from `start_time_s` (the start of the
/// first sample interval) at `site`, compensated with `params` (named `set` in errors). The one
/// place where a replay is put together: `navigate`, `report` and the diagnosis's real tracks
/// all come from here.
pub fn build_replay(
    set: &str,
    params: &ImuErrorParams,
    site: Geodetic,
    sample_interval_s: f64,
    start_time_s: f64,
    options: &ReplayOptions,
) -> Result<Replay, ReplayError> {
    let compensator = Compensator::new(*params).ok_or_else(|| ReplayError::SingularParams {
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
        StartMode::Align(alignment) => Start::SelfAlign(alignment),
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
    Ok(Replay::new(config, compensator, site, start_time_s)
        .with_reconstruction(options.reconstruct)
        .with_stamped_intervals(options.stamped_intervals))
}
