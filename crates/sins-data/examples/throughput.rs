//! Throwaway measurement: write and read a synthetic 15 h / 200 Hz dataset (10.8 M rows) and
//! print throughput and peak RSS.
//!
//! ```text
//! cargo run --release -p sins-data --example throughput -- \
//!     [--rows N] [--compression uncompressed|snappy|lz4|zstd1|zstd3|all] [--rg ROWS] \
//!     [--dir DIR] [--segment] [--reference] [--csv] [--keep]
//! cargo run --release -p sins-data --example throughput -- --read-file FILE [--no-recycle]
//! ```
#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use std::path::PathBuf;
use std::time::Instant;

use sins_data::{
    ColumnSet, Compression, DatasetMeta, DatasetReader, DatasetWriter, ParquetWriteOptions,
    ReferenceRow, SampleBatch,
};
use sins_imu::ImuSample;
use sins_nav::{Geodetic, Vec3};

struct Rng(u64);
impl Rng {
    fn next_f64(&mut self) -> f64 {
        // xorshift64*, uniform in [-0.5, 0.5)
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

fn vm_hwm_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|kb| kb.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn reset_hwm() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn make_batch(rng: &mut Rng, first: u64, n: usize, rate_hz: f64, cols: ColumnSet) -> SampleBatch {
    let dt = 1.0 / rate_hz;
    let samples = (0..n as u64)
        .map(|k| {
            let i = first + k;
            let t_s = (i + 1) as f64 / rate_hz;
            ImuSample {
                t_s,
                dtheta_rad: Vec3::new(
                    3.6e-7 + 1e-7 * rng.next_f64(),
                    1e-7 * rng.next_f64(),
                    2.9e-7 + 1e-7 * rng.next_f64(),
                ),
                dv_mps: Vec3::new(
                    1e-3 * rng.next_f64(),
                    1e-3 * rng.next_f64(),
                    9.8 * dt + 1e-3 * rng.next_f64(),
                ),
                temp_degc: [
                    25.0 + 1e-4 * t_s + 0.01 * rng.next_f64(),
                    25.5 + 1e-4 * t_s + 0.01 * rng.next_f64(),
                    24.8 + 1e-4 * t_s + 0.01 * rng.next_f64(),
                ],
            }
        })
        .collect();
    let segment_index = cols.segment.then(|| {
        (0..n as u64)
            .map(|k| ((first + k) / 720_000 % 4) as u16)
            .collect()
    });
    // Turntable-like truth: fixed position, zero velocity, piecewise-constant attitude.
    let reference = cols.reference.then(|| {
        (0..n as u64)
            .map(|k| {
                let step = ((first + k) / 20_000) as f64;
                ReferenceRow {
                    lat_rad: 0.6972,
                    lon_rad: 2.0298,
                    height_m: 50.0,
                    vel_n_mps: 0.0,
                    vel_e_mps: 0.0,
                    vel_d_mps: 0.0,
                    pitch_rad: (step * 0.7).sin(),
                    roll_rad: (step * 1.3).sin(),
                    yaw_rad: (step * 0.1).sin(),
                }
            })
            .collect()
    });
    SampleBatch {
        first_row: first,
        samples,
        segment_index,
        reference,
    }
}

/// Stream the whole file; returns (rows, checksum, batches).
fn read_through(r: &mut DatasetReader, recycle: bool) -> (u64, f64, usize) {
    let (mut rows, mut acc, mut batches) = (0u64, 0.0, 0);
    let mut b = SampleBatch::default();
    loop {
        let more = if recycle {
            r.next_batch_into(&mut b).expect("read")
        } else {
            match r.next_batch().expect("read") {
                Some(x) => {
                    b = x;
                    true
                }
                None => false,
            }
        };
        if !more {
            break;
        }
        rows += b.samples.len() as u64;
        acc += b.samples[b.samples.len() - 1].dv_mps.z;
        batches += 1;
    }
    (rows, acc, batches)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1).cloned())
    };
    if let Some(path) = arg("--read-file") {
        let t0 = Instant::now();
        let mut r = DatasetReader::open(&path).expect("open");
        let (rows, acc, _) = read_through(&mut r, !args.iter().any(|a| a == "--no-recycle"));
        println!(
            "read {rows} rows in {:.3} s, peak RSS {:.0} MB ({acc:.1})",
            t0.elapsed().as_secs_f64(),
            vm_hwm_mb()
        );
        return;
    }
    let n_rows: u64 = arg("--rows")
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_800_000);
    let rg: usize = arg("--rg")
        .and_then(|s| s.parse().ok())
        .unwrap_or(sins_data::DEFAULT_ROW_GROUP_ROWS);
    let dir = PathBuf::from(arg("--dir").unwrap_or_else(|| "/tmp".into()));
    let comp = arg("--compression").unwrap_or_else(|| "lz4".into());
    let csv = args.iter().any(|a| a == "--csv");
    let cols = ColumnSet {
        temperature: true,
        segment: args.iter().any(|a| a == "--segment"),
        reference: args.iter().any(|a| a == "--reference"),
    };
    let comps: Vec<(&str, Compression)> = [
        ("uncompressed", Compression::Uncompressed),
        ("snappy", Compression::Snappy),
        ("lz4", Compression::Lz4),
        ("zstd1", Compression::Zstd(1)),
        ("zstd3", Compression::Zstd(3)),
    ]
    .into_iter()
    .filter(|(name, _)| comp == "all" || comp == *name)
    .collect();
    let rate_hz = 200.0;
    let meta = DatasetMeta::new(rate_hz, Geodetic::from_deg(39.9, 116.3, 50.0), "throughput");
    let labels: Vec<String> = ["alignment", "stationary", "pattern1", "pattern2"]
        .map(String::from)
        .to_vec();
    let gen_batch = 65_536usize;

    // Generation alone, to separate the writer's cost from the synthetic data's.
    let t0 = Instant::now();
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut first = 0u64;
    let mut sink = 0.0;
    while first < n_rows {
        let n = gen_batch.min((n_rows - first) as usize);
        let b = make_batch(&mut rng, first, n, rate_hz, cols);
        sink += b.samples[0].t_s;
        first += n as u64;
    }
    let gen_s = t0.elapsed().as_secs_f64();
    println!("rows {n_rows}, generation alone {gen_s:.3} s ({sink:.0})");
    let n_cols = cols.float_columns().len() as f64;
    let raw_mb = n_rows as f64 * n_cols * 8.0 / 1e6;

    for (name, compression) in comps {
        let path = dir.join(if csv {
            "sins-throughput.csv".to_string()
        } else {
            format!("sins-throughput-{name}.parquet")
        });
        let opts = ParquetWriteOptions {
            compression,
            row_group_rows: rg,
        };
        reset_hwm();
        let t0 = Instant::now();
        let mut w =
            DatasetWriter::create_with_options(&path, &meta, cols, &labels, opts).expect("create");
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let mut first = 0u64;
        while first < n_rows {
            let n = gen_batch.min((n_rows - first) as usize);
            let b = make_batch(&mut rng, first, n, rate_hz, cols);
            w.write_batch(&b).expect("write");
            first += n as u64;
        }
        let t_fin = Instant::now();
        let summary = w.finish().expect("finish");
        let fin_s = t_fin.elapsed().as_secs_f64();
        let write_s = t0.elapsed().as_secs_f64();
        let write_hwm = vm_hwm_mb();

        if args.iter().any(|a| a == "--skip-read") {
            println!(
                "{name:>12}: file {:.0} MB | write {write_s:.2} s incl. gen, finish+fsync {fin_s:.2} s, peak RSS {write_hwm:.0} MB",
                summary.n_bytes as f64 / 1e6
            );
            continue;
        }
        reset_hwm();
        let t0 = Instant::now();
        let mut r = DatasetReader::open(&path).expect("open");
        let open_s = t0.elapsed().as_secs_f64();
        let (rows, acc, batches) = read_through(&mut r, !args.iter().any(|a| a == "--no-recycle"));
        let read_s = t0.elapsed().as_secs_f64();
        let read_hwm = vm_hwm_mb();
        assert_eq!(rows, n_rows);
        println!(
            "{name:>12}: file {:.0} MB ({:.2} of raw) | write {write_s:.2} s incl. gen, {:.2} s excl. gen, finish+fsync {fin_s:.2} s, {:.0} MB/s raw, peak RSS {write_hwm:.0} MB | read {read_s:.2} s (open {open_s:.3} s, {batches} batches), {:.0} MB/s raw, peak RSS {read_hwm:.0} MB ({acc:.1})",
            summary.n_bytes as f64 / 1e6,
            summary.n_bytes as f64 / 1e6 / raw_mb,
            write_s - gen_s,
            raw_mb / (write_s - gen_s).max(1e-9),
            raw_mb / read_s,
        );
        if !args.iter().any(|a| a == "--keep") {
            let _ = std::fs::remove_file(&path);
        }
    }
}
