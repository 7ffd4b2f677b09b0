//! Column names and the in-memory record types of the dataset format.

use std::path::{Path, PathBuf};

use sins_imu::ImuSample;

use crate::error::DataError;
use crate::meta::DatasetMeta;

/// Largest batch returned by readers (rows). Parquet files written by this crate with the
/// default options have smaller row groups, so a batch is exactly one row group; larger row
/// groups (files from elsewhere) are split.
pub const MAX_BATCH_ROWS: usize = 1 << 17;

/// Sample time at the end of the sample interval (s). Required.
pub const COL_T_S: &str = "t_s";
/// Required columns, in file order: time (s), angular increments (rad), velocity increments (m/s).
pub const REQUIRED_COLUMNS: [&str; 7] = [
    COL_T_S,
    "dtheta_x_rad",
    "dtheta_y_rad",
    "dtheta_z_rad",
    "dv_x_mps",
    "dv_y_mps",
    "dv_z_mps",
];
/// Optional all-or-nothing group: accelerometer thermometer readings x, y, z (degC).
pub const TEMPERATURE_COLUMNS: [&str; 3] = ["temp_ax_degc", "temp_ay_degc", "temp_az_degc"];
/// Optional string column with a segment label per row ("alignment", "pattern1", ...).
pub const SEGMENT_COLUMN: &str = "segment";
/// Optional all-or-nothing group: the truth state at the sample time, in [`ReferenceRow`] order.
pub const REFERENCE_COLUMNS: [&str; 9] = [
    "ref_lat_rad",
    "ref_lon_rad",
    "ref_height_m",
    "ref_vel_n_mps",
    "ref_vel_e_mps",
    "ref_vel_d_mps",
    "ref_pitch_rad",
    "ref_roll_rad",
    "ref_yaw_rad",
];

/// Maximum number of distinct segment labels (a segment index is a `u16`).
pub const MAX_SEGMENT_LABELS: usize = u16::MAX as usize + 1;

/// Which optional column groups a dataset has.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ColumnSet {
    /// The three `temp_a?_degc` columns (degC) are present.
    pub temperature: bool,
    /// The `segment` label column is present.
    pub segment: bool,
    /// The nine `ref_*` truth columns are present.
    pub reference: bool,
}

impl ColumnSet {
    /// Only the required columns.
    pub const REQUIRED_ONLY: Self = Self {
        temperature: false,
        segment: false,
        reference: false,
    };
    /// Every optional group.
    pub const ALL: Self = Self {
        temperature: true,
        segment: true,
        reference: true,
    };

    /// Names of the Float64 columns of this set, in file order (the `segment` column, a string,
    /// is not included).
    pub fn float_columns(&self) -> Vec<&'static str> {
        let mut out: Vec<&'static str> = REQUIRED_COLUMNS.to_vec();
        if self.temperature {
            out.extend(TEMPERATURE_COLUMNS);
        }
        if self.reference {
            out.extend(REFERENCE_COLUMNS);
        }
        out
    }

    /// Names of all columns of this set, in file order.
    pub fn all_columns(&self) -> Vec<&'static str> {
        let mut out: Vec<&'static str> = REQUIRED_COLUMNS.to_vec();
        if self.temperature {
            out.extend(TEMPERATURE_COLUMNS);
        }
        if self.segment {
            out.push(SEGMENT_COLUMN);
        }
        if self.reference {
            out.extend(REFERENCE_COLUMNS);
        }
        out
    }
}

/// Truth state at a sample time: position (rad, rad, m), NED velocity (m/s) and Euler angles
/// (rad, in the project's pitch/roll/yaw convention).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReferenceRow {
    /// Geodetic latitude (rad).
    pub lat_rad: f64,
    /// Longitude (rad).
    pub lon_rad: f64,
    /// Height above the ellipsoid (m).
    pub height_m: f64,
    /// North velocity (m/s).
    pub vel_n_mps: f64,
    /// East velocity (m/s).
    pub vel_e_mps: f64,
    /// Down velocity (m/s).
    pub vel_d_mps: f64,
    /// Pitch (rad).
    pub pitch_rad: f64,
    /// Roll (rad).
    pub roll_rad: f64,
    /// Yaw (rad).
    pub yaw_rad: f64,
}

impl ReferenceRow {
    /// The nine values in [`REFERENCE_COLUMNS`] order.
    pub fn to_array(&self) -> [f64; 9] {
        [
            self.lat_rad,
            self.lon_rad,
            self.height_m,
            self.vel_n_mps,
            self.vel_e_mps,
            self.vel_d_mps,
            self.pitch_rad,
            self.roll_rad,
            self.yaw_rad,
        ]
    }

    /// Build from nine values in [`REFERENCE_COLUMNS`] order.
    pub fn from_array(v: [f64; 9]) -> Self {
        let [
            lat_rad,
            lon_rad,
            height_m,
            vel_n_mps,
            vel_e_mps,
            vel_d_mps,
            pitch_rad,
            roll_rad,
            yaw_rad,
        ] = v;
        Self {
            lat_rad,
            lon_rad,
            height_m,
            vel_n_mps,
            vel_e_mps,
            vel_d_mps,
            pitch_rad,
            roll_rad,
            yaw_rad,
        }
    }
}

/// A run of consecutive dataset rows. Readers return these in file order; writers accept them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleBatch {
    /// 0-based dataset row index of `samples[0]` (set by readers, ignored by writers).
    pub first_row: u64,
    /// The IMU samples. Temperatures are NaN when the dataset has no temperature columns.
    pub samples: Vec<ImuSample>,
    /// Per-row index into the dataset's segment labels, when the `segment` column is present.
    pub segment_index: Option<Vec<u16>>,
    /// Per-row truth state, when the reference columns are present.
    pub reference: Option<Vec<ReferenceRow>>,
}

impl SampleBatch {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// True when the batch has no rows.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }
}

/// On-disk format of a dataset.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DatasetFormat {
    /// Apache Parquet (the normal format).
    Parquet,
    /// Comma-separated text with `# key = value` metadata comment lines.
    Csv,
}

impl DatasetFormat {
    /// Format selected by a file extension (`.parquet` or `.csv`, case-insensitive).
    pub fn from_extension(path: &Path) -> Result<Self, DataError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("parquet") => Ok(Self::Parquet),
            Some("csv") => Ok(Self::Csv),
            _ => Err(DataError::UnsupportedExtension {
                file: path.to_path_buf(),
            }),
        }
    }
}

/// What a reader learned about a dataset when opening it.
#[derive(Clone, Debug, PartialEq)]
pub struct DatasetInfo {
    /// The dataset file.
    pub path: PathBuf,
    /// Its format.
    pub format: DatasetFormat,
    /// File-level metadata.
    pub meta: DatasetMeta,
    /// Optional column groups present.
    pub columns: ColumnSet,
    /// Same as `columns.temperature`: when false, `ImuSample::temp_degc` is NaN.
    pub has_temperature: bool,
    /// Number of data rows.
    pub n_rows: u64,
    /// Segment labels; `SampleBatch::segment_index` indexes into this (empty without a segment
    /// column). Parquet files written by this crate return exactly the writer's labels; files
    /// from elsewhere (and CSV) list the distinct values in order of first appearance.
    pub segment_labels: Vec<String>,
    /// Columns present in the file that are not part of the format (ignored).
    pub ignored_columns: Vec<String>,
}

/// Result of a successful [`crate::DatasetWriter::finish`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WriteSummary {
    /// The file written.
    pub path: PathBuf,
    /// Its format.
    pub format: DatasetFormat,
    /// Number of data rows written.
    pub n_rows: u64,
    /// File size (bytes).
    pub n_bytes: u64,
}
