//! Every kind of bad input yields a specific error naming the file and the row/column/key.

use crate::common;

use std::path::{Path, PathBuf};

use common::{good_columns, kv_with, meta, write, write_raw_csv, write_raw_parquet};
use polars::prelude::{Column, DataFrame};
use sins_data::{
    ColumnSet, DataError, DatasetWriter, KEY_SAMPLE_RATE_HZ, KEY_SCHEMA_VERSION,
    KEY_SITE_LATITUDE_DEG, read_all,
};

fn fail(path: &Path) -> (DataError, String) {
    let err = read_all(path).expect_err("bad input must be rejected");
    let msg = err.to_string();
    let name = path.file_name().unwrap().to_str().unwrap();
    assert!(msg.contains(name), "message must name the file: {msg}");
    assert_eq!(err.file(), path);
    eprintln!("{msg}");
    (err, msg)
}

/// Write good columns after `edit` in both formats; return both paths.
fn both(
    dir: &Path,
    stem: &str,
    edit: impl Fn(&mut Vec<(String, Vec<f64>)>),
    kv: Vec<(String, String)>,
) -> [PathBuf; 2] {
    let mut cols = good_columns(40);
    edit(&mut cols);
    let pq = dir.join(format!("{stem}.parquet"));
    let csv = dir.join(format!("{stem}.csv"));
    write_raw_parquet(&pq, &cols, &kv);
    write_raw_csv(&csv, &cols, &kv);
    [pq, csv]
}

fn good_kv() -> Vec<(String, String)> {
    meta().to_key_values()
}

#[test]
fn raw_good_files_are_accepted() {
    // Guards the helpers: the bad-input tests below only differ by their one defect.
    let dir = tempfile::tempdir().unwrap();
    for p in both(dir.path(), "good", |_| {}, good_kv()) {
        let (info, b) = read_all(&p).unwrap();
        assert_eq!(b.len(), 40);
        assert!(info.has_temperature);
    }
}

#[test]
fn truncated_parquet() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.parquet");
    write(&p, 5000, 5000, ColumnSet::ALL);
    let bytes = std::fs::read(&p).unwrap();
    std::fs::write(&p, &bytes[..bytes.len() / 2]).unwrap();
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::CorruptParquet { .. }), "{msg}");
    assert!(msg.contains("corrupt or truncated"), "{msg}");
}

#[test]
fn missing_required_column() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(
        dir.path(),
        "nocol",
        |c| c.retain(|(n, _)| n != "dv_y_mps"),
        good_kv(),
    ) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::MissingColumn { .. }), "{msg}");
        assert!(msg.contains("'dv_y_mps'"), "{msg}");
    }
}

#[test]
fn nan_value() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(dir.path(), "nan", |c| c[5].1[17] = f64::NAN, good_kv()) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::NonFinite { .. }), "{msg}");
        assert!(
            msg.contains("row 17") && msg.contains("'dv_y_mps'"),
            "{msg}"
        );
        if p.extension().unwrap() == "csv" {
            // 9 metadata comment lines + header, so data row 17 is line 28.
            assert!(msg.contains("line 28"), "{msg}");
        }
    }
}

#[test]
fn t_s_not_increasing() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(
        dir.path(),
        "backwards",
        |c| c[0].1[9] = c[0].1[8],
        good_kv(),
    ) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::TimeNotIncreasing { .. }), "{msg}");
        assert!(msg.contains("row 9") && msg.contains("0.045"), "{msg}");
    }
}

#[test]
fn gap_in_t_s() {
    let dir = tempfile::tempdir().unwrap();
    let drop_row = |c: &mut Vec<(String, Vec<f64>)>| {
        c.iter_mut().for_each(|(_, v)| {
            v.remove(20);
        })
    };
    for p in both(dir.path(), "gap", drop_row, good_kv()) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::TimeGap { .. }), "{msg}");
        assert!(
            msg.contains("row 20") && msg.contains("0.01 s") && msg.contains("0.005 s"),
            "{msg}"
        );
    }
}

#[test]
fn swapped_rows_are_out_of_order_not_a_gap() {
    let dir = tempfile::tempdir().unwrap();
    let swap = |c: &mut Vec<(String, Vec<f64>)>| c[0].1.swap(20, 21);
    for p in both(dir.path(), "swapped", swap, good_kv()) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::TimeNotIncreasing { .. }), "{msg}");
        // Row 21 holds t_s = 0.105 s after row 20's 0.11 s.
        assert!(
            msg.contains("row 21") && msg.contains("0.105") && msg.contains("0.11 s"),
            "{msg}"
        );
        assert!(!msg.contains("gap"), "{msg}");
    }
}

#[test]
fn gap_in_the_last_row_is_still_a_gap() {
    let dir = tempfile::tempdir().unwrap();
    let stretch_last = |c: &mut Vec<(String, Vec<f64>)>| c[0].1[39] += 0.005;
    for p in both(dir.path(), "lastgap", stretch_last, good_kv()) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::TimeGap { .. }), "{msg}");
        assert!(msg.contains("row 39") && msg.contains("0.01 s"), "{msg}");
    }
}

#[test]
fn sample_rate_disagrees_with_t_s() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(
        dir.path(),
        "rate",
        |_| {},
        kv_with(KEY_SAMPLE_RATE_HZ, Some("100")),
    ) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::SampleRateMismatch { .. }), "{msg}");
        assert!(
            msg.contains("metadata says 100 Hz") && msg.contains("(200 Hz)"),
            "{msg}"
        );
        assert!(msg.contains("row 1"), "{msg}");
    }
}

#[test]
fn missing_metadata_key() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(
        dir.path(),
        "nokey",
        |_| {},
        kv_with(KEY_SITE_LATITUDE_DEG, None),
    ) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::MissingMetadata { .. }), "{msg}");
        assert!(msg.contains("'sinsbench.site_latitude_deg'"), "{msg}");
    }
}

#[test]
fn unparsable_metadata_and_unsupported_version() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(
        dir.path(),
        "badrate",
        |_| {},
        kv_with(KEY_SAMPLE_RATE_HZ, Some("fast")),
    ) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::InvalidMetadata { .. }), "{msg}");
        assert!(
            msg.contains("'sinsbench.sample_rate_hz'") && msg.contains("\"fast\""),
            "{msg}"
        );
    }
    for p in both(
        dir.path(),
        "v2",
        |_| {},
        kv_with(KEY_SCHEMA_VERSION, Some("2")),
    ) {
        let (err, msg) = fail(&p);
        assert!(
            matches!(err, DataError::UnsupportedSchemaVersion { found: 2, .. }),
            "{msg}"
        );
    }
}

#[test]
fn partial_temperature_group() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(
        dir.path(),
        "halftemp",
        |c| c.retain(|(n, _)| n != "temp_ay_degc"),
        good_kv(),
    ) {
        let (err, msg) = fail(&p);
        assert!(
            matches!(
                err,
                DataError::PartialColumnGroup {
                    group: "temperature",
                    ..
                }
            ),
            "{msg}"
        );
        assert!(msg.contains("temp_ay_degc"), "{msg}");
    }
}

#[test]
fn wrong_column_type() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("inttime.parquet");
    let mut columns: Vec<Column> = good_columns(10)
        .into_iter()
        .map(|(n, v)| Column::new(n.as_str().into(), v))
        .collect();
    columns[0] = Column::new("t_s".into(), (1..=10i64).collect::<Vec<_>>());
    let mut df = DataFrame::new(10, columns).unwrap();
    sins_data::write_parquet_df_atomic(&p, &mut df, &good_kv()).unwrap();
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::WrongColumnType { .. }), "{msg}");
    assert!(msg.contains("'t_s'") && msg.contains("Int64"), "{msg}");
}

#[test]
fn garbage_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("garbage.parquet");
    let junk: Vec<u8> = (0..10_000u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    std::fs::write(&p, junk).unwrap();
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::NotADataset { .. }), "{msg}");
    let p = dir.path().join("prose.csv");
    std::fs::write(&p, "Dear diary,\ntoday I logged no IMU data.\n").unwrap();
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::NotADataset { .. }), "{msg}");
    let p = dir.path().join("zero.parquet");
    std::fs::write(&p, "").unwrap();
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::NotADataset { .. }), "{msg}");
    // PAR1 magic followed by junk: corrupt Parquet, not a panic.
    let p = dir.path().join("fake.parquet");
    std::fs::write(&p, b"PAR1 this is not really parquet PAR1").unwrap();
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::CorruptParquet { .. }), "{msg}");
}

#[test]
fn empty_dataset() {
    let dir = tempfile::tempdir().unwrap();
    for p in both(
        dir.path(),
        "empty",
        |c| c.iter_mut().for_each(|(_, v)| v.clear()),
        good_kv(),
    ) {
        let (err, msg) = fail(&p);
        assert!(matches!(err, DataError::Empty { .. }), "{msg}");
        assert!(msg.contains("empty dataset"), "{msg}");
    }
    // The writer refuses to produce one as well.
    let p = dir.path().join("nothing.parquet");
    let w = DatasetWriter::create(&p, &meta(), ColumnSet::REQUIRED_ONLY, &[]).unwrap();
    let err = w.finish().unwrap_err();
    assert!(matches!(err, DataError::Empty { .. }), "{err}");
    assert!(!p.exists());
}

#[test]
fn malformed_csv_line_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("short.csv");
    let mut cols = good_columns(5);
    cols.truncate(7);
    write_raw_csv(&p, &cols, &good_kv());
    let mut text = std::fs::read_to_string(&p).unwrap();
    text.push_str("0.03,1,2\n");
    std::fs::write(&p, text).unwrap();
    let (err, msg) = fail(&p);
    assert!(
        matches!(err, DataError::MalformedCsv { line: 16, .. }),
        "{msg}"
    );
    assert!(
        msg.contains("line 16") && msg.contains("expected 7 fields"),
        "{msg}"
    );
}

#[test]
fn writer_rejects_bad_rows_with_row_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("w.parquet");
    let mut w = DatasetWriter::create(&p, &meta(), ColumnSet::REQUIRED_ONLY, &[]).unwrap();
    let mut b = common::batch(0, 10, ColumnSet::REQUIRED_ONLY);
    b.samples[6].dtheta_rad.y = f64::INFINITY;
    let msg = w.write_batch(&b).unwrap_err().to_string();
    assert!(
        msg.contains("w.parquet") && msg.contains("row 6") && msg.contains("'dtheta_y_rad'"),
        "{msg}"
    );
    assert!(
        w.write_batch(&common::batch(0, 1, ColumnSet::REQUIRED_ONLY))
            .is_err()
    );
    assert!(w.finish().is_err());
    assert!(!p.exists());
}

#[test]
fn null_value_in_parquet() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("null.parquet");
    let mut columns: Vec<Column> = good_columns(10)
        .into_iter()
        .map(|(n, v)| Column::new(n.as_str().into(), v))
        .collect();
    let mut dvz: Vec<Option<f64>> = vec![Some(0.01); 10];
    dvz[4] = None;
    columns[6] = Column::new("dv_z_mps".into(), dvz);
    let mut df = DataFrame::new(10, columns).unwrap();
    sins_data::write_parquet_df_atomic(&p, &mut df, &good_kv()).unwrap();
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::BadValue { .. }), "{msg}");
    assert!(
        msg.contains("row 4") && msg.contains("'dv_z_mps'") && msg.contains("null"),
        "{msg}"
    );
}

#[test]
fn segment_of_wrong_type() {
    let dir = tempfile::tempdir().unwrap();
    let mut cols = good_columns(10);
    cols.push(("segment".to_string(), vec![1.0; 10]));
    let p = dir.path().join("numseg.parquet");
    write_raw_parquet(&p, &cols, &good_kv());
    let (err, msg) = fail(&p);
    assert!(matches!(err, DataError::WrongColumnType { .. }), "{msg}");
    assert!(msg.contains("'segment'") && msg.contains("String"), "{msg}");
}
