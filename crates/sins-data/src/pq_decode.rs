//! Low-level Parquet decoding of one column chunk at a time (polars-parquet), reading only the
//! chunk's bytes with positioned reads (no whole-file mmap, so resident memory stays bounded).

use std::collections::HashMap;
use std::fs::File;
use std::io::{Cursor, Read, Seek, SeekFrom};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;

use polars::prelude::PlSmallStr;
use polars_arrow::array::{Array, PrimitiveArray, Utf8ViewArray};
use polars_arrow::datatypes::{ArrowDataType, Field};
use polars_buffer::Buffer;
use polars_parquet::parquet::encoding::Encoding;
use polars_parquet::parquet::page::split_buffer;
use polars_parquet::read::{
    BasicDecompressor, ColumnChunkMetadata, PageReader, PhysicalType, RowGroupMetadata,
    column_iter_to_arrays,
};

use crate::error::{DataError, RowRef};
use crate::schema::{MAX_SEGMENT_LABELS, SEGMENT_COLUMN};

/// Largest page (compressed or not) the reader will allocate for (guards corrupt headers).
const MAX_PAGE_BYTES: usize = 1 << 28;

/// Run `f`, turning a panic inside the Parquet decoder into a [`DataError::CorruptParquet`].
pub(crate) fn no_panic<T>(
    file: &Path,
    f: impl FnOnce() -> Result<T, DataError>,
) -> Result<T, DataError> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(DataError::corrupt(file, format!("decoder failed: {msg}")))
        }
    }
}

/// The single leaf column chunk of root column `name` in a row group.
pub(crate) fn chunk_of<'a>(
    file: &Path,
    rg: &'a RowGroupMetadata,
    name: &str,
) -> Result<&'a ColumnChunkMetadata, DataError> {
    let mut it = rg
        .columns_under_root_iter(name)
        .ok_or_else(|| DataError::corrupt(file, format!("row group lacks column '{name}'")))?;
    let first = it
        .next()
        .ok_or_else(|| DataError::corrupt(file, format!("row group lacks column '{name}'")))?;
    if it.next().is_some() {
        return Err(DataError::WrongColumnType {
            file: file.to_path_buf(),
            column: name.to_string(),
            expected: "a flat column",
            found: "a nested column".to_string(),
        });
    }
    Ok(first)
}

/// Buffers the decoder thread reuses from row group to row group, so steady-state reading
/// allocates (and page-faults) almost nothing.
#[derive(Default)]
pub(crate) struct Scratch {
    /// Raw bytes of the current column chunk.
    chunk: Vec<u8>,
    /// Page decompression buffer.
    decomp: Vec<u8>,
}

/// Read the raw (compressed) bytes of a column chunk into `out` (replacing its contents).
fn read_chunk_into(
    file: &Path,
    f: &mut File,
    chunk: &ColumnChunkMetadata,
    out: &mut Vec<u8>,
) -> Result<(), DataError> {
    let range = chunk.byte_range();
    let len = range.end.saturating_sub(range.start);
    out.clear();
    let got = f
        .seek(SeekFrom::Start(range.start))
        .and_then(|_| f.take(len).read_to_end(out))
        .map_err(|e| DataError::io(file, "reading a column chunk", e))?;
    if got as u64 != len {
        return Err(DataError::corrupt(
            file,
            "column chunk extends past the end of the file",
        ));
    }
    Ok(())
}

/// Read the raw (compressed) bytes of a column chunk.
pub(crate) fn read_chunk(
    file: &Path,
    f: &mut File,
    chunk: &ColumnChunkMetadata,
) -> Result<Buffer<u8>, DataError> {
    let mut buf = Vec::new();
    read_chunk_into(file, f, chunk, &mut buf)?;
    Ok(Buffer::from_vec(buf))
}

/// Read and decode a Float64 column chunk of `n_rows` rows into `out` (replacing its
/// contents). Required, plain-encoded columns (what this crate writes) are decoded directly
/// with reused buffers; anything else goes through the general polars decoder.
#[allow(clippy::too_many_arguments)]
pub(crate) fn decode_f64_into(
    file: &Path,
    f: &mut File,
    chunk: &ColumnChunkMetadata,
    name: &str,
    first_row: u64,
    n_rows: usize,
    scratch: &mut Scratch,
    out: &mut Vec<f64>,
) -> Result<(), DataError> {
    read_chunk_into(file, f, chunk, &mut scratch.chunk)?;
    out.clear();
    out.reserve(n_rows);
    let decomp = &mut scratch.decomp;
    let fast = Buffer::with_vec(&mut scratch.chunk, |bytes| {
        plain_required_f64(file, chunk, bytes, decomp, out)
    })?;
    if !fast {
        out.clear();
        let bytes = Buffer::from_vec(scratch.chunk.clone());
        let values = decode_f64(file, chunk, bytes, name, first_row, n_rows)?;
        out.extend_from_slice(&values);
    }
    if out.len() != n_rows {
        return Err(DataError::corrupt(
            file,
            format!(
                "column '{name}' has {} values in a row group of {n_rows} rows",
                out.len()
            ),
        ));
    }
    Ok(())
}

/// Fast path for a required (non-null), plain-encoded DOUBLE chunk; `Ok(false)` when the chunk
/// is not of that kind. Every clone of `bytes` is dropped before returning.
fn plain_required_f64(
    file: &Path,
    chunk: &ColumnChunkMetadata,
    bytes: Buffer<u8>,
    decomp: &mut Vec<u8>,
    out: &mut Vec<f64>,
) -> Result<bool, DataError> {
    let desc = &chunk.descriptor().descriptor;
    if desc.max_def_level != 0
        || desc.max_rep_level != 0
        || desc.primitive_type.physical_type != PhysicalType::Double
    {
        return Ok(false);
    }
    let pages = PageReader::new(Cursor::new(bytes), chunk, vec![], MAX_PAGE_BYTES);
    let mut d = BasicDecompressor::new(pages, std::mem::take(decomp));
    let corrupt = |e: &dyn std::fmt::Display| DataError::corrupt(file, e);
    let mut run = || -> Result<bool, DataError> {
        if d.read_dict_page().map_err(|e| corrupt(&e))?.is_some() {
            return Ok(false);
        }
        while let Some(item) = d.next() {
            let page = item
                .and_then(|it| it.decompress(&mut d))
                .map_err(|e| corrupt(&e))?;
            if page.encoding() != Encoding::Plain {
                return Ok(false);
            }
            let n = page.num_values();
            let values = split_buffer(&page).map_err(|e| corrupt(&e))?.values;
            let Some(values) = values.get(..n.saturating_mul(8)) else {
                return Err(corrupt(&"data page shorter than its value count"));
            };
            out.extend(
                values
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(<[u8; 8]>::try_from(b).unwrap_or_default())),
            );
            d.reuse_page_buffer(page);
        }
        Ok(true)
    };
    let r = run();
    *decomp = d.into_inner();
    r
}

fn decompressor(chunk: &ColumnChunkMetadata, bytes: Buffer<u8>) -> BasicDecompressor {
    let pages = PageReader::new(Cursor::new(bytes), chunk, vec![], MAX_PAGE_BYTES);
    BasicDecompressor::new(pages, vec![])
}

/// Decode a whole column chunk into arrays of the requested type.
fn decode(
    file: &Path,
    chunk: &ColumnChunkMetadata,
    bytes: Buffer<u8>,
    name: &str,
    dtype: ArrowDataType,
) -> Result<Vec<Box<dyn Array>>, DataError> {
    let field = Field::new(PlSmallStr::from_str(name), dtype, true);
    let ptype = &chunk.descriptor().descriptor.primitive_type;
    let (arrays, _) =
        column_iter_to_arrays(vec![decompressor(chunk, bytes)], vec![ptype], field, None)
            .map_err(|e| DataError::corrupt(file, format!("column '{name}': {e}")))?;
    Ok(arrays)
}

/// Decode a Float64 column chunk of `n_rows` rows; nulls are reported at their row.
fn decode_f64(
    file: &Path,
    chunk: &ColumnChunkMetadata,
    bytes: Buffer<u8>,
    name: &str,
    first_row: u64,
    n_rows: usize,
) -> Result<Buffer<f64>, DataError> {
    let arrays = decode(file, chunk, bytes, name, ArrowDataType::Float64)?;
    let mut parts: Vec<Buffer<f64>> = Vec::with_capacity(arrays.len());
    let mut offset = 0u64;
    for a in &arrays {
        let a = a
            .as_any()
            .downcast_ref::<PrimitiveArray<f64>>()
            .ok_or_else(|| DataError::corrupt(file, format!("column '{name}' is not Float64")))?;
        if let Some(i) = a.validity().and_then(|v| v.iter().position(|ok| !ok)) {
            return Err(null_value(file, first_row + offset + i as u64, name));
        }
        offset += a.len() as u64;
        parts.push(a.values().clone());
    }
    let total: usize = parts.iter().map(|p| p.len()).sum();
    if total != n_rows {
        return Err(DataError::corrupt(
            file,
            format!("column '{name}' has {total} values in a row group of {n_rows} rows"),
        ));
    }
    Ok(match parts.len() {
        1 => parts.pop().unwrap_or_default(),
        _ => Buffer::from_vec(parts.iter().flat_map(|p| p.iter().copied()).collect()),
    })
}

fn null_value(file: &Path, row: u64, column: &str) -> DataError {
    DataError::BadValue {
        file: file.to_path_buf(),
        at: RowRef::row(row),
        column: column.to_string(),
        text: String::new(),
        reason: "missing value (null)",
    }
}

/// Decode the segment column chunk and map each value to its label index.
pub(crate) fn decode_segment(
    file: &Path,
    chunk: &ColumnChunkMetadata,
    bytes: Buffer<u8>,
    lookup: &HashMap<String, u16>,
    first_row: u64,
    n_rows: usize,
) -> Result<Vec<u16>, DataError> {
    let arrays = decode(file, chunk, bytes, SEGMENT_COLUMN, ArrowDataType::Utf8View)?;
    let mut out = Vec::with_capacity(n_rows);
    for a in &arrays {
        let a = a
            .as_any()
            .downcast_ref::<Utf8ViewArray>()
            .ok_or_else(|| DataError::corrupt(file, "column 'segment' is not a string column"))?;
        let mut prev: Option<(u128, u16)> = None;
        for (i, view) in a.views().iter().enumerate() {
            let raw = view.as_u128();
            if let Some((p, idx)) = prev
                && p == raw
            {
                out.push(idx);
                continue;
            }
            let row = first_row + out.len() as u64;
            if a.validity().is_some_and(|v| !v.get_bit(i)) {
                return Err(null_value(file, row, SEGMENT_COLUMN));
            }
            let s = a.value(i);
            let idx = *lookup.get(s).ok_or_else(|| DataError::BadSegment {
                file: file.to_path_buf(),
                at: RowRef::row(row),
                reason: format!("value {s:?} is not in the column's dictionary"),
            })?;
            prev = Some((raw, idx));
            out.push(idx);
        }
    }
    if out.len() != n_rows {
        return Err(DataError::corrupt(
            file,
            format!(
                "column 'segment' has {} values in a row group of {n_rows} rows",
                out.len()
            ),
        ));
    }
    Ok(out)
}

/// Append the segment labels of one row group's chunk to `labels` (new ones only): the
/// dictionary page when every data page is dictionary-encoded (this keeps the writer's exact
/// label list, unused labels included), otherwise the distinct values in order of appearance.
pub(crate) fn collect_segment_labels(
    file: &Path,
    chunk: &ColumnChunkMetadata,
    bytes: Buffer<u8>,
    first_row: u64,
    labels: &mut Vec<String>,
    lookup: &mut HashMap<String, u16>,
) -> Result<(), DataError> {
    let corrupt =
        |e: &dyn std::fmt::Display| DataError::corrupt(file, format!("column 'segment': {e}"));
    let mut d = decompressor(chunk, bytes.clone());
    let dict = d.read_dict_page().map_err(|e| corrupt(&e))?;
    let mut all_dict_encoded = dict.is_some();
    while all_dict_encoded {
        let Some(item) = d.next() else { break };
        let page = item
            .and_then(|it| it.decompress(&mut d))
            .map_err(|e| corrupt(&e))?;
        all_dict_encoded = matches!(
            page.encoding(),
            Encoding::RleDictionary | Encoding::PlainDictionary
        );
    }
    let mut add = |s: &str| -> Result<(), DataError> {
        if !lookup.contains_key(s) {
            if labels.len() >= MAX_SEGMENT_LABELS {
                return Err(DataError::BadSegment {
                    file: file.to_path_buf(),
                    at: RowRef::row(first_row),
                    reason: format!("more than {MAX_SEGMENT_LABELS} distinct labels"),
                });
            }
            lookup.insert(s.to_string(), labels.len() as u16);
            labels.push(s.to_string());
        }
        Ok(())
    };
    match dict {
        Some(dict) if all_dict_encoded => {
            let mut rest: &[u8] = &dict.buffer;
            for _ in 0..dict.num_values {
                let (len, tail) = rest
                    .split_first_chunk::<4>()
                    .ok_or_else(|| corrupt(&"truncated dictionary page"))?;
                let len = u32::from_le_bytes(*len) as usize;
                if tail.len() < len {
                    return Err(corrupt(&"truncated dictionary page"));
                }
                let (value, tail) = tail.split_at(len);
                let s = std::str::from_utf8(value).map_err(|e| corrupt(&e))?;
                add(s)?;
                rest = tail;
            }
        }
        _ => {
            for a in decode(file, chunk, bytes, SEGMENT_COLUMN, ArrowDataType::Utf8View)? {
                if let Some(a) = a.as_any().downcast_ref::<Utf8ViewArray>() {
                    let mut prev: Option<&str> = None;
                    for s in a.values_iter() {
                        if prev != Some(s) {
                            add(s)?;
                            prev = Some(s);
                        }
                    }
                }
            }
        }
    }
    Ok(())
}
