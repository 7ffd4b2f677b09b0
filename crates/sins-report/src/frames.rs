//! The single-table Parquet outputs of the CLI's commands, built with polars here so that the
//! CLI holds no DataFrame: a replay's error track (`sinsbench navigate --errors`) and a
//! calibration's convergence history (`sinsbench calibrate --history`). Both are written aside
//! and renamed into place ([`sins_data::write_parquet_df_atomic`]).

use crate::ReportError;
use polars::prelude::{Column, DataFrame, PolarsError};
use sins_harness::ErrorPoint;
use std::path::Path;

fn polars(what: &str, path: &Path) -> impl FnOnce(PolarsError) -> ReportError {
    let what = format!("{what} {}", path.display());
    move |source| ReportError::Polars { what, source }
}

/// Write a replay's error track to `path`: one row per point, columns `t_s` (s), `north_m`,
/// `east_m`, `horizontal_m` (m), `vel_n_mps`, `vel_e_mps` (m/s) and `segment` (the label of
/// the point's segment in `labels`, `-` when it has none); the key `sinsbench.dataset` names
/// the replayed `dataset`.
pub fn write_error_track(
    path: &Path,
    dataset: &str,
    points: &[ErrorPoint],
    labels: &[String],
) -> Result<(), ReportError> {
    let col = |name: &str, f: &dyn Fn(&ErrorPoint) -> f64| {
        Column::new(name.into(), points.iter().map(f).collect::<Vec<f64>>())
    };
    let segment: Vec<&str> = points
        .iter()
        .map(|p| labels.get(p.segment as usize).map_or("-", String::as_str))
        .collect();
    let mut df = DataFrame::new(
        points.len(),
        vec![
            col("t_s", &|p| p.t_s),
            col("north_m", &|p| p.north_m),
            col("east_m", &|p| p.east_m),
            col("horizontal_m", &|p| p.horizontal_m()),
            col("vel_n_mps", &|p| p.vel_n_mps),
            col("vel_e_mps", &|p| p.vel_e_mps),
            Column::new("segment".into(), segment),
        ],
    )
    .map_err(polars("error track", path))?;
    let kv = vec![("sinsbench.dataset".to_string(), dataset.to_string())];
    sins_data::write_parquet_df_atomic(path, &mut df, &kv)?;
    Ok(())
}

/// Write a calibration's convergence history to `path`: a column `t_s` (s, `times_s`), then
/// each of `columns` as `(name, values)` in the caller's units, one value per time; the key
/// `sinsbench.kind` is `calibration_history`.
pub fn write_calibration_history(
    path: &Path,
    times_s: Vec<f64>,
    columns: Vec<(String, Vec<f64>)>,
) -> Result<(), ReportError> {
    let n = times_s.len();
    let mut all = vec![Column::new("t_s".into(), times_s)];
    all.extend(
        columns
            .into_iter()
            .map(|(name, values)| Column::new(name.into(), values)),
    );
    let mut df = DataFrame::new(n, all).map_err(polars("calibration history", path))?;
    sins_data::write_parquet_df_atomic(
        path,
        &mut df,
        &[("sinsbench.kind".into(), "calibration_history".into())],
    )?;
    Ok(())
}
