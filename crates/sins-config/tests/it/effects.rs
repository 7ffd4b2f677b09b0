//! `[[imu.effect]]` tables: every kind loaded into SI specs, written back bit-exactly, and every
//! kind of mistake named with file, key and line.

use sins_config::{effects_to_toml, parse_effects_toml};
use sins_imu::{EffectKind, EffectSpec};
use sins_nav::{DEG, DEG_PER_H, G0_MPS2, UG, Vec3};
use std::path::{Path, PathBuf};

fn experiments() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../experiments")
}

/// The error-free experiment with `extra` appended to its `[imu]` table, written into `dir`.
fn with_imu_extra(dir: &Path, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(experiments().join("error_free_navigation.toml")).unwrap();
    let imu = "truth = \"imu/ideal.toml\"";
    assert!(text.contains(imu));
    let text = text.replace(imu, &format!("{imu}\n{extra}"));
    for sub in ["imu", "schemes"] {
        let d = dir.join(sub);
        std::fs::create_dir_all(&d).unwrap();
        for f in std::fs::read_dir(experiments().join(sub)).unwrap() {
            let f = f.unwrap().path();
            std::fs::copy(&f, d.join(f.file_name().unwrap())).unwrap();
        }
    }
    let path = dir.join("e.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Equal to a few ulps (the reader rounds once, the expected values here several times).
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 5e-16 * b.abs()
}

fn close3(a: Vec3, b: [f64; 3]) -> bool {
    (0..3).all(|i| close(a[i], b[i]))
}

#[test]
fn effect_tables_become_si_specs() {
    let dir = tempfile::tempdir().unwrap();
    let extra = "[[imu.effect]]\nkind = \"accel_bias_quadratic_temp\"\ncoeff_ug_per_degc2 = [1.0, 0.0, -2.0]\nreference_degc = 20.0\n\
                 [[imu.effect]]\nkind = \"gyro_bias_temp\"\ncoeff_deg_per_h_per_degc = [0.001, 0.0, 0.0]\nreference_degc = 25.0\n";
    let e = sins_config::load_experiment(with_imu_extra(dir.path(), extra)).unwrap();
    let fx = &e.scenarios[0].effects;
    assert_eq!(fx.len(), 2);
    match &fx[0] {
        EffectSpec::AccelBiasQuadraticTemp {
            coeff_mps2_per_degc2,
            reference_degc,
        } => {
            assert!((coeff_mps2_per_degc2.z + 2.0 * 9.806_65e-6).abs() < 1e-18);
            assert_eq!(*reference_degc, 20.0);
        }
        other => panic!("wrong effect {other:?}"),
    }
    assert_eq!(fx[1].name(), "gyro_bias_temp");
}

/// One table of every kind in paper-style units, and the SI spec it must give.
#[test]
fn every_kind_parses_from_paper_units() {
    let text = r#"
[[imu.effect]]
kind = "accel_bias_quadratic_temp"
coeff_ug_per_degc2 = [0.05, 0, -0.1]
[[imu.effect]]
kind = "gyro_bias_temp"
coeff_deg_per_h_per_degc = [0.0005, 0.0, 0.001]
reference_degc = 25
[[imu.effect]]
kind = "accel_bias_temp_rate"
coeff_ug_per_degc_per_min = [10.0, 0.0, 0.0]
[[imu.effect]]
kind = "gyro_bias_temp_rate"
coeff_deg_per_h_per_degc_per_min = [0.0, 0.005, 0.0]
[[imu.effect]]
kind = "thermal_lag"
tau_s = [60, 90.5, 0]
[[imu.effect]]
kind = "accel_quadratic_nonlinearity"
k2_ug_per_g2 = [10.0, 10.0, 20.0]
[[imu.effect]]
kind = "size_effect"
lever_arm_x_mm = [10.0, 0.0, 0.0]
lever_arm_z_mm = [0.0, 5.0, -12.0]
[[imu.effect]]
kind = "gyro_scale_asymmetry"
asymmetry_ppm = [2.0, -1.0, 3.0]
[[imu.effect]]
kind = "gyro_g_sensitivity"
coeff_deg_per_h_per_g = [0.0, 0.0, 0.001]
[[imu.effect]]
kind = "accel_time_offset"
delay_ms = [0.5, 0.5, 0.5]
[[imu.effect]]
kind = "gyro_bias_random_walk"
intensity_deg_per_h_per_sqrt_h = [0.001, 0.001, 0.002]
seed = 42
[[imu.effect]]
kind = "accel_bias_random_walk"
intensity_ug_per_sqrt_h = [2.0, 0.0, 0.0]
seed = 0x10
correlation_s = 3600
[[imu.effect]]
kind = "gyro_bias_oscillation"
amplitude_deg_per_h = [0.005, 0.0, 0.0]
period_s = 2700
phase_deg = 90
[[imu.effect]]
kind = "accel_bias_step"
step_ug = [0.0, 20.0, 0.0]
time_s = 3600.5
[[imu.effect]]
kind = "accel_cross_coupling"
coeff_ug_per_g2 = [0.0, 0.0, 20.0]
[[imu.effect]]
kind = "gyro_bias_step"
step_deg_per_h = [0.002, 0.0, 0.0]
time_s = 5000
[[imu.effect]]
kind = "gyro_bias_ramp"
rate_deg_per_h_per_h = [0.0, 0.001, 0.0]
[[imu.effect]]
kind = "accel_bias_ramp"
rate_ug_per_h = [0.0, 0.0, 10.0]
time_s = 100
[[imu.effect]]
kind = "gyro_bias_transient"
amplitude_deg_per_h = [0.01, 0.0, 0.0]
time_s = 0
time_constant_s = 900
[[imu.effect]]
kind = "accel_bias_transient"
amplitude_ug = [0.0, 30.0, 0.0]
[[imu.effect]]
kind = "gyro_bias_plateau"
level_deg_per_h = [0.002, 0.0, 0.0]
time_s = 5000
rise_time_s = 5400
[[imu.effect]]
kind = "accel_bias_plateau"
level_ug = [0.0, 20.0, 0.0]
[[imu.effect]]
kind = "gyro_bias_pulse"
level_deg_per_h = [0.0, 0.0, 0.002]
time_s = 4000
duration_s = 900
[[imu.effect]]
kind = "accel_bias_pulse"
level_ug = [20.0, 0.0, 0.0]
[[imu.effect]]
kind = "gyro_bias_decaying_oscillation"
amplitude_deg_per_h = [0.0, 0.002, 0.0]
time_s = 100
period_s = 7200
time_constant_s = 10800
[[imu.effect]]
kind = "accel_bias_decaying_oscillation"
amplitude_ug = [0.0, 0.0, 20.0]
"#;
    let fx = parse_effects_toml(text, "fx.toml").unwrap();
    let kinds: Vec<EffectKind> = fx.iter().map(|s| s.kind()).collect();
    assert_eq!(
        kinds,
        EffectKind::ALL.to_vec(),
        "one table of every kind, in order"
    );
    let ug_g2 = UG / (G0_MPS2 * G0_MPS2);
    for spec in &fx {
        let ok = match *spec {
            EffectSpec::AccelBiasQuadraticTemp {
                coeff_mps2_per_degc2: c,
                reference_degc,
            } => close3(c, [0.05 * UG, 0.0, -0.1 * UG]) && reference_degc == 20.0,
            EffectSpec::GyroBiasTemp {
                coeff_radps_per_degc: c,
                reference_degc,
            } => close3(c, [0.0005 * DEG_PER_H, 0.0, 0.001 * DEG_PER_H]) && reference_degc == 25.0,
            EffectSpec::AccelBiasTempRate {
                coeff_mps2_per_degc_per_s: c,
            } => close3(c, [10.0 * UG * 60.0, 0.0, 0.0]),
            EffectSpec::GyroBiasTempRate {
                coeff_radps_per_degc_per_s: c,
            } => close3(c, [0.0, 0.005 * DEG_PER_H * 60.0, 0.0]),
            EffectSpec::ThermalLag { tau_s } => tau_s == Vec3::new(60.0, 90.5, 0.0),
            EffectSpec::AccelQuadratic { k2_per_mps2 } => {
                close3(k2_per_mps2, [10.0 * ug_g2, 10.0 * ug_g2, 20.0 * ug_g2])
            }
            EffectSpec::SizeEffect { lever_arm_m } => {
                close3(lever_arm_m[0], [0.01, 0.0, 0.0])
                    && lever_arm_m[1] == Vec3::zeros()
                    && close3(lever_arm_m[2], [0.0, 0.005, -0.012])
            }
            EffectSpec::GyroScaleAsymmetry { asymmetry } => close3(asymmetry, [2e-6, -1e-6, 3e-6]),
            EffectSpec::GyroGSensitivity {
                coeff_radps_per_mps2: c,
            } => close3(c, [0.0, 0.0, 0.001 * DEG_PER_H / G0_MPS2]),
            EffectSpec::AccelTimeOffset { delay_s } => close3(delay_s, [5e-4; 3]),
            EffectSpec::GyroBiasRandomWalk {
                intensity_radps_per_sqrt_s: q,
                correlation_s,
                seed,
            } => {
                let u = DEG_PER_H / 60.0;
                close3(q, [0.001 * u, 0.001 * u, 0.002 * u])
                    && correlation_s == f64::INFINITY
                    && seed == 42
            }
            EffectSpec::AccelBiasRandomWalk {
                intensity_mps2_per_sqrt_s: q,
                correlation_s,
                seed,
            } => close3(q, [2.0 * UG / 60.0, 0.0, 0.0]) && correlation_s == 3600.0 && seed == 16,
            EffectSpec::GyroBiasOscillation {
                amplitude_radps,
                period_s,
                phase_rad,
            } => {
                close3(amplitude_radps, [0.005 * DEG_PER_H, 0.0, 0.0])
                    && period_s == 2700.0
                    && close(phase_rad, 90.0 * DEG)
            }
            EffectSpec::AccelBiasStep { step_mps2, time_s } => {
                close3(step_mps2, [0.0, 20.0 * UG, 0.0]) && time_s == 3600.5
            }
            EffectSpec::AccelCrossCoupling { coeff_per_mps2 } => {
                close3(coeff_per_mps2, [0.0, 0.0, 20.0 * ug_g2])
            }
            EffectSpec::BiasEvent {
                kind,
                magnitude_si: m,
                onset_s,
                time_constant_s,
            } => match kind {
                EffectKind::GyroBiasStep => {
                    close3(m, [0.002 * DEG_PER_H, 0.0, 0.0]) && onset_s == 5000.0
                }
                // Defaults: onset 7200 s, time constant 1800 s.
                EffectKind::GyroBiasRamp => {
                    close3(m, [0.0, 0.001 * DEG_PER_H / 3600.0, 0.0]) && onset_s == 7200.0
                }
                EffectKind::AccelBiasRamp => {
                    close3(m, [0.0, 0.0, 10.0 * UG / 3600.0]) && onset_s == 100.0
                }
                EffectKind::GyroBiasTransient => {
                    close3(m, [0.01 * DEG_PER_H, 0.0, 0.0])
                        && onset_s == 0.0
                        && time_constant_s == 900.0
                }
                EffectKind::AccelBiasTransient => {
                    close3(m, [0.0, 30.0 * UG, 0.0]) && time_constant_s == 1800.0
                }
                _ => false,
            },
            EffectSpec::BiasProfile {
                kind,
                magnitude_si: m,
                onset_s,
                duration_s,
                time_constant_s,
            } => match kind {
                EffectKind::GyroBiasPlateau => {
                    close3(m, [0.002 * DEG_PER_H, 0.0, 0.0])
                        && onset_s == 5000.0
                        && duration_s == 5400.0
                }
                // Defaults: onset 7200 s, duration 3600 s, time constant 7200 s.
                EffectKind::AccelBiasPlateau => {
                    close3(m, [0.0, 20.0 * UG, 0.0]) && onset_s == 7200.0 && duration_s == 3600.0
                }
                EffectKind::GyroBiasPulse => {
                    close3(m, [0.0, 0.0, 0.002 * DEG_PER_H])
                        && onset_s == 4000.0
                        && duration_s == 900.0
                }
                EffectKind::AccelBiasPulse => {
                    close3(m, [20.0 * UG, 0.0, 0.0]) && duration_s == 3600.0
                }
                EffectKind::GyroBiasDecayingOscillation => {
                    close3(m, [0.0, 0.002 * DEG_PER_H, 0.0])
                        && onset_s == 100.0
                        && duration_s == 7200.0
                        && time_constant_s == 10_800.0
                }
                EffectKind::AccelBiasDecayingOscillation => {
                    close3(m, [0.0, 0.0, 20.0 * UG])
                        && duration_s == 3600.0
                        && time_constant_s == 7200.0
                }
                _ => false,
            },
        };
        assert!(ok, "{spec:?}");
    }
}

/// Awkward SI values (not short decimals in any unit) and non-default auxiliary values.
fn awkward(kind: EffectKind, n: usize) -> EffectSpec {
    let x: Vec<f64> = (0..kind.n_components())
        .map(|i| kind.typical_magnitude_si() * (1.0 + 0.123_456_789_012_345 * (i + n) as f64) / 3.0)
        .collect();
    let spec = EffectSpec::zero(kind).with_magnitudes_si(&x).unwrap();
    match spec {
        EffectSpec::AccelBiasQuadraticTemp {
            coeff_mps2_per_degc2,
            ..
        } => EffectSpec::AccelBiasQuadraticTemp {
            coeff_mps2_per_degc2,
            reference_degc: 1.0 / 3.0,
        },
        EffectSpec::GyroBiasRandomWalk {
            intensity_radps_per_sqrt_s,
            ..
        } => EffectSpec::GyroBiasRandomWalk {
            intensity_radps_per_sqrt_s,
            correlation_s: 1e4 / 7.0,
            seed: u64::MAX,
        },
        EffectSpec::GyroBiasOscillation {
            amplitude_radps, ..
        } => EffectSpec::GyroBiasOscillation {
            amplitude_radps,
            period_s: 2700.0 / 7.0,
            phase_rad: -1.0 / 3.0,
        },
        EffectSpec::AccelBiasStep { step_mps2, .. } => EffectSpec::AccelBiasStep {
            step_mps2,
            time_s: 1e5 / 3.0,
        },
        // Steps and ramps have no time constant (their files none): the default stays.
        EffectSpec::BiasEvent {
            kind,
            magnitude_si,
            time_constant_s,
            ..
        } => EffectSpec::BiasEvent {
            kind,
            magnitude_si,
            onset_s: 1e5 / 7.0,
            time_constant_s: match kind {
                EffectKind::GyroBiasTransient | EffectKind::AccelBiasTransient => 1e4 / 3.0,
                _ => time_constant_s,
            },
        },
        EffectSpec::BiasProfile {
            kind, magnitude_si, ..
        } => EffectSpec::BiasProfile {
            kind,
            magnitude_si,
            onset_s: 1e5 / 7.0,
            duration_s: 1e4 / 7.0,
            time_constant_s: match kind {
                // Plateaus and pulses have no time constant (their files none).
                EffectKind::GyroBiasDecayingOscillation
                | EffectKind::AccelBiasDecayingOscillation => 1e4 / 3.0,
                _ => sins_imu::effects::spec::DEFAULT_PROFILE_TIME_CONSTANT_S,
            },
        },
        s => s,
    }
}

#[test]
fn writing_then_reading_is_bit_exact_for_every_kind() {
    let specs: Vec<EffectSpec> = EffectKind::ALL
        .iter()
        .enumerate()
        .map(|(n, &k)| awkward(k, n))
        .collect();
    let text = effects_to_toml(&specs);
    let back = parse_effects_toml(&text, "written.toml").unwrap();
    assert_eq!(back, specs, "{text}");
    // Pasted into an experiment file, the same specs come out of every run.
    let dir = tempfile::tempdir().unwrap();
    let e = sins_config::load_experiment(with_imu_extra(dir.path(), &text)).unwrap();
    assert_eq!(e.scenarios[0].effects, specs);
    // Defaults are written out too, and an empty list writes nothing.
    let unit = effects_to_toml(&[EffectSpec::unit(EffectKind::AccelBiasRandomWalk, 1)]);
    assert!(
        unit.contains("correlation_s = inf") && unit.contains("seed = 0"),
        "{unit}"
    );
    assert_eq!(
        parse_effects_toml(&effects_to_toml(&[]), "e").unwrap(),
        vec![]
    );
}

/// The load error of the error-free experiment with `extra` effect tables, as text.
fn load_error(extra: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    sins_config::load_experiment(with_imu_extra(dir.path(), extra))
        .unwrap_err()
        .to_string()
}

fn assert_mentions(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "`{p}` missing from: {msg}");
    }
}

#[test]
fn unknown_effect_kind_and_key_are_named() {
    let err = load_error("[[imu.effect]]\nkind = \"warp_drive\"\n");
    assert_mentions(
        &err,
        &["e.toml", "imu.effect[0].kind", "warp_drive", "thermal_lag"],
    );
    let bad_key = "[[imu.effect]]\nkind = \"gyro_bias_temp\"\ncoeff_deg_per_h_per_degc = [0.0, 0.0, 0.0]\nreference_degc = 20.0\nslope = 1\n";
    let err = load_error(bad_key);
    assert_mentions(
        &err,
        &["e.toml", "imu.effect[0].slope", "coeff_deg_per_h_per_degc"],
    );
    // A key of another kind is unknown here.
    let err = load_error("[[imu.effect]]\nkind = \"thermal_lag\"\ntau_s = [1, 2, 3]\nseed = 3\n");
    assert_mentions(&err, &["imu.effect[0].seed", "tau_s"]);
}

#[test]
fn bad_values_name_file_key_line_and_problem() {
    let head = "[[imu.effect]]\nkind = \"thermal_lag\"\ntau_s = [1.0, 2.0, 3.0]\n";
    // (second table, expected fragments): the second table starts on line 5 of the extra text.
    let cases: &[(&str, &[&str])] = &[
        (
            "[[imu.effect]]\nkind = \"accel_time_offset\"\n",
            &["imu.effect[1].delay_ms", "missing", "ms"],
        ),
        (
            "[[imu.effect]]\nkind = \"accel_time_offset\"\ndelay_ms = [0.5, 0.5]\n",
            &["imu.effect[1].delay_ms", "3 numbers", "found 2"],
        ),
        (
            "[[imu.effect]]\nkind = \"accel_time_offset\"\ndelay_ms = 0.5\n",
            &["imu.effect[1].delay_ms", "array"],
        ),
        (
            "[[imu.effect]]\nkind = \"accel_time_offset\"\ndelay_ms = [0.5, \"x\", 0.5]\n",
            &["imu.effect[1].delay_ms[1]", "a string"],
        ),
        (
            "[[imu.effect]]\nkind = \"accel_time_offset\"\ndelay_ms = [0.5, nan, 0.5]\n",
            &["imu.effect[1].delay_ms[1]", "finite"],
        ),
        (
            "[[imu.effect]]\nkind = \"gyro_bias_random_walk\"\nintensity_deg_per_h_per_sqrt_h = [0, 0, 1e-3]\n",
            &["imu.effect[1].seed", "missing"],
        ),
        (
            "[[imu.effect]]\nkind = \"gyro_bias_random_walk\"\nintensity_deg_per_h_per_sqrt_h = [0, 0, 1e-3]\nseed = -1\n",
            &["imu.effect[1].seed", "integer"],
        ),
        (
            "[[imu.effect]]\nkind = \"accel_bias_random_walk\"\nintensity_ug_per_sqrt_h = [0, 0, 1]\nseed = 1\ncorrelation_s = 0\n",
            &["imu.effect[1].correlation_s", "> 0"],
        ),
        (
            "[[imu.effect]]\nkind = \"gyro_bias_oscillation\"\namplitude_deg_per_h = [0, 0, 1e-3]\nperiod_s = -5\n",
            &["imu.effect[1].period_s", "> 0"],
        ),
        (
            "[[imu.effect]]\nkind = 3\n",
            &["imu.effect[1].kind", "string"],
        ),
        (
            "[[imu.effect]]\ntau_s = [1, 2, 3]\n",
            &["imu.effect[1].kind", "missing", "size_effect"],
        ),
    ];
    for (second, parts) in cases {
        let err = load_error(&format!("{head}{second}"));
        assert_mentions(&err, parts);
        assert!(err.contains("e.toml"), "{err}");
    }
    // Lines: the bad value sits on the line of its key in e.toml.
    let text = std::fs::read_to_string(experiments().join("error_free_navigation.toml")).unwrap();
    let imu_line = text
        .lines()
        .position(|l| l.starts_with("truth = "))
        .unwrap()
        + 1;
    let err = load_error(&format!(
        "{head}[[imu.effect]]\nkind = \"accel_time_offset\"\ndelay_ms = [0.5, nan, 0.5]\n"
    ));
    assert!(err.contains(&format!("e.toml:{}:", imu_line + 6)), "{err}");
}

#[test]
fn a_standalone_document_reports_syntax_errors_with_its_origin() {
    let err = parse_effects_toml("[[imu.effect]\nkind = ", "manifest.toml")
        .unwrap_err()
        .to_string();
    assert!(err.contains("manifest.toml"), "{err}");
    let err = parse_effects_toml("[imu]\neffect = 3\n", "manifest.toml")
        .unwrap_err()
        .to_string();
    assert_mentions(&err, &["manifest.toml", "imu.effect", "array of tables"]);
}
