//! A pre-check of a Parquet footer's Thrift (compact protocol) encoding before the `parquet`
//! crate reads it: every list, set, map and binary must declare a length no larger than the
//! bytes left in the footer. Every element takes at least one byte, so a valid footer always
//! passes.
//!
//! Why: the `parquet` crate (58) pre-sizes each list from its declared length
//! (`Vec::with_capacity` in `read_thrift_vec` and for the row groups), so a 2.7 KB file whose
//! footer claims 2^31 key/value pairs asks for about 100 GB, and the allocation failure aborts
//! the process (no panic to catch). Its reader also dispatches on field ids alone and ignores the
//! declared Thrift type, so the walk here must read exactly as it does: in every struct it reads
//! by id (all those on the way from `FileMetaData` to a list, the logical-type and column-order
//! unions included) a field must carry the type parquet.thrift gives its id, field ids wrap to
//! 16 bits as there, and lists of booleans (which it skips as zero bytes) are refused. Fuzz
//! findings (against polars-parquet, whose reader has the same habits):
//! `tests/data/fuzz/footer_*.parquet`.

use crate::DataError;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

/// Refuses the Parquet file `f` (of `file_len` bytes) when its footer declares a length beyond
/// its own size; a file whose footer this check cannot locate is left to the reader's errors.
pub(crate) fn check_footer<F: Read + Seek>(
    path: &Path,
    f: &mut F,
    file_len: u64,
) -> Result<(), DataError> {
    if file_len < 12 {
        return Ok(());
    }
    let io = |e| DataError::io(path, "reading the Parquet footer", e);
    let mut tail = [0u8; 8];
    f.seek(SeekFrom::End(-8)).map_err(io)?;
    f.read_exact(&mut tail).map_err(io)?;
    let len = u64::from(u32::from_le_bytes([tail[0], tail[1], tail[2], tail[3]]));
    if &tail[4..] != b"PAR1" || len > file_len - 8 {
        f.seek(SeekFrom::Start(0)).map_err(io)?;
        return Ok(()); // the reader reports these itself
    }
    let mut footer = vec![0u8; len as usize];
    f.seek(SeekFrom::End(-8 - len as i64)).map_err(io)?;
    f.read_exact(&mut footer).map_err(io)?;
    f.seek(SeekFrom::Start(0)).map_err(io)?;
    let mut r = Reader {
        buf: &footer,
        pos: 0,
    };
    r.walk_struct(Known::FileMetaData, 0)
        .map_err(|reason| DataError::corrupt(path, reason))
}

/// The footer structs the `parquet` crate reads field by field (parquet.thrift).
#[derive(Clone, Copy, Debug)]
enum Known {
    FileMetaData,
    SchemaElement,
    RowGroup,
    ColumnChunk,
    ColumnMetaData,
    KeyValue,
    SortingColumn,
    PageEncodingStats,
    Statistics,
    SizeStatistics,
    GeospatialStatistics,
    BoundingBox,
    LogicalType,
    DecimalType,
    TimestampType,
    TimeUnit,
    IntType,
    VariantType,
    GeometryType,
    GeographyType,
    ColumnOrder,
    /// Any other struct (the empty ones of the unions, encryption): walked by declared types.
    Other,
}

/// What a Thrift compact type reads as: i16, i32 and i64 are all varints.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Class {
    Bool,
    Byte,
    Varint,
    Double,
    Binary,
    List,
    Map,
    Struct,
}

fn class(ty: u8) -> Option<Class> {
    Some(match ty {
        1 | 2 => Class::Bool,
        3 => Class::Byte,
        4..=6 => Class::Varint,
        7 => Class::Double,
        8 => Class::Binary,
        9 | 10 => Class::List,
        11 => Class::Map,
        12 => Class::Struct,
        _ => return None,
    })
}

/// A field as the format declares it.
#[derive(Clone, Copy, Debug)]
enum Field {
    Scalar(Class),
    List(Class, Known),
    Struct(Known),
}

impl Known {
    /// The format's type of field `id` (`None`: an id the reader skips by its declared type).
    fn field(self, id: i16) -> Option<Field> {
        use Class::{Binary as B, Bool, Byte, Double, Struct as S, Varint as V};
        use Field::{List, Scalar, Struct};
        use Known::*;
        Some(match (self, id) {
            (FileMetaData, 1 | 3) => Scalar(V),
            (FileMetaData, 2) => List(S, SchemaElement),
            (FileMetaData, 4) => List(S, RowGroup),
            (FileMetaData, 5) => List(S, KeyValue),
            (FileMetaData, 6 | 9) => Scalar(B),
            (FileMetaData, 7) => List(S, ColumnOrder),
            (FileMetaData, 8) => Struct(Other),
            (SchemaElement, 1..=3 | 5..=9) => Scalar(V),
            (SchemaElement, 4) => Scalar(B),
            (SchemaElement, 10) => Struct(LogicalType),
            (RowGroup, 1) => List(S, ColumnChunk),
            (RowGroup, 2 | 3 | 5..=7) => Scalar(V),
            (RowGroup, 4) => List(S, SortingColumn),
            (ColumnChunk, 1 | 9) => Scalar(B),
            (ColumnChunk, 2 | 4..=7) => Scalar(V),
            (ColumnChunk, 3) => Struct(ColumnMetaData),
            (ColumnChunk, 8) => Struct(Other),
            (ColumnMetaData, 1 | 4..=7 | 9..=11 | 14 | 15) => Scalar(V),
            (ColumnMetaData, 2) => List(V, Other),
            (ColumnMetaData, 3) => List(B, Other),
            (ColumnMetaData, 8) => List(S, KeyValue),
            (ColumnMetaData, 12) => Struct(Statistics),
            (ColumnMetaData, 13) => List(S, PageEncodingStats),
            (ColumnMetaData, 16) => Struct(SizeStatistics),
            (ColumnMetaData, 17) => Struct(GeospatialStatistics),
            (KeyValue, 1 | 2) => Scalar(B),
            (SortingColumn, 1) => Scalar(V),
            (SortingColumn, 2 | 3) => Scalar(Bool),
            (PageEncodingStats, 1..=3) => Scalar(V),
            (Statistics, 1 | 2 | 5 | 6) => Scalar(B),
            (Statistics, 3 | 4) => Scalar(V),
            (Statistics, 7 | 8) => Scalar(Bool),
            (SizeStatistics, 1) => Scalar(V),
            (SizeStatistics, 2 | 3) => List(V, Other),
            (GeospatialStatistics, 1) => Struct(BoundingBox),
            (GeospatialStatistics, 2) => List(V, Other),
            (BoundingBox, 1..=8) => Scalar(Double),
            (LogicalType, 1..=4 | 6 | 11..=15) => Struct(Other),
            (LogicalType, 5) => Struct(DecimalType),
            (LogicalType, 7 | 8) => Struct(TimestampType),
            (LogicalType, 10) => Struct(IntType),
            (LogicalType, 16) => Struct(VariantType),
            (LogicalType, 17) => Struct(GeometryType),
            (LogicalType, 18) => Struct(GeographyType),
            (DecimalType, 1 | 2) => Scalar(V),
            (TimestampType, 1) => Scalar(Bool),
            (TimestampType, 2) => Struct(TimeUnit),
            (TimeUnit, 1..=3) => Struct(Other),
            (IntType, 1) => Scalar(Byte),
            (IntType, 2) => Scalar(Bool),
            (VariantType, 1) => Scalar(Byte),
            (GeometryType, 1) => Scalar(B),
            (GeographyType, 1) => Scalar(B),
            (GeographyType, 2) => Scalar(V),
            (ColumnOrder, 1) => Struct(Other),
            _ => return None,
        })
    }
}

struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

const MAX_DEPTH: u32 = 64;

impl Reader<'_> {
    fn left(&self) -> usize {
        self.buf.len() - self.pos
    }

    fn byte(&mut self) -> Result<u8, String> {
        let b = *self.buf.get(self.pos).ok_or("footer ends inside a value")?;
        self.pos += 1;
        Ok(b)
    }

    fn varint(&mut self) -> Result<u64, String> {
        let mut v = 0u64;
        for shift in (0..64).step_by(7) {
            let b = self.byte()?;
            v |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Ok(v);
            }
        }
        Err("varint longer than 10 bytes".into())
    }

    /// A declared element count or byte length: at most the bytes left.
    fn length(&mut self, what: &str) -> Result<usize, String> {
        let v = self.varint()?;
        if v > self.left() as u64 {
            return Err(format!(
                "footer declares a {what} of length {v} with only {} bytes left",
                self.left()
            ));
        }
        Ok(v as usize)
    }

    fn skip_struct(&mut self, depth: u32) -> Result<(), String> {
        self.walk_struct(Known::Other, depth)
    }

    /// Walks a struct; in the structs the `parquet` crate reads by id (`kind`), a field must
    /// carry the type parquet.thrift gives its id, since that reader ignores the declared type
    /// (a struct declared where it reads a list let a 2^31-element list header through).
    fn walk_struct(&mut self, kind: Known, depth: u32) -> Result<(), String> {
        if depth > MAX_DEPTH {
            return Err("footer nests structs too deeply".into());
        }
        let mut id: i16 = 0;
        loop {
            let h = self.byte()?;
            let ty = h & 0x0f;
            if ty == 0 {
                return Ok(());
            }
            id = if h >> 4 == 0 {
                // Long-form field id: a zigzag varint, truncated to 16 bits as the reader does.
                let z = self.varint()?;
                ((z >> 1) as i64 ^ -((z & 1) as i64)) as i16
            } else {
                id.checked_add(i16::from(h >> 4))
                    .ok_or("footer field id overflows 16 bits")?
            };
            let Some(field) = kind.field(id) else {
                match ty {
                    1 | 2 => {} // bool: value in the type
                    t => self.skip_value(t, depth)?,
                }
                continue;
            };
            let want = match field {
                Field::Scalar(c) => c,
                Field::List(..) => Class::List,
                Field::Struct(_) => Class::Struct,
            };
            if class(ty) != Some(want) {
                return Err(format!(
                    "footer field {id} of {kind:?} has Thrift type {ty}, the format says {want:?}"
                ));
            }
            match field {
                Field::Scalar(Class::Bool) => {} // value in the type
                Field::Scalar(_) => self.skip_value(ty, depth)?,
                Field::List(elem, child) => self.walk_list(elem, child, depth)?,
                Field::Struct(child) => self.walk_struct(child, depth + 1)?,
            }
        }
    }

    /// The header of a list or set: (element type, count), the count at most the bytes left.
    /// A zero header byte is an empty list (some writers leave out the element type then).
    fn list_header(&mut self) -> Result<(u8, usize), String> {
        let h = self.byte()?;
        let n = if h >> 4 == 0x0f {
            self.length("list")?
        } else {
            usize::from(h >> 4)
        };
        if n > self.left() {
            let left = self.left();
            return Err(format!(
                "footer declares a list of {n} with only {left} bytes left"
            ));
        }
        if h != 0 && matches!(h & 0x0f, 1 | 2) {
            // The reader would skip such elements as zero bytes, out of step with the data.
            return Err("footer holds a list of booleans (no Parquet field is one)".into());
        }
        Ok((h & 0x0f, n))
    }

    /// A list the reader reads with elements of class `elem` (structs of kind `child`).
    fn walk_list(&mut self, elem: Class, child: Known, depth: u32) -> Result<(), String> {
        let (ty, n) = self.list_header()?;
        if n == 0 {
            return Ok(());
        }
        if class(ty) != Some(elem) {
            return Err(format!(
                "footer list has elements of Thrift type {ty}, the format says {elem:?}"
            ));
        }
        for _ in 0..n {
            if elem == Class::Struct {
                self.walk_struct(child, depth + 1)?;
            } else {
                self.skip_value(ty, depth + 1)?;
            }
        }
        Ok(())
    }

    fn skip_value(&mut self, ty: u8, depth: u32) -> Result<(), String> {
        if depth > MAX_DEPTH {
            return Err("footer nests values too deeply".into());
        }
        match ty {
            1..=3 => {
                self.byte()?; // bool (in a list) or byte
            }
            4..=6 => {
                self.varint()?;
            }
            7 => {
                if self.left() < 8 {
                    return Err("footer ends inside a double".into());
                }
                self.pos += 8;
            }
            8 => {
                let n = self.length("binary")?;
                self.pos += n;
            }
            9 | 10 => {
                let (elem, n) = self.list_header()?;
                for _ in 0..n {
                    self.skip_value(elem, depth + 1)?;
                }
            }
            11 => {
                let n = self.length("map")?;
                if n > 0 {
                    let kv = self.byte()?;
                    for _ in 0..n {
                        self.skip_value(kv >> 4, depth + 1)?;
                        self.skip_value(kv & 0x0f, depth + 1)?;
                    }
                }
            }
            12 => self.skip_struct(depth + 1)?,
            t => return Err(format!("footer has an unknown Thrift type {t}")),
        }
        Ok(())
    }
}
