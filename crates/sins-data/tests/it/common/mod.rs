//! Shared helpers for the sins-data integration tests.
#![allow(dead_code)]
#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use std::path::Path;

use polars::prelude::{Column, DataFrame};
use sins_data::{ColumnSet, DatasetMeta, DatasetWriter, ReferenceRow, SampleBatch, WriteSummary};
use sins_imu::ImuSample;
use sins_nav::{Geodetic, Vec3};

pub const RATE_HZ: f64 = 200.0;

pub fn meta() -> DatasetMeta {
    let mut m = DatasetMeta::new(
        RATE_HZ,
        Geodetic::from_deg(39.95, 116.33, 43.5),
        "test dataset, with \"quotes\"\nand a second line",
    );
    m.extra.insert("experiment".into(), "roundtrip".into());
    m.extra.insert("seed".into(), "42".into());
    m.extra.insert("run".into(), "3".into());
    m
}

pub fn labels() -> Vec<String> {
    [
        "alignment",
        "stationary",
        "pattern 1, fast",
        "long label beyond twelve bytes",
    ]
    .map(String::from)
    .to_vec()
}

/// Deterministic awkward values (full-precision mantissas, magnitudes from 1e-300 up to the
/// plausibility limits of the readers: at most 0.016 rad per 5 ms sample, within ±0.62 otherwise).
fn val(i: u64, k: u64) -> f64 {
    let x = ((i * 2654435761 + k * 40503) % 1_000_003) as f64 / 1_000_003.0 - 0.5;
    match k % 4 {
        0 => x * 1e-7,
        1 => x * std::f64::consts::PI * 1e-2,
        2 => x * 1e-300,
        _ => x * 1.234_567_8,
    }
}

/// `n` rows starting at dataset row `first` (t_s = (row + 1) / rate).
pub fn batch(first: u64, n: usize, cols: ColumnSet) -> SampleBatch {
    let samples = (first..first + n as u64)
        .map(|i| ImuSample {
            t_s: (i + 1) as f64 / RATE_HZ,
            dtheta_rad: Vec3::new(val(i, 0), val(i, 1), val(i, 2)),
            dv_mps: Vec3::new(val(i, 3), val(i, 4), val(i, 5)),
            temp_degc: if cols.temperature {
                [20.0 + val(i, 6), 21.0 + val(i, 7), -5.0 + val(i, 8)]
            } else {
                [f64::NAN; 3]
            },
        })
        .collect();
    let segment_index = cols.segment.then(|| {
        (first..first + n as u64)
            .map(|i| ((i / 7) % 3) as u16)
            .collect()
    });
    let reference = cols.reference.then(|| {
        (first..first + n as u64)
            .map(|i| ReferenceRow::from_array(std::array::from_fn(|k| val(i, 10 + k as u64))))
            .collect()
    });
    SampleBatch {
        first_row: first,
        samples,
        segment_index,
        reference,
    }
}

/// Write `n` rows in writer batches of `chunk` rows.
pub fn write(path: &Path, n: usize, chunk: usize, cols: ColumnSet) -> WriteSummary {
    let mut w = DatasetWriter::create(path, &meta(), cols, &labels()).expect("create");
    let mut first = 0;
    while first < n {
        let k = chunk.min(n - first);
        w.write_batch(&batch(first as u64, k, cols)).expect("write");
        first += k;
    }
    w.finish().expect("finish")
}

/// The metadata key/value pairs of `meta()` with `key` replaced (`None` = removed).
pub fn kv_with(key: &str, value: Option<&str>) -> Vec<(String, String)> {
    let mut kv = meta().to_key_values();
    kv.retain(|(k, _)| k != key);
    if let Some(v) = value {
        kv.push((key.to_string(), v.to_string()));
    }
    kv
}

/// Float columns of `n` good rows (required + temperature) as (name, values).
pub fn good_columns(n: usize) -> Vec<(String, Vec<f64>)> {
    let b = batch(
        0,
        n,
        ColumnSet {
            temperature: true,
            ..ColumnSet::default()
        },
    );
    let cols = ColumnSet {
        temperature: true,
        ..ColumnSet::default()
    }
    .float_columns();
    cols.iter()
        .enumerate()
        .map(|(k, name)| {
            let v = b
                .samples
                .iter()
                .map(|s| match k {
                    0 => s.t_s,
                    1..=3 => s.dtheta_rad[k - 1],
                    4..=6 => s.dv_mps[k - 4],
                    _ => s.temp_degc[k - 7],
                })
                .collect();
            (name.to_string(), v)
        })
        .collect()
}

/// Write arbitrary Float64 columns and metadata as Parquet (bypassing the validating writer).
pub fn write_raw_parquet(path: &Path, cols: &[(String, Vec<f64>)], kv: &[(String, String)]) {
    let height = cols.first().map_or(0, |c| c.1.len());
    let columns = cols
        .iter()
        .map(|(name, v)| Column::new(name.as_str().into(), v.clone()))
        .collect();
    let mut df = DataFrame::new(height, columns).expect("df");
    sins_data::write_parquet_df_atomic(path, &mut df, kv).expect("raw parquet");
}

/// Write arbitrary CSV text: metadata comments, header, rows.
pub fn write_raw_csv(path: &Path, cols: &[(String, Vec<f64>)], kv: &[(String, String)]) {
    let mut s = String::new();
    for (k, v) in kv {
        s.push_str(&format!("# {k} = {}\n", v.replace('\n', "\\n")));
    }
    let names: Vec<&str> = cols.iter().map(|c| c.0.as_str()).collect();
    s.push_str(&names.join(","));
    s.push('\n');
    let n = cols.first().map_or(0, |c| c.1.len());
    for i in 0..n {
        let row: Vec<String> = cols.iter().map(|c| format!("{}", c.1[i])).collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    std::fs::write(path, s).expect("write csv");
}
