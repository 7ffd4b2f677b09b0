//! The PSINS compact `.imu` text format: `%` comment lines, then three header lines
//! (1: pitch, roll, yaw [deg, yaw counter-clockwise from north] and VE, VN, VU [m/s];
//! 2: latitude, longitude [deg], height [m], t0 [s], sampling interval [ms], g [m/s^2];
//! 3: gyro scale [arcsec per count] x3, accelerometer scale [ug*s per count] x3, ug being
//! 1e-6 times the header's g), then six integer counts per line: angular increments x, y, z
//! and velocity increments x, y, z, in the body frame x right, y forward, z up.

use std::io::BufRead;
use std::path::Path;

use crate::description::{Channels, ColumnRef, Description, Quantity, Rule, Site};
use crate::error::{ImportError, SourcePos};
use crate::source::{Source, open_maybe_gzip};

/// The PSINS header.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PsinsHeader {
    /// Initial pitch, roll, yaw (deg; PSINS and sinsbench share the convention).
    pub attitude_deg: [f64; 3],
    /// Initial velocity east, north, up (m/s).
    pub vel_enu_mps: [f64; 3],
    /// Latitude, longitude (deg), height (m).
    pub site: [f64; 3],
    /// Time of the start (s).
    pub t0_s: f64,
    /// Sampling interval (ms).
    pub interval_ms: f64,
    /// The g of the accelerometer scale (m/s^2).
    pub g_mps2: f64,
    /// Gyro scales (arcsec per count).
    pub gyro_arcsec: [f64; 3],
    /// Accelerometer scales (ug*s per count).
    pub accel_ug_s: [f64; 3],
}

/// Read the header, and return it with a source positioned at the first sample line and the
/// description the import applies (columns 0-5, counts with the header's scales, no time
/// column, the header's rate, site and start).
pub fn open(
    file: &Path,
    user: &Description,
) -> Result<(PsinsHeader, Source, Description), ImportError> {
    let mut reader = open_maybe_gzip(file)?;
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut line = String::new();
    let mut lines = 0u64;
    while rows.len() < 3 {
        line.clear();
        lines += 1;
        let n = reader.read_line(&mut line).map_err(|e| ImportError::Io {
            file: file.to_path_buf(),
            action: "reading the PSINS header",
            source: e,
        })?;
        let at = SourcePos {
            record: 0,
            line: Some(lines),
            byte: None,
        };
        if n == 0 {
            return Err(ImportError::Record {
                file: file.to_path_buf(),
                at,
                reason: format!(
                    "the file ends after {} of the 3 PSINS header lines (not a PSINS .imu file?)",
                    rows.len()
                ),
            });
        }
        let t = line.trim();
        if t.is_empty() || t.starts_with('%') {
            continue;
        }
        let nums: Result<Vec<f64>, _> = t.split_ascii_whitespace().map(str::parse::<f64>).collect();
        let want = 6;
        match nums {
            Ok(v) if v.len() == want && v.iter().all(|x| x.is_finite()) => rows.push(v),
            _ => {
                return Err(ImportError::Record {
                    file: file.to_path_buf(),
                    at,
                    reason: format!(
                        "PSINS header line {} must hold {want} finite numbers, found '{t}'",
                        rows.len() + 1
                    ),
                });
            }
        }
    }
    let h = PsinsHeader {
        attitude_deg: [rows[0][0], rows[0][1], rows[0][2]],
        vel_enu_mps: [rows[0][3], rows[0][4], rows[0][5]],
        site: [rows[1][0], rows[1][1], rows[1][2]],
        t0_s: rows[1][3],
        interval_ms: rows[1][4],
        g_mps2: rows[1][5],
        gyro_arcsec: [rows[2][0], rows[2][1], rows[2][2]],
        accel_ug_s: [rows[2][3], rows[2][4], rows[2][5]],
    };
    if !(h.interval_ms > 0.0) {
        return Err(ImportError::desc(
            file,
            "PSINS header line 2, sampling interval (ms)",
            format!("{} is not a positive interval", h.interval_ms),
        ));
    }
    let desc = effective(&h, user);
    Ok((h, Source::whitespace_after(file, reader, lines), desc))
}

/// The description applied to a PSINS file: the header's values, then what the user's
/// description adds (site, segments, metadata, axes, time rules override the header).
fn effective(h: &PsinsHeader, user: &Description) -> Description {
    let counts = |cols: [usize; 3], unit: &str, scale: [f64; 3], g: Option<f64>| Channels {
        columns: cols.map(ColumnRef::Index),
        quantity: Quantity::Increment,
        unit: "counts".to_string(),
        count_scale: Some(scale),
        count_unit: Some(unit.to_string()),
        rule: Rule::Trapezoid,
        g_mps2: g,
    };
    let mut d = user.clone();
    d.gyro = Some(counts([0, 1, 2], "arcsec", h.gyro_arcsec, None));
    d.accel = Some(counts([3, 4, 5], "ug*s", h.accel_ug_s, Some(h.g_mps2)));
    d.time.column = None;
    d.time.counter = None;
    d.time.rate_hz = Some(1000.0 / h.interval_ms);
    d.time.stamps = crate::description::Stamps::Nominal;
    d.time.start_s = h.t0_s;
    d.site = user.site.or(Some(Site {
        latitude_deg: h.site[0],
        longitude_deg: h.site[1],
        height_m: h.site[2],
    }));
    let names = ["initial_pitch_deg", "initial_roll_deg", "initial_yaw_deg"];
    for (k, name) in names.iter().enumerate() {
        d.metadata
            .entry(name.to_string())
            .or_insert(toml::Value::Float(h.attitude_deg[k]));
    }
    let v = [
        "initial_vel_e_mps",
        "initial_vel_n_mps",
        "initial_vel_u_mps",
    ];
    for (k, name) in v.iter().enumerate() {
        d.metadata
            .entry(name.to_string())
            .or_insert(toml::Value::Float(h.vel_enu_mps[k]));
    }
    d
}
