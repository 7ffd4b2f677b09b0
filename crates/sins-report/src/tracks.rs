//! The 1 Hz error tracks of one experiment as Parquet (long format: one row per parameter set
//! and time), and the per-segment table aggregated from them with polars (one row per
//! parameter set and contiguous stretch of a segment label). The aggregation is a second,
//! independent path to the per-segment maxima that `sins_harness::segments` computes while the
//! replay streams (summary.json, report.md); the tests hold the two to each other.

use crate::ReportError;
use polars::prelude::{Column, DataFrame, IntoLazy, PolarsError, SortMultipleOptions, col, lit};
use sins_harness::ErrorPoint;
use sins_harness::pipeline::{RunOutcome, Track};
use sins_harness::segments::label_of;
use std::path::Path;

/// Write `<run>_errors.parquet` (`errors`) and `<run>_segments.parquet` (`segments`).
pub(crate) fn write_tracks(
    errors: &Path,
    segments: &Path,
    o: &RunOutcome,
) -> Result<(), ReportError> {
    let polars = |what: &str, source: PolarsError| ReportError::Polars {
        what: format!("{what} of {}", o.run),
        source,
    };
    let mut df = error_table(&o.tracks, &o.labels).map_err(|e| polars("error table", e))?;
    let mut per_segment = segment_table(&df).map_err(|e| polars("per-segment table", e))?;
    let kv = vec![("sinsbench.experiment".to_string(), o.run.clone())];
    sins_data::write_parquet_df_atomic(errors, &mut df, &kv)?;
    sins_data::write_parquet_df_atomic(segments, &mut per_segment, &kv)?;
    Ok(())
}

/// The error table: columns `set, t_s, segment, stretch, north_m, east_m, horizontal_m,
/// vel_n_mps, vel_e_mps` (m, m/s); `stretch` counts the contiguous stretches of equal segment
/// within a set (0, 1, ...).
pub(crate) fn error_table(tracks: &[Track], labels: &[String]) -> Result<DataFrame, PolarsError> {
    let rows: Vec<(&str, &ErrorPoint, u32)> = tracks
        .iter()
        .flat_map(|t| {
            let mut stretch = 0u32;
            let mut previous = t.points.first().map(|p| p.segment);
            t.points.iter().map(move |p| {
                if previous != Some(p.segment) {
                    stretch += 1;
                    previous = Some(p.segment);
                }
                (t.set.as_str(), p, stretch)
            })
        })
        .collect();
    let col_f64 = |name: &str, f: &dyn Fn(&ErrorPoint) -> f64| {
        Column::new(
            name.into(),
            rows.iter().map(|(_, p, _)| f(p)).collect::<Vec<f64>>(),
        )
    };
    DataFrame::new(
        rows.len(),
        vec![
            Column::new(
                "set".into(),
                rows.iter().map(|(s, _, _)| *s).collect::<Vec<&str>>(),
            ),
            col_f64("t_s", &|p| p.t_s),
            Column::new(
                "segment".into(),
                rows.iter()
                    .map(|(_, p, _)| label_of(labels, p.segment))
                    .collect::<Vec<String>>(),
            ),
            Column::new(
                "stretch".into(),
                rows.iter().map(|(_, _, k)| *k).collect::<Vec<u32>>(),
            ),
            col_f64("north_m", &|p| p.north_m),
            col_f64("east_m", &|p| p.east_m),
            col_f64("horizontal_m", &|p| p.horizontal_m()),
            col_f64("vel_n_mps", &|p| p.vel_n_mps),
            col_f64("vel_e_mps", &|p| p.vel_e_mps),
        ],
    )
}

/// The per-segment table of an [`error_table`]: per set and stretch (in order) the `segment`
/// label, `start_s` and `end_s` (first and last point), `max_horizontal_m`, `t_max_s` (its
/// first time) and `rms_horizontal_m`.
pub(crate) fn segment_table(errors: &DataFrame) -> Result<DataFrame, PolarsError> {
    let h = || col("horizontal_m");
    errors
        .clone()
        .lazy()
        .group_by_stable([col("set"), col("stretch")])
        .agg([
            col("segment").first(),
            col("t_s").min().alias("start_s"),
            col("t_s").max().alias("end_s"),
            h().max().alias("max_horizontal_m"),
            col("t_s")
                .filter(h().eq(h().max()))
                .first()
                .alias("t_max_s"),
            (h() * h()).mean().pow(lit(0.5)).alias("rms_horizontal_m"),
        ])
        .sort(
            ["set", "stretch"],
            SortMultipleOptions::default().with_maintain_order(true),
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use sins_harness::segments::stretches;
    use sins_nav::Quat;
    use sins_replay::ReplaySummary;

    fn point(t_s: f64, north_m: f64, east_m: f64, segment: u16) -> ErrorPoint {
        ErrorPoint {
            t_s,
            north_m,
            east_m,
            vel_n_mps: 0.0,
            vel_e_mps: 0.0,
            segment,
            ned_from_body: Quat::identity(),
        }
    }

    /// Two sets over segments 0, 1, 0, 2 (label 0 twice): polars' aggregation of the error
    /// table gives the streaming stretches of `sins_harness` row for row.
    #[test]
    fn polars_per_segment_table_matches_the_streaming_maxima() {
        let labels: Vec<String> = ["alignment", "pattern1", "stationary"]
            .map(String::from)
            .to_vec();
        let track = |set: &str, scale: f64| {
            let points: Vec<ErrorPoint> = (0..400)
                .map(|k| {
                    let t = k as f64;
                    let seg = [0u16, 1, 0, 2][k / 100];
                    let wobble = (0.37 * t).sin() * 30.0;
                    point(t, scale * (t + wobble), scale * 0.5 * wobble, seg)
                })
                .collect();
            Track {
                set: set.into(),
                stretches: stretches(&points, &labels),
                summary: ReplaySummary::from_points(&points, 400.0),
                points,
            }
        };
        let tracks = vec![track("30", 1.0), track("42", 0.25)];
        let df = segment_table(&error_table(&tracks, &labels).expect("errors")).expect("agg");
        assert_eq!(df.height(), 8);
        let f = |name: &str| -> Vec<f64> {
            let c = df.column(name).expect(name).f64().expect("f64");
            c.into_no_null_iter().collect()
        };
        let segment = df.column("segment").expect("segment").str().expect("str");
        let labels_out: Vec<String> = (0..df.height())
            .map(|i| segment.get(i).unwrap_or("null").to_string())
            .collect();
        let expected: Vec<_> = tracks.iter().flat_map(|t| t.stretches.iter()).collect();
        for (i, s) in expected.iter().enumerate() {
            assert_eq!(labels_out[i], s.label, "row {i}");
            assert_eq!(f("start_s")[i], s.start_s, "row {i}");
            assert_eq!(f("end_s")[i], s.end_s, "row {i}");
            assert_eq!(f("max_horizontal_m")[i], s.max_horizontal_m, "row {i}");
            assert_eq!(f("t_max_s")[i], s.t_max_s, "row {i}");
            let rel = (f("rms_horizontal_m")[i] / s.rms_horizontal_m - 1.0).abs();
            assert!(rel < 1e-12, "row {i}: {rel}");
        }
    }
}
