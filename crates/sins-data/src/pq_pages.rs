//! Where the `parquet` crate's page reader gets a column chunk's pages from: the chunk's bytes
//! in memory (read with one positioned read per chunk into a buffer reused from row group to
//! row group), each page's header checked before the column reader sees it.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;
use std::sync::Arc;

use bytes::{Buf, Bytes, BytesMut};
use parquet::basic::Encoding;
use parquet::column::page::{Page, PageMetadata, PageReader};
use parquet::errors::ParquetError;
use parquet::file::reader::{ChunkReader, Length};
use parquet::file::serialized_reader::SerializedPageReader;

use crate::error::DataError;
use crate::pq_batch::ReadPlan;

/// A [`ParquetError`] as a [`DataError`]: an operating-system I/O error stays one, anything else
/// means the file is corrupt; `what` says where (row group, column).
pub(crate) fn pq_err(file: &Path, what: &str, e: ParquetError) -> DataError {
    if let ParquetError::External(inner) = &e
        && let Some(io) = inner.downcast_ref::<std::io::Error>()
        && io.kind() != std::io::ErrorKind::UnexpectedEof
    {
        let source = std::io::Error::new(io.kind(), io.to_string());
        return DataError::io(file, "reading the Parquet file", source);
    }
    DataError::corrupt(file, format!("{what}: {e}"))
}

/// "row group 3, column 't_s'".
pub(crate) fn at(rg: usize, name: &str) -> String {
    format!("row group {rg}, column '{name}'")
}

/// The byte range of leaf column `leaf` in row group `rg` (checked on open to lie in the file).
fn chunk_range(plan: &ReadPlan, rg: usize, leaf: usize) -> Option<(u64, usize)> {
    let chunk = plan.metadata.row_groups().get(rg)?.columns().get(leaf)?;
    let start = chunk
        .dictionary_page_offset()
        .unwrap_or(chunk.data_page_offset());
    Some((
        u64::try_from(start).ok()?,
        usize::try_from(chunk.compressed_size()).ok()?,
    ))
}

/// The page reader of leaf column `leaf` in row group `rg`, reading its bytes from `source`
/// (the byte range was checked on open: the `parquet` crate asserts it is not negative).
pub(crate) fn pages<R: ChunkReader + 'static>(
    plan: &ReadPlan,
    rg: usize,
    leaf: usize,
    name: &str,
    source: Arc<R>,
) -> Result<CheckedPages<R>, DataError> {
    let path = plan.path.as_path();
    let chunk = plan
        .metadata
        .row_groups()
        .get(rg)
        .and_then(|g| g.columns().get(leaf))
        .ok_or_else(|| DataError::corrupt(path, format!("{}: not in the footer", at(rg, name))))?;
    let rows = plan.rg_rows.get(rg).copied().unwrap_or(0);
    let inner = SerializedPageReader::new(source, chunk, rows, None)
        .map_err(|e| pq_err(path, &at(rg, name), e))?;
    Ok(CheckedPages {
        inner,
        max_def: chunk.column_descr().max_def_level(),
        seen_dict: false,
        seen_data: false,
    })
}

/// The column chunks of one row group, read into memory with one positioned read each (into a
/// buffer reused from row group to row group) and handed to the page readers without copies.
#[derive(Default)]
pub(crate) struct RowGroupBytes {
    /// The buffer of the previous row group, reclaimed once its pages are gone.
    last: Option<Bytes>,
}

impl RowGroupBytes {
    /// Read the chunks of `leaves` in row group `rg`; one source per leaf, in that order.
    pub fn load(
        &mut self,
        plan: &ReadPlan,
        rg: usize,
        leaves: &[(usize, &str)],
    ) -> Result<Vec<Arc<ChunkBytes>>, DataError> {
        let path = plan.path.as_path();
        let mut ranges = Vec::with_capacity(leaves.len());
        for &(leaf, name) in leaves {
            let range = chunk_range(plan, rg, leaf);
            ranges.push(range.ok_or_else(|| {
                DataError::corrupt(path, format!("{}: no byte range", at(rg, name)))
            })?);
        }
        let total: usize = ranges.iter().map(|r| r.1).sum();
        // Reuse the previous buffer when nothing refers to it any more; its bytes past `total`
        // are stale and never looked at, and it is only zeroed where it grows.
        let mut buf = match self.last.take().map(Bytes::try_into_mut) {
            Some(Ok(b)) => b,
            _ => BytesMut::new(),
        };
        if buf.len() < total {
            buf.resize(total, 0);
        }
        // Positioned reads through the shared handle: only the decoder thread reads now.
        let mut file: &File = &plan.file;
        let mut offset = 0;
        for (&(start, len), &(_, name)) in ranges.iter().zip(leaves) {
            file.seek(SeekFrom::Start(start))
                .and_then(|_| file.read_exact(&mut buf[offset..offset + len]))
                .map_err(|e| match e.kind() {
                    std::io::ErrorKind::UnexpectedEof => DataError::corrupt(
                        path,
                        format!("{}: the file ends inside the column", at(rg, name)),
                    ),
                    _ => DataError::io(path, "reading a column chunk", e),
                })?;
            offset += len;
        }
        let all = buf.freeze();
        let mut offset = 0;
        let sources = ranges
            .iter()
            .map(|&(start, len)| {
                let bytes = all.slice(offset..offset + len);
                offset += len;
                Arc::new(ChunkBytes { start, bytes })
            })
            .collect();
        self.last = Some(all);
        Ok(sources)
    }
}

/// One column chunk's bytes, served to the page reader at their offsets in the file.
pub(crate) struct ChunkBytes {
    start: u64,
    bytes: Bytes,
}

impl ChunkBytes {
    fn slice(&self, start: u64, len: Option<usize>) -> parquet::errors::Result<Bytes> {
        let from = start
            .checked_sub(self.start)
            .and_then(|o| usize::try_from(o).ok())
            .filter(|&o| o <= self.bytes.len());
        let to = from.and_then(|o| len.map_or(Some(self.bytes.len()), |l| o.checked_add(l)));
        match (from, to) {
            (Some(from), Some(to)) if to <= self.bytes.len() => Ok(self.bytes.slice(from..to)),
            _ => Err(ParquetError::EOF(format!(
                "a page at offset {start} runs past the end of its column chunk"
            ))),
        }
    }
}

impl Length for ChunkBytes {
    fn len(&self) -> u64 {
        self.start + self.bytes.len() as u64
    }
}

impl ChunkReader for ChunkBytes {
    type T = bytes::buf::Reader<Bytes>;

    fn get_read(&self, start: u64) -> parquet::errors::Result<Self::T> {
        Ok(self.slice(start, None)?.reader())
    }

    fn get_bytes(&self, start: u64, length: usize) -> parquet::errors::Result<Bytes> {
        self.slice(start, Some(length))
    }
}

/// The pages of a column chunk, each checked before the `parquet` crate's column reader sees
/// it: that reader trusts a page's header where it should not (it panics on a
/// dictionary-encoded page without a dictionary page, and slices a buffer by the level lengths
/// a header declares), so a damaged header is refused here instead.
pub(crate) struct CheckedPages<R: ChunkReader + 'static> {
    inner: SerializedPageReader<R>,
    max_def: i16,
    seen_dict: bool,
    seen_data: bool,
}

impl<R: ChunkReader + 'static> CheckedPages<R> {
    fn check(&mut self, page: &Page) -> Result<(), ParquetError> {
        let bad = |why: &str| Err(ParquetError::General(format!("damaged page header: {why}")));
        let (encoding, levels_len) = match page {
            Page::DictionaryPage { .. } => {
                if self.seen_dict || self.seen_data {
                    return bad("a dictionary page after the first page");
                }
                self.seen_dict = true;
                return Ok(());
            }
            #[allow(deprecated)]
            Page::DataPage {
                buf,
                num_values,
                encoding,
                def_level_encoding: Encoding::BIT_PACKED,
                ..
            } if self.max_def > 0 => {
                let bits = u64::from(u16::BITS - (self.max_def as u16).leading_zeros());
                let need = (u64::from(*num_values) * bits).div_ceil(8);
                (*encoding, (need, buf.len() as u64))
            }
            Page::DataPage { encoding, .. } => (*encoding, (0, 0)),
            Page::DataPageV2 {
                buf,
                encoding,
                def_levels_byte_len,
                rep_levels_byte_len,
                ..
            } => {
                let need = u64::from(*def_levels_byte_len) + u64::from(*rep_levels_byte_len);
                (*encoding, (need, buf.len() as u64))
            }
        };
        self.seen_data = true;
        if matches!(
            encoding,
            Encoding::RLE_DICTIONARY | Encoding::PLAIN_DICTIONARY
        ) && !self.seen_dict
        {
            return bad("a dictionary-encoded data page without a dictionary page");
        }
        if levels_len.0 > levels_len.1 {
            return bad("definition and repetition levels longer than the page");
        }
        Ok(())
    }
}

impl<R: ChunkReader + 'static> Iterator for CheckedPages<R> {
    type Item = parquet::errors::Result<Page>;

    fn next(&mut self) -> Option<Self::Item> {
        self.get_next_page().transpose()
    }
}

impl<R: ChunkReader + 'static> PageReader for CheckedPages<R> {
    fn get_next_page(&mut self) -> parquet::errors::Result<Option<Page>> {
        let page = self.inner.get_next_page()?;
        if let Some(p) = &page {
            self.check(p)?;
        }
        Ok(page)
    }

    fn peek_next_page(&mut self) -> parquet::errors::Result<Option<PageMetadata>> {
        self.inner.peek_next_page()
    }

    fn skip_next_page(&mut self) -> parquet::errors::Result<()> {
        self.inner.skip_next_page()
    }
}
