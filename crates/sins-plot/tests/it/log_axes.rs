//! Logarithmic axes: where data land, gaps for non-positive values, decade ticks and their
//! labels, sub-decade ranges, and a shared x axis that must agree.

use sins_plot::{
    AllanPanel, AllanSeries, Figure, Line, Panel, PanelGeometry, PlotError, Rgb, RgbImage, Span,
    allan_figure, series_color,
};

use crate::common::{RED, TEAL, bare_panel, px, render};

/// How much red ink a pixel carries (0 white or grey, 1 pure red).
fn redness(c: Rgb) -> f64 {
    (f64::from(c.r) - f64::from(c.g)).max(0.0) / 255.0
}

fn reddish(c: Rgb) -> bool {
    redness(c) > 0.12
}

/// The red ink's centre (continuous image x) along row `y` of the plot area.
fn red_centroid_x(img: &RgbImage, g: &PanelGeometry, y: i32) -> f64 {
    let a = g.plot_area;
    let (mut sum, mut w) = (0.0, 0.0);
    for x in a.x..a.right() {
        let r = redness(px(img, x, y));
        sum += r * (f64::from(x) + 0.5);
        w += r;
    }
    assert!(w > 0.5, "no red ink in row {y}");
    sum / w
}

#[test]
fn ten_on_a_log_axis_from_1_to_100_lands_in_the_middle() {
    // A vertical line at x = 10 (linear y axis): its ink must sit at the middle of the plot
    // area (on a linear axis from 1 to 100 it would sit at 9/99 of the width).
    let fig = Figure::new().panel(
        bare_panel()
            .log_x()
            .x_range(1.0, 100.0)
            .y_range(0.0, 1.0)
            .line(Line::new("", vec![10.0, 10.0], vec![0.0, 1.0]).color(RED)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    let a = g.plot_area;
    let middle = f64::from(a.x) + f64::from(a.width) / 2.0;
    assert!(
        (g.x_to_px(10.0) - middle).abs() < 1e-9,
        "{}",
        g.x_to_px(10.0)
    );
    let c = red_centroid_x(&img, g, a.y + a.height / 2);
    assert!((c - middle).abs() < 0.5, "ink centre {c}, middle {middle}");
    // The axis is logarithmic, in data units, and spans exactly the fixed range.
    assert!(g.x_ticks.log && !g.y_ticks.log);
    assert_eq!((g.x_ticks.lo, g.x_ticks.hi), (1.0, 100.0));
    assert_eq!(g.x_ticks.values, [1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0]);
    assert_eq!(g.x_ticks.labels, ["1", "2", "5", "10", "20", "50", "100"]);
    // Decades are equally spaced; non-positive x has no position.
    let d1 = g.x_to_px(10.0) - g.x_to_px(1.0);
    let d2 = g.x_to_px(100.0) - g.x_to_px(10.0);
    assert!((d1 - d2).abs() < 1e-9 && d1 > 100.0, "{d1} {d2}");
    assert!(g.x_to_px(0.0).is_nan() && g.x_to_px(-3.0).is_nan());
}

#[test]
fn a_log_y_axis_puts_decades_equally_apart() {
    // y = x on a linear x axis from 0 to 1000, log y: the line reaches y = 1, 10, 100 at
    // x = 1, 10, 100, and those rows are equally spaced.
    let x: Vec<f64> = (1..=1000).map(f64::from).collect();
    let fig = Figure::new().panel(
        bare_panel()
            .log_y()
            .x_range(0.0, 1000.0)
            .line(Line::new("", x.clone(), x).color(RED)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    assert!(g.y_ticks.log);
    assert_eq!((g.y_ticks.lo, g.y_ticks.hi), (1.0, 1000.0));
    assert_eq!(g.y_ticks.labels, ["1", "10", "100", "1000"]);
    let (r1, r10, r100) = (g.y_to_px(1.0), g.y_to_px(10.0), g.y_to_px(100.0));
    assert!(((r1 - r10) - (r10 - r100)).abs() < 1e-9);
    // The line passes through (100, 100): red at that pixel, not 20 rows above or below.
    let (col, row) = (g.x_to_px(100.0).floor() as i32, r100.floor() as i32);
    assert!(reddish(px(&img, col, row)), "{:?}", px(&img, col, row));
    assert!(!reddish(px(&img, col, row - 20)) && !reddish(px(&img, col, row + 20)));
}

#[test]
fn non_positive_values_leave_gaps() {
    // log x: the point at x = 0 breaks the line between x = 10 and x = 100.
    let fig = Figure::new().panel(
        bare_panel()
            .log_x()
            .x_range(1.0, 1000.0)
            .y_range(0.0, 2.0)
            .line(Line::new("", vec![1.0, 10.0, 0.0, 100.0, 1000.0], vec![1.0; 5]).color(RED)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    let row = g.y_to_px(1.0).floor() as i32;
    for x in [2.0, 5.0, 200.0, 500.0] {
        let col = g.x_to_px(x).floor() as i32;
        assert!(reddish(px(&img, col, row)), "x = {x}: no line");
    }
    for x in [20.0, 30.0, 50.0] {
        let col = g.x_to_px(x).floor() as i32;
        let a = g.plot_area;
        assert!(
            (a.y..a.bottom()).all(|y| !reddish(px(&img, col, y))),
            "x = {x}: the gap is drawn"
        );
    }
    // log y: a negative and a zero y break the line; the automatic range ignores them.
    let fig = Figure::new().panel(
        bare_panel().log_y().x_range(0.0, 6.0).line(
            Line::new(
                "",
                vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
                vec![10.0, 10.0, -5.0, 10.0, 0.0, 10.0, 10.0],
            )
            .color(RED),
        ),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    assert_eq!(
        (g.y_ticks.lo, g.y_ticks.hi),
        (1.0, 100.0),
        "{:?}",
        g.y_ticks
    );
    let a = g.plot_area;
    let row = g.y_to_px(10.0).floor() as i32;
    assert!(reddish(px(&img, g.x_to_px(0.5).floor() as i32, row)));
    assert!(reddish(px(&img, g.x_to_px(5.5).floor() as i32, row)));
    for x in [1.5, 2.0, 2.5, 3.5, 4.0, 4.5] {
        let col = g.x_to_px(x).floor() as i32;
        assert!(
            (a.y..a.bottom()).all(|y| !reddish(px(&img, col, y))),
            "x = {x}: the gap is drawn"
        );
    }
}

#[test]
fn decade_ticks_are_labelled_with_the_value_and_drawn() {
    let x = vec![0.013, 0.2, 5.0, 870.0];
    let fig = Figure::new().panel(
        bare_panel()
            .log_x()
            .log_y()
            .line(Line::new("", x.clone(), x).color(RED)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    // x: the tight data range, the decades inside it.
    assert_eq!((g.x_ticks.lo, g.x_ticks.hi), (0.013, 870.0));
    assert_eq!(g.x_ticks.values, [0.1, 1.0, 10.0, 100.0]);
    assert_eq!(g.x_ticks.labels, ["0.1", "1", "10", "100"]);
    // y: widened to the enclosing decades.
    assert_eq!(
        g.y_ticks.values,
        [0.01, 0.1, 1.0, 10.0, 100.0, 1000.0],
        "{:?}",
        g.y_ticks
    );
    assert_eq!(g.y_ticks.labels, ["0.01", "0.1", "1", "10", "100", "1000"]);
    // Tick marks left of the frame (1 px outside the plot area): a major tick 5 px long at
    // y = 1, a minor one 3 px long at y = 2, nothing at y = 1.5.
    let a = g.plot_area;
    let black = |x: i32, y: i32| px(&img, x, y) == Rgb::BLACK;
    let row = |v: f64| g.y_to_px(v).floor() as i32;
    assert!(black(a.x - 6, row(1.0)) && black(a.x - 2, row(1.0)));
    assert!(black(a.x - 4, row(2.0)) && !black(a.x - 5, row(2.0)));
    assert!(!black(a.x - 3, row(1.5)));
    // Below the frame: a major tick at x = 10, a minor one at x = 30.
    let col = |v: f64| g.x_to_px(v).floor() as i32;
    assert!(black(col(10.0), a.bottom() + 5));
    assert!(black(col(30.0), a.bottom() + 3) && !black(col(30.0), a.bottom() + 4));
}

#[test]
fn sub_decade_ranges_still_get_two_labelled_ticks() {
    let fig = Figure::new().panel(
        bare_panel()
            .log_x()
            .log_y()
            .line(Line::new("", vec![2.12, 2.87], vec![2.3, 4.1]).color(RED)),
    );
    let (_, geo) = render(&fig);
    let g = &geo[0];
    // y widens to the enclosing decade, 1-2-5 ticks.
    assert_eq!(g.y_ticks.labels, ["1", "2", "5", "10"]);
    // x stays tight: at least two distinct labelled ticks inside it.
    let t = &g.x_ticks;
    assert!(t.values.len() >= 2, "{t:?}");
    assert!(t.values.iter().all(|v| (2.12..=2.87).contains(v)), "{t:?}");
    let mut labels = t.labels.clone();
    labels.dedup();
    assert_eq!(labels.len(), t.values.len(), "{t:?}");
}

#[test]
fn a_span_from_zero_on_a_log_axis_reaches_the_left_edge() {
    let fig = Figure::new().panel(
        bare_panel()
            .log_x()
            .x_range(1.0, 100.0)
            .y_range(0.0, 1.0)
            .span(Span::new("", 0.0, 10.0).color(TEAL).alpha(1.0)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    let a = g.plot_area;
    let mid_row = a.y + a.height / 2;
    let middle = g.x_to_px(10.0).floor() as i32;
    assert_eq!(px(&img, a.x, mid_row), TEAL);
    assert_eq!(px(&img, middle - 1, mid_row), TEAL);
    assert_ne!(px(&img, middle + 2, mid_row), TEAL);
}

#[test]
fn a_shared_x_axis_must_agree_on_log() {
    let line = || Line::new("", vec![1.0, 10.0], vec![1.0, 2.0]);
    let mixed = Figure::new()
        .share_x(true)
        .panel(Panel::new("a").log_x().line(line()))
        .panel(Panel::new("b").line(line()));
    match mixed.render() {
        Err(PlotError::SharedXScaleMismatch {
            panel: 1,
            panel_title,
            scale: "linear",
        }) => assert_eq!(panel_title, "b"),
        other => panic!("expected a scale mismatch, got {other:?}"),
    }
    // Not shared: each panel has its own axis.
    let separate = Figure::new()
        .panel(Panel::new("a").log_x().line(line()))
        .panel(Panel::new("b").line(line()));
    let (_, geo) = render(&separate);
    assert!(geo[0].x_ticks.log && !geo[1].x_ticks.log);
    // Shared and agreeing: one range over both panels.
    let shared = Figure::new()
        .share_x(true)
        .panel(Panel::new("a").log_x().line(line()))
        .panel(
            Panel::new("b")
                .log_x()
                .line(Line::new("", vec![0.5, 3.0], vec![1.0, 2.0])),
        );
    let (_, geo) = render(&shared);
    assert_eq!(geo[0].x_ticks, geo[1].x_ticks);
    assert_eq!((geo[1].x_ticks.lo, geo[1].x_ticks.hi), (0.5, 10.0));
}

#[test]
fn a_log_axis_needs_positive_fixed_bounds() {
    let bad = Figure::new().panel(Panel::new("p").log_y().y_range(0.0, 10.0));
    assert!(matches!(
        bad.render(),
        Err(PlotError::InvalidRange { axis: "y", .. })
    ));
    let bad = Figure::new().panel(Panel::new("p").log_x().x_range(-1.0, 10.0));
    assert!(matches!(
        bad.render(),
        Err(PlotError::InvalidRange { axis: "x", .. })
    ));
    let bad = Figure::new()
        .share_x(true)
        .x_range(0.0, 10.0)
        .panel(Panel::new("p").log_x());
    assert!(matches!(
        bad.render(),
        Err(PlotError::InvalidRange { axis: "x", .. })
    ));
}

#[test]
fn allan_figure_has_log_axes_labelled_with_values() {
    let tau: Vec<f64> = (0..12).map(|i| 0.01 * 2f64.powi(i)).collect();
    let adev: Vec<f64> = tau.iter().map(|t| 0.05 / t.sqrt()).collect();
    let lo: Vec<f64> = adev.iter().map(|a| 0.95 * a).collect();
    let hi: Vec<f64> = adev.iter().map(|a| 1.05 * a).collect();
    let s = AllanSeries {
        label: "x",
        tau_s: &tau,
        adev: &adev,
        lo: &lo,
        hi: &hi,
        fit: &[],
    };
    let panel = |title| AllanPanel {
        title,
        unit: "deg/h",
        series: vec![s],
    };
    let r = allan_figure("Allan", &[panel("gyro"), panel("accel")])
        .render()
        .unwrap_or_else(|e| panic!("{e}"));
    let g = &r.panels[1];
    // tau from 0.01 to 20.48 s; ADEV from 0.011 to 0.5, the band from 0.0105 to 0.525: the
    // y axis from 0.01 to 1 with 1-2-5 ticks.
    assert_eq!(g.x_ticks.labels, ["0.01", "0.1", "1", "10"]);
    assert_eq!((g.x_ticks.lo, g.x_ticks.hi), (0.01, tau[11]));
    assert_eq!(
        g.y_ticks.labels,
        ["0.01", "0.02", "0.05", "0.1", "0.2", "0.5", "1"]
    );
    // The ADEV line (slope -1/2 in log-log) through its sample at tau = 0.64 s (0.0625 deg/h):
    // the line's colour at that pixel, not 25 rows above or below (outside the +-5 % band).
    let col = g.x_to_px(0.64).floor() as i32;
    let row = g.y_to_px(0.05 / 0.8).floor() as i32;
    let near = |c: Rgb, d: i32| {
        let k = series_color(0);
        (i32::from(c.r) - i32::from(k.r)).abs() < d
            && (i32::from(c.g) - i32::from(k.g)).abs() < d
            && (i32::from(c.b) - i32::from(k.b)).abs() < d
    };
    assert!(
        near(px(&r.image, col, row), 40),
        "{:?}",
        px(&r.image, col, row)
    );
    assert!(!near(px(&r.image, col, row - 25), 80));
    assert!(!near(px(&r.image, col, row + 25), 80));
}
