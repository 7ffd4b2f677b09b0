//! The gate's thresholds parser: `sins_config::load_thresholds` on arbitrary bytes, and a
//! thresholds file that loads is checked against a real report summary (fixtures/summary.json)
//! and rendered as JUnit XML, as `sinsbench gate` does.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sins_config::{load_thresholds, read_summary};
use sins_harness::gate::junit_xml;
use sins_harness::summary::Summary;
use sinsbench_fuzz::{guard, render, write_input};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn summary() -> &'static (PathBuf, Summary) {
    static S: OnceLock<(PathBuf, Summary)> = OnceLock::new();
    S.get_or_init(|| {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/summary.json");
        let s = read_summary(&p).expect("fixtures/summary.json is a valid summary");
        (p, s)
    })
}

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let (summary_path, summary) = summary();
        let path = write_input("thresholds.toml", data);
        match load_thresholds(&path) {
            Ok(t) => match t.check(summary, summary_path) {
                Ok(checks) => {
                    let _ = junit_xml("fuzz", &checks);
                }
                Err(e) => {
                    render(&e);
                }
            },
            Err(e) => {
                render(&e);
            }
        }
    })
});
