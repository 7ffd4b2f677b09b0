//! Where the samples of a run come from. A dataset of 15 h at 200 Hz holds 10.8 M samples, so
//! the diagnosis never keeps one in memory: it reads a [`SampleSource`] from the start once per
//! pass, in bounded batches. [`MemorySource`] (small data, tests) and [`SimSource`] (regenerates
//! a simulated run on every pass, deterministically) are provided; the CLI wraps its dataset
//! reader.

use crate::error::DiagError;
use sins_imu::ImuSample;
use sins_sim::Simulator;

/// The consumer of one pass: a batch of consecutive samples and the segment index of each.
pub type BatchSink<'a> = dyn FnMut(&[ImuSample], &[u16]) -> Result<(), DiagError> + 'a;

/// A re-readable, time-ordered stream of raw IMU samples with segment indices (into the run's
/// label list). Sample `k` covers `(t0 + k h, t0 + (k+1) h]` with constant `h`.
pub trait SampleSource: Send {
    /// Sample interval `h` (s).
    fn sample_interval_s(&self) -> f64;
    /// Start `t0` of the first sample interval (s); the first sample has `t_s = t0 + h`.
    fn start_time_s(&self) -> f64 {
        0.0
    }
    /// Feed every sample from the first, in batches, to `sink`; each call starts again at the
    /// beginning. Stops at the first error of the sink or of the source (mapped to
    /// [`DiagError::Source`]) and returns it.
    fn visit(&mut self, sink: &mut BatchSink<'_>) -> Result<(), DiagError>;
    /// An independent source of the same samples, so that a second pass can read the run
    /// while another one does (`None`, the default: the source is read by one pass at a time).
    fn try_clone(&self) -> Option<Box<dyn SampleSource>> {
        None
    }
}

/// Samples held in memory (for short data and tests).
#[derive(Clone, Debug)]
pub struct MemorySource {
    /// The samples in time order.
    pub samples: Vec<ImuSample>,
    /// Segment index of each sample.
    pub segments: Vec<u16>,
    /// Sample interval (s).
    pub sample_interval_s: f64,
}

impl SampleSource for MemorySource {
    fn sample_interval_s(&self) -> f64 {
        self.sample_interval_s
    }
    fn start_time_s(&self) -> f64 {
        self.samples
            .first()
            .map_or(0.0, |s| s.t_s - self.sample_interval_s)
    }
    fn visit(&mut self, sink: &mut BatchSink<'_>) -> Result<(), DiagError> {
        for (s, g) in self
            .samples
            .chunks(65_536)
            .zip(self.segments.chunks(65_536))
        {
            sink(s, g)?;
        }
        Ok(())
    }

    fn try_clone(&self) -> Option<Box<dyn SampleSource>> {
        Some(Box::new(self.clone()))
    }
}

/// A simulated run regenerated on every pass (bit-identical each time: the simulator restarts
/// its noise streams from the seed). Segment indices are label indices
/// ([`Simulator::segment_labels`]).
pub struct SimSource {
    sim: Simulator,
    label_of: Vec<u16>,
    batch_len: usize,
}

impl SimSource {
    /// Wrap a simulator. A pass regenerates the data, so an extra effect that keeps state of its
    /// own across [`Simulator::run`] calls (e.g. a random walk with its own generator) would
    /// differ between passes: materialise such runs (e.g. [`MemorySource`]) instead.
    pub fn new(sim: Simulator) -> Self {
        Self {
            label_of: sim.segment_label_indices().to_vec(),
            sim,
            batch_len: 65_536,
        }
    }

    /// The segment labels of the run.
    pub fn segment_labels(&self) -> Vec<String> {
        self.sim.segment_labels().to_vec()
    }

    /// The simulator.
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }
}

impl SampleSource for SimSource {
    fn sample_interval_s(&self) -> f64 {
        self.sim.sample_interval_s()
    }
    fn visit(&mut self, sink: &mut BatchSink<'_>) -> Result<(), DiagError> {
        let label_of = &self.label_of;
        let mut seg = Vec::new();
        self.sim.run(self.batch_len, |b| {
            seg.clear();
            seg.extend(
                b.segment_index
                    .iter()
                    .map(|&s| label_of.get(s as usize).copied().unwrap_or(s)),
            );
            sink(&b.samples, &seg)
        })
    }
}
