//! Damaged Parquet files are refused with an error naming the file, never a panic or an abort:
//! bytes overwritten in the middle of the pages, and a sweep of single-byte changes over a
//! whole small file (page headers, page data, footer).

use crate::common;

use std::path::Path;

use sins_data::{ColumnSet, Compression, DatasetWriter, ParquetWriteOptions, read_all};

/// A small dataset with every column group, in row groups of `rg` rows; its bytes.
fn small_file(
    path: &Path,
    n: usize,
    rg: usize,
    compression: Compression,
) -> Result<Vec<u8>, Box<dyn std::error::Error>> {
    let opts = ParquetWriteOptions {
        compression,
        row_group_rows: rg,
    };
    let labels = common::labels();
    let mut w =
        DatasetWriter::create_with_options(path, &common::meta(), ColumnSet::ALL, &labels, opts)?;
    w.write_batch(&common::batch(0, n, ColumnSet::ALL))?;
    w.finish()?;
    Ok(std::fs::read(path)?)
}

/// Read `path` (whose file name is `name`); an error must name the file and must not be a
/// decoder panic. Returns whether the file was refused.
fn refused(path: &Path, name: &str) -> bool {
    match read_all(path) {
        Ok(_) => false,
        Err(e) => {
            let msg = e.to_string();
            assert!(msg.contains(name), "message must name the file: {msg}");
            assert_eq!(e.file(), path);
            assert!(!msg.contains("panicked"), "{msg}");
            true
        }
    }
}

#[test]
fn corrupt_page_bytes_in_the_middle_are_refused() {
    // LZ4 (the default) and no compression: 0xff bytes are a NaN among the values or a broken
    // LZ4 block. (Pages carry no checksum, so damage can also decode into other valid values,
    // e.g. inside a zstd stream of the nearly constant reference columns: not refusable.)
    let dir = tempfile::tempdir().unwrap();
    for c in [Compression::Lz4, Compression::Uncompressed] {
        let good = dir.path().join("good.parquet");
        let bytes = small_file(&good, 5000, 1000, c).unwrap();
        let path = dir.path().join("damaged.parquet");
        // Positions across the middle of the data pages (the footer is at the end).
        for k in 1..=9 {
            let at = bytes.len() * (k + 2) / 16;
            let mut damaged = bytes.clone();
            damaged[at..at + 64].fill(0xff);
            std::fs::write(&path, &damaged).unwrap();
            assert!(
                refused(&path, "damaged.parquet"),
                "{c:?}: 64 bytes of 0xff at {at} were accepted"
            );
        }
    }
}

#[test]
fn single_byte_changes_anywhere_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.parquet");
    let bytes = small_file(&good, 300, 100, Compression::Lz4).unwrap();
    let path = dir.path().join("sweep.parquet");
    let mut n_refused = 0;
    let step = (bytes.len() / 400).max(1);
    for at in (0..bytes.len()).step_by(step) {
        for value in [0x00, 0xff, bytes[at] ^ 0x10] {
            let mut damaged = bytes.clone();
            damaged[at] = value;
            std::fs::write(&path, &damaged).unwrap();
            n_refused += usize::from(refused(&path, "sweep.parquet"));
        }
    }
    assert!(n_refused > 0);
    eprintln!("{n_refused} damaged files refused");
}
