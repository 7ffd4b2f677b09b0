//! Dataset schema and streaming Parquet/CSV I/O for sinsbench.
//!
//! A dataset is one row per IMU sample:
//!
//! | column | type | unit | presence |
//! |---|---|---|---|
//! | `t_s` | Float64 | s | required, strictly increasing by 1/rate (recorded stamps may jitter) |
//! | `dtheta_{x,y,z}_rad` | Float64 | rad | required |
//! | `dv_{x,y,z}_mps` | Float64 | m/s | required |
//! | `temp_a{x,y,z}_degc` | Float64 | degC | optional, all three or none |
//! | `segment` | String | – | optional label per row |
//! | `ref_lat_rad`, `ref_lon_rad`, `ref_height_m`, `ref_vel_{n,e,d}_mps`, `ref_{pitch,roll,yaw}_rad` | Float64 | rad, m, m/s | optional, all nine or none |
//!
//! File-level metadata (Parquet key/value metadata, or leading `# key = value` lines in CSV):
//! `sinsbench.schema_version` (`1`), `sinsbench.sample_rate_hz`, `sinsbench.site_latitude_deg`,
//! `sinsbench.site_longitude_deg`, `sinsbench.site_height_m`, `sinsbench.description` (optional,
//! empty when absent), `sinsbench.time_base` (optional: `nominal` or `recorded`); any other
//! `sinsbench.<name>` key is kept in [`DatasetMeta::extra`] under `<name>`.
//!
//! Writing ([`DatasetWriter`]) and reading ([`DatasetReader`]) stream in bounded batches and
//! validate every row (finite values, `t_s` strictly increasing with steps of 1/rate within
//! 45 % and a mean step within 1 % of 1/rate);
//! every [`DataError`] names the file and, where it applies, the row, line, column or key.
//!
//! Parquet files are read and written with the Apache Arrow `parquet` crate's file API (no
//! Arrow arrays in between). The writer ([`DatasetWriter`]) encodes and compresses one row group
//! at a time on a background thread with `SerializedFileWriter`; the `segment` column chunk is
//! encoded by this crate, so that its dictionary page holds the writer's exact label list. The
//! reader ([`DatasetReader`]) checks the footer's Thrift encoding before `parquet` parses it and
//! every page header before its column reader decodes the page, then decodes row group by row
//! group, only the columns it needs, on a background thread one batch ahead of the consumer:
//! memory stays at a few row groups whatever the file size, and a damaged file is a
//! [`DataError`], never a panic. Files written by the earlier polars-parquet based writer read
//! as before, and polars reads the files written now.
//!
//! Parquet layout, chosen by measurement on this project's 2-core VM with a synthetic
//! 15 h / 200 Hz dataset (10.8 M rows, 10 Float64 columns = 864 MB raw; `examples/throughput.rs`):
//! LZ4 (raw) pages, row groups of 2^16 rows (= one reader batch; throughput is flat from 2^15 to
//! 2^18 rows, memory grows with it), plain encoding for floats (one data page per column chunk),
//! a dictionary for `segment` (uncompressed pages: a few bytes per row group), no statistics and
//! no page index. Noisy IMU floats barely compress (LZ4 0.95, zstd-1 0.83 of raw) but
//! constant-ish columns do (with the reference group, LZ4 halves the file); LZ4 decodes as fast
//! as uncompressed while zstd-1 takes ~2.5x as long to read and ~2x the time to write. Measured
//! with the file in the page cache (VM shared with other work): writing ~1.0 s besides
//! generating the data (the early-sync thread keeps the final fsync at a few 10 ms), reading
//! 0.35-0.42 s; the earlier polars-parquet based reader took 0.30-0.35 s, the difference being
//! the `parquet` crate's LZ4 decoder (`lz4_flex`) and the buffers it zero-fills. Nearly constant
//! columns (the reference group) decode slowly there, `lz4_flex` copying their long repeats byte
//! by byte: with the segment and reference columns the 15 h file reads in ~1.3 s (before:
//! ~0.65 s). Peak RSS: ~33 MB writing, ~36 MB reading. Use [`DatasetReader::next_batch_into`]
//! (or [`DatasetReader::recycle`]) in replay loops to reuse batch buffers.

#![warn(missing_docs)]

mod atomic;
mod csv_read;
mod csv_write;
mod early_sync;
mod error;
mod layout;
mod meta;
mod pq_batch;
mod pq_column;
mod pq_dict;
mod pq_footer;
mod pq_pages;
mod pq_read;
mod pq_segment;
mod pq_write;
mod reader;
mod schema;
mod validate;
mod writer;

pub use atomic::atomic_write;
#[cfg(feature = "polars")]
pub use atomic::write_parquet_df_atomic;
pub use error::{DataError, RowRef};
pub use meta::{
    DatasetMeta, EXTRA_TIME_BASE, KEY_DESCRIPTION, KEY_PREFIX, KEY_SAMPLE_RATE_HZ,
    KEY_SCHEMA_VERSION, KEY_SITE_HEIGHT_M, KEY_SITE_LATITUDE_DEG, KEY_SITE_LONGITUDE_DEG,
    SCHEMA_VERSION,
};
pub use pq_write::{Compression, DEFAULT_COMPRESSION, DEFAULT_ROW_GROUP_ROWS, ParquetWriteOptions};
pub use reader::{DatasetReader, read_all};
pub use schema::{
    COL_T_S, ColumnSet, DatasetFormat, DatasetInfo, MAX_BATCH_ROWS, MAX_SEGMENT_LABELS,
    REFERENCE_COLUMNS, REQUIRED_COLUMNS, ReferenceRow, SEGMENT_COLUMN, SampleBatch,
    TEMPERATURE_COLUMNS, WriteSummary,
};
pub use validate::{MEAN_STEP_TOLERANCE_FRACTION, STEP_TOLERANCE_FRACTION};
pub use writer::DatasetWriter;
