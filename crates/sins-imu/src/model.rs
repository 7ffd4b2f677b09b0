//! Forward error model (eqs 1-2: what the simulator applies to true increments) and its exact
//! inverse (the compensation of eqs 3-5: what a calibrated system applies to raw increments).
//!
//! Both act on increments over one sample interval `dt_s`: the bias terms integrate to
//! `B · dt_s`, the matrix terms multiply the true increment. Temperatures are treated as constant
//! over one sample (5 ms), which the thermal time constants of minutes make exact to ~1e-9.

use crate::effects::{EffectContext, ExtraEffect};
use crate::params::ImuErrorParams;
use sins_nav::{Mat3, Vec3};

mod lanes;

/// The truth an IMU applies: eq (1) for the accelerometers, eq (2) for the gyros, then every
/// enabled extra effect in order. Adding an effect never touches the paper's terms.
pub struct ForwardModel {
    params: ImuErrorParams,
    gyro_matrix: Mat3,
    effects: Vec<Box<dyn ExtraEffect>>,
}

impl ForwardModel {
    /// Forward model with the paper's terms only.
    pub fn new(params: ImuErrorParams) -> Self {
        Self {
            gyro_matrix: Mat3::identity() + params.gyro_error_matrix(),
            params,
            effects: Vec::new(),
        }
    }

    /// Add an effect outside the paper's model; effects are applied in the order added.
    pub fn with_effect(mut self, effect: Box<dyn ExtraEffect>) -> Self {
        self.effects.push(effect);
        self
    }

    /// The paper-model coefficients of this IMU.
    pub fn params(&self) -> &ImuErrorParams {
        &self.params
    }

    /// Return every extra effect to its state before the first sample (see
    /// [`ExtraEffect::reset`]), so that a second pass over the same samples is identical.
    pub fn reset_effects(&mut self) {
        for e in &mut self.effects {
            e.reset();
        }
    }

    /// Names of the enabled extra effects.
    pub fn effect_names(&self) -> Vec<&'static str> {
        self.effects.iter().map(|e| e.name()).collect()
    }

    /// Raw increments from true ones. `accel_temp_degc` is the true temperature of each
    /// accelerometer (not the thermometer reading); `ctx` carries what the extra effects need.
    pub fn apply(
        &mut self,
        true_dtheta_rad: &Vec3,
        true_dv_mps: &Vec3,
        dt_s: f64,
        accel_temp_degc: &[f64; 3],
        ctx: &EffectContext,
    ) -> (Vec3, Vec3) {
        let p = &self.params;
        let dtemp = p.temperature_offsets_degc(accel_temp_degc);
        let mut dtheta = p.gyro.bias_radps * dt_s + self.gyro_matrix * true_dtheta_rad;
        let accel_matrix = Mat3::identity() + p.accel_error_matrix(&dtemp);
        let mut dv = p.accel_bias_mps2(&dtemp) * dt_s + accel_matrix * true_dv_mps;
        for e in &mut self.effects {
            e.apply(ctx, &mut dtheta, &mut dv);
        }
        (dtheta, dv)
    }
}

/// Compensation of raw increments with a calibrated parameter set: the exact inverse of the
/// paper terms of [`ForwardModel`]. Eqs (3)-(5) of the paper write the same inverse to first
/// order as corrected scale-factor and installation matrices (K = K̃ - (δK + ΔT·TK) K̃,
/// M = M̃ - (δM + ΔT·TM) K̃) and a corrected bias; here the 3x3 systems are solved exactly so
/// that compensation of forward-model output returns the true increments to rounding error.
/// A 30-state set ignores temperatures.
#[derive(Clone, Debug)]
pub struct Compensator {
    params: ImuErrorParams,
    gyro_inverse: Mat3,
    accel_inverse_const: Option<Mat3>,
}

impl Compensator {
    /// Compensator for a parameter set. Fails only if `I + E` is singular, which needs error
    /// coefficients of order one (not an IMU).
    pub fn new(params: ImuErrorParams) -> Option<Self> {
        let gyro_inverse = (Mat3::identity() + params.gyro_error_matrix()).try_inverse()?;
        let accel_inverse_const = match params.model {
            crate::ParamModel::States30 => {
                Some((Mat3::identity() + params.accel_error_matrix(&[0.0; 3])).try_inverse()?)
            }
            crate::ParamModel::States42 => None,
        };
        Some(Self {
            params,
            gyro_inverse,
            accel_inverse_const,
        })
    }

    /// The parameter set applied.
    pub fn params(&self) -> &ImuErrorParams {
        &self.params
    }

    /// True when the compensation uses the thermometer readings.
    pub fn uses_temperature(&self) -> bool {
        self.accel_inverse_const.is_none()
    }

    /// Compensated angular increment (rad) from a raw one over `dt_s` seconds.
    #[inline]
    pub fn dtheta_rad(&self, raw_dtheta_rad: &Vec3, dt_s: f64) -> Vec3 {
        self.gyro_inverse * (raw_dtheta_rad - self.params.gyro.bias_radps * dt_s)
    }

    /// Compensated velocity increment (m/s) from a raw one over `dt_s` seconds, with the
    /// thermometer readings `temp_degc` of the three accelerometers.
    #[inline]
    pub fn dv_mps(&self, raw_dv_mps: &Vec3, dt_s: f64, temp_degc: &[f64; 3]) -> Vec3 {
        match &self.accel_inverse_const {
            Some(inv) => inv * (raw_dv_mps - self.params.accel.bias_mps2 * dt_s),
            None => {
                let dtemp = self.params.temperature_offsets_degc(temp_degc);
                let m = Mat3::identity() + self.params.accel_error_matrix(&dtemp);
                let rhs = raw_dv_mps - self.params.accel_bias_mps2(&dtemp) * dt_s;
                solve3(&m, &rhs)
            }
        }
    }
}

/// Solve `m x = b` for a well-conditioned 3x3 `m` by Cramer's rule (`m` is the identity plus
/// terms of order 1e-3, so the result is accurate to a few ulps; see the round-trip test).
#[inline]
fn solve3(m: &Mat3, b: &Vec3) -> Vec3 {
    let (c0, c1, c2) = (m.column(0), m.column(1), m.column(2));
    let inv_det = 1.0 / c0.dot(&c1.cross(&c2));
    Vec3::new(
        b.dot(&c1.cross(&c2)),
        c0.dot(&b.cross(&c2)),
        c0.dot(&c1.cross(b)),
    ) * inv_det
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{AccelParams, GyroParams, ParamModel, TemperatureCoeffs};
    use sins_nav::{ARCSEC, DEG_PER_H, UG};

    /// Ten times the magnitudes of the paper's Table 1 presets and Table 3 coefficients.
    pub(crate) fn ten_times_paper() -> ImuErrorParams {
        let s = 10.0;
        ImuErrorParams {
            model: ParamModel::States42,
            gyro: GyroParams {
                bias_radps: Vec3::new(0.003, 0.003, 0.003) * DEG_PER_H * s,
                scale: Vec3::new(20e-6, 40e-6, 60e-6) * s,
                misalignment_rad: [-61.88 * ARCSEC * s, 41.25 * ARCSEC * s, -20.63 * ARCSEC * s],
            },
            accel: AccelParams {
                bias_mps2: Vec3::new(1.0, 1.0, 1.0) * UG * s,
                scale: Vec3::new(10e-6, 30e-6, 50e-6) * s,
                misalignment_rad: [-41.25, 20.62, 61.88, -61.88, -20.62, 41.25]
                    .map(|a| a * ARCSEC * s),
            },
            temperature: TemperatureCoeffs {
                bias_mps2_per_degc: Vec3::new(-2.77, 2.63, -25.45) * UG * s,
                scale_per_degc: Vec3::new(19.33e-6, 13.96e-6, 35.58e-6) * s,
                misalignment_rad_per_degc: [-0.12, -0.02, -0.13, 0.14, 0.37, -0.47]
                    .map(|a| a * ARCSEC * s),
            },
            reference_temperature_degc: 20.0,
        }
    }

    #[test]
    fn column_j_of_temperature_matrix_scales_with_accelerometer_j() {
        let mut p = ImuErrorParams::ideal(ParamModel::States42);
        p.temperature.misalignment_rad_per_degc = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        p.temperature.scale_per_degc = Vec3::new(7.0, 8.0, 9.0);
        let e = p.accel_error_matrix(&[1.0, 10.0, 100.0]);
        // Column x: TK_ax, TM_ayx, TM_azx times ΔT_x; column y times ΔT_y; column z times ΔT_z.
        assert_eq!(e.column(0).into_owned(), Vec3::new(7.0, 1.0, 2.0));
        assert_eq!(e.column(1).into_owned(), Vec3::new(30.0, 80.0, 40.0));
        assert_eq!(e.column(2).into_owned(), Vec3::new(500.0, 600.0, 900.0));
    }

    #[test]
    fn compensation_inverts_forward_model_to_1e12_at_ten_times_paper_magnitudes() {
        let p = ten_times_paper();
        let mut fwd = ForwardModel::new(p);
        let comp = Compensator::new(p).unwrap();
        let dt = 0.005;
        let cases = [
            (
                Vec3::new(3e-7, -2e-7, 1e-7),
                Vec3::new(0.001, -0.002, 0.049),
                [0.0, 5.0, 40.0],
            ),
            (
                Vec3::new(0.05, -0.01, 0.02),
                Vec3::new(0.03, 0.04, -0.02),
                [-10.0, 25.0, 60.0],
            ),
            (
                Vec3::new(-1e-3, 4e-3, 0.0),
                Vec3::new(-0.049, 0.0, 0.0),
                [20.0, 20.0, 20.0],
            ),
        ];
        for (dth, dv, temp) in cases {
            let ctx = EffectContext::at_rest(0.0, dt, temp);
            let (rth, rv) = fwd.apply(&dth, &dv, dt, &temp, &ctx);
            assert!(
                (rth - dth).norm() > 1e-6 * dth.norm(),
                "model must change the increment"
            );
            let cth = comp.dtheta_rad(&rth, dt);
            let cv = comp.dv_mps(&rv, dt, &temp);
            assert!(
                (cth - dth).norm() <= 1e-12 * dth.norm(),
                "{:e}",
                (cth - dth).norm() / dth.norm()
            );
            assert!(
                (cv - dv).norm() <= 1e-12 * dv.norm(),
                "{:e}",
                (cv - dv).norm() / dv.norm()
            );
        }
    }

    #[test]
    fn thirty_state_compensation_ignores_temperature() {
        let mut p = ten_times_paper();
        p.model = ParamModel::States30;
        p.temperature = TemperatureCoeffs::default();
        let comp = Compensator::new(p).unwrap();
        assert!(!comp.uses_temperature());
        let dv = Vec3::new(0.01, 0.02, 0.03);
        assert_eq!(
            comp.dv_mps(&dv, 0.005, &[0.0; 3]),
            comp.dv_mps(&dv, 0.005, &[50.0; 3])
        );
    }
}
