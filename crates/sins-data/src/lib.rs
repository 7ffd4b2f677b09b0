#![doc = include_str!("../README.md")]
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
