//! The bin's forcing added to the columns' moments in AVX2 lanes: a column's three NED
//! components side by side in one vector (the fourth lane is padding), its moments in
//! registers over the bin. Every lane does the scalar code's multiplies and adds in the scalar
//! code's order ([`sins_nav::simd4`]: never fused), and the accelerometer's down component and
//! the padding lanes are never written back, so the moments are the scalar path's to the bit.
//! An effect column whose perturbations of a bin lie along one body axis takes one product per
//! sample instead of the rotation's three (see [`add_triad`]).

use super::BinSamples;
use crate::columns::{ColumnEval, ParamSlot, Triad};
use crate::model::Moments;
use pulp::f64x4;
use sins_nav::Vec3;
use sins_nav::simd4::{F4, Token, vectorize};

/// The columns `evals` (with their moments `mom`) and the bin's samples, for
/// [`vectorize`]; the effect columns' perturbations are evaluated into the bin's buffer.
pub(super) struct AddBin<'a> {
    pub(super) evals: &'a mut [ColumnEval],
    pub(super) mom: &'a mut [Moments],
    pub(super) bin: &'a mut BinSamples,
    pub(super) s: Token,
}

/// A column's moments as lanes: gyro `[N, E, D, pad]` and accelerometer `[N, E, -, pad]` for
/// each of the three moments.
struct Acc {
    g: [F4; 3],
    a: [F4; 3],
}

impl Acc {
    #[inline(always)]
    fn load(s: Token, m: &Moments) -> Self {
        let g = |f: &crate::model::Forcing| F4 {
            v: f64x4(f[0], f[1], f[2], 0.0),
            s,
        };
        let a = |f: &crate::model::Forcing| F4 {
            v: f64x4(f[3], f[4], 0.0, 0.0),
            s,
        };
        Self {
            g: [g(&m.m1), g(&m.m2), g(&m.m3)],
            a: [a(&m.m1), a(&m.m2), a(&m.m3)],
        }
    }

    #[inline(always)]
    fn store(&self, m: &mut Moments) {
        for (f, (g, a)) in [&mut m.m1, &mut m.m2, &mut m.m3]
            .into_iter()
            .zip(self.g.iter().zip(&self.a))
        {
            let f64x4(n, e, d, _) = g.v;
            let f64x4(an, ae, _, _) = a.v;
            f[0] = n;
            f[1] = e;
            f[2] = d;
            f[3] = an;
            f[4] = ae;
        }
    }
}

/// `m1 += u`, `m2 += u w`, `m3 += u w²/2` in lanes ([`Moments::add_part`]).
#[inline(always)]
fn add(m: &mut [F4; 3], u: F4, w: F4, hw2: F4) {
    m[0] = m[0] + u;
    m[1] = m[1] + u * w;
    m[2] = m[2] + u * hw2;
}

/// The bin's attitude columns, times before the bin end and `w²/2`, as lanes.
struct BinLanes<'b> {
    /// Column j of every sample's C_nb, padded to four lanes.
    cols: &'b [Vec<F4>; 3],
    /// Time of each sample before the bin end (s).
    w: &'b [F4],
    /// Half its square (s²).
    hw2: &'b [F4],
}

/// Add a coefficient column's bin to its moments `m`, its scalar of each sample in `values`.
#[inline(always)]
fn add_param(s: Token, p: &ParamSlot, m: &mut Moments, values: &[f64], b: &BinLanes<'_>) {
    let mut acc = Acc::load(s, m);
    let part = match p.triad {
        Triad::Gyro => &mut acc.g,
        Triad::Accel => &mut acc.a,
    };
    let samples = b.cols[p.row].iter().zip(values).zip(b.w.iter().zip(b.hw2));
    for ((c, &v), (&w, &hw2)) in samples {
        add(part, *c * v, w, hw2);
    }
    acc.store(m);
}

/// How one triad's perturbations of a bin spread over the body axes.
#[derive(Clone, Copy, PartialEq)]
enum Shape {
    /// Every sample's perturbation is zero: nothing to add.
    Zero,
    /// Only this axis's component is ever other than +0.0 (in bits).
    Axis(usize),
    /// Anything else.
    Full,
}

/// The shape of one triad's perturbations from the OR of each component's bits over them.
fn shape(bits: [u64; 3]) -> Shape {
    match bits.map(|b| b != 0) {
        [false, false, false] => Shape::Zero,
        [true, false, false] => Shape::Axis(0),
        [false, true, false] => Shape::Axis(1),
        [false, false, true] => Shape::Axis(2),
        _ => Shape::Full,
    }
}

/// Add one triad's perturbations (`triad` picks them out of `perturbations`) of a bin to its
/// moments `m`, resolved in NED; `shape` is theirs.
///
/// A perturbation along body axis `j` only (the others +0.0) is resolved as `c_j v_j`, with
/// the moments of the full product `(c_0 v_0 + c_1 v_1) + c_2 v_2` to the bit: adding the two
/// zero products leaves a non-zero lane as it is, and can change only the sign of a zero one;
/// that sign never reaches a moment, because a moment starts at +0.0 and a rounded sum is -0.0
/// only when both terms are, so a moment is never -0.0, and it takes +0.0 and -0.0 alike.
#[inline(always)]
fn add_triad(
    s: Token,
    m: &mut [F4; 3],
    perturbations: &[(Vec3, Vec3)],
    triad: impl Fn(&(Vec3, Vec3)) -> &Vec3,
    shape: Shape,
    b: &BinLanes<'_>,
) {
    let times = b.w.iter().zip(b.hw2);
    match shape {
        Shape::Zero => {}
        Shape::Axis(j) => {
            for ((p, c), (&w, &hw2)) in perturbations.iter().zip(&b.cols[j]).zip(times) {
                let v = triad(p)[j];
                if v != 0.0 {
                    add(m, *c * F4::splat(s, v), w, hw2);
                }
            }
        }
        Shape::Full => {
            let cols = b.cols[0].iter().zip(&b.cols[1]).zip(&b.cols[2]);
            for ((p, ((c0, c1), c2)), (&w, &hw2)) in perturbations.iter().zip(cols).zip(times) {
                let v = triad(p);
                if *v != Vec3::zeros() {
                    // nalgebra's C v: (c0 v0 + c1 v1) + c2 v2, component by component.
                    add(m, *c0 * v.x + *c1 * v.y + *c2 * v.z, w, hw2);
                }
            }
        }
    }
}

/// Add an effect column's bin (its perturbations in `bin.perturbations`) to its moments.
#[inline(always)]
fn add_effect(s: Token, m: &mut Moments, perturbations: &[(Vec3, Vec3)], b: &BinLanes<'_>) {
    let (mut g, mut a) = ([0u64; 3], [0u64; 3]);
    for (dtheta, dv) in perturbations {
        for i in 0..3 {
            g[i] |= dtheta[i].to_bits();
            a[i] |= dv[i].to_bits();
        }
    }
    let (g, a) = (shape(g), shape(a));
    let mut acc = Acc::load(s, m);
    add_triad(s, &mut acc.g, perturbations, |p| &p.0, g, b);
    add_triad(s, &mut acc.a, perturbations, |p| &p.1, a, b);
    acc.store(m);
}

impl pulp::WithSimd for AddBin<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let s = self.s;
        let bin = self.bin;
        let lanes = |x: f64| F4::splat(s, x);
        let cols: [Vec<F4>; 3] = std::array::from_fn(|j| {
            bin.c_nb
                .iter()
                .map(|c| F4 {
                    v: f64x4(c[(0, j)], c[(1, j)], c[(2, j)], 0.0),
                    s,
                })
                .collect()
        });
        let w: Vec<F4> = bin.w_s.iter().map(|&x| lanes(x)).collect();
        let hw2: Vec<F4> = bin.half_w2_s2.iter().map(|&x| lanes(x)).collect();
        let b = BinLanes {
            cols: &cols,
            w: &w,
            hw2: &hw2,
        };
        for (e, m) in self.evals.iter_mut().zip(self.mom.iter_mut()) {
            match e {
                ColumnEval::Param(p) => {
                    p.scalars(&bin.inputs, &mut bin.values);
                    add_param(s, p, m, &bin.values, &b);
                }
                ColumnEval::Effect(effect) => {
                    effect.perturbations(&bin.ctxs, &mut bin.perturbations);
                    add_effect(s, m, &bin.perturbations, &b);
                }
            }
        }
    }
}

/// Add the bin's forcing to `evals`' moments in lanes (see [`AddBin`]).
pub(super) fn add_bin(op: AddBin<'_>) {
    vectorize(op.s, op)
}
