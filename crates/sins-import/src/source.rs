//! Record sources: delimited text (through the `csv` crate), whitespace-separated text, fixed
//! binary records, and the PSINS `.imu` text format. Gzip-compressed files are read as they are.
//! A source yields, per record, the numbers of the fields the import asked for.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use crate::description::{Binary, ByteOrder, ColumnRef, Delimited};
use crate::error::{ImportError, SourcePos};

/// Open `path` for reading as it comes: through a gzip decoder when it starts with the gzip
/// magic, or the one file of a zip archive (its first member that is not a directory when
/// there are several, named in errors).
pub fn open_maybe_gzip(path: &Path) -> Result<Box<dyn BufRead + Send>, ImportError> {
    let io = |action: &'static str| {
        move |e| ImportError::Io {
            file: path.to_path_buf(),
            action,
            source: e,
        }
    };
    let mut f = BufReader::with_capacity(1 << 20, File::open(path).map_err(io("opening"))?);
    let head = f.fill_buf().map_err(io("reading"))?;
    if head.starts_with(&[0x1f, 0x8b]) {
        return Ok(Box::new(BufReader::with_capacity(
            1 << 20,
            flate2::bufread::MultiGzDecoder::new(f),
        )));
    }
    if head.starts_with(b"PK\x03\x04") {
        return open_zip_member(path);
    }
    Ok(Box::new(f))
}

/// The single data file of a zip archive, inflated as a stream.
fn open_zip_member(path: &Path) -> Result<Box<dyn BufRead + Send>, ImportError> {
    use std::io::{Seek, SeekFrom};
    let bad = |reason: String| ImportError::Record {
        file: path.to_path_buf(),
        at: SourcePos::default(),
        reason,
    };
    let file = File::open(path).map_err(|e| ImportError::Io {
        file: path.to_path_buf(),
        action: "opening",
        source: e,
    })?;
    let mut archive =
        zip::ZipArchive::new(file).map_err(|e| bad(format!("not a readable zip archive: {e}")))?;
    let files: Vec<usize> = (0..archive.len())
        .filter(|&i| {
            archive
                .name_for_index(i)
                .is_some_and(|n| n.is_ok_and(|n| !n.ends_with('/')))
        })
        .collect();
    let [index] = files[..] else {
        return Err(bad(format!(
            "a zip archive must hold exactly one file to be read as it comes; this one holds {} \
             (extract the one you want)",
            files.len()
        )));
    };
    let (start, size, method) = {
        let member = archive
            .by_index_raw(index)
            .map_err(|e| bad(format!("zip member {index}: {e}")))?;
        let start = member
            .data_start()
            .ok_or_else(|| bad(format!("zip member {index}: no data offset")))?;
        (start, member.compressed_size(), member.compression())
    };
    let mut raw = archive.into_inner();
    raw.seek(SeekFrom::Start(start))
        .map_err(|e| ImportError::Io {
            file: path.to_path_buf(),
            action: "seeking to the zip member",
            source: e,
        })?;
    let body = BufReader::with_capacity(1 << 20, raw.take(size));
    Ok(match method {
        zip::CompressionMethod::Stored => Box::new(body),
        zip::CompressionMethod::Deflated => Box::new(BufReader::with_capacity(
            1 << 20,
            flate2::bufread::DeflateDecoder::new(body),
        )),
        other => {
            return Err(bad(format!(
                "the zip member is compressed with {other:?}; only stored and deflated members \
                 are read (extract it)"
            )));
        }
    })
}

/// A binary field type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum FieldType {
    F32,
    F64,
    I16,
    I32,
    U16,
    U32,
    Pad(usize),
}

impl FieldType {
    fn parse(text: &str) -> Option<Self> {
        Some(match text.trim() {
            "f32" => Self::F32,
            "f64" => Self::F64,
            "i16" => Self::I16,
            "i32" => Self::I32,
            "u16" => Self::U16,
            "u32" => Self::U32,
            t => Self::Pad(t.strip_prefix("pad")?.parse().ok().filter(|n| *n > 0)?),
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I16 | Self::U16 => 2,
            Self::F32 | Self::I32 | Self::U32 => 4,
            Self::F64 => 8,
            Self::Pad(n) => n,
        }
    }

    fn decode(self, b: &[u8], big: bool) -> f64 {
        macro_rules! get {
            ($t:ty, $n:expr) => {{
                let mut a = [0u8; $n];
                a.copy_from_slice(&b[..$n]);
                if big {
                    <$t>::from_be_bytes(a) as f64
                } else {
                    <$t>::from_le_bytes(a) as f64
                }
            }};
        }
        match self {
            Self::F32 => get!(f32, 4),
            Self::F64 => get!(f64, 8),
            Self::I16 => get!(i16, 2),
            Self::I32 => get!(i32, 4),
            Self::U16 => get!(u16, 2),
            Self::U32 => get!(u32, 4),
            Self::Pad(_) => f64::NAN,
        }
    }
}

enum Kind {
    Csv(csv::Reader<Box<dyn BufRead + Send>>, csv::ByteRecord),
    Whitespace(Box<dyn BufRead + Send>, String),
    Binary {
        reader: Box<dyn BufRead + Send>,
        types: Vec<FieldType>,
        offsets: Vec<usize>,
        buf: Vec<u8>,
        big: bool,
    },
}

/// An open record source.
pub struct Source {
    file: PathBuf,
    kind: Kind,
    /// Field names (header or binary field names; empty without a header).
    names: Vec<String>,
    /// Lines before the first data line (text formats).
    line_offset: u64,
    lines_read: u64,
    record: u64,
    byte: u64,
    wanted: Vec<usize>,
    wanted_names: Vec<String>,
}

impl Source {
    /// A source over `kind` with no record read yet.
    fn base(file: &Path, kind: Kind, names: Vec<String>, line_offset: u64, byte: u64) -> Self {
        Self {
            file: file.to_path_buf(),
            kind,
            names,
            line_offset,
            lines_read: 0,
            record: 0,
            byte,
            wanted: Vec::new(),
            wanted_names: Vec::new(),
        }
    }

    /// Open delimited text (CSV, TSV, `;`, whitespace).
    pub fn delimited(file: &Path, d: &Delimited) -> Result<Self, ImportError> {
        let mut reader = open_maybe_gzip(file)?;
        let mut line = String::new();
        let mut lines = 0u64;
        let read_line =
            |reader: &mut Box<dyn BufRead + Send>, line: &mut String, lines: &mut u64| {
                line.clear();
                *lines += 1;
                reader
                    .read_line(line)
                    .map_err(|e| io_or_text(file, *lines, e))
            };
        for _ in 0..d.skip_lines {
            read_line(&mut reader, &mut line, &mut lines)?;
        }
        let delim = match d.delimiter.as_str() {
            "whitespace" => None,
            "tab" | "\t" => Some(b'\t'),
            s if s.len() == 1 && s.is_ascii() => Some(s.as_bytes()[0]),
            other => {
                return Err(ImportError::desc(
                    file,
                    "delimited.delimiter",
                    format!("'{other}' is not one ASCII character, \"tab\" or \"whitespace\""),
                ));
            }
        };
        let comment = match d.comment {
            Some(c) if c.is_ascii() => Some(c as u8),
            Some(c) => {
                return Err(ImportError::desc(
                    file,
                    "delimited.comment",
                    format!("'{c}' is not an ASCII character"),
                ));
            }
            None => None,
        };
        let empty = Kind::Whitespace(Box::new(std::io::empty()), String::new());
        let mut src = Self::base(file, empty, Vec::new(), lines, 0);
        match delim {
            Some(b) => {
                let mut csv = csv::ReaderBuilder::new()
                    .delimiter(b)
                    .has_headers(d.header)
                    .comment(comment)
                    // Fields are trimmed as they are parsed, and only the wanted ones:
                    // `Trim::All` re-allocates every record.
                    .flexible(false)
                    .from_reader(reader);
                if d.header {
                    let h = csv.byte_headers().map_err(|e| src.csv_error(e))?;
                    src.names = h
                        .iter()
                        .map(|f| String::from_utf8_lossy(f).trim().to_string())
                        .collect();
                }
                src.kind = Kind::Csv(csv, csv::ByteRecord::new());
            }
            None => {
                if d.header {
                    loop {
                        if read_line(&mut reader, &mut line, &mut lines)? == 0 {
                            return Err(src.record_error("no header line"));
                        }
                        let t = line.trim();
                        if t.is_empty() || comment.is_some_and(|c| t.as_bytes()[0] == c) {
                            continue;
                        }
                        src.names = t.split_ascii_whitespace().map(str::to_string).collect();
                        break;
                    }
                }
                src.line_offset = lines;
                src.kind = Kind::Whitespace(reader, String::new());
            }
        }
        Ok(src)
    }

    /// Open whitespace-separated text that continues `reader` after `lines` lines (PSINS).
    pub fn whitespace_after(file: &Path, reader: Box<dyn BufRead + Send>, lines: u64) -> Self {
        Self::base(
            file,
            Kind::Whitespace(reader, String::new()),
            Vec::new(),
            lines,
            0,
        )
    }

    /// Open fixed binary records.
    pub fn binary(file: &Path, b: &Binary) -> Result<Self, ImportError> {
        let mut reader = open_maybe_gzip(file)?;
        let mut types = Vec::new();
        let mut offsets = Vec::new();
        let mut size = 0usize;
        for (k, f) in b.fields.iter().enumerate() {
            let t = FieldType::parse(&f.kind).ok_or_else(|| {
                ImportError::desc(
                    file,
                    &format!("binary.fields[{k}].type"),
                    format!("'{}' is not f32, f64, i16, i32, u16, u32 or padN", f.kind),
                )
            })?;
            types.push(t);
            offsets.push(size);
            size += t.size();
        }
        if size == 0 {
            return Err(ImportError::desc(file, "binary.fields", "no fields"));
        }
        let skipped = std::io::copy(
            &mut (&mut reader).take(b.header_bytes),
            &mut std::io::sink(),
        )
        .map_err(|e| ImportError::Io {
            file: file.to_path_buf(),
            action: "skipping the header bytes",
            source: e,
        })?;
        if skipped < b.header_bytes {
            return Err(ImportError::Record {
                file: file.to_path_buf(),
                at: SourcePos::default(),
                reason: format!(
                    "the file has {skipped} bytes, fewer than binary.header_bytes = {}",
                    b.header_bytes
                ),
            });
        }
        let kind = Kind::Binary {
            reader,
            types,
            offsets,
            buf: vec![0; size],
            big: b.byte_order == ByteOrder::Big,
        };
        let names = b.fields.iter().map(|f| f.name.clone()).collect();
        Ok(Self::base(file, kind, names, 0, b.header_bytes))
    }

    /// The field index of a column reference; `key` names it in errors.
    pub fn resolve(&self, key: &str, col: &ColumnRef) -> Result<usize, ImportError> {
        match col {
            ColumnRef::Index(i) => {
                if let Kind::Binary { types, .. } = &self.kind
                    && *i >= types.len()
                {
                    return Err(ImportError::desc(
                        &self.file,
                        key,
                        format!("column {i}: a record has {} fields", types.len()),
                    ));
                }
                Ok(*i)
            }
            ColumnRef::Name(n) => self.names.iter().position(|h| h == n).ok_or_else(|| {
                ImportError::desc(
                    &self.file,
                    key,
                    if self.names.is_empty() {
                        format!("'{n}': the file has no header; give a 0-based column index")
                    } else {
                        format!(
                            "'{n}' is not a column (the file has: {})",
                            self.names.join(", ")
                        )
                    },
                )
            }),
        }
    }

    /// Ask for these fields (indices from [`Source::resolve`]), named as the description names
    /// them; [`Source::next`] returns them in this order.
    pub fn want(&mut self, fields: Vec<(usize, String)>) -> Result<(), ImportError> {
        if let Kind::Binary { types, .. } = &self.kind
            && let Some((i, name)) = fields
                .iter()
                .find(|(i, _)| matches!(types[*i], FieldType::Pad(_)))
        {
            return Err(ImportError::desc(
                &self.file,
                name,
                format!("field {i} is padding"),
            ));
        }
        (self.wanted, self.wanted_names) = fields.into_iter().unzip();
        Ok(())
    }

    /// The next record's wanted fields into `out`; `None` at the end of the file.
    pub fn next(&mut self, out: &mut Vec<f64>) -> Result<Option<SourcePos>, ImportError> {
        out.clear();
        match &mut self.kind {
            Kind::Csv(reader, rec) => {
                let more = reader.read_byte_record(rec);
                let more =
                    more.map_err(|e| csv_err(&self.file, self.line_offset, self.record, e))?;
                if !more {
                    return Ok(None);
                }
                let at = SourcePos {
                    record: self.record,
                    line: rec.position().map(|p| p.line() + self.line_offset),
                    byte: None,
                };
                for (k, &i) in self.wanted.iter().enumerate() {
                    let text = rec.get(i).unwrap_or(b"");
                    out.push(parse_number(&self.file, at, &self.wanted_names[k], text)?);
                }
                self.record += 1;
                Ok(Some(at))
            }
            Kind::Whitespace(reader, line) => loop {
                line.clear();
                self.lines_read += 1;
                let line_no = self.line_offset + self.lines_read;
                let n = reader
                    .read_line(line)
                    .map_err(|e| io_or_text(&self.file, line_no, e))?;
                if n == 0 {
                    return Ok(None);
                }
                if line.trim().is_empty() || line.trim_start().starts_with(['#', '%']) {
                    continue;
                }
                let at = SourcePos {
                    record: self.record,
                    line: Some(line_no),
                    byte: None,
                };
                let fields: Vec<&str> = line.split_ascii_whitespace().collect();
                for (k, &i) in self.wanted.iter().enumerate() {
                    let Some(text) = fields.get(i) else {
                        return Err(ImportError::Record {
                            file: self.file.clone(),
                            at,
                            reason: format!(
                                "{} fields, but {} is field {i} (0-based)",
                                fields.len(),
                                self.wanted_names[k]
                            ),
                        });
                    };
                    out.push(parse_number(
                        &self.file,
                        at,
                        &self.wanted_names[k],
                        text.as_bytes(),
                    )?);
                }
                self.record += 1;
                return Ok(Some(at));
            },
            Kind::Binary {
                reader,
                types,
                offsets,
                buf,
                big,
            } => {
                let at = SourcePos {
                    record: self.record,
                    line: None,
                    byte: Some(self.byte),
                };
                let got = read_full(reader, buf).map_err(|e| ImportError::Io {
                    file: self.file.clone(),
                    action: "reading a record",
                    source: e,
                })?;
                if got == 0 {
                    return Ok(None);
                }
                if got < buf.len() {
                    return Err(ImportError::Record {
                        file: self.file.clone(),
                        at,
                        reason: format!(
                            "the file ends inside a record: {got} of {} bytes (truncated, or \
                             binary.fields / header_bytes do not match the file)",
                            buf.len()
                        ),
                    });
                }
                for (k, &i) in self.wanted.iter().enumerate() {
                    let x = types[i].decode(&buf[offsets[i]..], *big);
                    if !x.is_finite() {
                        return Err(ImportError::Value {
                            file: self.file.clone(),
                            at,
                            column: self.wanted_names[k].as_str().into(),
                            text: x.to_string().into(),
                            reason: "is not finite",
                        });
                    }
                    out.push(x);
                }
                self.record += 1;
                self.byte += buf.len() as u64;
                Ok(Some(at))
            }
        }
    }

    fn record_error(&self, reason: &str) -> ImportError {
        ImportError::Record {
            file: self.file.clone(),
            at: SourcePos {
                record: self.record,
                line: Some(self.line_offset + 1),
                byte: None,
            },
            reason: reason.to_string(),
        }
    }

    fn csv_error(&self, e: csv::Error) -> ImportError {
        csv_err(&self.file, self.line_offset, self.record, e)
    }
}

fn read_full(r: &mut dyn Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut n = 0;
    while n < buf.len() {
        match r.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(n)
}

fn csv_err(file: &Path, line_offset: u64, record: u64, e: csv::Error) -> ImportError {
    let line = e.position().map(|p| p.line() + line_offset);
    let reason = match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => format!("{len} fields where the first record has {expected_len}"),
        csv::ErrorKind::Io(io) => format!("I/O error: {io}"),
        _ => e.to_string(),
    };
    ImportError::Record {
        file: file.to_path_buf(),
        at: SourcePos {
            record,
            line,
            byte: None,
        },
        reason,
    }
}

fn io_or_text(file: &Path, line: u64, e: std::io::Error) -> ImportError {
    if e.kind() == std::io::ErrorKind::InvalidData {
        ImportError::Record {
            file: file.to_path_buf(),
            at: SourcePos {
                record: 0,
                line: Some(line),
                byte: None,
            },
            reason: "not valid UTF-8 text (or a damaged gzip stream)".to_string(),
        }
    } else {
        ImportError::Io {
            file: file.to_path_buf(),
            action: "reading",
            source: e,
        }
    }
}

/// Parse a finite number from a field's bytes.
fn parse_number(file: &Path, at: SourcePos, column: &str, text: &[u8]) -> Result<f64, ImportError> {
    let bad = |reason| ImportError::Value {
        file: file.to_path_buf(),
        at,
        column: column.into(),
        text: String::from_utf8_lossy(text).into(),
        reason,
    };
    let s = text.trim_ascii();
    if s.is_empty() {
        return Err(bad("is an empty field"));
    }
    let x: f64 = match fast_float2::parse(s) {
        Ok(x) => x,
        Err(_) if std::str::from_utf8(s).is_err() => return Err(bad("is not UTF-8 text")),
        Err(_) => return Err(bad("is not a number")),
    };
    if !x.is_finite() {
        return Err(bad("is not finite"));
    }
    Ok(x)
}
