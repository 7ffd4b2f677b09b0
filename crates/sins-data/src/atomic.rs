//! Crash-safe file replacement: write a temporary file beside the target, fsync it, rename it
//! over the target. A failure or crash never leaves a half-written file at the target path and
//! never clobbers a good existing file.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use polars::prelude::{DataFrame, KeyValueMetadata, ParquetCompression, ParquetWriter};

use crate::error::DataError;

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// A temporary file beside a target path; removed on drop unless [`TempPath::commit`] ran.
#[derive(Debug)]
pub(crate) struct TempPath {
    path: PathBuf,
    target: PathBuf,
    armed: bool,
}

impl TempPath {
    /// Create a new, empty, uniquely named temporary file in the target's directory.
    pub fn create(target: &Path) -> Result<(Self, File), DataError> {
        let name = target
            .file_name()
            .ok_or_else(|| DataError::invalid_write(target, "the path has no file name"))?;
        let dir = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        for _ in 0..100 {
            let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
            let mut tmp_name = std::ffi::OsString::from(".");
            tmp_name.push(name);
            tmp_name.push(format!(".tmp-{}-{n}", std::process::id()));
            let path = dir.join(tmp_name);
            match OpenOptions::new().write(true).create_new(true).open(&path) {
                Ok(file) => {
                    let guard = Self {
                        path,
                        target: target.to_path_buf(),
                        armed: true,
                    };
                    return Ok((guard, file));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => {
                    return Err(DataError::io(
                        target,
                        "creating a temporary file in the target directory",
                        e,
                    ));
                }
            }
        }
        Err(DataError::invalid_write(
            target,
            "could not find a free temporary file name",
        ))
    }

    /// fsync `file` (the temporary file, fully written), rename it over the target and fsync
    /// the directory (best effort).
    pub fn commit(mut self, file: File) -> Result<(), DataError> {
        file.sync_all()
            .map_err(|e| DataError::io(&self.target, "syncing the temporary file", e))?;
        drop(file);
        std::fs::rename(&self.path, &self.target).map_err(|e| {
            DataError::io(&self.target, "renaming the temporary file into place", e)
        })?;
        self.armed = false;
        if let Some(dir) = self.target.parent() {
            let dir = if dir.as_os_str().is_empty() {
                Path::new(".")
            } else {
                dir
            };
            if let Ok(d) = File::open(dir) {
                let _ = d.sync_all();
            }
        }
        Ok(())
    }
}

impl Drop for TempPath {
    fn drop(&mut self) {
        if self.armed {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// Atomically create or replace `path`: `write` fills a fresh temporary file in the same
/// directory; on success the file is fsynced and renamed over `path`; on error (or panic) the
/// temporary file is removed and `path` is untouched.
///
/// ```no_run
/// use std::io::Write;
/// sins_data::atomic_write(std::path::Path::new("report.txt"), |f| {
///     f.write_all(b"hello\n")
///         .map_err(|e| sins_data::DataError::Io {
///             file: "report.txt".into(),
///             action: "writing",
///             source: e,
///         })
/// })?;
/// # Ok::<(), sins_data::DataError>(())
/// ```
pub fn atomic_write<T, E, F>(path: &Path, write: F) -> Result<T, E>
where
    F: FnOnce(&mut File) -> Result<T, E>,
    E: From<DataError>,
{
    let (tmp, mut file) = TempPath::create(path)?;
    let out = write(&mut file)?;
    tmp.commit(file)?;
    Ok(out)
}

/// Atomically write a DataFrame (e.g. a report table) as a zstd-compressed Parquet file with
/// the given file-level key/value metadata. Returns the file size (bytes).
pub fn write_parquet_df_atomic(
    path: &Path,
    df: &mut DataFrame,
    kv_meta: &[(String, String)],
) -> Result<u64, DataError> {
    atomic_write(path, |file| {
        ParquetWriter::new(&mut *file)
            .with_compression(ParquetCompression::Zstd(None))
            .with_key_value_metadata(Some(KeyValueMetadata::from_static(kv_meta.to_vec())))
            .finish(df)
            .map_err(|source| DataError::Polars {
                file: path.to_path_buf(),
                source,
            })
    })
}
