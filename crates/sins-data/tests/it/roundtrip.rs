//! Round trips and streaming behaviour of the dataset writer and reader.

use crate::common;

use common::{RATE_HZ, batch, labels, meta, write};
use sins_data::{
    ColumnSet, Compression, DatasetFormat, DatasetReader, DatasetWriter, MAX_BATCH_ROWS,
    ParquetWriteOptions, SampleBatch, read_all,
};

fn assert_bit_identical(a: &SampleBatch, b: &SampleBatch) {
    assert_eq!(a.samples.len(), b.samples.len());
    for (i, (x, y)) in a.samples.iter().zip(&b.samples).enumerate() {
        let bits = |s: &sins_imu::ImuSample| {
            let mut v = vec![s.t_s.to_bits()];
            v.extend(s.dtheta_rad.iter().map(|x| x.to_bits()));
            v.extend(s.dv_mps.iter().map(|x| x.to_bits()));
            v.extend(s.temp_degc.iter().map(|x| x.to_bits()));
            v
        };
        assert_eq!(bits(x), bits(y), "sample {i}");
    }
    assert_eq!(a.segment_index, b.segment_index);
    let ref_bits = |r: &Option<Vec<sins_data::ReferenceRow>>| {
        r.as_ref().map(|v| {
            v.iter()
                .flat_map(|r| r.to_array().map(f64::to_bits))
                .collect::<Vec<_>>()
        })
    };
    assert_eq!(ref_bits(&a.reference), ref_bits(&b.reference));
}

fn roundtrip(ext: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("all.{ext}"));
    let n = 1000;
    let summary = write(&path, n, 333, ColumnSet::ALL);
    assert_eq!(summary.n_rows, n as u64);
    let (info, got) = read_all(&path).unwrap();
    assert_eq!(
        info.meta,
        meta(),
        "metadata incl. extra and site must round-trip exactly"
    );
    assert_eq!(info.columns, ColumnSet::ALL);
    assert!(info.has_temperature);
    assert_eq!(info.n_rows, n as u64);
    assert_eq!(info.path, path);
    assert_bit_identical(&got, &batch(0, n, ColumnSet::ALL));
    let used: Vec<String> = labels()[..3].to_vec();
    match info.format {
        // Parquet keeps the writer's exact label list (the unused fourth label too).
        DatasetFormat::Parquet => assert_eq!(info.segment_labels, labels()),
        // CSV lists labels in order of first appearance (all used ones, in that order here).
        DatasetFormat::Csv => assert_eq!(info.segment_labels, used),
    }
}

#[test]
fn parquet_round_trip_is_bit_identical() {
    roundtrip("parquet");
}

#[test]
fn csv_round_trip_is_bit_identical() {
    roundtrip("csv");
}

#[test]
fn every_compression_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    for c in [
        Compression::Uncompressed,
        Compression::Snappy,
        Compression::Lz4,
        Compression::Zstd(1),
    ] {
        let path = dir
            .path()
            .join(format!("{c:?}.parquet").replace(['(', ')'], "_"));
        let opts = ParquetWriteOptions {
            compression: c,
            row_group_rows: 100,
        };
        let mut w =
            DatasetWriter::create_with_options(&path, &meta(), ColumnSet::ALL, &labels(), opts)
                .unwrap();
        w.write_batch(&batch(0, 250, ColumnSet::ALL)).unwrap();
        w.finish().unwrap();
        let (_, got) = read_all(&path).unwrap();
        assert_bit_identical(&got, &batch(0, 250, ColumnSet::ALL));
    }
}

#[test]
fn large_file_arrives_in_bounded_batches() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["parquet", "csv"] {
        let path = dir.path().join(format!("big.{ext}"));
        let n = 2 * MAX_BATCH_ROWS + 12_345;
        let cols = ColumnSet {
            temperature: true,
            segment: true,
            reference: false,
        };
        write(&path, n, 50_000, cols);
        let mut r = DatasetReader::open(&path).unwrap();
        assert_eq!(r.info().n_rows, n as u64);
        let mut all = SampleBatch {
            segment_index: Some(Vec::new()),
            ..SampleBatch::default()
        };
        let mut n_batches = 0;
        while let Some(b) = r.next_batch().unwrap() {
            assert!(
                b.len() <= MAX_BATCH_ROWS,
                "{ext}: batch of {} rows",
                b.len()
            );
            assert_eq!(
                b.first_row,
                all.samples.len() as u64,
                "{ext}: batches in file order"
            );
            all.samples.extend(b.samples);
            all.segment_index
                .as_mut()
                .unwrap()
                .extend(b.segment_index.unwrap());
            n_batches += 1;
        }
        assert!(n_batches >= 3, "{ext}: {n_batches} batches");
        assert!(r.next_batch().unwrap().is_none());
        assert_bit_identical(&all, &batch(0, n, cols));
    }
}

#[test]
fn dataset_without_temperature_reads_nan_temperatures() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["parquet", "csv"] {
        let path = dir.path().join(format!("notemp.{ext}"));
        write(&path, 50, 50, ColumnSet::REQUIRED_ONLY);
        let (info, got) = read_all(&path).unwrap();
        assert!(!info.has_temperature, "{ext}");
        assert!(!info.columns.temperature && !info.columns.segment && !info.columns.reference);
        assert!(info.segment_labels.is_empty());
        assert!(got.segment_index.is_none() && got.reference.is_none());
        assert!(
            got.samples
                .iter()
                .all(|s| s.temp_degc.iter().all(|t| t.is_nan()))
        );
        assert_eq!(got.samples[49].t_s, 50.0 / RATE_HZ);
    }
}

#[test]
fn reader_is_an_iterator() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("it.parquet");
    write(&path, 10, 10, ColumnSet::REQUIRED_ONLY);
    let batches: Vec<_> = DatasetReader::open(&path).unwrap().collect();
    assert_eq!(batches.len(), 1);
    assert_eq!(batches[0].as_ref().unwrap().len(), 10);
}

#[test]
fn recycling_batches_gives_identical_data() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["parquet", "csv"] {
        let path = dir.path().join(format!("recycle.{ext}"));
        let n = MAX_BATCH_ROWS + 777;
        write(&path, n, 40_000, ColumnSet::ALL);
        let mut r = DatasetReader::open(&path).unwrap();
        let mut cur = SampleBatch::default();
        let mut all = SampleBatch {
            segment_index: Some(Vec::new()),
            reference: Some(Vec::new()),
            ..SampleBatch::default()
        };
        let mut count = 0;
        while r.next_batch_into(&mut cur).unwrap() {
            assert_eq!(cur.first_row, all.samples.len() as u64);
            all.samples.extend_from_slice(&cur.samples);
            all.segment_index
                .as_mut()
                .unwrap()
                .extend_from_slice(cur.segment_index.as_ref().unwrap());
            all.reference
                .as_mut()
                .unwrap()
                .extend_from_slice(cur.reference.as_ref().unwrap());
            count += 1;
        }
        assert!(count >= 2, "{ext}: {count} batches");
        assert!(cur.is_empty());
        assert_bit_identical(&all, &batch(0, n, ColumnSet::ALL));
    }
}

#[test]
fn foreign_parquet_with_nullable_columns_and_plain_strings_reads() {
    use polars::prelude::{Column, DataFrame};
    // A file as pandas/polars would write it: nullable Float64 columns, a String segment
    // column, an extra unknown column; this exercises the general (non-fast-path) decoder.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("foreign.parquet");
    let n = 300;
    let b = batch(0, n, ColumnSet::REQUIRED_ONLY);
    let mut cols: Vec<Column> = vec![
        Column::new(
            "t_s".into(),
            b.samples.iter().map(|s| s.t_s).collect::<Vec<_>>(),
        ),
        Column::new("notes".into(), vec![1i32; n]),
    ];
    for (k, name) in ["dtheta_x_rad", "dtheta_y_rad", "dtheta_z_rad"]
        .iter()
        .enumerate()
    {
        cols.push(Column::new(
            (*name).into(),
            b.samples
                .iter()
                .map(|s| s.dtheta_rad[k])
                .collect::<Vec<_>>(),
        ));
    }
    for (k, name) in ["dv_x_mps", "dv_y_mps", "dv_z_mps"].iter().enumerate() {
        cols.push(Column::new(
            (*name).into(),
            b.samples.iter().map(|s| s.dv_mps[k]).collect::<Vec<_>>(),
        ));
    }
    let seg: Vec<&str> = (0..n)
        .map(|i| ["b-second", "a-first", "c"][(i / 50 + 1) % 3])
        .collect();
    cols.push(Column::new("segment".into(), seg.clone()));
    let mut df = DataFrame::new(n, cols).unwrap();
    sins_data::write_parquet_df_atomic(&path, &mut df, &meta().to_key_values()).unwrap();
    let (info, got) = read_all(&path).unwrap();
    assert_eq!(info.ignored_columns, ["notes"]);
    assert!(info.columns.segment && !info.has_temperature);
    let idx = got.segment_index.unwrap();
    for (i, s) in seg.iter().enumerate() {
        assert_eq!(info.segment_labels[idx[i] as usize], *s, "row {i}");
    }
    for (x, y) in got.samples.iter().zip(&b.samples) {
        assert_eq!(
            (x.t_s, x.dtheta_rad, x.dv_mps),
            (y.t_s, y.dtheta_rad, y.dv_mps)
        );
    }
}

#[test]
fn writer_rejects_bad_extra_metadata_names() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = meta();
    m.extra.insert("sinsbench.seed".into(), "1".into());
    let err = DatasetWriter::create(dir.path().join("x.parquet"), &m, ColumnSet::ALL, &labels())
        .err()
        .unwrap();
    assert!(err.to_string().contains("sinsbench.seed"), "{err}");
}

#[test]
fn row_groups_larger_than_a_batch_are_split() {
    // Files from elsewhere may hold more rows per row group than a batch: the reader splits them.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bigrg.parquet");
    let n = 2 * MAX_BATCH_ROWS + 5000;
    let opts = ParquetWriteOptions {
        compression: Compression::Lz4,
        row_group_rows: MAX_BATCH_ROWS + 1000,
    };
    let mut w = DatasetWriter::create_with_options(&path, &meta(), ColumnSet::ALL, &labels(), opts)
        .unwrap();
    let all = batch(0, n, ColumnSet::ALL);
    w.write_batch(&all).unwrap();
    w.finish().unwrap();
    let mut r = DatasetReader::open(&path).unwrap();
    let mut sizes = Vec::new();
    let mut got = SampleBatch {
        segment_index: Some(Vec::new()),
        reference: Some(Vec::new()),
        ..SampleBatch::default()
    };
    while let Some(b) = r.next_batch().unwrap() {
        assert_eq!(b.first_row, got.samples.len() as u64);
        sizes.push(b.len());
        got.samples.extend(b.samples);
        got.segment_index
            .as_mut()
            .unwrap()
            .extend(b.segment_index.unwrap());
        got.reference.as_mut().unwrap().extend(b.reference.unwrap());
    }
    let rg = MAX_BATCH_ROWS + 1000;
    assert_eq!(
        sizes,
        [MAX_BATCH_ROWS, 1000, MAX_BATCH_ROWS, 1000, n - 2 * rg],
        "row groups in batches of at most MAX_BATCH_ROWS"
    );
    assert_bit_identical(&got, &all);
}
