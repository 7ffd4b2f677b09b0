//! The Allan-variance estimator against closed forms: white rate noise (σ²/τ), a random walk of
//! the rate (K²τ/3) and a quantised ramp (the sawtooth model of `quant`). Statistical bounds are
//! 4 standard deviations of the chi-square law with the estimator's equivalent degrees of
//! freedom (a false failure about once in 16 000 runs per assertion; the seeds are fixed, so a
//! run is deterministic).

use sins_noiseid::allan::{NoiseType, PooledTau, edf, overlapping_avar, second_difference_sum};
use sins_noiseid::quant::ramp_quantization_avar;
use sins_sim::{GaussianStream, Quantizer};

fn cumulative(increments: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut x = vec![0.0];
    let mut s = 0.0;
    for v in increments {
        s += v;
        x.push(s);
    }
    x
}

#[test]
fn white_rate_noise_has_allan_variance_sigma2_over_tau() {
    let h: f64 = 0.01;
    let density = 3e-3; // rad/√s
    let mut g = GaussianStream::new(7, 1);
    let n = 400_000;
    let x = cumulative((0..n).map(|_| density * h.sqrt() * g.next_standard()));
    for m in [1usize, 4, 16, 64, 256, 1024] {
        let tau = m as f64 * h;
        let avar = overlapping_avar(&x, m, h).unwrap_or(f64::NAN);
        let expected = density * density / tau;
        let nu = edf(NoiseType::WhiteFrequency, x.len() as u64, m as u64);
        let z = (avar / expected - 1.0) / (2.0 / nu).sqrt();
        assert!(
            z.abs() < 4.0,
            "m {m}: avar {avar:e} vs {expected:e}, z {z:.2}"
        );
    }
}

#[test]
fn rate_random_walk_has_allan_variance_k2_tau_over_3() {
    let h: f64 = 0.1;
    let k = 2e-4; // rate unit/√s
    let m = 64usize;
    let mut pooled = PooledTau {
        tau_s: m as f64 * h,
        ..PooledTau::default()
    };
    for rep in 0..60u64 {
        let mut g = GaussianStream::new(100 + rep, 1);
        let mut rate = 0.0;
        let x = cumulative((0..20_000).map(|_| {
            rate += k * h.sqrt() * g.next_standard();
            rate * h
        }));
        let (ss, cnt) = second_difference_sum(&x, m);
        pooled.add(rep as usize, ss, cnt, x.len() as u64, m as u64);
    }
    let avar = pooled.avar().unwrap_or(f64::NAN);
    // Discrete walk of sample means: K²τ/3 + K²h/(6m).
    let tau = m as f64 * h;
    let expected = k * k * tau / 3.0 + k * k * h / (6.0 * m as f64);
    let nu = pooled.edf(NoiseType::RandomWalkFrequency);
    let z = (avar / expected - 1.0) / (2.0 / nu).sqrt();
    assert!(
        z.abs() < 4.0,
        "avar {avar:e} vs {expected:e}, edf {nu:.0}, z {z:.2}"
    );
}

#[test]
fn quantised_ramp_follows_the_sawtooth_model_not_3q2_over_tau2() {
    let h = 0.005;
    let q = 4.848_136_811_095_36e-6; // 1 arcsec
    let w = q / 0.37; // one quantum per 0.37 s
    let mut quant = Quantizer::new(q);
    let n = 400_000; // 2000 s, 5400 quantum periods
    let x = cumulative((0..n).map(|_| quant.apply(w * h)));
    let mut below = 0;
    for m in [1usize, 2, 4, 8, 16, 32, 64, 128, 256, 512] {
        let tau = m as f64 * h;
        let avar = overlapping_avar(&x, m, h).unwrap_or(f64::NAN);
        let model = ramp_quantization_avar(q, w, tau, 0.0, 0.0);
        let white = 3.0 * q * q / 12.0 / (tau * tau);
        // Deterministic data: the average over thousands of quantum periods matches the
        // start-phase average to a few per cent of the white level.
        assert!(
            (avar - model).abs() < 0.03 * white,
            "m {m}: avar {avar:e}, model {model:e}, white {white:e}"
        );
        if avar < 0.5 * white {
            below += 1;
        }
    }
    // At τ well below the quantum period the white formula overstates the variance.
    assert!(below >= 5, "only {below} points below half the white level");
}
