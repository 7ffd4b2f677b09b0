//! Numerical kernel of the reconstruction: the sixth-order Magnus step on so(3) and se(3), the
//! SE(3) exponential and products.

use crate::{Quat, Vec3};

/// An element `(ω, f)` of the Lie algebra se(3): rotation part (rad) and translation part (m/s).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Se3 {
    pub w: Vec3,
    pub v: Vec3,
}

/// The operations of a Lie algebra that the Magnus step needs.
pub(super) trait Lie: Copy {
    /// `a·self + b·o`.
    fn lin(self, a: f64, o: Self, b: f64) -> Self;
    /// Lie bracket for right multiplication (`Ẏ = Y A`): the matrix commutator `[Y, X]`.
    fn br(self, y: Self) -> Self;
}

impl Lie for Vec3 {
    #[inline(always)]
    fn lin(self, a: f64, o: Self, b: f64) -> Self {
        self * a + o * b
    }
    #[inline(always)]
    fn br(self, y: Self) -> Self {
        y.cross(&self)
    }
}

impl Lie for Se3 {
    #[inline(always)]
    fn lin(self, a: f64, o: Se3, b: f64) -> Se3 {
        Se3 {
            w: self.w * a + o.w * b,
            v: self.v * a + o.v * b,
        }
    }
    /// `(y.w × x.w, y.w × x.v − x.w × y.v)`.
    #[inline(always)]
    fn br(self, y: Se3) -> Se3 {
        Se3 {
            w: y.w.cross(&self.w),
            v: y.w.cross(&self.v) - self.w.cross(&y.v),
        }
    }
}

impl Se3 {
    #[inline(always)]
    pub fn from6(x: &[f64; 6]) -> Self {
        Se3 {
            w: Vec3::new(x[0], x[1], x[2]),
            v: Vec3::new(x[3], x[4], x[5]),
        }
    }
}

/// Sixth-order Magnus step (Blanes–Casas–Ros 2000) from the moments `B_0, B_1, B_2` of the
/// step: with `α1 = 9/4 B0 − 15 B2`, `α2 = 12 B1`, `α3 = −15 B0 + 180 B2`, `C1 = [α1, α2]`,
/// `C2 = −[α1, 2α3 + C1]/60`, `Ω = α1 + α3/12 + [−20α1 − α3 + C1, α2 + C2]/240`. Rewritten
/// with `u = α1`, `D = [u, B1]`, `E = [u, 8/3 B2 + D/5]` (so `C1 = 12 D`, `C2 = −E`) as
/// `Ω = B0 + 3/5 [D − 10/9 u − 20/3 B2, B1 − E/12]`, which uses `[u, u] = 0`.
#[inline(always)]
pub(super) fn magnus6<L: Lie>(b0: L, b1: L, b2: L) -> L {
    let u = b0.lin(9.0 / 4.0, b2, -15.0);
    let d = u.br(b1);
    let e = u.br(b2.lin(8.0 / 3.0, d, 1.0 / 5.0));
    let p = d.lin(1.0, u.lin(-10.0 / 9.0, b2, -20.0 / 3.0), 1.0);
    let q = b1.lin(1.0, e, -1.0 / 12.0);
    // α1 + α3/12 = B0 exactly: add B0 itself so that the first-order term is unrounded.
    b0.lin(1.0, p.br(q), 3.0 / 5.0)
}

/// `Σ c_i xⁱ` by Horner's rule.
#[inline(always)]
pub(super) fn horner(x: f64, c: &[f64]) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * x + ci)
}

/// Series of `(1 − cos θ)/θ²` in `θ²`; its first four terms below [`JAC_SHORT_BELOW`].
pub(super) const JAC_A: [f64; 6] = [
    1.0 / 2.0,
    -1.0 / 24.0,
    1.0 / 720.0,
    -1.0 / 40320.0,
    1.0 / 3628800.0,
    -1.0 / 479001600.0,
];
/// Series of `(θ − sin θ)/θ³` in `θ²`; its first four terms below [`JAC_SHORT_BELOW`].
pub(super) const JAC_B: [f64; 6] = [
    1.0 / 6.0,
    -1.0 / 120.0,
    1.0 / 5040.0,
    -1.0 / 362880.0,
    1.0 / 39916800.0,
    -1.0 / 6227020800.0,
];
/// `θ²` (rad²) below which four terms of the Jacobian's series suffice (truncation below 1e-19
/// relative: substeps and single intervals).
pub(super) const JAC_SHORT_BELOW: f64 = 1e-3;
/// `θ²` (rad²) below which the Jacobian takes its series (six terms).
pub(super) const JAC_SERIES_BELOW: f64 = 0.04;

/// `J(φ) ρ` with the left Jacobian `J = I + (1 − cos θ)/θ² [φ×] + (θ − sin θ)/θ³ [φ×]²`: the
/// translation part of `exp((φ, ρ))`.
#[inline(always)]
pub(super) fn left_jacobian_times(phi: &Vec3, rho: &Vec3) -> Vec3 {
    let t2 = phi.norm_squared();
    let (a, b) = if t2 < JAC_SHORT_BELOW {
        (horner(t2, &JAC_A[..4]), horner(t2, &JAC_B[..4]))
    } else if t2 < JAC_SERIES_BELOW {
        (horner(t2, &JAC_A), horner(t2, &JAC_B))
    } else {
        let t = t2.sqrt();
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    let pr = phi.cross(rho);
    rho + pr * a + phi.cross(&pr) * b
}

/// Series of `cos(θ/2)` in `x = θ²/4`; its first four terms below [`EXP_SHORT_BELOW`].
pub(super) const EXP_C: [f64; 6] = [
    1.0,
    -1.0 / 2.0,
    1.0 / 24.0,
    -1.0 / 720.0,
    1.0 / 40320.0,
    -1.0 / 3628800.0,
];
/// Series of `sin(θ/2)/θ` in `x = θ²/4`; its first four terms below [`EXP_SHORT_BELOW`].
pub(super) const EXP_S: [f64; 6] = [
    1.0 / 2.0,
    -1.0 / 12.0,
    1.0 / 240.0,
    -1.0 / 10080.0,
    1.0 / 725760.0,
    -1.0 / 79833600.0,
];
/// `x = θ²/4` below which four terms suffice (truncation below 1e-19, θ < 0.035 rad).
pub(super) const EXP_SHORT_BELOW: f64 = 3e-4;
/// `x` below which the exponential takes its series (six terms; truncation below 1e-20,
/// θ < 0.2 rad).
pub(super) const EXP_SERIES_BELOW: f64 = 0.01;

/// Unit quaternion of a rotation vector, by series for small angles.
#[inline(always)]
pub(super) fn quat_exp(phi: &Vec3) -> Quat {
    let x = 0.25 * phi.norm_squared();
    let (c, s) = if x < EXP_SHORT_BELOW {
        (horner(x, &EXP_C[..4]), horner(x, &EXP_S[..4]))
    } else if x < EXP_SERIES_BELOW {
        (horner(x, &EXP_C), horner(x, &EXP_S))
    } else {
        let h = x.sqrt();
        (h.cos(), h.sin() / (2.0 * h))
    };
    Quat::new_unchecked(nalgebra::Quaternion::new(
        c,
        s * phi.x,
        s * phi.y,
        s * phi.z,
    ))
}

/// Series of `2 asin(s)/s / 2` in `s²`, for angles below 0.2 rad (truncation below 1e-19
/// relative).
pub(super) const LOG_C: [f64; 9] = [
    1.0,
    1.0 / 6.0,
    3.0 / 40.0,
    5.0 / 112.0,
    35.0 / 1152.0,
    63.0 / 2816.0,
    231.0 / 13312.0,
    143.0 / 10240.0,
    6435.0 / 557056.0,
];
/// `s²` (the squared vector part) below which the logarithm takes its series.
pub(super) const LOG_SERIES_BELOW: f64 = 0.01;

/// Rotation vector of a unit quaternion with a non-negative scalar part.
#[inline(always)]
fn quat_log(q: &Quat) -> Vec3 {
    let (w, v) = (q.w, q.imag());
    let s2 = v.norm_squared();
    let f = if s2 < LOG_SERIES_BELOW {
        2.0 * horner(s2, &LOG_C)
    } else {
        let s = s2.sqrt();
        2.0 * s.atan2(w) / s
    };
    v * f
}

/// The motion over one sample interval, `exp(Ω)` in SE(3), in the form the [`Product`] takes it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Motion {
    /// Rotation vector (rad) of a single-step interval (zero for a split one).
    pub phi: Vec3,
    /// The rotation as a quaternion (unit to rounding).
    pub q: Quat,
    /// Translation `J(φ) ρ` (m/s).
    pub dv: Vec3,
    /// Whether the rotation came from substeps (then only `q` describes it).
    pub split: bool,
}

impl Motion {
    /// `exp(om)` of a single Magnus step (or a constant-rate sample).
    #[inline(always)]
    pub fn single(om: Se3) -> Self {
        Self {
            phi: om.w,
            q: quat_exp(&om.w),
            dv: left_jacobian_times(&om.w, &om.v),
            split: false,
        }
    }

    /// The interval of sample `cur` from its substep rotation moments `rot` (rows as in
    /// `taps::stencil_taps`) and whole-interval velocity moments `vel` (`B_1, B_2`): the
    /// rotation is the product of the substeps' sixth-order Magnus steps on so(3); the velocity
    /// increment comes from one sixth-order step on se(3) over the whole interval, whose
    /// rotation moments are combined from the substep ones (its error, below 1e-3 ug under
    /// Table 4 pattern 3, is negligible).
    #[inline(always)]
    pub fn split(cur: &[f64; 6], rot: &[[f64; 3]], vel: &[[f64; 3]; 2]) -> Self {
        let n = rot.len().div_ceil(3);
        let sigma = 1.0 / n as f64;
        let v3 = |x: &[f64; 3]| Vec3::new(x[0], x[1], x[2]);
        let whole = Se3::from6(cur);
        let (mut rest, mut w1, mut w2) = (whole.w, Vec3::zeros(), Vec3::zeros());
        let mut q = Quat::identity();
        for s in 0..n {
            let r = &rot[3 * s..];
            // The last substep's B_0 is what the others leave of the sample.
            let (b0, b1, b2) = match s + 1 < n {
                true => (v3(&r[0]), v3(&r[1]), v3(&r[2])),
                false => (rest, v3(&r[0]), v3(&r[1])),
            };
            rest -= b0;
            let d = (s as f64 + 0.5) * sigma - 0.5;
            w1 += b1 * sigma + b0 * d;
            w2 += b2 * (sigma * sigma) + b1 * (2.0 * sigma * d) + b0 * (d * d);
            let e = quat_exp(&magnus6(b0, b1, b2)).into_inner();
            q = Quat::new_unchecked(if s == 0 { e } else { q.into_inner() * e });
        }
        let om = magnus6(
            whole,
            Se3 {
                w: w1,
                v: v3(&vel[0]),
            },
            Se3 {
                w: w2,
                v: v3(&vel[1]),
            },
        );
        Self {
            phi: Vec3::zeros(),
            q,
            dv: left_jacobian_times(&om.w, &om.v),
            split: true,
        }
    }
}

/// A product of SE(3) exponentials `exp(Ω_1) exp(Ω_2) …` (right multiplication): the rotation
/// `C` and the translation `ΔV` (m/s). A single factor is kept as its exact rotation vector.
#[derive(Clone, Copy, Debug)]
pub(super) struct Product {
    steps: usize,
    phi: Vec3,
    /// `exp(phi)`, needed once a second factor comes.
    phi_q: Quat,
    q: Quat,
    dv: Vec3,
}

impl Product {
    /// The identity.
    pub fn new() -> Self {
        Self {
            steps: 0,
            phi: Vec3::zeros(),
            phi_q: Quat::identity(),
            q: Quat::identity(),
            dv: Vec3::zeros(),
        }
    }

    /// Right-multiply by the motion `m`.
    #[inline(always)]
    pub fn apply(&mut self, m: &Motion) {
        match self.steps {
            0 if !m.split => (self.phi, self.phi_q, self.dv) = (m.phi, m.q, m.dv),
            0 => (self.q, self.dv) = (m.q, m.dv),
            _ => {
                if self.steps == 1 {
                    self.q = self.phi_q;
                }
                self.dv += self.q * m.dv;
                // Unit to rounding; normalised once in `finish`.
                self.q = Quat::new_unchecked(self.q.into_inner() * m.q.into_inner());
            }
        }
        // A split factor is a quaternion at once, not a single rotation vector.
        self.steps = match m.split {
            true => self.steps.max(1) + 1,
            false => self.steps + 1,
        };
    }

    /// The rotation vector (rad) and translation (m/s) of the product.
    pub fn finish(&self) -> (Vec3, Vec3) {
        match self.steps {
            0 | 1 => (self.phi, self.dv),
            _ => (quat_log(&Quat::new_normalize(self.q.into_inner())), self.dv),
        }
    }
}

/// The exact motion of `intervals` intervals at the constant rate and specific force of the
/// sample `x`: `φ = n Δθ`, `ΔV = J(φ) n Δv` (rad, m/s).
pub(super) fn constant_rate(x: &[f64; 6], intervals: usize) -> (Vec3, Vec3) {
    let s = Se3::from6(x).lin(intervals as f64, Se3::default(), 0.0);
    (s.w, left_jacobian_times(&s.w, &s.v))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The textbook form of the sixth-order step.
    fn magnus6_reference(b0: Se3, b1: Se3, b2: Se3) -> Se3 {
        let a1 = b0.lin(9.0 / 4.0, b2, -15.0);
        let a2 = b1.lin(12.0, b1, 0.0);
        let a3 = b0.lin(-15.0, b2, 180.0);
        let c1 = a1.br(a2);
        let c2 = a1.br(a3.lin(2.0, c1, 1.0)).lin(-1.0 / 60.0, c1, 0.0);
        let t = a1
            .lin(-20.0, a3, -1.0)
            .lin(1.0, c1, 1.0)
            .br(a2.lin(1.0, c2, 1.0));
        a1.lin(1.0, a3, 1.0 / 12.0).lin(1.0, t, 1.0 / 240.0)
    }

    #[test]
    fn rewritten_magnus6_matches_the_textbook_form() {
        let v = |a: f64, b: f64, c: f64| Vec3::new(a, b, c);
        let b0 = Se3 {
            w: v(0.03, -0.02, 0.05),
            v: v(0.01, 0.02, 0.049),
        };
        let b1 = Se3 {
            w: v(0.002, 0.004, -0.003),
            v: v(-0.001, 0.0005, 0.002),
        };
        let b2 = Se3 {
            w: v(0.0029, -0.0012, 0.0041),
            v: v(0.0011, -0.0003, 0.0042),
        };
        let (x, y) = (magnus6(b0, b1, b2), magnus6_reference(b0, b1, b2));
        assert!((x.w - y.w).norm() < 4e-17 && (x.v - y.v).norm() < 4e-17);
        assert!((x.w - b0.w).norm() > 1e-6);
    }

    #[test]
    fn series_match_closed_forms() {
        for t in [0.01, 0.031, 0.0317, 0.0347, 0.035, 0.1, 0.19, 0.21, 0.5] {
            let phi = Vec3::new(0.3, -0.5, 0.8).normalize() * t;
            let q = quat_exp(&phi);
            let exact = Quat::from_scaled_axis(phi);
            assert!((q.coords - exact.coords).norm() < 2e-17, "{t}");
            assert!((quat_log(&exact) - phi).norm() < 2e-16 * t, "{t}");
            let rho = Vec3::new(0.1, 0.2, -9.8);
            let (c, s) = (t.cos(), t.sin());
            let k = phi / t;
            let j = rho + (1.0 - c) / t * k.cross(&rho) + (t - s) / t * k.cross(&k.cross(&rho));
            assert!((left_jacobian_times(&phi, &rho) - j).norm() < 1e-14, "{t}");
        }
    }
}
