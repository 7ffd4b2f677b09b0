//! Batches of updates: the stencil of every interval, the quiet-sample test and path, and a pool
//! of worker threads that computes owned batches in the background, returning them in order.

use super::Reconstructed;
use super::kernel::{Motion, Product, Se3, constant_rate};
use super::lanes::{LANES, LaneQueue, Run};
use super::taps::{Taps, is_slow};
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

    /// Compute its updates: segment by segment, first the motion of every interval that needs
    /// one (four at a time, [`LaneQueue`]), then their products per update.
    pub fn compute(&self, taps: &Taps, scratch: &mut Scratch) -> Vec<Reconstructed> {
        let (v, m) = (self.view(), self.per_update);
        let mut cache = None;
        let mut queue = LaneQueue::new();
        let Scratch {
            cols,
            motions,
            need,
        } = scratch;
        motions.resize(SEGMENT_UPDATES * m, Motion::single(Se3::default()));
        let mut quiet = [false; SEGMENT_UPDATES];
        let mut out = Vec::with_capacity((self.k_end - self.k0).div_ceil(m));
        for (c, col) in cols.iter_mut().enumerate() {
            col.clear();
            col.extend(self.data.iter().map(|x| x[c]));
        }
        let cols = cols.each_ref().map(Vec::as_slice);
        let mut k = self.k0;
        while k < self.k_end {
            let end = (k + SEGMENT_UPDATES * m).min(self.k_end);
            let updates = || (k..end).step_by(m).map(|k0| (k0, (k0 + m).min(end)));
            need.clear();
            for (u, (k0, k1)) in updates().enumerate() {
                quiet[u] = v.quiet_update(taps, k0, k1);
                if !quiet[u] {
                    need.extend(k0..k1);
                }
            }
            let mut i = 0;
            while i < need.len() {
                // Four consecutive intervals of one shape go to the lanes straight from the
                // columns; the others through the queue.
                let first = need[i];
                if queue.has_lanes()
                    && need.get(i + LANES - 1) == Some(&(first + LANES - 1))
                    && let Some(run) = v.run(taps, first, cols)
                    && queue.run(&run, motions, first - k)
                {
                    i += LANES;
                    continue;
                }
                v.queue_interval(taps, first, &mut queue, motions, first - k);
                i += 1;
            }
            queue.flush(motions);
            let mut bounds = [(0, 0); SEGMENT_UPDATES];
            let mut n_updates = 0;
            for (slot, b) in bounds.iter_mut().zip(updates()) {
                *slot = b;
                n_updates += 1;
            }
            let bounds = &bounds[..n_updates];
            let mut u = 0;
            while u < bounds.len() {
                // Four updates of as many intervals each, none quiet: their products side by
                // side; the others one by one.
                let group = bounds.get(u..u + LANES).filter(|g| {
                    let len = g[0].1 - g[0].0;
                    g.iter().all(|&(a, b)| b - a == len) && !quiet[u..u + LANES].contains(&true)
                });
                let lanes = group.and_then(|g| {
                    let starts = std::array::from_fn(|l| g[l].0 - k);
                    queue.products(motions, starts, g[0].1 - g[0].0)
                });
                if let (Some(g), Some(lanes)) = (group, lanes) {
                    for (&(k0, k1), (phi_rad, dv_body_mps)) in g.iter().zip(lanes) {
                        out.push(Reconstructed {
                            phi_rad,
                            dv_body_mps,
                            intervals: k1 - k0,
                        });
                    }
                    u += LANES;
                    continue;
                }
                let (k0, k1) = bounds[u];
                out.push(match quiet[u] {
                    true => v.constant_update(k0, k1, &mut cache),
                    false => {
                        let mut acc = Product::new();
                        for motion in &motions[k0 - k..k1 - k] {
                            acc.apply(motion);
                        }
                        let (phi_rad, dv_body_mps) = acc.finish();
                        Reconstructed {
                            phi_rad,
                            dv_body_mps,
                            intervals: k1 - k0,
                        }
                    }
                });
                u += 1;
            }
            k = end;
        }
        out
    }
}

/// Buffers that [`Job::compute`] reuses from job to job: the samples as columns, the motions of
/// a segment's intervals and which intervals need one.
#[derive(Default)]
pub(super) struct Scratch {
    cols: [Vec<f64>; 6],
    motions: Vec<Motion>,
    need: Vec<usize>,
}

/// Updates per segment of [`Job::compute`].
const SEGMENT_UPDATES: usize = 16;

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

    /// Stencil `(start, len)` of interval `k`, which the job holds.
    fn held_stencil(&self, width: usize, k: usize) -> (usize, usize) {
        #[allow(
            clippy::expect_used,
            reason = "the batch holds every interval from k0 to k1 and its neighbours"
        )]
        self.stencil(width, k).expect("computable interval")
    }

    /// Whether the update made of the intervals `k0..k1` takes the closed form: every stencil
    /// of it is quiet (constant rate over all of it).
    fn quiet_update(&self, taps: &Taps, k0: usize, k1: usize) -> bool {
        if !self.quiet_path {
            return false;
        }
        let (s0, _) = self.held_stencil(taps.width, k0);
        let (s1, n1) = self.held_stencil(taps.width, k1 - 1);
        self.run[s1 + n1 - 1 - self.base] as usize >= s1 + n1 - s0 - 1
    }

    /// The constant-rate update of the quiet intervals `k0..k1`. `cache` holds the last one
    /// (its sample's bits and result), reused for identical quiet updates.
    fn constant_update(
        &self,
        k0: usize,
        k1: usize,
        cache: &mut Option<([u64; 6], Reconstructed)>,
    ) -> Reconstructed {
        let intervals = k1 - k0;
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
        r
    }

    /// The four intervals from `k` as a [`Run`] of the samples' columns `cols` (indexed from
    /// `base`), if they share one stencil shape and kind (slow or not) and none is quiet.
    fn run<'a>(&self, taps: &'a Taps, k: usize, cols: [&'a [f64]; 6]) -> Option<Run<'a>> {
        let (s, n) = self.held_stencil(taps.width, k);
        let slow = is_slow(&self.data[k - self.base]);
        for l in 0..LANES {
            let (sl, nl) = self.held_stencil(taps.width, k + l);
            let quiet = self.quiet_path && self.run[sl + nl - 1 - self.base] as usize >= nl - 1;
            if (sl, nl) != (s + l, n) || quiet || is_slow(&self.data[k + l - self.base]) != slow {
                return None;
            }
        }
        let (taps, substeps) = taps.shape(n, k - s, slow);
        Some(Run {
            cols,
            start: s - self.base,
            offset: k - s,
            taps,
            substeps,
        })
    }

    /// The motion of interval `k` into `out[at]`: at once on a quiet stencil, else queued.
    #[inline(always)]
    fn queue_interval(
        &self,
        taps: &Taps,
        k: usize,
        queue: &mut LaneQueue,
        out: &mut [Motion],
        at: usize,
    ) {
        let (s, n) = self.held_stencil(taps.width, k);
        let (a, b) = (s - self.base, s + n - self.base);
        if self.quiet_path && self.run[b - 1] as usize >= n - 1 {
            out[at] = Motion::single(Se3::from6(&self.data[k - self.base]));
        } else if queue.has_lanes() {
            queue.push(at, &taps.moments(&self.data[a..b], k - s), out);
        } else {
            out[at] = taps.motion(&self.data[a..b], k - s);
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
                let mut scratch = Scratch::default();
                for job in job_rx {
                    if out_tx.send(job.compute(&taps, &mut scratch)).is_err() {
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
