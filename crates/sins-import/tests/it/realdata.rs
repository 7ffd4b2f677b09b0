//! The public real recordings of `../shared/realdata/` read as they come (CI has a copy of
//! `shared/` beside the clone; on a machine without it these tests say so and pass).

use std::path::{Path, PathBuf};

use sins_data::read_all;
use sins_import::{Description, ImportRequest, import};

fn realdata(rel: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/realdata")
        .join(rel);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "SKIPPED: {} is not here (no shared/ beside the clone)",
            p.display()
        );
        None
    }
}

#[test]
fn lasergyro_imu_reads_as_it_comes() {
    let Some(src) = realdata("psins-lasergyro/lasergyro.imu") else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("lasergyro.parquet");
    let desc = Description::psins();
    let rep = import(
        &ImportRequest {
            source: &src,
            description: &desc,
            description_file: &src,
            description_text: "format = \"psins\"",
            out: &out,
        },
        &mut |_| {},
    )
    .unwrap();
    // The README's provenance.
    assert_eq!(
        rep.source_sha256,
        "5de921e75f690c91ce6b7d3e811e547e050c4f1d000f648f537a59521206ba4d"
    );
    assert_eq!(rep.records, 184_718);
    assert!(rep.gaps.is_empty());
    let (info, b) = read_all(&out).unwrap();
    assert_eq!(b.samples.len(), 184_718);
    assert_eq!(info.meta.sample_rate_hz, 100.0);
    assert_eq!(info.meta.extra["initial_yaw_deg"], "-90.6");
    // The first line of counts, "0 0 2 0 0 80": 0.1 arcsec and 125 ug*s per count (g 9.780327).
    let arcsec = std::f64::consts::PI / 648_000.0;
    let s = &b.samples[0];
    assert!((s.dtheta_rad.z - 0.2 * arcsec).abs() < 1e-18);
    assert!((s.dv_mps.z - 80.0 * 125e-6 * 9.780_327).abs() < 1e-15);
    assert!((s.t_s - 0.01).abs() < 1e-15);
    // The mean rate over the 31 min is about the Earth rate (14.85 deg/h, README).
    let n = b.samples.len() as f64;
    let sum = b
        .samples
        .iter()
        .fold(sins_nav::Vec3::zeros(), |a, s| a + s.dtheta_rad);
    let rate_deg_h = (sum / (n * 0.01)).norm().to_degrees() * 3600.0;
    assert!((rate_deg_h - 14.85).abs() < 0.1, "{rate_deg_h}");
}

#[test]
fn adis16405_csv_gz_reads_as_it_comes() {
    let Some(src) = realdata("adis16405/adis_16405_imu1.csv.gz") else {
        return;
    };
    let desc_file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments/import/adis16405.toml");
    let (desc, text) = Description::load(&desc_file).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("adis.parquet");
    let rep = import(
        &ImportRequest {
            source: &src,
            description: &desc,
            description_file: &desc_file,
            description_text: &text,
            out: &out,
        },
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(rep.records, 1_000_000);
    assert!(rep.gaps.is_empty(), "{}", rep.gaps_line());
    let (info, b) = read_all(&out).unwrap();
    assert_eq!(b.samples.len(), 1_000_000);
    assert_eq!(info.segment_labels[0], "stationary");
    // Accelerometer z reads -1.016 g in the file; with the sensor's z down, body up reads +.
    let n = b.samples.len() as f64;
    let up = b.samples.iter().map(|s| s.dv_mps.z).sum::<f64>() / (n * 0.01) / 9.80665;
    assert!((up - 1.016).abs() < 0.005, "{up}");
    // The first row: gyro x -0.05 deg/s, held over 10 ms, is body forward (frd: forward = x).
    assert!((b.samples[0].dtheta_rad.y - (-0.05f64).to_radians() * 0.01).abs() < 1e-15);
}
