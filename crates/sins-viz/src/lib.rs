//! Rerun `.rrd` logs of sinsbench results, for offline viewing in the Rerun viewer.
//! Only this crate links rerun, so the numeric crates build and test in seconds.

use std::path::Path;

mod nav;
pub use nav::{
    Annotation, NavRecording, ScalarSeries, Strip2, TIMELINE, write_navigation, write_timeseries,
};

/// Errors while writing a Rerun recording.
#[derive(Debug, thiserror::Error)]
pub enum VizError {
    /// The recording could not be created or written.
    #[error("{path}: cannot write Rerun recording: {message}")]
    Rerun {
        /// Target file.
        path: String,
        /// What rerun reported.
        message: String,
    },
}

/// One named time series: `(t_s, value)` pairs logged as scalars under `entity`.
pub struct Series<'a> {
    /// Entity path, e.g. `calibration/B_gx`.
    pub entity: &'a str,
    /// Samples (time in seconds, value in the series' unit).
    pub points: &'a [(f64, f64)],
}

/// Write scalar time series to an `.rrd` file on a `time_s` timeline (application id
/// `sinsbench`, recording named `name`).
pub fn write_series(path: &Path, name: &str, series: &[Series<'_>]) -> Result<(), VizError> {
    let err = |e: &dyn std::fmt::Display| VizError::Rerun {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let rec = rerun::RecordingStreamBuilder::new("sinsbench")
        .recording_name(name)
        .save(path)
        .map_err(|e| err(&e))?;
    for s in series {
        for &(t, v) in s.points {
            rec.set_duration_secs("time_s", t);
            rec.log(s.entity, &rerun::Scalars::single(v))
                .map_err(|e| err(&e))?;
        }
    }
    rec.flush_blocking().map_err(|e| err(&e))?;
    Ok(())
}
