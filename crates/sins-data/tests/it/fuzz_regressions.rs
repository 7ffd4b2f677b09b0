//! Inputs found by fuzzing (`fuzz/`, `just fuzz`) that crashed a dataset reader. Each must be
//! refused with an error naming the file: never an abort, a panic or a hang. They were found
//! against polars-parquet; the `parquet` crate that reads the files now pre-sizes lists from
//! their declared lengths and reads footer fields by id the same way, so the footer pre-check
//! (`src/pq_footer.rs`) guards it too.

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
        err.contains("footer_list_length.parquet") && err.contains("footer"),
        "{err}"
    );
}

/// Found by `dataset_parquet` after the pre-check above (libFuzzer: out-of-memory, malloc of
/// 12 GB), count raised by hand to 2^31 - 1: FileMetaData field 2 (`schema`) is declared as a
/// *struct* (header byte 0x1c) but polars-parquet's hand-written reader dispatches on the field
/// id alone and reads it as a list, whose header (`f7 ff ff ff ff 07`) then claims 2^31 - 1
/// SchemaElements: 223 GB asked for, SIGABRT ("memory allocation of 223338299288 bytes
/// failed"; `sinsbench navigate --dataset FILE` dies the same way). The pre-check follows the
/// declared types, so it saw a short struct and passed the file. Fixed: on polars' path to every
/// list (FileMetaData, RowGroup, ColumnChunk, ColumnMetaData) a field must carry the type
/// parquet.thrift gives its id, and each list's element type and count are checked.
#[test]
fn parquet_footer_field_of_the_wrong_type_is_refused() {
    let path = data("footer_field_type.parquet");
    let err = match sins_data::DatasetReader::open(&path) {
        Ok(_) => {
            panic!("a footer whose schema field is a struct claiming 2^31 elements was accepted")
        }
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("footer_field_type.parquet") && err.contains("the format says"),
        "{err}"
    );
}

/// Found by `dataset_parquet` after the two fixes above (libFuzzer: out-of-memory, malloc of
/// 5.0 GB): FileMetaData field 1 (`version`, an i32) is declared as a list. The declared-type
/// walk skipped a one-element list, while polars read a varint there and then, out of step,
/// took the next bytes as a 2^31-element `schema` list. Fixed: in every struct polars reads
/// (FileMetaData, SchemaElement, RowGroup, ColumnChunk, ColumnMetaData, KeyValue, ...) a field
/// must carry the type class parquet.thrift gives its id.
#[test]
fn parquet_footer_scalar_declared_as_a_list_is_refused() {
    let path = data("footer_version_as_list.parquet");
    let err = match sins_data::DatasetReader::open(&path) {
        Ok(_) => panic!("a footer whose version field is a list was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("footer_version_as_list.parquet") && err.contains("the format says"),
        "{err}"
    );
}
