//! Batches of updates: the stencil of every interval, the quiet-sample test and path, and a pool
//! of worker threads that computes owned batches in the background, returning them in order.

use super::Reconstructed;
use super::kernel::{Product, constant_rate};
use super::taps::Taps;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, TryRecvError, channel};
use std::thread::JoinHandle;

/// Largest `|Δθ| δθ` (rad) between consecutive samples of a quiet stencil. Even multiplied by
/// the stencil width and its tap sizes (about 100) and accumulated systematically, this is below
/// 1e-9 deg/h.
const QUIET_ROT_RAD: f64 = 1e-19;
/// Largest `|Δθ| δv + |Δv| δθ` (m/s) between consecutive samples of a quiet stencil (below
/// 1e-5 ug in the same sense).
const QUIET_VEL_MPS: f64 = 1e-15;

/// Whether consecutive samples `a`, `b` are equal for the reconstruction: the terms that a
/// change between them can contribute to the coning and sculling corrections are bounded by
/// `|Δθ| δθ` (rad) and `|Δθ| δv + |Δv| δθ` (m/s), and both must be negligible
/// (`QUIET_ROT_RAD`, `QUIET_VEL_MPS`; maximum norms). The simulator's stationary increments, for
/// instance, jitter by up to 2e-9 relative (the rounding of `t_k+1 − t_k` at t = 15 h).
#[inline]
pub(super) fn quiet_pair(a: &[f64; 6], b: &[f64; 6]) -> bool {
    if a == b {
        return true;
    }
    let (mut th, mut v, mut dth, mut dv) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for c in 0..3 {
        th = th.max(a[c].abs());
        dth = dth.max((a[c] - b[c]).abs());
        v = v.max(a[c + 3].abs());
        dv = dv.max((a[c + 3] - b[c + 3]).abs());
    }
    th * dth <= QUIET_ROT_RAD && th * dv + v * dth <= QUIET_VEL_MPS
}

/// The samples a batch of updates needs, and where they sit in the record.
#[derive(Clone, Debug, Default)]
pub(super) struct Job {
    /// Samples `base..base + data.len()` as `[Δθ, Δv]` (rad, m/s).
    pub data: Vec<[f64; 6]>,
    /// Length of the run of quiet pairs ending at each sample.
    pub run: Vec<u32>,
    /// Absolute index of `data[0]`.
    pub base: usize,
    /// Absolute indices of the first samples of new pieces (ascending).
    pub breaks: Vec<usize>,
    /// End of the data if known.
    pub end: Option<usize>,
    /// Samples pushed so far (stencils may not reach beyond).
    pub pushed: usize,
    /// Intervals `k0..k_end` to compute, in updates of `per_update`.
    pub k0: usize,
    /// End of the intervals to compute.
    pub k_end: usize,
    /// Intervals per update.
    pub per_update: usize,
    /// Take the closed-form path on quiet stencils.
    pub quiet_path: bool,
}

/// A borrowed [`Job`].
#[derive(Clone, Copy)]
pub(super) struct View<'a> {
    pub data: &'a [[f64; 6]],
    pub run: &'a [u32],
    pub base: usize,
    pub breaks: &'a [usize],
    pub end: Option<usize>,
    pub pushed: usize,
    pub quiet_path: bool,
}

impl Job {
    /// The job as a view.
    pub fn view(&self) -> View<'_> {
        View {
            data: &self.data,
            run: &self.run,
            base: self.base,
            breaks: &self.breaks,
            end: self.end,
            pushed: self.pushed,
            quiet_path: self.quiet_path,
        }
    }

    /// Compute its updates.
    pub fn compute(&self, taps: &Taps) -> Vec<Reconstructed> {
        let (v, m) = (self.view(), self.per_update);
        let mut cache = None;
        (self.k0..self.k_end)
            .step_by(m)
            .map(|k| v.update(taps, k, (k + m).min(self.k_end), &mut cache))
            .collect()
    }
}

impl View<'_> {
    /// Stencil `(start, len)` (absolute) of interval `k` for stencils of `width` samples, or
    /// `None` if it needs samples not yet pushed: centred, shifted to stay inside its piece.
    pub fn stencil(&self, width: usize, k: usize) -> Option<(usize, usize)> {
        let i = self.breaks.partition_point(|&b| b <= k);
        let ps = if i == 0 { 0 } else { self.breaks[i - 1] };
        let pe = self.breaks.get(i).copied().or(self.end);
        let half = (width - 1) / 2;
        let (s, n) = match pe {
            Some(pe) => {
                let n = width.min(pe - ps);
                (k.saturating_sub(half).clamp(ps, pe - n), n)
            }
            None => (k.saturating_sub(half).max(ps), width),
        };
        (s + n <= self.pushed).then_some((s, n))
    }

    /// The update made of the intervals `k0..k1`. `cache` holds the last quiet update (its
    /// sample's bits and result), reused for identical quiet updates.
    fn update(
        &self,
        taps: &Taps,
        k0: usize,
        k1: usize,
        cache: &mut Option<([u64; 6], Reconstructed)>,
    ) -> Reconstructed {
        let intervals = k1 - k0;
        #[allow(
            clippy::expect_used,
            reason = "the batch holds every interval from k0 to k1 and its neighbours"
        )]
        let stencil = |k| self.stencil(taps.width, k).expect("computable interval");
        if self.quiet_path {
            let ((s0, _), (s1, n1)) = (stencil(k0), stencil(k1 - 1));
            if self.run[s1 + n1 - 1 - self.base] as usize >= s1 + n1 - s0 - 1 {
                // Every stencil of the update is quiet: constant rate over all of it.
                let x = &self.data[k0 - self.base];
                let bits = x.map(f64::to_bits);
                if let Some((b, r)) = cache
                    && r.intervals == intervals
                    && b.iter().zip(&bits).all(|(p, q)| p == q)
                {
                    return *r;
                }
                let (phi_rad, dv_body_mps) = constant_rate(x, intervals);
                let r = Reconstructed {
                    phi_rad,
                    dv_body_mps,
                    intervals,
                };
                *cache = Some((bits, r));
                return r;
            }
        }
        let mut acc = Product::new();
        for k in k0..k1 {
            let (s, n) = stencil(k);
            let (a, b) = (s - self.base, s + n - self.base);
            if self.quiet_path && self.run[b - 1] as usize >= n - 1 {
                acc.constant_rate(&self.data[k - self.base]);
            } else {
                taps.interval(&self.data[a..b], k - s, &mut acc);
            }
        }
        let (phi_rad, dv_body_mps) = acc.finish();
        Reconstructed {
            phi_rad,
            dv_body_mps,
            intervals,
        }
    }
}

/// Worker threads computing jobs in the background; results come back in submission order.
pub(super) struct Workers {
    to: Vec<Sender<Job>>,
    from: Vec<Receiver<Vec<Reconstructed>>>,
    handles: Vec<JoinHandle<()>>,
    submitted: usize,
    received: usize,
}

impl Workers {
    /// `n` (at least 1) workers sharing `taps`.
    pub fn new(n: usize, taps: Arc<Taps>) -> Self {
        let (mut to, mut from, mut handles) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..n.max(1) {
            let (job_tx, job_rx) = channel::<Job>();
            let (out_tx, out_rx) = channel();
            let taps = Arc::clone(&taps);
            handles.push(std::thread::spawn(move || {
                for job in job_rx {
                    if out_tx.send(job.compute(&taps)).is_err() {
                        break;
                    }
                }
            }));
            to.push(job_tx);
            from.push(out_rx);
        }
        Self {
            to,
            from,
            handles,
            submitted: 0,
            received: 0,
        }
    }

    /// Jobs submitted and not yet received.
    pub fn in_flight(&self) -> usize {
        self.submitted - self.received
    }

    /// Queue a job (round robin).
    #[allow(
        clippy::expect_used,
        reason = "a worker ends only with the pool or by panicking, which is propagated"
    )]
    pub fn submit(&mut self, job: Job) {
        let w = self.submitted % self.to.len();
        self.to[w].send(job).expect("reconstruction worker alive");
        self.submitted += 1;
    }

    /// The results of the oldest job in flight: waiting for them if `wait`, else only if done.
    #[allow(
        clippy::expect_used,
        reason = "a worker's panic is propagated to the caller"
    )]
    pub fn next(&mut self, wait: bool) -> Option<Vec<Reconstructed>> {
        if self.in_flight() == 0 {
            return None;
        }
        let rx = &self.from[self.received % self.from.len()];
        let out = match wait {
            true => Some(rx.recv().expect("reconstruction worker panicked")),
            false => match rx.try_recv() {
                Ok(out) => Some(out),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => panic!("reconstruction worker panicked"),
            },
        };
        self.received += out.is_some() as usize;
        out
    }
}

impl Drop for Workers {
    fn drop(&mut self) {
        self.to.clear();
        for h in self.handles.drain(..) {
            let _ = h.join();
        }
    }
}
