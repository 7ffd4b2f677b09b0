//! `DatasetReader` on arbitrary bytes in a `.parquet` file: open (magic, footer, metadata,
//! schema) and stream every batch. Any error is fine; a panic, hang or runaway allocation is
//! not.
#![no_main]

use libfuzzer_sys::fuzz_target;
use sinsbench_fuzz::{guard, render, write_input};

fuzz_target!(|data: &[u8]| {
    guard(|| {
        let path = write_input("input.parquet", data);
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
