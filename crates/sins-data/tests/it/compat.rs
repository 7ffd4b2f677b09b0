//! The Parquet format across writers and readers: a file written by the earlier writer (built on
//! polars-parquet) reads back exactly, and files written now read with polars.

use crate::common;

use std::path::PathBuf;

use common::{batch, labels, meta, write};
use polars::prelude::{ParquetReader, SerReader};
use sins_data::{
    ColumnSet, Compression, DatasetReader, DatasetWriter, ParquetWriteOptions, ReferenceRow,
    read_all,
};
use sins_imu::ImuSample;
use sins_nav::{Geodetic, Vec3};

/// The synthetic rows of `examples/throughput.rs` (same generator and seed): what the fixture
/// file holds.
fn throughput_rows(n: u64) -> (Vec<ImuSample>, Vec<ReferenceRow>) {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        let x = state.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let rate_hz = 200.0;
    let dt = 1.0 / rate_hz;
    let samples = (0..n)
        .map(|i| {
            let t_s = (i + 1) as f64 / rate_hz;
            ImuSample {
                t_s,
                dtheta_rad: Vec3::new(
                    3.6e-7 + 1e-7 * next(),
                    1e-7 * next(),
                    2.9e-7 + 1e-7 * next(),
                ),
                dv_mps: Vec3::new(1e-3 * next(), 1e-3 * next(), 9.8 * dt + 1e-3 * next()),
                temp_degc: [
                    25.0 + 1e-4 * t_s + 0.01 * next(),
                    25.5 + 1e-4 * t_s + 0.01 * next(),
                    24.8 + 1e-4 * t_s + 0.01 * next(),
                ],
            }
        })
        .collect();
    let reference = (0..n)
        .map(|i| {
            let step = (i / 20_000) as f64;
            ReferenceRow {
                lat_rad: 0.6972,
                lon_rad: 2.0298,
                height_m: 50.0,
                pitch_rad: (step * 0.7).sin(),
                roll_rad: (step * 1.3).sin(),
                yaw_rad: (step * 0.1).sin(),
                ..ReferenceRow::default()
            }
        })
        .collect();
    (samples, reference)
}

/// Written before the switch to the `parquet` crate, by the polars-parquet based writer:
/// `throughput --rows 300 --rg 128 --segment --reference --keep --skip-read` (LZ4 raw, three
/// row groups, a dictionary of four labels of which the 300 rows use only the first).
#[test]
fn file_from_the_earlier_writer_reads_back_exactly() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/compat/polars_parquet_writer_lz4.parquet");
    let mut r = DatasetReader::open(&path).unwrap();
    let info = r.info().clone();
    assert_eq!(info.n_rows, 300);
    assert_eq!(info.columns, ColumnSet::ALL);
    assert_eq!(
        info.segment_labels,
        ["alignment", "stationary", "pattern1", "pattern2"],
        "the writer's labels, the unused ones too"
    );
    assert_eq!(info.meta.sample_rate_hz, 200.0);
    assert_eq!(info.meta.description, "throughput");
    assert_eq!(info.meta.site, Geodetic::from_deg(39.9, 116.3, 50.0));
    let (samples, reference) = throughput_rows(300);
    let mut sizes = Vec::new();
    while let Some(b) = r.next_batch().unwrap() {
        let rows = b.first_row as usize..b.first_row as usize + b.len();
        sizes.push(b.len());
        assert_eq!(b.samples, samples[rows.clone()]);
        assert_eq!(b.reference.as_deref(), Some(&reference[rows.clone()]));
        assert_eq!(b.segment_index, Some(vec![0; rows.len()]));
    }
    assert_eq!(sizes, [128, 128, 44], "one batch per row group");
}

/// Files written now, with every compression, read with polars (its own Parquet decoder):
/// the same columns, values and segment strings.
#[test]
fn files_written_now_read_with_polars() {
    let dir = tempfile::tempdir().unwrap();
    let n = 1000;
    let expected = batch(0, n, ColumnSet::ALL);
    for c in [
        Compression::Lz4,
        Compression::Uncompressed,
        Compression::Snappy,
        Compression::Zstd(1),
    ] {
        let path = dir.path().join("now.parquet");
        if c == Compression::Lz4 {
            write(&path, n, 333, ColumnSet::ALL);
        } else {
            let opts = ParquetWriteOptions {
                compression: c,
                row_group_rows: 300,
            };
            let mut w =
                DatasetWriter::create_with_options(&path, &meta(), ColumnSet::ALL, &labels(), opts)
                    .unwrap();
            w.write_batch(&expected).unwrap();
            w.finish().unwrap();
        }
        let df = ParquetReader::new(std::fs::File::open(&path).unwrap())
            .finish()
            .unwrap_or_else(|e| panic!("{c:?}: polars cannot read the file: {e}"));
        assert_eq!(df.height(), n, "{c:?}");
        let names: Vec<&str> = df.get_column_names().iter().map(|s| s.as_str()).collect();
        let mut want = ColumnSet::ALL.float_columns();
        want.push("segment");
        assert_eq!(names, want, "{c:?}");
        let f64s = |name: &str| -> Vec<f64> {
            let col = df.column(name).unwrap().f64().unwrap().clone();
            col.into_no_null_iter().collect()
        };
        let t: Vec<f64> = expected.samples.iter().map(|s| s.t_s).collect();
        assert_eq!(f64s("t_s"), t, "{c:?}");
        let dvz: Vec<f64> = expected.samples.iter().map(|s| s.dv_mps.z).collect();
        assert_eq!(f64s("dv_z_mps"), dvz, "{c:?}");
        let yaw: Vec<f64> = expected
            .reference
            .iter()
            .flatten()
            .map(|r| r.yaw_rad)
            .collect();
        assert_eq!(f64s("ref_yaw_rad"), yaw, "{c:?}");
        let seg = df.column("segment").unwrap().str().unwrap().clone();
        let got: Vec<&str> = seg.iter().map(|s| s.unwrap_or("<null>")).collect();
        let labels = labels();
        let want: Vec<&str> = expected
            .segment_index
            .iter()
            .flatten()
            .map(|&i| labels[usize::from(i)].as_str())
            .collect();
        assert_eq!(got, want, "{c:?}");
        // And this crate reads them back with the writer's exact label list.
        let (info, back) = read_all(&path).unwrap();
        assert_eq!(info.segment_labels, labels, "{c:?}");
        assert_eq!(back.segment_index, expected.segment_index, "{c:?}");
    }
}

/// A `segment` column dictionary-encoded by another writer (the `parquet` crate's own column
/// writer, whose indices mix bit-packed and RLE runs, in several data pages): read through the
/// dictionary indices, the labels come out row by row as written.
#[test]
fn segment_dictionary_from_another_writer_reads_row_by_row() {
    use parquet::basic::{LogicalType, Repetition, Type as PhysicalType};
    use parquet::data_type::{ByteArray, ByteArrayType, DoubleType};
    use parquet::file::metadata::KeyValue;
    use parquet::file::properties::WriterProperties;
    use parquet::file::writer::SerializedFileWriter;
    use parquet::schema::types::Type;
    use std::sync::Arc;

    let n = 50_000;
    let b = batch(0, n, ColumnSet::REQUIRED_ONLY);
    let names = ["a-first", "b-second", "c-third", "d-fourth"];
    // Short runs (bit-packed) alternate with long ones (RLE).
    let label_of = |i: usize| {
        if (i / 500).is_multiple_of(2) {
            (i * 7 / 3) % 3
        } else {
            3
        }
    };
    let mut fields = Vec::new();
    for name in ColumnSet::REQUIRED_ONLY.float_columns() {
        let t = Type::primitive_type_builder(name, PhysicalType::DOUBLE)
            .with_repetition(Repetition::REQUIRED)
            .build()
            .unwrap();
        fields.push(Arc::new(t));
    }
    let segment = Type::primitive_type_builder("segment", PhysicalType::BYTE_ARRAY)
        .with_repetition(Repetition::REQUIRED)
        .with_logical_type(Some(LogicalType::String))
        .build()
        .unwrap();
    fields.push(Arc::new(segment));
    let schema = Type::group_type_builder("other")
        .with_fields(fields)
        .build()
        .unwrap();
    let kv = meta()
        .to_key_values()
        .into_iter()
        .map(|(k, v)| KeyValue::new(k, v))
        .collect();
    let props = WriterProperties::builder()
        .set_key_value_metadata(Some(kv))
        .set_data_page_row_count_limit(7000)
        .set_max_row_group_row_count(Some(20_000))
        .build();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("other.parquet");
    let file = std::fs::File::create(&path).unwrap();
    let mut w = SerializedFileWriter::new(file, Arc::new(schema), Arc::new(props)).unwrap();
    for start in (0..n).step_by(20_000) {
        let rows = start..(start + 20_000).min(n);
        let mut rg = w.next_row_group().unwrap();
        for k in 0..7 {
            let values: Vec<f64> = b.samples[rows.clone()]
                .iter()
                .map(|s| match k {
                    0 => s.t_s,
                    1..=3 => s.dtheta_rad[k - 1],
                    _ => s.dv_mps[k - 4],
                })
                .collect();
            let mut col = rg.next_column().unwrap().unwrap();
            col.typed::<DoubleType>()
                .write_batch(&values, None, None)
                .unwrap();
            col.close().unwrap();
        }
        let labels: Vec<ByteArray> = rows
            .clone()
            .map(|i| ByteArray::from(names[label_of(i)]))
            .collect();
        let mut col = rg.next_column().unwrap().unwrap();
        col.typed::<ByteArrayType>()
            .write_batch(&labels, None, None)
            .unwrap();
        col.close().unwrap();
        rg.close().unwrap();
    }
    w.close().unwrap();
    let (info, got) = read_all(&path).unwrap();
    let motion = |s: &ImuSample| (s.t_s, s.dtheta_rad, s.dv_mps);
    let same = got
        .samples
        .iter()
        .map(motion)
        .eq(b.samples.iter().map(motion));
    assert!(same, "the float columns read back as written");
    let idx = got.segment_index.unwrap();
    assert_eq!(idx.len(), n);
    for (i, &k) in idx.iter().enumerate() {
        assert_eq!(
            info.segment_labels[usize::from(k)],
            names[label_of(i)],
            "row {i}"
        );
    }
}
