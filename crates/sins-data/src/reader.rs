//! [`DatasetReader`]: format detection, validation and bounded-batch streaming.

use std::fs::File;
use std::io::Read;
use std::path::Path;

use crate::csv_read::{CsvSource, open_csv};
use crate::error::DataError;
use crate::pq_read::{ParquetSource, open_parquet};
use crate::schema::{DatasetInfo, SampleBatch};

// One reader per open file: the variant size difference costs nothing.
#[allow(clippy::large_enum_variant)]
enum Source {
    Parquet(ParquetSource),
    Csv(CsvSource),
}

/// Streaming dataset reader. [`DatasetReader::open`] detects the format (Parquet by its `PAR1`
/// magic, otherwise CSV), validates metadata and schema (CSV files are fully validated on open);
/// [`DatasetReader::next_batch`] then yields batches of at most
/// [`crate::MAX_BATCH_ROWS`] rows in file order, validating values and the time axis. Parquet
/// row groups are decoded on a background thread one row group ahead, so resident memory stays
/// at a few row groups whatever the file size.
pub struct DatasetReader {
    info: DatasetInfo,
    source: Source,
}

impl DatasetReader {
    /// Open a dataset file.
    pub fn open(path: impl AsRef<Path>) -> Result<Self, DataError> {
        let path = path.as_ref();
        let mut f = File::open(path).map_err(|e| DataError::io(path, "opening", e))?;
        let mut head = [0u8; 4096];
        let mut n = 0;
        while n < head.len() {
            match f.read(&mut head[n..]) {
                Ok(0) => break,
                Ok(k) => n += k,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(DataError::io(path, "reading", e)),
            }
        }
        let head = &head[..n];
        if n == 0 {
            return Err(DataError::NotADataset {
                file: path.to_path_buf(),
                reason: "the file is empty (0 bytes)".to_string(),
            });
        }
        if head.starts_with(b"PAR1") {
            let (info, src) = open_parquet(path, f)?;
            return Ok(Self {
                info,
                source: Source::Parquet(src),
            });
        }
        let text_ok = !head.contains(&0)
            && match std::str::from_utf8(head) {
                Ok(_) => true,
                // A multi-byte character cut by the 4 KiB window is fine.
                Err(e) => e.error_len().is_none(),
            };
        if !text_ok {
            return Err(DataError::NotADataset {
                file: path.to_path_buf(),
                reason: "not Parquet (no PAR1 magic) and not CSV text".to_string(),
            });
        }
        let (info, src) = open_csv(path, f)?;
        Ok(Self {
            info,
            source: Source::Csv(src),
        })
    }

    /// What was learned when opening: metadata, columns, row count, segment labels, path.
    pub fn info(&self) -> &DatasetInfo {
        &self.info
    }

    /// The next batch (at most [`crate::MAX_BATCH_ROWS`] rows), `None` after the last one.
    /// After an error, further calls return `Ok(None)`.
    pub fn next_batch(&mut self) -> Result<Option<SampleBatch>, DataError> {
        match &mut self.source {
            Source::Parquet(p) => p.next_batch(),
            Source::Csv(c) => c.next_batch(&self.info),
        }
    }
}

impl DatasetReader {
    /// Give a consumed batch back so its buffers are reused for a later batch. Optional, but it
    /// avoids allocating (and page-faulting) ~10 MB per batch, which is a large part of the
    /// cost of replaying a long dataset.
    pub fn recycle(&mut self, batch: SampleBatch) {
        match &mut self.source {
            Source::Parquet(p) => p.recycle(batch),
            Source::Csv(c) => c.recycle(batch),
        }
    }

    /// Replace `batch` with the next batch, recycling its previous buffers; `Ok(false)` (and
    /// an empty `batch`) after the last one. The allocation-free way to stream a dataset:
    ///
    /// ```no_run
    /// # fn main() -> Result<(), sins_data::DataError> {
    /// let mut reader = sins_data::DatasetReader::open("run.parquet")?;
    /// let mut batch = sins_data::SampleBatch::default();
    /// while reader.next_batch_into(&mut batch)? {
    ///     for s in &batch.samples { let _ = s.t_s; }
    /// }
    /// # Ok(()) }
    /// ```
    pub fn next_batch_into(&mut self, batch: &mut SampleBatch) -> Result<bool, DataError> {
        let old = std::mem::take(batch);
        if old.samples.capacity() > 0 {
            self.recycle(old);
        }
        match self.next_batch()? {
            Some(b) => {
                *batch = b;
                Ok(true)
            }
            None => Ok(false),
        }
    }
}

impl Iterator for DatasetReader {
    type Item = Result<SampleBatch, DataError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_batch().transpose()
    }
}

/// Read a whole dataset into one batch (for small files and tests; memory grows with the file).
pub fn read_all(path: impl AsRef<Path>) -> Result<(DatasetInfo, SampleBatch), DataError> {
    let mut reader = DatasetReader::open(path)?;
    let cols = reader.info().columns;
    let mut all = SampleBatch {
        first_row: 0,
        samples: Vec::new(),
        segment_index: cols.segment.then(Vec::new),
        reference: cols.reference.then(Vec::new),
    };
    while let Some(batch) = reader.next_batch()? {
        all.samples.extend(batch.samples);
        if let (Some(a), Some(b)) = (all.segment_index.as_mut(), batch.segment_index) {
            a.extend(b);
        }
        if let (Some(a), Some(b)) = (all.reference.as_mut(), batch.reference) {
            a.extend(b);
        }
    }
    Ok((reader.info, all))
}
