//! Quantization at rest: a laser gyro's pulse counting, or an accelerometer's velocity pulses
//! (the same model in m/s, its ramp the specific force along the axis).
//!
//! Pulse counting outputs whole quanta `q` and carries the remainder, so the cumulative output
//! is the cumulative input rounded: the angle error `e_k` is the rounding error of the
//! cumulative input, `|e_k| ≤ q/2`. Its Allan variance is `(6C(0) − 8C(τ) + 2C(2τ))/(2τ²)`
//! with `C` the autocovariance of `e`. When the input moves by many quanta between samples
//! (vibration) `e` is white with variance `q²/12` and this is the textbook `3Q²/τ²`,
//! `Q = q/√12`. At rest it is not: the input is a slow ramp (Earth rate, about one quantum per
//! 0.2-1 s) and `e` a sawtooth of the phase `u = θ/q`, whose autocovariance at a lag of `a`
//! cycles is `C₀(a) = q² (1/12 − f(1 − f)/2)`, `f = frac(a)`. A quantised ramp therefore has
//! an Allan variance far below `3Q²/τ²` at `τ` shorter than a quantum's period and oscillating
//! around it beyond. The lag `a = ω τ / q` is blurred by the angle random walk, the bias wander
//! and the uncertainty of the mean rate `ω`; with a Gaussian blur of `s` cycles
//! `C_s(a) = E[C₀(a + s z)]`, computed exactly here (truncated normal moments of the
//! periodic parabola). For blurs beyond two cycles `C_s = 0` and the white value holds.
//!
//! The quantum itself is read from the data: quantised increments are whole multiples of `q`
//! ([`LatticeDetector`]).

use sins_diag::normal_cdf;

fn normal_pdf(x: f64) -> f64 {
    (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

/// `E[w(1 − w); 0 ≤ w < 1]` for `w ~ N(mu, s²)`.
fn parabola_piece(mu: f64, s: f64) -> f64 {
    let (a, b) = ((0.0 - mu) / s, (1.0 - mu) / s);
    let p = normal_cdf(b) - normal_cdf(a);
    let (pa, pb) = (normal_pdf(a), normal_pdf(b));
    let e1 = mu * p + s * (pa - pb);
    let e2 = mu * mu * p + 2.0 * mu * s * (pa - pb) + s * s * (p + a * pa - b * pb);
    e1 - e2
}

/// Autocovariance (rad²) of the rounding error of a ramp with quantum `q_rad` at a lag of
/// `a_cycles` quanta, blurred by a Gaussian of `blur_cycles` (see the module doc).
pub fn sawtooth_autocovariance(q_rad: f64, a_cycles: f64, blur_cycles: f64) -> f64 {
    let f = a_cycles - a_cycles.floor();
    let g = if blur_cycles <= 1e-9 {
        f * (1.0 - f)
    } else if blur_cycles > 2.0 {
        1.0 / 6.0
    } else {
        // Sum over the periods that the blurred lag reaches (±9 sigma).
        let lo = (f - 9.0 * blur_cycles).floor() as i64;
        let hi = (f + 9.0 * blur_cycles).ceil() as i64;
        (lo..=hi)
            .map(|k| parabola_piece(f - k as f64, blur_cycles))
            .sum()
    };
    q_rad * q_rad * (1.0 / 12.0 - 0.5 * g)
}

/// Expected Allan variance ((rad/s)²) of the quantization error of a gyro at rest turning at
/// `rate_radps` (its axis' mean rate: Earth rate plus bias) with quantum `q_rad`, at `τ`; the
/// lag blur grows with `τ` as `blur² = (N² τ + (δω τ)²)/q²` for angle random walk `N`
/// (rad/√s) and a rate uncertainty `δω` (rad/s; bias wander, error of the mean rate).
pub fn ramp_quantization_avar(
    q_rad: f64,
    rate_radps: f64,
    tau_s: f64,
    arw_rad_per_sqrt_s: f64,
    rate_uncertainty_radps: f64,
) -> f64 {
    if q_rad <= 0.0 || tau_s <= 0.0 {
        return 0.0;
    }
    let blur = |t: f64| {
        ((arw_rad_per_sqrt_s.powi(2) * t + (rate_uncertainty_radps * t).powi(2)).sqrt()) / q_rad
    };
    let a = rate_radps.abs() * tau_s / q_rad;
    let c0 = q_rad * q_rad / 12.0;
    let c1 = sawtooth_autocovariance(q_rad, a, blur(tau_s));
    let c2 = sawtooth_autocovariance(q_rad, 2.0 * a, blur(2.0 * tau_s));
    ((6.0 * c0 - 8.0 * c1 + 2.0 * c2) / (2.0 * tau_s * tau_s)).max(0.0)
}

/// Finds the common quantum of a stream of increments: the floating-point greatest common
/// divisor of their magnitudes (Euclid with a relative tolerance). Quantised data give the
/// quantum; continuous data collapse to a tiny value and are reported as not quantised.
///
/// The lattice is also checked over every sample offered to [`LatticeDetector::check`]: the
/// GCD of the first [`LATTICE_PROBE`] non-zero increments is the candidate quantum, and every
/// later increment is counted on or off its lattice. A lattice that holds for only part of the
/// data (an output corrected in floating point from some point on), or only by chance (every
/// increment the same multiple, as a noise-free unquantised ramp gives), is not a quantum:
/// [`LatticeDetector::quantum`] is then `None` and [`LatticeDetector::coverage`] says why.
#[derive(Clone, Debug, Default)]
pub struct LatticeDetector {
    gcd: f64,
    max_abs: f64,
    broken: bool,
    /// The first non-zero magnitudes, until the candidate is fixed.
    probe: Vec<f64>,
    /// The candidate quantum (GCD of the probe).
    candidate: Option<f64>,
    on: u64,
    off: u64,
    /// Distinct multiples of the candidate seen (up to 4).
    multiples: Vec<u64>,
}

/// Non-zero increments whose GCD fixes the candidate quantum of the coverage check.
pub const LATTICE_PROBE: usize = 4096;
/// Largest fraction of increments off the lattice for it to count as the output's quantum.
pub const LATTICE_MAX_OFF_FRACTION: f64 = 1e-4;

/// How well the increments sit on a lattice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LatticeCoverage {
    /// The candidate quantum (input unit).
    pub quantum: f64,
    /// Increments checked.
    pub checked: u64,
    /// Of those, off the lattice.
    pub off: u64,
    /// Distinct multiples of the quantum seen (at most 4 counted).
    pub multiples: usize,
}

impl LatticeCoverage {
    /// Fraction of the increments on the lattice.
    pub fn fraction_on(&self) -> f64 {
        if self.checked == 0 {
            0.0
        } else {
            1.0 - self.off as f64 / self.checked as f64
        }
    }

    /// Whether the lattice holds for (nearly) every increment and is more than chance.
    pub fn holds(&self) -> bool {
        self.checked > 0
            && (self.off as f64) <= LATTICE_MAX_OFF_FRACTION * self.checked as f64
            && self.multiples >= 2
    }
}

/// Relative tolerance of the floating-point GCD (quantised outputs are `n·q` rounded once).
const GCD_TOLERANCE: f64 = 1e-7;
/// Most quanta per sample accepted as a lattice.
const MAX_QUANTA: f64 = 1000.0;

impl LatticeDetector {
    /// Feed one increment of the data the quantum is read from (also checked for coverage).
    #[inline]
    pub fn push(&mut self, x: f64) {
        self.check(x);
        if self.broken {
            return;
        }
        let v = x.abs();
        if !v.is_finite() {
            self.broken = true;
            return;
        }
        if v == 0.0 {
            return;
        }
        self.max_abs = self.max_abs.max(v);
        self.gcd = if self.gcd == 0.0 {
            v
        } else {
            fgcd(self.gcd, v)
        };
        if self.gcd * MAX_QUANTA < self.max_abs {
            self.broken = true;
        }
    }

    /// Count one increment on or off the candidate lattice (any sample, still or moving).
    #[inline]
    pub fn check(&mut self, x: f64) {
        let v = x.abs();
        if !v.is_finite() {
            self.off += 1;
            return;
        }
        let Some(q) = self.candidate else {
            if v > 0.0 {
                self.probe.push(v);
                if self.probe.len() >= LATTICE_PROBE {
                    self.fix_candidate();
                }
            } else {
                // Zero is on every lattice.
                self.count(0.0, 1.0);
            }
            return;
        };
        self.count(v, q);
    }

    fn count(&mut self, v: f64, q: f64) {
        let m = v / q;
        let r = m.round();
        if (m - r).abs() <= 1e-6 * r.max(1.0) {
            self.on += 1;
            let k = r as u64;
            if self.multiples.len() < 4 && !self.multiples.contains(&k) {
                self.multiples.push(k);
            }
        } else {
            self.off += 1;
        }
    }

    fn fix_candidate(&mut self) {
        let q = self
            .probe
            .iter()
            .fold(0.0, |g, &v| if g == 0.0 { v } else { fgcd(g, v) });
        let probe = std::mem::take(&mut self.probe);
        if q > 0.0 {
            self.candidate = Some(q);
            for v in probe {
                self.count(v, q);
            }
        }
    }

    /// The coverage of the candidate lattice so far (`None` before any non-zero increment).
    pub fn coverage(&self) -> Option<LatticeCoverage> {
        let mut d = self.clone();
        if d.candidate.is_none() {
            d.fix_candidate();
        }
        d.candidate.map(|q| LatticeCoverage {
            quantum: q,
            checked: d.on + d.off,
            off: d.off,
            multiples: d.multiples.len(),
        })
    }

    /// The quantum (same unit as the input) if the increments lie on a lattice of at most
    /// 1000 quanta per sample, at least one non-zero increment was seen, and the coverage check
    /// holds (see the type's doc).
    pub fn quantum(&self) -> Option<f64> {
        if self.broken || self.gcd <= 0.0 {
            return None;
        }
        self.coverage()
            .is_some_and(|c| c.holds())
            .then_some(self.gcd)
    }

    /// The candidate quantum (from the first non-zero increments) of a lattice that holds for at
    /// least half of the increments but not all (an output corrected in floating point from
    /// some point on still carries the rounding of its lattice); `None` when the lattice holds throughout ([`LatticeDetector::quantum`]) or
    /// for less than half, or is chance (a single multiple).
    pub fn partial_quantum(&self) -> Option<f64> {
        self.coverage()
            .filter(|c| !c.holds() && c.multiples >= 2 && c.fraction_on() >= 0.5)
            .map(|c| c.quantum)
    }
}

fn fgcd(a: f64, b: f64) -> f64 {
    let (mut a, mut b) = if a >= b { (a, b) } else { (b, a) };
    let tol = GCD_TOLERANCE * b;
    for _ in 0..64 {
        if b <= tol {
            return a;
        }
        let r = a - (a / b).round() * b;
        let r = r.abs();
        (a, b) = (b, r);
    }
    0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blurred_autocovariance_tends_to_the_sharp_one_and_to_zero() {
        let q = 1.0;
        for a in [0.0, 0.1, 0.37, 0.5, 0.93] {
            let sharp = sawtooth_autocovariance(q, a, 0.0);
            let nearly = sawtooth_autocovariance(q, a, 1e-4);
            assert!((sharp - nearly).abs() < 1e-4, "{a}: {sharp} {nearly}");
            // Exactly about 1e-20 (Fourier terms decay as exp(-2π²b²k²)); the CDF differences
            // of statrs' erfc leave a few 1e-11 (4e-10 of the variance q²/12).
            let far = sawtooth_autocovariance(q, a, 1.5);
            assert!(far.abs() < 1e-9, "{a}: {far}");
        }
        // Zero lag: the variance of a uniform rounding error, q²/12.
        assert!((sawtooth_autocovariance(q, 0.0, 0.0) - 1.0 / 12.0).abs() < 1e-15);
    }

    #[test]
    fn lattice_detector_finds_the_quantum_and_rejects_continuous_data() {
        let q = 4.848_136_811_095_36e-6;
        let mut d = LatticeDetector::default();
        for n in [0i32, 1, -1, 3, 0, 2, 7, -2] {
            d.push(f64::from(n) * q);
        }
        let got = d.quantum().unwrap_or(0.0);
        assert!((got / q - 1.0).abs() < 1e-9, "{got}");
        let mut c = LatticeDetector::default();
        for k in 0..1000 {
            c.push(5e-8 + 1e-8 * (f64::from(k) * 0.7).sin());
        }
        assert_eq!(c.quantum(), None);
    }

    #[test]
    fn a_lattice_that_holds_for_half_the_data_is_reported_and_not_used() {
        let q = 4.848_136_811_095_36e-6; // 1 arcsec
        let rate = 0.37 * q; // quanta per sample: a gyro at rest, 0 or 1 quantum each
        let mut d = LatticeDetector::default();
        let mut angle = 0.0f64;
        let mut out = 0.0f64;
        for k in 0..200_000 {
            angle += rate + 0.05 * q * ((k as f64) * 0.913).sin();
            if k < 100_000 {
                // Pulse counting: whole quanta, remainder carried.
                let n = ((angle - out) / q).floor();
                out += n * q;
                d.push(n * q);
            } else {
                // From here on corrected in floating point: off the lattice.
                d.push(rate * 1.000_123);
            }
        }
        let c = d.coverage().unwrap();
        assert!(
            (c.quantum / q - 1.0).abs() < 1e-9,
            "candidate {}",
            c.quantum / q
        );
        assert!((c.fraction_on() - 0.5).abs() < 0.01, "{}", c.fraction_on());
        assert!(!c.holds());
        assert_eq!(d.quantum(), None);
        // The whole run on the lattice: the quantum, and a coverage of 1.
        let mut e = LatticeDetector::default();
        let (mut angle, mut out) = (0.0f64, 0.0f64);
        for k in 0..200_000 {
            angle += rate + 0.05 * q * ((k as f64) * 0.913).sin();
            let n = ((angle - out) / q).floor();
            out += n * q;
            e.push(n * q);
        }
        assert!((e.quantum().unwrap() / q - 1.0).abs() < 1e-9);
        assert_eq!(e.coverage().unwrap().off, 0);
    }

    #[test]
    fn a_smooth_noise_free_output_is_no_lattice() {
        // Every increment the same value (an unquantised, noise-free ramp): one multiple.
        let mut d = LatticeDetector::default();
        for _ in 0..10_000 {
            d.push(3.3e-7);
        }
        let c = d.coverage().unwrap();
        assert_eq!((c.off, c.multiples), (0, 1));
        assert_eq!(d.quantum(), None);
    }
}
