//! Turning decoded row-group columns into validated [`SampleBatch`]es.

use sins_imu::ImuSample;
use sins_nav::Vec3;

use crate::error::{DataError, RowRef};
use crate::schema::{ColumnSet, ReferenceRow, SampleBatch};
use crate::validate::{ColumnLimit, TimeCheck, first_non_finite, non_finite};
use polars_parquet::read::FileMetadata;
use std::collections::HashMap;
use std::path::PathBuf;

/// Everything the decoder thread needs, immutable.
pub(crate) struct ReadPlan {
    pub path: PathBuf,
    pub metadata: FileMetadata,
    pub columns: ColumnSet,
    pub float_names: Vec<&'static str>,
    pub lookup: HashMap<String, u16>,
    pub rate_hz: f64,
    /// Plausibility range of each Float64 column (same order as `float_names`).
    pub limits: Vec<Option<ColumnLimit>>,
}

/// Decoded columns of one row group (buffers reused across row groups).
pub(crate) struct RowGroupColumns {
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

/// Validate rows `start..end` of a decoded row group and assemble them into a batch, reusing
/// the buffers of `spare` when given.
pub(crate) fn build_batch(
    plan: &ReadPlan,
    cols: &RowGroupColumns,
    start: usize,
    end: usize,
    time: &mut TimeCheck,
    spare: Option<SampleBatch>,
) -> Result<SampleBatch, DataError> {
    let path = plan.path.as_path();
    let base = cols.first_row + start as u64;
    let n = end - start;
    // Non-finite values: report the earliest row, first column in file order on ties.
    let mut worst: Option<(usize, usize)> = None;
    for (ci, col) in cols.floats.iter().enumerate() {
        let limit = worst.map_or(end, |(r, _)| r + 1);
        if let Some(i) = first_non_finite(&col[start..limit]) {
            let r = start + i;
            if worst.is_none_or(|(wr, _)| r < wr) {
                worst = Some((r, ci));
            }
        }
    }
    if let Some((r, ci)) = worst {
        let value = cols.floats[ci][r];
        let at = RowRef::row(cols.first_row + r as u64);
        return Err(non_finite(path, at, plan.float_names[ci], value));
    }
    // Every column slice has exactly `n` elements, so the loops below index without checks.
    let col = |k: usize| -> &[f64] { &cols.floats[k][start..end][..n] };
    let t = col(0);
    time.check_slice(path, base, t)?;
    let (spare_samples, spare_segment, spare_reference) = match spare {
        Some(b) => (Some(b.samples), b.segment_index, b.reference),
        None => (None, None, None),
    };
    let mut samples = reuse(spare_samples, n);
    let (dtx, dty, dtz, dvx, dvy, dvz) = (col(1), col(2), col(3), col(4), col(5), col(6));
    let has_temp = plan.columns.temperature;
    if has_temp {
        let (tx, ty, tz) = (col(7), col(8), col(9));
        samples.extend((0..n).map(|i| ImuSample {
            t_s: t[i],
            dtheta_rad: Vec3::new(dtx[i], dty[i], dtz[i]),
            dv_mps: Vec3::new(dvx[i], dvy[i], dvz[i]),
            temp_degc: [tx[i], ty[i], tz[i]],
        }));
    } else {
        samples.extend((0..n).map(|i| ImuSample {
            t_s: t[i],
            dtheta_rad: Vec3::new(dtx[i], dty[i], dtz[i]),
            dv_mps: Vec3::new(dvx[i], dvy[i], dvz[i]),
            temp_degc: [f64::NAN; 3],
        }));
    }
    let reference = plan.columns.reference.then(|| {
        let k0 = if has_temp { 10 } else { 7 };
        let r: [&[f64]; 9] = std::array::from_fn(|k| col(k0 + k));
        let mut out = reuse(spare_reference, n);
        out.extend((0..n).map(|i| ReferenceRow {
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
        out
    });
    let segment_index = cols.segment.as_ref().map(|s| {
        let mut out = reuse(spare_segment, n);
        out.extend_from_slice(&s[start..end]);
        out
    });
    Ok(SampleBatch {
        first_row: base,
        samples,
        segment_index,
        reference,
    })
}
