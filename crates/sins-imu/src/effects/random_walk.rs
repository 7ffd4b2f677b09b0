//! Bias drift beyond the modelled noise: a seeded random walk (or Gauss-Markov) bias.

use super::{EffectContext, ExtraEffect};
use rand_chacha::ChaCha8Rng;
use rand_core::{Rng, SeedableRng};
use sins_nav::Vec3;

/// ChaCha stream ids (under the effect's own seed) of the gyro and accelerometer walks, axis added.
const GYRO_STREAM: u64 = 0x6779_0000;
const ACCEL_STREAM: u64 = 0x6163_0000;

/// A bias that wanders beyond the noise model of the calibration: per axis
/// `b_{k+1} = φ b_k + q sqrt(τ_c (1 - φ^2)/2) w_k` with `φ = exp(-dt/τ_c)`, `w_k ~ N(0, 1)`,
/// starting at `b_0 = 0` (the calibrated value); `τ_c = ∞` is a pure random walk
/// `b_{k+1} = b_k + q sqrt(dt) w_k` (std `q sqrt(t)` after t). Integrated as `b_k dt` per sample.
///
/// The intensity q is in rad/s/sqrt(s) (gyro; file unit deg/h/sqrt(h)) or m/s^2/sqrt(s)
/// (accelerometer; ug/sqrt(h)). Deterministic: each axis draws from its own ChaCha8 stream of the
/// seed (Box-Muller), so a given seed and intensity give bit-identical samples, and for a fixed
/// seed the output is exactly linear in q. The diagnosis, which does not know the realisation,
/// treats it as a noise term (process noise q^2 on the bias), see
/// [`super::Linearity::RandomProcess`]. Typical: 0.001 deg/h/sqrt(h), 2 ug/sqrt(h).
#[derive(Clone, Debug)]
pub struct BiasRandomWalk {
    name: &'static str,
    on_gyro: bool,
    intensity: Vec3,
    correlation_s: f64,
    seed: u64,
    stream_base: u64,
    rngs: [Normal; 3],
    bias: Vec3,
}

impl BiasRandomWalk {
    /// Gyro bias walk of intensity `intensity_radps_per_sqrt_s` (rad/s/sqrt(s)).
    pub fn gyro(intensity_radps_per_sqrt_s: Vec3, correlation_s: f64, seed: u64) -> Self {
        Self::new(
            "gyro_bias_random_walk",
            true,
            intensity_radps_per_sqrt_s,
            correlation_s,
            seed,
            GYRO_STREAM,
        )
    }

    /// Accelerometer bias walk of intensity `intensity_mps2_per_sqrt_s` (m/s^2/sqrt(s)).
    pub fn accel(intensity_mps2_per_sqrt_s: Vec3, correlation_s: f64, seed: u64) -> Self {
        Self::new(
            "accel_bias_random_walk",
            false,
            intensity_mps2_per_sqrt_s,
            correlation_s,
            seed,
            ACCEL_STREAM,
        )
    }

    fn new(
        name: &'static str,
        on_gyro: bool,
        intensity: Vec3,
        correlation_s: f64,
        seed: u64,
        stream_base: u64,
    ) -> Self {
        Self {
            name,
            on_gyro,
            intensity,
            correlation_s,
            seed,
            stream_base,
            rngs: std::array::from_fn(|j| Normal::new(seed, stream_base + j as u64)),
            bias: Vec3::zeros(),
        }
    }

    /// Current bias (rad/s or m/s^2).
    pub fn bias(&self) -> Vec3 {
        self.bias
    }

    /// `(φ, drive)` for a step of `dt_s`: the decay and the std of the drive per unit intensity.
    fn step_factors(&self, dt_s: f64) -> (f64, f64) {
        if self.correlation_s.is_infinite() {
            return (1.0, dt_s.sqrt());
        }
        let x = dt_s / self.correlation_s;
        (
            (-x).exp(),
            (-(-2.0 * x).exp_m1() * 0.5 * self.correlation_s).sqrt(),
        )
    }
}

impl ExtraEffect for BiasRandomWalk {
    fn name(&self) -> &'static str {
        self.name
    }

    fn apply(&mut self, ctx: &EffectContext, dtheta: &mut Vec3, dv: &mut Vec3) {
        let target = if self.on_gyro { dtheta } else { dv };
        *target += self.bias * ctx.dt_s;
        let (phi, drive) = self.step_factors(ctx.dt_s);
        for j in 0..3 {
            let w = self.rngs[j].next();
            self.bias[j] = phi * self.bias[j] + self.intensity[j] * drive * w;
        }
    }

    fn reset(&mut self) {
        *self = Self::new(
            self.name,
            self.on_gyro,
            self.intensity,
            self.correlation_s,
            self.seed,
            self.stream_base,
        );
    }
}

/// Standard normal deviates by the Box-Muller transform from one ChaCha8 stream.
#[derive(Clone, Debug)]
struct Normal {
    rng: ChaCha8Rng,
    spare: Option<f64>,
}

impl Normal {
    fn new(seed: u64, stream: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(stream);
        Self { rng, spare: None }
    }

    fn next(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        // u1 in (0, 1], u2 in [0, 1).
        let u1 = ((self.rng.next_u64() >> 11) + 1) as f64 * (1.0 / (1u64 << 53) as f64);
        let u2 = (self.rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
        let r = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * u2).sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Final bias of `n` samples of a walk of `q` on x with `seed`.
    fn final_bias(q: f64, correlation_s: f64, seed: u64, n: usize, h: f64) -> (f64, f64) {
        let mut e = BiasRandomWalk::gyro(Vec3::new(q, 0.0, 0.0), correlation_s, seed);
        let ctx = EffectContext::at_rest(0.0, h, [20.0; 3]);
        let mut angle = 0.0;
        for _ in 0..n {
            let (d, dv) = e.perturbation(&ctx);
            assert_eq!(dv, Vec3::zeros());
            assert_eq!((d.y, d.z), (0.0, 0.0));
            angle += d.x;
        }
        (e.bias().x, angle)
    }

    #[test]
    fn walk_is_seeded_deterministic_and_linear_for_a_fixed_seed() {
        let a = final_bias(1e-6, f64::INFINITY, 7, 2000, 0.005);
        assert_eq!(a, final_bias(1e-6, f64::INFINITY, 7, 2000, 0.005));
        assert_ne!(a, final_bias(1e-6, f64::INFINITY, 8, 2000, 0.005));
        let b = final_bias(2e-6, f64::INFINITY, 7, 2000, 0.005);
        assert_eq!((b.0, b.1), (2.0 * a.0, 2.0 * a.1));
    }

    #[test]
    fn walk_spread_grows_as_sqrt_time_and_gauss_markov_saturates() {
        // Across 400 seeds, the std of the bias after t = 1000 s (steps of 1 s) is q sqrt(t)
        // for the walk and q sqrt(τ/2 (1 - e^{-2t/τ})) for a Gauss-Markov of τ = 100 s.
        let q = 1.0;
        let (n, seeds) = (1000, 400);
        let var = |corr: f64| {
            (0..seeds)
                .map(|s| final_bias(q, corr, s, n, 1.0).0.powi(2))
                .sum::<f64>()
                / seeds as f64
        };
        let walk = var(f64::INFINITY);
        // Relative standard error of a variance from 400 samples: sqrt(2/400) = 7 %.
        assert!((walk / 1000.0 - 1.0).abs() < 0.25, "{walk}");
        let gm = var(100.0);
        let want = 50.0 * (1.0 - (-20.0f64).exp());
        assert!((gm / want - 1.0).abs() < 0.25, "{gm} vs {want}");
    }

    #[test]
    fn reset_replays_the_same_realisation() {
        let mut e = BiasRandomWalk::accel(Vec3::new(1e-5, 2e-5, 3e-5), f64::INFINITY, 3);
        let ctx = EffectContext::at_rest(0.0, 0.005, [20.0; 3]);
        let first: Vec<_> = (0..100).map(|_| e.perturbation(&ctx)).collect();
        e.reset();
        let second: Vec<_> = (0..100).map(|_| e.perturbation(&ctx)).collect();
        assert_eq!(first, second);
        assert!(first.iter().all(|(d, _)| *d == Vec3::zeros()));
    }
}
