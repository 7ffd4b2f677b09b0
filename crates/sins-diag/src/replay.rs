//! The real error track of a run: replay its samples with the calibrated parameter set exactly
//! as `sinsbench navigate` does (self-alignment, reconstruction, vertical channel held; the
//! replay is built by `sins_replay::setup::build_replay` from [`ReplaySetup::replay_options`]),
//! and collect the per-second temperature means in the same pass.

use crate::error::DiagError;
use crate::source::SampleSource;
use crate::temperature::TemperatureSeries;
use sins_imu::effects::{ContextTracker, EffectContext, ExtraEffect};
use sins_imu::{Compensator, ImuErrorParams, ImuSample};
use sins_nav::alignment::AlignmentConfig;
use sins_nav::reconstruct::ReconstructConfig;
use sins_nav::{ConingOrder, Geodetic, StrapdownConfig, VerticalChannel};
use sins_replay::setup::{ReplayOptions, StartMode, VerticalMode, build_replay};
use sins_replay::{ErrorPoint, ReplaySummary};

/// The part of a replay the diagnosis lets a caller choose (must match the replay that produced
/// a given track); [`ReplaySetup::replay_options`] turns it into `sins_replay`'s options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReplaySetup {
    /// Self-alignment settings (default: 20 min, as `navigate --start align`).
    pub alignment: AlignmentConfig,
    /// Increment algorithm (default: reconstruction).
    pub coning: ConingOrder,
    /// Reconstruction settings (threads do not change results).
    pub reconstruct: ReconstructConfig,
    /// Half-window of the temperature-rate fit (s).
    pub temperature_rate_half_window_s: usize,
}

impl Default for ReplaySetup {
    fn default() -> Self {
        Self {
            alignment: AlignmentConfig::default(),
            coning: ConingOrder::Reconstruct,
            reconstruct: ReconstructConfig::default(),
            temperature_rate_half_window_s: 60,
        }
    }
}

impl ReplaySetup {
    /// The replay options this set-up stands for: `navigate --start align` with its alignment,
    /// increment algorithm and reconstruction, the height held, 1 Hz output and the nominal
    /// sample interval (the twin is built on it, so the real track is too). The diagnosis
    /// replays nothing else: its sensitivities replicate exactly this alignment and channel.
    pub fn replay_options(&self) -> ReplayOptions {
        ReplayOptions {
            coning: self.coning,
            vertical: VerticalMode::Hold,
            start: StartMode::Align(self.alignment),
            reconstruct: self.reconstruct,
            output_interval_s: 1.0,
            stamped_intervals: false,
            start_s: None,
        }
    }

    /// The mechanization settings for data sampled every `h_s` at `site` (height held).
    pub fn strapdown(&self, h_s: f64, site: &Geodetic) -> StrapdownConfig {
        StrapdownConfig {
            sample_interval_s: h_s,
            coning: self.coning,
            vertical: VerticalChannel::Hold {
                height_m: site.height_m,
            },
        }
    }
}

/// The real error track of one run and what the diagnosis needs besides.
#[derive(Clone, Debug)]
pub struct RealTrack {
    /// 1 Hz error points (north/east position and velocity errors, attitude estimate).
    pub points: Vec<ErrorPoint>,
    /// Per-second temperature means and rates.
    pub temperatures: TemperatureSeries,
    /// Summary of the replay (maximum / RMS / final horizontal error).
    pub summary: Option<ReplaySummary>,
}

/// Replay `source` at `site` with `params` as the real pipeline does; one pass.
pub fn replay_run(
    run: &str,
    source: &mut dyn SampleSource,
    params: &ImuErrorParams,
    site: &Geodetic,
    setup: &ReplaySetup,
) -> Result<RealTrack, DiagError> {
    replay_impl(run, source, params, site, setup, None)
}

/// Replay `source` as [`replay_run`] does, with the perturbation of `effect` removed from every
/// raw sample first: the real run as the model extended by `effect` would compensate it. The
/// effect's context (its "true" increments) is the compensated sample, its temperature rates
/// come from `temperatures` (the series of the plain replay).
pub fn replay_corrected(
    run: &str,
    source: &mut dyn SampleSource,
    params: &ImuErrorParams,
    site: &Geodetic,
    setup: &ReplaySetup,
    effect: &mut dyn ExtraEffect,
    temperatures: &TemperatureSeries,
) -> Result<RealTrack, DiagError> {
    effect.reset();
    replay_impl(
        run,
        source,
        params,
        site,
        setup,
        Some((effect, temperatures)),
    )
}

/// Samples corrected at a time before the replay takes them (a few hundred kB).
const CORRECTED_CHUNK: usize = 4096;

fn replay_impl(
    run: &str,
    source: &mut dyn SampleSource,
    params: &ImuErrorParams,
    site: &Geodetic,
    setup: &ReplaySetup,
    mut correction: Option<(&mut dyn ExtraEffect, &TemperatureSeries)>,
) -> Result<RealTrack, DiagError> {
    let h = source.sample_interval_s();
    let t0 = source.start_time_s();
    let mut replay = build_replay(run, params, *site, h, t0, &setup.replay_options())
        .map_err(|e| DiagError::input(run, e.to_string()))?;
    let comp = Compensator::new(*params)
        .ok_or_else(|| DiagError::input(run, "parameter set is singular"))?;
    let mut tracker = ContextTracker::new();
    let mut temps = TemperatureSeries::new(t0);
    let mut corrected = Vec::new();
    source.visit(&mut |samples, segments| {
        let samples = &samples[..samples.len().min(segments.len())];
        for s in samples {
            temps.push(s, h);
        }
        match correction.as_mut() {
            Some((effect, series)) => {
                for (part, seg) in samples
                    .chunks(CORRECTED_CHUNK)
                    .zip(segments.chunks(CORRECTED_CHUNK))
                {
                    corrected.clear();
                    corrected.extend(part.iter().map(|s| {
                        let ctx = sample_context(&mut tracker, &comp, s, h, series);
                        let (p_theta, p_v) = effect.perturbation(&ctx);
                        let mut c = *s;
                        c.dtheta_rad -= p_theta;
                        c.dv_mps -= p_v;
                        c
                    }));
                    replay.push_batch(&corrected, Some(seg))?;
                }
            }
            None => replay.push_batch(samples, Some(segments))?,
        }
        Ok(())
    })?;
    temps.finish(setup.temperature_rate_half_window_s);
    let (points, summary) = replay.finish()?;
    Ok(RealTrack {
        points,
        temperatures: temps,
        summary: Some(summary),
    })
}

/// The effect context of raw sample `s` (interval `h`): its compensated increments as the true
/// motion, its thermometer readings and the smoothed temperature rate of `temps` at the middle
/// of the sample.
pub(crate) fn sample_context(
    tracker: &mut ContextTracker,
    comp: &Compensator,
    s: &ImuSample,
    h: f64,
    temps: &TemperatureSeries,
) -> EffectContext {
    tracker.next(
        s.t_s,
        h,
        comp.dtheta_rad(&s.dtheta_rad, h),
        comp.dv_mps(&s.dv_mps, h, &s.temp_degc),
        s.temp_degc,
        temps.rate_at(s.t_s - 0.5 * h),
    )
}

/// The temperature series of a run alone (a cheap pass), for tracks replayed elsewhere.
pub fn temperature_series(
    source: &mut dyn SampleSource,
    half_window_s: usize,
) -> Result<TemperatureSeries, DiagError> {
    let h = source.sample_interval_s();
    let mut temps = TemperatureSeries::new(source.start_time_s());
    source.visit(&mut |samples, _| {
        samples.iter().for_each(|s| temps.push(s, h));
        Ok(())
    })?;
    temps.finish(half_window_s);
    Ok(temps)
}
