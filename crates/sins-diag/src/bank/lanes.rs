//! The bin's forcing added to the columns' moments in AVX2 lanes: a column's three NED
//! components side by side in one vector (the fourth lane is padding), its moments in
//! registers over the bin. Every lane does the scalar code's multiplies and adds in the scalar
//! code's order ([`sins_nav::simd4`]: never fused), and the accelerometer's down component and
//! the padding lanes are never written back, so the moments are the scalar path's to the bit.

use super::BinSamples;
use crate::columns::{ColumnEval, Triad};
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

impl pulp::WithSimd for AddBin<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let s = self.s;
        let bin = self.bin;
        let lanes = |x: f64| F4::splat(s, x);
        // Column j of every sample's C_nb, padded to four lanes.
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
        for (e, m) in self.evals.iter_mut().zip(self.mom.iter_mut()) {
            let mut acc = Acc::load(s, m);
            match e {
                ColumnEval::Param(p) => {
                    let part = match p.triad {
                        Triad::Gyro => &mut acc.g,
                        Triad::Accel => &mut acc.a,
                    };
                    p.scalars(&bin.inputs, &mut bin.values);
                    let col = &cols[p.row];
                    for (((c, &v), &w), &hw2) in col.iter().zip(&bin.values).zip(&w).zip(&hw2) {
                        add(part, *c * v, w, hw2);
                    }
                }
                ColumnEval::Effect(effect) => {
                    effect.perturbations(&bin.ctxs, &mut bin.perturbations);
                    let samples = bin.perturbations.iter().zip(&w).zip(&hw2);
                    for (k, (((dtheta, dv), &w), &hw2)) in samples.enumerate() {
                        let c = [cols[0][k], cols[1][k], cols[2][k]];
                        // nalgebra's C v: (c0 v0 + c1 v1) + c2 v2, component by component.
                        let rotate = |v: &Vec3| c[0] * v.x + c[1] * v.y + c[2] * v.z;
                        if *dtheta != Vec3::zeros() {
                            add(&mut acc.g, rotate(dtheta), w, hw2);
                        }
                        if *dv != Vec3::zeros() {
                            add(&mut acc.a, rotate(dv), w, hw2);
                        }
                    }
                }
            }
            acc.store(m);
        }
    }
}

/// Add the bin's forcing to `evals`' moments in lanes (see [`AddBin`]).
pub(super) fn add_bin(op: AddBin<'_>) {
    vectorize(op.s, op)
}
