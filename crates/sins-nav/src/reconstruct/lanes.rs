//! Four intervals side by side: the Magnus steps, exponentials and Jacobians of
//! `super::kernel`, and the products of four updates' motions, evaluated on four independent
//! problems at once, one per lane of the AVX2 vectors of `crate::simd4`. Every lane performs the
//! scalar code's operations in the scalar code's order (separate multiplies and adds, the same
//! association, the same series chosen lane by lane), so each result is the scalar one to the
//! bit; a chunk with a lane outside the series' ranges falls back to the scalar code whole.

use super::kernel::{
    EXP_C, EXP_S, EXP_SERIES_BELOW, EXP_SHORT_BELOW, JAC_A, JAC_B, JAC_SERIES_BELOW,
    JAC_SHORT_BELOW, LOG_C, LOG_SERIES_BELOW, Lie, Motion, Se3, magnus6,
};
use super::taps::{MAX_ROT_ROWS, Moments, SplitMoments};
use crate::Vec3;
pub(super) use crate::simd4::LANES;
use crate::simd4::{F4, Q4, Token as V3, V4, horner, vectorize};
use pulp::f64x4;

impl Lie for V4 {
    #[inline(always)]
    fn lin(self, a: f64, o: Self, b: f64) -> Self {
        self * a + o * b
    }
    #[inline(always)]
    fn br(self, y: Self) -> Self {
        y.cross(&self)
    }
}

/// An se(3) element per lane.
#[derive(Clone, Copy, Debug)]
struct Se34 {
    w: V4,
    v: V4,
}

impl Lie for Se34 {
    #[inline(always)]
    fn lin(self, a: f64, o: Self, b: f64) -> Self {
        Se34 {
            w: self.w * a + o.w * b,
            v: self.v * a + o.v * b,
        }
    }
    #[inline(always)]
    fn br(self, y: Self) -> Self {
        Se34 {
            w: y.w.cross(&self.w),
            v: y.w.cross(&self.v) - self.w.cross(&y.v),
        }
    }
}

impl Se34 {
    /// Rows `(ω, f)` of lane-major storage.
    #[inline(always)]
    fn of(s: V3, c: &[Lanes; 6]) -> Self {
        Se34 {
            w: V4::of(s, &c[..3]),
            v: V4::of(s, &c[3..]),
        }
    }
}

/// [`super::kernel::quat_log`]: the series where `s² < 0.01`, lane by lane the closed form
/// elsewhere.
#[inline(always)]
fn quat_log(q: &Q4) -> V4 {
    let v = q.vector();
    let s2 = v.norm_squared();
    let mut f = horner(s2, &LOG_C) * 2.0;
    if !s2.all_below(LOG_SERIES_BELOW) {
        let f64x4(a, b, c, d) = f.v;
        let mut lanes = [a, b, c, d];
        for (l, fl) in lanes.iter_mut().enumerate() {
            let s2l = s2.lane(l);
            if !(s2l < LOG_SERIES_BELOW) {
                let sl = s2l.sqrt();
                *fl = 2.0 * sl.atan2(q.w.lane(l)) / sl;
            }
        }
        f.v = f64x4(lanes[0], lanes[1], lanes[2], lanes[3]);
    }
    v.scale(f)
}

/// [`super::kernel::left_jacobian_times`] per lane; `None` when a lane needs the closed form.
#[inline(always)]
fn left_jacobian_times(phi: &V4, rho: &V4) -> Option<V4> {
    let t2 = phi.norm_squared();
    if !t2.all_below(JAC_SERIES_BELOW) {
        return None;
    }
    let a = t2.below_select(JAC_SHORT_BELOW, horner(t2, &JAC_A[..4]), horner(t2, &JAC_A));
    let b = t2.below_select(JAC_SHORT_BELOW, horner(t2, &JAC_B[..4]), horner(t2, &JAC_B));
    let pr = phi.cross(rho);
    Some(*rho + pr.scale(a) + phi.cross(&pr).scale(b))
}

/// [`super::kernel::quat_exp`] per lane; `None` when a lane needs the closed form.
#[inline(always)]
fn quat_exp(phi: &V4) -> Option<Q4> {
    let x = phi.norm_squared() * 0.25;
    if !x.all_below(EXP_SERIES_BELOW) {
        return None;
    }
    let c = x.below_select(EXP_SHORT_BELOW, horner(x, &EXP_C[..4]), horner(x, &EXP_C));
    let s = x.below_select(EXP_SHORT_BELOW, horner(x, &EXP_S[..4]), horner(x, &EXP_S));
    Some(Q4 {
        w: c,
        i: s * phi.x,
        j: s * phi.y,
        k: s * phi.z,
    })
}

/// [`Motion::single`] of `magnus6(B_0, B_1, B_2)` for four intervals, into `out[at[l]]`;
/// false (nothing written) if a lane is outside the series' ranges.
#[inline(always)]
fn single(b: [Se34; 3], out: &mut [Motion], at: &[usize; LANES]) -> bool {
    let om = magnus6(b[0], b[1], b[2]);
    let (Some(dv), Some(q)) = (left_jacobian_times(&om.w, &om.v), quat_exp(&om.w)) else {
        return false;
    };
    for (l, &at) in at.iter().enumerate() {
        out[at] = Motion {
            phi: om.w.lane(l),
            q: q.lane(l),
            dv: dv.lane(l),
            split: false,
        };
    }
    true
}

/// [`Motion::split`] for four intervals: the samples `whole`, the substep rotation moment rows
/// `rot` (`3 · substeps − 1` of them) and the velocity moments `vel`, into `out[at[l]]`; false
/// (nothing written) if a lane is outside the series' ranges.
#[inline(always)]
fn split(whole: Se34, rot: &[V4], vel: [V4; 2], out: &mut [Motion], at: &[usize; LANES]) -> bool {
    let n = rot.len().div_ceil(3);
    let sigma = 1.0 / n as f64;
    let s = whole.w.x.s;
    let (mut rest, mut w1, mut w2) = (whole.w, V4::zeros(s), V4::zeros(s));
    let mut q: Option<Q4> = None;
    for i in 0..n {
        let (b0, b1, b2) = match i + 1 < n {
            true => (rot[3 * i], rot[3 * i + 1], rot[3 * i + 2]),
            false => (rest, rot[3 * i], rot[3 * i + 1]),
        };
        rest = rest - b0;
        let d = (i as f64 + 0.5) * sigma - 0.5;
        w1 = w1 + (b1 * sigma + b0 * d);
        w2 = w2 + (b2 * (sigma * sigma) + b1 * (2.0 * sigma * d) + b0 * (d * d));
        let Some(e) = quat_exp(&magnus6(b0, b1, b2)) else {
            return false;
        };
        q = Some(match q {
            None => e,
            Some(q) => q.mul(&e),
        });
    }
    let om = magnus6(whole, Se34 { w: w1, v: vel[0] }, Se34 { w: w2, v: vel[1] });
    let (Some(dv), Some(q)) = (left_jacobian_times(&om.w, &om.v), q) else {
        return false;
    };
    for (l, &at) in at.iter().enumerate() {
        out[at] = Motion {
            phi: Vec3::zeros(),
            q: q.lane(l),
            dv: dv.lane(l),
            split: true,
        };
    }
    true
}

/// Four consecutive intervals that share one stencil shape, from the samples as columns.
pub(super) struct Run<'a> {
    /// The samples' six components, `[Δθ, Δv]` (rad, m/s), one column each.
    pub cols: [&'a [f64]; 6],
    /// Column index of the first interval's stencil start (lane `l` starts at `start + l`).
    pub start: usize,
    /// Offset of the current sample in the stencil.
    pub offset: usize,
    /// The shape's taps (rows per sample as in `taps::stencil_taps`).
    pub taps: &'a [f64],
    /// Magnus steps of the taps.
    pub substeps: usize,
}

/// `R` moment rows from tap row `r0` over components `c0..c0 + 3` of four consecutive
/// stencils: each lane sums `taps[j · stride + r] · w[j][c]` over `j` in order from zero, as
/// `taps::moments` does.
#[inline(always)]
fn run_moments(s: V3, run: &Run, stride: usize, r0: usize, c0: usize, out: &mut [V4]) {
    let width = run.taps.len() / stride;
    for (r, o) in out.iter_mut().enumerate() {
        let mut acc = [F4::splat(s, 0.0); 3];
        for j in 0..width {
            let t = F4::splat(s, run.taps[j * stride + r0 + r]);
            for (c, a) in acc.iter_mut().enumerate() {
                let w = &run.cols[c0 + c][run.start + j..run.start + j + LANES];
                *a = *a
                    + t * F4 {
                        v: f64x4(w[0], w[1], w[2], w[3]),
                        s,
                    };
            }
        }
        *o = V4 {
            x: acc[0],
            y: acc[1],
            z: acc[2],
        };
    }
}

/// The motions of a [`Run`] into `out[at[l]]`: false (nothing written) if a lane is outside
/// the series' ranges.
#[inline(always)]
fn run_motions(s: V3, run: &Run, out: &mut [Motion], at: &[usize; LANES]) -> bool {
    let cur = |c0: usize| {
        let i = run.start + run.offset;
        let f = |c: usize| {
            let w = &run.cols[c][i..i + LANES];
            F4 {
                v: f64x4(w[0], w[1], w[2], w[3]),
                s,
            }
        };
        V4 {
            x: f(c0),
            y: f(c0 + 1),
            z: f(c0 + 2),
        }
    };
    let whole = Se34 {
        w: cur(0),
        v: cur(3),
    };
    let zero = V4::zeros(s);
    match run.substeps {
        1 => {
            let (mut w, mut v) = ([zero; 2], [zero; 2]);
            run_moments(s, run, 2, 0, 0, &mut w);
            run_moments(s, run, 2, 0, 3, &mut v);
            let b = |p: usize| Se34 { w: w[p], v: v[p] };
            single([whole, b(0), b(1)], out, at)
        }
        n => {
            let (rows, stride) = (3 * n - 1, 3 * n + 1);
            let mut rot = [zero; MAX_ROT_ROWS];
            let mut vel = [zero; 2];
            run_moments(s, run, stride, 0, 0, &mut rot[..rows]);
            run_moments(s, run, stride, rows, 3, &mut vel);
            split(whole, &rot[..rows], vel, out, at)
        }
    }
}

/// The products of four updates' motions, for [`LaneQueue::products`]: lane `l` multiplies
/// `motions[starts[l]..starts[l] + len]`.
struct Products<'a> {
    motions: &'a [Motion],
    starts: [usize; LANES],
    len: usize,
    s: V3,
}

impl pulp::WithSimd for Products<'_> {
    type Output = Option<[(Vec3, Vec3); LANES]>;

    /// As [`super::kernel::Product`]: the first factor's rotation (as a quaternion) and
    /// translation, then `ΔV += q ΔV_i`, `q ← q q_i` per further factor; the rotation vector
    /// is the first factor's if it is the only one and a single step, else the logarithm of
    /// the normalised quaternion. `None` when the update is one factor, a single step in some
    /// lanes and substeps in others.
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        let (s, m, st) = (self.s, self.motions, self.starts);
        let at = |i: usize| [&m[st[0] + i], &m[st[1] + i], &m[st[2] + i], &m[st[3] + i]];
        let v4 = |v: [&Vec3; LANES]| V4 {
            x: F4 {
                v: f64x4(v[0].x, v[1].x, v[2].x, v[3].x),
                s,
            },
            y: F4 {
                v: f64x4(v[0].y, v[1].y, v[2].y, v[3].y),
                s,
            },
            z: F4 {
                v: f64x4(v[0].z, v[1].z, v[2].z, v[3].z),
                s,
            },
        };
        let first = at(0);
        let mut q = Q4::of(s, first.map(|f| &f.q));
        let mut dv = v4(first.map(|f| &f.dv));
        for i in 1..self.len {
            let mi = at(i);
            dv = dv + q.rotate(&v4(mi.map(|f| &f.dv)));
            q = q.mul(&Q4::of(s, mi.map(|f| &f.q)));
        }
        let phi = match self.len {
            1 if first.iter().all(|f| !f.split) => v4(first.map(|f| &f.phi)),
            1 if first.iter().any(|f| !f.split) => return None,
            _ => quat_log(&q.normalize()),
        };
        Some(std::array::from_fn(|l| (phi.lane(l), dv.lane(l))))
    }
}

/// One `f64` per lane, as the queue stores them.
type Lanes = [f64; LANES];

/// Split moments of four intervals, lane-major.
#[derive(Clone, Copy, Default)]
struct SplitLanes {
    cur: [Lanes; 6],
    rot: [[Lanes; 3]; MAX_ROT_ROWS],
    vel: [[Lanes; 3]; 2],
}

/// Intervals waiting for a full chunk, by kind: where each motion goes and its moments,
/// lane-major. Full chunks are evaluated four lanes at once where the CPU has AVX2, else (and
/// for part-filled chunks) one by one with the scalar code: the same bits either way.
pub(super) struct LaneQueue {
    single: [[Lanes; 6]; 3],
    single_at: [usize; LANES],
    n_single: usize,
    split: SplitLanes,
    split_at: [usize; LANES],
    rot_rows: usize,
    n_split: usize,
    avx2: Option<V3>,
}

/// Four intervals to evaluate, in code compiled for AVX2 ([`vectorize`]).
enum Chunk<'a> {
    /// The queue's full chunk of a kind (`split` or not).
    Queued(&'a LaneQueue, bool),
    /// Four consecutive intervals of one shape, going to `out[at..at + 4]`.
    Run(&'a Run<'a>, usize),
}

/// A [`Chunk`] with where its motions go.
struct Eval<'a> {
    chunk: Chunk<'a>,
    out: &'a mut [Motion],
    s: V3,
}

impl pulp::WithSimd for Eval<'_> {
    type Output = bool;

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> bool {
        let (s, out) = (self.s, self.out);
        match self.chunk {
            Chunk::Queued(q, false) => {
                let b = |p: usize| Se34::of(s, &q.single[p]);
                single([b(0), b(1), b(2)], out, &q.single_at)
            }
            Chunk::Queued(q, true) => {
                let m = &q.split;
                let mut rot = [V4::zeros(s); MAX_ROT_ROWS];
                for (r, lanes) in rot.iter_mut().zip(&m.rot[..q.rot_rows]) {
                    *r = V4::of(s, lanes);
                }
                let vel = [V4::of(s, &m.vel[0]), V4::of(s, &m.vel[1])];
                split(
                    Se34::of(s, &m.cur),
                    &rot[..q.rot_rows],
                    vel,
                    out,
                    &q.split_at,
                )
            }
            Chunk::Run(run, at) => run_motions(s, run, out, &[at, at + 1, at + 2, at + 3]),
        }
    }
}

impl LaneQueue {
    /// An empty queue.
    pub fn new() -> Self {
        Self {
            single: [[[0.0; LANES]; 6]; 3],
            single_at: [0; LANES],
            n_single: 0,
            split: SplitLanes::default(),
            split_at: [0; LANES],
            rot_rows: 0,
            n_split: 0,
            avx2: V3::try_new(),
        }
    }

    /// Queue the interval whose motion goes to `out[at]`; a full chunk is evaluated at once.
    #[inline(always)]
    pub fn push(&mut self, at: usize, m: &Moments, out: &mut [Motion]) {
        match m {
            Moments::Single(b) => {
                let l = self.n_single;
                for (p, bp) in b.iter().enumerate() {
                    let row = &mut self.single[p];
                    for c in 0..3 {
                        row[c][l] = bp.w[c];
                        row[c + 3][l] = bp.v[c];
                    }
                }
                self.single_at[l] = at;
                self.n_single += 1;
                if self.n_single == LANES {
                    self.evaluate(false, out);
                }
            }
            Moments::Split(s) => {
                let l = self.n_split;
                let m = &mut self.split;
                for c in 0..6 {
                    m.cur[c][l] = s.cur[c];
                }
                for (row, r) in m.rot.iter_mut().zip(&s.rot[..s.rot_rows]) {
                    for c in 0..3 {
                        row[c][l] = r[c];
                    }
                }
                for (row, r) in m.vel.iter_mut().zip(&s.vel) {
                    for c in 0..3 {
                        row[c][l] = r[c];
                    }
                }
                self.rot_rows = s.rot_rows;
                self.split_at[l] = at;
                self.n_split += 1;
                if self.n_split == LANES {
                    self.evaluate(true, out);
                }
            }
        }
    }

    /// Evaluate a full chunk.
    fn evaluate(&mut self, split: bool, out: &mut [Motion]) {
        let done = self.avx2.is_some_and(|s| {
            let chunk = Chunk::Queued(self, split);
            vectorize(s, Eval { chunk, out, s })
        });
        if !done {
            self.scalar(split, out);
        }
        match split {
            true => self.n_split = 0,
            false => self.n_single = 0,
        }
    }

    /// Whether the CPU has AVX2 (else every motion is evaluated by the scalar code).
    pub fn has_lanes(&self) -> bool {
        self.avx2.is_some()
    }

    /// Evaluate four consecutive intervals of one shape into `out[at..at + 4]` if the CPU has
    /// AVX2 and they are inside the series' ranges; false (nothing written) otherwise.
    pub fn run(&self, run: &Run, out: &mut [Motion], at: usize) -> bool {
        self.avx2.is_some_and(|s| {
            let chunk = Chunk::Run(run, at);
            vectorize(s, Eval { chunk, out, s })
        })
    }

    /// The products of four updates' motions (lane `l`: `motions[starts[l]..][..len]`) in code
    /// compiled for AVX2: `(φ, ΔV)` per update, or `None` (the scalar
    /// [`super::kernel::Product`] does them then).
    pub fn products(
        &self,
        motions: &[Motion],
        starts: [usize; LANES],
        len: usize,
    ) -> Option<[(Vec3, Vec3); LANES]> {
        let s = self.avx2?;
        let p = Products {
            motions,
            starts,
            len,
            s,
        };
        vectorize(s, p)
    }

    /// Evaluate the intervals left in part-filled chunks.
    pub fn flush(&mut self, out: &mut [Motion]) {
        for split in [false, true] {
            self.scalar(split, out);
        }
        (self.n_single, self.n_split) = (0, 0);
    }

    /// The queued intervals of a kind, one by one with the scalar code.
    fn scalar(&self, split: bool, out: &mut [Motion]) {
        let n = if split { self.n_split } else { self.n_single };
        for l in 0..n {
            let (at, m) = match split {
                false => (self.single_at[l], Moments::Single(self.single_lane(l))),
                true => (self.split_at[l], Moments::Split(self.split_lane(l))),
            };
            out[at] = m.motion();
        }
    }

    fn single_lane(&self, l: usize) -> [Se3; 3] {
        std::array::from_fn(|p| {
            let c = &self.single[p];
            Se3 {
                w: Vec3::new(c[0][l], c[1][l], c[2][l]),
                v: Vec3::new(c[3][l], c[4][l], c[5][l]),
            }
        })
    }

    fn split_lane(&self, l: usize) -> SplitMoments {
        let (m, row) = (&self.split, |r: &[Lanes; 3]| [r[0][l], r[1][l], r[2][l]]);
        let mut s = SplitMoments {
            cur: std::array::from_fn(|c| m.cur[c][l]),
            rot: [[0.0; 3]; MAX_ROT_ROWS],
            rot_rows: self.rot_rows,
            vel: [row(&m.vel[0]), row(&m.vel[1])],
        };
        for (r, lanes) in s.rot.iter_mut().zip(&m.rot) {
            *r = row(lanes);
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reconstruct::taps::{Taps, is_slow};

    /// Uniform deviates in [−1, 1) (xorshift64*).
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
            x as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// `n` samples turning by about `scale` rad each about a wandering axis, with a specific
    /// force near 1 g.
    fn samples(rng: &mut Rng, n: usize, scale: f64) -> Vec<[f64; 6]> {
        let axis = [0.6, -0.5, 0.62];
        (0..n)
            .map(|_| {
                let r = |a: f64, rng: &mut Rng| scale * (a + 0.1 * rng.next());
                let v = |a: f64, rng: &mut Rng| 0.005 * (a + 0.01 * rng.next());
                [
                    r(axis[0], rng),
                    r(axis[1], rng),
                    r(axis[2], rng),
                    v(0.1, rng),
                    v(-0.2, rng),
                    v(9.8, rng),
                ]
            })
            .collect()
    }

    fn bits(m: &Motion) -> Vec<u64> {
        let q = m.q.coords;
        m.phi
            .iter()
            .chain(q.iter())
            .chain(m.dv.iter())
            .map(|x| x.to_bits())
            .chain([u64::from(m.split)])
            .collect()
    }

    /// Four consecutive full stencils evaluated in the lanes, straight from the columns and
    /// through the queue, give the scalar motions to the bit, for one to four substeps and
    /// rotations from 1e-5 to 0.25 rad per sample (every series branch; the last beyond the
    /// Jacobian's series, where the chunk falls back to the scalar code).
    #[test]
    fn the_lanes_give_the_scalar_motions_bit_for_bit() {
        let Some(s) = V3::try_new() else {
            eprintln!("this CPU has no AVX2: the lanes are never used");
            return;
        };
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (mut in_lanes, mut fell_back) = (0, 0);
        for substeps in 1..=4 {
            let taps = Taps::new(6, substeps);
            for scale in [1e-5, 3e-3, 0.02, 0.05, 0.25] {
                for _ in 0..20 {
                    let w = samples(&mut rng, 13 + LANES - 1, scale);
                    let scalar: Vec<Motion> = (0..LANES)
                        .map(|l| taps.moments(&w[l..l + 13], 6).motion())
                        .collect();
                    let slow = is_slow(&w[6]);
                    assert!((0..LANES).all(|l| is_slow(&w[6 + l]) == slow));
                    let cols: [Vec<f64>; 6] =
                        std::array::from_fn(|c| w.iter().map(|x| x[c]).collect());
                    let (t, n) = taps.shape(13, 6, slow);
                    let run = Run {
                        cols: cols.each_ref().map(Vec::as_slice),
                        start: 0,
                        offset: 6,
                        taps: t,
                        substeps: n,
                    };
                    let mut out = vec![Motion::single(Se3::default()); LANES];
                    let chunk = Chunk::Run(&run, 0);
                    let done = vectorize(
                        s,
                        Eval {
                            chunk,
                            out: &mut out,
                            s,
                        },
                    );
                    let mut queued = vec![Motion::single(Se3::default()); LANES];
                    let mut queue = LaneQueue::new();
                    for l in 0..LANES {
                        queue.push(l, &taps.moments(&w[l..l + 13], 6), &mut queued);
                    }
                    queue.flush(&mut queued);
                    for l in 0..LANES {
                        if done {
                            assert_eq!(bits(&out[l]), bits(&scalar[l]), "run {substeps} {scale}");
                        }
                        assert_eq!(
                            bits(&queued[l]),
                            bits(&scalar[l]),
                            "queue {substeps} {scale}"
                        );
                    }
                    match done {
                        true => in_lanes += 1,
                        false => fell_back += 1,
                    }
                }
            }
        }
        // The widest rotation (0.25 rad per sample) is beyond the Jacobian's series whatever
        // the substeps; everything else runs in the lanes.
        assert_eq!((in_lanes, fell_back), (320, 80));
    }

    /// Four updates' products in the lanes equal the scalar [`super::super::kernel::Product`]
    /// to the bit: one to four factors, single steps and substeps, rotations per update from
    /// 1e-4 rad to 0.6 rad (the logarithm's series and its closed form, lane by lane).
    #[test]
    fn the_lane_products_are_the_scalar_products_bit_for_bit() {
        use super::super::kernel::Product;
        let Some(_) = V3::try_new() else {
            eprintln!("this CPU has no AVX2: the lanes are never used");
            return;
        };
        let queue = LaneQueue::new();
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let (mut in_lanes, mut refused) = (0, 0);
        for len in 1..=4 {
            for scale in [1e-4, 0.01, 0.06, 0.15] {
                for trial in 0..25 {
                    let motions: Vec<Motion> = (0..LANES * len)
                        .map(|i| {
                            let r = |rng: &mut Rng| scale * rng.next();
                            let om = Se3 {
                                w: Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng)),
                                v: Vec3::new(0.01 * rng.next(), 0.01 * rng.next(), 0.049),
                            };
                            let single = Motion::single(om);
                            // Every other trial, some factors come from substeps.
                            match trial % 2 == 1 && i % 3 == 0 {
                                true => Motion {
                                    phi: Vec3::zeros(),
                                    split: true,
                                    ..single
                                },
                                false => single,
                            }
                        })
                        .collect();
                    let starts = std::array::from_fn(|l| l * len);
                    let Some(lanes) = queue.products(&motions, starts, len) else {
                        refused += 1;
                        continue;
                    };
                    in_lanes += 1;
                    for (l, (phi, dv)) in lanes.iter().enumerate() {
                        let mut p = Product::new();
                        for m in &motions[starts[l]..starts[l] + len] {
                            p.apply(m);
                        }
                        let (sphi, sdv) = p.finish();
                        let b = |v: &Vec3| v.map(f64::to_bits);
                        assert_eq!((b(phi), b(dv)), (b(&sphi), b(&sdv)), "{len} {scale}");
                    }
                }
            }
        }
        // Refused: the one-factor updates that mix single steps and substeps (the 12 odd
        // trials of each scale with one factor).
        assert_eq!((in_lanes, refused), (352, 48));
    }
}
