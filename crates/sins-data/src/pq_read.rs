//! Streaming Parquet reader (the `parquet` crate's footer, page and column readers): metadata
//! and schema are validated on open; row groups are read, decoded, validated and turned into
//! [`SampleBatch`]es by one background thread, one batch ahead of the consumer, strictly in file
//! order.

use std::fs::File;
use std::path::Path;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::thread::JoinHandle;

use parquet::basic::{ConvertedType, LogicalType, Repetition, Type as PhysicalType};
use parquet::data_type::{ByteArrayType, DoubleType};
use parquet::file::metadata::ParquetMetaDataReader;
use parquet::schema::types::Type;

use crate::error::DataError;
use crate::layout::resolve_layout;
use crate::meta::DatasetMeta;
use crate::pq_batch::{DecodedColumns, ReadPlan, build_batch};
use crate::pq_column::{Column, Labels};
use crate::pq_dict::SegmentIndices;
use crate::pq_pages::{RowGroupBytes, pq_err};
use crate::schema::MAX_BATCH_ROWS;
use crate::schema::{DatasetFormat, DatasetInfo, SEGMENT_COLUMN, SampleBatch};
use crate::validate::{TimeCheck, check_meta, column_limits};

type BatchResult = Result<SampleBatch, DataError>;

/// An open Parquet dataset.
pub(crate) struct ParquetSource {
    plan: Arc<ReadPlan>,
    started: bool,
    rx: Option<Receiver<BatchResult>>,
    recycle_tx: Option<Sender<SampleBatch>>,
    handle: Option<JoinHandle<()>>,
    done: bool,
}

/// Open and validate a Parquet dataset.
pub(crate) fn open_parquet(
    path: &Path,
    f: File,
) -> Result<(DatasetInfo, ParquetSource), DataError> {
    let file_len = f
        .metadata()
        .map_err(|e| DataError::io(path, "reading the file size", e))?
        .len();
    let metadata = ParquetMetaDataReader::new()
        .parse_and_finish(&f)
        .map_err(|e| pq_err(path, "reading the footer", e))?;
    let fm = metadata.file_metadata();
    let kv: Vec<(&str, &str)> = fm
        .key_value_metadata()
        .into_iter()
        .flatten()
        .map(|kv| (kv.key.as_str(), kv.value.as_deref().unwrap_or("")))
        .collect();
    let meta = DatasetMeta::from_key_values(path, kv)?;
    check_meta(path, &meta)?;
    let schema = fm.schema_descr();
    let fields = schema.root_schema().get_fields();
    let names: Vec<String> = fields.iter().map(|t| t.name().to_string()).collect();
    let layout = resolve_layout(path, &names)?;
    let columns = layout.columns;
    let float_names = columns.float_columns();
    // The leaf column of root field `pos`, once its type is known to be flat.
    let leaf_of =
        |pos: usize| (0..schema.num_columns()).find(|&i| schema.get_column_root_idx(i) == pos);
    let mut float_leaves = Vec::with_capacity(float_names.len());
    for (name, &pos) in float_names.iter().zip(&layout.float_pos) {
        let t = &fields[pos];
        let leaf =
            leaf_of(pos).filter(|_| is_flat(t) && t.get_physical_type() == PhysicalType::DOUBLE);
        float_leaves
            .push(leaf.ok_or_else(|| wrong_type(path, name, "Float64 (Parquet DOUBLE)", t))?);
    }
    let segment_leaf = match layout.segment_pos {
        Some(pos) => {
            let t = &fields[pos];
            let leaf = leaf_of(pos).filter(|_| is_flat(t) && is_string(t));
            Some(leaf.ok_or_else(|| wrong_type(path, SEGMENT_COLUMN, "String", t))?)
        }
        None => None,
    };
    let corrupt = |why: String| DataError::corrupt(path, why);
    let n_rows = u64::try_from(fm.num_rows())
        .map_err(|_| corrupt(format!("the footer says {} rows", fm.num_rows())))?;
    let mut rg_rows = Vec::with_capacity(metadata.num_row_groups());
    let mut rg_total = 0u64;
    for (i, rg) in metadata.row_groups().iter().enumerate() {
        let rows = usize::try_from(rg.num_rows()).map_err(|_| {
            corrupt(format!(
                "row group {i} says it holds {} rows",
                rg.num_rows()
            ))
        })?;
        rg_total = rg_total.saturating_add(rows as u64);
        rg_rows.push(rows);
    }
    if rg_total != n_rows {
        return Err(corrupt(format!(
            "footer says {n_rows} rows but the row groups hold {rg_total}"
        )));
    }
    if n_rows == 0 {
        return Err(DataError::Empty {
            file: path.to_path_buf(),
        });
    }
    let mut needed: Vec<(&str, usize)> = float_names
        .iter()
        .copied()
        .zip(float_leaves.iter().copied())
        .collect();
    needed.extend(segment_leaf.map(|leaf| (SEGMENT_COLUMN, leaf)));
    for (i, rg) in metadata.row_groups().iter().enumerate() {
        // The reader holds a row group's chunks in memory: they cannot add up to more than the
        // file unless the footer is wrong.
        let mut rg_bytes = 0u64;
        for &(name, leaf) in &needed {
            let c = rg
                .columns()
                .get(leaf)
                .ok_or_else(|| corrupt(format!("row group {i} lacks column '{name}'")))?;
            let start = c.dictionary_page_offset().unwrap_or(c.data_page_offset());
            let len = c.compressed_size();
            let end = u64::try_from(start)
                .ok()
                .zip(u64::try_from(len).ok())
                .and_then(|(s, l)| s.checked_add(l));
            if end.is_none_or(|end| end > file_len) {
                return Err(corrupt(format!(
                    "row group {i}, column '{name}': its {len} bytes from offset {start} lie \
                     outside the file ({file_len} bytes)"
                )));
            }
            rg_bytes = rg_bytes.saturating_add(len.unsigned_abs());
        }
        if rg_bytes > file_len {
            return Err(corrupt(format!(
                "row group {i}: its column chunks add up to {rg_bytes} bytes, more than the \
                 file ({file_len} bytes)"
            )));
        }
    }
    let mut plan = ReadPlan {
        path: path.to_path_buf(),
        file: Arc::new(f),
        metadata,
        columns,
        limits: column_limits(&float_names, meta.sample_rate_hz),
        float_names,
        float_leaves,
        segment_leaf,
        segment_direct: Vec::new(),
        rg_rows,
        lookup: Default::default(),
        rate_hz: meta.sample_rate_hz,
    };
    let mut labels = Labels::default();
    if let Some(leaf) = segment_leaf {
        let mut first_row = 0u64;
        let mut direct = Vec::with_capacity(plan.rg_rows.len());
        for (rg, &rows) in plan.rg_rows.iter().enumerate() {
            direct.push(labels.collect(&plan, rg, leaf, first_row)?);
            first_row += rows as u64;
        }
        plan.segment_direct = direct;
    }
    plan.lookup = labels.lookup;
    let info = DatasetInfo {
        path: path.to_path_buf(),
        format: DatasetFormat::Parquet,
        meta,
        columns,
        has_temperature: columns.temperature,
        n_rows,
        segment_labels: labels.list,
        ignored_columns: layout.ignored,
    };
    let source = ParquetSource {
        plan: Arc::new(plan),
        started: false,
        rx: None,
        recycle_tx: None,
        handle: None,
        done: false,
    };
    Ok((info, source))
}

/// A primitive column, not repeated (nullable or not).
fn is_flat(t: &Type) -> bool {
    let info = t.get_basic_info();
    t.is_primitive() && !(info.has_repetition() && info.repetition() == Repetition::REPEATED)
}

/// A BYTE_ARRAY column annotated as UTF-8 text.
fn is_string(t: &Type) -> bool {
    let info = t.get_basic_info();
    t.get_physical_type() == PhysicalType::BYTE_ARRAY
        && (matches!(info.logical_type_ref(), Some(LogicalType::String))
            || info.converted_type() == ConvertedType::UTF8)
}

/// The type of a column, in the words polars and arrow use, with the Parquet physical type.
fn describe(t: &Type) -> String {
    let info = t.get_basic_info();
    if !t.is_primitive() {
        return "a nested column (group)".to_string();
    }
    if info.has_repetition() && info.repetition() == Repetition::REPEATED {
        return "a repeated (list) column".to_string();
    }
    let physical = t.get_physical_type();
    let name = match (physical, info.logical_type_ref()) {
        (_, Some(LogicalType::Integer(int))) => {
            format!(
                "{}Int{}",
                if int.is_signed { "" } else { "U" },
                int.bit_width
            )
        }
        (PhysicalType::BYTE_ARRAY, _) if is_string(t) => "String".to_string(),
        (PhysicalType::BOOLEAN, _) => "Boolean".to_string(),
        (PhysicalType::INT32, _) => "Int32".to_string(),
        (PhysicalType::INT64, _) => "Int64".to_string(),
        (PhysicalType::INT96, _) => "Int96".to_string(),
        (PhysicalType::FLOAT, _) => "Float32".to_string(),
        (PhysicalType::DOUBLE, _) => "Float64".to_string(),
        (PhysicalType::BYTE_ARRAY, _) => "Binary".to_string(),
        (PhysicalType::FIXED_LEN_BYTE_ARRAY, _) => "FixedSizeBinary".to_string(),
    };
    format!("{name} (Parquet {physical})")
}

fn wrong_type(path: &Path, column: &str, expected: &'static str, found: &Type) -> DataError {
    DataError::WrongColumnType {
        file: path.to_path_buf(),
        column: column.to_string(),
        expected,
        found: describe(found),
    }
}

impl ParquetSource {
    /// The next batch in file order, `None` after the last one (and after an error).
    pub fn next_batch(&mut self) -> Result<Option<SampleBatch>, DataError> {
        if self.done {
            return Ok(None);
        }
        if !self.started {
            self.started = true;
            let (tx, rx) = sync_channel::<BatchResult>(1);
            let (recycle_tx, recycle_rx) = channel::<SampleBatch>();
            let plan = Arc::clone(&self.plan);
            let handle = std::thread::Builder::new()
                .name("sins-data-parquet-reader".into())
                .spawn(move || {
                    if let Err(e) = decode(&plan, &tx, &recycle_rx) {
                        let _ = tx.send(Err(e));
                    }
                })
                .map_err(|e| DataError::io(&self.plan.path, "starting the reader thread", e))?;
            self.rx = Some(rx);
            self.recycle_tx = Some(recycle_tx);
            self.handle = Some(handle);
        }
        let received = self.rx.as_ref().map(|rx| rx.recv());
        match received {
            Some(Ok(Ok(batch))) => Ok(Some(batch)),
            Some(Ok(Err(e))) => {
                self.done = true;
                Err(e)
            }
            // Channel closed: the decoder finished, or died (a bug, reported as such).
            _ => {
                self.done = true;
                match self.handle.take().map(JoinHandle::join) {
                    Some(Err(_)) => Err(DataError::corrupt(
                        &self.plan.path,
                        "internal error: the Parquet decoder thread panicked",
                    )),
                    _ => Ok(None),
                }
            }
        }
    }

    /// Hand a consumed batch's buffers back to the decoder for reuse.
    pub fn recycle(&mut self, batch: SampleBatch) {
        if let Some(tx) = &self.recycle_tx {
            let _ = tx.send(batch);
        }
    }
}

impl Drop for ParquetSource {
    fn drop(&mut self) {
        self.rx = None; // unblocks the decoder's send, so it exits
        self.recycle_tx = None;
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

/// Decode every row group in file order, sending one batch per [`MAX_BATCH_ROWS`] rows at most;
/// stops early (with `Ok`) when the consumer has gone.
fn decode(
    plan: &ReadPlan,
    tx: &SyncSender<BatchResult>,
    recycled: &Receiver<SampleBatch>,
) -> Result<(), DataError> {
    let path = plan.path.as_path();
    let mut time = TimeCheck::new(plan.rate_hz);
    let mut cols = DecodedColumns {
        first_row: 0,
        n_rows: 0,
        floats: vec![Vec::new(); plan.float_names.len()],
        segment: plan.segment_leaf.map(|_| Vec::new()),
    };
    let (mut strings, mut spare) = (Vec::new(), Vec::new());
    let mut leaves: Vec<(usize, &str)> = plan
        .float_leaves
        .iter()
        .copied()
        .zip(plan.float_names.iter().copied())
        .collect();
    leaves.extend(plan.segment_leaf.map(|leaf| (leaf, SEGMENT_COLUMN)));
    let mut buffer = RowGroupBytes::default();
    let mut first_row = 0u64;
    for (rg, &rows) in plan.rg_rows.iter().enumerate() {
        let mut sources: Vec<_> = buffer
            .load(plan, rg, &leaves)?
            .into_iter()
            .map(Some)
            .collect();
        let (float_sources, segment_source) = sources.split_at_mut(plan.float_names.len());
        // Readers open when first read and close as soon as their column is done, so that one
        // decompressed page at a time is alive: the allocator then reuses its memory instead
        // of handing it back to the system and faulting it in again for the next.
        let mut floats: Vec<Option<Column<DoubleType>>> =
            plan.float_names.iter().map(|_| None).collect();
        let mut segment: Option<Segment> = None;
        let mut done = 0;
        loop {
            let n = (rows - done).min(MAX_BATCH_ROWS);
            let last = done + n == rows;
            let columns = floats.iter_mut().zip(float_sources.iter_mut());
            let names = plan.float_names.iter().zip(&plan.float_leaves);
            for (((slot, source), (&name, &leaf)), out) in columns.zip(names).zip(&mut cols.floats)
            {
                let col = match slot {
                    Some(col) => col,
                    None => {
                        let source = source.take().ok_or_else(|| missing(path))?;
                        slot.insert(Column::open(plan, (rg, leaf, name), first_row, source)?)
                    }
                };
                col.read(path, n, out)?;
                if last {
                    col.finish(path, &mut spare)?;
                    *slot = None;
                }
            }
            if let (Some(leaf), Some(out)) = (plan.segment_leaf, cols.segment.as_mut()) {
                let col = match &mut segment {
                    Some(col) => col,
                    None => {
                        let source = segment_source.first_mut().and_then(Option::take);
                        let source = source.ok_or_else(|| missing(path))?;
                        segment.insert(if plan.segment_direct.get(rg) == Some(&true) {
                            Segment::Direct(SegmentIndices::open(
                                plan, rg, leaf, first_row, source,
                            )?)
                        } else {
                            let id = (rg, leaf, SEGMENT_COLUMN);
                            Segment::Values(Column::open(plan, id, first_row, source)?)
                        })
                    }
                };
                match col {
                    Segment::Direct(c) => c.read(path, n, &plan.lookup, out)?,
                    Segment::Values(c) => {
                        c.read_segment(path, n, &plan.lookup, &mut strings, out)?
                    }
                }
                if last {
                    match col {
                        Segment::Direct(c) => c.finish(path, &plan.lookup)?,
                        Segment::Values(c) => c.finish(path, &mut strings)?,
                    }
                    segment = None;
                }
            }
            if n > 0 {
                cols.first_row = first_row + done as u64;
                cols.n_rows = n;
                let batch = build_batch(plan, &cols, &mut time, recycled.try_recv().ok())?;
                if tx.send(Ok(batch)).is_err() {
                    return Ok(());
                }
            }
            done += n;
            if last {
                break;
            }
        }
        // Nothing may refer to the row group's bytes any more, so the next one reuses them.
        strings.clear();
        first_row += rows as u64;
    }
    time.finish(path)
}

/// How a row group's `segment` chunk is read.
// One per row group: the variant size difference costs nothing.
#[allow(clippy::large_enum_variant)]
enum Segment {
    /// Label indices straight from dictionary-encoded pages.
    Direct(SegmentIndices),
    /// Strings from the column reader, looked up.
    Values(Column<ByteArrayType>),
}

fn missing(path: &Path) -> DataError {
    DataError::corrupt(path, "internal: a column chunk was not read")
}
