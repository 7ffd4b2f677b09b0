//! A pre-check of a Parquet footer's Thrift (compact protocol) encoding before polars reads it:
//! every list, set, map and binary must declare a length no larger than the bytes left in the
//! footer. Every element takes at least one byte, so a valid footer always passes.
//!
//! Why: polars-parquet pre-sizes each list from its declared length (`Vec::with_capacity` in its
//! hand-written Thrift reader), so a 2.7 KB file whose footer claims 2^31 key/value pairs makes
//! `read_metadata` ask for about 100 GB, and the allocation failure aborts the process (no
//! panic: `catch_unwind` cannot help). Fuzz finding `tests/data/fuzz/footer_list_length.parquet`.

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

/// The footer structs polars reads (parquet.thrift), whose fields it reads by id alone.
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
    /// Any other struct (unions such as LogicalType): walked by its declared types.
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
    /// The format's type of field `id` (`None`: an id polars skips by its declared type).
    fn field(self, id: i64) -> Option<Field> {
        use Class::{Binary as B, Bool, Struct as S, Varint as V};
        use Field::{List, Scalar, Struct};
        use Known::*;
        Some(match (self, id) {
            (FileMetaData, 1 | 3) => Scalar(V),
            (FileMetaData, 2) => List(S, SchemaElement),
            (FileMetaData, 4) => List(S, RowGroup),
            (FileMetaData, 5) => List(S, KeyValue),
            (FileMetaData, 6 | 9) => Scalar(B),
            (FileMetaData, 7) => List(S, Other),
            (FileMetaData, 8) => Struct(Other),
            (SchemaElement, 1..=3 | 5..=9) => Scalar(V),
            (SchemaElement, 4) => Scalar(B),
            (SchemaElement, 10) => Struct(Other),
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
            (ColumnMetaData, 17) => Struct(Other),
            (KeyValue, 1 | 2) => Scalar(B),
            (SortingColumn, 1) => Scalar(V),
            (SortingColumn, 2 | 3) => Scalar(Bool),
            (PageEncodingStats, 1..=3) => Scalar(V),
            (Statistics, 1 | 2 | 5 | 6) => Scalar(B),
            (Statistics, 3 | 4) => Scalar(V),
            (Statistics, 7 | 8) => Scalar(Bool),
            (SizeStatistics, 1) => Scalar(V),
            (SizeStatistics, 2 | 3) => List(V, Other),
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

    /// Walks a struct; in the structs on polars' path to a list (`kind`), a field must carry
    /// the type parquet.thrift gives its id, since polars reads by id and ignores the declared
    /// type (a struct declared where it reads a list let a 2^31-element list header through).
    fn walk_struct(&mut self, kind: Known, depth: u32) -> Result<(), String> {
        if depth > MAX_DEPTH {
            return Err("footer nests structs too deeply".into());
        }
        let mut id: i64 = 0;
        loop {
            let h = self.byte()?;
            let ty = h & 0x0f;
            if ty == 0 {
                return Ok(());
            }
            id = if h >> 4 == 0 {
                let z = self.varint()? as i64;
                (z >> 1) ^ -(z & 1) // long-form field id, zigzag
            } else {
                id + i64::from(h >> 4)
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

    /// A list polars reads with elements of class `elem` (structs of kind `child`).
    fn walk_list(&mut self, elem: Class, child: Known, depth: u32) -> Result<(), String> {
        let h = self.byte()?;
        let n = if h >> 4 == 0x0f {
            self.length("list")?
        } else {
            usize::from(h >> 4)
        };
        let ty = h & 0x0f;
        if class(ty) != Some(elem) {
            return Err(format!(
                "footer list has elements of Thrift type {ty}, the format says {elem:?}"
            ));
        }
        if n > self.left() {
            let left = self.left();
            return Err(format!(
                "footer declares a list of {n} with only {left} bytes left"
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
                for _ in 0..n {
                    self.skip_value(h & 0x0f, depth + 1)?;
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
