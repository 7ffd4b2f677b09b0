//! Row checks shared by the readers and the writer: finite values and a regular, strictly
//! increasing time axis that agrees with the metadata sample rate.
//!
//! A step that disagrees with the sample interval is reported one row late: when the next row
//! goes back in time, the two rows are out of order (e.g. a swapped pair) and the error says
//! that `t_s` is not increasing there, rather than calling the first of them a gap. Callers
//! therefore call [`TimeCheck::finish`] after the last row.

use std::path::Path;

use crate::error::{DataError, RowRef};

/// Relative tolerance on a `t_s` step, as a fraction of the nominal interval 1/rate.
pub const STEP_TOLERANCE_FRACTION: f64 = 0.01;

/// Sequential checker of the `t_s` axis.
#[derive(Clone, Debug)]
pub(crate) struct TimeCheck {
    rate_hz: f64,
    dt_s: f64,
    prev_t_s: Option<f64>,
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
            self.finish(file)?;
            self.check_step(file, at, prev_t_s, t_s)?;
        }
        self.prev_t_s = Some(t_s);
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

    /// The gap found at the latest row, if any: call after the last row of `file`.
    pub fn finish(&mut self, file: &Path) -> Result<(), DataError> {
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
