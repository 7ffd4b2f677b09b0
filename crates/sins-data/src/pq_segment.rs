//! The `segment` column chunk of one row group, encoded here rather than by the `parquet`
//! crate's column writer, which builds a dictionary from the values it sees: this one writes a
//! PLAIN dictionary page holding the writer's labels in their order, unused ones included (so a
//! reader gets exactly that label list back, as from files written before), then RLE_DICTIONARY
//! data pages of the rows' label indices (Parquet v1 pages, the column being required). The
//! pages are not compressed: a few labels and run-length-encoded indices take a few bytes per
//! row group.

use bytes::Bytes;
use parquet::basic::{Compression, Encoding};
use parquet::column::page::{CompressedPage, Page, PageWriter};
use parquet::column::writer::ColumnCloseResult;
use parquet::errors::{ParquetError, Result};
use parquet::file::metadata::ColumnChunkMetaData;
use parquet::file::writer::{SerializedPageWriter, TrackedWrite};
use parquet::schema::types::ColumnDescPtr;

/// Rows per data page (bounds a page whatever the row-group size).
const PAGE_ROWS: usize = 1 << 16;

/// The encoded chunk (to append with `SerializedRowGroupWriter::append_column`) and its
/// metadata, offsets relative to the chunk's start.
pub(crate) fn segment_chunk(
    descr: ColumnDescPtr,
    labels: &[String],
    keys: &[u16],
) -> Result<(Bytes, ColumnCloseResult)> {
    let mut dict = Vec::new();
    for label in labels {
        let len = u32::try_from(label.len())
            .map_err(|_| ParquetError::General("a segment label over 4 GiB".into()))?;
        dict.extend_from_slice(&len.to_le_bytes());
        dict.extend_from_slice(label.as_bytes());
    }
    let n_labels = u32::try_from(labels.len())
        .map_err(|_| ParquetError::General("too many segment labels".into()))?;
    // At least one bit, so that every reader takes the page as an ordinary one.
    let bit_width = (u32::BITS - n_labels.saturating_sub(1).leading_zeros()).max(1) as u8;
    let mut sink = TrackedWrite::new(Vec::new());
    let mut pages = SerializedPageWriter::new(&mut sink);
    let dict_len = dict.len();
    pages.write_page(CompressedPage::new(
        Page::DictionaryPage {
            buf: Bytes::from(dict),
            num_values: n_labels,
            encoding: Encoding::PLAIN,
            is_sorted: false,
        },
        dict_len,
    ))?;
    let mut data_offset = None;
    for chunk in keys.chunks(PAGE_ROWS) {
        let buf = rle_indices(chunk, bit_width);
        let len = buf.len();
        let spec = pages.write_page(CompressedPage::new(
            Page::DataPage {
                buf: Bytes::from(buf),
                num_values: chunk.len() as u32,
                encoding: Encoding::RLE_DICTIONARY,
                def_level_encoding: Encoding::RLE,
                rep_level_encoding: Encoding::RLE,
                statistics: None,
            },
            len,
        ))?;
        data_offset.get_or_insert(spec.offset);
    }
    pages.close()?;
    let bytes = Bytes::from(sink.into_inner()?);
    let size = bytes.len() as i64;
    let metadata = ColumnChunkMetaData::builder(descr)
        .set_compression(Compression::UNCOMPRESSED)
        .set_encodings(vec![
            Encoding::PLAIN,
            Encoding::RLE,
            Encoding::RLE_DICTIONARY,
        ])
        .set_num_values(keys.len() as i64)
        .set_total_compressed_size(size)
        .set_total_uncompressed_size(size)
        .set_dictionary_page_offset(Some(0))
        .set_data_page_offset(data_offset.unwrap_or(size as u64) as i64)
        .build()?;
    let close = ColumnCloseResult {
        bytes_written: size as u64,
        rows_written: keys.len() as u64,
        metadata,
        bloom_filter: None,
        column_index: None,
        offset_index: None,
    };
    Ok((bytes, close))
}

/// Dictionary indices as a Parquet data page body: the bit width, then the RLE/bit-packing
/// hybrid encoding using RLE runs only (runs of equal labels are long in a dataset).
fn rle_indices(keys: &[u16], bit_width: u8) -> Vec<u8> {
    let value_bytes = usize::from(bit_width).div_ceil(8);
    let mut out = vec![bit_width];
    let mut i = 0;
    while let Some(&key) = keys.get(i) {
        let run = keys[i..].iter().take_while(|&&k| k == key).count();
        // Header: ULEB128 of (run length << 1), low bit 0 = an RLE run.
        let mut header = (run as u64) << 1;
        loop {
            let byte = (header & 0x7f) as u8;
            header >>= 7;
            if header == 0 {
                out.push(byte);
                break;
            }
            out.push(byte | 0x80);
        }
        out.extend_from_slice(&key.to_le_bytes()[..value_bytes]);
        i += run;
    }
    out
}
