//! File-level metadata: the `sinsbench.*` key/value pairs of a dataset.

use std::collections::BTreeMap;
use std::path::Path;

use sins_nav::Geodetic;

use crate::error::DataError;

/// The dataset schema version this build reads and writes.
pub const SCHEMA_VERSION: u32 = 1;
/// Prefix of every metadata key of the format.
pub const KEY_PREFIX: &str = "sinsbench.";
/// Metadata key: schema version (integer, `"1"`).
pub const KEY_SCHEMA_VERSION: &str = "sinsbench.schema_version";
/// Metadata key: sample rate (Hz).
pub const KEY_SAMPLE_RATE_HZ: &str = "sinsbench.sample_rate_hz";
/// Metadata key: site geodetic latitude (deg).
pub const KEY_SITE_LATITUDE_DEG: &str = "sinsbench.site_latitude_deg";
/// Metadata key: site longitude (deg).
pub const KEY_SITE_LONGITUDE_DEG: &str = "sinsbench.site_longitude_deg";
/// Metadata key: site height above the ellipsoid (m).
pub const KEY_SITE_HEIGHT_M: &str = "sinsbench.site_height_m";
/// Metadata key: free-text description (optional; empty when absent).
pub const KEY_DESCRIPTION: &str = "sinsbench.description";
/// Extra metadata name (without the prefix) of the time base: `nominal` (t = t0 + k / rate,
/// the default when absent) or `recorded` (the recorder's stamps, which may jitter).
pub const EXTRA_TIME_BASE: &str = "time_base";

const STANDARD_KEYS: [&str; 6] = [
    KEY_SCHEMA_VERSION,
    KEY_SAMPLE_RATE_HZ,
    KEY_SITE_LATITUDE_DEG,
    KEY_SITE_LONGITUDE_DEG,
    KEY_SITE_HEIGHT_M,
    KEY_DESCRIPTION,
];

/// File-level metadata of a dataset.
#[derive(Clone, Debug, PartialEq)]
pub struct DatasetMeta {
    /// Schema version (always [`SCHEMA_VERSION`] for files this build reads or writes).
    pub schema_version: u32,
    /// Nominal sample rate (Hz); consecutive `t_s` differ by 1/rate.
    pub sample_rate_hz: f64,
    /// Site of the (stationary part of the) experiment; stored in the file in degrees and metres.
    pub site: Geodetic,
    /// Free-text description.
    pub description: String,
    /// Further `sinsbench.<name>` keys, stored here as `<name>` (prefix stripped), e.g.
    /// `"experiment"`, `"seed"`, `"run"`. Names use only ASCII letters, digits, `_`, `-`, `.`.
    pub extra: BTreeMap<String, String>,
}

impl DatasetMeta {
    /// Metadata with the current schema version and no extra keys.
    pub fn new(sample_rate_hz: f64, site: Geodetic, description: impl Into<String>) -> Self {
        Self {
            schema_version: SCHEMA_VERSION,
            sample_rate_hz,
            site,
            description: description.into(),
            extra: BTreeMap::new(),
        }
    }

    /// True when `t_s` holds recorded stamps (`sinsbench.time_base = recorded`): navigation
    /// then integrates over each sample's own interval.
    pub fn recorded_stamps(&self) -> bool {
        self.extra
            .get(EXTRA_TIME_BASE)
            .is_some_and(|v| v == "recorded")
    }

    /// The nominal sample interval 1/rate (s).
    pub fn sample_interval_s(&self) -> f64 {
        1.0 / self.sample_rate_hz
    }

    /// Check the metadata can be written (finite positive rate, finite site, valid extra names).
    pub(crate) fn validate_for_write(&self, file: &Path) -> Result<(), DataError> {
        let bad = |reason: String| Err(DataError::invalid_write(file, reason));
        if self.schema_version != SCHEMA_VERSION {
            return bad(format!(
                "schema_version {} cannot be written (this build writes {SCHEMA_VERSION})",
                self.schema_version
            ));
        }
        if !(self.sample_rate_hz.is_finite() && self.sample_rate_hz > 0.0) {
            return bad(format!(
                "sample_rate_hz = {} must be finite and positive",
                self.sample_rate_hz
            ));
        }
        let s = &self.site;
        if !(s.lat_rad.is_finite() && s.lon_rad.is_finite() && s.height_m.is_finite()) {
            return bad(format!("site {s:?} must be finite"));
        }
        for name in self.extra.keys() {
            let full = format!("{KEY_PREFIX}{name}");
            let name_ok = !name.is_empty()
                && name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
            if !name_ok || name.starts_with(KEY_PREFIX) || STANDARD_KEYS.contains(&full.as_str()) {
                return bad(format!(
                    "extra metadata name {name:?} is invalid (give it without the \
                     '{KEY_PREFIX}' prefix, use only ASCII letters, digits, '_', '-', '.', \
                     and do not repeat a standard key)"
                ));
            }
        }
        Ok(())
    }

    /// The key/value pairs stored in the file, standard keys first, then `extra` in key order.
    pub fn to_key_values(&self) -> Vec<(String, String)> {
        let mut kv = vec![
            (
                KEY_SCHEMA_VERSION.to_string(),
                self.schema_version.to_string(),
            ),
            (
                KEY_SAMPLE_RATE_HZ.to_string(),
                self.sample_rate_hz.to_string(),
            ),
            (
                KEY_SITE_LATITUDE_DEG.to_string(),
                deg_for_exact_rad(self.site.lat_rad).to_string(),
            ),
            (
                KEY_SITE_LONGITUDE_DEG.to_string(),
                deg_for_exact_rad(self.site.lon_rad).to_string(),
            ),
            (
                KEY_SITE_HEIGHT_M.to_string(),
                self.site.height_m.to_string(),
            ),
            (KEY_DESCRIPTION.to_string(), self.description.clone()),
        ];
        kv.extend(
            self.extra
                .iter()
                .map(|(k, v)| (format!("{KEY_PREFIX}{k}"), v.clone())),
        );
        kv
    }

    /// Parse the metadata from a file's key/value pairs (keys without the `sinsbench.` prefix
    /// are ignored). The schema version is checked first.
    pub(crate) fn from_key_values<'a>(
        file: &Path,
        pairs: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, DataError> {
        let mut map: BTreeMap<&str, &str> = BTreeMap::new();
        for (k, v) in pairs {
            if !k.starts_with(KEY_PREFIX) {
                continue;
            }
            if map.insert(k, v).is_some() {
                return Err(invalid(file, k, v, "the key appears more than once"));
            }
        }
        let get = |key: &str| {
            map.get(key)
                .copied()
                .ok_or_else(|| DataError::MissingMetadata {
                    file: file.to_path_buf(),
                    key: key.to_string(),
                })
        };
        let version_text = get(KEY_SCHEMA_VERSION)?;
        let schema_version: u32 = version_text
            .trim()
            .parse()
            .map_err(|_| invalid(file, KEY_SCHEMA_VERSION, version_text, "not an integer"))?;
        if schema_version != SCHEMA_VERSION {
            return Err(DataError::UnsupportedSchemaVersion {
                file: file.to_path_buf(),
                found: schema_version,
                supported: SCHEMA_VERSION,
            });
        }
        let num = |key: &str, lo: f64, hi: f64, what: &str| -> Result<f64, DataError> {
            let text = get(key)?;
            let x: f64 = text
                .trim()
                .parse()
                .map_err(|_| invalid(file, key, text, "not a number"))?;
            if !(x.is_finite() && lo <= x && x <= hi) {
                return Err(invalid(file, key, text, what));
            }
            Ok(x)
        };
        let sample_rate_hz = num(
            KEY_SAMPLE_RATE_HZ,
            f64::MIN_POSITIVE,
            f64::MAX,
            "must be finite and positive",
        )?;
        let lat_deg = num(KEY_SITE_LATITUDE_DEG, -90.0, 90.0, "must be in [-90, 90]")?;
        let lon_deg = num(
            KEY_SITE_LONGITUDE_DEG,
            -360.0,
            360.0,
            "must be in [-360, 360]",
        )?;
        let height_m = num(KEY_SITE_HEIGHT_M, f64::MIN, f64::MAX, "must be finite")?;
        let description = map.get(KEY_DESCRIPTION).copied().unwrap_or("").to_string();
        let extra = map
            .iter()
            .filter(|(k, _)| !STANDARD_KEYS.contains(k))
            .map(|(k, v)| (k[KEY_PREFIX.len()..].to_string(), v.to_string()))
            .collect();
        let extra: BTreeMap<String, String> = extra;
        if let Some(v) = extra.get(EXTRA_TIME_BASE)
            && v != "nominal"
            && v != "recorded"
        {
            let key = format!("{KEY_PREFIX}{EXTRA_TIME_BASE}");
            return Err(invalid(file, &key, v, "must be 'nominal' or 'recorded'"));
        }
        Ok(Self {
            schema_version,
            sample_rate_hz,
            site: Geodetic::from_deg(lat_deg, lon_deg, height_m),
            description,
            extra,
        })
    }
}

fn invalid(file: &Path, key: &str, value: &str, reason: &str) -> DataError {
    DataError::InvalidMetadata {
        file: file.to_path_buf(),
        key: key.to_string(),
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

/// A value in degrees whose `to_radians()` is exactly `rad` when one exists within a few ulps of
/// `rad.to_degrees()` (so the site survives the degree round trip of the file bit-exactly).
fn deg_for_exact_rad(rad: f64) -> f64 {
    let d0 = rad.to_degrees();
    if d0.to_radians() == rad {
        return d0;
    }
    let (mut up, mut down) = (d0, d0);
    for _ in 0..8 {
        up = up.next_up();
        down = down.next_down();
        if up.to_radians() == rad {
            return up;
        }
        if down.to_radians() == rad {
            return down;
        }
    }
    d0
}
