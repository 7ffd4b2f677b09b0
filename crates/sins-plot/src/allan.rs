//! Allan-deviation plots: ADEV against averaging time on logarithmic axes (both
//! [`Panel::log_x`] and [`Panel::log_y`]; decade ticks labelled with the value, `0.01 .. 1000`
//! s), data with their confidence band and the fitted model, one panel per sensor triad.

use crate::color::series_color;
use crate::{Band, Figure, LegendPosition, Line, Panel};

/// One channel's Allan deviation (any rate unit, the same for all its vectors; values that are
/// not positive, or not finite, leave a gap on the log axes).
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

/// A figure of stacked Allan panels: a shared logarithmic x axis (`tau [s]`), a logarithmic y
/// axis per panel (`ADEV [unit]`).
pub fn allan_figure(title: &str, panels: &[AllanPanel<'_>]) -> Figure {
    let mut fig = Figure::new().title(title).share_x(true);
    for p in panels {
        let mut panel = Panel::new(p.title)
            .x_label("tau [s]")
            .y_label(format!("ADEV [{}]", p.unit))
            .log_x()
            .log_y()
            .legend(LegendPosition::TopRight);
        for (k, s) in p.series.iter().enumerate() {
            let color = series_color(k);
            panel = panel
                .band(Band::new("", s.tau_s, s.lo, s.hi).color(color))
                .line(Line::new(s.label, s.tau_s, s.adev).color(color));
            if !s.fit.is_empty() {
                panel = panel.line(
                    Line::new(format!("{} fit", s.label), s.tau_s, s.fit)
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
