//! High-order reconstruction of the attitude and velocity increments of each sample interval for
//! offline (look-ahead) strapdown replay.
//!
//! The cumulative angle `A(t) = Σ Δθ` and velocity `V(t) = Σ Δv` are known exactly at every
//! sample boundary. Around interval `k` they are interpolated by the polynomial through the
//! `2L + 2` boundaries of the `2L + 1` samples `k − L ..= k + L` (shifted to stay inside the
//! current smooth *piece* near its ends: one-sided stencils at breaks and at the ends of the data).
//! The interpolant reproduces every `Δθ_j`, `Δv_j` exactly; its derivative is the rate `ω(t)` and
//! specific force `f(t)` (degree `2L`). The exact kinematics
//! `Ẏ = Y [[ω×, f], [0, 0]]`, `Y = [[C_b(k)b(t), ΔV(t)], [0, 1]]` (the special Euclidean group
//! SE(3); right multiplication) are then integrated over the interval in `substeps` steps of the
//! sixth-order Magnus method of Blanes, Casas and Ros (2000) written with the exact Legendre
//! moments `B_p = h⁻ᵖ ∫ (t − h/2)ᵖ (ω, f) dt`, `p = 0, 1, 2`, of the interpolant. The moments are
//! fixed linear combinations (FIR taps, precomputed) of the samples in the stencil, and
//! `Σ B_0 = (Δθ_k, Δv_k)` exactly, so the first-order terms are exact. The output per interval is
//! the rotation vector `φ_k` (`C_b(k)b(k+1) = exp([φ_k×])`) and the specific-force velocity
//! increment `ΔV_k = ∫ C_b(k)b(t) f(t) dt` resolved in the body frame at the interval start, as
//! [`crate::Strapdown::advance_interval`] consumes them.
//!
//! Quiet stretches (every sample of a stencil equal to its predecessor to within changes whose
//! effect on the coning and sculling terms is negligible, below 1e-19 rad and 1e-15 m/s per
//! sample pair: stationary or constant-rate data) take the exact constant-rate path,
//! `φ = Δθ`, `ΔV = J(Δθ) Δv`, which is what the general path yields there to that level.
//!
//! With two or more substeps the rotation is the product of the substeps' Magnus steps on so(3)
//! and the velocity increment comes from one sixth-order step on se(3) over the whole interval,
//! which is far more accurate than the velocity needs (below 1e-3 ug under Table 4 pattern 3).
//!
//! Consecutive intervals can be grouped into one navigation update (`intervals_per_update`): their
//! exact body motions are multiplied, `C = Π exp(φ_k)`, `ΔV = Σ C_k ΔV_k`, so that the
//! navigation-frame part of the mechanization (Earth rate, transport rate, gravity) runs less
//! often while the body motion stays exact.
//!
//! Every update is a pure function of its stencils, so the results are bit-identical whatever
//! the threading. Four intervals at a time are evaluated side by side in the lanes of an AVX2
//! vector where the CPU has one, each lane doing the scalar code's operations in its order, so
//! the results are also the same bits whatever the CPU (module `lanes`; other CPUs, and other
//! architectures, evaluate every interval with the scalar code). With `threads > 1`, batches of `batch_len` samples are computed by `threads`
//! background workers while the caller keeps pushing (and navigating): the reconstruction
//! overlaps the rest of the replay. Results are returned in order.

mod batch;
mod kernel;
mod lanes;
mod taps;

use crate::Vec3;
use crate::mechanization::Increment;
use batch::{Job, Scratch, View, Workers, quiet_pair};
use std::sync::Arc;
use taps::Taps;

/// Samples pushed between two polls of the background workers for finished batches.
const POLL_EVERY_SAMPLES: usize = 64;

/// Settings of an [`IncrementReconstructor`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReconstructConfig {
    /// Stencil half-width `L` (samples): the interpolant spans `2L + 1` samples and the output
    /// lags the input by `L` samples. `0` degenerates to the single-sample constant-rate update.
    pub half_width: usize,
    /// Magnus steps per sample interval (clamped to 1..=4) on fast intervals (rotation per
    /// sample above 0.01 rad); the attitude error falls as `substeps⁻⁶`. Slower intervals take
    /// one step.
    pub substeps: usize,
    /// Sample intervals per output update (at least 1).
    pub intervals_per_update: usize,
    /// Threads: 1 computes in the caller's thread when a batch is complete; `n > 1` starts `n`
    /// background workers, so that the caller's own work (navigation) overlaps them.
    pub threads: usize,
    /// Samples per batch (at least 1, rounded up to whole updates); the output lags the input
    /// by up to this many samples (two batches per worker with threads) more than `half_width`.
    pub batch_len: usize,
    /// Take the closed-form path on quiet stencils.
    pub quiet_path: bool,
}

impl Default for ReconstructConfig {
    /// `L = 6` (13-sample stencil), two Magnus steps per interval, four intervals per update,
    /// two worker threads, batches of 8192 samples, quiet path on.
    fn default() -> Self {
        Self {
            half_width: 6,
            substeps: 2,
            intervals_per_update: 4,
            threads: 2,
            batch_len: 8192,
            quiet_path: true,
        }
    }
}

/// The reconstructed increments of one update (body frame at the update start).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Reconstructed {
    /// Rotation vector of `C_b(start)b(end)` (rad).
    pub phi_rad: Vec3,
    /// Specific-force velocity increment `∫ C_b(start)b(t) f(t) dt` (m/s).
    pub dv_body_mps: Vec3,
    /// Sample intervals spanned: `intervals_per_update`, fewer for the last update of the data.
    pub intervals: usize,
}

/// Streaming reconstructor: push compensated increments in time order (marking breaks between
/// smooth pieces, e.g. at motion-segment changes where the rate jumps), pop one
/// [`Reconstructed`] per `intervals_per_update` samples in the same order, at least
/// `half_width` samples (plus batching) later; [`IncrementReconstructor::finish`] flushes the
/// tail with one-sided stencils.
pub struct IncrementReconstructor {
    config: ReconstructConfig,
    taps: Arc<Taps>,
    /// Samples `base..pushed` still needed, as `[Δθ, Δv]`, and their quiet runs.
    data: Vec<[f64; 6]>,
    run: Vec<u32>,
    base: usize,
    pushed: usize,
    /// Absolute indices of the first samples of new pieces (ascending, > 0).
    breaks: Vec<usize>,
    /// First interval not yet submitted (a multiple of `intervals_per_update` until the end).
    next: usize,
    finished: bool,
    out: Vec<Reconstructed>,
    out_pos: usize,
    popped: usize,
    workers: Option<Workers>,
    /// Samples pushed when the workers were last asked in vain for results.
    polled_at: usize,
    /// Buffers of the computation in the caller's thread (one thread).
    scratch: Scratch,
}

impl std::fmt::Debug for IncrementReconstructor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("IncrementReconstructor")
            .field("config", &self.config)
            .field("pushed", &self.pushed)
            .field("popped", &self.popped)
            .field("finished", &self.finished)
            .finish_non_exhaustive()
    }
}

impl IncrementReconstructor {
    /// Reconstructor with `config` (out-of-range values are clamped: substeps to 1..=4,
    /// intervals_per_update, threads and batch_len to at least 1).
    pub fn new(config: ReconstructConfig) -> Self {
        let m = config.intervals_per_update.max(1);
        let config = ReconstructConfig {
            substeps: config.substeps.clamp(1, 4),
            intervals_per_update: m,
            threads: config.threads.max(1),
            batch_len: config.batch_len.max(1).div_ceil(m) * m,
            ..config
        };
        Self {
            taps: Arc::new(Taps::new(config.half_width, config.substeps)),
            config,
            data: Vec::new(),
            run: Vec::new(),
            base: 0,
            pushed: 0,
            breaks: Vec::new(),
            next: 0,
            finished: false,
            out: Vec::new(),
            out_pos: 0,
            popped: 0,
            workers: None,
            polled_at: 0,
            scratch: Scratch::default(),
        }
    }

    /// The (clamped) configuration.
    pub fn config(&self) -> &ReconstructConfig {
        &self.config
    }

    /// Add the next sample. Panics after [`Self::finish`].
    pub fn push(&mut self, inc: &Increment) {
        assert!(!self.finished, "push after finish");
        let (d, v) = (&inc.dtheta_rad, &inc.dv_mps);
        let x = [d.x, d.y, d.z, v.x, v.y, v.z];
        let run = match self.data.last() {
            Some(p) if quiet_pair(&x, p) => self.run[self.run.len() - 1] + 1,
            _ => 0,
        };
        self.data.push(x);
        self.run.push(run);
        self.pushed += 1;
        if self.pushed >= self.next + self.config.batch_len + self.config.half_width {
            self.submit_ready();
        }
    }

    /// Declare that the next pushed sample starts a new smooth piece (the rate or specific force
    /// may jump at this boundary): no stencil straddles it. No effect at the start.
    pub fn start_new_piece(&mut self) {
        if self.pushed > 0 && self.breaks.last() != Some(&self.pushed) {
            self.breaks.push(self.pushed);
        }
    }

    /// End of the data: every remaining interval becomes available to [`Self::pop`].
    pub fn finish(&mut self) {
        self.finished = true;
        self.submit_ready();
    }

    /// The next reconstructed update, in order, if computed (with background workers, their
    /// finished batches are collected at most every 64 pushed samples; after [`Self::finish`],
    /// waits for the workers until every update has been returned).
    pub fn pop(&mut self) -> Option<Reconstructed> {
        if self.out_pos == self.out.len() {
            // The workers return whole batches: asking after every sample costs a channel
            // poll per sample (3 % of a replay) and gains nothing.
            if !self.finished && self.pushed < self.polled_at + POLL_EVERY_SAMPLES {
                return None;
            }
            let Some(more) = self.workers.as_mut()?.next(self.finished) else {
                self.polled_at = self.pushed;
                return None;
            };
            self.absorb(more);
        }
        let r = *self.out.get(self.out_pos)?;
        self.out_pos += 1;
        self.popped += r.intervals;
        Some(r)
    }

    /// Samples pushed whose update has not been popped yet.
    pub fn pending(&self) -> usize {
        self.pushed - self.popped
    }

    /// Append computed updates to the output queue.
    fn absorb(&mut self, mut more: Vec<Reconstructed>) {
        self.out.drain(..self.out_pos);
        self.out.append(&mut more);
        self.out_pos = 0;
    }

    fn view(&self) -> View<'_> {
        View {
            data: &self.data,
            run: &self.run,
            base: self.base,
            breaks: &self.breaks,
            end: self.finished.then_some(self.pushed),
            pushed: self.pushed,
            quiet_path: self.config.quiet_path,
        }
    }

    /// Number of intervals from `next` that can be computed now, in whole updates unless the
    /// data have ended.
    fn ready(&self) -> usize {
        if self.finished {
            return self.pushed - self.next;
        }
        let (v, width) = (self.view(), self.taps.width);
        // Away from breaks, interval k needs k + L < pushed; a piece that has ended is complete.
        let ended = self.breaks.last().copied().unwrap_or(0);
        let mut k = self
            .pushed
            .saturating_sub(self.config.half_width)
            .max(ended)
            .max(self.next);
        while k > self.next && v.stencil(width, k - 1).is_none() {
            k -= 1;
        }
        let m = self.config.intervals_per_update;
        (k - self.next) / m * m
    }

    /// Compute (or hand to the workers) every update that is computable now.
    fn submit_ready(&mut self) {
        let n = self.ready();
        if n == 0 {
            return;
        }
        let (k0, k_end) = (self.next, self.next + n);
        // The stencils of k0..k_end lie within [k0 − 2L, k_end + 2L].
        let reach = 2 * self.config.half_width + 1;
        let lo = k0.saturating_sub(reach).max(self.base) - self.base;
        let hi = (k_end + reach).min(self.pushed) - self.base;
        let v = self.view();
        let job = Job {
            data: v.data[lo..hi].to_vec(),
            run: v.run[lo..hi].to_vec(),
            base: self.base + lo,
            breaks: v.breaks.to_vec(),
            end: v.end,
            pushed: self.pushed,
            k0,
            k_end,
            per_update: self.config.intervals_per_update,
            quiet_path: self.config.quiet_path,
        };
        self.next = k_end;
        if self.config.threads == 1 {
            let done = job.compute(&self.taps, &mut self.scratch);
            self.absorb(done);
        } else {
            let (threads, taps) = (self.config.threads, &self.taps);
            let workers = self
                .workers
                .get_or_insert_with(|| Workers::new(threads, Arc::clone(taps)));
            // At most two jobs per worker in flight: wait for the oldest beyond that.
            let waiting = (workers.in_flight() >= 2 * threads).then(|| workers.next(true));
            workers.submit(job);
            if let Some(Some(more)) = waiting {
                self.absorb(more);
            }
        }
        self.compact();
    }

    /// Drop samples that no future stencil needs (stencils start at most `2L` before their
    /// interval) once enough have accumulated.
    fn compact(&mut self) {
        let keep_from = self.next.saturating_sub(2 * self.config.half_width + 1);
        if keep_from > self.base + 4 * self.config.batch_len.max(1024) {
            let d = keep_from - self.base;
            self.data.drain(..d);
            self.run.drain(..d);
            self.base = keep_from;
            let first = self
                .breaks
                .partition_point(|&b| b <= keep_from)
                .saturating_sub(1);
            self.breaks.drain(..first);
        }
    }
}

/// Reconstruct a whole record at once: `breaks` are the indices of samples that start new
/// smooth pieces. Returns one [`Reconstructed`] per `intervals_per_update` increments.
pub fn reconstruct_all(
    config: ReconstructConfig,
    incs: &[Increment],
    breaks: &[usize],
) -> Vec<Reconstructed> {
    let mut r = IncrementReconstructor::new(config);
    let mut out = Vec::with_capacity(incs.len() / r.config.intervals_per_update + 1);
    let mut b = breaks.iter().peekable();
    for (k, inc) in incs.iter().enumerate() {
        let mut new_piece = false;
        while let Some(&x) = b.next_if(|&&x| x <= k) {
            new_piece |= x == k;
        }
        if new_piece {
            r.start_new_piece();
        }
        r.push(inc);
        out.extend(std::iter::from_fn(|| r.pop()));
    }
    r.finish();
    out.extend(std::iter::from_fn(|| r.pop()));
    out
}
