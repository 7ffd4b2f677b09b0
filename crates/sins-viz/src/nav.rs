//! A navigation experiment as a Rerun recording: error time series of several parameter sets on
//! one `time` timeline (sent column-wise), the north/east error trajectory as 2-D line strips,
//! segment annotations as a text log, and a blueprint that opens on a sensible layout
//! (trajectory beside the horizontal error, position / velocity / attitude errors and
//! temperatures below, the segment log at the bottom).

use crate::VizError;
use rerun::blueprint::{
    Blueprint, Horizontal, Spatial2DView, TextLogView, TimeSeriesView, Vertical,
};
use std::path::Path;

/// Name of the timeline every series is logged on (duration, seconds from the data start).
pub const TIMELINE: &str = "time";

/// One scalar time series.
#[derive(Clone, Debug)]
pub struct ScalarSeries {
    /// Entity path, e.g. `errors/position/north/42-state`. The first path component chooses the
    /// view it appears in (see [`NavRecording`]).
    pub entity: String,
    /// Sample times (s).
    pub times_s: Vec<f64>,
    /// Values (in the unit the entity name states).
    pub values: Vec<f64>,
}

/// A 2-D polyline, e.g. the north/east error trajectory (x = east, y = north, metres).
#[derive(Clone, Debug)]
pub struct Strip2 {
    /// Entity path under `trajectory/`.
    pub entity: String,
    /// Vertices.
    pub points: Vec<[f32; 2]>,
    /// RGBA colour.
    pub color: [u8; 4],
}

/// A text annotation at a time (segment starts).
#[derive(Clone, Debug)]
pub struct Annotation {
    /// Time (s).
    pub t_s: f64,
    /// Text.
    pub text: String,
}

/// Everything one navigation experiment logs. Entities are laid out by their first path
/// component: `trajectory/…` (2-D view), `errors/horizontal/…`, `errors/position/…`,
/// `errors/velocity/…`, `errors/attitude/…`, `temperature/…` (time-series views) and
/// `segments` (text log).
#[derive(Clone, Debug, Default)]
pub struct NavRecording {
    /// Scalar series.
    pub series: Vec<ScalarSeries>,
    /// Line strips (static).
    pub strips: Vec<Strip2>,
    /// Segment annotations.
    pub annotations: Vec<Annotation>,
}

fn layout() -> Blueprint {
    let ts = |name: &str, origin: &str| TimeSeriesView::new(name).with_origin(origin);
    Blueprint::new(Vertical::new([
        Horizontal::new([
            Spatial2DView::new("north/east error trajectory (m)")
                .with_origin("trajectory")
                .into(),
            ts("horizontal error (m)", "errors/horizontal").into(),
        ])
        .into(),
        Horizontal::new([
            ts("position error (m)", "errors/position").into(),
            ts("velocity error (m/s)", "errors/velocity").into(),
            ts("attitude error (arcsec)", "errors/attitude").into(),
        ])
        .into(),
        Horizontal::new([
            ts("accelerometer temperature (degC)", "temperature").into(),
            TextLogView::new("segments").with_origin("segments").into(),
        ])
        .into(),
    ]))
}

/// Write `rec` to an `.rrd` file (application `sinsbench`, recording `name`) with its blueprint.
pub fn write_navigation(path: &Path, name: &str, rec: &NavRecording) -> Result<(), VizError> {
    write_with_layout(path, name, rec, layout())
}

/// Write `rec` with a plain layout: one time-series view per `(title, entity origin)`, stacked,
/// and the text log of `segments` at the bottom when there are annotations.
pub fn write_timeseries(
    path: &Path,
    name: &str,
    rec: &NavRecording,
    views: &[(&str, &str)],
) -> Result<(), VizError> {
    let mut items: Vec<rerun::blueprint::ContainerLike> = views
        .iter()
        .map(|(title, origin)| TimeSeriesView::new(*title).with_origin(*origin).into())
        .collect();
    if !rec.annotations.is_empty() {
        items.push(TextLogView::new("segments").with_origin("segments").into());
    }
    write_with_layout(path, name, rec, Blueprint::new(Vertical::new(items)))
}

fn write_with_layout(
    path: &Path,
    name: &str,
    rec: &NavRecording,
    blueprint: Blueprint,
) -> Result<(), VizError> {
    let err = |e: &dyn std::fmt::Display| VizError::Rerun {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let (stream, storage) = crate::memory_stream(
        rerun::RecordingStreamBuilder::new("sinsbench")
            .recording_name(name)
            .with_blueprint(blueprint),
        path,
    )?;
    for s in &rec.series {
        let (times, values) = (s.times_s.iter().copied(), s.values.iter().copied());
        crate::send_scalars(&stream, s.entity.as_str(), TIMELINE, times, values)
            .map_err(|e| err(&e))?;
    }
    for s in &rec.strips {
        let strip = rerun::LineStrips2D::new([s.points.clone()]).with_colors([
            rerun::Color::from_unmultiplied_rgba(s.color[0], s.color[1], s.color[2], s.color[3]),
        ]);
        stream
            .log_static(s.entity.as_str(), &strip)
            .map_err(|e| err(&e))?;
    }
    for a in &rec.annotations {
        stream.set_duration_secs(TIMELINE, a.t_s);
        stream
            .log("segments", &rerun::TextLog::new(a.text.as_str()))
            .map_err(|e| err(&e))?;
    }
    crate::save_memory(&storage, path)
}
