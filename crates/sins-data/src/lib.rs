//! Dataset schema and streaming Parquet/CSV I/O for sinsbench.
//!
//! A dataset is one row per IMU sample:
//!
//! | column | type | unit | presence |
//! |---|---|---|---|
//! | `t_s` | Float64 | s | required, strictly increasing by 1/rate |
//! | `dtheta_{x,y,z}_rad` | Float64 | rad | required |
//! | `dv_{x,y,z}_mps` | Float64 | m/s | required |
//! | `temp_a{x,y,z}_degc` | Float64 | degC | optional, all three or none |
//! | `segment` | String | – | optional label per row |
//! | `ref_lat_rad`, `ref_lon_rad`, `ref_height_m`, `ref_vel_{n,e,d}_mps`, `ref_{pitch,roll,yaw}_rad` | Float64 | rad, m, m/s | optional, all nine or none |
//!
//! File-level metadata (Parquet key/value metadata, or leading `# key = value` lines in CSV):
//! `sinsbench.schema_version` (`1`), `sinsbench.sample_rate_hz`, `sinsbench.site_latitude_deg`,
//! `sinsbench.site_longitude_deg`, `sinsbench.site_height_m`, `sinsbench.description`; any other
//! `sinsbench.<name>` key is kept in [`DatasetMeta::extra`] under `<name>`.
//!
//! Writing ([`DatasetWriter`]) and reading ([`DatasetReader`]) stream in bounded batches and
//! validate every row (finite values, `t_s` strictly increasing with steps of 1/rate within 1 %);
//! every [`DataError`] names the file and, where it applies, the row, line, column or key.
//!
//! Parquet layout, chosen by measurement on this project's 2-core VM with a synthetic
//! 15 h / 200 Hz dataset (10.8 M rows, 10 Float64 columns = 864 MB raw; `examples/throughput.rs`):
//! LZ4 (raw) pages, row groups of 2^16 rows (= one reader batch; throughput is flat from 2^15 to
//! 2^18 rows, memory grows with it), plain encoding for floats, a dictionary for `segment`, no
//! min/max statistics. Noisy IMU floats barely compress (LZ4 0.95,
//! zstd-1 0.83 of raw) but constant-ish columns do (with the reference group, LZ4 halves the
//! file); LZ4 decodes almost as fast as uncompressed (read ~0.35-0.5 s for the whole file)
//! while zstd-1 takes ~1.5 s to read and ~2x the CPU to write. Writing costs ~0.6 s of CPU on the
//! encoder thread (concurrent with the producer) plus the kernel's page-cache copy and the final
//! fsync (an early-sync thread keeps the latter at ~0.2-0.3 s). Peak RSS: ~40 MB writing, ~25 MB
//! reading. Use [`DatasetReader::next_batch_into`] (or [`DatasetReader::recycle`]) in replay
//! loops to reuse batch buffers.

#![warn(missing_docs)]

mod atomic;
mod csv_read;
mod csv_write;
mod early_sync;
mod error;
mod layout;
mod meta;
mod pq_batch;
mod pq_decode;
mod pq_footer;
mod pq_read;
mod pq_write;
mod reader;
mod schema;
mod validate;
mod writer;

pub use atomic::{atomic_write, write_parquet_df_atomic};
pub use error::{DataError, RowRef};
pub use meta::{
    DatasetMeta, KEY_DESCRIPTION, KEY_PREFIX, KEY_SAMPLE_RATE_HZ, KEY_SCHEMA_VERSION,
    KEY_SITE_HEIGHT_M, KEY_SITE_LATITUDE_DEG, KEY_SITE_LONGITUDE_DEG, SCHEMA_VERSION,
};
pub use pq_read::MAX_BATCH_ROWS;
pub use pq_write::{Compression, DEFAULT_COMPRESSION, DEFAULT_ROW_GROUP_ROWS, ParquetWriteOptions};
pub use reader::{DatasetReader, read_all};
pub use schema::{
    COL_T_S, ColumnSet, DatasetFormat, DatasetInfo, MAX_SEGMENT_LABELS, REFERENCE_COLUMNS,
    REQUIRED_COLUMNS, ReferenceRow, SEGMENT_COLUMN, SampleBatch, TEMPERATURE_COLUMNS, WriteSummary,
};
pub use validate::STEP_TOLERANCE_FRACTION;
pub use writer::DatasetWriter;
