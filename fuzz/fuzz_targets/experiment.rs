//! The experiment parser: `load_experiment` on arbitrary bytes written as an experiment file
//! next to a copy of the shipped `experiments/` (so `imu/*.toml` and `schemes/*.csv` references
//! resolve), and the same text through `parse_effects_toml` (the `--effects FILE` tables).
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, experiments_copy, render, write_at};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let path = write_at(&experiments_copy().join("fuzz_experiment.toml"), data);
        match sins_config::load_experiment(&path) {
            Ok(exp) => {
                for s in &exp.scenarios {
                    let _ = sins_config::motion_duration_s(&s.motion);
                    let _ = sins_config::chamber_duration_s(&s.thermal);
                }
            }
            Err(e) => {
                render(&e);
            }
        }
        if let Ok(text) = std::str::from_utf8(data) {
            match sins_config::parse_effects_toml(text, "fuzz_effects.toml") {
                Ok(effects) => {
                    let _ = sins_config::effects_to_toml(&effects);
                }
                Err(e) => {
                    render(&e);
                }
            }
        }
    })
});
