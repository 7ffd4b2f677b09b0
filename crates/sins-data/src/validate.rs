//! Row checks shared by the readers and the writer: finite values and a strictly increasing
//! time axis that agrees with the metadata sample rate.
//!
//! Recorded time stamps jitter: a step between 0.55 and 1.45 sample intervals is one interval
//! ([`STEP_TOLERANCE_FRACTION`]); a longer one is a gap (dropped samples, which
//! `sinsbench import` bridges), a shorter one an error. Over the whole file the mean step must
//! agree with 1/rate within [`MEAN_STEP_TOLERANCE_FRACTION`], so jitter cannot hide a wrong
//! rate.
//!
//! A step that disagrees with the sample interval is reported one row late: when the next row
//! goes back in time, the two rows are out of order (e.g. a swapped pair) and the error says
//! that `t_s` is not increasing there, rather than calling the first of them a gap. Callers
//! therefore call [`TimeCheck::finish`] after the last row.

use std::path::Path;

use crate::error::{DataError, RowRef};

/// Relative tolerance on one `t_s` step, as a fraction of the nominal interval 1/rate: recorded
/// stamps jitter (a PC-stamped 64 Hz log by about 1 %, a USB logger by tens of percent). A step
/// of 1.45 intervals or more is a gap (a dropped sample is a step of 2).
pub const STEP_TOLERANCE_FRACTION: f64 = 0.45;

/// Relative tolerance on the mean step over the whole file, (last - first) / (rows - 1),
/// against 1/rate: a wrong `sinsbench.sample_rate_hz` cannot hide behind the jitter band.
pub const MEAN_STEP_TOLERANCE_FRACTION: f64 = 0.01;

/// Sequential checker of the `t_s` axis.
#[derive(Clone, Debug)]
pub(crate) struct TimeCheck {
    rate_hz: f64,
    dt_s: f64,
    prev_t_s: Option<f64>,
    /// First row's `t_s` and its row reference.
    first: Option<(RowRef, f64)>,
    /// Rows checked.
    n_rows: u64,
    /// Latest row checked.
    last_at: Option<RowRef>,
    first_step_seen: bool,
    /// A gap found at the latest row (where, step in s), reported unless the next row goes
    /// back in time.
    pending_gap: Option<(RowRef, f64)>,
}

impl TimeCheck {
    /// A checker for nominal rate `rate_hz` (finite, positive).
    pub fn new(rate_hz: f64) -> Self {
        Self {
            rate_hz,
            dt_s: 1.0 / rate_hz,
            prev_t_s: None,
            first: None,
            n_rows: 0,
            last_at: None,
            first_step_seen: false,
            pending_gap: None,
        }
    }

    /// Check consecutive rows `first_row..` with times `t_s` (all finite): a branch-free pass
    /// over the whole slice, then, only if it finds a problem, the row-by-row check that
    /// reports it.
    pub fn check_slice(
        &mut self,
        file: &Path,
        first_row: u64,
        t_s: &[f64],
    ) -> Result<(), DataError> {
        let (Some(&last), Some(prev)) = (t_s.last(), self.prev_t_s) else {
            return self.check_rows(file, first_row, t_s);
        };
        if !self.first_step_seen || self.pending_gap.is_some() {
            return self.check_rows(file, first_row, t_s);
        }
        let (dt, frac) = (self.dt_s, STEP_TOLERANCE_FRACTION);
        let good = |a: f64, b: f64| {
            let step = b - a;
            (b > a) & ((step - dt).abs() <= frac * dt + 4.0 * f64::EPSILON * b.abs())
        };
        let all_good = good(prev, t_s[0])
            & t_s
                .iter()
                .zip(&t_s[1..])
                .fold(true, |ok, (&a, &b)| ok & good(a, b));
        if all_good {
            self.prev_t_s = Some(last);
            self.n_rows += t_s.len() as u64;
            self.last_at = Some(RowRef::row(first_row + t_s.len() as u64 - 1));
            Ok(())
        } else {
            self.check_rows(file, first_row, t_s)
        }
    }

    fn check_rows(&mut self, file: &Path, first_row: u64, t_s: &[f64]) -> Result<(), DataError> {
        for (i, &t) in t_s.iter().enumerate() {
            self.check(file, RowRef::row(first_row + i as u64), t)?;
        }
        Ok(())
    }

    /// Check the next row's (finite) `t_s`. The first step that disagrees with 1/rate is a
    /// [`DataError::SampleRateMismatch`] when it is the file's first step; a later one is a
    /// [`DataError::TimeGap`], reported at the next row (or by [`TimeCheck::finish`]) unless
    /// that row goes back in time, which is a [`DataError::TimeNotIncreasing`].
    #[inline]
    pub fn check(&mut self, file: &Path, at: RowRef, t_s: f64) -> Result<(), DataError> {
        if let Some(prev_t_s) = self.prev_t_s {
            if t_s <= prev_t_s {
                return Err(DataError::TimeNotIncreasing {
                    file: file.to_path_buf(),
                    at,
                    prev_t_s,
                    t_s,
                });
            }
            self.finish_gap(file)?;
            self.check_step(file, at, prev_t_s, t_s)?;
        } else {
            self.first = Some((at, t_s));
        }
        self.prev_t_s = Some(t_s);
        self.n_rows += 1;
        self.last_at = Some(at);
        Ok(())
    }

    /// Check one step of `t_s` against 1/rate (see [`TimeCheck::check`]).
    fn check_step(
        &mut self,
        file: &Path,
        at: RowRef,
        prev_t_s: f64,
        t_s: f64,
    ) -> Result<(), DataError> {
        let step_s = t_s - prev_t_s;
        // 1 % of the interval plus a few ulps of the absolute time for rounding of t_s.
        let tol_s = STEP_TOLERANCE_FRACTION * self.dt_s + 4.0 * f64::EPSILON * t_s.abs();
        if (step_s - self.dt_s).abs() <= tol_s {
            self.first_step_seen = true;
            return Ok(());
        }
        if !self.first_step_seen {
            return Err(DataError::SampleRateMismatch {
                file: file.to_path_buf(),
                at,
                meta_rate_hz: self.rate_hz,
                step_s,
                implied_rate_hz: 1.0 / step_s,
            });
        }
        self.pending_gap = Some((at, step_s));
        Ok(())
    }

    /// The gap found at the latest row, if any, then the mean step over the whole file: call
    /// after the last row of `file`.
    pub fn finish(&mut self, file: &Path) -> Result<(), DataError> {
        self.finish_gap(file)?;
        let (Some((_, t0)), Some(t1), Some(at)) = (self.first, self.prev_t_s, self.last_at) else {
            return Ok(());
        };
        if self.n_rows < 2 {
            return Ok(());
        }
        let mean_step_s = (t1 - t0) / (self.n_rows - 1) as f64;
        let tol = MEAN_STEP_TOLERANCE_FRACTION * self.dt_s + 4.0 * f64::EPSILON * t1.abs();
        if (mean_step_s - self.dt_s).abs() > tol {
            return Err(DataError::SampleRateMismatch {
                file: file.to_path_buf(),
                at,
                meta_rate_hz: self.rate_hz,
                step_s: mean_step_s,
                implied_rate_hz: 1.0 / mean_step_s,
            });
        }
        Ok(())
    }

    /// The gap found at the latest row, if any.
    fn finish_gap(&mut self, file: &Path) -> Result<(), DataError> {
        match self.pending_gap.take() {
            Some((at, step_s)) => Err(DataError::TimeGap {
                file: file.to_path_buf(),
                at,
                step_s,
                expected_step_s: self.dt_s,
            }),
            None => Ok(()),
        }
    }
}

/// Index of the first non-finite value, if any (vectorisable fast path for the all-good case).
pub(crate) fn first_non_finite(values: &[f64]) -> Option<usize> {
    const CHUNK: usize = 256;
    for (ci, chunk) in values.chunks(CHUNK).enumerate() {
        if !chunk.iter().fold(true, |ok, x| ok & x.is_finite()) {
            let i = chunk.iter().position(|x| !x.is_finite()).unwrap_or(0);
            return Some(ci * CHUNK + i);
        }
    }
    None
}

/// Error for a non-finite value.
pub(crate) fn non_finite(file: &Path, at: RowRef, column: &str, value: f64) -> DataError {
    DataError::NonFinite {
        file: file.to_path_buf(),
        at,
        column: column.to_string(),
        value,
    }
}

/// Gyro full-scale range (rad/s) behind the angular-increment limit: ±1000 deg/s, the range of
/// tactical and navigation IMUs such as the HG1700 and LN-200 class (the same figure as
/// `sins_config::plausible::GYRO_FULL_SCALE_DEG_PER_S`). A saturated gyro cannot integrate more
/// than this rate over one sample interval.
pub const GYRO_FULL_SCALE_RADPS: f64 = 1000.0 * std::f64::consts::PI / 180.0;

/// Accelerometer full-scale range (m/s^2) behind the velocity-increment limit: ±60 g, the input
/// range of the quartz flexure accelerometers (QA-2000 class) of navigation-grade IMUs (the
/// same figure as `sins_config::plausible::ACCEL_FULL_SCALE_G`).
pub const ACCEL_FULL_SCALE_MPS2: f64 = 60.0 * 9.806_65;

/// Accepted sensor temperatures (degC): the extended military range with margin below
/// (-60 degC) and the maximum junction temperature of the electronics above (125 degC).
pub const TEMPERATURE_RANGE_DEGC: (f64, f64) = (-60.0, 125.0);

/// Accepted heights above the ellipsoid (m): from below the deepest ocean floor (-12 km) to the
/// edge of space (100 km), as `sins_config::plausible::{MIN_HEIGHT_M, MAX_HEIGHT_M}`.
pub const HEIGHT_RANGE_M: (f64, f64) = (-12_000.0, 100_000.0);

/// Highest accepted `sinsbench.sample_rate_hz` (Hz): five times the fastest navigation-grade IMU
/// output (2 kHz), as `sins_config::plausible::MAX_SAMPLE_RATE_HZ`.
pub const MAX_SAMPLE_RATE_HZ: f64 = 10_000.0;

/// The accepted range of one Float64 column and why, for error messages.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ColumnLimit {
    /// Lowest accepted value (column unit).
    pub lo: f64,
    /// Highest accepted value (column unit).
    pub hi: f64,
    /// What the range stands for.
    pub why: String,
}

/// The plausibility range of column `name` in a dataset sampled at `rate_hz` (`None` for
/// columns without one: `t_s`, reference velocities and attitude). Increments are limited to
/// the full-scale rate times one sample interval, with the 1 % timing tolerance of the `t_s`
/// check on top.
pub(crate) fn column_limit(name: &str, rate_hz: f64) -> Option<ColumnLimit> {
    let dt_s = (1.0 + STEP_TOLERANCE_FRACTION) / rate_hz;
    let sym = |x: f64, why: String| Some(ColumnLimit { lo: -x, hi: x, why });
    let range = |(lo, hi): (f64, f64), why: String| Some(ColumnLimit { lo, hi, why });
    match name {
        "dtheta_x_rad" | "dtheta_y_rad" | "dtheta_z_rad" => sym(
            GYRO_FULL_SCALE_RADPS * dt_s,
            format!(
                "a navigation-grade gyro saturates at 1000 deg/s, i.e. {:.4} rad per sample at \
                 {rate_hz} Hz",
                GYRO_FULL_SCALE_RADPS * dt_s
            ),
        ),
        "dv_x_mps" | "dv_y_mps" | "dv_z_mps" => sym(
            ACCEL_FULL_SCALE_MPS2 * dt_s,
            format!(
                "a navigation-grade accelerometer saturates at 60 g, i.e. {:.4} m/s per sample \
                 at {rate_hz} Hz",
                ACCEL_FULL_SCALE_MPS2 * dt_s
            ),
        ),
        "temp_ax_degc" | "temp_ay_degc" | "temp_az_degc" => range(
            TEMPERATURE_RANGE_DEGC,
            "an IMU works between -60 and 125 degC".to_string(),
        ),
        "ref_lat_rad" => sym(
            std::f64::consts::FRAC_PI_2,
            "a latitude lies within ±pi/2 rad (±90 deg)".to_string(),
        ),
        "ref_lon_rad" => sym(
            2.0 * std::f64::consts::PI,
            "a longitude lies within ±2 pi rad (±360 deg, as the metadata site)".to_string(),
        ),
        "ref_height_m" => range(
            HEIGHT_RANGE_M,
            "a height on the Earth lies between -12 km (below the deepest ocean floor) and \
             100 km (the edge of space)"
                .to_string(),
        ),
        _ => None,
    }
}

/// Limits of the Float64 columns `names` (in file order) at `rate_hz`.
pub(crate) fn column_limits(names: &[&str], rate_hz: f64) -> Vec<Option<ColumnLimit>> {
    names.iter().map(|n| column_limit(n, rate_hz)).collect()
}

/// Error for a value outside its column's plausibility range.
pub(crate) fn implausible(
    file: &Path,
    at: RowRef,
    column: &str,
    value: f64,
    limit: &ColumnLimit,
) -> DataError {
    DataError::Implausible {
        file: file.to_path_buf(),
        at,
        column: column.to_string(),
        value,
        why: format!(
            "accepted {}..{}: {}",
            short_number(limit.lo),
            short_number(limit.hi),
            limit.why
        ),
    }
}

/// Index of the first value of `values` outside `lo..=hi` (finite values assumed), if any:
/// a branch-free pass per chunk for the all-good case.
#[inline]
pub(crate) fn first_outside(values: &[f64], lo: f64, hi: f64) -> Option<usize> {
    const CHUNK: usize = 256;
    for (ci, chunk) in values.chunks(CHUNK).enumerate() {
        if !chunk.iter().fold(true, |ok, &x| ok & (x >= lo) & (x <= hi)) {
            let i = chunk
                .iter()
                .position(|&x| !(lo..=hi).contains(&x))
                .unwrap_or(0);
            return Some(ci * CHUNK + i);
        }
    }
    None
}

/// Check the metadata against the plausibility limits: sample rate at most
/// [`MAX_SAMPLE_RATE_HZ`], site height within [`HEIGHT_RANGE_M`].
pub(crate) fn check_meta(file: &Path, meta: &crate::DatasetMeta) -> Result<(), DataError> {
    let rate = meta.sample_rate_hz;
    if rate > MAX_SAMPLE_RATE_HZ {
        return Err(DataError::InvalidMetadata {
            file: file.to_path_buf(),
            key: crate::KEY_SAMPLE_RATE_HZ.to_string(),
            value: rate.to_string(),
            reason: format!(
                "above the {MAX_SAMPLE_RATE_HZ} Hz maximum (navigation-grade IMUs deliver \
                 100 Hz to 2 kHz)"
            ),
        });
    }
    let h = meta.site.height_m;
    if !(HEIGHT_RANGE_M.0..=HEIGHT_RANGE_M.1).contains(&h) {
        return Err(DataError::InvalidMetadata {
            file: file.to_path_buf(),
            key: crate::KEY_SITE_HEIGHT_M.to_string(),
            value: h.to_string(),
            reason: "not a height on the Earth (accepted: -12000 m, below the deepest ocean \
                     floor, to 100000 m, the edge of space)"
                .to_string(),
        });
    }
    Ok(())
}

/// `x` with at most 6 significant digits, shortest form (0.0881391272 -> 0.0881391).
fn short_number(x: f64) -> String {
    format!("{x:.5e}")
        .parse::<f64>()
        .map_or_else(|_| x.to_string(), |r| r.to_string())
}
