//! Accelerometer nonlinearity: the quadratic term K2 f_j^2 (in the catalogue) and the cross-axis
//! coupling f_(j+1) f_(j+2) (deliberately outside it).

use super::{EffectContext, ExtraEffect};
use sins_nav::Vec3;

/// Accelerometer quadratic nonlinearity: `δf_j = K2_j f_j^2`, with `f_j` the mean specific force
/// of the sample along the accelerometer's input axis (`δdv_j = K2_j dv_j^2 / dt`).
///
/// Physics: the second-order term of a pendulous accelerometer's model equation (pendulum
/// displacement and torquer nonlinearity). Under vibration it rectifies: a zero-mean oscillating
/// specific force gives a mean bias `K2 <f^2>` (vibration rectification error). On an axis whose
/// specific force is constant (the vertical of a level IMU) it is indistinguishable from a bias.
/// Quartz accelerometers of this class: K2 below 10-20 ug/g^2.
#[derive(Clone, Copy, Debug)]
pub struct AccelQuadratic {
    /// K2 per axis (1/(m/s^2)).
    pub k2_per_mps2: Vec3,
}

impl ExtraEffect for AccelQuadratic {
    fn name(&self) -> &'static str {
        "accel_quadratic_nonlinearity"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        let v = ctx.true_dv_mps;
        for j in 0..3 {
            dv[j] += self.k2_per_mps2[j] * v[j] * v[j] / ctx.dt_s;
        }
    }
}

/// Outside the diagnosis catalogue. Accelerometer cross-axis coupling:
/// `δf_j = c_j f_(j+1) f_(j+2)` (indices mod 3: x couples f_y f_z, y couples f_z f_x, z couples
/// f_x f_y), the cross-product term K_ip f_i f_p of the pendulous accelerometer model. Kept to test
/// that the diagnosis reports "none of the catalogue explains it". Typical ~20 ug/g^2.
#[derive(Clone, Copy, Debug)]
pub struct AccelCrossCoupling {
    /// Coefficient per axis (1/(m/s^2)).
    pub coeff_per_mps2: Vec3,
}

impl ExtraEffect for AccelCrossCoupling {
    fn name(&self) -> &'static str {
        "accel_cross_coupling"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        let v = ctx.true_dv_mps;
        for j in 0..3 {
            dv[j] += self.coeff_per_mps2[j] * v[(j + 1) % 3] * v[(j + 2) % 3] / ctx.dt_s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::{G0_MPS2, UG};

    const UG_PER_G2: f64 = UG / (G0_MPS2 * G0_MPS2);

    fn with_force(f: Vec3, h: f64) -> EffectContext {
        let mut c = EffectContext::at_rest(1.0, h, [20.0; 3]);
        c.true_dv_mps = f * h;
        c.prev_true_dv_mps = c.true_dv_mps;
        c
    }

    #[test]
    fn quadratic_term_gives_k2_g2_at_one_g_and_rectifies_vibration() {
        let h = 0.005;
        let mut e = AccelQuadratic {
            k2_per_mps2: Vec3::new(10.0, 0.0, 20.0) * UG_PER_G2,
        };
        // Level: +1 g on z -> 20 ug on z; +-1 g on x -> +10 ug on x either way (even in f).
        let (_, dv) = e.perturbation(&with_force(Vec3::new(0.0, 0.0, G0_MPS2), h));
        assert!((dv.z / h - 20.0 * UG).abs() < 1e-15 * UG);
        for s in [1.0, -1.0] {
            let (_, dv) = e.perturbation(&with_force(Vec3::new(s * G0_MPS2, 0.0, 0.0), h));
            assert!((dv.x / h - 10.0 * UG).abs() < 1e-15 * UG);
        }
        // A zero-mean sinusoidal 2 g vibration on x, sampled at 200 Hz with 8 samples per period:
        // mean error K2 <f^2> = K2 A^2/2 = 20 ug, although the mean force is zero.
        let n = 8000;
        let a = 2.0 * G0_MPS2;
        let mut sum = 0.0;
        for k in 0..n {
            let phase = 2.0 * std::f64::consts::PI * k as f64 / 8.0 + 0.3;
            let (_, dv) = e.perturbation(&with_force(Vec3::new(a * phase.sin(), 0.0, 0.0), h));
            sum += dv.x;
        }
        let mean = sum / (n as f64 * h);
        assert!((mean - 20.0 * UG).abs() < 1e-9 * UG, "{}", mean / UG);
    }

    #[test]
    fn cross_coupling_needs_two_axes_loaded() {
        let h = 0.005;
        let mut e = AccelCrossCoupling {
            coeff_per_mps2: Vec3::new(0.0, 0.0, 20.0) * UG_PER_G2,
        };
        // Level (f on z only) or f on x only: nothing on z.
        for f in [Vec3::new(0.0, 0.0, G0_MPS2), Vec3::new(G0_MPS2, 0.0, 0.0)] {
            assert_eq!(e.perturbation(&with_force(f, h)).1, Vec3::zeros());
        }
        // Tilted 45 deg about z... in x-y: f_x = f_y = g/sqrt2 -> 20 ug * 1/2 = 10 ug on z.
        let s = G0_MPS2 / 2f64.sqrt();
        let (_, dv) = e.perturbation(&with_force(Vec3::new(s, s, 0.0), h));
        assert!((dv.z / h - 10.0 * UG).abs() < 1e-13 * UG);
        assert_eq!((dv.x, dv.y), (0.0, 0.0));
    }
}
