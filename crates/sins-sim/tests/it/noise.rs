//! Statistics of the sensor noise: white noise, Gauss-Markov bias, quantization.

use sins_nav::{ARCSEC, DEG, UG, Vec3};
use sins_sim::{GaussMarkov, GaussianStream, NoiseModel, Quantizer, SensorNoise};

fn std_of(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n).sqrt()
}

#[test]
fn white_noise_per_sample_std_is_density_times_sqrt_dt() {
    let dt = 0.005;
    let arw = 0.001 * DEG / 60.0; // 0.001 deg/sqrt(h)
    let vrw = 10.0 * UG; // 10 ug/sqrt(Hz)
    let model = NoiseModel {
        gyro_arw_rad_per_sqrt_s: arw,
        accel_vrw_mps_per_sqrt_s: vrw,
        ..NoiseModel::default()
    };
    let mut noise = SensorNoise::new(&model, 11, dt).unwrap();
    let n = 200_000;
    let mut g = [
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    ];
    let mut a = [
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::with_capacity(n),
    ];
    for _ in 0..n {
        let (mut th, mut v) = (Vec3::zeros(), Vec3::zeros());
        noise.apply(&mut th, &mut v);
        for j in 0..3 {
            g[j].push(th[j]);
            a[j].push(v[j]);
        }
    }
    for j in 0..3 {
        let sg = std_of(&g[j]) / (arw * dt.sqrt());
        let sa = std_of(&a[j]) / (vrw * dt.sqrt());
        assert!((sg - 1.0).abs() < 0.03, "gyro axis {j}: ratio {sg}");
        assert!((sa - 1.0).abs() < 0.03, "accel axis {j}: ratio {sa}");
    }
    // Independent axes and sources: the correlation of gyro x with gyro y and accel x is ~0.
    let corr = |x: &[f64], y: &[f64]| {
        x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>() / (n as f64 * std_of(x) * std_of(y))
    };
    assert!(corr(&g[0], &g[1]).abs() < 0.01);
    assert!(corr(&g[0], &a[0]).abs() < 0.01);
}

#[test]
fn gauss_markov_has_stationary_std_and_exponential_autocorrelation() {
    let (sigma, tau, dt) = (2.0, 0.5, 0.005); // correlation 100 samples
    let mut gauss = GaussianStream::new(3, 4);
    let mut gm = GaussMarkov::new(sigma, tau, dt, &mut gauss);
    let n = 2_000_000;
    let mut x = Vec::with_capacity(n);
    for _ in 0..n {
        x.push(gm.value());
        gm.step(&mut gauss);
    }
    let s = std_of(&x);
    assert!((s / sigma - 1.0).abs() < 0.03, "stationary std {s}");
    let acf = |lag: usize| {
        let num: f64 = x.iter().zip(&x[lag..]).map(|(a, b)| a * b).sum();
        num / ((n - lag) as f64 * s * s)
    };
    let r1 = acf(1);
    assert!((r1 - (-dt / tau).exp()).abs() < 1e-3, "lag-1 {r1}");
    let r100 = acf(100);
    assert!((r100 - (-1.0f64).exp()).abs() < 0.03, "lag-100 {r100}");
    // The initial value is drawn from the stationary law: across streams its std is sigma.
    let first: Vec<f64> = (0..20_000)
        .map(|s| GaussMarkov::new(sigma, tau, dt, &mut GaussianStream::new(s, 4)).value())
        .collect();
    assert!((std_of(&first) / sigma - 1.0).abs() < 0.03);
}

#[test]
fn infinite_correlation_time_is_a_random_constant() {
    let mut gauss = GaussianStream::new(8, 2);
    let mut gm = GaussMarkov::new(1e-6, f64::INFINITY, 0.005, &mut gauss);
    let b0 = gm.value();
    assert!(b0 != 0.0);
    for _ in 0..1000 {
        gm.step(&mut gauss);
    }
    assert_eq!(gm.value(), b0);
}

#[test]
fn quantized_output_is_whole_pulses_and_never_drifts() {
    let q = 1.5 * ARCSEC;
    let mut quant = Quantizer::new(q);
    let mut gauss = GaussianStream::new(21, 7);
    let (mut cum_in, mut cum_out) = (0.0f64, 0.0f64);
    let mut worst = 0.0f64;
    for k in 0..500_000 {
        // Mix of sub-pulse and multi-pulse increments with a slow drift.
        let x = 0.7 * q * gauss.next_standard() + 3e-3 * q * (k as f64 * 1e-3).sin();
        let y = quant.apply(x);
        let pulses = y / q;
        assert!(
            (pulses - pulses.round()).abs() < 1e-9,
            "not whole pulses: {pulses}"
        );
        cum_in += x;
        cum_out += y;
        worst = worst.max((cum_out - cum_in).abs());
        assert!((quant.remainder() - (cum_in - cum_out)).abs() < 1e-9 * q);
    }
    assert!(
        worst <= 0.5 * q * (1.0 + 1e-9),
        "cumulative error {} pulses",
        worst / q
    );
    // Without the carried remainder the error would grow: many sub-half-pulse inputs still pass.
    let mut q2 = Quantizer::new(1.0);
    let out: f64 = (0..10).map(|_| q2.apply(0.3)).sum();
    assert_eq!(out, 3.0);
}

#[test]
fn zero_noise_model_leaves_increments_untouched() {
    let mut noise = SensorNoise::new(&NoiseModel::default(), 1, 0.005).unwrap();
    let (mut th, mut v) = (Vec3::new(1e-3, -2e-3, 3e-3), Vec3::new(0.01, 0.02, -0.049));
    let (th0, v0) = (th, v);
    noise.apply(&mut th, &mut v);
    assert_eq!((th, v), (th0, v0));
}
