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

use parquet::basic::{
    Compression as Codec, Encoding, LogicalType, Repetition, Type as PhysicalType, ZstdLevel,
};
use parquet::data_type::DoubleType;
use parquet::errors::ParquetError;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::{EnabledStatistics, WriterProperties, WriterVersion};
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::{ColumnDescPtr, Type};

use crate::early_sync::EarlySync;
use crate::error::DataError;
use crate::pq_segment::segment_chunk;
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
        let invalid = |e: ParquetError| DataError::invalid_write(file, e.to_string());
        let schema = Arc::new(schema(&names, columns.segment).map_err(invalid)?);
        let kv = kv
            .into_iter()
            .map(|(key, value)| KeyValue::new(key, value))
            .collect();
        // Plain-encoded floats in one page per column chunk at the default row-group size (no
        // row-count limit on pages), no statistics, hence no page index either: nothing here
        // reads them and min/max cost encoder time.
        let props = WriterProperties::builder()
            .set_writer_version(WriterVersion::PARQUET_1_0)
            .set_compression(codec(file, opts.compression)?)
            .set_dictionary_enabled(false)
            .set_encoding(Encoding::PLAIN)
            .set_statistics_enabled(EnabledStatistics::None)
            .set_offset_index_disabled(true)
            .set_data_page_row_count_limit(usize::MAX)
            .set_key_value_metadata(Some(kv))
            .build();
        let early_sync = EarlySync::start(&out);
        // A small buffer: pages (~0.5 MB) bypass it and go straight to the file (one copy
        // less); it only batches the small page headers.
        let writer = SerializedFileWriter::new(
            BufWriter::with_capacity(1 << 16, out),
            schema,
            Arc::new(props),
        )
        .map_err(invalid)?;
        let segment_descr = columns
            .segment
            .then(|| writer.schema_descr().column(names.len()));
        let (tx, rx) = sync_channel::<RowGroupData>(1);
        let aborted = Arc::new(AtomicBool::new(false));
        let job = EncoderJob {
            aborted: Arc::clone(&aborted),
            file: file.to_path_buf(),
            writer,
            segment_descr,
            labels: labels.to_vec(),
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

fn codec(file: &Path, c: Compression) -> Result<Codec, DataError> {
    Ok(match c {
        Compression::Uncompressed => Codec::UNCOMPRESSED,
        Compression::Snappy => Codec::SNAPPY,
        Compression::Lz4 => Codec::LZ4_RAW,
        Compression::Zstd(level) => Codec::ZSTD(
            ZstdLevel::try_new(level)
                .map_err(|e| DataError::invalid_write(file, format!("zstd level: {e}")))?,
        ),
    })
}

/// The file schema: the Float64 columns `names`, then `segment` (UTF-8 strings), all required.
fn schema(names: &[&str], segment: bool) -> parquet::errors::Result<Type> {
    let mut fields = Vec::with_capacity(names.len() + 1);
    for name in names {
        let t = Type::primitive_type_builder(name, PhysicalType::DOUBLE)
            .with_repetition(Repetition::REQUIRED)
            .build()?;
        fields.push(Arc::new(t));
    }
    if segment {
        let t = Type::primitive_type_builder(SEGMENT_COLUMN, PhysicalType::BYTE_ARRAY)
            .with_repetition(Repetition::REQUIRED)
            .with_logical_type(Some(LogicalType::String))
            .build()?;
        fields.push(Arc::new(t));
    }
    Type::group_type_builder("sinsbench")
        .with_fields(fields)
        .build()
}

/// State owned by the background encoder thread.
struct EncoderJob {
    aborted: Arc<AtomicBool>,
    file: PathBuf,
    writer: SerializedFileWriter<BufWriter<File>>,
    segment_descr: Option<ColumnDescPtr>,
    labels: Vec<String>,
    early_sync: Option<EarlySync>,
}

impl EncoderJob {
    fn run(mut self, rx: Receiver<RowGroupData>) -> Result<File, DataError> {
        for rg in rx {
            if self.aborted.load(Ordering::SeqCst) {
                break;
            }
            let raw_bytes = rg.floats.iter().map(|c| c.len() as u64 * 8).sum();
            self.write_row_group(&rg)
                .map_err(|e| self.pq_err("writing a row group", e))?;
            if let Some(s) = self.early_sync.as_mut() {
                s.wrote(raw_bytes);
            }
        }
        if self.aborted.load(Ordering::SeqCst) {
            return Err(DataError::invalid_write(&self.file, "write aborted"));
        }
        let file = self.file.clone();
        let buffered = self
            .writer
            .into_inner()
            .map_err(|e| pq_write_err(&file, "writing the Parquet footer", e))?;
        let out = buffered
            .into_inner()
            .map_err(|e| DataError::io(&file, "flushing the Parquet file", e.into_error()))?;
        if let Some(s) = self.early_sync.take() {
            s.finish()
                .map_err(|e| DataError::io(&file, "syncing the Parquet file", e))?;
        }
        Ok(out)
    }

    fn pq_err(&self, what: &str, e: ParquetError) -> DataError {
        pq_write_err(&self.file, what, e)
    }

    fn write_row_group(&mut self, rg: &RowGroupData) -> parquet::errors::Result<()> {
        let mut group = self.writer.next_row_group()?;
        for values in &rg.floats {
            let mut column = group
                .next_column()?
                .ok_or_else(|| ParquetError::General("more columns than the schema".into()))?;
            column
                .typed::<DoubleType>()
                .write_batch(values, None, None)?;
            column.close()?;
        }
        if let (Some(keys), Some(descr)) = (&rg.segment, &self.segment_descr) {
            let (bytes, close) = segment_chunk(descr.clone(), &self.labels, keys)?;
            group.append_column(&bytes, close)?;
        }
        group.close()?;
        Ok(())
    }
}

/// A [`ParquetError`] while writing: an I/O error stays one, anything else is reported with
/// `what` was being written.
fn pq_write_err(file: &Path, what: &str, e: ParquetError) -> DataError {
    if let ParquetError::External(inner) = &e
        && let Some(io) = inner.downcast_ref::<std::io::Error>()
    {
        let source = std::io::Error::new(io.kind(), io.to_string());
        return DataError::io(file, "writing the Parquet file", source);
    }
    DataError::invalid_write(file, format!("{what}: {e}"))
}
