//! Gyro-accelerometer time offset: the accelerometer samples are delayed relative to the gyros.

use super::{EffectContext, ExtraEffect};
use sins_nav::Vec3;

/// Accelerometer j's samples are delayed by τ_j behind the gyros (separate converters, filters or
/// latching), so its increment over `(t - dt, t]` is really the one over `(t - dt - τ_j, t - τ_j]`.
/// To first order in τ (exact when the specific force is linear in time):
/// `δdv_j = -τ_j (df_j/dt) dt = -(τ_j/dt) (dv_j,k - dv_j,k-1)`.
///
/// Linear in τ. Its sum over a run telescopes (no net velocity), but with the body rotating the
/// delayed specific force is resolved with the wrong attitude, which rectifies like a sculling
/// error under vibration. Typical sampling skew: a fraction of a millisecond.
#[derive(Clone, Copy, Debug)]
pub struct AccelTimeOffset {
    /// Delay per accelerometer (s; negative = ahead of the gyros).
    pub delay_s: Vec3,
}

impl ExtraEffect for AccelTimeOffset {
    fn name(&self) -> &'static str {
        "accel_time_offset"
    }
    fn apply(&mut self, ctx: &EffectContext, _dtheta: &mut Vec3, dv: &mut Vec3) {
        let ddv = ctx.true_dv_mps - ctx.prev_true_dv_mps;
        for j in 0..3 {
            dv[j] -= self.delay_s[j] / ctx.dt_s * ddv[j];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::ContextTracker;

    #[test]
    fn delay_on_a_ramp_equals_minus_tau_times_the_force_rate() {
        let h = 0.005;
        let tau = Vec3::new(0.5e-3, -0.2e-3, 0.0);
        let mut e = AccelTimeOffset { delay_s: tau };
        // f(t) = f0 + b t on every axis; the exact increment of the delayed signal is
        // ∫ f(s - τ) ds = dv - τ b dt.
        let f0 = Vec3::new(0.3, -1.0, 9.8);
        let b = Vec3::new(2.0, 0.5, -1.0);
        let mut tracker = ContextTracker::new();
        for k in 0..50 {
            let (t0, t1) = (k as f64 * h, (k + 1) as f64 * h);
            let dv = f0 * h + b * (0.5 * (t1 * t1 - t0 * t0));
            let ctx = tracker.next(t1, h, Vec3::zeros(), dv, [20.0; 3], [0.0; 3]);
            let (_, d) = e.perturbation(&ctx);
            if k == 0 {
                // No history: the first sample is left alone.
                assert_eq!(d, Vec3::zeros());
                continue;
            }
            let want = -tau.component_mul(&b) * h;
            assert!((d - want).norm() < 1e-16, "{k}: {d:?} vs {want:?}");
            // Against the exact delayed increment.
            for j in 0..3 {
                let fj = |t: f64| f0[j] * t + 0.5 * b[j] * t * t;
                let delayed = fj(t1 - tau[j]) - fj(t0 - tau[j]);
                assert!((dv[j] + d[j] - delayed).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn constant_force_is_not_affected() {
        let mut e = AccelTimeOffset {
            delay_s: Vec3::new(1e-3, 1e-3, 1e-3),
        };
        let mut c = EffectContext::at_rest(1.0, 0.005, [20.0; 3]);
        c.true_dv_mps = Vec3::new(0.0, 0.0, 9.8 * 0.005);
        c.prev_true_dv_mps = c.true_dv_mps;
        assert_eq!(e.perturbation(&c).1, Vec3::zeros());
    }
}
