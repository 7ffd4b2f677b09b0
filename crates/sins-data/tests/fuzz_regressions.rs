//! Inputs found by fuzzing (`fuzz/`, `just fuzz`) that crashed a dataset reader. Each must be
//! refused with an error naming the file: never an abort, a panic or a hang.

use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz")
        .join(name)
}

/// Found by `dataset_parquet` (libFuzzer: out-of-memory, malloc of 10.7 GB) and made worse by
/// hand: a 2.7 KB file whose footer declares its key/value metadata list to hold 2^31 - 1
/// entries. polars-parquet pre-sizes the list from the declared count, so `read_metadata` asked
/// for 103 GB and the allocation failure aborted the process (SIGABRT). Fixed by the footer
/// pre-check in `src/pq_footer.rs`.
#[test]
fn parquet_footer_declaring_a_huge_list_is_refused() {
    let path = data("footer_list_length.parquet");
    let err = match sins_data::DatasetReader::open(&path) {
        Ok(_) => panic!("a footer that declares 2^31 key/value pairs in 2.7 KB was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("footer_list_length.parquet") && err.contains("footer declares"),
        "{err}"
    );
}
