//! The import step of `sinsbench bench`: a 15 h / 200 Hz recording imported from CSV text and
//! from binary records, beside the project's own CSV reader on the same rows.

use crate::child::child;
use crate::out::say;
use anyhow::{Context, Result};
use std::io::{BufWriter, Write};
use std::path::Path;

/// Simulate nav1 as CSV, time reading it with the dataset reader, importing it, and importing
/// the same rows written as binary f64 records.
pub fn run(dir: &Path, exp: &Path, nav_exp: &Path) -> Result<()> {
    let csv_dir = dir.join("csv");
    let p = |x: &Path| x.display().to_string();
    child(&[
        "simulate",
        &p(nav_exp),
        "--run",
        "nav1",
        "--format",
        "csv",
        "--out",
        &p(&csv_dir),
    ])?;
    let csv = csv_dir.join("nav1.csv");
    let mb = |f: &Path| std::fs::metadata(f).map_or(0.0, |m| m.len() as f64 / 1e6);
    let m = child(&["read-dataset", &p(&csv)])?;
    say!(
        "read the project's own CSV, 15 h / 200 Hz ({:.0} MB, validated and parsed): {:.2} s wall, peak RSS {:.0} MB",
        mb(&csv),
        m.wall_s,
        m.peak_rss_mb
    )?;
    let out = dir.join("imported.parquet");
    let m = child(&[
        "import",
        &p(&csv),
        "--description",
        &p(&exp.join("import/sinsbench_csv.toml")),
        "--out",
        &p(&out),
    ])?;
    say!(
        "import the same CSV as a recording (SHA-256, survey pass, conversion, Parquet): {:.2} s wall, peak RSS {:.0} MB",
        m.wall_s,
        m.peak_rss_mb
    )?;
    let bin = dir.join("nav1_f64.bin");
    write_f64_records(&dir.join("nav1.parquet"), &bin)?;
    let m = child(&[
        "import",
        &p(&bin),
        "--description",
        &p(&exp.join("import/f64_records.toml")),
        "--out",
        &p(&out),
    ])?;
    say!(
        "import 15 h / 200 Hz binary f64 records ({:.0} MB): {:.2} s wall, peak RSS {:.0} MB",
        mb(&bin),
        m.wall_s,
        m.peak_rss_mb
    )?;
    for f in [&csv, &bin, &out] {
        std::fs::remove_file(f).ok();
    }
    Ok(())
}

/// Write a dataset's time and increments as little-endian f64 records (56 bytes each).
fn write_f64_records(dataset: &Path, out: &Path) -> Result<()> {
    let mut reader = sins_data::DatasetReader::open(dataset)?;
    let f = std::fs::File::create(out).with_context(|| format!("creating {}", out.display()))?;
    let mut w = BufWriter::with_capacity(1 << 20, f);
    while let Some(b) = reader.next_batch()? {
        for s in &b.samples {
            let v = [
                s.t_s,
                s.dtheta_rad.x,
                s.dtheta_rad.y,
                s.dtheta_rad.z,
                s.dv_mps.x,
                s.dv_mps.y,
                s.dv_mps.z,
            ];
            for x in v {
                w.write_all(&x.to_le_bytes())?;
            }
        }
    }
    w.flush()?;
    Ok(())
}

/// `sinsbench read-dataset FILE` (hidden): read and validate every row, print the row count.
pub fn read_dataset(file: &Path) -> Result<()> {
    let mut reader = sins_data::DatasetReader::open(file)?;
    let mut rows = 0u64;
    while let Some(b) = reader.next_batch()? {
        rows += b.samples.len() as u64;
        reader.recycle(b);
    }
    say!("{}: {rows} rows", file.display())?;
    Ok(())
}
