//! `[[imu.effect]]` tables: loaded into SI specs; unknown kinds and keys are named.

use sins_imu::EffectSpec;
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

#[test]
fn unknown_effect_kind_and_key_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let err = sins_config::load_experiment(with_imu_extra(
        dir.path(),
        "[[imu.effect]]\nkind = \"warp_drive\"\n",
    ))
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("warp_drive") && err.contains("e.toml"),
        "{err}"
    );
    let bad_key = "[[imu.effect]]\nkind = \"gyro_bias_temp\"\ncoeff_deg_per_h_per_degc = [0.0, 0.0, 0.0]\nreference_degc = 20.0\nslope = 1\n";
    let err = sins_config::load_experiment(with_imu_extra(dir.path(), bad_key))
        .unwrap_err()
        .to_string();
    assert!(err.contains("slope"), "{err}");
}
