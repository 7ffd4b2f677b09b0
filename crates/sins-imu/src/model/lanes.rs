//! Compensation of four samples side by side, one per lane of the AVX2 vectors of
//! `sins_nav::simd4`. Every lane performs the scalar code's operations in the scalar code's
//! order (nalgebra's matrix-vector product, cross and dot products, term for term; separate
//! multiplies and adds), so each increment is the one [`Compensator::dtheta_rad`] and
//! [`Compensator::dv_mps`] give, to the bit. Without AVX2, and for the last samples of a batch
//! that do not fill four lanes, the scalar code runs.

use super::Compensator;
use crate::sample::ImuSample;
use pulp::f64x4;
use sins_nav::simd4::{self, F4, LANES, Token, V4};
use sins_nav::{Increment, Mat3, Vec3};

impl Compensator {
    /// Append to `out` the compensated increments of `samples`, sample `i` over `dt_s[i]`
    /// seconds (rad and m/s): each equal to the bit to [`Compensator::dtheta_rad`] and
    /// [`Compensator::dv_mps`] of that sample, in four lanes where the CPU has AVX2. Takes
    /// `min(samples.len(), dt_s.len())` samples. The caller checks the temperatures first (a
    /// reading that is not finite gives a compensated increment that is not finite).
    pub fn compensate_into(&self, samples: &[ImuSample], dt_s: &[f64], out: &mut Vec<Increment>) {
        let n = samples.len().min(dt_s.len());
        out.reserve(n);
        let mut done = 0;
        if let Some(s) = simd4::token() {
            simd4::vectorize(
                s,
                Quads {
                    comp: self,
                    samples: &samples[..n],
                    dt_s: &dt_s[..n],
                    out,
                    s,
                },
            );
            done = n - n % LANES;
        }
        for (x, &h) in samples[done..n].iter().zip(&dt_s[done..n]) {
            out.push(Increment {
                dtheta_rad: self.dtheta_rad(&x.dtheta_rad, h),
                dv_mps: self.dv_mps(&x.dv_mps, h, &x.temp_degc),
            });
        }
    }
}

/// The whole quads of a batch, for [`Compensator::compensate_into`].
struct Quads<'a> {
    comp: &'a Compensator,
    samples: &'a [ImuSample],
    dt_s: &'a [f64],
    out: &'a mut Vec<Increment>,
    s: Token,
}

impl pulp::WithSimd for Quads<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let s = self.s;
        let (quads, _) = self.samples.as_chunks::<LANES>();
        let (hs, _) = self.dt_s.as_chunks::<LANES>();
        for (q, h) in quads.iter().zip(hs) {
            let lanes = |f: &dyn Fn(&ImuSample) -> f64| F4 {
                v: f64x4(f(&q[0]), f(&q[1]), f(&q[2]), f(&q[3])),
                s,
            };
            let v4 = |f: &dyn Fn(&ImuSample) -> &Vec3| V4 {
                x: lanes(&|x| f(x).x),
                y: lanes(&|x| f(x).y),
                z: lanes(&|x| f(x).z),
            };
            let dt = F4 {
                v: f64x4(h[0], h[1], h[2], h[3]),
                s,
            };
            let dtheta = mat_vec(
                &self.comp.gyro_inverse,
                &(v4(&|x| &x.dtheta_rad) - splat3(s, &self.comp.params.gyro.bias_radps).scale(dt)),
            );
            let raw_dv = v4(&|x| &x.dv_mps);
            let dv = match &self.comp.accel_inverse_const {
                Some(inv) => mat_vec(
                    inv,
                    &(raw_dv - splat3(s, &self.comp.params.accel.bias_mps2).scale(dt)),
                ),
                None => {
                    let temp = [0, 1, 2].map(|j| lanes(&|x| x.temp_degc[j]));
                    self.comp.dv_with_temperature(s, &raw_dv, dt, &temp)
                }
            };
            for l in 0..LANES {
                self.out.push(Increment {
                    dtheta_rad: dtheta.lane(l),
                    dv_mps: dv.lane(l),
                });
            }
        }
    }
}

impl Compensator {
    /// [`Compensator::dv_mps`]'s temperature branch in four lanes: the error matrix and bias
    /// at the lanes' temperature offsets, then Cramer's rule as `solve3`.
    #[inline(always)]
    fn dv_with_temperature(&self, s: Token, raw_dv: &V4, dt: F4, temp: &[F4; 3]) -> V4 {
        let p = &self.params;
        let c = |x: f64| F4::splat(s, x);
        let r = c(p.reference_temperature_degc);
        let [dx, dy, dz] = [temp[0] - r, temp[1] - r, temp[2] - r];
        let (a, t) = (&p.accel, &p.temperature);
        let [yx, zx, xy, zy, xz, yz] = a.misalignment_rad.map(c);
        let [tyx, tzx, txy, tzy, txz, tyz] = t.misalignment_rad_per_degc.map(c);
        let (sc, ts) = (splat3(s, &a.scale), splat3(s, &t.scale_per_degc));
        // `Mat3::identity() + E`, column by column: one on the diagonal, zero elsewhere.
        let (one, zero) = (c(1.0), c(0.0));
        let c0 = V4 {
            x: one + (sc.x + ts.x * dx),
            y: zero + (yx + tyx * dx),
            z: zero + (zx + tzx * dx),
        };
        let c1 = V4 {
            x: zero + (xy + txy * dy),
            y: one + (sc.y + ts.y * dy),
            z: zero + (zy + tzy * dy),
        };
        let c2 = V4 {
            x: zero + (xz + txz * dz),
            y: zero + (yz + tyz * dz),
            z: one + (sc.z + ts.z * dz),
        };
        let (b0, tb) = (splat3(s, &a.bias_mps2), splat3(s, &t.bias_mps2_per_degc));
        let bias = V4 {
            x: b0.x + tb.x * dx,
            y: b0.y + tb.y * dy,
            z: b0.z + tb.z * dz,
        };
        let b = *raw_dv - bias.scale(dt);
        let c12 = c1.cross(&c2);
        let inv_det = one / c0.dot(&c12);
        V4 {
            x: b.dot(&c12),
            y: c0.dot(&b.cross(&c2)),
            z: c0.dot(&c1.cross(&b)),
        }
        .scale(inv_det)
    }
}

/// `v` in every lane.
#[inline(always)]
fn splat3(s: Token, v: &Vec3) -> V4 {
    V4 {
        x: F4::splat(s, v.x),
        y: F4::splat(s, v.y),
        z: F4::splat(s, v.z),
    }
}

/// nalgebra's `Mat3 * Vec3` (column by column: `(m₀₀v₀ + m₀₁v₁) + m₀₂v₂`, ...) in each lane.
#[inline(always)]
fn mat_vec(m: &Mat3, v: &V4) -> V4 {
    let s = v.x.s;
    let row = |i: usize| {
        let e = |j: usize| F4::splat(s, m[(i, j)]);
        e(0) * v.x + e(1) * v.y + e(2) * v.z
    };
    V4 {
        x: row(0),
        y: row(1),
        z: row(2),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tests::ten_times_paper;
    use crate::params::ParamModel;
    use rand_chacha::ChaCha8Rng;
    use rand_core::{Rng, SeedableRng};

    /// A uniform draw in `[-1, 1)`.
    fn unit(rng: &mut ChaCha8Rng) -> f64 {
        (rng.next_u64() >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// Random samples: rates to 2 rad/s and specific forces to 30 m/s² over 1-10 ms, and
    /// temperatures from -40 to 80 degC (vibration and a thermal chamber's range).
    fn samples(n: usize, seed: u64) -> (Vec<ImuSample>, Vec<f64>) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut v = |scale: f64| Vec3::new(unit(&mut rng), unit(&mut rng), unit(&mut rng)) * scale;
        let mut xs = Vec::with_capacity(n);
        let mut hs = Vec::with_capacity(n);
        for i in 0..n {
            let h = 0.0055 + 0.0045 * v(1.0).x;
            let (dth, dv, t) = (v(2.0 * h), v(30.0 * h), v(60.0));
            xs.push(ImuSample {
                t_s: i as f64 * h,
                dtheta_rad: dth,
                dv_mps: dv,
                temp_degc: [20.0 + t.x, 20.0 + t.y, 20.0 + t.z],
            });
            hs.push(h);
        }
        (xs, hs)
    }

    /// The lanes give each sample's scalar compensation to the bit, for both parameter
    /// models, at ten times the paper's magnitudes, including a batch length that leaves a
    /// scalar tail.
    #[test]
    fn lanes_equal_the_scalar_compensation_to_the_bit() {
        for model in [ParamModel::States42, ParamModel::States30] {
            let mut p = ten_times_paper();
            p.model = model;
            let comp = Compensator::new(p).unwrap();
            let (xs, hs) = samples(100_003, 7);
            let mut out = Vec::new();
            comp.compensate_into(&xs, &hs, &mut out);
            assert_eq!(out.len(), xs.len());
            let mut differ = 0;
            for ((x, &h), inc) in xs.iter().zip(&hs).zip(&out) {
                let dth = comp.dtheta_rad(&x.dtheta_rad, h);
                let dv = comp.dv_mps(&x.dv_mps, h, &x.temp_degc);
                let bits = |v: &Vec3| v.map(f64::to_bits);
                if bits(&dth) != bits(&inc.dtheta_rad) || bits(&dv) != bits(&inc.dv_mps) {
                    differ += 1;
                }
            }
            assert_eq!(differ, 0, "{model:?}: {differ} samples differ");
            // The temperature terms matter here: a 42-state set compensates differently.
            if model == ParamModel::States42 {
                let x = &xs[0];
                let cold = ImuSample {
                    temp_degc: [20.0; 3],
                    ..*x
                };
                let mut one = Vec::new();
                comp.compensate_into(&[cold; 4], &[hs[0]; 4], &mut one);
                assert_ne!(one[0].dv_mps, out[0].dv_mps);
            }
        }
    }
}
