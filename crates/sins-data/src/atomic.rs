//! Crash-safe file replacement: write a temporary file beside the target, fsync it, rename it
//! over the target. A failure or crash never leaves a half-written file at the target path and
//! never clobbers a good existing file.

use std::fs::File;
use std::path::Path;

#[cfg(feature = "polars")]
use polars::prelude::{DataFrame, KeyValueMetadata, ParquetCompression, ParquetWriter};
use sins_files::Temporary;

use crate::error::DataError;

/// A temporary file beside a target path (`.NAME.tmp-PID-N`, registered with
/// [`sins_files`] so that the binary's signal handler removes it); removed on drop
/// unless [`TempPath::commit`] ran.
#[derive(Debug)]
pub(crate) struct TempPath {
    temp: Temporary,
    target: std::path::PathBuf,
}

impl TempPath {
    /// Create a new, empty, uniquely named temporary file in the target's directory. Refuses a
    /// target that is an existing directory.
    pub fn create(target: &Path) -> Result<(Self, File), DataError> {
        let (temp, file) = Temporary::file(target).map_err(|e| {
            if e.kind() == std::io::ErrorKind::IsADirectory {
                DataError::invalid_write(target, e.to_string())
            } else {
                DataError::io(
                    target,
                    "creating a temporary file in the target directory",
                    e,
                )
            }
        })?;
        Ok((
            Self {
                temp,
                target: target.to_path_buf(),
            },
            file,
        ))
    }

    /// fsync `file` (the temporary file, fully written), rename it over the target and fsync
    /// the directory (best effort), by [`Temporary::commit_file`].
    pub fn commit(self, file: File) -> Result<(), DataError> {
        self.temp.commit_file(file, &self.target).map_err(|e| {
            DataError::io(
                &self.target,
                "syncing the temporary file and renaming it into place",
                e,
            )
        })
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
#[cfg(feature = "polars")]
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
