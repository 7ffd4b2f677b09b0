//! Precomputed FIR taps: the Legendre moments of the derivative of the Lagrange interpolant of
//! the cumulative increments, for every stencil shape, and the per-interval kernel using them.

use super::kernel::{Motion, Se3, magnus6};

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton iteration on the Legendre polynomial).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-17 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Moment taps of one stencil shape: `n` samples, current interval at `offset`. Moment
/// `(s, p)` is `σ⁻ᵖ ∫ (x − x_s)ᵖ u_j(x) dx` over substep `s` (length σ = 1/substeps in sample
/// units, midpoint `x_s`), where `u_j(x)` is the weight of sample `j` in the derivative of the
/// Lagrange interpolant of the cumulative sums at the boundaries `0..=n`; computed by
/// Gauss–Legendre quadrature, exact for these polynomials. Rows per sample `j`
/// (`taps[j * rows + r]`): with one substep, `B_1, B_2` of the interval; otherwise the
/// substep moments `(s, 0..3)` for every substep but the last, `(S−1, 1..3)` (the last `B_0`
/// follows from `Σ B_0 = sample`), then `B_1, B_2` of the whole interval.
fn stencil_taps(n: usize, offset: usize, substeps: usize) -> Vec<f64> {
    let gl = gauss_legendre(n / 2 + 3);
    let sigma = 1.0 / substeps as f64;
    // All substep moments: sub[(s * 3 + p) * n + j].
    let mut sub = vec![0.0; 3 * substeps * n];
    let mut lp = vec![0.0; n + 1];
    for s in 0..substeps {
        let mid = offset as f64 + (s as f64 + 0.5) * sigma;
        for &(xi, wg) in &gl {
            let x = mid + 0.5 * sigma * xi;
            // ℓ'_m(x) of the Lagrange basis on the nodes 0..=n.
            for (m, l) in lp.iter_mut().enumerate() {
                let (mut prod, mut sum) = (1.0, 0.0);
                for q in (0..=n).filter(|&q| q != m) {
                    prod *= (x - q as f64) / (m as f64 - q as f64);
                    sum += 1.0 / (x - q as f64);
                }
                *l = prod * sum;
            }
            // Sample j's rate weight: Σ_{m > j} ℓ'_m(x).
            let mut u = 0.0;
            for j in (0..n).rev() {
                u += lp[j + 1];
                let mut pw = 0.5 * sigma * wg;
                for p in 0..3 {
                    sub[(s * 3 + p) * n + j] += pw * u;
                    pw *= 0.5 * xi;
                }
            }
        }
    }
    let rows = if substeps == 1 { 2 } else { 3 * substeps + 1 };
    let mut taps = vec![0.0; n * rows];
    for j in 0..n {
        let m = |s: usize, p: usize| sub[(s * 3 + p) * n + j];
        let t = &mut taps[j * rows..(j + 1) * rows];
        // Whole-interval B_1, B_2 from the substep moments (x − ½ = σ u + d_s).
        let (mut w1, mut w2) = (0.0, 0.0);
        for s in 0..substeps {
            let d = (s as f64 + 0.5) * sigma - 0.5;
            w1 += sigma * m(s, 1) + d * m(s, 0);
            w2 += sigma * sigma * m(s, 2) + 2.0 * sigma * d * m(s, 1) + d * d * m(s, 0);
        }
        t[rows - 2] = w1;
        t[rows - 1] = w2;
        for s in 0..substeps.saturating_sub(1) {
            t[3 * s..3 * s + 3].copy_from_slice(&[m(s, 0), m(s, 1), m(s, 2)]);
        }
        if substeps > 1 {
            let s = substeps - 1;
            t[3 * s..3 * s + 2].copy_from_slice(&[m(s, 1), m(s, 2)]);
        }
    }
    taps
}

/// `R` moment rows of a stencil over the components `C0..C0 + C` of the samples:
/// `Σ_j taps[j * stride + r0 + r] · w[j][C0 + c]`, in passes of at most four rows so that the
/// accumulators stay in registers.
#[inline(always)]
fn moments<const R: usize, const C0: usize, const C: usize>(
    w: &[[f64; 6]],
    taps: &[f64],
    stride: usize,
    r0: usize,
) -> [[f64; C]; R] {
    let mut acc = [[0.0; C]; R];
    for p0 in (0..R).step_by(4) {
        let rows = r0 + p0..r0 + (p0 + 4).min(R);
        let mut part = [[0.0; C]; 4];
        for (x, t) in w.iter().zip(taps.chunks_exact(stride)) {
            for (a, &tr) in part.iter_mut().zip(&t[rows.clone()]) {
                for c in 0..C {
                    a[c] += tr * x[C0 + c];
                }
            }
        }
        for (a, p) in acc[p0..].iter_mut().zip(part) {
            *a = p;
        }
    }
    acc
}

/// Rotation per sample (rad) below which an interval takes a single Magnus step even when more
/// substeps are configured: 0.01 rad per 5 ms sample is 115 deg/s. The Magnus error grows with
/// the 7th power of the rotation per step, so the slow intervals contribute nothing measurable
/// (error-free floor over the paper's 15 h run: 0.3 m with and without this switch) while the
/// kernel runs at the single-step cost outside the fast vibration peaks.
pub(super) const SUBSTEP_MIN_ROTATION_RAD: f64 = 0.01;

/// Whether the sample `(Δθ, Δv)` rotates by less than [`SUBSTEP_MIN_ROTATION_RAD`].
#[inline(always)]
pub(super) fn is_slow(cur: &[f64; 6]) -> bool {
    cur[0] * cur[0] + cur[1] * cur[1] + cur[2] * cur[2]
        < SUBSTEP_MIN_ROTATION_RAD * SUBSTEP_MIN_ROTATION_RAD
}

/// Taps of every stencil shape: `by_shape[n - 1][offset]`.
type ShapeTaps = Vec<Vec<Vec<f64>>>;

fn all_shapes(width: usize, substeps: usize) -> ShapeTaps {
    (1..=width)
        .map(|n| (0..n).map(|i| stencil_taps(n, i, substeps)).collect())
        .collect()
}

/// Precomputed taps of every stencil shape `(n, offset)`, `1 <= n <= 2L + 1`.
#[derive(Clone, Debug)]
pub(super) struct Taps {
    /// Full stencil width `2L + 1` (samples).
    pub width: usize,
    substeps: usize,
    /// Taps for `substeps` Magnus steps per interval.
    by_shape: ShapeTaps,
    /// Taps for a single step (used below [`SUBSTEP_MIN_ROTATION_RAD`]) when `substeps > 1`.
    single: Option<ShapeTaps>,
}

impl Taps {
    /// Taps for half-width `L` and `substeps` (1..=4) Magnus steps per interval.
    pub fn new(half_width: usize, substeps: usize) -> Self {
        assert!((1..=4).contains(&substeps), "substeps must be 1..=4");
        let width = 2 * half_width + 1;
        Self {
            width,
            substeps,
            by_shape: all_shapes(width, substeps),
            single: (substeps > 1).then(|| all_shapes(width, 1)),
        }
    }

    /// The taps and Magnus steps of the stencil of `n` samples with the current one at `offset`,
    /// for a slow interval (below [`SUBSTEP_MIN_ROTATION_RAD`]) or not.
    #[inline(always)]
    pub fn shape(&self, n: usize, offset: usize, slow: bool) -> (&[f64], usize) {
        match (&self.single, slow) {
            (Some(single), true) => (&single[n - 1][offset], 1),
            _ => (&self.by_shape[n - 1][offset], self.substeps),
        }
    }

    /// The moments of the interval whose stencil samples (6-vectors) are `w`, current sample
    /// `w[offset]`: one Magnus step's below [`SUBSTEP_MIN_ROTATION_RAD`], else `substeps`
    /// steps'.
    #[inline(always)]
    pub fn moments(&self, w: &[[f64; 6]], offset: usize) -> Moments {
        self.with_moments(w, offset, Moments::Single, |cur, rot, vel| {
            let mut m = SplitMoments {
                cur: *cur,
                rot: [[0.0; 3]; MAX_ROT_ROWS],
                rot_rows: rot.len(),
                vel,
            };
            m.rot[..rot.len()].copy_from_slice(rot);
            Moments::Split(m)
        })
    }

    /// The motion over the interval whose stencil samples are `w`, current sample `w[offset]`
    /// (scalar evaluation, each substep count compiled on its own).
    #[inline(always)]
    pub fn motion(&self, w: &[[f64; 6]], offset: usize) -> Motion {
        self.with_moments(
            w,
            offset,
            |[b0, b1, b2]| Motion::single(magnus6(b0, b1, b2)),
            |cur, rot, vel| Motion::split(cur, rot, &vel),
        )
    }

    /// The interval's moments handed to `single` (`B_0, B_1, B_2` of one step) or to `split`
    /// (the sample, the substep rotation rows and the velocity `B_1, B_2`).
    #[inline(always)]
    fn with_moments<R>(
        &self,
        w: &[[f64; 6]],
        offset: usize,
        single: impl FnOnce([Se3; 3]) -> R,
        split: impl FnOnce(&[f64; 6], &[[f64; 3]], [[f64; 3]; 2]) -> R,
    ) -> R {
        let cur = &w[offset];
        let (t, substeps) = self.shape(w.len(), offset, is_slow(cur));
        match substeps {
            1 => {
                let [b1, b2] = moments::<2, 0, 6>(w, t, 2, 0);
                single([Se3::from6(cur), Se3::from6(&b1), Se3::from6(&b2)])
            }
            2 => split(
                cur,
                &moments::<5, 0, 3>(w, t, 7, 0),
                moments::<2, 3, 3>(w, t, 7, 5),
            ),
            3 => split(
                cur,
                &moments::<8, 0, 3>(w, t, 10, 0),
                moments::<2, 3, 3>(w, t, 10, 8),
            ),
            _ => split(
                cur,
                &moments::<11, 0, 3>(w, t, 13, 0),
                moments::<2, 3, 3>(w, t, 13, 11),
            ),
        }
    }
}

/// Rotation moment rows of the most substeps (four: `3 · 4 − 1`).
pub(super) const MAX_ROT_ROWS: usize = 11;

/// The moments of an interval taken in substeps.
#[derive(Clone, Copy, Debug)]
pub(super) struct SplitMoments {
    /// The sample `(Δθ, Δv)` (rad, m/s).
    pub cur: [f64; 6],
    /// Substep rotation moments, rows as in [`stencil_taps`]; the first `rot_rows` are used.
    pub rot: [[f64; 3]; MAX_ROT_ROWS],
    /// Rotation rows in use (`3 · substeps − 1`).
    pub rot_rows: usize,
    /// Whole-interval velocity moments `B_1, B_2` (m/s).
    pub vel: [[f64; 3]; 2],
}

/// The moments of one interval, as its Magnus steps take them.
#[derive(Clone, Copy, Debug)]
#[allow(
    clippy::large_enum_variant,
    reason = "made and consumed once per interval on the stack; a box would allocate per interval"
)]
pub(super) enum Moments {
    /// One step on se(3): `B_0` (the sample), `B_1`, `B_2`.
    Single([Se3; 3]),
    /// Substeps on so(3) and one step on se(3) for the velocity.
    Split(SplitMoments),
}

impl Moments {
    /// The interval's motion (scalar evaluation).
    #[inline(always)]
    pub fn motion(&self) -> Motion {
        match self {
            Moments::Single([b0, b1, b2]) => Motion::single(magnus6(*b0, *b1, *b2)),
            Moments::Split(m) => Motion::split(&m.cur, &m.rot[..m.rot_rows], &m.vel),
        }
    }
}
