//! PNG plots of one experiment: the horizontal error and its north / east components against
//! time, one panel per parameter set (each on its own scale), with the segments shaded, and the
//! accelerometer temperatures.

use crate::ReportError;
use crate::run::ResolvedSet;
use sins_harness::pipeline::RunOutcome;
use sins_harness::segments::SegmentStretch;
use sins_plot::{Figure, Line, Panel, Span, series_color, span_color};

/// Colour of a segment label: one palette entry per distinct label, stationary stretches light.
fn span_for(s: &SegmentStretch, labels: &mut Vec<String>) -> Span {
    let i = labels
        .iter()
        .position(|l| l == &s.label)
        .unwrap_or_else(|| {
            labels.push(s.label.clone());
            labels.len() - 1
        });
    Span::new(s.display_name(), s.start_s / 3600.0, s.end_s / 3600.0).color(span_color(i))
}

fn spans(o: &RunOutcome) -> Vec<Span> {
    let mut labels = Vec::new();
    o.tracks
        .first()
        .map(|t| {
            t.stretches
                .iter()
                .map(|s| span_for(s, &mut labels))
                .collect()
        })
        .unwrap_or_default()
}

fn err(what: &str, run: &str, e: sins_plot::PlotError) -> ReportError {
    ReportError::Mismatch(format!("plot '{what}' of {run}: {e}"))
}

/// True when the run recorded accelerometer temperatures.
pub(crate) fn has_temperatures(o: &RunOutcome) -> bool {
    o.temperatures
        .iter()
        .any(|p| p.temp_degc.iter().any(|v| v.is_finite()))
}

/// The plots of one experiment as (name, PNG bytes).
pub(crate) fn render(
    o: &RunOutcome,
    sets: &[ResolvedSet],
) -> Result<Vec<(&'static str, Vec<u8>)>, ReportError> {
    // One panel per parameter set, each on its own scale: the 30-state track can end 160 km
    // off while the 42-state one stays within 3 km, which one shared axis flattens to a line.
    let mut errors = Figure::new().size_px(1600, 420).share_x(true);
    let n = o.tracks.len();
    for (i, t) in o.tracks.iter().enumerate() {
        let label = sets
            .iter()
            .find(|s| s.key == t.set)
            .map_or(t.set.clone(), |s| format!("{}: {}", s.key, s.label));
        let x: Vec<f64> = t.points.iter().map(|p| p.t_s / 3600.0).collect();
        let km = |f: &dyn Fn(&sins_harness::ErrorPoint) -> f64| -> Vec<f64> {
            t.points.iter().map(|p| f(p) / 1000.0).collect()
        };
        let mut panel = Panel::new(format!(
            "{}: position error with {label} (horizontal; north solid, east dashed)",
            o.run
        ))
        .y_label("error [km]")
        .y_include(0.0)
        .line(Line::new("horizontal", x.clone(), km(&|p| p.horizontal_m())).color(series_color(i)))
        .line(Line::new("north", x.clone(), km(&|p| p.north_m)).color(series_color(n + 2 * i)))
        .line(
            Line::new("east", x, km(&|p| p.east_m))
                .color(series_color(n + 2 * i + 1))
                .dashed(),
        );
        if i + 1 == n {
            panel = panel.x_label("time [h]");
        }
        errors = errors.panel(panel);
    }
    for s in spans(o) {
        errors = errors.span(s);
    }
    let errors_png = errors
        .to_png_bytes()
        .map_err(|e| err("errors", &o.run, e))?;

    if !has_temperatures(o) {
        return Ok(vec![("errors", errors_png)]);
    }
    let x: Vec<f64> = o.temperatures.iter().map(|p| p.t_s / 3600.0).collect();
    let mut temps = Panel::new(format!(
        "{}: accelerometer temperatures (thermometer readings, 1 s means)",
        o.run
    ))
    .x_label("time [h]")
    .y_label("temperature [degC]");
    for (j, axis) in ["x", "y", "z"].into_iter().enumerate() {
        let y: Vec<f64> = o.temperatures.iter().map(|p| p.temp_degc[j]).collect();
        if y.iter().any(|v| v.is_finite()) {
            temps = temps.line(
                Line::new(format!("accelerometer {axis}"), x.clone(), y).color(series_color(j + 2)),
            );
        }
    }
    let mut temperature = Figure::new().size_px(1600, 360).panel(temps);
    for s in spans(o) {
        temperature = temperature.span(s);
    }
    let temperature_png = temperature
        .to_png_bytes()
        .map_err(|e| err("temperature", &o.run, e))?;
    Ok(vec![
        ("errors", errors_png),
        ("temperature", temperature_png),
    ])
}
