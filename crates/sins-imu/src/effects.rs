//! Effects outside the paper's error model. Each is a named, switchable term applied after
//! eqs (1)-(2) by [`crate::ForwardModel`]; the sim-to-real work adds its catalogue here. An effect
//! sees the true motion and temperatures of the sample through [`EffectContext`] and perturbs the
//! raw increments in place, so adding one is local to its own type.

use sins_nav::Vec3;

/// What an extra effect may depend on, for one sample interval.
#[derive(Clone, Copy, Debug)]
pub struct EffectContext {
    /// Time at the end of the interval (s).
    pub t_s: f64,
    /// Sample interval (s).
    pub dt_s: f64,
    /// True angular increment (rad) over the interval.
    pub true_dtheta_rad: Vec3,
    /// True velocity increment (m/s) over the interval.
    pub true_dv_mps: Vec3,
    /// True accelerometer temperatures (degC).
    pub accel_temp_degc: [f64; 3],
    /// Rate of change of the true accelerometer temperatures (degC/s).
    pub accel_temp_rate_degc_per_s: [f64; 3],
}

impl EffectContext {
    /// A context with zero motion at constant temperature (handy for tests).
    pub fn at_rest(t_s: f64, dt_s: f64, accel_temp_degc: [f64; 3]) -> Self {
        Self {
            t_s,
            dt_s,
            true_dtheta_rad: Vec3::zeros(),
            true_dv_mps: Vec3::zeros(),
            accel_temp_degc,
            accel_temp_rate_degc_per_s: [0.0; 3],
        }
    }
}

/// An error term that the paper's model leaves out.
pub trait ExtraEffect: Send {
    /// Stable snake_case name used in files and reports.
    fn name(&self) -> &'static str;
    /// Perturb the raw increments of one sample (after the paper's terms).
    fn apply(&mut self, ctx: &EffectContext, dtheta_rad: &mut Vec3, dv_mps: &mut Vec3);
}

/// A data description of one extra effect (what experiment files name), buildable into the
/// [`ExtraEffect`] the forward model applies. Values in SI.
#[derive(Clone, Debug, PartialEq)]
pub enum EffectSpec {
    /// See [`AccelBiasQuadraticTemp`].
    AccelBiasQuadraticTemp {
        /// Coefficient per axis (m/s^2/degC^2).
        coeff_mps2_per_degc2: Vec3,
        /// Reference temperature (degC).
        reference_degc: f64,
    },
    /// See [`GyroBiasTemp`].
    GyroBiasTemp {
        /// Coefficient per axis (rad/s/degC).
        coeff_radps_per_degc: Vec3,
        /// Reference temperature (degC).
        reference_degc: f64,
    },
}

impl EffectSpec {
    /// The effect's stable name (as in files and reports).
    pub fn name(&self) -> &'static str {
        self.build().name()
    }

    /// The effect, ready for [`crate::ForwardModel::with_effect`].
    pub fn build(&self) -> Box<dyn ExtraEffect> {
        match *self {
            EffectSpec::AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2,
                reference_degc,
            } => Box::new(AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2,
                reference_degc,
            }),
            EffectSpec::GyroBiasTemp {
                coeff_radps_per_degc,
                reference_degc,
            } => Box::new(GyroBiasTemp {
                coeff_radps_per_degc,
                reference_degc,
            }),
        }
    }
}

/// Second-order temperature coefficient of the accelerometer bias: `K2_j (T_j - T_ref)^2`.
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
/// `TB_g,j (T - T_ref)`, driven by the mean accelerometer temperature.
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
        let t = ctx.accel_temp_degc.iter().sum::<f64>() / 3.0 - self.reference_degc;
        *dtheta += self.coeff_radps_per_degc * (t * ctx.dt_s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ForwardModel, ImuErrorParams, ParamModel};

    #[test]
    fn effects_are_local_and_named() {
        let mut fwd = ForwardModel::new(ImuErrorParams::ideal(ParamModel::States42)).with_effect(
            Box::new(AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2: Vec3::new(1e-6, 0.0, 0.0),
                reference_degc: 20.0,
            }),
        );
        assert_eq!(fwd.effect_names(), vec!["accel_bias_quadratic_temp"]);
        let temp = [30.0, 30.0, 30.0];
        let ctx = EffectContext::at_rest(0.0, 0.01, temp);
        let (_, dv) = fwd.apply(&Vec3::zeros(), &Vec3::zeros(), 0.01, &temp, &ctx);
        assert!((dv.x - 1e-6 * 100.0 * 0.01).abs() < 1e-18);
        assert_eq!(dv.y, 0.0);
    }
}
