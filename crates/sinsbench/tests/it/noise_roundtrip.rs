//! What `noise` writes, `diagnose --noise-from` reads (issue 30): on a very short still
//! stretch, on a run without temperatures compensated with a 30-state set, and on a single
//! noiseless stretch (whose rate random walks the data cannot bound: once written as `inf`,
//! which the reader refuses), `noise` exits 0, its noise.toml holds no infinite figure and no
//! NaN, the reader `diagnose` uses takes it, and `diagnose --noise-from` runs with it.

use crate::common;
use common::{csv_without_temperatures, ideal30, run, s};
use std::path::Path;

/// A level, still IMU at 100 Hz without temperature columns, `seconds` long, with white noise
/// on every channel (1e-8 rad and 1e-6 m/s per increment; a fixed xorshift seed).
fn noisy_csv(path: &Path, seconds: usize) {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut uniform = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    let mut gauss = || {
        let (u, v) = (uniform(), uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    let mut text = String::from(
        "# sinsbench.schema_version = 1\n# sinsbench.sample_rate_hz = 100\n# sinsbench.site_latitude_deg = 28.22\n\
         # sinsbench.site_longitude_deg = 112.99\n# sinsbench.site_height_m = 60\n# sinsbench.description = noisy, no temps\n\
         t_s,dtheta_x_rad,dtheta_y_rad,dtheta_z_rad,dv_x_mps,dv_y_mps,dv_z_mps\n",
    );
    for k in 1..=seconds * 100 {
        text.push_str(&format!(
            "{},{:e},{:e},{:e},{:e},{:e},{:e}\n",
            k as f64 / 100.0,
            1e-8 * gauss(),
            6e-7 + 1e-8 * gauss(),
            3.4e-7 + 1e-8 * gauss(),
            1e-6 * gauss(),
            1e-6 * gauss(),
            0.098 + 1e-6 * gauss()
        ));
    }
    std::fs::write(path, text).unwrap();
}

/// `noise` on `dataset` (with `extra` options) into `out`, then the checks of the module doc
/// and `diagnose --noise-from` on `navigation` (with `params`); returns the noise file's text.
fn round_trip(
    case: &str,
    dataset: &Path,
    extra: &[&str],
    out: &Path,
    navigation: &Path,
    params: &Path,
) -> String {
    let mut args = vec![
        "noise".to_string(),
        "--dataset".into(),
        s(dataset),
        "--out".into(),
        s(out),
    ];
    args.extend(extra.iter().map(|a| a.to_string()));
    let o = run(&args);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{case}: noise failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        stdout.contains("use it with `diagnose --noise-from"),
        "{case}: {stdout}"
    );
    let file = out.join("noise.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let figures: Vec<&str> = text
        .lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .collect();
    for l in &figures {
        assert!(!l.to_lowercase().contains("nan"), "{case}: NaN in {l}");
        // No infinite figure anywhere: a random constant's correlation time and a 1-sigma the
        // data did not bound are left out with a comment (they were once written as `inf`).
        let value = l.split('#').next().unwrap_or_default();
        assert!(
            !value.contains("inf"),
            "{case}: an infinite figure in {l}\n{text}"
        );
    }
    let walks = text
        .split("[imu.unresolved_walk]")
        .nth(1)
        .unwrap_or_default()
        .split("\n[")
        .next()
        .unwrap_or_default();
    assert!(
        walks
            .lines()
            .filter(|l| !l.starts_with('#'))
            .all(|l| !l.contains("inf")),
        "{case}: an infinite walk bound:\n{text}"
    );
    let md = std::fs::read_to_string(out.join("noise.md")).unwrap();
    assert!(!md.contains("NaN"), "{case}: NaN in noise.md");
    // The reader diagnose uses.
    if let Err(e) = sins_config::load_noise(&file) {
        panic!("{case}: the noise file does not read back: {e}\n{text}");
    }
    let o = run(&[
        "diagnose",
        "--dataset",
        &s(navigation),
        "--params",
        &s(params),
        "--noise-from",
        &s(&file),
        "--out",
        &s(&out.with_extension("diagnosis")),
    ]);
    assert!(
        o.status.success(),
        "{case}: diagnose --noise-from {} failed: {}",
        s(&file),
        String::from_utf8_lossy(&o.stderr)
    );
    text
}

#[test]
fn noise_files_read_back_in_diagnose_on_edge_cases() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let params = ideal30(d);
    // 1500 s: the 20 min alignment and two fit times after it, the least diagnose takes.
    let nav = d.join("nav.csv");
    noisy_csv(&nav, 1500);

    // A very short still stretch: 15 s, the identification's shortest stretch 10 s.
    let short = d.join("short.csv");
    noisy_csv(&short, 15);
    round_trip(
        "a 15 s stretch",
        &short,
        &["--min-stretch-s", "10"],
        &d.join("n_short"),
        &nav,
        &params,
    );

    // A run without temperatures, compensated with a 30-state set.
    round_trip(
        "no temperatures, 30-state set",
        &nav,
        &["--params", &s(&params)],
        &d.join("n_30"),
        &nav,
        &params,
    );

    // A single noiseless stretch: the data put no finite bound on either rate random walk,
    // which are left out of the file with a note (and not fitted by the diagnosis).
    let flat = d.join("flat.csv");
    csv_without_temperatures(&flat, 200 * 300);
    let text = round_trip(
        "a single noiseless stretch",
        &flat,
        &[],
        &d.join("n_flat"),
        &nav,
        &params,
    );
    assert!(
        text.contains(
            "# accel_ug_per_sqrt_h left out: the stationary data put no finite 95 % bound"
        ),
        "{text}"
    );
    let table = sins_config::load_noise(d.join("n_flat/noise.toml")).unwrap();
    let [g, a] = table.unresolved_walk_per_sqrt_s.expect("the walk table");
    assert!(
        g.is_infinite() && a.is_infinite(),
        "read back as unbounded: {g} {a}"
    );
}
