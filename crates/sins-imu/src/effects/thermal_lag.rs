//! Thermal lag between thermometer and sensor: the paper's temperature terms act on a sensor
//! temperature that lags the thermometer reading.

use super::{EffectContext, ExtraEffect};
use crate::params::ImuErrorParams;
use sins_nav::{Mat3, Vec3};

/// The temperature of accelerometer j's sensing element lags the temperature its thermometer
/// measures by an extra first-order time constant τ_j: `dT_s,j/dt = (T_j - T_s,j)/τ_j`. The truth
/// temperature terms of eq (1) (TB, TK, TM of the parameter set) act on `T_s`, while the
/// compensation (and the forward model's own terms) use `T`; the perturbation is the difference:
/// `δf = TB ∘ (T_s - T) + E_T(T_s - T) f`, with `E_T` the temperature part of the accelerometer
/// error matrix (column j times `T_s,j - T_j`).
///
/// Discretisation: `T` is taken linear between sample midpoints and the lag is solved exactly
/// over each step; the first sample starts in the quasi-steady state `T_s = T - τ dT/dt` (exact
/// for a ramp, `T_s = T` at rest). Linearised about τ = 0: `T_s - T ≈ -τ_j dT_j/dt`, i.e. the
/// signature of an `accel_bias_temp_rate` of coefficient `-τ_j TB_j` plus a specific-force
/// dependent part from TK and TM (see the module documentation on separability). With a 30-state
/// truth (no temperature terms) the effect is zero.
///
/// Typical: about a minute between a case-mounted thermometer and the proof mass.
#[derive(Clone, Debug)]
pub struct ThermalLag {
    tau_s: Vec3,
    params: ImuErrorParams,
    /// `(t_s, T, T_s)` of the previous sample.
    state: Option<(f64, [f64; 3], [f64; 3])>,
    /// `E_a(0)` of `params` (it does not change).
    matrix_at_zero: Mat3,
    /// Per axis, the last step (s) and its decay `exp(-step/τ)`: steps repeat, so the
    /// exponential is mostly computed once.
    decay: [(f64, f64); 3],
}

impl ThermalLag {
    /// Lag of time constants `tau_s` (s, >= 0; 0 or negative = no lag) acting through the temperature
    /// coefficients of `truth`.
    pub fn new(tau_s: Vec3, truth: &ImuErrorParams) -> Self {
        Self {
            tau_s,
            params: *truth,
            state: None,
            matrix_at_zero: truth.accel_error_matrix(&[0.0; 3]),
            decay: [(f64::NAN, f64::NAN); 3],
        }
    }

    /// Advance the sensor temperatures to this sample and return them (degC).
    fn sensor_temp_degc(&mut self, ctx: &EffectContext) -> [f64; 3] {
        let temp = ctx.accel_temp_degc;
        let sensor: [f64; 3] = match self.state {
            None => {
                std::array::from_fn(|j| temp[j] - self.tau_s[j] * ctx.accel_temp_rate_degc_per_s[j])
            }
            Some((t_prev, temp_prev, sensor_prev)) => {
                let step = ctx.t_s - t_prev;
                std::array::from_fn(|j| {
                    let tau = self.tau_s[j];
                    if tau <= 0.0 || step <= 0.0 {
                        return temp[j];
                    }
                    let rate = (temp[j] - temp_prev[j]) / step;
                    if self.decay[j].0.to_bits() != step.to_bits() {
                        self.decay[j] = (step, (-step / tau).exp());
                    }
                    let decay = self.decay[j].1;
                    let particular = temp[j] - rate * tau;
                    let dev_prev = sensor_prev[j] - (temp_prev[j] - rate * tau);
                    particular + dev_prev * decay
                })
            }
        };
        self.state = Some((ctx.t_s, temp, sensor));
        sensor
    }
}

impl ExtraEffect for ThermalLag {
    fn name(&self) -> &'static str {
        "thermal_lag"
    }

    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        let sensor = self.sensor_temp_degc(ctx);
        let d: [f64; 3] = std::array::from_fn(|j| sensor[j] - ctx.accel_temp_degc[j]);
        let p = &self.params;
        let tb = &p.temperature.bias_mps2_per_degc;
        let bias = Vec3::new(tb.x * d[0], tb.y * d[1], tb.z * d[2]);
        // The temperature part of E_a is linear in the offsets: E_a(d) - E_a(0).
        let matrix: Mat3 = p.accel_error_matrix(&d) - self.matrix_at_zero;
        *dv += bias * ctx.dt_s + matrix * ctx.true_dv_mps;
    }

    fn reset(&mut self) {
        self.state = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ParamModel;
    use sins_nav::UG;

    fn truth() -> ImuErrorParams {
        let mut p = ImuErrorParams::ideal(ParamModel::States42);
        p.temperature.bias_mps2_per_degc = Vec3::new(-2.77, 2.63, -25.45) * UG;
        p.temperature.scale_per_degc = Vec3::new(19.33e-6, 13.96e-6, 35.58e-6);
        p.reference_temperature_degc = 20.0;
        p
    }

    /// Steady ramp of `rate` degC/s from 20 degC, level IMU (f = +g on z).
    fn ramp_ctx(k: usize, rate: f64) -> EffectContext {
        let h = 0.005;
        let t = (k + 1) as f64 * h;
        let temp = 20.0 + rate * (t - 0.5 * h);
        let mut c = EffectContext::at_rest(t, h, [temp; 3]);
        c.accel_temp_rate_degc_per_s = [rate; 3];
        c.true_dv_mps = Vec3::new(0.0, 0.0, 9.8 * h);
        c.prev_true_dv_mps = c.true_dv_mps;
        c
    }

    #[test]
    fn on_a_ramp_the_sensor_lags_by_tau_times_the_rate() {
        let p = truth();
        let tau = Vec3::new(60.0, 0.0, 120.0);
        let rate = 10.0 / 3600.0;
        let mut e = ThermalLag::new(tau, &p);
        for k in 0..20_000 {
            let c = ramp_ctx(k, rate);
            let (dth, dv) = e.perturbation(&c);
            assert_eq!(dth, Vec3::zeros());
            // T_s - T = -tau * rate on every sample (quasi-steady start, exact lag solution), to
            // the rounding of temperatures near 20 degC accumulated over tau/h steps.
            let want_x = -60.0 * rate * p.temperature.bias_mps2_per_degc.x * c.dt_s;
            assert!(
                (dv.x - want_x).abs() < 1e-9 * want_x.abs(),
                "{k}: {} vs {want_x}",
                dv.x
            );
            assert_eq!(dv.y, 0.0, "no lag on y");
            let dz = -120.0 * rate;
            let want_z = (p.temperature.bias_mps2_per_degc.z * c.dt_s
                + p.temperature.scale_per_degc.z * c.true_dv_mps.z)
                * dz;
            assert!((dv.z - want_z).abs() < 1e-9 * want_z.abs());
        }
    }

    #[test]
    fn a_step_in_temperature_decays_with_tau_and_vanishes_at_rest() {
        let p = truth();
        let mut e = ThermalLag::new(Vec3::new(30.0, 30.0, 30.0), &p);
        let h = 0.005;
        // Constant 25 degC: no lag once settled (starts settled).
        for k in 0..10 {
            let c = EffectContext::at_rest((k + 1) as f64 * h, h, [25.0; 3]);
            assert_eq!(e.perturbation(&c).1, Vec3::zeros());
        }
        // The thermometer jumps to 26 degC within one sample (rate 1/h on that step only): the
        // sensor then closes the gap as exp(-t/tau).
        let mut last = 0.0;
        for k in 10..(10 + 6000) {
            let c = EffectContext::at_rest((k + 1) as f64 * h, h, [26.0; 3]);
            let (_, dv) = e.perturbation(&c);
            let gap = dv.x / (p.temperature.bias_mps2_per_degc.x * h);
            let t_since = (k - 9) as f64 * h;
            // Linear over the jump step, then the exact exponential: the gap after the step is
            // -(tau/h)(1 - e^{-h/tau}), decaying as e^{-t/tau}.
            let after_step = -(30.0 / h) * (1.0 - (-h / 30.0f64).exp());
            let want = after_step * (-(t_since - h) / 30.0).exp();
            assert!((gap - want).abs() < 1e-9, "{k}: {gap} vs {want}");
            last = gap;
        }
        assert!(last.abs() < 0.4 && last < 0.0);
    }

    #[test]
    fn zero_tau_or_no_temperature_terms_give_nothing() {
        let mut e = ThermalLag::new(Vec3::zeros(), &truth());
        let mut thirty = ThermalLag::new(
            Vec3::new(60.0, 60.0, 60.0),
            &ImuErrorParams::ideal(ParamModel::States30),
        );
        for k in 0..100 {
            let c = ramp_ctx(k, 0.01);
            assert_eq!(e.perturbation(&c).1, Vec3::zeros());
            assert_eq!(thirty.perturbation(&c).1, Vec3::zeros());
        }
    }
}
