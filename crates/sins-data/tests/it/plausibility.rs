//! Plausibility guards of the readers: a value no real IMU on the Earth can produce is refused
//! in both formats with an error naming the file, the column and the row (and the CSV line).

use crate::common;

use std::path::{Path, PathBuf};

use common::{good_columns, kv_with, meta, write_raw_csv, write_raw_parquet};
use sins_data::{DataError, KEY_SAMPLE_RATE_HZ, KEY_SITE_HEIGHT_M, read_all};

/// `cols` with the default metadata as `<stem>.parquet` and `<stem>.csv` in `dir`.
fn write_both(dir: &Path, stem: &str, cols: &[(String, Vec<f64>)]) -> [PathBuf; 2] {
    let kv = meta().to_key_values();
    let pq = dir.join(format!("{stem}.parquet"));
    let csv = dir.join(format!("{stem}.csv"));
    write_raw_parquet(&pq, cols, &kv);
    write_raw_csv(&csv, cols, &kv);
    [pq, csv]
}

/// Write 40 good rows in both formats after setting `column` at `row` to `value`.
fn with_value(dir: &Path, stem: &str, column: &str, row: usize, value: f64) -> [PathBuf; 2] {
    let mut cols = good_columns(40);
    let c = cols
        .iter_mut()
        .find(|(n, _)| n == column)
        .expect("column exists");
    c.1[row] = value;
    write_both(dir, stem, &cols)
}

/// Both files are refused with an [`DataError::Implausible`] at `row` of `column`; returns the
/// CSV message.
fn refused(paths: &[PathBuf; 2], column: &str, row: u64, why: &str) -> String {
    let mut last = String::new();
    for p in paths {
        let err = read_all(p).expect_err("implausible value must be refused");
        let msg = err.to_string();
        eprintln!("{msg}");
        let name = p.file_name().unwrap().to_str().unwrap();
        assert!(
            matches!(&err, DataError::Implausible { at, column: c, .. } if at.row == row && c == column),
            "{err:?}"
        );
        for part in [name, &format!("row {row}"), &format!("'{column}'"), why] {
            assert!(msg.contains(part), "{part:?} missing from: {msg}");
        }
        last = msg;
    }
    last
}

#[test]
fn good_values_at_the_limits_are_accepted() {
    // 1000 deg/s for one 5 ms sample, 60 g, the temperature range's ends.
    let dir = tempfile::tempdir().unwrap();
    let mut cols = good_columns(40);
    for (name, v) in cols.iter_mut() {
        match name.as_str() {
            "dtheta_z_rad" => v[3] = 1000f64.to_radians() * 0.005,
            "dv_x_mps" => v[4] = -60.0 * 9.806_65 * 0.005,
            "temp_ax_degc" => v[5] = -60.0,
            "temp_az_degc" => v[5] = 125.0,
            _ => {}
        }
    }
    for p in write_both(dir.path(), "edge", &cols) {
        read_all(&p).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn angular_increment_of_10_rad_per_sample_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let paths = with_value(dir.path(), "spin", "dtheta_y_rad", 17, 10.0);
    let msg = refused(&paths, "dtheta_y_rad", 17, "1000 deg/s");
    // CSV: the line too (9 metadata lines and the header come first).
    assert!(msg.contains("line 28"), "{msg}");
}

#[test]
fn velocity_increment_of_a_million_g_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let paths = with_value(dir.path(), "dv", "dv_z_mps", 3, -1e6 * 9.806_65 * 0.005);
    refused(&paths, "dv_z_mps", 3, "60 g");
}

#[test]
fn temperature_of_a_million_degc_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let paths = with_value(dir.path(), "hot", "temp_ay_degc", 39, 1e6);
    refused(&paths, "temp_ay_degc", 39, "-60 and 125 degC");
    let paths = with_value(dir.path(), "cold", "temp_ax_degc", 0, -80.0);
    refused(&paths, "temp_ax_degc", 0, "-60 and 125 degC");
}

/// Good rows with the reference group, one value replaced.
fn reference_file(dir: &Path, stem: &str, column: &str, row: usize, value: f64) -> [PathBuf; 2] {
    let mut cols = good_columns(40);
    let truth = [
        ("ref_lat_rad", 0.5),
        ("ref_lon_rad", 2.0),
        ("ref_height_m", 60.0),
        ("ref_vel_n_mps", 0.0),
        ("ref_vel_e_mps", 0.0),
        ("ref_vel_d_mps", 0.0),
        ("ref_pitch_rad", 0.0),
        ("ref_roll_rad", 0.0),
        ("ref_yaw_rad", 0.0),
    ];
    for (name, v) in truth {
        let mut values = vec![v; 40];
        if name == column {
            values[row] = value;
        }
        cols.push((name.to_string(), values));
    }
    write_both(dir, stem, &cols)
}

#[test]
fn reference_height_of_1e30_m_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let paths = reference_file(dir.path(), "high", "ref_height_m", 12, 1e30);
    refused(&paths, "ref_height_m", 12, "edge of space");
}

#[test]
fn reference_latitude_beyond_the_pole_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let paths = reference_file(dir.path(), "lat", "ref_lat_rad", 8, 1.6);
    refused(&paths, "ref_lat_rad", 8, "latitude");
    let paths = reference_file(dir.path(), "lon", "ref_lon_rad", 9, -7.0);
    refused(&paths, "ref_lon_rad", 9, "longitude");
}

#[test]
fn the_earliest_bad_row_is_reported_across_columns() {
    let dir = tempfile::tempdir().unwrap();
    let mut cols = good_columns(40);
    for (name, v) in cols.iter_mut() {
        match name.as_str() {
            "dv_x_mps" => v[30] = 1e3,
            "temp_az_degc" => v[11] = 500.0,
            _ => {}
        }
    }
    let kv = meta().to_key_values();
    let pq = dir.path().join("two.parquet");
    let csv = dir.path().join("two.csv");
    write_raw_parquet(&pq, &cols, &kv);
    write_raw_csv(&csv, &cols, &kv);
    refused(&[pq, csv], "temp_az_degc", 11, "degC");
}

fn refused_meta(key: &str, value: &str, why: &str) {
    let dir = tempfile::tempdir().unwrap();
    let cols = good_columns(40);
    let kv = kv_with(key, Some(value));
    let pq = dir.path().join("meta.parquet");
    let csv = dir.path().join("meta.csv");
    write_raw_parquet(&pq, &cols, &kv);
    write_raw_csv(&csv, &cols, &kv);
    for p in [pq, csv] {
        let err = DataReaderError::of(&p);
        assert!(
            matches!(&err, DataError::InvalidMetadata { key: k, .. } if k == key),
            "{err:?}"
        );
        let msg = err.to_string();
        for part in [p.file_name().unwrap().to_str().unwrap(), key, why] {
            assert!(msg.contains(part), "{part:?} missing from: {msg}");
        }
    }
}

/// The error of opening `path`.
struct DataReaderError;
impl DataReaderError {
    fn of(path: &Path) -> DataError {
        match sins_data::DatasetReader::open(path) {
            Ok(_) => panic!("{} must be refused on open", path.display()),
            Err(e) => e,
        }
    }
}

#[test]
fn sample_rate_of_1e9_hz_is_refused_on_open() {
    refused_meta(KEY_SAMPLE_RATE_HZ, "1e9", "10000 Hz maximum");
}

#[test]
fn site_height_of_1e30_m_is_refused_on_open() {
    refused_meta(KEY_SITE_HEIGHT_M, "1e30", "not a height on the Earth");
}
