//! A pre-check of a Parquet footer's Thrift (compact protocol) encoding: every list, set, map
//! and binary declares a length no larger than the bytes left in the footer. Every element takes
//! at least one byte, so a valid footer always passes; a footer that claims 2^31 key/value pairs
//! in 30 bytes does not.
//!
//! Why: polars-parquet 0.55.2 pre-sizes each list from its declared length
//! (`Vec::with_capacity(list.size)` in `handwritten_thrift/file_metadata_thrift.rs`), so such a
//! footer makes `read_metadata` allocate up to ~100 GB, and the allocation failure aborts the
//! process (no panic: `catch_unwind` cannot help). Fuzz finding
//! `crates/sins-data/tests/data/fuzz/footer_list_length.parquet`. This is the proposed fix: call
//! [`check_parquet_footer`] on the file before `read_metadata` (sins-data's `open_parquet`); until
//! then the `dataset_parquet` target skips inputs it rejects, so that fuzzing goes on past it.

/// `Err(reason)` when the footer of the Parquet file `file` (or of a file whose last
/// `file.len()` bytes these are, footer included) declares a length beyond its own size.
pub fn check_parquet_footer(file: &[u8]) -> Result<(), String> {
    let n = file.len();
    if n < 12 || &file[n - 4..] != b"PAR1" {
        return Ok(()); // not a footer this check can read: leave it to the reader's errors
    }
    let len = u32::from_le_bytes([file[n - 8], file[n - 7], file[n - 6], file[n - 5]]) as usize;
    if len > n - 8 {
        return Ok(()); // the reader reports this itself
    }
    let mut r = Reader { buf: &file[n - 8 - len..n - 8], pos: 0 };
    r.skip_struct(0)
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
        if depth > MAX_DEPTH {
            return Err("footer nests structs too deeply".into());
        }
        loop {
            let h = self.byte()?;
            let ty = h & 0x0f;
            if ty == 0 {
                return Ok(());
            }
            if h >> 4 == 0 {
                self.varint()?; // long-form field id
            }
            match ty {
                1 | 2 => {} // bool: value in the type
                t => self.skip_value(t, depth)?,
            }
        }
    }

    fn skip_value(&mut self, ty: u8, depth: u32) -> Result<(), String> {
        if depth > MAX_DEPTH {
            return Err("footer nests values too deeply".into());
        }
        match ty {
            1 | 2 | 3 => {
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
                    return Err(format!("footer declares a list of {n} with only {left} bytes left"));
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
