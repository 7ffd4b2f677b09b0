//! Effects deliberately outside the diagnosis catalogue, for blind out-of-catalogue cases: a gyro
//! bias oscillating with a 45 min period and an accelerometer bias step. (The accelerometer
//! cross-axis coupling, also outside, lives with the other nonlinearity in
//! [`super::nonlinearity`].) A correct diagnosis reports these as "none of the catalogue explains
//! it".

use super::{EffectContext, ExtraEffect};
use sins_nav::Vec3;

/// Gyro bias oscillating in time: `δω_j = A_j sin(2π t/P + φ)`, integrated exactly over each
/// sample. With P = 45 min (between the Schuler period and the patterns' length) it mimics, e.g.,
/// a cooling-fan or air-conditioning cycle coupling into the gyro bias. Typical 0.005 deg/h.
#[derive(Clone, Copy, Debug)]
pub struct GyroBiasOscillation {
    /// Amplitude per axis (rad/s).
    pub amplitude_radps: Vec3,
    /// Period (s).
    pub period_s: f64,
    /// Phase at t = 0 (rad).
    pub phase_rad: f64,
}

impl ExtraEffect for GyroBiasOscillation {
    fn name(&self) -> &'static str {
        "gyro_bias_oscillation"
    }
    fn apply(&mut self, ctx: &EffectContext, dtheta: &mut Vec3, _dv: &mut Vec3) {
        let w = std::f64::consts::TAU / self.period_s;
        let (t0, t1) = (ctx.t_s - ctx.dt_s, ctx.t_s);
        // ∫ sin(w s + φ) ds over (t0, t1] = 2 sin(w h/2) sin(w t_mid + φ) / w.
        let mid = 0.5 * (t0 + t1);
        let integral = 2.0 * (0.5 * w * ctx.dt_s).sin() * (w * mid + self.phase_rad).sin() / w;
        *dtheta += self.amplitude_radps * integral;
    }
}

/// Accelerometer bias step: `δf_j = s_j` from `t_step` on (integrated exactly over the sample that
/// contains the step). Mimics a mechanical shift or an electronics mode change. Typical 20 ug.
#[derive(Clone, Copy, Debug)]
pub struct AccelBiasStep {
    /// Step per axis (m/s^2).
    pub step_mps2: Vec3,
    /// Time of the step (s).
    pub time_s: f64,
}

impl ExtraEffect for AccelBiasStep {
    fn name(&self) -> &'static str {
        "accel_bias_step"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        let on = (ctx.t_s - self.time_s).clamp(0.0, ctx.dt_s);
        if on > 0.0 {
            *dv += self.step_mps2 * on;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_nav::{DEG_PER_H, UG};

    #[test]
    fn oscillation_integrates_to_zero_over_a_period_and_peaks_at_the_amplitude() {
        let a = 0.005 * DEG_PER_H;
        let mut e = GyroBiasOscillation {
            amplitude_radps: Vec3::new(a, 0.0, 0.0),
            period_s: 2700.0,
            phase_rad: 0.0,
        };
        let h = 0.5;
        let mut ctx = EffectContext::at_rest(0.0, h, [20.0; 3]);
        let (mut sum, mut peak) = (0.0f64, 0.0f64);
        for k in 0..5400 {
            ctx.t_s = (k + 1) as f64 * h;
            let (d, _) = e.perturbation(&ctx);
            sum += d.x;
            peak = peak.max(d.x / h);
        }
        assert!(sum.abs() < 1e-12 * a * 2700.0, "{sum}");
        assert!((peak / a - 1.0).abs() < 1e-6, "{}", peak / a);
        // The angle at a quarter period: A P/(2π) (1 - cos(π/2)) = A P/(2π).
        let mut e2 = e;
        let quarter: f64 = (0..1350)
            .map(|k| {
                ctx.t_s = (k + 1) as f64 * h;
                e2.perturbation(&ctx).0.x
            })
            .sum();
        assert!((quarter - a * 2700.0 / std::f64::consts::TAU).abs() < 1e-12 * a * 2700.0);
    }

    #[test]
    fn step_switches_on_at_its_time_with_the_partial_sample() {
        let mut e = AccelBiasStep {
            step_mps2: Vec3::new(0.0, 20.0 * UG, 0.0),
            time_s: 1.002,
        };
        let h = 0.005;
        let mut ctx = EffectContext::at_rest(1.0, h, [20.0; 3]);
        assert_eq!(e.perturbation(&ctx).1, Vec3::zeros());
        ctx.t_s = 1.005;
        assert!((e.perturbation(&ctx).1.y - 20.0 * UG * 0.003).abs() < 1e-18);
        ctx.t_s = 2.0;
        assert!((e.perturbation(&ctx).1.y - 20.0 * UG * h).abs() < 1e-20);
    }
}
