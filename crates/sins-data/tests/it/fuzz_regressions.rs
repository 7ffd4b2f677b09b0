//! Inputs found by fuzzing (`fuzz/`, `just fuzz`) that crashed a dataset reader. Each must be
//! refused with an error naming the file: never an abort, a panic or a hang. They were found
//! against polars-parquet. The `parquet` crate (58) that then read the files pre-sized lists from
//! their declared lengths too, and a 361-line walk of the footer's Thrift guarded it. `parquet` 60
//! bounds every list and string by the bytes left and checks each list's element type
//! (arrow-rs #10979 for #10920), so the walk is gone and these files, with the offset sweep at
//! the end, are the guard: without the walk, under `parquet` 58, the first and the sweep abort.

use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fuzz")
        .join(name)
}

/// Found by `dataset_parquet` (libFuzzer: out-of-memory, malloc of 10.7 GB) and made worse by
/// hand: a 2.7 KB file whose footer declares its key/value metadata list to hold 2^31 - 1
/// entries. polars-parquet pre-sizes the list from the declared count, so `read_metadata` asked
/// for 103 GB and the allocation failure aborted the process (SIGABRT). `parquet` 58 did the same
/// (206 GB asked for, SIGABRT); 60 refuses the list as longer than the footer.
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

/// Found by `dataset_parquet` after the first fix (libFuzzer: out-of-memory, malloc of
/// 12 GB), count raised by hand to 2^31 - 1: FileMetaData field 2 (`schema`) is declared as a
/// *struct* (header byte 0x1c) but polars-parquet's hand-written reader dispatches on the field
/// id alone and reads it as a list, whose header (`f7 ff ff ff ff 07`) then claims 2^31 - 1
/// SchemaElements: 223 GB asked for, SIGABRT ("memory allocation of 223338299288 bytes
/// failed"; `sinsbench navigate --dataset FILE` dies the same way). `parquet` 60 checks the list's
/// element type and refuses the file ("Expected list element type of Struct but got Double").
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
        err.contains("footer_field_type.parquet") && err.contains("reading the footer"),
        "{err}"
    );
}

/// Found by `dataset_parquet` after the two fixes above (libFuzzer: out-of-memory, malloc of
/// 5.0 GB): FileMetaData field 1 (`version`, an i32) is declared as a list. The declared-type
/// walk skipped a one-element list, while polars read a varint there and then, out of step,
/// took the next bytes as a 2^31-element `schema` list. `parquet` 60 refuses it by the list's
/// element type, as the file above.
#[test]
fn parquet_footer_scalar_declared_as_a_list_is_refused() {
    let path = data("footer_version_as_list.parquet");
    let err = match sins_data::DatasetReader::open(&path) {
        Ok(_) => panic!("a footer whose version field is a list was accepted"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("footer_version_as_list.parquet") && err.contains("reading the footer"),
        "{err}"
    );
}

/// Every offset of a small dataset (all optional columns, so a dictionary page and string
/// statistics are in it) overwritten with a huge declared length: a Thrift varint of 2^31 - 1,
/// the same as a list header of structs, of binaries, and a 64-bit varint. The footer, the page
/// headers and the pages all get each one. Every file must be refused or read; an abort on a
/// runaway allocation kills this test's process, a panic fails it. This is the guard that
/// replaced the footer pre-check when `parquet` 60 began to bound lists and strings by the
/// bytes left (arrow-rs #10920); it found nothing with the pre-check removed.
#[test]
fn every_offset_declaring_a_huge_length_is_refused_or_read() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.parquet");
    let cols = sins_data::ColumnSet {
        temperature: true,
        segment: true,
        reference: true,
    };
    crate::common::write(&good, 60, 25, cols);
    let bytes = std::fs::read(&good).unwrap();
    let patterns: [&[u8]; 4] = [
        &[0xff, 0xff, 0xff, 0xff, 0x07],
        &[0xfc, 0xff, 0xff, 0xff, 0xff, 0x07],
        &[0xf8, 0xff, 0xff, 0xff, 0xff, 0x07],
        &[0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x01],
    ];
    let bad = dir.path().join("bad.parquet");
    let (mut refused, mut read) = (0usize, 0usize);
    for pattern in patterns {
        for at in 0..bytes.len() {
            let mut b = bytes.clone();
            let end = (at + pattern.len()).min(b.len());
            b[at..end].copy_from_slice(&pattern[..end - at]);
            std::fs::write(&bad, &b).unwrap();
            let mut reader = match sins_data::DatasetReader::open(&bad) {
                Ok(r) => r,
                Err(e) => {
                    assert!(e.to_string().contains("bad.parquet"), "{e}");
                    refused += 1;
                    continue;
                }
            };
            let mut batch = sins_data::SampleBatch::default();
            loop {
                match reader.next_batch_into(&mut batch) {
                    Ok(true) => {}
                    Ok(false) => {
                        read += 1;
                        break;
                    }
                    Err(e) => {
                        assert!(e.to_string().contains("bad.parquet"), "{e}");
                        refused += 1;
                        break;
                    }
                }
            }
        }
    }
    assert_eq!(refused + read, 4 * bytes.len());
    // Most offsets hold header or footer bytes or data the plausibility checks refuse.
    assert!(refused > bytes.len(), "{refused} refused, {read} read");
}
