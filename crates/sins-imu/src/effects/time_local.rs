//! Effects local in time, outside the diagnosis catalogue: a bias that steps, starts to drift
//! (a ramp) or jumps and decays (an exponential transient) at an onset time. Real IMUs show all
//! three: bias jumps after a shock or a mode change, a slow drift after a thermal event, the
//! turn-on transient of a laser-gyro bias. Each is integrated exactly over the sample that
//! contains the onset, so the injected increment is the integral of the bias profile.
//!
//! The diagnosis looks for these with a scan over onset time (`sins_diag::events`), not as
//! catalogue candidates: a correct diagnosis reports them as time-local events outside the
//! catalogue, with their channel and onset.

use super::kind::Sensor;
use super::{EffectContext, ExtraEffect};
use sins_nav::Vec3;

/// The time profile of a [`BiasEvent`], per unit magnitude, from the onset on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventShape {
    /// `b(t) = 1` for `t ≥ t_0`.
    Step,
    /// `b(t) = (t - t_0)` (the magnitude is a rate, per second).
    Ramp,
    /// `b(t) = exp(-(t - t_0)/τ)`.
    Transient {
        /// Time constant τ (s, > 0).
        time_constant_s: f64,
    },
}

impl EventShape {
    /// `∫ b(s) ds` from the onset to `t_0 + u` (`u ≥ 0`), per unit magnitude.
    pub fn integral(self, u_s: f64) -> f64 {
        if u_s <= 0.0 {
            return 0.0;
        }
        match self {
            EventShape::Step => u_s,
            EventShape::Ramp => 0.5 * u_s * u_s,
            EventShape::Transient { time_constant_s } => {
                time_constant_s * -(-u_s / time_constant_s).exp_m1()
            }
        }
    }

    /// Short name for reports: `step`, `ramp` or `transient`.
    pub fn name(self) -> &'static str {
        match self {
            EventShape::Step => "step",
            EventShape::Ramp => "ramp",
            EventShape::Transient { .. } => "transient",
        }
    }
}

/// A bias event on one sensor triad: `δ_j(t) = m_j b(t - t_0)` with `b` the [`EventShape`].
#[derive(Clone, Copy, Debug)]
pub struct BiasEvent {
    /// Which triad (gyro: rad/s; accelerometer: m/s²).
    pub sensor: Sensor,
    /// Magnitude per axis (SI; a ramp's is per second).
    pub magnitude: Vec3,
    /// Onset `t_0` (s, on the dataset's time axis).
    pub onset_s: f64,
    /// Time profile.
    pub shape: EventShape,
}

impl ExtraEffect for BiasEvent {
    fn name(&self) -> &'static str {
        match (self.sensor, self.shape) {
            (Sensor::Gyro, EventShape::Step) => "gyro_bias_step",
            (Sensor::Gyro, EventShape::Ramp) => "gyro_bias_ramp",
            (Sensor::Gyro, EventShape::Transient { .. }) => "gyro_bias_transient",
            (Sensor::Accel, EventShape::Step) => "accel_bias_step",
            (Sensor::Accel, EventShape::Ramp) => "accel_bias_ramp",
            (Sensor::Accel, EventShape::Transient { .. }) => "accel_bias_transient",
        }
    }

    fn apply(&mut self, ctx: &EffectContext, dtheta: &mut Vec3, dv: &mut Vec3) {
        let (u0, u1) = (ctx.t_s - ctx.dt_s - self.onset_s, ctx.t_s - self.onset_s);
        if u1 <= 0.0 {
            return;
        }
        let w = self.shape.integral(u1) - self.shape.integral(u0.max(0.0));
        match self.sensor {
            Sensor::Gyro => *dtheta += self.magnitude * w,
            Sensor::Accel => *dv += self.magnitude * w,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn total(e: &mut BiasEvent, h: f64, n: usize) -> (Vec3, Vec3) {
        let mut ctx = EffectContext::at_rest(0.0, h, [20.0; 3]);
        let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
        for k in 0..n {
            ctx.t_s = (k + 1) as f64 * h;
            let (d, v) = e.perturbation(&ctx);
            a += d;
            b += v;
        }
        (a, b)
    }

    #[test]
    fn increments_add_up_to_the_integral_of_the_profile() {
        let (h, n) = (0.005, 200_000); // 1000 s
        let t0 = 123.4567;
        for (shape, want) in [
            (EventShape::Step, 1000.0 - t0),
            (EventShape::Ramp, 0.5 * (1000.0 - t0) * (1000.0 - t0)),
            (
                EventShape::Transient {
                    time_constant_s: 300.0,
                },
                300.0 * (1.0 - (-(1000.0 - t0) / 300.0f64).exp()),
            ),
        ] {
            let mut g = BiasEvent {
                sensor: Sensor::Gyro,
                magnitude: Vec3::new(0.0, 2.0, 0.0),
                onset_s: t0,
                shape,
            };
            let (a, b) = total(&mut g, h, n);
            assert!(
                (a.y - 2.0 * want).abs() < 1e-9 * want,
                "{shape:?}: {} vs {}",
                a.y,
                want
            );
            assert_eq!((a.x, b), (0.0, Vec3::zeros()));
            let mut f = BiasEvent {
                sensor: Sensor::Accel,
                ..g
            };
            let (a, b) = total(&mut f, h, n);
            assert!((b.y - 2.0 * want).abs() < 1e-9 * want);
            assert_eq!(a, Vec3::zeros());
        }
    }

    #[test]
    fn nothing_before_the_onset() {
        let mut e = BiasEvent {
            sensor: Sensor::Accel,
            magnitude: Vec3::new(1.0, 1.0, 1.0),
            onset_s: 10.0,
            shape: EventShape::Step,
        };
        assert_eq!(total(&mut e, 0.005, 2000).1, Vec3::zeros());
    }
}
