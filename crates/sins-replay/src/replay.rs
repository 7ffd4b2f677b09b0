//! The replay state machine: compensation → (alignment) → navigation → 1 Hz error points.
//!
//! With `ConingOrder::Reconstruct` the navigation consumes the high-order look-ahead
//! reconstruction of `sins_nav::reconstruct`: each interval is navigated once its stencil is
//! complete, so the navigation state and the error points lag the pushed samples by the
//! reconstruction's look-ahead and batch, and [`Replay::finish`] flushes the tail. A change of
//! the segment index between consecutive samples starts a new smooth piece (the turntable's rate
//! jumps at segment boundaries), so that no interpolation stencil straddles it.

use crate::metrics::{ErrorPoint, ReplaySummary};
use sins_imu::{Compensator, ImuSample};
use sins_nav::alignment::{AlignmentConfig, AlignmentError, SelfAlignment};
use sins_nav::reconstruct::{IncrementReconstructor, ReconstructConfig};
use sins_nav::{ConingOrder, Geodetic, Increment, NavState, Strapdown, StrapdownConfig};
use std::collections::VecDeque;

/// How navigation starts.
#[derive(Clone, Copy, Debug)]
pub enum Start {
    /// Stationary self-alignment over the first `duration_s` of the data (paper: 20 min).
    SelfAlign(AlignmentConfig),
    /// A known initial state (e.g. the simulator's truth), valid at the start of the data.
    Known(NavState),
}

/// Replay settings.
#[derive(Clone, Copy, Debug)]
pub struct ReplayConfig {
    /// Mechanization (sample interval, coning algorithm, vertical channel).
    pub nav: StrapdownConfig,
    /// How navigation starts.
    pub start: Start,
    /// Interval of the error output (s), e.g. 1 Hz.
    pub output_interval_s: f64,
}

/// Errors of a replay.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// The alignment stage failed.
    #[error(transparent)]
    Alignment(#[from] AlignmentError),
    /// The parameter set needs temperatures that the data lack.
    #[error(
        "sample at t = {t_s} s has no accelerometer temperatures, but the parameter set has temperature terms"
    )]
    MissingTemperature {
        /// Time of the offending sample (s).
        t_s: f64,
    },
    /// No navigation happened (data shorter than the alignment).
    #[error("no navigation output: the data end before alignment completes ({0})")]
    NoOutput(String),
    /// A parameter set cannot be inverted for compensation.
    #[error("parameter set '{set}' is singular (I + E not invertible)")]
    SingularParams {
        /// Parameter set key.
        set: String,
    },
}

// One phase per replay, switched once: the variant size difference costs nothing.
#[allow(clippy::large_enum_variant)]
enum Phase {
    Aligning(Box<SelfAlignment>),
    Navigating(Strapdown),
    Reconstructing(Box<Reconstructing>),
}

/// Navigation on reconstructed increments: the segment index of every pushed sample whose
/// interval has not been navigated yet.
struct Reconstructing {
    nav: Strapdown,
    recon: IncrementReconstructor,
    segments: VecDeque<u16>,
    /// Each queued sample's own interval (s), with stamped intervals only.
    intervals: VecDeque<f64>,
}

impl Phase {
    /// The navigation phase that `config` selects, starting from `state`.
    fn navigating(config: &ReplayConfig, recon: ReconstructConfig, state: NavState) -> Self {
        let nav = Strapdown::new(config.nav, state);
        match config.nav.coning {
            ConingOrder::Reconstruct => Phase::Reconstructing(Box::new(Reconstructing {
                nav,
                recon: IncrementReconstructor::new(recon),
                segments: VecDeque::new(),
                intervals: VecDeque::new(),
            })),
            _ => Phase::Navigating(nav),
        }
    }
}

/// Append the error point of `nav`'s state, attributed to `segment`.
fn record(points: &mut Vec<ErrorPoint>, nav: &Strapdown, site: &Geodetic, segment: u16) {
    let st = nav.state();
    let d = st.position.ned_offset_from_m(site);
    points.push(ErrorPoint {
        t_s: st.t_s,
        north_m: d.x,
        east_m: d.y,
        vel_n_mps: st.vel_ned_mps.x,
        vel_e_mps: st.vel_ned_mps.y,
        segment,
        ned_from_body: st.ned_from_body,
    });
}

/// Streaming replay: feed samples in time order with [`Replay::push`], then [`Replay::finish`].
pub struct Replay {
    config: ReplayConfig,
    compensator: Compensator,
    site: Geodetic,
    phase: Phase,
    points: Vec<ErrorPoint>,
    samples_per_output: usize,
    nav_samples: usize,
    nav_start_s: f64,
    recon: ReconstructConfig,
    /// Integrate over each sample's recorded interval (see [`Replay::with_stamped_intervals`]).
    stamped: bool,
    /// The previous sample's `t_s`, with stamped intervals.
    prev_t_s: Option<f64>,
    /// Scratch of [`Replay::push_batch`]: a chunk's intervals (s) and compensated increments.
    hs: Vec<f64>,
    incs: Vec<Increment>,
}

/// Samples that [`Replay::push_batch`] compensates before it navigates them.
const BATCH_CHUNK: usize = 1024;

impl Replay {
    /// Replay at the fixed `site` with samples starting at `t0_s` (the start of the first
    /// sample interval).
    pub fn new(config: ReplayConfig, compensator: Compensator, site: Geodetic, t0_s: f64) -> Self {
        let phase = match config.start {
            Start::SelfAlign(a) => {
                Phase::Aligning(Box::new(SelfAlignment::new(a, config.nav, site, t0_s)))
            }
            Start::Known(state) => Phase::navigating(&config, ReconstructConfig::default(), state),
        };
        let h = config.nav.sample_interval_s;
        Self {
            samples_per_output: ((config.output_interval_s / h).round() as usize).max(1),
            config,
            compensator,
            site,
            phase,
            points: Vec::new(),
            nav_samples: 0,
            nav_start_s: t0_s,
            recon: ReconstructConfig::default(),
            stamped: false,
            prev_t_s: None,
            hs: Vec::new(),
            incs: Vec::new(),
        }
    }

    /// With `stamped`, each sample is integrated over its own interval, the step of `t_s`
    /// from the previous sample (the first sample, and the alignment, use the nominal
    /// interval): for recorded time stamps that are trusted. The reconstruction then
    /// interpolates the increments as if equally spaced and advances over the sum of the
    /// stamped intervals. Without it (the default) every sample covers 1/rate.
    pub fn with_stamped_intervals(mut self, stamped: bool) -> Self {
        self.stamped = stamped;
        self
    }

    /// Settings of the reconstruction used with `ConingOrder::Reconstruct` (default
    /// [`ReconstructConfig::default`]); call before the first [`Replay::push`].
    pub fn with_reconstruction(mut self, recon: ReconstructConfig) -> Self {
        self.recon = recon;
        if let Phase::Reconstructing(r) = &mut self.phase {
            r.recon = IncrementReconstructor::new(recon);
        }
        self
    }

    /// Feed one raw sample with its segment index.
    #[inline]
    pub fn push(&mut self, s: &ImuSample, segment: u16) -> Result<(), ReplayError> {
        let h = self.interval_of(s);
        let inc = self.compensate(s, h)?;
        self.push_increment(&inc, h, segment)
    }

    /// The interval `s` covers (s): its stamped step with stamped intervals, else 1/rate.
    #[inline]
    fn interval_of(&mut self, s: &ImuSample) -> f64 {
        let mut h = self.config.nav.sample_interval_s;
        if self.stamped {
            if let Some(prev) = self.prev_t_s {
                h = s.t_s - prev;
            }
            self.prev_t_s = Some(s.t_s);
        }
        h
    }

    /// An error if the parameter set needs temperatures that `s` lacks.
    #[inline]
    fn check_temperatures(&self, s: &ImuSample) -> Result<(), ReplayError> {
        let temp = &s.temp_degc;
        if self.compensator.uses_temperature()
            && !(temp[0].is_finite() && temp[1].is_finite() && temp[2].is_finite())
        {
            return Err(ReplayError::MissingTemperature { t_s: s.t_s });
        }
        Ok(())
    }

    /// The compensated increments of `s` over `h` seconds.
    #[inline]
    fn compensate(&self, s: &ImuSample, h: f64) -> Result<Increment, ReplayError> {
        self.check_temperatures(s)?;
        let temp = &s.temp_degc;
        Ok(Increment {
            dtheta_rad: self.compensator.dtheta_rad(&s.dtheta_rad, h),
            dv_mps: self.compensator.dv_mps(&s.dv_mps, h, temp),
        })
    }

    /// Feed one compensated increment over `h` seconds with its segment index.
    #[inline]
    fn push_increment(&mut self, inc: &Increment, h: f64, segment: u16) -> Result<(), ReplayError> {
        match &mut self.phase {
            Phase::Aligning(a) => {
                if a.push(inc)? {
                    let result = a.finish()?;
                    self.nav_start_s = result.state.t_s;
                    self.phase = Phase::navigating(&self.config, self.recon, result.state);
                }
            }
            Phase::Navigating(nav) => {
                if self.stamped {
                    nav.push_timed(inc, h);
                } else {
                    nav.push(inc);
                }
                self.nav_samples += 1;
                if self.nav_samples.is_multiple_of(self.samples_per_output)
                    && nav.pending_samples() == 0
                {
                    record(&mut self.points, nav, &self.site, segment);
                }
            }
            Phase::Reconstructing(r) => {
                if r.segments.back().is_some_and(|&g| g != segment) {
                    r.recon.start_new_piece();
                }
                r.recon.push(inc);
                r.segments.push_back(segment);
                if self.stamped {
                    r.intervals.push_back(h);
                }
                self.navigate_reconstructed();
            }
        }
        Ok(())
    }

    /// Feed a batch of samples with per-sample segment indices (or all segment 0).
    pub fn push_batch(
        &mut self,
        samples: &[ImuSample],
        segments: Option<&[u16]>,
    ) -> Result<(), ReplayError> {
        let samples = &samples[..segments.map_or(samples.len(), |g| g.len().min(samples.len()))];
        for chunk in (0..samples.len()).step_by(BATCH_CHUNK) {
            let part = &samples[chunk..(chunk + BATCH_CHUNK).min(samples.len())];
            let mut hs = std::mem::take(&mut self.hs);
            let mut incs = std::mem::take(&mut self.incs);
            hs.clear();
            incs.clear();
            // Compensate up to the first sample without temperatures, which stops the batch
            // after the samples before it, as pushing one at a time would.
            let mut failed = None;
            for s in part {
                let h = self.interval_of(s);
                if let Err(e) = self.check_temperatures(s) {
                    failed = Some(e);
                    break;
                }
                hs.push(h);
            }
            self.compensator.compensate_into(part, &hs, &mut incs);
            let mut result = Ok(());
            for (k, (inc, &h)) in incs.iter().zip(&hs).enumerate() {
                let g = segments.map_or(0, |g| g[chunk + k]);
                result = self.push_increment(inc, h, g);
                if result.is_err() {
                    break;
                }
            }
            self.hs = hs;
            self.incs = incs;
            result?;
            if let Some(e) = failed {
                return Err(e);
            }
        }
        Ok(())
    }

    /// Navigate every interval the reconstructor has completed.
    fn navigate_reconstructed(&mut self) {
        let Phase::Reconstructing(r) = &mut self.phase else {
            return;
        };
        let h = self.config.nav.sample_interval_s;
        while let Some(x) = r.recon.pop() {
            let interval_s = if r.intervals.is_empty() {
                h * x.intervals as f64
            } else {
                r.intervals
                    .drain(..x.intervals.min(r.intervals.len()))
                    .sum()
            };
            r.nav
                .advance_interval(&x.phi_rad, &x.dv_body_mps, interval_s);
            #[allow(
                clippy::expect_used,
                reason = "a segment index is queued with every sample"
            )]
            let segment = r
                .segments
                .drain(..x.intervals)
                .next_back()
                .expect("a segment per sample");
            // An output point whenever the update reaches or crosses an output time.
            let before = self.nav_samples / self.samples_per_output;
            self.nav_samples += x.intervals;
            if self.nav_samples / self.samples_per_output > before {
                record(&mut self.points, &r.nav, &self.site, segment);
            }
        }
    }

    /// Error points so far.
    pub fn points(&self) -> &[ErrorPoint] {
        &self.points
    }

    /// Final navigation state, if navigating.
    pub fn nav_state(&self) -> Option<&NavState> {
        match &self.phase {
            Phase::Navigating(n) => Some(n.state()),
            Phase::Reconstructing(r) => Some(r.nav.state()),
            Phase::Aligning(_) => None,
        }
    }

    /// Finish: the error track and its summary.
    pub fn finish(mut self) -> Result<(Vec<ErrorPoint>, ReplaySummary), ReplayError> {
        if let Phase::Reconstructing(r) = &mut self.phase {
            r.recon.finish();
            self.navigate_reconstructed();
        }
        match self.phase {
            Phase::Aligning(a) => {
                a.finish()?;
                Err(ReplayError::NoOutput("alignment incomplete".into()))
            }
            Phase::Navigating(_) | Phase::Reconstructing(_) => {
                let end_s = self.nav_state().map_or(self.nav_start_s, |st| st.t_s);
                let summary = ReplaySummary::from_points(&self.points, end_s - self.nav_start_s);
                Ok((self.points, summary))
            }
        }
    }
}
