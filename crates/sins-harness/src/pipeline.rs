//! In-memory pipelines: replay one stream of samples under several parameter sets at once
//! ([`MultiReplay`]), simulate-and-replay ([`simulate_and_replay`]) and simulate-and-calibrate
//! ([`simulate_and_calibrate`]). Nothing here touches files: datasets read by `sins-data` feed
//! [`MultiReplay`] batch by batch exactly as the simulator does.

use crate::HarnessError;
use crate::feed::{Consumer, feed};
use crate::segments::{SegmentStretch, stretches};
use sins_imu::{ImuErrorParams, ImuSample, ParamModel};
use sins_kf::{
    CalibrationConfig, CalibrationError, CalibrationFilter, CalibrationResult, FilterNoise,
};
use sins_nav::{Geodetic, Quat};
use sins_replay::setup::{ReplayOptions, build_replay};
use sins_replay::{ErrorPoint, Replay, ReplayError, ReplaySummary};
use sins_sim::{NoiseModel, Scenario, SimBatch, Simulator};

/// Samples per simulator batch (bounded memory: ~2 MB of samples).
const SIM_BATCH: usize = 16_384;
/// Samples of a batch that every replay of [`MultiReplay`] takes before the next slice (320 kB).
const REPLAY_SLICE: usize = 4096;

/// A named parameter set to replay with.
#[derive(Clone, Debug)]
pub struct NamedParams {
    /// Short key used in summaries and thresholds (e.g. "42-state").
    pub key: String,
    /// The coefficients.
    pub params: ImuErrorParams,
}

/// The navigation error track of one parameter set on one run.
#[derive(Clone, Debug)]
pub struct Track {
    /// Parameter set key.
    pub set: String,
    /// Error points at the output interval after alignment.
    pub points: Vec<ErrorPoint>,
    /// Whole-run summary.
    pub summary: ReplaySummary,
    /// Per-stretch maxima.
    pub stretches: Vec<SegmentStretch>,
}

/// Accelerometer temperatures averaged over one output interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TemperaturePoint {
    /// End of the interval (s).
    pub t_s: f64,
    /// Mean thermometer reading of each accelerometer (degC); NaN without temperatures.
    pub temp_degc: [f64; 3],
}

/// Everything one run yields.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// Run or dataset name.
    pub run: String,
    /// Segment labels (indexed by `ErrorPoint::segment`).
    pub labels: Vec<String>,
    /// One track per parameter set, in the order given.
    pub tracks: Vec<Track>,
    /// Thermometer readings at the output interval.
    pub temperatures: Vec<TemperaturePoint>,
    /// True attitude `ned_from_body` at the output times (from the simulator or the reference
    /// columns), when known.
    pub truth_attitude: Option<Vec<(f64, Quat)>>,
    /// Duration of the data (s).
    pub duration_s: f64,
}

/// Replays one sample stream under several parameter sets at once.
pub struct MultiReplay {
    run: String,
    labels: Vec<String>,
    replays: Vec<(String, Replay)>,
    samples_per_output: usize,
    temp_sum: [f64; 3],
    temp_count: usize,
    temperatures: Vec<TemperaturePoint>,
    last_t_s: f64,
}

impl MultiReplay {
    /// Replays of run `run` (for errors) under each of `sets`, for samples every
    /// `sample_interval_s` from `start_time_s` (the start of the first sample's interval) at
    /// `site`; `labels` name the segment indices of the samples.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        run: &str,
        sets: &[NamedParams],
        site: Geodetic,
        sample_interval_s: f64,
        start_time_s: f64,
        labels: Vec<String>,
        options: &ReplayOptions,
    ) -> Result<Self, HarnessError> {
        let replays = sets
            .iter()
            .map(|s| {
                build_replay(
                    &s.key,
                    &s.params,
                    site,
                    sample_interval_s,
                    start_time_s,
                    options,
                )
                .map(|r| (s.key.clone(), r))
                .map_err(|source| match source {
                    ReplayError::SingularParams { set } => HarnessError::SingularParams { set },
                    source => HarnessError::Replay {
                        run: run.to_string(),
                        set: s.key.clone(),
                        source,
                    },
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            run: run.to_string(),
            labels,
            replays,
            samples_per_output: ((options.output_interval_s / sample_interval_s).round() as usize)
                .max(1),
            temp_sum: [0.0; 3],
            temp_count: 0,
            temperatures: Vec::new(),
            last_t_s: 0.0,
        })
    }

    /// Feed a batch of samples (time order) with their segment indices (or all segment 0).
    pub fn push_batch(
        &mut self,
        samples: &[ImuSample],
        segments: Option<&[u16]>,
    ) -> Result<(), HarnessError> {
        // A slice of the batch at a time to every replay, so that it stays in the core's
        // cache while each replay takes it (each replay still takes its samples in order).
        for start in (0..samples.len()).step_by(REPLAY_SLICE) {
            let end = (start + REPLAY_SLICE).min(samples.len());
            let segments = segments.map(|g| &g[start.min(g.len())..end.min(g.len())]);
            for (key, replay) in &mut self.replays {
                replay
                    .push_batch(&samples[start..end], segments)
                    .map_err(|source| HarnessError::Replay {
                        run: self.run.clone(),
                        set: key.clone(),
                        source,
                    })?;
            }
        }
        for s in samples {
            for (acc, t) in self.temp_sum.iter_mut().zip(s.temp_degc) {
                *acc += t;
            }
            self.temp_count += 1;
            self.last_t_s = s.t_s;
            if self.temp_count == self.samples_per_output {
                let n = self.temp_count as f64;
                self.temperatures.push(TemperaturePoint {
                    t_s: s.t_s,
                    temp_degc: self.temp_sum.map(|v| v / n),
                });
                self.temp_sum = [0.0; 3];
                self.temp_count = 0;
            }
        }
        Ok(())
    }

    /// Finish every replay.
    pub fn finish(self) -> Result<RunOutcome, HarnessError> {
        let mut tracks = Vec::with_capacity(self.replays.len());
        for (key, replay) in self.replays {
            let (points, summary) = replay.finish().map_err(|source| HarnessError::Replay {
                run: self.run.clone(),
                set: key.clone(),
                source,
            })?;
            let stretches = stretches(&points, &self.labels);
            tracks.push(Track {
                set: key,
                points,
                summary,
                stretches,
            });
        }
        Ok(RunOutcome {
            run: self.run,
            labels: self.labels,
            tracks,
            temperatures: self.temperatures,
            truth_attitude: None,
            duration_s: self.last_t_s,
        })
    }
}

/// Simulate `scenario` and replay it under every parameter set in one pass, without files.
/// With `threads` ≥ 2 the simulator runs on a thread of its own beside the replays (the same
/// batches in the same order: the outcome does not depend on `threads`). `progress` is called
/// with the number of samples done after each batch.
pub fn simulate_and_replay(
    scenario: &Scenario,
    sets: &[NamedParams],
    options: &ReplayOptions,
    threads: usize,
    progress: &mut dyn FnMut(u64),
) -> Result<RunOutcome, HarnessError> {
    let sim_err = |source| HarnessError::Simulation {
        run: scenario.name.clone(),
        source,
    };
    let mut sim = Simulator::from_scenario(scenario).map_err(sim_err)?;
    let label_of_segment = sim.segment_label_indices().to_vec();
    let mut multi = MultiReplay::new(
        &scenario.name,
        sets,
        scenario.site,
        sim.sample_interval_s(),
        0.0,
        sim.segment_labels().to_vec(),
        options,
    )?;
    let mut labels_buf: Vec<u16> = Vec::with_capacity(SIM_BATCH);
    let replays: Consumer<'_> = Box::new(|b: &SimBatch| {
        labels_buf.clear();
        labels_buf.extend(
            b.segment_index
                .iter()
                .map(|&s| label_of_segment.get(s as usize).copied().unwrap_or(0)),
        );
        multi.push_batch(&b.samples, Some(&labels_buf))
    });
    feed(&mut sim, SIM_BATCH, threads, &mut [replays], progress)?;
    let mut outcome = multi.finish()?;
    let mut cursor = 0usize;
    let truth = outcome
        .temperatures
        .iter()
        .map(|p| (p.t_s, sim.timeline().ned_from_body_at(p.t_s, &mut cursor)))
        .collect();
    outcome.truth_attitude = Some(truth);
    Ok(outcome)
}

/// The calibration filter's process noise for a sensor with the simulator's noise model (the
/// filter assumes the sensor it calibrates; quantization is left to the white noise floor).
pub fn filter_noise_for(noise: &NoiseModel) -> FilterNoise {
    FilterNoise::from_sensor(
        noise.gyro_arw_rad_per_sqrt_s,
        noise.gyro_bias_instability_radps,
        noise.gyro_bias_correlation_s,
        noise.accel_vrw_mps_per_sqrt_s,
        noise.accel_bias_instability_mps2,
        noise.accel_bias_correlation_s,
    )
}

/// The system-level calibration filter of `model` for samples of `sample_interval_s` (s) at
/// `site`, with process noise `noise`, starting from the ideal IMU, its temperature terms
/// referred to `reference_temperature_degc` (the set-up of `sinsbench calibrate`).
pub fn calibration_filter(
    model: ParamModel,
    sample_interval_s: f64,
    site: Geodetic,
    noise: FilterNoise,
    reference_temperature_degc: f64,
) -> Result<CalibrationFilter, CalibrationError> {
    let mut config = CalibrationConfig::new(model, sample_interval_s, site);
    config.noise = noise;
    let mut initial = ImuErrorParams::ideal(model);
    initial.reference_temperature_degc = reference_temperature_degc;
    CalibrationFilter::new(config, initial)
}

/// Simulate a calibration run once and calibrate it with one filter per entry of `models`
/// (30- and/or 42-state), without files. The filters' noise is the scenario's noise model; the
/// temperature terms are referred to `reference_temperature_degc`. With `threads` ≥ 2 the
/// simulator and each filter run on threads of their own (same batches, same order: the results
/// do not depend on `threads`). Results in the order of `models`.
pub fn simulate_and_calibrate(
    scenario: &Scenario,
    models: &[ParamModel],
    reference_temperature_degc: f64,
    threads: usize,
    progress: &mut dyn FnMut(u64),
) -> Result<Vec<CalibrationResult>, HarnessError> {
    let cal_err = |model: ParamModel| {
        let run = scenario.name.clone();
        move |source| HarnessError::Calibration {
            run: run.clone(),
            states: model.n_states(),
            source,
        }
    };
    let mut sim =
        Simulator::from_scenario(scenario).map_err(|source| HarnessError::Simulation {
            run: scenario.name.clone(),
            source,
        })?;
    let mut filters = Vec::with_capacity(models.len());
    for &model in models {
        let filter = calibration_filter(
            model,
            sim.sample_interval_s(),
            scenario.site,
            filter_noise_for(&scenario.noise),
            reference_temperature_degc,
        )
        .map_err(cal_err(model))?;
        filters.push((model, filter));
    }
    let mut consumers: Vec<Consumer<'_>> = filters
        .iter_mut()
        .map(|(model, filter)| {
            let err = cal_err(*model);
            Box::new(move |b: &SimBatch| filter.push_batch(&b.samples, None).map_err(&err))
                as Consumer<'_>
        })
        .collect();
    feed(&mut sim, SIM_BATCH, threads, &mut consumers, progress)?;
    drop(consumers);
    filters
        .into_iter()
        .map(|(model, f)| f.finish().map_err(cal_err(model)))
        .collect()
}

/// Number of samples a scenario produces (for progress bars).
pub fn scenario_samples(scenario: &Scenario) -> Result<u64, HarnessError> {
    Simulator::from_scenario(scenario)
        .map(|s| s.n_samples() as u64)
        .map_err(|source| HarnessError::Simulation {
            run: scenario.name.clone(),
            source,
        })
}
