//! The report-configuration parser (`sinsbench report --config`, `gate --config`):
//! `load_report_config` on arbitrary bytes written next to a copy of the shipped
//! `experiments/harness/` files.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, experiments_copy, render, write_at};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let path = write_at(&experiments_copy().join("harness/fuzz_report.toml"), data);
        match sins_config::load_report_config(&path) {
            Ok(c) => {
                let _ = format!("{c:?}");
            }
            Err(e) => {
                render(&e);
            }
        }
    })
});
