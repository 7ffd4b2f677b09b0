//! Effects local in time, outside the diagnosis catalogue: a bias that steps, starts to drift
//! (a ramp) or jumps and decays (an exponential transient) at an onset time. Real IMUs show all
//! three: bias jumps after a shock or a mode change, a slow drift after a thermal event, the
//! turn-on transient of a laser-gyro bias. Three more shapes test the diagnosis outside the
//! shapes its scan looks for: a ramp to a plateau (a drift that settles), a rectangular pulse
//! (a mode held for a while) and a decaying oscillation (a thermal control loop settling). Each
//! is integrated exactly over the sample that contains the onset (and its end, or the end of
//! its rise), so the injected increment is the integral of the bias profile.
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
    /// `b(t) = (t - t_0)/r` for `t_0 ≤ t < t_0 + r`, then `1` (a ramp to a plateau; the
    /// magnitude is the plateau level).
    Plateau {
        /// Rise time r (s, > 0).
        rise_s: f64,
    },
    /// `b(t) = 1` for `t_0 ≤ t < t_0 + D`, then `0` (a rectangular pulse).
    Pulse {
        /// Duration D (s, > 0).
        duration_s: f64,
    },
    /// `b(t) = sin(2π (t - t_0)/P) exp(-(t - t_0)/τ)` (a decaying oscillation).
    DecayingOscillation {
        /// Period P (s, > 0).
        period_s: f64,
        /// Decay time constant τ (s, > 0).
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
            EventShape::Plateau { rise_s } => {
                if u_s < rise_s {
                    0.5 * u_s * u_s / rise_s
                } else {
                    0.5 * rise_s + (u_s - rise_s)
                }
            }
            EventShape::Pulse { duration_s } => u_s.min(duration_s),
            EventShape::DecayingOscillation {
                period_s,
                time_constant_s,
            } => {
                // ∫_0^u sin(ω s) e^{-a s} ds = [ω - e^{-a u} (a sin ω u + ω cos ω u)] / (a² + ω²).
                let w = std::f64::consts::TAU / period_s;
                let a = 1.0 / time_constant_s;
                let (s, c) = (w * u_s).sin_cos();
                (w - (-a * u_s).exp() * (a * s + w * c)) / (a * a + w * w)
            }
        }
    }

    /// The profile `b(t_0 + u)` itself, per unit magnitude (0 before the onset).
    pub fn value(self, u_s: f64) -> f64 {
        if u_s < 0.0 {
            return 0.0;
        }
        match self {
            EventShape::Step => 1.0,
            EventShape::Ramp => u_s,
            EventShape::Transient { time_constant_s } => (-u_s / time_constant_s).exp(),
            EventShape::Plateau { rise_s } => (u_s / rise_s).min(1.0),
            EventShape::Pulse { duration_s } => {
                if u_s < duration_s {
                    1.0
                } else {
                    0.0
                }
            }
            EventShape::DecayingOscillation {
                period_s,
                time_constant_s,
            } => (std::f64::consts::TAU * u_s / period_s).sin() * (-u_s / time_constant_s).exp(),
        }
    }

    /// Short name for reports: `step`, `ramp`, `transient`, `plateau`, `pulse` or
    /// `decaying oscillation`.
    pub fn name(self) -> &'static str {
        match self {
            EventShape::Step => "step",
            EventShape::Ramp => "ramp",
            EventShape::Transient { .. } => "transient",
            EventShape::Plateau { .. } => "plateau",
            EventShape::Pulse { .. } => "pulse",
            EventShape::DecayingOscillation { .. } => "decaying oscillation",
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
            (Sensor::Gyro, EventShape::Plateau { .. }) => "gyro_bias_plateau",
            (Sensor::Accel, EventShape::Plateau { .. }) => "accel_bias_plateau",
            (Sensor::Gyro, EventShape::Pulse { .. }) => "gyro_bias_pulse",
            (Sensor::Accel, EventShape::Pulse { .. }) => "accel_bias_pulse",
            (Sensor::Gyro, EventShape::DecayingOscillation { .. }) => {
                "gyro_bias_decaying_oscillation"
            }
            (Sensor::Accel, EventShape::DecayingOscillation { .. }) => {
                "accel_bias_decaying_oscillation"
            }
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

    /// [`Self::apply`] to zero increments, sample by sample, with the profile's integral at the
    /// start of a sample taken from the sample before when the two times are the same number
    /// (most are: `(t_k - h) - t_0` against `t_(k-1) - t_0`), so a transient's exponential is
    /// mostly computed once per sample instead of twice.
    fn perturbations(&mut self, ctxs: &[EffectContext], out: &mut Vec<(Vec3, Vec3)>) {
        out.clear();
        // The last end time's bits and the integral there.
        let mut last: Option<(u64, f64)> = None;
        out.extend(ctxs.iter().map(|ctx| {
            let (mut dtheta, mut dv) = (Vec3::zeros(), Vec3::zeros());
            let (u0, u1) = (ctx.t_s - ctx.dt_s - self.onset_s, ctx.t_s - self.onset_s);
            if u1 <= 0.0 {
                return (dtheta, dv);
            }
            let u0 = u0.max(0.0);
            let i0 = match last {
                Some((bits, integral)) if bits == u0.to_bits() => integral,
                _ => self.shape.integral(u0),
            };
            let i1 = self.shape.integral(u1);
            last = Some((u1.to_bits(), i1));
            let w = i1 - i0;
            match self.sensor {
                Sensor::Gyro => dtheta += self.magnitude * w,
                Sensor::Accel => dv += self.magnitude * w,
            }
            (dtheta, dv)
        }));
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

    /// The new shapes with hour-scale parameters (as the blind suite draws them).
    fn new_shapes() -> [EventShape; 3] {
        [
            EventShape::Plateau { rise_s: 5400.0 },
            EventShape::Pulse { duration_s: 2700.0 },
            EventShape::DecayingOscillation {
                period_s: 7200.0,
                time_constant_s: 10_800.0,
            },
        ]
    }

    /// Composite Simpson quadrature of the profile over `[a, b]` (`n` even intervals); the end
    /// values are the one-sided limits inside the interval (taken 1e-9 s inside), so that a
    /// piece ending at a pulse's end integrates the pulse's level.
    fn simpson(shape: EventShape, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut sum = shape.value(a + 1e-9) + shape.value(b - 1e-9);
        for i in 1..n {
            sum += if i % 2 == 1 { 4.0 } else { 2.0 } * shape.value(a + i as f64 * h);
        }
        sum * h / 3.0
    }

    /// [`simpson`] on each smooth piece of `[a, b]`: split at the end of a plateau's rise or of
    /// a pulse.
    fn quad(shape: EventShape, a: f64, b: f64, n: usize) -> f64 {
        let kink = match shape {
            EventShape::Plateau { rise_s } => Some(rise_s),
            EventShape::Pulse { duration_s } => Some(duration_s),
            _ => None,
        };
        match kink {
            Some(k) if a < k && k < b => simpson(shape, a, k, n) + simpson(shape, k, b, n),
            _ => simpson(shape, a, b, n),
        }
    }

    #[test]
    fn analytic_integrals_match_a_fine_quadrature_of_the_profile() {
        // Simpson with 20 000 intervals per smooth piece (the plateau's and the pulse's kinks
        // are piece ends): error below 1e-9 of the integral's scale (here 1e-10 relative to
        // max(|integral|, 1 s) is asked), over times before, at and after the kinks.
        for shape in new_shapes() {
            for u in [0.37, 1000.0, 2700.0, 3333.3, 5400.0, 9000.0, 54_000.0] {
                let want = quad(shape, 0.0, u, 20_000);
                let got = shape.integral(u);
                assert!(
                    (got - want).abs() <= 1e-10 * want.abs().max(1.0),
                    "{shape:?} at {u}: {got} vs {want}"
                );
            }
            assert_eq!(shape.integral(0.0), 0.0);
            assert_eq!(shape.integral(-5.0), 0.0);
            assert_eq!(shape.value(-1.0), 0.0);
        }
        // Closed forms at a few points: half the rise, then one second per second.
        let p = EventShape::Plateau { rise_s: 5400.0 };
        assert_eq!(p.integral(5400.0), 2700.0);
        assert_eq!(p.integral(6400.0), 3700.0);
        let q = EventShape::Pulse { duration_s: 2700.0 };
        assert_eq!(q.integral(10_000.0), 2700.0);
        // A decaying oscillation's integral tends to ω/(a² + ω²).
        let (pp, tau) = (7200.0, 10_800.0);
        let w = std::f64::consts::TAU / pp;
        let o = EventShape::DecayingOscillation {
            period_s: pp,
            time_constant_s: tau,
        };
        let limit = w / (1.0 / (tau * tau) + w * w);
        assert!((o.integral(1e7) - limit).abs() < 1e-9 * limit);
    }

    #[test]
    fn new_shapes_increments_add_up_to_the_integral_and_hold_exactly_over_kinks() {
        // 15 h at 10 Hz (the onset and the kinks fall inside samples), gyro and accelerometer.
        let (h, n) = (0.1, 540_000);
        let t0 = 3600.0 * 2.0 + 0.0437;
        for shape in new_shapes() {
            let want = shape.integral(n as f64 * h - t0);
            for sensor in [Sensor::Gyro, Sensor::Accel] {
                let mut e = BiasEvent {
                    sensor,
                    magnitude: Vec3::new(3.0, 0.0, -1.0),
                    onset_s: t0,
                    shape,
                };
                let (g, a) = total(&mut e, h, n);
                let (on, off) = match sensor {
                    Sensor::Gyro => (g, a),
                    Sensor::Accel => (a, g),
                };
                assert_eq!(off, Vec3::zeros());
                assert_eq!(on.y, 0.0);
                assert!(
                    (on.x - 3.0 * want).abs() <= 1e-9 * want.abs().max(1.0),
                    "{shape:?} {sensor:?}: {} vs {}",
                    on.x,
                    3.0 * want
                );
                assert!((on.z + want).abs() <= 1e-9 * want.abs().max(1.0));
            }
            // The sample that holds the onset carries exactly the part after the onset, and each
            // sample the integral of the profile over it.
            let mut e = BiasEvent {
                sensor: Sensor::Gyro,
                magnitude: Vec3::new(1.0, 0.0, 0.0),
                onset_s: t0,
                shape,
            };
            let mut ctx = EffectContext::at_rest(0.0, h, [20.0; 3]);
            for k in [72_000usize, 72_001, 72_002, 99_000, 126_000] {
                ctx.t_s = (k + 1) as f64 * h;
                let (d, _) = e.perturbation(&ctx);
                let (u0, u1) = (ctx.t_s - h - t0, ctx.t_s - t0);
                let quad = quad(shape, u0.max(0.0), u1.max(0.0), 2000);
                assert!((d.x - quad).abs() <= 1e-9 * h, "{shape:?} sample {k}");
            }
        }
        assert_eq!(
            BiasEvent {
                sensor: Sensor::Accel,
                magnitude: Vec3::zeros(),
                onset_s: 0.0,
                shape: EventShape::Pulse { duration_s: 1.0 },
            }
            .name(),
            "accel_bias_pulse"
        );
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
