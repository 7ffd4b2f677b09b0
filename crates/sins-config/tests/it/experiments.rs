//! The repository's `experiments/` folder: every file loads and has the paper's numbers.

use crate::common;

use common::experiments_dir;
use sins_config::{chamber_duration_s, load_experiment, load_params, motion_duration_s};
use sins_imu::ParamModel;
use sins_sim::scenario::{ChamberSegment, MotionSegment, Scenario};
use std::collections::BTreeSet;

fn files(sub: &str, ext: &str) -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(experiments_dir().join(sub))
        .expect("experiments dir")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some(ext))
        .collect();
    v.sort();
    v
}

#[test]
fn every_experiment_and_parameter_file_loads() {
    let experiments = files("", "toml");
    assert!(
        experiments.len() >= 3,
        "expected the experiment files, found {experiments:?}"
    );
    for path in &experiments {
        let e = load_experiment(path).unwrap_or_else(|err| panic!("{err}"));
        assert!(!e.scenarios.is_empty(), "{}", path.display());
        for s in &e.scenarios {
            assert!(motion_duration_s(&s.motion) > 0.0);
            assert!(s.truth.is_finite());
        }
    }
    let params = files("imu", "toml");
    assert_eq!(params.len(), 3, "{params:?}");
    for path in &params {
        let p = load_params(path).unwrap_or_else(|err| panic!("{err}"));
        assert_eq!(p.params.model, ParamModel::States42, "{}", path.display());
    }
}

fn experiment(name: &str) -> sins_config::Experiment {
    load_experiment(experiments_dir().join(name)).unwrap_or_else(|e| panic!("{e}"))
}

fn labels(s: &Scenario) -> Vec<&str> {
    s.motion
        .segments
        .iter()
        .map(|m| match m {
            MotionSegment::Dwell { label, .. }
            | MotionSegment::Rotate { label, .. }
            | MotionSegment::Vibrate { label, .. } => label.as_str(),
        })
        .collect()
}

#[test]
fn paper_calibration_matches_section_4() {
    let e = experiment("paper_calibration.toml");
    assert_eq!(e.kind.as_deref(), Some("calibration"));
    assert_eq!(e.scenarios.len(), 1);
    let s = &e.scenarios[0];
    assert_eq!(s.seed, 1);
    assert_eq!(s.rate_hz, 200.0);
    let total = motion_duration_s(&s.motion);
    assert!((total - 4.2 * 3600.0).abs() < 1.0, "total {total} s");
    assert_eq!(s.motion.segments.len(), 1 + 72 * 2);
    let l = labels(s);
    assert_eq!(l[0], "alignment");
    assert!(l[1..].iter().all(|x| *x == "scheme"));
    let MotionSegment::Dwell { duration_s, .. } = &s.motion.segments[0] else {
        panic!("first segment must be the alignment dwell")
    };
    assert_eq!(*duration_s, 1200.0);
    // 10 s rotations at 9 deg/s, then dwells of (13920 - 720)/72 s.
    for pair in s.motion.segments[1..].chunks(2) {
        let MotionSegment::Rotate {
            angle_rad,
            rate_radps,
            axis_body,
            ..
        } = &pair[0]
        else {
            panic!("expected a rotation")
        };
        assert!((angle_rad.abs() / rate_radps - 10.0).abs() < 1e-9);
        assert!((rate_radps - 9.0 * sins_nav::DEG).abs() < 1e-15);
        assert!((axis_body.norm() - 1.0).abs() < 1e-15);
        let MotionSegment::Dwell { duration_s, .. } = &pair[1] else {
            panic!("expected a dwell")
        };
        assert!(
            (duration_s - 183.333_333_333_333_3).abs() < 1e-9,
            "{duration_s}"
        );
    }
    // Chamber: 0 degC rising at 10 degC/h for the whole run.
    assert_eq!(s.thermal.chamber_start_degc, 0.0);
    assert_eq!(s.thermal.chamber.len(), 1);
    let ChamberSegment::Ramp {
        duration_s,
        rate_degc_per_s,
    } = s.thermal.chamber[0]
    else {
        panic!("expected a ramp")
    };
    assert!((duration_s - 15120.0).abs() < 1e-9);
    assert!((rate_degc_per_s * 3600.0 - 10.0).abs() < 1e-12);
    for tau in s.thermal.accel_time_constant_s {
        assert!((600.0..=1800.0).contains(&tau), "{tau}");
    }
    // Site 112.99 E 28.22 N.
    assert!((s.site.lat_rad.to_degrees() - 28.22).abs() < 1e-12);
    assert!((s.site.lon_rad.to_degrees() - 112.99).abs() < 1e-12);
    // Start attitude pitch 1, roll -91, yaw -91.
    let eul = sins_nav::attitude::euler_from_ned_from_body(&s.motion.initial_ned_from_body);
    let expected = sins_nav::ned_from_body_euler(&sins_nav::Euler::from_deg(1.0, -91.0, -91.0));
    assert!(
        s.motion.initial_ned_from_body.angle_to(&expected) < 1e-12,
        "{eul:?}"
    );
}

#[test]
fn paper_navigation_has_three_15h_runs() {
    let e = experiment("paper_navigation.toml");
    assert_eq!(e.kind.as_deref(), Some("navigation"));
    assert_eq!(e.scenarios.len(), 3);
    let names: Vec<_> = e.scenarios.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["nav1", "nav2", "nav3"]);
    let seeds: BTreeSet<u64> = e.scenarios.iter().map(|s| s.seed).collect();
    assert_eq!(seeds.len(), 3, "seeds must differ");
    for s in &e.scenarios {
        let total = motion_duration_s(&s.motion);
        assert!(
            (total - 15.0 * 3600.0).abs() < 1e-6,
            "{} lasts {total} s",
            s.name
        );
        assert!(
            chamber_duration_s(&s.thermal) >= total - 1e-6,
            "{}: chamber profile too short",
            s.name
        );
        assert_eq!(
            labels(s),
            [
                "alignment",
                "stationary",
                "pattern1",
                "stationary",
                "pattern2",
                "stationary",
                "pattern3"
            ]
        );
        let stationary: f64 = s.motion.segments[..2]
            .iter()
            .map(|m| match m {
                MotionSegment::Dwell { duration_s, .. } => *duration_s,
                _ => panic!("the first 5 h are stationary"),
            })
            .sum();
        assert_eq!(stationary, 5.0 * 3600.0);
        // Pattern 3 of Table 4: x 8 deg / 0.2 s, y 9 deg / 0.1 s, z 15 deg / 0.15 s.
        let MotionSegment::Vibrate {
            amplitude_rad,
            period_s,
            duration_s,
            ..
        } = &s.motion.segments[6]
        else {
            panic!("expected pattern 3")
        };
        assert_eq!(*duration_s, 9600.0);
        let amp_deg = amplitude_rad.map(f64::to_degrees);
        for (got, want) in amp_deg.iter().zip([8.0, 9.0, 15.0]) {
            assert!((got - want).abs() < 1e-12, "{amp_deg:?}");
        }
        assert_eq!(period_s.as_slice(), [0.2, 0.1, 0.15]);
        // A sustained drop: the chamber ends at least 15 degC below where it started.
        let drop: f64 = s
            .thermal
            .chamber
            .iter()
            .map(ChamberSegment::trend_change_degc)
            .sum();
        assert!(drop < -15.0, "{}: drop {drop}", s.name);
        assert!(s.truth.reference_temperature_degc == 20.0);
    }
    assert_ne!(e.scenarios[0].thermal, e.scenarios[1].thermal);
    assert_ne!(e.scenarios[1].thermal, e.scenarios[2].thermal);
    assert_ne!(e.scenarios[0].thermal, e.scenarios[2].thermal);
}

#[test]
fn error_free_navigation_is_ideal() {
    let e = experiment("error_free_navigation.toml");
    assert_eq!(e.scenarios.len(), 1);
    let s = &e.scenarios[0];
    assert_eq!(
        s.truth,
        sins_imu::ImuErrorParams::ideal(ParamModel::States42)
    );
    assert_eq!(s.noise, sins_sim::scenario::NoiseModel::default());
    assert_eq!(s.thermal.thermometer_noise_degc, 0.0);
    let nav = experiment("paper_navigation.toml");
    assert_eq!(
        s.motion, nav.scenarios[0].motion,
        "same motion as paper_navigation"
    );
}

#[test]
fn units_are_converted_on_loaded_values() {
    let s = &experiment("paper_calibration.toml").scenarios[0];
    let close = |a: f64, b: f64, rel: f64| (a - b).abs() <= rel * b.abs();
    // Truth (Table 1): 0.003 deg/h, 20 ppm, -61.88 arcsec, 1 ug, 0.2 ug/degC, 3 ppm/degC, -0.6 arcsec/degC.
    let t = &s.truth;
    assert!(close(t.gyro.bias_radps.x, 0.003 * 4.848_136_81e-6, 1e-8));
    assert!(close(t.gyro.scale.x, 20e-6, 1e-15));
    assert!(close(
        t.gyro.misalignment_rad[0],
        -61.88 * 4.848_136_8e-6,
        1e-8
    ));
    assert!(close(t.accel.bias_mps2.x, 9.806_65e-6, 1e-15));
    assert!(close(
        t.accel.misalignment_rad[2],
        61.88 * 4.848_136_8e-6,
        1e-8
    ));
    assert!(close(
        t.temperature.bias_mps2_per_degc.x,
        0.2 * 9.806_65e-6,
        1e-15
    ));
    assert!(close(t.temperature.scale_per_degc.z, 3e-6, 1e-15));
    assert!(close(
        t.temperature.misalignment_rad_per_degc[5],
        -0.6 * 4.848_136_8e-6,
        1e-8
    ));
    // Noise: 0.0005 deg/sqrt(h) = 0.0005 * 4.84813681e-6 * 60 rad/sqrt(s), ...
    let n = &s.noise;
    assert!(close(
        n.gyro_arw_rad_per_sqrt_s,
        0.0005 * 4.848_136_81e-6 * 60.0,
        1e-8
    ));
    assert!(close(
        n.gyro_bias_instability_radps,
        0.0005 * 4.848_136_81e-6 / 0.617_364_283,
        1e-8
    ));
    assert!(close(n.gyro_quantum_rad, 4.848_136_8e-6, 1e-8));
    assert!(close(n.accel_vrw_mps_per_sqrt_s, 10.0 * 9.806_65e-6, 1e-15));
    assert!(close(
        n.accel_bias_instability_mps2,
        5.0 * 9.806_65e-6 / 0.617_364_283,
        1e-15
    ));
    assert_eq!(n.gyro_bias_correlation_s, 3600.0);
    // Navigation truth: Table 3 temperature coefficients.
    let t = experiment("paper_navigation.toml").scenarios[0].truth;
    assert!(close(
        t.temperature.bias_mps2_per_degc.z,
        -25.45 * 9.806_65e-6,
        1e-15
    ));
    assert!(close(t.temperature.scale_per_degc.x, 19.33e-6, 1e-15));
    let tm = t
        .temperature
        .misalignment_rad_per_degc
        .map(|v| v / 4.848_136_8e-6);
    for (got, want) in tm.iter().zip([-0.12, -0.02, -0.13, 0.14, 0.37, -0.47]) {
        assert!((got - want).abs() < 1e-8, "{tm:?}");
    }
}

/// Data rows of a CSV (comments and blank lines dropped).
fn data_rows(text: &str) -> Vec<String> {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(str::to_owned)
        .collect()
}

#[test]
fn scheme_and_pattern_tables_are_copies_of_the_paper_folder() {
    let pairs = [
        (
            "schemes/calibration_18step.csv",
            "calibration_scheme_18step.csv",
        ),
        (
            "schemes/table4_vibration_patterns.csv",
            "table4_vibration_patterns.csv",
        ),
    ];
    for (ours, paper) in pairs {
        let ours = std::fs::read_to_string(experiments_dir().join(ours)).expect("project copy");
        let Ok(theirs) = std::fs::read_to_string(format!("/work/shared/paper/{paper}")) else {
            eprintln!("paper folder not available; skipping the comparison for {paper}");
            continue;
        };
        assert_eq!(data_rows(&ours), data_rows(&theirs), "{paper}");
        assert!(
            ours.contains("# step,axis_x") || ours.contains("# pattern,axis"),
            "comments kept"
        );
    }
}
