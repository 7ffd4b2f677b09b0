//! The gate's summary reader: `sins_config::read_summary` on arbitrary bytes; a summary that
//! reads is checked against the shipped thresholds (experiments/harness/gate_paper.toml),
//! rendered as JUnit XML and written back as JSON, as `sinsbench gate` and `report` do.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sins_config::{load_thresholds, read_summary, summary_to_json};
use sins_harness::gate::{Thresholds, junit_xml};
use sinsbench_fuzz::{guard, render, write_input};
use std::path::Path;
use std::sync::OnceLock;

fn thresholds() -> &'static Thresholds {
    static T: OnceLock<Thresholds> = OnceLock::new();
    T.get_or_init(|| {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments/harness/gate_paper.toml");
        load_thresholds(&p).expect("the shipped gate thresholds load")
    })
}

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let path = write_input("summary.json", data);
        match read_summary(&path) {
            Ok(s) => {
                match thresholds().check(&s, &path) {
                    Ok(checks) => {
                        let _ = junit_xml(&format!("sinsbench gate {}", s.name), &checks);
                    }
                    Err(e) => {
                        render(&e);
                    }
                }
                let _ = summary_to_json(&s);
            }
            Err(e) => {
                render(&e);
            }
        }
    })
});
