//! Streaming CSV reader. The metadata comment lines and the header are read line by line; the
//! data rows are parsed by the `csv` crate (RFC 4180 quoting, CRLF). Opening makes one
//! validating pass over the whole file (row count, segment labels, every value and time step
//! checked, with exact line numbers); batches are then parsed in a second pass.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufRead, BufReader, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use sins_imu::ImuSample;
use sins_nav::Vec3;

use crate::error::{DataError, RowRef};
use crate::layout::{Layout, resolve_layout};
use crate::meta::{DatasetMeta, KEY_PREFIX};
use crate::pq_batch::reuse;
use crate::schema::MAX_BATCH_ROWS;
use crate::schema::{DatasetFormat, DatasetInfo, MAX_SEGMENT_LABELS, ReferenceRow, SampleBatch};
use crate::validate::{ColumnLimit, TimeCheck, check_meta, column_limits, implausible, non_finite};

/// Line source with 1-based line numbers and UTF-8 checking.
struct Lines {
    path: PathBuf,
    reader: BufReader<File>,
    buf: String,
    line_no: u64,
}

impl Lines {
    fn new(path: &Path, f: File) -> Self {
        Self {
            path: path.to_path_buf(),
            reader: BufReader::with_capacity(1 << 20, f),
            buf: String::new(),
            line_no: 0,
        }
    }

    /// Next line (1-based number, text without its terminator); `None` at end of file.
    fn next_line(&mut self) -> Result<Option<(u64, &str)>, DataError> {
        self.buf.clear();
        self.line_no += 1;
        match self.reader.read_line(&mut self.buf) {
            Ok(0) => Ok(None),
            Ok(_) => Ok(Some((
                self.line_no,
                self.buf.trim_end_matches(['\n', '\r']),
            ))),
            Err(e) if e.kind() == std::io::ErrorKind::InvalidData => Err(DataError::MalformedCsv {
                file: self.path.clone(),
                line: self.line_no,
                reason: "not valid UTF-8 text".to_string(),
            }),
            Err(e) => Err(DataError::io(&self.path, "reading CSV", e)),
        }
    }
}

/// The data rows after the header, through the `csv` crate: 1-based line numbers in the file.
struct Body {
    path: PathBuf,
    csv: csv::Reader<BufReader<File>>,
    /// Lines before the first data line (comments and header).
    line_offset: u64,
}

impl Body {
    fn new(path: &Path, lines: Lines) -> Self {
        Self {
            path: path.to_path_buf(),
            line_offset: lines.line_no,
            csv: csv::ReaderBuilder::new()
                .has_headers(false)
                .flexible(true)
                .from_reader(lines.reader),
        }
    }

    /// Read the next record into `rec`; its 1-based line, `None` at the end of the file.
    fn next(&mut self, rec: &mut csv::ByteRecord) -> Result<Option<u64>, DataError> {
        match self.csv.read_byte_record(rec) {
            Ok(false) => Ok(None),
            Ok(true) => Ok(Some(
                self.line_offset + rec.position().map_or(0, csv::Position::line),
            )),
            Err(e) => {
                let line = self.line_offset + e.position().map_or(0, csv::Position::line);
                match e.into_kind() {
                    csv::ErrorKind::Io(io) => Err(DataError::io(&self.path, "reading CSV", io)),
                    other => Err(DataError::MalformedCsv {
                        file: self.path.clone(),
                        line,
                        reason: format!("{other:?}"),
                    }),
                }
            }
        }
    }
}

/// Fields of a header or record line, through the `csv` crate.
fn split_fields(line: &str) -> Result<Vec<String>, String> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(line.as_bytes());
    let mut rec = csv::StringRecord::new();
    match reader.read_record(&mut rec) {
        Ok(_) => Ok(rec.iter().map(str::to_string).collect()),
        Err(e) => Err(e.to_string()),
    }
}

/// Parses and validates data rows.
struct RowParser {
    path: PathBuf,
    layout: Layout,
    float_names: Vec<&'static str>,
    n_fields: usize,
    time: TimeCheck,
    /// Plausibility range of each Float64 column (same order as `float_names`).
    limits: Vec<Option<ColumnLimit>>,
    values: Vec<f64>,
}

impl RowParser {
    /// Parse one data record into `self.values`; returns the segment text when present.
    fn parse<'a>(
        &mut self,
        rec: &'a csv::ByteRecord,
        at: RowRef,
    ) -> Result<Option<&'a str>, DataError> {
        let line_no = at.line.unwrap_or(0);
        if rec.len() != self.n_fields {
            return Err(DataError::MalformedCsv {
                file: self.path.clone(),
                line: line_no,
                reason: format!(
                    "expected {} fields (as in the header), found {}",
                    self.n_fields,
                    rec.len()
                ),
            });
        }
        let text_of = |pos: usize| {
            std::str::from_utf8(rec.get(pos).unwrap_or(b"")).map_err(|_| DataError::MalformedCsv {
                file: self.path.clone(),
                line: line_no,
                reason: "not valid UTF-8 text".to_string(),
            })
        };
        self.values.clear();
        for (k, &pos) in self.layout.float_pos.iter().enumerate() {
            let text = text_of(pos)?.trim();
            let name = self.float_names[k];
            let x: f64 = text.parse().map_err(|_| DataError::BadValue {
                file: self.path.clone(),
                at,
                column: name.to_string(),
                text: text.to_string(),
                reason: if text.is_empty() {
                    "empty cell"
                } else {
                    "not a number"
                },
            })?;
            if !x.is_finite() {
                return Err(non_finite(&self.path, at, name, x));
            }
            if let Some(Some(limit)) = self.limits.get(k)
                && !(limit.lo..=limit.hi).contains(&x)
            {
                return Err(implausible(&self.path, at, name, x, limit));
            }
            self.values.push(x);
        }
        self.time.check(&self.path, at, self.values[0])?;
        self.layout.segment_pos.map(text_of).transpose()
    }
}

/// An open CSV dataset (second pass).
pub(crate) struct CsvSource {
    body: Body,
    rec: csv::ByteRecord,
    parser: RowParser,
    lookup: HashMap<String, u16>,
    row: u64,
    done: bool,
    spare: Option<SampleBatch>,
}

/// Open a CSV dataset: parse the metadata and header, then validate every row.
pub(crate) fn open_csv(path: &Path, mut f: File) -> Result<(DatasetInfo, CsvSource), DataError> {
    f.seek(SeekFrom::Start(0))
        .map_err(|e| DataError::io(path, "rewinding", e))?;
    let f2 = f
        .try_clone()
        .map_err(|e| DataError::io(path, "opening", e))?;
    let mut lines = Lines::new(path, f);
    let (meta, layout, header_lines) = read_preamble(path, &mut lines)?;
    check_meta(path, &meta)?;
    let new_parser = |layout: Layout| RowParser {
        path: path.to_path_buf(),
        limits: column_limits(&layout.columns.float_columns(), meta.sample_rate_hz),
        float_names: layout.columns.float_columns(),
        n_fields: layout.float_pos.len()
            + usize::from(layout.segment_pos.is_some())
            + layout.ignored.len(),
        layout,
        time: TimeCheck::new(meta.sample_rate_hz),
        values: Vec::new(),
    };
    // Pass 1: count rows, collect labels in order of first appearance, validate everything.
    let mut parser = new_parser(layout.clone());
    let mut labels: Vec<String> = Vec::new();
    let mut lookup: HashMap<String, u16> = HashMap::new();
    let mut n_rows = 0u64;
    let mut body = Body::new(path, lines);
    let mut rec = csv::ByteRecord::new();
    while let Some(line_no) = body.next(&mut rec)? {
        let at = RowRef::csv(n_rows, line_no);
        if let Some(seg) = parser.parse(&rec, at)?
            && !lookup.contains_key(seg)
        {
            if labels.len() >= MAX_SEGMENT_LABELS {
                return Err(DataError::BadSegment {
                    file: path.to_path_buf(),
                    at,
                    reason: format!("more than {MAX_SEGMENT_LABELS} distinct labels"),
                });
            }
            lookup.insert(seg.to_string(), labels.len() as u16);
            labels.push(seg.to_string());
        }
        n_rows += 1;
    }
    parser.time.finish(path)?;
    if n_rows == 0 {
        return Err(DataError::Empty {
            file: path.to_path_buf(),
        });
    }
    // Pass 2 starts right after the header.
    let mut f2 = f2;
    f2.seek(SeekFrom::Start(0))
        .map_err(|e| DataError::io(path, "rewinding", e))?;
    let mut lines2 = Lines::new(path, f2);
    for _ in 0..header_lines {
        lines2.next_line()?;
    }
    let info = DatasetInfo {
        path: path.to_path_buf(),
        format: DatasetFormat::Csv,
        meta: meta.clone(),
        columns: layout.columns,
        has_temperature: layout.columns.temperature,
        n_rows,
        segment_labels: labels,
        ignored_columns: layout.ignored.clone(),
    };
    let source = CsvSource {
        body: Body::new(path, lines2),
        rec: csv::ByteRecord::new(),
        parser: new_parser(layout),
        lookup,
        row: 0,
        done: false,
        spare: None,
    };
    Ok((info, source))
}

/// Read the comment lines and the header; returns the metadata, the layout and the number of
/// lines consumed.
fn read_preamble(path: &Path, lines: &mut Lines) -> Result<(DatasetMeta, Layout, u64), DataError> {
    let mut kv: Vec<(String, String)> = Vec::new();
    let header = loop {
        let Some((_, line)) = lines.next_line()? else {
            return Err(not_csv(path, "no header row"));
        };
        if let Some(comment) = line.strip_prefix('#') {
            if let Some((k, v)) = comment.split_once('=') {
                let v = v.strip_prefix(' ').unwrap_or(v);
                kv.push((k.trim().to_string(), unescape_meta_value(v)));
            }
            continue;
        }
        if line.trim().is_empty() {
            continue;
        }
        break line.to_string();
    };
    let fields = split_fields(&header).map_err(|reason| DataError::MalformedCsv {
        file: path.to_path_buf(),
        line: lines.line_no,
        reason,
    })?;
    let names: Vec<String> = fields.iter().map(|f| f.trim().to_string()).collect();
    if !names.iter().any(|n| n == "t_s") {
        let reason = format!("line {} is not a header with a t_s column", lines.line_no);
        if !kv.iter().any(|(k, _)| k.starts_with(KEY_PREFIX)) {
            return Err(not_csv(path, &reason));
        }
    }
    let meta =
        DatasetMeta::from_key_values(path, kv.iter().map(|(k, v)| (k.as_str(), v.as_str())))?;
    let layout = resolve_layout(path, &names)?;
    Ok((meta, layout, lines.line_no))
}

fn not_csv(path: &Path, reason: &str) -> DataError {
    DataError::NotADataset {
        file: path.to_path_buf(),
        reason: format!("not Parquet (no PAR1 magic) and not a sinsbench CSV ({reason})"),
    }
}

fn unescape_meta_value(v: &str) -> String {
    let mut out = String::with_capacity(v.len());
    let mut chars = v.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('r') => out.push('\r'),
            Some(other) => out.push(other),
            None => out.push('\\'),
        }
    }
    out
}

impl CsvSource {
    /// Keep a consumed batch's buffers for the next batch.
    pub fn recycle(&mut self, batch: SampleBatch) {
        self.spare = Some(batch);
    }

    /// The next batch of at most [`MAX_BATCH_ROWS`] rows, `None` at the end (and after an error).
    pub fn next_batch(&mut self, info: &DatasetInfo) -> Result<Option<SampleBatch>, DataError> {
        if self.done {
            return Ok(None);
        }
        let r = self.fill(info);
        if !matches!(r, Ok(Some(_))) {
            self.done = true;
        }
        r
    }

    fn fill(&mut self, info: &DatasetInfo) -> Result<Option<SampleBatch>, DataError> {
        let cols = info.columns;
        let cap = MAX_BATCH_ROWS.min(usize::try_from(info.n_rows).unwrap_or(MAX_BATCH_ROWS));
        let spare = self.spare.take().unwrap_or_default();
        let mut batch = SampleBatch {
            first_row: self.row,
            samples: reuse(Some(spare.samples), cap),
            segment_index: cols.segment.then(|| reuse(spare.segment_index, cap)),
            reference: cols.reference.then(|| reuse(spare.reference, cap)),
        };
        while batch.samples.len() < MAX_BATCH_ROWS {
            let Some(line_no) = self.body.next(&mut self.rec)? else {
                self.parser.time.finish(&info.path)?;
                break;
            };
            let at = RowRef::csv(self.row, line_no);
            let seg = self.parser.parse(&self.rec, at)?;
            if let (Some(seg), Some(out)) = (seg, batch.segment_index.as_mut()) {
                let idx = *self.lookup.get(seg).ok_or_else(|| DataError::BadSegment {
                    file: info.path.clone(),
                    at,
                    reason: format!("label {seg:?} was not seen when the file was opened"),
                })?;
                out.push(idx);
            }
            let v = &self.parser.values;
            let temp_degc = if cols.temperature {
                [v[7], v[8], v[9]]
            } else {
                [f64::NAN; 3]
            };
            batch.samples.push(ImuSample {
                t_s: v[0],
                dtheta_rad: Vec3::new(v[1], v[2], v[3]),
                dv_mps: Vec3::new(v[4], v[5], v[6]),
                temp_degc,
            });
            if let Some(out) = batch.reference.as_mut() {
                let k0 = if cols.temperature { 10 } else { 7 };
                out.push(ReferenceRow::from_array(std::array::from_fn(|k| v[k0 + k])));
            }
            self.row += 1;
        }
        Ok((!batch.samples.is_empty()).then_some(batch))
    }
}
