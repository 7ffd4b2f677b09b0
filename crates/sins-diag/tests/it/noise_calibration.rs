//! Monte Carlo checks of the twin's noise model under vibration (slow; `--ignored`). They back
//! the quantization factor of `NoiseSpec::gyro_quantum_factor`; the paper-size figure comes
//! from `examples/qerr.rs` and `examples/full_speed.rs --seed N`.

use crate::common;
use common::*;
use sins_diag::diagnose;
use sins_diag::input::DiagnoseConfig;
use sins_diag::noise::NoiseSpec;

/// Noise-only 4 h runs with Table 4 vibration at 200 Hz: mean chi-square against its expected
/// value over six seeds (the noise-free twin mean subtracted).
#[test]
#[ignore]
fn chi_square_of_noise_only_vibration_runs() {
    let hours = 4.0;
    let (mut sum, mut expected) = (0.0, 0.0);
    for seed in 0..6 {
        let mut sc = scenario(
            vibration_motion(hours),
            200.0,
            ramp_thermal(10.0, 6.0, hours),
        );
        sc.noise = paper_noise();
        sc.thermal.thermometer_noise_degc = 0.01;
        sc.seed = 1000 + seed;
        let truth = sc.truth;
        let mut clean = sc.clone();
        clean.noise = Default::default();
        clean.thermal.thermometer_noise_degc = 0.0;
        let twin = track(&clean, &truth).1.points;
        let mut inp = input(&[sc], &truth, None);
        inp.runs[0].twin_mean = Some(twin);
        let d = diagnose(&mut inp, &DiagnoseConfig::default()).expect("diagnosis");
        eprintln!(
            "seed {seed}: chi2 {:.1} expected {:.1}",
            d.null_test.chi2, d.null_test.dof
        );
        sum += d.null_test.chi2;
        expected += d.null_test.dof;
    }
    let ratio = sum / expected;
    eprintln!("mean chi2 / expected = {ratio:.3}");
    assert!((ratio - 1.0).abs() < 0.35, "{ratio}");
}

/// The navigation error that gyro quantization adds under vibration (quantised minus
/// unquantised replays, same seeds) against the twin's white-remainder model at factor 1.
#[test]
#[ignore]
fn quantization_error_against_its_model() {
    let hours = 4.0;
    let seeds = 4;
    let mut sum_sq = [[0.0f64; 2]; 8];
    let mut model = [[0.0f64; 2]; 8];
    for seed in 0..seeds {
        let mut sc = scenario(
            vibration_motion(hours),
            200.0,
            ramp_thermal(10.0, 2.0, hours),
        );
        sc.noise = paper_noise();
        sc.seed = 500 + seed;
        let truth = sc.truth;
        let (_, with_q) = track(&sc, &truth);
        let mut noq = sc.clone();
        noq.noise.gyro_quantum_rad = 0.0;
        let (_, without_q) = track(&noq, &truth);
        let mut qonly = sc.clone();
        qonly.noise = sins_sim::NoiseModel {
            gyro_quantum_rad: paper_noise().gyro_quantum_rad,
            ..Default::default()
        };
        let mut inp = input(&[qonly], &truth, None);
        let mut spec = NoiseSpec::from(&sins_sim::NoiseModel {
            gyro_quantum_rad: paper_noise().gyro_quantum_rad,
            ..Default::default()
        });
        spec.gyro_quantum_factor = 1.0;
        inp.noise = spec;
        let cfg = DiagnoseConfig {
            floor_sigma_m: 1e-3,
            floor_expected_sigma_m: 0.0,
            ..Default::default()
        };
        let d = diagnose(&mut inp, &cfg).expect("diagnosis");
        let s = &d.series[0];
        let n = s.t_s.len();
        for q in 0..8 {
            let k = (q + 1) * n / 8 - 1;
            let (a, b) = (at(&with_q, s.t_s[k]), at(&without_q, s.t_s[k]));
            sum_sq[q][0] += (a[0] - b[0]).powi(2);
            sum_sq[q][1] += (a[1] - b[1]).powi(2);
            model[q] = [s.sigma_north_m[k], s.sigma_east_m[k]];
        }
    }
    let mut ratio = 0.0;
    for q in 2..8 {
        for c in 0..2 {
            ratio += sum_sq[q][c] / seeds as f64 / model[q][c].powi(2) / 12.0;
        }
        eprintln!(
            "eighth {}: rms quantization error N {:.2} E {:.2} m, model sigma N {:.2} E {:.2} m",
            q + 1,
            (sum_sq[q][0] / seeds as f64).sqrt(),
            (sum_sq[q][1] / seeds as f64).sqrt(),
            model[q][0],
            model[q][1]
        );
    }
    eprintln!("variance factor of this motion: {ratio:.3}");
    assert!(ratio > 0.0 && ratio < 1.0, "{ratio}");
}
