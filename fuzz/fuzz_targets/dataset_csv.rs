//! `DatasetReader` on arbitrary bytes in a `.csv` file: open (metadata comment lines,
//! header, full validation) and stream every batch. Any error is fine; a panic, hang or
//! runaway allocation is not. Inputs with the Parquet magic are left to `dataset_parquet`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, read_dataset, write_input};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        if data.starts_with(b"PAR1") {
            return;
        }
        let path = write_input("input.csv", data);
        read_dataset(&path);
    })
});
