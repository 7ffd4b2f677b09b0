//! The `segment` column's label indices straight from its dictionary-encoded pages: the
//! dictionary page maps each entry to a label, the data pages' RLE/bit-packing hybrid indices
//! (parquet.apache.org, "Encodings") are mapped through it. This is what this crate and the
//! earlier writer write (a required column, every data page dictionary-encoded); it spares the
//! column reader's strings, a reference-counted copy per row that made a 15 h dataset with a
//! segment column read three times slower. Other `segment` chunks go through the column reader.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use bytes::Bytes;
use parquet::basic::Encoding;
use parquet::column::page::{Page, PageReader};

use crate::error::{DataError, RowRef};
use crate::pq_batch::ReadPlan;
use crate::pq_pages::{CheckedPages, ChunkBytes, at, pages, pq_err};
use crate::schema::SEGMENT_COLUMN;

/// The values of a PLAIN-encoded BYTE_ARRAY dictionary page, as UTF-8 strings.
pub(crate) fn dictionary_values(buf: &[u8], num_values: u32) -> Result<Vec<&str>, String> {
    let mut rest = buf;
    let mut out = Vec::new();
    for _ in 0..num_values {
        let (len, tail) = rest
            .split_first_chunk::<4>()
            .ok_or("truncated dictionary page")?;
        let len = u32::from_le_bytes(*len) as usize;
        if tail.len() < len {
            return Err("truncated dictionary page".into());
        }
        let (value, tail) = tail.split_at(len);
        out.push(std::str::from_utf8(value).map_err(|_| "a dictionary value is not UTF-8")?);
        rest = tail;
    }
    Ok(out)
}

/// Label indices of one row group's `segment` chunk, read in row order.
pub(crate) struct SegmentIndices {
    pages: CheckedPages<ChunkBytes>,
    rg: usize,
    /// Label index of each dictionary entry.
    map: Vec<u16>,
    /// Indices of the current data page.
    run: Hybrid,
    /// Values left in the current data page.
    page_left: usize,
    /// Dataset row of the next value.
    next_row: u64,
}

impl SegmentIndices {
    /// Start reading the chunk of row group `rg` (first dataset row `first_row`) from `source`.
    pub fn open(
        plan: &ReadPlan,
        rg: usize,
        leaf: usize,
        first_row: u64,
        source: Arc<ChunkBytes>,
    ) -> Result<Self, DataError> {
        Ok(Self {
            pages: pages(plan, rg, leaf, SEGMENT_COLUMN, source)?,
            rg,
            map: Vec::new(),
            run: Hybrid::default(),
            page_left: 0,
            next_row: first_row,
        })
    }

    fn corrupt(&self, file: &Path, why: impl std::fmt::Display) -> DataError {
        let row = self.next_row;
        DataError::corrupt(
            file,
            format!("{} near row {row}: {why}", at(self.rg, SEGMENT_COLUMN)),
        )
    }

    /// Move to the next data page; `false` at the end of the chunk.
    fn next_page(&mut self, file: &Path, lookup: &HashMap<String, u16>) -> Result<bool, DataError> {
        loop {
            let page = self
                .pages
                .get_next_page()
                .map_err(|e| pq_err(file, &at(self.rg, SEGMENT_COLUMN), e))?;
            let (buf, num_values, encoding) = match page {
                None => return Ok(false),
                Some(Page::DictionaryPage {
                    buf, num_values, ..
                }) => {
                    let values = dictionary_values(&buf, num_values)
                        .map_err(|why| self.corrupt(file, why))?;
                    let mut map = Vec::with_capacity(values.len());
                    for v in values {
                        let label = lookup.get(v).ok_or_else(|| {
                            self.corrupt(file, format!("label {v:?} was not seen on open"))
                        })?;
                        map.push(*label);
                    }
                    self.map = map;
                    continue;
                }
                Some(Page::DataPage {
                    buf,
                    num_values,
                    encoding,
                    ..
                }) => (buf, num_values, encoding),
                Some(Page::DataPageV2 {
                    buf,
                    num_values,
                    encoding,
                    num_nulls,
                    def_levels_byte_len,
                    rep_levels_byte_len,
                    ..
                }) => {
                    if num_nulls > 0 {
                        return Err(self.corrupt(file, "nulls in a required column"));
                    }
                    // The page check made sure the levels fit in the page.
                    let levels =
                        (def_levels_byte_len as usize).saturating_add(rep_levels_byte_len as usize);
                    (buf.slice(levels.min(buf.len())..), num_values, encoding)
                }
            };
            if !matches!(
                encoding,
                Encoding::RLE_DICTIONARY | Encoding::PLAIN_DICTIONARY
            ) {
                return Err(self.corrupt(file, "a data page that is not dictionary-encoded"));
            }
            self.run = Hybrid::new(buf).map_err(|why| self.corrupt(file, why))?;
            self.page_left = num_values as usize;
            if self.page_left > 0 {
                return Ok(true);
            }
        }
    }

    /// The next `n` label indices, in `out` (replacing its contents).
    pub fn read(
        &mut self,
        file: &Path,
        n: usize,
        lookup: &HashMap<String, u16>,
        out: &mut Vec<u16>,
    ) -> Result<(), DataError> {
        out.clear();
        out.reserve(n);
        while out.len() < n {
            if self.page_left == 0 && !self.next_page(file, lookup)? {
                return Err(self.corrupt(file, "the column ends before the row group"));
            }
            let k = (n - out.len()).min(self.page_left);
            let before = out.len();
            if let Err(why) = self.run.decode(k, &self.map, out) {
                self.next_row += (out.len() - before) as u64;
                let at = RowRef::row(self.next_row);
                return Err(DataError::BadSegment {
                    file: file.to_path_buf(),
                    at,
                    reason: why,
                });
            }
            self.page_left -= k;
            self.next_row += k as u64;
        }
        Ok(())
    }

    /// Check that the chunk holds no value beyond the row group's rows.
    pub fn finish(&mut self, file: &Path, lookup: &HashMap<String, u16>) -> Result<(), DataError> {
        if self.page_left > 0 || self.next_page(file, lookup)? {
            return Err(self.corrupt(file, "more values than the row group's rows"));
        }
        Ok(())
    }
}

/// A decoder of the RLE/bit-packing hybrid encoding of dictionary indices (bit width first).
#[derive(Default)]
struct Hybrid {
    buf: Bytes,
    /// Byte position of the next run header.
    pos: usize,
    bit_width: usize,
    /// Values left in the current RLE run, and its label index.
    rle_left: usize,
    rle_label: u16,
    /// Values left in the current bit-packed run, and the bit position of the next one.
    packed_left: usize,
    bit_pos: usize,
}

impl Hybrid {
    fn new(buf: Bytes) -> Result<Self, String> {
        let bit_width = usize::from(*buf.first().ok_or("an empty data page")?);
        if bit_width > 32 {
            return Err(format!("a dictionary index width of {bit_width} bits"));
        }
        Ok(Self {
            buf,
            pos: 1,
            bit_width,
            ..Self::default()
        })
    }

    /// Append `k` label indices to `out`; an error says what is wrong with the data.
    fn decode(&mut self, mut k: usize, map: &[u16], out: &mut Vec<u16>) -> Result<(), String> {
        let label = |index: u64| -> Result<u16, String> {
            usize::try_from(index)
                .ok()
                .and_then(|i| map.get(i).copied())
                .ok_or_else(|| format!("dictionary index {index} beyond its {} entries", map.len()))
        };
        while k > 0 {
            if self.rle_left > 0 {
                let m = k.min(self.rle_left);
                out.extend(std::iter::repeat_n(self.rle_label, m));
                self.rle_left -= m;
                k -= m;
            } else if self.packed_left > 0 {
                let m = k.min(self.packed_left);
                for _ in 0..m {
                    let index = self
                        .bits(self.bit_pos)
                        .ok_or("bit-packed indices end early")?;
                    out.push(label(index)?);
                    self.bit_pos += self.bit_width;
                }
                self.packed_left -= m;
                k -= m;
            } else {
                let header = self.uleb128().ok_or("the indices end early")?;
                let count = usize::try_from(header >> 1).map_err(|_| "a run too long")?;
                if header & 1 == 0 {
                    let width = self.bit_width.div_ceil(8);
                    let end = self.pos.checked_add(width).ok_or("a run ends early")?;
                    let bytes = self.buf.get(self.pos..end).ok_or("a run ends early")?;
                    let index = bytes.iter().rev().fold(0u64, |v, &b| v << 8 | u64::from(b));
                    self.pos += width;
                    self.rle_label = label(index)?;
                    self.rle_left = count;
                } else {
                    let values = count.checked_mul(8).ok_or("a run too long")?;
                    let bytes = count.checked_mul(self.bit_width).ok_or("a run too long")?;
                    self.bit_pos = self.pos * 8;
                    self.pos = self.pos.saturating_add(bytes);
                    self.packed_left = values;
                }
            }
        }
        Ok(())
    }

    /// The `bit_width` bits at bit position `at` (least significant bit first), if all there.
    fn bits(&self, at: usize) -> Option<u64> {
        let (first, shift) = (at / 8, at % 8);
        let last = (at + self.bit_width).div_ceil(8);
        let bytes = self.buf.get(first..last.max(first))?;
        let word = bytes.iter().rev().fold(0u64, |v, &b| v << 8 | u64::from(b));
        Some((word >> shift) & ((1u64 << self.bit_width) - 1))
    }

    /// The ULEB128 number at `pos` (at most 5 bytes), moving past it.
    fn uleb128(&mut self) -> Option<u64> {
        let mut v = 0u64;
        for i in 0..5 {
            let b = *self.buf.get(self.pos)?;
            self.pos += 1;
            v |= u64::from(b & 0x7f) << (7 * i);
            if b & 0x80 == 0 {
                return Some(v);
            }
        }
        None
    }
}
