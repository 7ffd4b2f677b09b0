//! `DatasetReader` on arbitrary bytes in a `.parquet` file: open (magic, footer, metadata,
//! schema) and stream every batch. Any error is fine; a panic, hang or runaway allocation is
//! not.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, read_dataset, write_input};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let path = write_input("input.parquet", data);
        read_dataset(&path);
    })
});
