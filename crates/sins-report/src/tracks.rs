//! The 1 Hz error tracks of one experiment as Parquet (long format: one row per parameter set
//! and time).

use crate::ReportError;
use polars::prelude::{Column, DataFrame};
use sins_harness::ErrorPoint;
use sins_harness::pipeline::RunOutcome;
use sins_harness::segments::label_of;
use std::path::Path;

/// Write `<dir>/<run>_errors.parquet`; columns `set, t_s, segment, north_m, east_m,
/// horizontal_m, vel_n_mps, vel_e_mps`.
pub(crate) fn write_tracks(path: &Path, o: &RunOutcome) -> Result<(), ReportError> {
    let rows: Vec<(&str, &ErrorPoint)> = o
        .tracks
        .iter()
        .flat_map(|t| t.points.iter().map(move |p| (t.set.as_str(), p)))
        .collect();
    let col = |name: &str, f: &dyn Fn(&ErrorPoint) -> f64| {
        Column::new(
            name.into(),
            rows.iter().map(|(_, p)| f(p)).collect::<Vec<f64>>(),
        )
    };
    let mut df = DataFrame::new(
        rows.len(),
        vec![
            Column::new(
                "set".into(),
                rows.iter().map(|(s, _)| *s).collect::<Vec<&str>>(),
            ),
            col("t_s", &|p| p.t_s),
            Column::new(
                "segment".into(),
                rows.iter()
                    .map(|(_, p)| label_of(&o.labels, p.segment))
                    .collect::<Vec<String>>(),
            ),
            col("north_m", &|p| p.north_m),
            col("east_m", &|p| p.east_m),
            col("horizontal_m", &|p| p.horizontal_m()),
            col("vel_n_mps", &|p| p.vel_n_mps),
            col("vel_e_mps", &|p| p.vel_e_mps),
        ],
    )
    .map_err(|source| ReportError::Polars {
        what: format!("error table of {}", o.run),
        source,
    })?;
    let kv = vec![("sinsbench.experiment".to_string(), o.run.clone())];
    sins_data::write_parquet_df_atomic(path, &mut df, &kv)?;
    Ok(())
}
