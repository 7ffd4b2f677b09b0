//! Allan-deviation plots: log-log ADEV against averaging time, data with their confidence band
//! and the fitted model, one panel per sensor triad. The chart axes are linear, so the plot
//! draws `log10` of both quantities and says so in the axis labels (tick `-1` is 0.1, `2` is
//! 100).

use crate::color::series_color;
use crate::{Band, Figure, LegendPosition, Line, Panel};

/// One channel's Allan deviation (any rate unit, the same for all its vectors; non-positive
/// values leave a gap).
#[derive(Debug, Clone, Copy)]
pub struct AllanSeries<'a> {
    /// Legend label (e.g. `x`).
    pub label: &'a str,
    /// Averaging times (s).
    pub tau_s: &'a [f64],
    /// Allan deviation.
    pub adev: &'a [f64],
    /// Lower end of its confidence interval.
    pub lo: &'a [f64],
    /// Upper end.
    pub hi: &'a [f64],
    /// Fitted model at the same `τ` (empty: none).
    pub fit: &'a [f64],
}

/// One panel: a title, the deviation's unit and its channels.
#[derive(Debug, Clone)]
pub struct AllanPanel<'a> {
    /// Panel title.
    pub title: &'a str,
    /// Unit of the deviations (e.g. `deg/h`).
    pub unit: &'a str,
    /// The channels.
    pub series: Vec<AllanSeries<'a>>,
}

fn log10s(v: &[f64]) -> Vec<f64> {
    v.iter()
        .map(|&x| {
            if x > 0.0 && x.is_finite() {
                x.log10()
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// A figure of stacked Allan panels (shared x axis).
pub fn allan_figure(title: &str, panels: &[AllanPanel<'_>]) -> Figure {
    let mut fig = Figure::new().title(title).share_x(true);
    for p in panels {
        let mut panel = Panel::new(p.title)
            .x_label("log10 tau [s]")
            .y_label(format!("log10 ADEV [{}]", p.unit))
            .legend(LegendPosition::TopRight);
        for (k, s) in p.series.iter().enumerate() {
            let color = series_color(k);
            let x = log10s(s.tau_s);
            panel = panel
                .band(Band::new("", x.clone(), log10s(s.lo), log10s(s.hi)).color(color))
                .line(Line::new(s.label, x.clone(), log10s(s.adev)).color(color));
            if !s.fit.is_empty() {
                panel = panel.line(
                    Line::new(format!("{} fit", s.label), x, log10s(s.fit))
                        .color(color)
                        .dashed(),
                );
            }
        }
        fig = fig.panel(panel);
    }
    fig
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn allan_figure_renders_a_png() {
        let tau: Vec<f64> = (0..12).map(|i| 0.01 * 2f64.powi(i)).collect();
        let adev: Vec<f64> = tau.iter().map(|t| 1.0 / t.sqrt()).collect();
        let lo: Vec<f64> = adev.iter().map(|a| 0.9 * a).collect();
        let hi: Vec<f64> = adev.iter().map(|a| 1.1 * a).collect();
        let s = AllanSeries {
            label: "x",
            tau_s: &tau,
            adev: &adev,
            lo: &lo,
            hi: &hi,
            fit: &adev,
        };
        let png = allan_figure(
            "Allan",
            &[AllanPanel {
                title: "gyro",
                unit: "deg/h",
                series: vec![s],
            }],
        )
        .to_png_bytes()
        .expect("png");
        assert_eq!(&png[1..4], b"PNG");
    }
}
