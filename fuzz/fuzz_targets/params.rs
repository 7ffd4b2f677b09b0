//! The parameter-file parser: the text as TOML (`parse_params_toml`) and as JSON
//! (`parse_params_json`). A set that parses must write out (`params_to_toml`,
//! `params_to_json`) to text that parses again: `calibrate` writes what `report` reads.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sins_config::{ParamSet, params_to_json, params_to_toml, parse_params_json, parse_params_toml};
use sinsbench_fuzz::{guard, render};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        // load_params reads the file with read_to_string: non-UTF-8 never reaches the parsers.
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        check(parse_params_toml(text, "fuzz.toml"));
        check(parse_params_json(text, "fuzz.json"));
    })
});

fn check(r: Result<ParamSet, sins_config::ConfigError>) {
    match r {
        Ok(set) => {
            let toml = params_to_toml(&set);
            if let Err(e) = parse_params_toml(&toml, "rewritten.toml") {
                panic!("params_to_toml wrote a file its parser refuses: {e}\n{toml}");
            }
            let json = params_to_json(&set);
            if let Err(e) = parse_params_json(&json, "rewritten.json") {
                panic!("params_to_json wrote a file its parser refuses: {e}\n{json}");
            }
        }
        Err(e) => {
            render(&e);
        }
    }
}
