//! The UQ study's directory: one JSON file per sample (`samples/`, written as each sample ends,
//! so a study can run in shards and resume), then `summary.json`, `report.md`,
//! `intervals.png` (the Monte Carlo intervals beside the paper's points) and `sensitivity.png`
//! (first-order Sobol indices per assumption, grouped first-order and total indices when the
//! pick-freeze design ran). Every file is written aside and renamed into place.

use crate::ReportError;
use sins_plot::{Figure, Line, Panel, Rgb, SERIES_PALETTE};
use sins_uq::sample::SampleOutcome;
use sins_uq::summary::UqSummary;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` aside and renames it into place
/// ([`sins_files::write_file_atomically`]), the error naming `path`.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    sins_files::write_file_atomically(path, bytes).map_err(|e| ReportError::io(path, e))
}

/// The file of one sample.
pub fn sample_path(dir: &Path, study: &str, index: usize) -> PathBuf {
    dir.join("samples").join(format!("{study}-{index:05}.json"))
}

/// Writes one sample's outcome.
pub fn write_sample(dir: &Path, o: &SampleOutcome) -> Result<(), ReportError> {
    let path = sample_path(dir, &o.study, o.index);
    let json = serde_json::to_vec(o)
        .map_err(|e| ReportError::Mismatch(format!("{}: {e}", path.display())))?;
    write_atomic(&path, &json)
}

/// Reads one sample's outcome, if its file exists.
pub fn read_sample(path: &Path) -> Result<Option<SampleOutcome>, ReportError> {
    match std::fs::read(path) {
        Ok(bytes) => serde_json::from_slice(&bytes).map(Some).map_err(|e| {
            ReportError::Mismatch(format!(
                "{}: not a sample file ({e}); delete it to rerun the sample",
                path.display()
            ))
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(ReportError::io(path, e)),
    }
}

/// Writes `summary.json`, `report.md`, `intervals.png` and `sensitivity.png` into `dir`;
/// returns the file names.
pub fn write_uq_outputs(dir: &Path, summary: &UqSummary) -> Result<Vec<String>, ReportError> {
    let json =
        serde_json::to_string_pretty(summary).map_err(|e| ReportError::Mismatch(e.to_string()))?;
    write_atomic(&dir.join("summary.json"), format!("{json}\n").as_bytes())?;
    write_atomic(
        &dir.join("report.md"),
        crate::uq_markdown::render_uq_markdown(summary).as_bytes(),
    )?;
    let plot = |e: sins_plot::PlotError| ReportError::Mismatch(format!("plot: {e}"));
    write_atomic(
        &dir.join("intervals.png"),
        &intervals_figure(summary).to_png_bytes().map_err(plot)?,
    )?;
    write_atomic(
        &dir.join("sensitivity.png"),
        &sensitivity_figure(summary).to_png_bytes().map_err(plot)?,
    )?;
    Ok([
        "summary.json",
        "report.md",
        "intervals.png",
        "sensitivity.png",
    ]
    .map(String::from)
    .to_vec())
}

/// A vertical segment at `x` from `lo` to `hi`.
fn segment(label: &str, x: f64, lo: f64, hi: f64, color: Rgb, width: f32) -> Line {
    Line::new(label, vec![x, x], vec![lo, hi])
        .color(color)
        .width_px(width)
}

fn tick(label: &str, x: f64, y: f64, color: Rgb) -> Line {
    Line::new(label, vec![x - 0.15, x + 0.15], vec![y, y])
        .color(color)
        .width_px(3.0)
}

/// The 5-95 % intervals and medians per cell beside the paper's values (and the point replica):
/// errors (nmi) on a logarithmic axis, improvements (%) on a linear one.
pub fn intervals_figure(s: &UqSummary) -> Figure {
    // Errors are drawn as they are on the log axis: a value that is not positive (not expected
    // of a maximum error) or not finite leaves its bar or tick out (a gap), where the former
    // `v.max(1e-6).log10()` drew it at 1e-6 nmi and stretched the axis down to there.
    let mut err = Panel::new(
        "maximum horizontal error: Monte Carlo 5-95 % (bar), median, point replica, paper",
    )
    .log_y()
    .y_label("error [nmi]")
    .x_label("cell: exp1 without, exp1 with, exp2 without, ...");
    let mut imp = Panel::new("improvement: Monte Carlo 5-95 %, median, paper")
        .y_label("%")
        .x_label("experiment");
    let (mut xe, mut xi) = (0.0, 0.0);
    for c in &s.cells {
        let first = if c.cell.ends_with("improvement") {
            xi == 0.0
        } else {
            xe == 0.0
        };
        let lbl = |t: &str| if first { t.to_string() } else { String::new() };
        let paper = c.validation.as_ref().map(|v| v.d);
        if c.cell.ends_with("improvement") {
            xi += 1.0;
            imp = imp.line(segment(
                &lbl("5-95 %"),
                xi,
                c.p05,
                c.p95,
                SERIES_PALETTE[0],
                6.0,
            ));
            imp = imp.line(tick(&lbl("median"), xi, c.median, Rgb::BLACK));
            if let Some(d) = paper {
                imp = imp.line(tick(&lbl("paper"), xi + 0.3, d, SERIES_PALETTE[3]));
            }
        } else {
            xe += 1.0;
            err = err.line(segment(
                &lbl("5-95 %"),
                xe,
                c.p05,
                c.p95,
                SERIES_PALETTE[0],
                6.0,
            ));
            err = err.line(tick(&lbl("median"), xe, c.median, Rgb::BLACK));
            if c.point.is_finite() {
                err = err.line(tick(
                    &lbl("point replica"),
                    xe - 0.3,
                    c.point,
                    SERIES_PALETTE[1],
                ));
            }
            if let Some(d) = paper {
                err = err.line(tick(&lbl("paper"), xe + 0.3, d, SERIES_PALETTE[3]));
            }
        }
    }
    Figure::new()
        .title("Table 5 as a prediction: replica Monte Carlo against the paper")
        .panel(err.x_range(0.3, xe + 0.7))
        .panel(imp.x_range(0.3, xi + 0.7))
}

/// First-order Sobol indices of the leading assumptions (bars with their 90 % bootstrap
/// intervals) for the first experiment's three cells.
pub fn sensitivity_figure(s: &UqSummary) -> Figure {
    let mut fig = Figure::new()
        .title("Global sensitivity (first-order Sobol indices from the full runs, 90 % bootstrap)");
    for c in s.cells.iter().take(3) {
        let Some(sens) = &c.sensitivity else { continue };
        let title = format!(
            "{}: first-order index of the 6 leading assumptions (sum of all {:.2})",
            c.cell, sens.sum_first_order
        );
        let mut p = Panel::new(title).y_label("index").y_range(0.0, 1.0);
        let shown = sens.inputs.len().min(6);
        for (k, g) in sens.inputs.iter().take(shown).enumerate() {
            let x = k as f64 + 1.0;
            let color = SERIES_PALETTE[k % SERIES_PALETTE.len()];
            p = p.line(segment(&g.name, x, 0.0, g.first_order, color, 14.0));
            p = p.line(segment("", x + 0.2, g.low, g.high, Rgb::BLACK, 2.0));
        }
        fig = fig.panel(p.x_range(0.3, shown as f64 + 0.7));
        if !sens.groups.is_empty() {
            fig = fig.panel(group_panel(&c.cell, &sens.groups));
        }
    }
    fig
}

/// Total (wide bar) and first-order (narrow bar) index of every group with their intervals.
fn group_panel(cell: &str, groups: &[sins_uq::sobol::GroupIndex]) -> Panel {
    let mut p = Panel::new(format!(
        "{cell}: grouped total (wide) and first-order (narrow) indices, pick-freeze"
    ))
    .y_label("index")
    .y_range(-0.2, 1.2);
    for (k, g) in groups.iter().enumerate() {
        let x = k as f64 + 1.0;
        let color = SERIES_PALETTE[k % SERIES_PALETTE.len()];
        p = p.line(segment(&g.group, x, 0.0, g.total[0], color, 14.0));
        p = p.line(segment(
            "",
            x + 0.22,
            g.total[1],
            g.total[2],
            Rgb::BLACK,
            2.0,
        ));
        p = p.line(segment("", x - 0.22, 0.0, g.first_order[0], color, 4.0));
        p = p.line(segment(
            "",
            x - 0.3,
            g.first_order[1],
            g.first_order[2],
            Rgb::BLACK,
            1.0,
        ));
    }
    p.x_range(0.3, groups.len() as f64 + 0.7)
}
