//! Streaming Parquet writer: rows are buffered column-wise up to one row group, then encoded,
//! compressed and written by a background thread (one row group in flight), so memory stays
//! bounded by a few row groups and the caller keeps producing data meanwhile.

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;

use polars::prelude::{PlSmallStr, PolarsError};
use polars_arrow::array::{Array, DictionaryArray, PrimitiveArray, Utf8ViewArray};
use polars_arrow::datatypes::{ArrowDataType, ArrowSchema, Field, IntegerType};
use polars_parquet::write::{
    CompressionOptions, Compressor, DynIter, DynStreamingIterator, Encoding,
    FallibleStreamingIterator, FileWriter, KeyValue, ParquetType, StatisticsOptions, Version,
    WriteOptions, ZstdLevel, array_to_columns, to_parquet_schema,
};

use crate::early_sync::EarlySync;
use crate::error::DataError;
use crate::schema::{ColumnSet, ReferenceRow, SEGMENT_COLUMN};
use sins_imu::ImuSample;

/// Page compression of Parquet datasets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    /// No compression (fastest to write and read, largest file).
    Uncompressed,
    /// Snappy.
    Snappy,
    /// LZ4 (raw block format).
    Lz4,
    /// Zstandard at the given level (1 = fastest).
    Zstd(i32),
}

/// Tunables of the Parquet writer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParquetWriteOptions {
    /// Page compression.
    pub compression: Compression,
    /// Rows per row group (also the reader's batch size); clamped to at least 1.
    pub row_group_rows: usize,
}

/// Default compression of dataset files (chosen by measurement, see the crate docs).
pub const DEFAULT_COMPRESSION: Compression = Compression::Lz4;
/// Default rows per row group: 2^16 rows (5.2 MB of Float64 for the 10 IMU columns). Throughput
/// is flat from 2^15 to 2^18 rows; memory grows with the size.
pub const DEFAULT_ROW_GROUP_ROWS: usize = 1 << 16;

impl Default for ParquetWriteOptions {
    fn default() -> Self {
        Self {
            compression: DEFAULT_COMPRESSION,
            row_group_rows: DEFAULT_ROW_GROUP_ROWS,
        }
    }
}

/// One row group's worth of columns, handed to the background thread.
struct RowGroupData {
    floats: Vec<Vec<f64>>,
    segment: Option<Vec<u16>>,
}

/// Column-wise row-group buffer plus the background encoder.
pub(crate) struct ParquetSink {
    file: PathBuf,
    row_group_rows: usize,
    n_float: usize,
    has_segment: bool,
    floats: Vec<Vec<f64>>,
    segment: Vec<u16>,
    tx: Option<SyncSender<RowGroupData>>,
    handle: Option<JoinHandle<Result<File, DataError>>>,
    aborted: Arc<AtomicBool>,
}

impl ParquetSink {
    /// Start writing to `out` (the temporary file). `file` is the user's path (for errors).
    pub fn start(
        file: &Path,
        out: File,
        columns: ColumnSet,
        labels: &[String],
        kv: Vec<(String, String)>,
        opts: ParquetWriteOptions,
    ) -> Result<Self, DataError> {
        let names = columns.float_columns();
        let mut fields: Vec<Field> = names
            .iter()
            .map(|n| Field::new(PlSmallStr::from_str(n), ArrowDataType::Float64, false))
            .collect();
        if columns.segment {
            let dtype = ArrowDataType::Dictionary(
                IntegerType::UInt16,
                Box::new(ArrowDataType::Utf8View),
                false,
            );
            fields.push(Field::new(
                PlSmallStr::from_static(SEGMENT_COLUMN),
                dtype,
                false,
            ));
        }
        let schema: ArrowSchema = fields.into_iter().map(|f| (f.name.clone(), f)).collect();
        // Only null counts: min/max statistics cost ~10 % of the encoder's time and nothing
        // here reads them.
        let statistics = StatisticsOptions {
            min_value: false,
            max_value: false,
            distinct_count: false,
            null_count: true,
            binary_statistics_truncate_length: None,
        };
        let options = WriteOptions {
            statistics,
            version: Version::V1,
            compression: compression_options(file, opts.compression)?,
            data_page_size: None,
        };
        let parquet_types = to_parquet_schema(&schema)
            .map_err(|e| DataError::invalid_write(file, e.to_string()))?
            .fields()
            .to_vec();
        let early_sync = EarlySync::start(&out);
        // A small buffer: pages (~1 MB) bypass it and go straight to the file (one copy less);
        // it only batches the small page headers.
        let writer = FileWriter::try_new(BufWriter::with_capacity(1 << 16, out), schema, options)
            .map_err(|e| DataError::invalid_write(file, e.to_string()))?;
        let labels_array: Box<dyn Array> = Box::new(Utf8ViewArray::from_slice_values(labels));
        let kv: Vec<KeyValue> = kv
            .into_iter()
            .map(|(key, value)| KeyValue {
                key,
                value: Some(value),
            })
            .collect();
        let (tx, rx) = sync_channel::<RowGroupData>(1);
        let aborted = Arc::new(AtomicBool::new(false));
        let job = EncoderJob {
            aborted: Arc::clone(&aborted),
            file: file.to_path_buf(),
            writer,
            parquet_types,
            options,
            labels_array,
            kv,
            early_sync,
        };
        let handle = std::thread::Builder::new()
            .name("sins-data-parquet-writer".into())
            .spawn(move || job.run(rx))
            .map_err(|e| DataError::io(file, "starting the writer thread", e))?;
        let row_group_rows = opts.row_group_rows.max(1);
        let n_float = names.len();
        Ok(Self {
            file: file.to_path_buf(),
            row_group_rows,
            n_float,
            has_segment: columns.segment,
            floats: new_buffers(n_float, row_group_rows),
            segment: Vec::new(),
            tx: Some(tx),
            handle: Some(handle),
            aborted,
        })
    }

    /// Append validated rows (the optional slices are present exactly when the column set has
    /// them), column by column; flushes each row group as it fills up.
    pub fn push_rows(
        &mut self,
        samples: &[ImuSample],
        temperature: bool,
        reference: Option<&[ReferenceRow]>,
        segment: Option<&[u16]>,
    ) -> Result<(), DataError> {
        let mut start = 0;
        while start < samples.len() {
            let room = self
                .row_group_rows
                .saturating_sub(self.floats[0].len())
                .max(1);
            let end = (start + room).min(samples.len());
            let s = &samples[start..end];
            let f = &mut self.floats;
            f[0].extend(s.iter().map(|x| x.t_s));
            for a in 0..3 {
                f[1 + a].extend(s.iter().map(|x| x.dtheta_rad[a]));
                f[4 + a].extend(s.iter().map(|x| x.dv_mps[a]));
            }
            let mut k = 7;
            if temperature {
                for a in 0..3 {
                    f[7 + a].extend(s.iter().map(|x| x.temp_degc[a]));
                }
                k = 10;
            }
            if let Some(r) = reference.and_then(|r| r.get(start..end)) {
                f[k].extend(r.iter().map(|x| x.lat_rad));
                f[k + 1].extend(r.iter().map(|x| x.lon_rad));
                f[k + 2].extend(r.iter().map(|x| x.height_m));
                f[k + 3].extend(r.iter().map(|x| x.vel_n_mps));
                f[k + 4].extend(r.iter().map(|x| x.vel_e_mps));
                f[k + 5].extend(r.iter().map(|x| x.vel_d_mps));
                f[k + 6].extend(r.iter().map(|x| x.pitch_rad));
                f[k + 7].extend(r.iter().map(|x| x.roll_rad));
                f[k + 8].extend(r.iter().map(|x| x.yaw_rad));
            }
            if let Some(seg) = segment.and_then(|g| g.get(start..end)) {
                self.segment.extend_from_slice(seg);
            }
            if self.floats[0].len() >= self.row_group_rows {
                self.flush()?;
            }
            start = end;
        }
        Ok(())
    }

    fn flush(&mut self) -> Result<(), DataError> {
        if self.floats[0].is_empty() {
            return Ok(());
        }
        let floats = std::mem::replace(
            &mut self.floats,
            new_buffers(self.n_float, self.row_group_rows),
        );
        let segment = self.has_segment.then(|| std::mem::take(&mut self.segment));
        let sent = match &self.tx {
            Some(tx) => tx.send(RowGroupData { floats, segment }).is_ok(),
            None => false,
        };
        if sent {
            Ok(())
        } else {
            // The encoder stopped: report its error.
            self.tx = None;
            match self.join() {
                Err(e) => Err(e),
                Ok(_) => Err(DataError::invalid_write(
                    &self.file,
                    "the Parquet writer thread stopped early",
                )),
            }
        }
    }

    fn join(&mut self) -> Result<File, DataError> {
        match self.handle.take() {
            Some(h) => h.join().unwrap_or_else(|_| {
                Err(DataError::invalid_write(
                    &self.file,
                    "the Parquet writer thread panicked",
                ))
            }),
            None => Err(DataError::invalid_write(
                &self.file,
                "the Parquet writer already failed",
            )),
        }
    }

    /// Write the last row group and the footer; returns the (unsynced) temporary file.
    pub fn finish(mut self) -> Result<File, DataError> {
        self.flush()?;
        self.tx = None;
        self.join()
    }
}

impl Drop for ParquetSink {
    /// Dropped without `finish`: stop the encoder without writing a footer.
    fn drop(&mut self) {
        if self.tx.is_some() {
            self.aborted.store(true, Ordering::SeqCst);
            self.tx = None;
        }
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

fn new_buffers(n: usize, cap: usize) -> Vec<Vec<f64>> {
    (0..n).map(|_| Vec::with_capacity(cap)).collect()
}

fn compression_options(file: &Path, c: Compression) -> Result<CompressionOptions, DataError> {
    Ok(match c {
        Compression::Uncompressed => CompressionOptions::Uncompressed,
        Compression::Snappy => CompressionOptions::Snappy,
        Compression::Lz4 => CompressionOptions::Lz4Raw,
        Compression::Zstd(level) => CompressionOptions::Zstd(Some(
            ZstdLevel::try_new(level)
                .map_err(|e| DataError::invalid_write(file, format!("zstd level: {e}")))?,
        )),
    })
}

/// State owned by the background encoder thread.
struct EncoderJob {
    aborted: Arc<AtomicBool>,
    file: PathBuf,
    writer: FileWriter<BufWriter<File>>,
    parquet_types: Vec<ParquetType>,
    options: WriteOptions,
    labels_array: Box<dyn Array>,
    kv: Vec<KeyValue>,
    early_sync: Option<EarlySync>,
}

impl EncoderJob {
    fn run(mut self, rx: Receiver<RowGroupData>) -> Result<File, DataError> {
        for rg in rx {
            if self.aborted.load(Ordering::SeqCst) {
                break;
            }
            let raw_bytes = rg.floats.iter().map(|c| c.len() as u64 * 8).sum();
            self.write_row_group(rg)?;
            if let Some(s) = self.early_sync.as_mut() {
                s.wrote(raw_bytes);
            }
        }
        if self.aborted.load(Ordering::SeqCst) {
            return Err(DataError::invalid_write(&self.file, "write aborted"));
        }
        let kv = std::mem::take(&mut self.kv);
        self.writer
            .end(Some(kv))
            .map_err(|e| self.polars_err("writing the Parquet footer", e))?;
        let file = self.file.clone();
        if let Some(s) = self.early_sync.take() {
            s.finish()
                .map_err(|e| DataError::io(&file, "syncing the Parquet file", e))?;
        }
        self.writer
            .into_inner()
            .into_inner()
            .map_err(|e| DataError::io(&file, "flushing the Parquet file", e.into_error()))
    }

    fn polars_err(&self, what: &str, e: PolarsError) -> DataError {
        match e {
            PolarsError::IO { error, .. } => {
                let io = std::io::Error::new(error.kind(), error.to_string());
                DataError::io(&self.file, "writing the Parquet file", io)
            }
            other => DataError::invalid_write(&self.file, format!("{what}: {other}")),
        }
    }

    fn write_row_group(&mut self, rg: RowGroupData) -> Result<(), DataError> {
        let n_rows = rg.floats.first().map_or(0, Vec::len);
        let mut arrays: Vec<(Box<dyn Array>, Encoding)> = rg
            .floats
            .into_iter()
            .map(|v| {
                let a: Box<dyn Array> = Box::new(PrimitiveArray::<f64>::from_vec(v));
                (a, Encoding::Plain)
            })
            .collect();
        if let Some(keys) = rg.segment {
            let dtype = ArrowDataType::Dictionary(
                IntegerType::UInt16,
                Box::new(ArrowDataType::Utf8View),
                false,
            );
            let dict = DictionaryArray::<u16>::try_new(
                dtype,
                PrimitiveArray::<u16>::from_vec(keys),
                self.labels_array.clone(),
            )
            .map_err(|e| self.polars_err("building the segment column", e))?;
            arrays.push((Box::new(dict), Encoding::RleDictionary));
        }
        let mut columns = Vec::with_capacity(arrays.len());
        for ((array, encoding), ptype) in arrays.into_iter().zip(&self.parquet_types) {
            let encoded = array_to_columns(array, ptype.clone(), self.options, &[encoding])
                .map_err(|e| self.polars_err("encoding a column", e))?;
            for pages in encoded {
                let pages = pages.map(|p| p.map_err(|e| e.into()));
                let compressed = Compressor::new(pages, self.options.compression, vec![])
                    .map_err(PolarsError::from);
                columns.push(Ok(DynStreamingIterator::new(compressed)));
            }
        }
        self.writer
            .write(n_rows as u64, DynIter::new(columns.into_iter()))
            .map_err(|e| self.polars_err("writing a row group", e))
    }
}
