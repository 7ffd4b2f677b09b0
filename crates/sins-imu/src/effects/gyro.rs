//! Gyro terms beyond eq (2): scale-factor asymmetry and g-sensitivity.

use super::{EffectContext, ExtraEffect};
use sins_nav::Vec3;

/// Gyro scale-factor asymmetry: the scale factor differs for positive and negative rates,
/// `(1 + a_j)` for ω_j > 0 and `(1 - a_j)` for ω_j < 0 on top of eq (2), i.e.
/// `δdθ_j = a_j |dθ_j|` per sample.
///
/// Physics: in a ring-laser gyro the lock-in and dither compensation and the readout are not
/// perfectly symmetric in the two senses of rotation; 1-5 ppm for this class. A symmetric
/// calibration (±θ pairs) sees apparent scale factors `+a` and `-a` whose mean vanishes, so it
/// never shows in the paper's scale-factor estimate, yet every ±θ pair leaves `2 a θ` of net angle,
/// and an oscillating rate leaves a drift `a <|ω_j|>` (vibration rectification).
#[derive(Clone, Copy, Debug)]
pub struct GyroScaleAsymmetry {
    /// Asymmetry per axis (dimensionless).
    pub asymmetry: Vec3,
}

impl ExtraEffect for GyroScaleAsymmetry {
    fn name(&self) -> &'static str {
        "gyro_scale_asymmetry"
    }
    fn apply(&mut self, ctx: &EffectContext, dtheta: &mut Vec3, _dv: &mut Vec3) {
        for j in 0..3 {
            dtheta[j] += self.asymmetry[j] * ctx.true_dtheta_rad[j].abs();
        }
    }
}

/// Gyro g-sensitivity: `δω_j = G_j f_j` (diagonal: each gyro sensitive to the specific force along
/// its own input axis), `δdθ_j = G_j dv_j` per sample.
///
/// Physics: acceleration-dependent bias from mechanical deformation of the cavity / mounting (for
/// mechanical gyros the mass unbalance). Laser gyros are nearly g-insensitive: ~0.001 deg/h/g.
/// On a level IMU it adds `G_z g` to the vertical gyro, indistinguishable from its bias; it
/// separates only when the orientation changes.
#[derive(Clone, Copy, Debug)]
pub struct GyroGSensitivity {
    /// Coefficient per axis (rad/s per m/s^2).
    pub coeff_radps_per_mps2: Vec3,
}

impl ExtraEffect for GyroGSensitivity {
    fn name(&self) -> &'static str {
        "gyro_g_sensitivity"
    }
    fn apply(&mut self, ctx: &EffectContext, dtheta: &mut Vec3, _dv: &mut Vec3) {
        *dtheta += self.coeff_radps_per_mps2.component_mul(&ctx.true_dv_mps);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::{DEG_PER_H, G0_MPS2};

    #[test]
    fn asymmetry_cancels_in_the_mean_scale_factor_but_not_in_the_net_angle() {
        let a = 3e-6;
        let mut e = GyroScaleAsymmetry {
            asymmetry: Vec3::new(0.0, 0.0, a),
        };
        let h = 0.005;
        // +90 deg then -90 deg about z at 10 deg/s: 900 samples each.
        let dth = 10f64.to_radians() * h;
        let (mut err_pos, mut err_neg) = (0.0, 0.0);
        let mut ctx = EffectContext::at_rest(0.0, h, [20.0; 3]);
        for k in 0..1800 {
            let s = if k < 900 { 1.0 } else { -1.0 };
            ctx.true_dtheta_rad = Vec3::new(0.0, 0.0, s * dth);
            let (d, _) = e.perturbation(&ctx);
            if k < 900 {
                err_pos += d.z
            } else {
                err_neg += d.z
            }
        }
        let theta = 900.0 * dth;
        // Apparent scale-factor errors of the two legs: +a and -a, mean zero.
        let (k_pos, k_neg) = (err_pos / theta, err_neg / -theta);
        assert!((k_pos - a).abs() < 1e-18 && (k_neg + a).abs() < 1e-18);
        assert!((k_pos + k_neg).abs() < 1e-20);
        // Net angle after the symmetric pair: 2 a theta, not zero.
        assert!((err_pos + err_neg - 2.0 * a * theta).abs() < 1e-18);
    }

    #[test]
    fn g_sensitivity_on_a_level_imu_loads_the_vertical_gyro() {
        let g = 0.001 * DEG_PER_H / G0_MPS2;
        let mut e = GyroGSensitivity {
            coeff_radps_per_mps2: Vec3::new(g, 2.0 * g, 3.0 * g),
        };
        let h = 0.005;
        let mut ctx = EffectContext::at_rest(0.0, h, [20.0; 3]);
        // Level, z up: f = (0, 0, +g).
        ctx.true_dv_mps = Vec3::new(0.0, 0.0, G0_MPS2 * h);
        let (d, dv) = e.perturbation(&ctx);
        assert_eq!(dv, Vec3::zeros());
        assert_eq!((d.x, d.y), (0.0, 0.0));
        assert!((d.z / h - 0.003 * DEG_PER_H).abs() < 1e-15 * DEG_PER_H);
        // Upside down: the sign flips.
        ctx.true_dv_mps = -ctx.true_dv_mps;
        assert!((e.perturbation(&ctx).0.z / h + 0.003 * DEG_PER_H).abs() < 1e-15 * DEG_PER_H);
    }
}
