//! The description file (TOML) that says how to read a recording: its layout, its time base,
//! the unit and kind of each channel, the body axes, temperatures, site, labels and metadata.
//!
//! Every table and key is documented in `docs/import.md`; `examples/` in that page shows the
//! descriptions of the public recordings the project was checked on.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::error::ImportError;

/// A whole description file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Description {
    /// Record layout: `"delimited"` (CSV, TSV, whitespace), `"binary"` (fixed records) or
    /// `"psins"` (the PSINS compact `.imu` text format, whose header gives period, site,
    /// attitude and count scales).
    pub format: Format,
    /// Free text stored as the dataset's `sinsbench.description` (optional).
    #[serde(default)]
    pub description: Option<String>,
    /// Delimited text settings (`format = "delimited"`).
    #[serde(default)]
    pub delimited: Option<Delimited>,
    /// Binary record settings (`format = "binary"`).
    #[serde(default)]
    pub binary: Option<Binary>,
    /// Time base: time stamp column, sample counter, nominal rate, gap rules.
    #[serde(default)]
    pub time: Time,
    /// Gyro channels (required except for PSINS files).
    #[serde(default)]
    pub gyro: Option<Channels>,
    /// Accelerometer channels (required except for PSINS files).
    #[serde(default)]
    pub accel: Option<Channels>,
    /// How the recording's sensor axes map to the paper's body frame (x right, y forward, z up).
    #[serde(default)]
    pub axes: Axes,
    /// Optional accelerometer thermometer columns.
    #[serde(default)]
    pub temperature: Option<Temperature>,
    /// The site (required unless the format's header gives it).
    #[serde(default)]
    pub site: Option<Site>,
    /// Segment labels by time (s, in the recording's own time base).
    #[serde(default)]
    pub segments: Vec<SegmentSpan>,
    /// Further metadata written as `sinsbench.<name>` keys (strings or numbers), for example
    /// `initial_yaw_deg` for `navigate --start truth`.
    #[serde(default)]
    pub metadata: BTreeMap<String, toml::Value>,
}

/// Record layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Format {
    /// Delimited text: one record per line.
    Delimited,
    /// Fixed-size binary records.
    Binary,
    /// PSINS compact text (`%` comments, three header lines, six integer counts per line).
    Psins,
}

/// Delimited text settings.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Delimited {
    /// `","`, `";"`, `"\t"` (or `"tab"`), or `"whitespace"` (any run of spaces and tabs).
    #[serde(default = "default_delimiter")]
    pub delimiter: String,
    /// The first record (after skipped and comment lines) names the columns.
    #[serde(default = "default_true")]
    pub header: bool,
    /// Lines starting with this character are skipped (optional).
    #[serde(default)]
    pub comment: Option<char>,
    /// Lines skipped at the start of the file, before the header.
    #[serde(default)]
    pub skip_lines: u64,
}

fn default_delimiter() -> String {
    ",".to_string()
}

fn default_true() -> bool {
    true
}

/// Fixed binary records.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Binary {
    /// Bytes skipped at the start of the file.
    #[serde(default)]
    pub header_bytes: u64,
    /// `"little"` (default) or `"big"`.
    #[serde(default)]
    pub byte_order: ByteOrder,
    /// The fields of one record, in order.
    pub fields: Vec<Field>,
}

/// Byte order of binary fields.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ByteOrder {
    /// Least significant byte first.
    #[default]
    Little,
    /// Most significant byte first.
    Big,
}

/// One field of a binary record.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Field {
    /// The name channels refer to.
    pub name: String,
    /// `f32`, `f64`, `i16`, `i32`, `u16`, `u32` or `pad<N>` (N bytes skipped).
    #[serde(rename = "type")]
    pub kind: String,
}

/// A column: by name (with a header or binary field names) or by 0-based index.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(untagged)]
pub enum ColumnRef {
    /// 0-based column index.
    Index(usize),
    /// Column or field name.
    Name(String),
}

impl std::fmt::Display for ColumnRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ColumnRef::Index(i) => write!(f, "column {i}"),
            ColumnRef::Name(n) => write!(f, "'{n}'"),
        }
    }
}

/// Time base.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Time {
    /// Time stamp column (optional).
    #[serde(default)]
    pub column: Option<ColumnRef>,
    /// Unit of the time stamps: `s` (default), `ms`, `us`, `ns`.
    #[serde(default = "default_time_unit")]
    pub unit: String,
    /// Sample counter column (integers, +1 per sample; optional). A jump of n + 1 means n
    /// dropped samples, whatever the time stamps say.
    #[serde(default)]
    pub counter: Option<ColumnRef>,
    /// The counter wraps at this value (e.g. 65536 for a 16-bit counter); optional.
    #[serde(default)]
    pub counter_modulo: Option<u64>,
    /// Nominal sample rate (Hz). Required without a time column; with one, the default is the
    /// median step of the first 1001 stamps.
    #[serde(default)]
    pub rate_hz: Option<f64>,
    /// Which time base the dataset carries: `nominal` (default: t = t0 + k / rate, the IMU's own
    /// clock; stamp jitter is only reported) or `recorded` (the stamps themselves; rates are
    /// integrated over the stamped intervals and navigation uses each sample's interval).
    #[serde(default)]
    pub stamps: Stamps,
    /// Gaps of up to this many missing samples are bridged (default 5).
    #[serde(default = "default_bridge")]
    pub max_bridge_samples: u64,
    /// A longer gap: `refuse` (default) or `split` (the data after it go to a further file).
    #[serde(default)]
    pub on_gap: OnGap,
    /// Start time (s) of the first sample's interval when there is no time column (default 0).
    #[serde(default)]
    pub start_s: f64,
}

impl Default for Time {
    fn default() -> Self {
        Self {
            column: None,
            unit: default_time_unit(),
            counter: None,
            counter_modulo: None,
            rate_hz: None,
            stamps: Stamps::default(),
            max_bridge_samples: default_bridge(),
            on_gap: OnGap::default(),
            start_s: 0.0,
        }
    }
}

fn default_time_unit() -> String {
    "s".to_string()
}

/// Default bridge limit (samples): a few dropped USB/serial packets, never a real outage.
pub const DEFAULT_MAX_BRIDGE_SAMPLES: u64 = 5;

fn default_bridge() -> u64 {
    DEFAULT_MAX_BRIDGE_SAMPLES
}

/// Which time base the dataset carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stamps {
    /// t = t0 + k / rate (the IMU's own sample clock).
    #[default]
    Nominal,
    /// The recorded stamps.
    Recorded,
}

/// What a gap longer than the bridge limit does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OnGap {
    /// Refuse the recording, naming the gap.
    #[default]
    Refuse,
    /// Start a further output file after the gap.
    Split,
}

/// Three channels of one sensor triad.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Channels {
    /// Columns of the sensor's x, y, z axes (sensor frame, before `[axes]`).
    pub columns: [ColumnRef; 3],
    /// `rate` (angular rate, specific force) or `increment` (angle, velocity increments).
    pub quantity: Quantity,
    /// Unit. Gyro rates: `rad/s`, `deg/s`, `deg/h`, `arcsec/s`; gyro increments: `rad`, `deg`,
    /// `arcsec`; accelerometer rates: `m/s^2`, `g`, `mg`, `ug`; accelerometer increments:
    /// `m/s`, `g*s`, `mg*s`, `ug*s`; or `counts` with `count_scale` and `count_unit`.
    pub unit: String,
    /// With `unit = "counts"`: one count is this many `count_unit`.
    #[serde(default)]
    pub count_scale: Option<[f64; 3]>,
    /// With `unit = "counts"`: the unit of `count_scale`.
    #[serde(default)]
    pub count_unit: Option<String>,
    /// Rates only: how a rate becomes an increment: `trapezoid` (default) or `hold`.
    #[serde(default)]
    pub rule: Rule,
    /// The g behind `g`, `mg`, `ug` units (m/s^2; default 9.80665).
    #[serde(default)]
    pub g_mps2: Option<f64>,
}

/// Rate or increment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    /// Angular rate (gyro) or specific force (accelerometer).
    Rate,
    /// Angle or velocity increment over the sample interval.
    Increment,
}

/// How a sampled rate becomes the increment over the interval ending at its sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Rule {
    /// `(r[k-1] + r[k]) / 2 * dt`: exact for a rate linear over the interval; the first record
    /// only opens the first interval.
    #[default]
    Trapezoid,
    /// `r[k] * dt`: the output at k is the mean rate over the interval ending at k (a
    /// sample-and-hold or box-car averaged output, as some datasheets state).
    Hold,
}

/// Axes: a named convention, a signed permutation, or a rotation matrix.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axes {
    /// Named sensor convention: `rfu` (x right, y forward, z up: the paper's; default), `frd`
    /// (forward, right, down), `flu` (forward, left, up).
    #[serde(default)]
    pub convention: Option<String>,
    /// Signed sensor axis along body right, e.g. `"+y"`.
    #[serde(default)]
    pub right: Option<String>,
    /// Signed sensor axis along body forward.
    #[serde(default)]
    pub forward: Option<String>,
    /// Signed sensor axis along body up.
    #[serde(default)]
    pub up: Option<String>,
    /// Rotation `body_from_sensor` (rows: body right, forward, up), orthonormal.
    #[serde(default)]
    pub body_from_sensor: Option<[[f64; 3]; 3]>,
}

/// Temperature columns.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Temperature {
    /// One column (used for all three accelerometers) or three (x, y, z).
    pub columns: Vec<ColumnRef>,
    /// `degC` (default), `K` or `degF`.
    #[serde(default = "default_temp_unit")]
    pub unit: String,
}

fn default_temp_unit() -> String {
    "degC".to_string()
}

/// The site.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Site {
    /// Geodetic latitude (deg).
    pub latitude_deg: f64,
    /// Longitude (deg).
    pub longitude_deg: f64,
    /// Height above the ellipsoid (m).
    pub height_m: f64,
}

/// A labelled time span.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpan {
    /// The label (e.g. `"stationary"`, `"alignment"`).
    pub label: String,
    /// Start (s, inclusive).
    pub from_s: f64,
    /// End (s, exclusive).
    pub to_s: f64,
}

impl Description {
    /// Parse a description from TOML text; `file` names it in errors.
    pub fn from_toml(text: &str, file: &Path) -> Result<Self, ImportError> {
        toml::from_str(text).map_err(|e| ImportError::Description {
            file: file.to_path_buf(),
            key: e
                .span()
                .map(|s| format!("bytes {}..{}", s.start, s.end))
                .unwrap_or_default(),
            reason: e.message().to_string(),
        })
    }

    /// Read and parse a description file.
    pub fn load(file: &Path) -> Result<(Self, String), ImportError> {
        let text = std::fs::read_to_string(file).map_err(|e| ImportError::Io {
            file: file.to_path_buf(),
            action: "reading the description",
            source: e,
        })?;
        Ok((Self::from_toml(&text, file)?, text))
    }

    /// The built-in description of a PSINS `.imu` file (everything from its header).
    pub fn psins() -> Self {
        Self {
            format: Format::Psins,
            description: None,
            delimited: None,
            binary: None,
            time: Time::default(),
            gyro: None,
            accel: None,
            axes: Axes::default(),
            temperature: None,
            site: None,
            segments: Vec::new(),
            metadata: BTreeMap::new(),
        }
    }
}
