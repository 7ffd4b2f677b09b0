//! The simulator: validates a [`Scenario`] and streams IMU samples in bounded batches.
//!
//! Sample k (0-based) covers `(k h, (k+1) h]` with `t_s = (k+1)/rate_hz`. Its true increments
//! are exact integrals ([`IncrementIntegrator`]); the truth error model is applied with the true
//! accelerometer temperatures at the interval midpoint, then the sensor noise (gyro quantization
//! last); `temp_degc` holds the thermometer readings at `t_s`.

use crate::error::{SimError, finite_reason};
use crate::increments::IncrementIntegrator;
use crate::motion::MotionTimeline;
use crate::noise::{GaussianStream, SensorNoise, stream};
use crate::scenario::Scenario;
use crate::thermal::{AccelThermal, Thermometers};
use sins_imu::{ContextTracker, ForwardModel, ImuSample};
use sins_nav::{Geodetic, Quat, Vec3};

/// Truth state of the IMU at a sample time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceState {
    /// Attitude C_b^n.
    pub ned_from_body: Quat,
    /// Position (the fixed turntable site).
    pub position: Geodetic,
    /// Velocity relative to the Earth in NED (m/s); zero on a fixed turntable.
    pub vel_ned_mps: Vec3,
}

/// A batch of consecutive samples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimBatch {
    /// IMU samples (raw increments and thermometer readings).
    pub samples: Vec<ImuSample>,
    /// Motion segment index of each sample (the segment containing the interval midpoint).
    pub segment_index: Vec<u16>,
    /// Truth state at each sample time, when the scenario asks for it.
    pub reference: Option<Vec<ReferenceState>>,
}

impl SimBatch {
    /// Number of samples in the batch.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// True when the batch holds no sample.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    fn clear(&mut self) {
        self.samples.clear();
        self.segment_index.clear();
        if let Some(r) = &mut self.reference {
            r.clear();
        }
    }
}

/// A validated scenario ready to generate its samples.
pub struct Simulator {
    scenario: Scenario,
    timeline: MotionTimeline,
    integrator: IncrementIntegrator,
    forward: ForwardModel,
    n_samples: usize,
    labels: Vec<String>,
    label_of_segment: Vec<u16>,
    thermal0: AccelThermal,
    thermometers0: Thermometers,
    noise0: SensorNoise,
}

fn field(field: &'static str, r: Option<String>) -> Result<(), SimError> {
    r.map_or(Ok(()), |reason| Err(SimError::Field { field, reason }))
}

impl Simulator {
    /// Validate `scenario` and prepare a simulator that applies `forward` (normally built from
    /// `scenario.truth`, possibly with extra effects) to the true increments.
    pub fn new(scenario: &Scenario, forward: ForwardModel) -> Result<Self, SimError> {
        let s = scenario;
        let bad_rate = !(s.rate_hz.is_finite() && s.rate_hz > 0.0);
        field(
            "rate_hz",
            bad_rate.then(|| format!("must be finite and positive, got {}", s.rate_hz)),
        )?;
        let lat = s.site.lat_rad;
        let bad_lat = !(lat.is_finite() && lat.abs() <= std::f64::consts::FRAC_PI_2);
        field(
            "site.lat_rad",
            bad_lat.then(|| format!("must be in [-π/2, π/2], got {lat}")),
        )?;
        field("site.lon_rad", finite_reason(s.site.lon_rad))?;
        field("site.height_m", finite_reason(s.site.height_m))?;
        let bad_truth = !s.truth.is_finite();
        field(
            "truth",
            bad_truth.then(|| "has a non-finite coefficient".to_string()),
        )?;
        let bad_fwd = !forward.params().is_finite();
        field(
            "forward model",
            bad_fwd.then(|| "has a non-finite coefficient".to_string()),
        )?;
        let h = 1.0 / s.rate_hz;
        let timeline = MotionTimeline::new(&s.motion)?;
        let integrator = IncrementIntegrator::new(&timeline, &s.site, s.quadrature_nodes, h)?;
        let n = (timeline.total_duration_s() * s.rate_hz).round();
        let bad_n = !(1.0..9.0e15).contains(&n);
        let reason = || format!("gives {n} samples at {} Hz (need 1 to 9e15)", s.rate_hz);
        field("motion.segments (total duration)", bad_n.then(reason))?;
        let thermal0 = AccelThermal::new(&s.thermal, 0.5 * h)?;
        let thermometers0 = Thermometers::new(
            s.thermal.thermometer_noise_degc,
            GaussianStream::new(s.seed, stream::THERMOMETER),
        );
        let noise0 = SensorNoise::new(&s.noise, s.seed, h)?;
        let mut labels: Vec<String> = Vec::new();
        let mut label_of_segment = Vec::with_capacity(timeline.n_segments());
        for i in 0..timeline.n_segments() {
            let label = timeline.segment_label(i).unwrap_or_default();
            let pos = match labels.iter().position(|l| l == label) {
                Some(p) => p,
                None => {
                    labels.push(label.to_string());
                    labels.len() - 1
                }
            };
            // At most 65536 segments (validated), hence at most 65536 labels.
            label_of_segment.push(u16::try_from(pos).unwrap_or(u16::MAX));
        }
        Ok(Self {
            scenario: s.clone(),
            timeline,
            integrator,
            forward,
            n_samples: n as usize,
            labels,
            label_of_segment,
            thermal0,
            thermometers0,
            noise0,
        })
    }

    /// Simulator applying the scenario's own truth coefficients and extra effects.
    pub fn from_scenario(scenario: &Scenario) -> Result<Self, SimError> {
        for (i, e) in scenario.effects.iter().enumerate() {
            let reason = format!("effect {i} ({}) has an invalid value: {e:?}", e.name());
            field("effects", (!e.is_valid()).then_some(reason))?;
        }
        let forward = scenario
            .effects
            .iter()
            .fold(ForwardModel::new(scenario.truth), |f, e| {
                f.with_effect(e.build(&scenario.truth))
            });
        Self::new(scenario, forward)
    }

    /// Number of samples: `round(total duration · rate_hz)`.
    pub fn n_samples(&self) -> usize {
        self.n_samples
    }

    /// Nominal sample interval `1/rate_hz` (s).
    pub fn sample_interval_s(&self) -> f64 {
        1.0 / self.scenario.rate_hz
    }

    /// Unique segment labels in order of first appearance.
    pub fn segment_labels(&self) -> &[String] {
        &self.labels
    }

    /// For each motion segment, the index of its label in [`Self::segment_labels`] (maps
    /// [`SimBatch::segment_index`] to a label).
    pub fn segment_label_indices(&self) -> &[u16] {
        &self.label_of_segment
    }

    /// The validated motion timeline.
    pub fn timeline(&self) -> &MotionTimeline {
        &self.timeline
    }

    /// The scenario being simulated.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// Generate all samples from t = 0, handing them to `sink` in batches of `batch_len`
    /// (at least 1; the last batch may be shorter). Memory is bounded by `batch_len`. Each call
    /// restarts the thermal state, the noise streams and the extra effects
    /// ([`ForwardModel::reset_effects`]), so repeated runs are identical. Stops at the first error
    /// of `sink` and returns it.
    pub fn run<E>(
        &mut self,
        batch_len: usize,
        mut sink: impl FnMut(&SimBatch) -> Result<(), E>,
    ) -> Result<(), E> {
        self.run_batches(batch_len, |b| sink(b))
    }

    fn run_batches<E>(
        &mut self,
        batch_len: usize,
        mut sink: impl FnMut(&mut SimBatch) -> Result<(), E>,
    ) -> Result<(), E> {
        let n = self.n_samples;
        let batch_len = batch_len.clamp(1, n.max(1));
        let rate = self.scenario.rate_hz;
        let h = 1.0 / rate;
        let site = self.scenario.site;
        let mut thermal = self.thermal0.clone();
        let mut thermometers = self.thermometers0.clone();
        let mut noise = self.noise0.clone();
        let mut contexts = ContextTracker::new();
        self.forward.reset_effects();
        let mut batch = SimBatch {
            samples: Vec::with_capacity(batch_len),
            segment_index: Vec::with_capacity(batch_len),
            reference: self
                .scenario
                .with_reference
                .then(|| Vec::with_capacity(batch_len)),
        };
        let mut piece_cursor = 0usize;
        let mut seg_cursor = 0usize;
        let mut ref_cursor = 0usize;
        let last_seg = self.timeline.n_segments() - 1;
        for k in 0..n {
            let t0_s = k as f64 / rate;
            let t1_s = (k + 1) as f64 / rate;
            let tm_s = (2 * k + 1) as f64 / (2.0 * rate);
            let (dtheta, dv) = self
                .integrator
                .increments_from(t0_s, t1_s, &mut piece_cursor);
            let mid_degc = thermal.advance_to(tm_s);
            let mid_rate = thermal.rate_degc_per_s();
            let end_degc = thermal.advance_to(t1_s);
            let ctx = contexts.next(t1_s, h, dtheta, dv, mid_degc, mid_rate);
            let (mut raw_dtheta, mut raw_dv) = self.forward.apply(&dtheta, &dv, h, &mid_degc, &ctx);
            noise.apply(&mut raw_dtheta, &mut raw_dv);
            let temp_degc = thermometers.read(end_degc);
            while seg_cursor < last_seg
                && self
                    .timeline
                    .segment_end_s(seg_cursor)
                    .is_some_and(|e| e <= tm_s)
            {
                seg_cursor += 1;
            }
            batch.samples.push(ImuSample {
                t_s: t1_s,
                dtheta_rad: raw_dtheta,
                dv_mps: raw_dv,
                temp_degc,
            });
            batch.segment_index.push(seg_cursor as u16);
            if let Some(r) = &mut batch.reference {
                r.push(ReferenceState {
                    ned_from_body: self.timeline.ned_from_body_at(t1_s, &mut ref_cursor),
                    position: site,
                    vel_ned_mps: Vec3::zeros(),
                });
            }
            if batch.len() == batch_len {
                sink(&mut batch)?;
                batch.clear();
            }
        }
        if !batch.is_empty() {
            sink(&mut batch)?;
        }
        Ok(())
    }
}

/// Simulate a whole (small) scenario into one batch.
pub fn simulate_to_vec(scenario: &Scenario, forward: ForwardModel) -> Result<SimBatch, SimError> {
    let mut sim = Simulator::new(scenario, forward)?;
    let mut all = SimBatch::default();
    let n = sim.n_samples();
    sim.run_batches(n, |b| {
        all = std::mem::take(b);
        Ok::<(), SimError>(())
    })?;
    Ok(all)
}
