//! Turning decoded Parquet columns into validated [`SampleBatch`]es.

use std::collections::HashMap;
use std::fs::File;
use std::path::PathBuf;
use std::sync::Arc;

use parquet::file::metadata::ParquetMetaData;
use sins_imu::ImuSample;
use sins_nav::Vec3;

use crate::error::{DataError, RowRef};
use crate::schema::{ColumnSet, ReferenceRow, SampleBatch};
use crate::validate::{
    ColumnLimit, TimeCheck, first_non_finite, first_outside, implausible, non_finite,
};

/// Everything the decoder thread needs, immutable.
pub(crate) struct ReadPlan {
    pub path: PathBuf,
    /// The open file (read with positioned reads, by one thread at a time).
    pub file: Arc<File>,
    pub metadata: ParquetMetaData,
    pub columns: ColumnSet,
    pub float_names: Vec<&'static str>,
    /// Leaf column index of each Float64 column (same order as `float_names`).
    pub float_leaves: Vec<usize>,
    /// Leaf column index of the `segment` column.
    pub segment_leaf: Option<usize>,
    /// For each row group, whether its `segment` label indices are read from the pages directly.
    pub segment_direct: Vec<bool>,
    /// Rows of each row group (validated on open: non-negative, summing to the file's rows).
    pub rg_rows: Vec<usize>,
    pub lookup: HashMap<String, u16>,
    pub rate_hz: f64,
    /// Plausibility range of each Float64 column (same order as `float_names`).
    pub limits: Vec<Option<ColumnLimit>>,
}

/// Decoded columns of consecutive rows (buffers reused from batch to batch).
pub(crate) struct DecodedColumns {
    /// Dataset row of the first value.
    pub first_row: u64,
    pub n_rows: usize,
    pub floats: Vec<Vec<f64>>,
    pub segment: Option<Vec<u16>>,
}

/// Take `v` out of a recycled batch (emptied, with room for `n`), or a new vector.
pub(crate) fn reuse<T>(v: Option<Vec<T>>, n: usize) -> Vec<T> {
    let mut v = v.unwrap_or_default();
    v.clear();
    v.reserve(n);
    v
}

/// Validate the decoded rows (finite values, time axis, plausible values) and assemble them
/// into a batch, reusing the buffers of `spare` when given. Errors are those of the checks in
/// this order: the earliest non-finite value, the time axis, the earliest implausible value.
pub(crate) fn build_batch(
    plan: &ReadPlan,
    cols: &DecodedColumns,
    time: &mut TimeCheck,
    spare: Option<SampleBatch>,
) -> Result<SampleBatch, DataError> {
    let path = plan.path.as_path();
    let n = cols.n_rows;
    let col = |k: usize| -> Result<&[f64], DataError> {
        cols.floats
            .get(k)
            .and_then(|c| c.get(..n))
            .ok_or_else(|| DataError::corrupt(path, "internal: a decoded column is too short"))
    };
    // Every value finite and plausible? NaN and infinities fail any range, so one branch-free
    // pass per column and block of rows (still in cache when the rows are assembled from it)
    // tells; only otherwise do the exact checks below locate the error.
    let bounds: Vec<(f64, f64)> = plan
        .limits
        .iter()
        .map(|l| l.as_ref().map_or((f64::MIN, f64::MAX), |l| (l.lo, l.hi)))
        .collect();
    let mut cs: Vec<&[f64]> = Vec::with_capacity(bounds.len());
    for k in 0..bounds.len() {
        cs.push(col(k)?);
    }
    let (spare_samples, spare_segment, spare_reference) = match spare {
        Some(b) => (Some(b.samples), b.segment_index, b.reference),
        None => (None, None, None),
    };
    let mut samples = reuse(spare_samples, n);
    let has_temp = plan.columns.temperature;
    let mut reference = plan.columns.reference.then(|| reuse(spare_reference, n));
    let mut clean = true;
    let mut start = 0;
    while start < n {
        let end = (start + BLOCK_ROWS).min(n);
        for (c, &(lo, hi)) in cs.iter().zip(&bounds) {
            clean &= all_within(&c[start..end], lo, hi);
        }
        let c = |k: usize| &cs[k][start..end];
        let (t, dtx, dty, dtz, dvx, dvy, dvz) = (c(0), c(1), c(2), c(3), c(4), c(5), c(6));
        let m = end - start;
        if has_temp {
            let (tx, ty, tz) = (c(7), c(8), c(9));
            samples.extend((0..m).map(|i| ImuSample {
                t_s: t[i],
                dtheta_rad: Vec3::new(dtx[i], dty[i], dtz[i]),
                dv_mps: Vec3::new(dvx[i], dvy[i], dvz[i]),
                temp_degc: [tx[i], ty[i], tz[i]],
            }));
        } else {
            samples.extend((0..m).map(|i| ImuSample {
                t_s: t[i],
                dtheta_rad: Vec3::new(dtx[i], dty[i], dtz[i]),
                dv_mps: Vec3::new(dvx[i], dvy[i], dvz[i]),
                temp_degc: [f64::NAN; 3],
            }));
        }
        if let Some(out) = reference.as_mut() {
            let k0 = if has_temp { 10 } else { 7 };
            let r: [&[f64]; 9] = std::array::from_fn(|k| c(k0 + k));
            out.extend((0..m).map(|i| ReferenceRow {
                lat_rad: r[0][i],
                lon_rad: r[1][i],
                height_m: r[2][i],
                vel_n_mps: r[3][i],
                vel_e_mps: r[4][i],
                vel_d_mps: r[5][i],
                pitch_rad: r[6][i],
                roll_rad: r[7][i],
                yaw_rad: r[8][i],
            }));
        }
        start = end;
    }
    if !clean {
        check_finite(plan, cols)?;
    }
    time.check_slice(path, cols.first_row, col(0)?)?;
    let segment_index = cols.segment.as_ref().map(|s| {
        let mut out = reuse(spare_segment, n);
        out.extend_from_slice(s);
        out
    });
    if !clean {
        check_plausible(plan, cols)?;
    }
    Ok(SampleBatch {
        first_row: cols.first_row,
        samples,
        segment_index,
        reference,
    })
}

/// Rows validated and assembled at a time: ten columns of them stay in the L2 cache.
const BLOCK_ROWS: usize = 2048;

/// Whether every value lies in `lo..=hi` (so is not NaN): a branch-free, vectorised pass.
fn all_within(values: &[f64], lo: f64, hi: f64) -> bool {
    values
        .iter()
        .fold(true, |ok, &x| ok & (x >= lo) & (x <= hi))
}

/// The earliest non-finite value, the first column in file order on ties.
fn check_finite(plan: &ReadPlan, cols: &DecodedColumns) -> Result<(), DataError> {
    let mut worst: Option<(usize, usize)> = None;
    for (ci, col) in cols.floats.iter().enumerate() {
        let stop = worst.map_or(cols.n_rows, |(r, _)| r + 1);
        if let Some(r) = col.get(..stop).and_then(first_non_finite)
            && worst.is_none_or(|(wr, _)| r < wr)
        {
            worst = Some((r, ci));
        }
    }
    match worst.and_then(|(r, ci)| Some((r, *plan.float_names.get(ci)?, *cols.floats[ci].get(r)?)))
    {
        Some((r, name, value)) => {
            let at = RowRef::row(cols.first_row + r as u64);
            Err(non_finite(&plan.path, at, name, value))
        }
        None => Ok(()),
    }
}

/// Check the decoded rows (all finite) against the plausibility range of every column; reports
/// the earliest row, the first column in file order on ties.
fn check_plausible(plan: &ReadPlan, cols: &DecodedColumns) -> Result<(), DataError> {
    let mut worst: Option<(usize, usize)> = None;
    for (ci, (col, limit)) in cols.floats.iter().zip(&plan.limits).enumerate() {
        let Some(limit) = limit else { continue };
        let stop = worst.map_or(cols.n_rows, |(r, _)| r + 1);
        let Some(rows) = col.get(..stop) else {
            continue;
        };
        if let Some(r) = first_outside(rows, limit.lo, limit.hi)
            && worst.is_none_or(|(wr, _)| r < wr)
        {
            worst = Some((r, ci));
        }
    }
    let Some((r, ci)) = worst else {
        return Ok(());
    };
    let (Some(name), Some(Some(limit)), Some(value)) = (
        plan.float_names.get(ci),
        plan.limits.get(ci),
        cols.floats.get(ci).and_then(|c| c.get(r)),
    ) else {
        return Err(DataError::corrupt(
            &plan.path,
            "internal: plausibility index",
        ));
    };
    let at = RowRef::row(cols.first_row + r as u64);
    Err(implausible(&plan.path, at, name, *value, limit))
}
