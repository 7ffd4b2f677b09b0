//! Writing a diagnosis directory atomically (every file written aside and renamed, the directory
//! staged and swapped in; a path in the way that is not a previous diagnosis is refused):
//! `report.md`, `diagnosis.json`, one PNG per run and
//! `diagnosis.rrd`.

use crate::GapError;
use crate::run::DiagnosisOutcome;
use sins_diag::events::TimeLocalEvent;
use sins_diag::report::RunSeries;
use sins_plot::{Band, Figure, Line, Marker, Panel, series_color};
use sins_report::ReportError;
use sins_viz::{NavRecording, ScalarSeries};
use std::path::{Path, PathBuf};

/// The gap of one run with the twin's envelope, the fitted effect and a marker at the onset of
/// each time-local event of the run.
fn plot_run(s: &RunSeries, events: &[TimeLocalEvent]) -> Result<Vec<u8>, sins_plot::PlotError> {
    let t_h: Vec<f64> = s.t_s.iter().map(|t| t / 3600.0).collect();
    let panel = |channel: &str, gap: &[f64], sigma: &[f64], fitted: &[f64]| {
        let lo: Vec<f64> = sigma.iter().map(|v| -3.0 * v).collect();
        let hi: Vec<f64> = sigma.iter().map(|v| 3.0 * v).collect();
        let markers = events.iter().filter(|e| e.run == s.run).map(|e| {
            Marker::new(format!("{} {}", e.channel, e.shape), e.onset_s / 3600.0)
                .color(series_color(3))
                .dashed()
        });
        markers
            .fold(
                Panel::new(format!("{}: {channel} position gap (real - twin)", s.run)),
                |p, m| p.marker(m),
            )
            .y_label("gap [m]")
            .x_label("time [h]")
            .band(Band::new("twin 3-sigma envelope", t_h.clone(), lo, hi).color(series_color(1)))
            .line(Line::new("real - twin", t_h.clone(), gap.to_vec()).color(series_color(0)))
            .line(
                Line::new("fitted effect", t_h.clone(), fitted.to_vec())
                    .color(series_color(2))
                    .dashed(),
            )
    };
    Figure::new()
        .size_px(1600, 380)
        .share_x(true)
        .panel(panel(
            "north",
            &s.gap_north_m,
            &s.sigma_north_m,
            &s.fitted_north_m,
        ))
        .panel(panel(
            "east",
            &s.gap_east_m,
            &s.sigma_east_m,
            &s.fitted_east_m,
        ))
        .to_png_bytes()
}

fn recording(o: &DiagnosisOutcome) -> NavRecording {
    let mut rec = NavRecording::default();
    for s in &o.diagnosis.series {
        for (ch, gap, sigma, fitted) in [
            ("north", &s.gap_north_m, &s.sigma_north_m, &s.fitted_north_m),
            ("east", &s.gap_east_m, &s.sigma_east_m, &s.fitted_east_m),
        ] {
            let mut add = |what: &str, values: Vec<f64>| {
                rec.series.push(ScalarSeries {
                    entity: format!("gap/{}/{ch}/{what}", s.run),
                    times_s: s.t_s.clone(),
                    values,
                })
            };
            add("real_minus_twin_m", gap.clone());
            add("plus_3_sigma_m", sigma.iter().map(|v| 3.0 * v).collect());
            add("minus_3_sigma_m", sigma.iter().map(|v| -3.0 * v).collect());
            add("fitted_effect_m", fitted.clone());
        }
    }
    rec
}

/// Write the diagnosis into `<dir_parent>/<name>/`, replacing an existing one only when complete.
pub fn write_diagnosis(
    dir_parent: &Path,
    name: &str,
    o: &DiagnosisOutcome,
) -> Result<PathBuf, GapError> {
    let files = sins_report::write_dir_atomically(dir_parent, name, "diagnose", |dir| {
        let mut files = Vec::new();
        let mut plots = Vec::new();
        for s in &o.diagnosis.series {
            let png = plot_run(s, &o.diagnosis.events.events)
                .map_err(|e| ReportError::Mismatch(format!("plot of run {}: {e}", s.run)))?;
            let f = format!("gap_{}.png", s.run);
            sins_report::write_bytes(&dir.join(&f), &png)?;
            plots.push(f.clone());
            files.push(f);
        }
        let views: Vec<(String, String)> = o
            .diagnosis
            .series
            .iter()
            .flat_map(|s| {
                ["north", "east"].map(|ch| {
                    (
                        format!("{} {ch} gap vs twin 3-sigma (m)", s.run),
                        format!("gap/{}/{ch}", s.run),
                    )
                })
            })
            .collect();
        let view_refs: Vec<(&str, &str)> = views
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect();
        sins_viz::write_timeseries(&dir.join("diagnosis.rrd"), name, &recording(o), &view_refs)?;
        files.push("diagnosis.rrd".into());
        let json = serde_json::to_string_pretty(o)
            .map_err(|e| ReportError::Mismatch(format!("serialising the diagnosis: {e}")))?;
        sins_report::write_bytes(&dir.join("diagnosis.json"), json.as_bytes())?;
        files.push("diagnosis.json".into());
        let md = crate::markdown::render_markdown(o, &plots);
        sins_report::write_bytes(&dir.join("report.md"), md.as_bytes())?;
        files.push("report.md".into());
        Ok(files)
    })?;
    Ok(files.dir)
}
