//! Seeded, deterministic sensor noise. Every noise source draws from its own ChaCha8 stream of
//! the scenario seed (same key, different stream id), so enabling or changing one source never
//! changes the numbers of another.
//!
//! - gyro angle random walk: white noise of σ = ARW·√dt per sample and axis (rad);
//! - gyro bias instability: first-order Gauss-Markov bias with stationary σ and correlation time
//!   τ, discretised exactly (`b_{k+1} = e^{−dt/τ} b_k + σ √(1 − e^{−2dt/τ}) w_k`, b_0 ~ N(0, σ²);
//!   τ = ∞ is a random constant), integrated over the sample as `b_k · dt`;
//! - accelerometer velocity random walk and Gauss-Markov bias, likewise;
//! - laser-gyro quantization: pulse counting with the remainder carried, applied last.

use crate::error::{SimError, non_negative_reason};
pub use crate::gaussian::GaussianStream;
use crate::scenario::NoiseModel;
use sins_nav::Vec3;

/// Stream ids of the noise sources (the ChaCha stream number under the scenario seed).
pub mod stream {
    /// Gyro angle random walk.
    pub const GYRO_WHITE: u64 = 1;
    /// Gyro Gauss-Markov bias.
    pub const GYRO_BIAS: u64 = 2;
    /// Accelerometer velocity random walk.
    pub const ACCEL_WHITE: u64 = 3;
    /// Accelerometer Gauss-Markov bias.
    pub const ACCEL_BIAS: u64 = 4;
    /// Thermometer white noise.
    pub const THERMOMETER: u64 = 5;
}

/// Peak of the Allan deviation of a first-order Gauss-Markov process, as a fraction of its
/// stationary standard deviation σ: `max_T σ_A(T)/σ = 0.6174` (reached at `T ≈ 1.89 τ`), from
/// `σ_A²(T) = σ² (τ/T)² (2T/τ − 3 + 4e^{−T/τ} − e^{−2T/τ})`. A datasheet "bias instability" B read
/// off an Allan plot therefore corresponds to a Gauss-Markov σ of `B / GM_ALLAN_PEAK_RATIO`.
pub const GM_ALLAN_PEAK_RATIO: f64 = 0.617_364_283;

/// Allan deviation (same unit as `sigma`) of a first-order Gauss-Markov process with stationary
/// std `sigma` and correlation time `tau_s`, at averaging time `t_s`.
pub fn gauss_markov_allan_deviation(sigma: f64, tau_s: f64, t_s: f64) -> f64 {
    let x = t_s / tau_s;
    sigma * ((2.0 * x - 3.0 + 4.0 * (-x).exp() - (-2.0 * x).exp()) / (x * x)).sqrt()
}

/// Gauss-Markov stationary σ whose Allan-deviation peak equals the bias-instability figure `b`.
pub fn gauss_markov_sigma_from_allan(b: f64) -> f64 {
    b / GM_ALLAN_PEAK_RATIO
}

/// First-order Gauss-Markov process sampled every `dt`, exactly discretised.
#[derive(Clone, Debug)]
pub struct GaussMarkov {
    phi: f64,
    drive_sigma: f64,
    value: f64,
}

impl GaussMarkov {
    /// Process of stationary std `sigma` and correlation time `correlation_s` (may be infinite:
    /// a random constant) sampled every `dt_s`; the initial value is drawn from the stationary
    /// distribution.
    pub fn new(sigma: f64, correlation_s: f64, dt_s: f64, gauss: &mut GaussianStream) -> Self {
        let x = dt_s / correlation_s;
        Self {
            phi: (-x).exp(),
            drive_sigma: sigma * (-(-2.0 * x).exp_m1()).sqrt(),
            value: sigma * gauss.next_standard(),
        }
    }

    /// Current value.
    #[inline]
    pub fn value(&self) -> f64 {
        self.value
    }

    /// Advance by one sample interval.
    #[inline]
    pub fn step(&mut self, gauss: &mut GaussianStream) {
        self.value = self.phi * self.value + self.drive_sigma * gauss.next_standard();
    }
}

/// Pulse counting of a laser gyro: outputs integer multiples of the quantum and carries the
/// remainder, so the cumulative output never differs from the cumulative input by more than half
/// a quantum.
#[derive(Clone, Copy, Debug)]
pub struct Quantizer {
    quantum: f64,
    remainder: f64,
}

impl Quantizer {
    /// Quantizer of `quantum` (same unit as the input, > 0).
    pub fn new(quantum: f64) -> Self {
        Self {
            quantum,
            remainder: 0.0,
        }
    }

    /// Output for input increment `x`: `round((carried + x)/q)·q`.
    #[inline]
    pub fn apply(&mut self, x: f64) -> f64 {
        /// 1.5 · 2^52: adding and subtracting it rounds to the nearest integer below 2^51.
        const MAGIC: f64 = 6_755_399_441_055_744.0;
        let total = self.remainder + x;
        let pulses = total / self.quantum;
        let pulses = if pulses.abs() < 2.0e15 {
            (pulses + MAGIC) - MAGIC
        } else {
            pulses.round()
        };
        let out = pulses * self.quantum;
        self.remainder = total - out;
        out
    }

    /// Input accumulated but not yet output (cumulative input − cumulative output).
    pub fn remainder(&self) -> f64 {
        self.remainder
    }
}

/// White noise and Gauss-Markov bias of one sensor triad.
#[derive(Clone, Debug)]
struct Triad {
    white_sigma: f64,
    white: GaussianStream,
    bias: Option<([GaussMarkov; 3], GaussianStream)>,
}

impl Triad {
    fn new(seed: u64, streams: (u64, u64), density: f64, bias: (f64, f64), dt_s: f64) -> Self {
        let (white_id, bias_id) = streams;
        let (sigma, tau) = bias;
        Self {
            white_sigma: density * dt_s.sqrt(),
            white: GaussianStream::new(seed, white_id),
            bias: (sigma > 0.0).then(|| {
                let mut g = GaussianStream::new(seed, bias_id);
                let gm = std::array::from_fn(|_| GaussMarkov::new(sigma, tau, dt_s, &mut g));
                (gm, g)
            }),
        }
    }

    /// Add the noise of one sample to `x` (an increment over `dt_s`).
    #[inline]
    fn apply(&mut self, x: &mut Vec3, dt_s: f64) {
        if self.white_sigma > 0.0 {
            for c in x.iter_mut() {
                *c += self.white_sigma * self.white.next_standard();
            }
        }
        if let Some((gm, g)) = &mut self.bias {
            for (c, b) in x.iter_mut().zip(gm.iter_mut()) {
                *c += b.value() * dt_s;
                b.step(g);
            }
        }
    }
}

/// All IMU noise of a scenario, applied to raw increments after the error model.
#[derive(Clone, Debug)]
pub struct SensorNoise {
    dt_s: f64,
    gyro: Triad,
    accel: Triad,
    quantizers: Option<[Quantizer; 3]>,
}

fn check(field: &'static str, r: Option<String>) -> Result<(), SimError> {
    r.map_or(Ok(()), |reason| Err(SimError::Field { field, reason }))
}

fn check_correlation(field: &'static str, sigma: f64, tau: f64) -> Result<(), SimError> {
    // NaN must fail too, hence no `tau <= 0.0`.
    let bad = sigma > 0.0 && tau.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
    check(
        field,
        bad.then(|| format!("must be positive (or infinite), got {tau}")),
    )
}

impl SensorNoise {
    /// Validate `model` and set up the streams of `seed` for samples every `dt_s` seconds.
    pub fn new(model: &NoiseModel, seed: u64, dt_s: f64) -> Result<Self, SimError> {
        let m = model;
        check(
            "noise.gyro_arw_rad_per_sqrt_s",
            non_negative_reason(m.gyro_arw_rad_per_sqrt_s),
        )?;
        let gb = m.gyro_bias_instability_radps;
        check("noise.gyro_bias_instability_radps", non_negative_reason(gb))?;
        check_correlation(
            "noise.gyro_bias_correlation_s",
            gb,
            m.gyro_bias_correlation_s,
        )?;
        check(
            "noise.gyro_quantum_rad",
            non_negative_reason(m.gyro_quantum_rad),
        )?;
        let vrw = m.accel_vrw_mps_per_sqrt_s;
        check("noise.accel_vrw_mps_per_sqrt_s", non_negative_reason(vrw))?;
        let ab = m.accel_bias_instability_mps2;
        check("noise.accel_bias_instability_mps2", non_negative_reason(ab))?;
        check_correlation(
            "noise.accel_bias_correlation_s",
            ab,
            m.accel_bias_correlation_s,
        )?;
        let gyro_streams = (stream::GYRO_WHITE, stream::GYRO_BIAS);
        let accel_streams = (stream::ACCEL_WHITE, stream::ACCEL_BIAS);
        Ok(Self {
            dt_s,
            gyro: Triad::new(
                seed,
                gyro_streams,
                m.gyro_arw_rad_per_sqrt_s,
                (gb, m.gyro_bias_correlation_s),
                dt_s,
            ),
            accel: Triad::new(
                seed,
                accel_streams,
                vrw,
                (ab, m.accel_bias_correlation_s),
                dt_s,
            ),
            quantizers: (m.gyro_quantum_rad > 0.0).then(|| [Quantizer::new(m.gyro_quantum_rad); 3]),
        })
    }

    /// Add the noise of one sample to raw increments, quantizing the gyro output last.
    #[inline]
    pub fn apply(&mut self, dtheta_rad: &mut Vec3, dv_mps: &mut Vec3) {
        self.gyro.apply(dtheta_rad, self.dt_s);
        self.accel.apply(dv_mps, self.dt_s);
        if let Some(q) = &mut self.quantizers {
            for (c, q) in dtheta_rad.iter_mut().zip(q.iter_mut()) {
                *c = q.apply(*c);
            }
        }
    }
}

#[cfg(test)]
mod allan_tests {
    use super::*;

    #[test]
    fn allan_peak_of_gauss_markov_is_0_6174_sigma_at_1_89_tau() {
        let (mut best, mut at) = (0.0, 0.0);
        for i in 1..100_000 {
            let t = i as f64 * 1e-4;
            let a = gauss_markov_allan_deviation(1.0, 1.0, t);
            if a > best {
                (best, at) = (a, t);
            }
        }
        assert!((best - GM_ALLAN_PEAK_RATIO).abs() < 1e-7, "peak {best}");
        assert!((at - 1.89).abs() < 0.01, "at {at} tau");
        let b = 0.005;
        let sigma = gauss_markov_sigma_from_allan(b);
        assert!((gauss_markov_allan_deviation(sigma, 3600.0, 1.8926 * 3600.0) - b).abs() < 1e-9);
    }
}
