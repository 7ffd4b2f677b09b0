//! Atomic replacement: failures never damage an existing good file or leave temporaries.

use crate::common;

use std::io::Write;
use std::path::Path;

use common::{batch, meta, write};
use sins_data::{ColumnSet, DataError, DatasetWriter, atomic_write, read_all};

fn dir_entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn failed_or_aborted_write_leaves_existing_file_untouched() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["parquet", "csv"] {
        let path = dir.path().join(format!("good.{ext}"));
        let n = if ext == "csv" { 2000 } else { 300_000 };
        write(&path, n, 70_000, ColumnSet::ALL);
        let before = std::fs::read(&path).unwrap();

        // 1. A write that fails half-way (non-finite value after more than a row group).
        let mut w =
            DatasetWriter::create(&path, &meta(), ColumnSet::ALL, &common::labels()).unwrap();
        w.write_batch(&batch(0, 200_000, ColumnSet::ALL)).unwrap();
        let mut bad = batch(200_000, 10, ColumnSet::ALL);
        bad.samples[3].t_s = f64::NAN;
        assert!(w.write_batch(&bad).is_err());
        assert!(w.finish().is_err());

        // 2. A write abandoned without finish (e.g. the simulation errored out).
        let mut w =
            DatasetWriter::create(&path, &meta(), ColumnSet::ALL, &common::labels()).unwrap();
        w.write_batch(&batch(0, 150_000, ColumnSet::ALL)).unwrap();
        drop(w);

        assert_eq!(std::fs::read(&path).unwrap(), before, "{ext}: file changed");
        read_all(&path).unwrap();
    }
    assert_eq!(
        dir_entries(dir.path()),
        ["good.csv", "good.parquet"],
        "temporaries left behind"
    );
}

#[test]
fn finish_replaces_existing_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.parquet");
    write(&path, 100, 100, ColumnSet::ALL);
    write(&path, 42, 42, ColumnSet::REQUIRED_ONLY);
    let (info, b) = read_all(&path).unwrap();
    assert_eq!((info.n_rows, b.len()), (42, 42));
    assert_eq!(dir_entries(dir.path()), ["d.parquet"]);
}

#[test]
fn atomic_write_helper_commits_or_leaves_target_alone() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("report.txt");
    let io = |e: std::io::Error| DataError::Io {
        file: "report.txt".into(),
        action: "writing",
        source: e,
    };
    atomic_write(&path, |f| f.write_all(b"first\n").map_err(io)).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "first\n");
    let r: Result<(), DataError> = atomic_write(&path, |f| {
        f.write_all(b"partial").map_err(io)?;
        Err(DataError::InvalidWrite {
            file: path.clone(),
            reason: "simulated failure".into(),
        })
    });
    assert!(r.is_err());
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "first\n");
    assert_eq!(dir_entries(dir.path()), ["report.txt"]);
}

#[test]
fn unsupported_extension_is_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.txt");
    let err = DatasetWriter::create(&path, &meta(), ColumnSet::ALL, &common::labels())
        .err()
        .unwrap();
    assert!(err.to_string().contains("d.txt"), "{err}");
    assert!(dir_entries(dir.path()).is_empty());
}
