//! Four `f64` lanes in an AVX2 vector, and 3-vectors and quaternions made of them, for
//! kernels that evaluate four independent problems side by side and must give each one the
//! scalar code's result to the bit: every operation is one IEEE multiply, add, subtract, divide
//! or square root per lane (never a fused multiply-add), so a lane computes exactly what the
//! scalar expression written in the same order computes. The lanes exist where the CPU has AVX2
//! ([`token`]); elsewhere callers take their scalar code.

use crate::{Quat, Vec3};
#[cfg(not(target_arch = "x86_64"))]
pub use portable::Token;
use pulp::f64x4;
#[cfg(target_arch = "x86_64")]
pub use pulp::x86::V3 as Token;
use std::ops::{Add, Div, Mul, Sub};

/// Lanes per vector.
pub const LANES: usize = 4;

/// The AVX2 token if this CPU has AVX2 (x86-64 only; `None` elsewhere).
pub fn token() -> Option<Token> {
    Token::try_new()
}

/// Run `op` in code compiled for AVX2 (x86-64), which the token proves the CPU has.
#[cfg(target_arch = "x86_64")]
pub fn vectorize<Op: pulp::WithSimd>(t: Token, op: Op) -> Op::Output {
    pulp::Simd::vectorize(t, op)
}

/// Elsewhere the token is never made, so this is never called.
#[cfg(not(target_arch = "x86_64"))]
pub fn vectorize<Op: pulp::WithSimd>(_t: Token, op: Op) -> Op::Output {
    op.with_simd(pulp::Scalar::new())
}

/// A stand-in for pulp's x86-64 token where there is none: `Token::try_new` always answers
/// `None`, so the callers take their scalar code; the operations exist only so that the lane
/// code compiles.
#[cfg(not(target_arch = "x86_64"))]
mod portable {
    use pulp::f64x4;

    /// No AVX2 token.
    #[derive(Clone, Copy, Debug)]
    pub struct Token;

    #[allow(
        missing_docs,
        reason = "pulp's names for the AVX2 token's operations, lane by lane; never called"
    )]
    impl Token {
        /// Never: there is no AVX2 here.
        pub fn try_new() -> Option<Self> {
            None
        }
        fn map2(a: f64x4, b: f64x4, f: impl Fn(f64, f64) -> f64) -> f64x4 {
            f64x4(f(a.0, b.0), f(a.1, b.1), f(a.2, b.2), f(a.3, b.3))
        }
        pub fn splat_f64x4(self, x: f64) -> f64x4 {
            f64x4(x, x, x, x)
        }
        pub fn add_f64x4(self, a: f64x4, b: f64x4) -> f64x4 {
            Self::map2(a, b, |x, y| x + y)
        }
        pub fn sub_f64x4(self, a: f64x4, b: f64x4) -> f64x4 {
            Self::map2(a, b, |x, y| x - y)
        }
        pub fn mul_f64x4(self, a: f64x4, b: f64x4) -> f64x4 {
            Self::map2(a, b, |x, y| x * y)
        }
        pub fn div_f64x4(self, a: f64x4, b: f64x4) -> f64x4 {
            Self::map2(a, b, |x, y| x / y)
        }
        pub fn sqrt_f64x4(self, a: f64x4) -> f64x4 {
            f64x4(a.0.sqrt(), a.1.sqrt(), a.2.sqrt(), a.3.sqrt())
        }
        pub fn cmp_lt_f64x4(self, a: f64x4, b: f64x4) -> [bool; 4] {
            [a.0 < b.0, a.1 < b.1, a.2 < b.2, a.3 < b.3]
        }
        pub fn select_f64x4(self, m: [bool; 4], a: f64x4, b: f64x4) -> f64x4 {
            let p = |m: bool, x: f64, y: f64| if m { x } else { y };
            f64x4(
                p(m[0], a.0, b.0),
                p(m[1], a.1, b.1),
                p(m[2], a.2, b.2),
                p(m[3], a.3, b.3),
            )
        }
    }
}

/// One `f64` per lane, in an AVX vector; the token proves that the CPU has AVX2.
#[derive(Clone, Copy, Debug)]
pub struct F4 {
    /// The lanes.
    pub v: f64x4,
    /// The proof that the CPU has AVX2.
    pub s: Token,
}

impl F4 {
    /// `x` in every lane.
    #[inline(always)]
    pub fn splat(s: Token, x: f64) -> Self {
        Self {
            v: s.splat_f64x4(x),
            s,
        }
    }

    /// Lane `l`.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> f64 {
        let f64x4(a, b, c, d) = self.v;
        [a, b, c, d][l]
    }

    /// Whether every lane is below `x` (false for NaN).
    #[inline(always)]
    pub fn all_below(&self, x: f64) -> bool {
        let f64x4(a, b, c, d) = self.v;
        a < x && b < x && c < x && d < x
    }

    /// Lane by lane: `a` where `self < x`, else `b`.
    #[inline(always)]
    pub fn below_select(&self, x: f64, a: F4, b: F4) -> F4 {
        let s = self.s;
        let mask = s.cmp_lt_f64x4(self.v, s.splat_f64x4(x));
        Self {
            v: s.select_f64x4(mask, a.v, b.v),
            s,
        }
    }
}

/// `impl $trait for F4` by the token's lane-by-lane `$op`.
macro_rules! lane_op {
    ($trait:ident, $f:ident, $op:ident) => {
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                F4 {
                    v: self.s.$op(self.v, o.v),
                    s: self.s,
                }
            }
        }
    };
}
lane_op!(Add, add, add_f64x4);
lane_op!(Sub, sub, sub_f64x4);
lane_op!(Mul, mul, mul_f64x4);
lane_op!(Div, div, div_f64x4);

impl Mul<f64> for F4 {
    type Output = F4;
    #[inline(always)]
    fn mul(self, a: f64) -> F4 {
        self * F4::splat(self.s, a)
    }
}

/// `Σ c_i xⁱ` by Horner's rule, from the highest power (as the reconstruction's scalar series).
#[inline(always)]
pub fn horner(x: F4, c: &[f64]) -> F4 {
    c.iter()
        .rev()
        .fold(F4::splat(x.s, 0.0), |acc, &ci| acc * x + F4::splat(x.s, ci))
}

/// A 3-vector per lane.
#[derive(Clone, Copy, Debug)]
pub struct V4 {
    /// First components.
    pub x: F4,
    /// Second components.
    pub y: F4,
    /// Third components.
    pub z: F4,
}

impl V4 {
    /// Rows `x, y, z` of lane-major storage.
    #[inline(always)]
    pub fn of(s: Token, c: &[[f64; LANES]]) -> Self {
        let f = |r: &[f64; LANES]| F4 {
            v: f64x4(r[0], r[1], r[2], r[3]),
            s,
        };
        Self {
            x: f(&c[0]),
            y: f(&c[1]),
            z: f(&c[2]),
        }
    }

    /// Zero in every lane.
    #[inline(always)]
    pub fn zeros(s: Token) -> Self {
        let z = F4::splat(s, 0.0);
        Self { x: z, y: z, z }
    }

    /// Lane `l`.
    #[inline(always)]
    pub fn lane(&self, l: usize) -> Vec3 {
        Vec3::new(self.x.lane(l), self.y.lane(l), self.z.lane(l))
    }

    /// nalgebra's `cross`, term for term.
    #[inline(always)]
    pub fn cross(&self, b: &V4) -> V4 {
        V4 {
            x: self.y * b.z - self.z * b.y,
            y: self.z * b.x - self.x * b.z,
            z: self.x * b.y - self.y * b.x,
        }
    }

    /// nalgebra's `dot` for 3-vectors: `(x·b.x + y·b.y) + z·b.z`.
    #[inline(always)]
    pub fn dot(&self, b: &V4) -> F4 {
        self.x * b.x + self.y * b.y + self.z * b.z
    }

    /// nalgebra's `norm_squared` for a 3-vector: `x² + y² + z²`, left to right.
    #[inline(always)]
    pub fn norm_squared(&self) -> F4 {
        self.dot(self)
    }

    /// Each lane's vector times that lane's scalar.
    #[inline(always)]
    pub fn scale(&self, a: F4) -> V4 {
        V4 {
            x: self.x * a,
            y: self.y * a,
            z: self.z * a,
        }
    }
}

impl Add for V4 {
    type Output = V4;
    #[inline(always)]
    fn add(self, o: V4) -> V4 {
        V4 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl Sub for V4 {
    type Output = V4;
    #[inline(always)]
    fn sub(self, o: V4) -> V4 {
        V4 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl Mul<f64> for V4 {
    type Output = V4;
    #[inline(always)]
    fn mul(self, a: f64) -> V4 {
        self.scale(F4::splat(self.x.s, a))
    }
}

/// A quaternion per lane (`w + i·x + j·y + k·z`).
#[derive(Clone, Copy, Debug)]
pub struct Q4 {
    /// Scalar parts.
    pub w: F4,
    /// `i` parts.
    pub i: F4,
    /// `j` parts.
    pub j: F4,
    /// `k` parts.
    pub k: F4,
}

impl Q4 {
    /// nalgebra's quaternion product, term for term.
    #[inline(always)]
    pub fn mul(&self, r: &Q4) -> Q4 {
        let s = self;
        Q4 {
            w: s.w * r.w - s.i * r.i - s.j * r.j - s.k * r.k,
            i: s.w * r.i + s.i * r.w + s.j * r.k - s.k * r.j,
            j: s.w * r.j - s.i * r.k + s.j * r.w + s.k * r.i,
            k: s.w * r.k + s.i * r.j - s.j * r.i + s.k * r.w,
        }
    }

    /// Lane by lane from four quaternions.
    #[inline(always)]
    pub fn of(s: Token, q: [&Quat; LANES]) -> Q4 {
        let f = |c: usize| F4 {
            v: f64x4(
                q[0].coords[c],
                q[1].coords[c],
                q[2].coords[c],
                q[3].coords[c],
            ),
            s,
        };
        // nalgebra stores `[i, j, k, w]`.
        Q4 {
            i: f(0),
            j: f(1),
            k: f(2),
            w: f(3),
        }
    }

    /// The vector parts `(i, j, k)`.
    #[inline(always)]
    pub fn vector(&self) -> V4 {
        V4 {
            x: self.i,
            y: self.j,
            z: self.k,
        }
    }

    /// nalgebra's `UnitQuaternion * Vector3`, term for term: `t = 2 (q × v)`,
    /// `t w + q × t + v`.
    #[inline(always)]
    pub fn rotate(&self, v: &V4) -> V4 {
        let t = self.vector().cross(v) * 2.0;
        let cross = self.vector().cross(&t);
        t.scale(self.w) + cross + *v
    }

    /// nalgebra's `Unit::new_normalize`: each coordinate over the norm, whose square sums the
    /// coordinates `[i, j, k, w]` as `(i² + k²) + (j² + w²)`.
    #[inline(always)]
    pub fn normalize(&self) -> Q4 {
        let s = self.w.s;
        let (a, b) = (
            self.i * self.i + self.k * self.k,
            self.j * self.j + self.w * self.w,
        );
        let n = F4 {
            v: s.sqrt_f64x4((a + b).v),
            s,
        };
        let d = |x: F4| F4 {
            v: s.div_f64x4(x.v, n.v),
            s,
        };
        Q4 {
            w: d(self.w),
            i: d(self.i),
            j: d(self.j),
            k: d(self.k),
        }
    }

    /// Lane `l`, as a unit quaternion (not normalised again).
    #[inline(always)]
    pub fn lane(&self, l: usize) -> Quat {
        Quat::new_unchecked(nalgebra::Quaternion::new(
            self.w.lane(l),
            self.i.lane(l),
            self.j.lane(l),
            self.k.lane(l),
        ))
    }
}
