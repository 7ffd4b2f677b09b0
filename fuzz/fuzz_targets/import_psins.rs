//! `sinsbench import --format psins` on arbitrary bytes: the PSINS header and count lines.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, import_bytes};

fuzz_target!(|data: &[u8]| {
    guard(|| import_bytes("recording.imu", data, "format = \"psins\"\n"))
});
