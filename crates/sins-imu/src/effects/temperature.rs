//! Temperature terms the paper's eq (1) leaves out: the second-order accelerometer bias
//! coefficient, the gyro bias temperature coefficient (the paper neglects gyro temperature) and
//! the temperature-rate (dT/dt) terms of both triads. All are linear in their coefficients and
//! computed from the true accelerometer temperatures of [`EffectContext`].

use super::{EffectContext, ExtraEffect};
use sins_nav::Vec3;

/// Second-order temperature coefficient of the accelerometer bias:
/// `δf_j = K2T_j (T_j - T_ref)^2`, integrated over the sample as `δf_j dt`.
///
/// Physics: the bias of a quartz pendulous accelerometer follows the temperature through the
/// torquer magnet and the flexure; the paper models it to first order (TB). Its curvature is
/// typically 0.01-0.1 ug/degC^2 (0.05 ug/degC^2 gives 20 ug over +-20 degC). Its linear part about
/// any temperature is absorbed by a calibrated TB and bias; what remains shows as a parabola in
/// the temperature.
#[derive(Clone, Copy, Debug)]
pub struct AccelBiasQuadraticTemp {
    /// Coefficient per axis (m/s^2/degC^2).
    pub coeff_mps2_per_degc2: Vec3,
    /// Reference temperature (degC).
    pub reference_degc: f64,
}

impl ExtraEffect for AccelBiasQuadraticTemp {
    fn name(&self) -> &'static str {
        "accel_bias_quadratic_temp"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        for j in 0..3 {
            let d = ctx.accel_temp_degc[j] - self.reference_degc;
            dv[j] += self.coeff_mps2_per_degc2[j] * d * d * ctx.dt_s;
        }
    }
}

/// Gyro bias temperature coefficient (the paper neglects gyro temperature):
/// `δω_j = TB_g,j (T_mean - T_ref)`, driven by the mean accelerometer temperature (the IMU has no
/// gyro thermometer; the gyros share the cluster's temperature).
///
/// Physics: the bias of a ring-laser gyro shifts with temperature through thermally driven gas
/// flow (Langmuir flow) and cavity gradients; typically 0.0002-0.001 deg/h/degC for this class.
#[derive(Clone, Copy, Debug)]
pub struct GyroBiasTemp {
    /// Coefficient per axis (rad/s/degC).
    pub coeff_radps_per_degc: Vec3,
    /// Reference temperature (degC).
    pub reference_degc: f64,
}

impl ExtraEffect for GyroBiasTemp {
    fn name(&self) -> &'static str {
        "gyro_bias_temp"
    }
    fn apply(&mut self, ctx: &EffectContext, dtheta: &mut Vec3, _dv: &mut Vec3) {
        let t = ctx.mean_temp_degc() - self.reference_degc;
        *dtheta += self.coeff_radps_per_degc * (t * ctx.dt_s);
    }
}

/// Accelerometer bias proportional to the rate of change of its temperature:
/// `δf_j = c_j dT_j/dt`.
///
/// Physics: while the temperature changes, gradients across the proof mass, flexure and magnet
/// shift the bias beyond what the steady-state coefficients give; it vanishes at constant
/// temperature. Typically ~10 ug per degC/min (file unit `ug/(degC/min)`).
#[derive(Clone, Copy, Debug)]
pub struct AccelBiasTempRate {
    /// Coefficient per axis (m/s^2 per degC/s).
    pub coeff_mps2_per_degc_per_s: Vec3,
}

impl ExtraEffect for AccelBiasTempRate {
    fn name(&self) -> &'static str {
        "accel_bias_temp_rate"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        for j in 0..3 {
            dv[j] +=
                self.coeff_mps2_per_degc_per_s[j] * ctx.accel_temp_rate_degc_per_s[j] * ctx.dt_s;
        }
    }
}

/// Gyro bias proportional to the rate of change of the (mean accelerometer) temperature:
/// `δω_j = c_j dT_mean/dt`.
///
/// Physics: thermal gradients along the laser cavity during transients (the Shupe-like
/// non-reciprocity of gas flow); typically ~0.005 deg/h per degC/min for this class.
#[derive(Clone, Copy, Debug)]
pub struct GyroBiasTempRate {
    /// Coefficient per axis (rad/s per degC/s).
    pub coeff_radps_per_degc_per_s: Vec3,
}

impl ExtraEffect for GyroBiasTempRate {
    fn name(&self) -> &'static str {
        "gyro_bias_temp_rate"
    }
    fn apply(&mut self, ctx: &EffectContext, dtheta: &mut Vec3, _dv: &mut Vec3) {
        *dtheta += self.coeff_radps_per_degc_per_s * (ctx.mean_temp_rate_degc_per_s() * ctx.dt_s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::{DEG_PER_H, UG};

    fn ctx(temp: [f64; 3], rate: [f64; 3]) -> EffectContext {
        let mut c = EffectContext::at_rest(1.0, 0.005, temp);
        c.accel_temp_rate_degc_per_s = rate;
        c
    }

    #[test]
    fn quadratic_temperature_bias_is_a_parabola_about_the_reference() {
        let mut e = AccelBiasQuadraticTemp {
            coeff_mps2_per_degc2: Vec3::new(0.05, 0.1, -0.2) * UG,
            reference_degc: 20.0,
        };
        // Symmetric about the reference, zero at it, 4x at twice the offset.
        let (_, at_30) = e.perturbation(&ctx([30.0, 30.0, 30.0], [0.0; 3]));
        let (_, at_10) = e.perturbation(&ctx([10.0, 10.0, 10.0], [0.0; 3]));
        let (_, at_40) = e.perturbation(&ctx([40.0, 40.0, 40.0], [0.0; 3]));
        let (_, at_20) = e.perturbation(&ctx([20.0, 20.0, 20.0], [0.0; 3]));
        assert!((at_30 - at_10).norm() < 1e-25);
        assert!((at_40 - at_30 * 4.0).norm() < 1e-22);
        assert_eq!(at_20, Vec3::zeros());
        // 0.05 ug/degC^2 at 10 degC off: 5 ug, times 5 ms.
        assert!((at_30.x - 5.0 * UG * 0.005).abs() < 1e-20);
    }

    #[test]
    fn gyro_bias_temperature_follows_the_mean_temperature() {
        let mut e = GyroBiasTemp {
            coeff_radps_per_degc: Vec3::new(1e-3, 0.0, -2e-3) * DEG_PER_H,
            reference_degc: 20.0,
        };
        // Mean of 10, 20, 60 is 30 degC: 10 degC above the reference.
        let (dth, dv) = e.perturbation(&ctx([10.0, 20.0, 60.0], [0.0; 3]));
        assert!((dth.x - 0.01 * DEG_PER_H * 0.005).abs() < 1e-22);
        assert!((dth.z + 0.02 * DEG_PER_H * 0.005).abs() < 1e-22);
        assert_eq!(dth.y, 0.0);
        assert_eq!(dv, Vec3::zeros());
    }

    #[test]
    fn temperature_rate_terms_vanish_at_constant_temperature_and_scale_with_the_rate() {
        let c = Vec3::new(10.0, -5.0, 1.0) * UG * 60.0;
        let mut a = AccelBiasTempRate {
            coeff_mps2_per_degc_per_s: c,
        };
        let mut g = GyroBiasTempRate {
            coeff_radps_per_degc_per_s: Vec3::new(0.005, 0.0, 0.0) * DEG_PER_H * 60.0,
        };
        // Any temperature, zero rate: nothing.
        for temp in [[-10.0; 3], [20.0; 3], [55.0, 3.0, 7.0]] {
            assert_eq!(
                a.perturbation(&ctx(temp, [0.0; 3])),
                (Vec3::zeros(), Vec3::zeros())
            );
            assert_eq!(
                g.perturbation(&ctx(temp, [0.0; 3])),
                (Vec3::zeros(), Vec3::zeros())
            );
        }
        // 1 degC/min on x: 10 ug on x only; the gyro sees the mean rate 1/3 degC/min.
        let rate = [1.0 / 60.0, 0.0, 0.0];
        let (_, dv) = a.perturbation(&ctx([20.0; 3], rate));
        assert!((dv.x - 10.0 * UG * 0.005).abs() < 1e-20);
        assert_eq!((dv.y, dv.z), (0.0, 0.0));
        let (dth, _) = g.perturbation(&ctx([20.0; 3], rate));
        assert!((dth.x - 0.005 / 3.0 * DEG_PER_H * 0.005).abs() < 1e-22);
    }
}
