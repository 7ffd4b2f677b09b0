//! `summary.json`: written then read back unchanged; malformed files name the file and field.

use sins_config::{read_summary, summary_to_json};
use sins_harness::summary::{SUMMARY_SCHEMA, Summary};
use std::path::{Path, PathBuf};

fn summary(with_nmi: f64, without_nmi: f64) -> Summary {
    Summary::example(with_nmi, without_nmi)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap_or_else(|e| panic!("cannot write {}: {e}", p.display()));
    p
}

#[test]
fn written_summary_reads_back_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let s = summary(2.11, 3.38);
    let p = write(dir.path(), "summary.json", &summary_to_json(&s));
    assert_eq!(read_summary(&p).unwrap(), s);
}

#[test]
fn malformed_summary_names_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "summary.json",
        "{\"schema\": 1, \"name\": \"x\"",
    );
    let e = read_summary(&p).unwrap_err().to_string();
    assert!(
        e.contains("summary.json") && e.contains("not a sinsbench summary"),
        "{e}"
    );
    let mut s = summary(1.0, 2.0);
    s.experiments[0]
        .results
        .get_mut("42-state")
        .unwrap()
        .max_horizontal_nmi = -1.0;
    let p = write(dir.path(), "neg.json", &summary_to_json(&s));
    let e = read_summary(&p).unwrap_err().to_string();
    assert!(
        e.contains("experiments['nav1'].results['42-state'].max_horizontal_nmi"),
        "{e}"
    );
    let mut s = summary(1.0, 2.0);
    s.schema = SUMMARY_SCHEMA + 1;
    let p = write(dir.path(), "new.json", &summary_to_json(&s));
    let e = read_summary(&p).unwrap_err().to_string();
    assert!(e.contains("new.json") && e.contains("key 'schema'"), "{e}");
}
