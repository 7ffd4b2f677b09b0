//! `DatasetReader` on arbitrary bytes in a `.csv` file: open (metadata comment lines,
//! header, full validation) and stream every batch. Any error is fine; a panic, hang or
//! runaway allocation is not. Inputs with the Parquet magic are left to `dataset_parquet`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, render, write_input};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        if data.starts_with(b"PAR1") {
            return;
        }
        let path = write_input("input.csv", data);
        read(&path);
    })
});

fn read(path: &std::path::Path) {
    let mut reader = match sins_data::DatasetReader::open(path) {
        Ok(r) => r,
        Err(e) => {
            render(&e);
            return;
        }
    };
    let _ = reader.info().meta.sample_interval_s();
    let mut batch = sins_data::SampleBatch::default();
    loop {
        match reader.next_batch_into(&mut batch) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                render(&e);
                break;
            }
        }
    }
}
