//! Recordings are written aside and renamed into place: a complete file decodes, a truncated
//! one is detected, and a write that cannot succeed ends at once with an error naming the file
//! (no flush that waits forever) and leaves nothing behind.

#![allow(clippy::unwrap_used, clippy::expect_used)] // a panic in a test or an example is its failure message

use sins_viz::{NavRecording, ScalarSeries, Series, VizError, verify_recording, write_navigation};
use std::path::Path;
use std::sync::mpsc;
use std::time::Duration;

fn recording() -> NavRecording {
    NavRecording {
        series: vec![ScalarSeries {
            entity: "errors/horizontal/truth".into(),
            times_s: (0..2000).map(f64::from).collect(),
            values: (0..2000).map(|k| f64::from(k).sqrt()).collect(),
        }],
        ..NavRecording::default()
    }
}

/// Runs `f` on a thread and fails the test if it has not returned within 60 s.
fn within_a_minute<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    rx.recv_timeout(Duration::from_secs(60))
        .expect("the write neither finished nor failed within 60 s")
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_written_recording_decodes_and_a_truncated_one_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nav.rrd");
    write_navigation(&path, "nav", &recording()).unwrap();
    assert!(verify_recording(&path).unwrap() > 0);
    let series = dir.path().join("cal.rrd");
    let points = [(0.0, 1.0), (1.0, 2.0)];
    sins_viz::write_series(
        &series,
        "cal",
        &[Series {
            entity: "calibration/x",
            points: &points,
        }],
    )
    .unwrap();
    assert!(verify_recording(&series).unwrap() > 0);
    assert_eq!(
        entries(dir.path()),
        vec!["cal.rrd", "nav.rrd"],
        "no temporary left"
    );
    let bytes = std::fs::read(&path).unwrap();
    let cut = dir.path().join("cut.rrd");
    std::fs::write(&cut, &bytes[..bytes.len() * 2 / 3]).unwrap();
    let e = verify_recording(&cut).unwrap_err();
    assert!(e.to_string().contains("cut.rrd"), "{e}");
    // However few bytes a file lost, it is refused (the decoder alone accepted a file that
    // lost up to the 32 bytes of its stream footer).
    for lost in 1..=64 {
        std::fs::write(&cut, &bytes[..bytes.len() - lost]).unwrap();
        assert!(
            verify_recording(&cut).is_err(),
            "{lost} bytes lost, accepted"
        );
    }
    // One flipped bit in the footer's payload fails its checksum.
    let mut flipped = bytes.clone();
    let entry = &bytes[bytes.len() - 32..bytes.len() - 24];
    let start = u64::from_le_bytes(entry.try_into().unwrap()) as usize;
    flipped[start] ^= 1;
    std::fs::write(&cut, &flipped).unwrap();
    assert!(verify_recording(&cut).is_err(), "a damaged footer accepted");
}

#[test]
fn a_write_that_cannot_succeed_fails_at_once_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    // The parent "directory" is a regular file: every write under it fails (ENOTDIR), as
    // writes fail on a full or read-only disk.
    let blocker = dir.path().join("not_a_dir");
    std::fs::write(&blocker, "x").unwrap();
    let path = blocker.join("nav.rrd");
    let p = path.clone();
    let e = within_a_minute(move || write_navigation(&p, "nav", &recording())).unwrap_err();
    assert!(matches!(e, VizError::Write { .. }), "{e:?}");
    assert!(e.to_string().contains(&path.display().to_string()), "{e}");

    // A directory where the recording goes is refused and left as it is.
    let taken = dir.path().join("taken.rrd");
    std::fs::create_dir(&taken).unwrap();
    std::fs::write(taken.join("mine.txt"), "keep").unwrap();
    let t = taken.clone();
    let e = within_a_minute(move || write_navigation(&t, "nav", &recording())).unwrap_err();
    assert!(e.to_string().contains("is a directory"), "{e}");
    assert_eq!(
        std::fs::read_to_string(taken.join("mine.txt")).unwrap(),
        "keep"
    );
    assert_eq!(
        entries(dir.path()),
        vec!["not_a_dir", "taken.rrd"],
        "no temporary left"
    );
}
