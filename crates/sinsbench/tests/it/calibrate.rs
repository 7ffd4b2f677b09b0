//! `sinsbench calibrate` end to end on a short calibration run: the parameter file, history and
//! Rerun recording are written and readable, and the estimates are close to the truth.

use crate::common;
use common::{
    csv_without_temperatures, exe, short_calibration_experiment, simulate_into, verify_rrd,
};

#[test]
fn calibrate_writes_params_history_and_a_readable_rrd() {
    let dir = tempfile::tempdir().expect("tempdir");
    let exp = short_calibration_experiment(dir.path());
    let out = dir.path().join("data");
    simulate_into(&exp, &out);
    let params = dir.path().join("cal.toml");
    let o = exe()
        .args([
            "calibrate",
            "--dataset",
            &out.join("cal1.parquet").display().to_string(),
            "--states",
            "42",
            "--out",
            &params.display().to_string(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("cal_history.parquet").is_file());
    verify_rrd(&dir.path().join("cal.rrd"));
    let text = std::fs::read_to_string(&params).unwrap();
    // Table 1's gyro x scale factor is 20 ppm; one scheme pass pins it to well under 2 ppm.
    let dk = text
        .lines()
        .find_map(|l| l.strip_prefix("dK_x_ppm = "))
        .and_then(|v| v.trim().parse::<f64>().ok())
        .expect("gyro dK_x_ppm in the parameter file");
    assert!((dk - 20.0).abs() < 2.0, "dK_gx = {dk} ppm");

    // A dataset without temperature columns cannot feed the 42-state filter.
    let csv = dir.path().join("nt.csv");
    csv_without_temperatures(&csv, 400);
    let o = exe()
        .args([
            "calibrate",
            "--dataset",
            &csv.display().to_string(),
            "--states",
            "42",
            "--out",
        ])
        .arg(dir.path().join("x.toml"))
        .arg("--quiet")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("nt.csv") && err.contains("temp_ax_degc") && err.contains("--states 30"),
        "{err}"
    );
}
