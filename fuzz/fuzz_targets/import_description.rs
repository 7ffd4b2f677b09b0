//! An arbitrary description file (TOML) applied to a small valid CSV recording: every key,
//! unit, axis and time rule the parser and the plan accept or refuse.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, import_bytes};

const RECORDING: &str = "t,gx,gy,gz,ax,ay,az,n\n0,1,2,3,0,0,1,0\n0.01,1,2,3,0,0,1,1\n\
                         0.02,1,2,3,0,0,1,2\n0.04,1,2,3,0,0,1,4\n0.05,1,2,3,0,0,1,5\n";

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let Ok(text) = std::str::from_utf8(data) else {
            return;
        };
        import_bytes("recording.csv", RECORDING.as_bytes(), text);
    })
});
