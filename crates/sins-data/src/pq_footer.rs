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

/// The footer structs on polars' path to a list (parquet.thrift).
#[derive(Clone, Copy, Debug)]
enum Known {
    FileMetaData,
    RowGroup,
    ColumnChunk,
    ColumnMetaData,
    Other,
}

impl Known {
    /// The Thrift type of field `id` (9 list, 12 struct, 5 i32, 8 binary), the element type of a
    /// list, and the kind of struct inside.
    fn field(self, id: i64) -> Option<(u8, u8, Known)> {
        use Known::*;
        Some(match (self, id) {
            (FileMetaData, 2 | 5 | 7) => (9, 12, Other),
            (FileMetaData, 4) => (9, 12, RowGroup),
            (RowGroup, 1) => (9, 12, ColumnChunk),
            (RowGroup, 4) => (9, 12, Other),
            (ColumnChunk, 3) => (12, 0, ColumnMetaData),
            (ColumnMetaData, 2) => (9, 5, Other),
            (ColumnMetaData, 3) => (9, 8, Other),
            (ColumnMetaData, 8 | 13) => (9, 12, Other),
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
            match kind.field(id) {
                Some((want, elem, child)) => {
                    if ty != want {
                        return Err(format!(
                            "footer field {id} of {kind:?} has Thrift type {ty}, the format says {want}"
                        ));
                    }
                    if want == 12 {
                        self.walk_struct(child, depth + 1)?;
                    } else {
                        self.walk_list(elem, child, depth)?;
                    }
                }
                None => match ty {
                    1 | 2 => {} // bool: value in the type
                    t => self.skip_value(t, depth)?,
                },
            }
        }
    }

    /// A list polars reads with elements of type `elem` (structs of kind `child`).
    fn walk_list(&mut self, elem: u8, child: Known, depth: u32) -> Result<(), String> {
        let h = self.byte()?;
        let n = if h >> 4 == 0x0f {
            self.length("list")?
        } else {
            usize::from(h >> 4)
        };
        if h & 0x0f != elem {
            return Err(format!(
                "footer list has elements of Thrift type {}, the format says {elem}",
                h & 0x0f
            ));
        }
        if n > self.left() {
            let left = self.left();
            return Err(format!(
                "footer declares a list of {n} with only {left} bytes left"
            ));
        }
        for _ in 0..n {
            if elem == 12 {
                self.walk_struct(child, depth + 1)?;
            } else {
                self.skip_value(elem, depth + 1)?;
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
