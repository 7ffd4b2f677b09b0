//! Unit factors to SI and the body-from-sensor rotation of the `[axes]` table.

use std::path::Path;

use sins_nav::{G0_MPS2, Mat3};

use crate::description::{Axes, Channels, Quantity};
use crate::error::ImportError;

/// One arcsecond (rad).
pub const ARCSEC_RAD: f64 = std::f64::consts::PI / (180.0 * 3600.0);

/// Which sensor a channel triad belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sensor {
    /// Gyros: angle (rad) or angular rate (rad/s).
    Gyro,
    /// Accelerometers: velocity increment (m/s) or specific force (m/s^2).
    Accel,
}

impl Sensor {
    fn key(self) -> &'static str {
        match self {
            Sensor::Gyro => "gyro",
            Sensor::Accel => "accel",
        }
    }
}

/// Factor from `unit` to SI for a sensor and quantity, or `None` when the unit does not fit.
fn unit_factor(sensor: Sensor, quantity: Quantity, unit: &str, g: f64) -> Option<f64> {
    let deg = std::f64::consts::PI / 180.0;
    let u = unit.trim();
    match (sensor, quantity) {
        (Sensor::Gyro, Quantity::Rate) => match u {
            "rad/s" => Some(1.0),
            "deg/s" => Some(deg),
            "deg/h" => Some(deg / 3600.0),
            "arcsec/s" => Some(ARCSEC_RAD),
            _ => None,
        },
        (Sensor::Gyro, Quantity::Increment) => match u {
            "rad" => Some(1.0),
            "deg" => Some(deg),
            "arcsec" => Some(ARCSEC_RAD),
            _ => None,
        },
        (Sensor::Accel, Quantity::Rate) => match u {
            "m/s^2" | "m/s2" => Some(1.0),
            "g" => Some(g),
            "mg" => Some(1e-3 * g),
            "ug" => Some(1e-6 * g),
            _ => None,
        },
        (Sensor::Accel, Quantity::Increment) => match u {
            "m/s" => Some(1.0),
            "g*s" => Some(g),
            "mg*s" => Some(1e-3 * g),
            "ug*s" => Some(1e-6 * g),
            _ => None,
        },
    }
}

fn units_list(sensor: Sensor, quantity: Quantity) -> &'static str {
    match (sensor, quantity) {
        (Sensor::Gyro, Quantity::Rate) => "rad/s, deg/s, deg/h, arcsec/s",
        (Sensor::Gyro, Quantity::Increment) => "rad, deg, arcsec",
        (Sensor::Accel, Quantity::Rate) => "m/s^2, g, mg, ug",
        (Sensor::Accel, Quantity::Increment) => "m/s, g*s, mg*s, ug*s",
    }
}

/// Per-axis factors from the file's numbers to SI (rad, rad/s, m/s, m/s^2) of a channel triad,
/// and a description of the conversion for the provenance record.
pub fn channel_factors(
    file: &Path,
    sensor: Sensor,
    ch: &Channels,
) -> Result<([f64; 3], String), ImportError> {
    let key = sensor.key();
    let g = ch.g_mps2.unwrap_or(G0_MPS2);
    if !(g.is_finite() && (9.7..=9.9).contains(&g)) {
        return Err(ImportError::desc(
            file,
            &format!("{key}.g_mps2"),
            format!("{g} is not a value of g on the Earth (9.7..9.9 m/s^2)"),
        ));
    }
    let bad_unit = |field: &str, unit: &str| {
        ImportError::desc(
            file,
            &format!("{key}.{field}"),
            format!(
                "'{unit}' is not a unit of a {key} {} (use {}, or counts with count_scale and \
                 count_unit)",
                quantity_word(ch.quantity),
                units_list(sensor, ch.quantity)
            ),
        )
    };
    if ch.unit.trim() == "counts" {
        let (Some(scale), Some(cu)) = (ch.count_scale, ch.count_unit.as_deref()) else {
            return Err(ImportError::desc(
                file,
                &format!("{key}.unit"),
                "unit = \"counts\" needs count_scale = [x, y, z] and count_unit",
            ));
        };
        let f =
            unit_factor(sensor, ch.quantity, cu, g).ok_or_else(|| bad_unit("count_unit", cu))?;
        if let Some(s) = scale.iter().find(|s| !(s.is_finite() && **s != 0.0)) {
            return Err(ImportError::desc(
                file,
                &format!("{key}.count_scale"),
                format!("{s} is not a finite, non-zero scale"),
            ));
        }
        let note = format!(
            "{key} {}: counts x [{}, {}, {}] {cu}{}",
            quantity_word(ch.quantity),
            scale[0],
            scale[1],
            scale[2],
            g_note(cu, g)
        );
        return Ok((scale.map(|s| s * f), note));
    }
    if ch.count_scale.is_some() || ch.count_unit.is_some() {
        return Err(ImportError::desc(
            file,
            &format!("{key}.count_scale"),
            "count_scale and count_unit apply only with unit = \"counts\"",
        ));
    }
    let f =
        unit_factor(sensor, ch.quantity, &ch.unit, g).ok_or_else(|| bad_unit("unit", &ch.unit))?;
    let note = format!(
        "{key} {}: {}{}",
        quantity_word(ch.quantity),
        ch.unit.trim(),
        g_note(&ch.unit, g)
    );
    Ok(([f; 3], note))
}

fn quantity_word(q: Quantity) -> &'static str {
    match q {
        Quantity::Rate => "rate",
        Quantity::Increment => "increment",
    }
}

fn g_note(unit: &str, g: f64) -> String {
    if unit.contains('g') && !unit.contains("deg") {
        format!(" (g = {g} m/s^2)")
    } else {
        String::new()
    }
}

/// Factor and offset from a time unit to seconds.
pub fn time_factor(file: &Path, unit: &str) -> Result<f64, ImportError> {
    match unit.trim() {
        "s" => Ok(1.0),
        "ms" => Ok(1e-3),
        "us" => Ok(1e-6),
        "ns" => Ok(1e-9),
        other => Err(ImportError::desc(
            file,
            "time.unit",
            format!("'{other}' is not a time unit (use s, ms, us or ns)"),
        )),
    }
}

/// `degC = a * value + b` for a temperature unit.
pub fn temperature_affine(file: &Path, unit: &str) -> Result<(f64, f64), ImportError> {
    match unit.trim() {
        "degC" | "C" => Ok((1.0, 0.0)),
        "K" => Ok((1.0, -273.15)),
        "degF" | "F" => Ok((5.0 / 9.0, -32.0 * 5.0 / 9.0)),
        other => Err(ImportError::desc(
            file,
            "temperature.unit",
            format!("'{other}' is not a temperature unit (use degC, K or degF)"),
        )),
    }
}

/// A signed sensor axis such as `"+y"` or `"-z"` as a unit row vector.
fn signed_axis(file: &Path, key: &str, text: &str) -> Result<[f64; 3], ImportError> {
    let t = text.trim();
    let (sign, axis) = match t.as_bytes() {
        [b'-', a] => (-1.0, *a),
        [b'+', a] | [a] => (1.0, *a),
        _ => (0.0, b'?'),
    };
    let mut row = [0.0; 3];
    match axis.to_ascii_lowercase() {
        b'x' => row[0] = sign,
        b'y' => row[1] = sign,
        b'z' => row[2] = sign,
        _ => {
            return Err(ImportError::desc(
                file,
                key,
                format!("'{text}' is not a signed sensor axis (write +x, -y, z, ...)"),
            ));
        }
    }
    Ok(row)
}

/// The rotation `body_from_sensor` described by `[axes]`, and its provenance note.
pub fn body_from_sensor(file: &Path, axes: &Axes) -> Result<(Mat3, String), ImportError> {
    let explicit = [&axes.right, &axes.forward, &axes.up];
    let given = usize::from(axes.convention.is_some())
        + usize::from(explicit.iter().any(|a| a.is_some()))
        + usize::from(axes.body_from_sensor.is_some());
    if given > 1 {
        return Err(ImportError::desc(
            file,
            "axes",
            "give one of convention, right/forward/up, or body_from_sensor",
        ));
    }
    let rows: [[f64; 3]; 3] = if let Some(m) = axes.body_from_sensor {
        m
    } else if explicit.iter().any(|a| a.is_some()) {
        let names = ["axes.right", "axes.forward", "axes.up"];
        let mut rows = [[0.0; 3]; 3];
        for (k, a) in explicit.iter().enumerate() {
            let Some(text) = a else {
                return Err(ImportError::desc(
                    file,
                    names[k],
                    "right, forward and up are given together",
                ));
            };
            rows[k] = signed_axis(file, names[k], text)?;
        }
        rows
    } else {
        match axes.convention.as_deref().unwrap_or("rfu") {
            "rfu" => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            "frd" => [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]],
            "flu" => [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            other => {
                return Err(ImportError::desc(
                    file,
                    "axes.convention",
                    format!(
                        "'{other}' is not a known convention (rfu, frd, flu; or give \
                         right/forward/up or body_from_sensor)"
                    ),
                ));
            }
        }
    };
    let m = Mat3::from_fn(|i, j| rows[i][j]);
    let orth = (m * m.transpose() - Mat3::identity()).abs().max();
    if !(orth < 1e-9 && m.determinant() > 0.0) {
        return Err(ImportError::desc(
            file,
            "axes",
            format!(
                "body_from_sensor {rows:?} is not a rotation (orthonormal rows, determinant +1; \
                 a mirror such as right = +x, forward = +y, up = -z swaps handedness)"
            ),
        ));
    }
    let note = if m == Mat3::identity() {
        "axes: sensor x, y, z = body right, forward, up".to_string()
    } else {
        format!("axes: body_from_sensor = {rows:?}")
    };
    Ok((m, note))
}
