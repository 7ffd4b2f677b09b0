//! [`DatasetWriter`]: validated, streaming, atomic dataset writing (Parquet or CSV by extension).

use std::path::{Path, PathBuf};

use crate::atomic::TempPath;
use crate::csv_write::CsvSink;
use crate::error::{DataError, RowRef};
use crate::meta::DatasetMeta;
use crate::pq_write::{ParquetSink, ParquetWriteOptions};
use crate::schema::{ColumnSet, DatasetFormat, MAX_SEGMENT_LABELS, SampleBatch, WriteSummary};
use crate::validate::{TimeCheck, non_finite};

enum Sink {
    Parquet(ParquetSink),
    Csv(CsvSink),
}

/// Streaming dataset writer. Rows go to a temporary file beside the target, which replaces the
/// target atomically in [`DatasetWriter::finish`]; dropping the writer or any error leaves the
/// target untouched. Rows are validated as they are written (finite values, strictly increasing
/// `t_s` with steps of 1/rate, segment indices in range), with the same errors a reader would
/// raise. Memory is bounded by one row group (Parquet) regardless of the dataset length.
pub struct DatasetWriter {
    // Field order matters: the sink (and its thread) is dropped before the temporary file.
    sink: Option<Sink>,
    temp: Option<TempPath>,
    path: PathBuf,
    format: DatasetFormat,
    columns: ColumnSet,
    float_names: Vec<&'static str>,
    n_labels: usize,
    time: TimeCheck,
    n_rows: u64,
    failed: bool,
    row: Vec<f64>,
    t_scratch: Vec<f64>,
}

impl DatasetWriter {
    /// Create a writer for `path` (`.parquet` or `.csv`) with default Parquet options.
    /// `segment_labels` are the labels that `SampleBatch::segment_index` refers to (used only
    /// when `columns.segment`).
    pub fn create(
        path: impl AsRef<Path>,
        meta: &DatasetMeta,
        columns: ColumnSet,
        segment_labels: &[String],
    ) -> Result<Self, DataError> {
        Self::create_with_options(
            path,
            meta,
            columns,
            segment_labels,
            ParquetWriteOptions::default(),
        )
    }

    /// Like [`DatasetWriter::create`] with explicit Parquet compression and row-group size
    /// (ignored for CSV).
    pub fn create_with_options(
        path: impl AsRef<Path>,
        meta: &DatasetMeta,
        columns: ColumnSet,
        segment_labels: &[String],
        options: ParquetWriteOptions,
    ) -> Result<Self, DataError> {
        let path = path.as_ref();
        let format = DatasetFormat::from_extension(path)?;
        meta.validate_for_write(path)?;
        let labels: &[String] = if columns.segment { segment_labels } else { &[] };
        if labels.len() > MAX_SEGMENT_LABELS {
            return Err(DataError::invalid_write(
                path,
                format!(
                    "{} segment labels (at most {MAX_SEGMENT_LABELS})",
                    labels.len()
                ),
            ));
        }
        let mut sorted: Vec<&String> = labels.iter().collect();
        sorted.sort();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(DataError::invalid_write(
                path,
                format!("duplicate segment label {:?}", w[0]),
            ));
        }
        if columns.segment && labels.is_empty() {
            return Err(DataError::invalid_write(
                path,
                "the segment column needs at least one label",
            ));
        }
        let (temp, file) = TempPath::create(path)?;
        let kv = meta.to_key_values();
        let sink = match format {
            DatasetFormat::Parquet => Sink::Parquet(ParquetSink::start(
                path, file, columns, labels, kv, options,
            )?),
            DatasetFormat::Csv => Sink::Csv(CsvSink::start(path, file, columns, labels, &kv)?),
        };
        let float_names = columns.float_columns();
        Ok(Self {
            sink: Some(sink),
            temp: Some(temp),
            path: path.to_path_buf(),
            format,
            columns,
            row: Vec::with_capacity(float_names.len()),
            float_names,
            n_labels: labels.len(),
            time: TimeCheck::new(meta.sample_rate_hz),
            n_rows: 0,
            failed: false,
            t_scratch: Vec::new(),
        })
    }

    /// Number of rows accepted so far.
    pub fn rows_written(&self) -> u64 {
        self.n_rows
    }

    /// Validate and append a batch. Its optional columns must match the writer's
    /// [`ColumnSet`] (temperatures are taken from the samples only when `columns.temperature`).
    /// After an error the writer is unusable and the target file is never touched.
    pub fn write_batch(&mut self, batch: &SampleBatch) -> Result<(), DataError> {
        if self.failed {
            return Err(DataError::invalid_write(
                &self.path,
                "the writer failed earlier; start a new one",
            ));
        }
        let r = self.write_rows(batch);
        if r.is_err() {
            self.failed = true;
        }
        r
    }

    fn write_rows(&mut self, batch: &SampleBatch) -> Result<(), DataError> {
        let n = batch.samples.len();
        let shape_err = |what: &str, has: bool, len: Option<usize>| {
            let reason = match len {
                Some(l) if has && l != n => format!("{what} has {l} rows but samples has {n}"),
                Some(_) if !has => format!("batch has {what} but the column set excludes it"),
                None if has => format!("the column set includes {what} but the batch lacks it"),
                _ => return None,
            };
            Some(reason)
        };
        let checks = [
            shape_err(
                "segment_index",
                self.columns.segment,
                batch.segment_index.as_ref().map(Vec::len),
            ),
            shape_err(
                "reference",
                self.columns.reference,
                batch.reference.as_ref().map(Vec::len),
            ),
        ];
        if let Some(reason) = checks.into_iter().flatten().next() {
            return Err(DataError::invalid_write(&self.path, reason));
        }
        self.validate(batch)?;
        let Some(sink) = self.sink.as_mut() else {
            return Err(DataError::invalid_write(&self.path, "the writer is closed"));
        };
        match sink {
            Sink::Parquet(p) => p.push_rows(
                &batch.samples,
                self.columns.temperature,
                batch.reference.as_deref(),
                batch.segment_index.as_deref(),
            )?,
            Sink::Csv(c) => {
                for i in 0..batch.samples.len() {
                    fill_row(&mut self.row, batch, i, self.columns.temperature);
                    let seg = batch.segment_index.as_ref().and_then(|v| v.get(i)).copied();
                    c.push_row(&self.row, seg)?;
                }
            }
        }
        self.n_rows += batch.samples.len() as u64;
        Ok(())
    }

    /// Check a whole batch (shapes already checked): finite values, the time axis, segment
    /// indices. Fast branch-free passes; the exact row and column are located only on failure.
    fn validate(&mut self, batch: &SampleBatch) -> Result<(), DataError> {
        let temps = self.columns.temperature;
        let finite = |v: &[f64]| v.iter().fold(true, |ok, x| ok & x.is_finite());
        let row_ok = |i: usize| {
            let s = &batch.samples[i];
            let mut ok =
                s.t_s.is_finite() & finite(s.dtheta_rad.as_slice()) & finite(s.dv_mps.as_slice());
            if temps {
                ok &= finite(&s.temp_degc);
            }
            if let Some(r) = batch.reference.as_ref().and_then(|r| r.get(i)) {
                ok &= finite(&r.to_array());
            }
            ok
        };
        if let Some(i) = (0..batch.samples.len()).find(|&i| !row_ok(i)) {
            fill_row(&mut self.row, batch, i, temps);
            let k = self.row.iter().position(|v| !v.is_finite()).unwrap_or(0);
            let at = RowRef::row(self.n_rows + i as u64);
            let column = self.float_names.get(k).copied().unwrap_or("?");
            return Err(non_finite(&self.path, at, column, self.row[k]));
        }
        self.t_scratch.clear();
        self.t_scratch.extend(batch.samples.iter().map(|s| s.t_s));
        self.time
            .check_slice(&self.path, self.n_rows, &self.t_scratch)?;
        if let Some(seg) = &batch.segment_index
            && let Some(i) = seg.iter().position(|&s| usize::from(s) >= self.n_labels)
        {
            return Err(DataError::BadSegment {
                file: self.path.clone(),
                at: RowRef::row(self.n_rows + i as u64),
                reason: format!(
                    "segment index {} out of range ({} labels)",
                    seg[i], self.n_labels
                ),
            });
        }
        Ok(())
    }

    /// Finish the file and atomically move it to the target path (replacing any existing file).
    /// An empty dataset is an error (and writes nothing).
    pub fn finish(mut self) -> Result<WriteSummary, DataError> {
        if self.failed {
            return Err(DataError::invalid_write(
                &self.path,
                "the writer failed earlier; nothing was written",
            ));
        }
        if self.n_rows == 0 {
            return Err(DataError::Empty {
                file: self.path.clone(),
            });
        }
        self.time.finish(&self.path)?;
        let file = match self.sink.take() {
            Some(Sink::Parquet(p)) => p.finish()?,
            Some(Sink::Csv(c)) => c.finish()?,
            None => return Err(DataError::invalid_write(&self.path, "the writer is closed")),
        };
        let temp = self
            .temp
            .take()
            .ok_or_else(|| DataError::invalid_write(&self.path, "the writer is closed"))?;
        temp.commit(file)?;
        let n_bytes = std::fs::metadata(&self.path)
            .map_err(|e| DataError::io(&self.path, "reading the size of the written file", e))?
            .len();
        Ok(WriteSummary {
            path: self.path.clone(),
            format: self.format,
            n_rows: self.n_rows,
            n_bytes,
        })
    }
}

/// The float columns of row `i` of `batch`, in `ColumnSet::float_columns` order.
fn fill_row(row: &mut Vec<f64>, batch: &SampleBatch, i: usize, temperature: bool) {
    row.clear();
    if let Some(s) = batch.samples.get(i) {
        row.push(s.t_s);
        row.extend(s.dtheta_rad.iter());
        row.extend(s.dv_mps.iter());
        if temperature {
            row.extend(s.temp_degc);
        }
    }
    if let Some(r) = batch.reference.as_ref().and_then(|r| r.get(i)) {
        row.extend(r.to_array());
    }
}
