//! End-to-end diagnoses of simulated "real" runs: a null case, a hidden effect, withheld
//! validation.

use crate::common;
use common::*;
use sins_diag::diagnose;
use sins_diag::input::DiagnoseConfig;
use sins_diag::report::Verdict;
use std::time::Instant;

/// A noisy run whose calibrated parameters are off by two sigma on a few coefficients: with
/// the calibration uncertainty in the twin the gap is consistent and nothing is found; without
/// it the same gap is significant.
#[test]
fn calibration_errors_within_their_sigma_are_no_gap() {
    use sins_nav::{ARCSEC, DEG_PER_H, UG, Vec3};
    let hours = 3.0;
    let mut sc = scenario(turning_motion(hours), 100.0, ramp_thermal(10.0, 8.0, hours));
    sc.noise = paper_noise();
    sc.thermal.thermometer_noise_degc = 0.01;
    let truth = sc.truth;
    let mut sigma = sins_imu::ImuErrorParams::ideal(sins_imu::ParamModel::States42);
    sigma.gyro.bias_radps = Vec3::repeat(0.002 * DEG_PER_H);
    sigma.accel.bias_mps2 = Vec3::repeat(20.0 * UG);
    sigma.gyro.scale = Vec3::repeat(5e-6);
    sigma.gyro.misalignment_rad = [5.0 * ARCSEC; 3];
    sigma.accel.scale = Vec3::repeat(5e-6);
    sigma.accel.misalignment_rad = [5.0 * ARCSEC; 6];
    sigma.temperature.bias_mps2_per_degc = Vec3::repeat(0.5 * UG);
    let mut params = truth;
    params.gyro.bias_radps.x += 2.0 * sigma.gyro.bias_radps.x;
    params.accel.bias_mps2.y -= 2.0 * sigma.accel.bias_mps2.y;
    params.temperature.bias_mps2_per_degc.z += 2.0 * sigma.temperature.bias_mps2_per_degc.z;
    let cfg = DiagnoseConfig::default();
    let mut inp = input(&[sc], &params, Some(sigma));
    let with = diagnose(&mut inp, &cfg).expect("diagnosis");
    eprintln!("with calibration sigma: {}", summary(&with));
    // The same uncertainty as a full covariance (the calibration filter's form) gives the same
    // metric.
    let sv = sins_diag::param_vector(&sigma);
    let mut cov = vec![0.0; 33 * 33];
    for i in 0..33 {
        cov[i * 33 + i] = sv[i] * sv[i];
    }
    inp.param_covariance = Some(cov);
    let full = diagnose(&mut inp, &cfg).expect("diagnosis");
    let rel = (full.null_test.chi2 - with.null_test.chi2).abs() / with.null_test.chi2;
    assert!(
        rel < 1e-6,
        "{} vs {}",
        full.null_test.chi2,
        with.null_test.chi2
    );
    inp.param_covariance = None;
    inp.param_sigma = None;
    let without = diagnose(&mut inp, &cfg).expect("diagnosis");
    eprintln!("without: {}", summary(&without));
    assert!(with.null_test.consistent, "{:?}", with.null_test);
    assert_eq!(with.verdict, Verdict::NoSignificantGap);
    assert!(!without.null_test.consistent, "{:?}", without.null_test);
    // The diagnosis serialises (the CLI writes it as JSON).
    let json = serde_json::to_string(&with).expect("json");
    let back: sins_diag::report::Diagnosis = serde_json::from_str(&json).expect("parse");
    assert_eq!(back.verdict, with.verdict);
}

/// The twin's chi-square over noise-only runs is calibrated: its mean over four seeds is its
/// expected value (sensor noise through the alignment replica, full time correlation).
#[test]
fn twin_covariance_is_calibrated_on_noise_only_runs() {
    let hours = 3.0;
    let (mut sum, mut expected) = (0.0, 0.0);
    let seeds = 4;
    for seed in 0..seeds {
        let mut sc = scenario(turning_motion(hours), 100.0, ramp_thermal(10.0, 8.0, hours));
        sc.noise = paper_noise();
        sc.thermal.thermometer_noise_degc = 0.01;
        sc.seed = 300 + seed;
        let truth = sc.truth;
        let mut inp = input(&[sc], &truth, None);
        let d = diagnose(&mut inp, &DiagnoseConfig::default()).expect("diagnosis");
        eprintln!(
            "seed {seed}: chi2 {:.1} expected {:.1}",
            d.null_test.chi2, d.null_test.dof
        );
        sum += d.null_test.chi2;
        expected += d.null_test.dof;
    }
    // Four draws of a chi-square of about 40 effective degrees of freedom: the mean has a
    // relative standard deviation of about 11 %.
    let ratio = sum / expected;
    assert!((ratio - 1.0).abs() < 0.35, "mean chi2 / expected = {ratio}");
}

/// Two noisy runs (different seeds and chamber ramps) with `effect` hidden in both.
fn two_runs(effect: Option<(sins_imu::EffectKind, usize, f64)>) -> Vec<sins_sim::Scenario> {
    let effects: Vec<_> = effect
        .iter()
        .map(|&(k, c, v)| effect_spec(k, c, v))
        .collect();
    noisy_runs(
        turning_motion,
        100.0,
        3.0,
        &[(10.0, 8.0, 21), (30.0, -6.0, 22)],
        &effects,
    )
}

fn effect_spec(k: sins_imu::EffectKind, c: usize, v: f64) -> sins_imu::EffectSpec {
    effect(k, c, v)
}

#[test]
fn hidden_gyro_temperature_coefficient_is_identified_and_validated() {
    use sins_imu::EffectKind;
    let t0 = Instant::now();
    let truth_value = 0.006;
    let scs = two_runs(Some((EffectKind::GyroBiasTemp, 2, truth_value)));
    let truth = scs[0].truth;
    let mut inp = input(&scs, &truth, None);
    let d = diagnose(&mut inp, &DiagnoseConfig::default()).expect("diagnosis");
    eprintln!("{}", summary(&d));
    eprintln!("took {:.1} s", t0.elapsed().as_secs_f64());
    assert_eq!(
        d.verdict,
        Verdict::Explained {
            by: "gyro_bias_temp".into()
        }
    );
    let best = &d.candidates[0];
    let z = best.components.iter().find(|c| c.label == "z").expect("z");
    assert!(z.retained);
    let sigma = z.sigma.expect("identified");
    assert!(
        (z.value - truth_value).abs() < 3.0 * sigma,
        "{} ± {sigma}",
        z.value
    );
    // Withheld validation: fitted without a run, the effect predicts that run's gap down to
    // the twin's own spread (one noise realisation: within 2.5 times its RMS sigma).
    assert_eq!(d.validation.len(), 2);
    for (v, s) in d.validation.iter().zip(&d.series) {
        assert!(v.informative);
        let sigma_rms = (s
            .sigma_north_m
            .iter()
            .chain(&s.sigma_east_m)
            .map(|x| x * x)
            .sum::<f64>()
            / (2 * s.t_s.len()) as f64)
            .sqrt();
        assert!(v.rms_shrinkage_percent > 60.0, "{v:?}");
        assert!(
            v.after.rms_gap_m < 2.5 * sigma_rms,
            "{v:?} vs sigma {sigma_rms}"
        );
    }
}

/// The diagnosis of `inp` with the default settings on `threads` workers, serialised.
fn diagnosis_json(inp: &mut sins_diag::input::DiagnosisInput, threads: usize) -> String {
    let cfg = DiagnoseConfig {
        threads,
        ..DiagnoseConfig::default()
    };
    let d = diagnose(inp, &cfg).expect("diagnosis");
    serde_json::to_string(&d).expect("json")
}

/// Runs of different lengths are handed to the workers longest first: whatever the thread
/// count, the diagnosis is bit-identical (serialised).
#[test]
fn the_diagnosis_does_not_depend_on_the_thread_count() {
    use sins_imu::EffectKind;
    let scs: Vec<_> = [(2.0, 41), (1.5, 42), (2.5, 43)]
        .iter()
        .map(|&(hours, seed)| {
            let mut sc = scenario(turning_motion(hours), 100.0, ramp_thermal(15.0, 6.0, hours));
            sc.noise = paper_noise();
            sc.seed = seed;
            sc.effects = vec![effect(EffectKind::GyroBiasTemp, 2, 0.006)];
            sc
        })
        .collect();
    let truth = scs[0].truth;
    let json: Vec<String> = [1, 2, 3]
        .iter()
        .map(|&threads| {
            let mut inp = input(&scs, &truth, None);
            diagnosis_json(&mut inp, threads)
        })
        .collect();
    assert!(json[0].contains("gyro_bias_temp"));
    assert!(json[0] == json[1] && json[1] == json[2]);
}

/// With a calibration run among the runs and two or more threads, the calibration run's
/// recalibrations run beside the sensitivity passes, on a second reader of the run: the
/// diagnosis is the one-thread diagnosis, bit for bit.
#[test]
fn the_recalibrations_beside_the_passes_change_no_bit() {
    use sins_diag::source::MemorySource;
    let exp = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../experiments/paper_truth_calibration.toml");
    let mut cal = sins_config::load_experiment(&exp)
        .expect("experiment")
        .scenarios[0]
        .clone();
    // 50 Hz keeps the run held in memory small; the filter takes any rate.
    cal.rate_hz = 50.0;
    let truth = cal.truth;
    let mut nav = scenario(turning_motion(1.5), 50.0, ramp_thermal(15.0, 6.0, 1.5));
    nav.noise = paper_noise();
    nav.truth = truth;
    let json: Vec<String> = [1, 2]
        .into_iter()
        .map(|threads| {
            let mut inp = input(&[cal.clone(), nav.clone()], &truth, None);
            // In memory, the calibration run reads twice at once.
            let mut samples = Vec::new();
            let mut segments = Vec::new();
            inp.runs[0]
                .source
                .visit(&mut |s, g| {
                    samples.extend_from_slice(s);
                    segments.extend_from_slice(g);
                    Ok(())
                })
                .expect("samples");
            let h = inp.runs[0].source.sample_interval_s();
            inp.runs[0].source = Box::new(MemorySource {
                samples,
                segments,
                sample_interval_s: h,
            });
            inp.calibration_run = Some(inp.runs[0].name.clone());
            diagnosis_json(&mut inp, threads)
        })
        .collect();
    assert!(
        json[0].contains("calibration absorption: run"),
        "no absorption"
    );
    assert!(json[0] == json[1]);
}
