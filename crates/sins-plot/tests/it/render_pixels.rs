//! Pixel-level checks of rendered figures: where lines, spans, bands and markers land.

use sins_plot::{Band, Figure, Line, Marker, Panel, Rgb, Span};

use crate::common::{RED, TEAL, bare_panel, px, render};

/// Clearly tinted towards red (line colour `RED` at any visible coverage).
fn reddish(c: Rgb) -> bool {
    i32::from(c.r) - i32::from(c.g) > 30 && i32::from(c.r) - i32::from(c.b) > 30
}

#[test]
fn horizontal_zero_line_lands_on_middle_row_and_spans_the_width() {
    let fig = Figure::new().panel(
        bare_panel()
            .x_range(0.0, 1.0)
            .y_range(-1.0, 1.0)
            .line(Line::new("", vec![0.0, 1.0], vec![0.0, 0.0]).color(RED)),
    );
    let (img, geo) = render(&fig);
    let a = geo[0].plot_area;
    let mid = a.y + a.height / 2;
    assert_eq!(geo[0].y_to_px(0.0).floor() as i32, mid);
    for x in a.x + 2..a.right() - 2 {
        assert_eq!(px(&img, x, mid), RED, "column {x}");
        assert!(!reddish(px(&img, x, mid - 3)), "row above, column {x}");
        assert!(!reddish(px(&img, x, mid + 3)), "row below, column {x}");
    }
    // The 2 px line covers exactly two pixels' worth per column.
    let ink: f64 = (a.y..a.bottom())
        .map(|y| 1.0 - f64::from(px(&img, a.x + a.width / 2, y).g) / 255.0)
        .sum();
    assert!((ink - 2.0).abs() < 0.05, "ink {ink}");
}

#[test]
fn line_is_clipped_to_the_plot_area() {
    let fig = Figure::new().panel(
        bare_panel()
            .x_range(0.0, 1.0)
            .y_range(-1.0, 1.0)
            .line(Line::new("", vec![-0.5, 0.5, 1.5], vec![-100.0, 100.0, -100.0]).color(RED)),
    );
    let (img, geo) = render(&fig);
    let a = geo[0].plot_area;
    let mut inside = 0;
    for y in 0..img.height() as i32 {
        for x in 0..img.width() as i32 {
            if reddish(px(&img, x, y)) {
                assert!(a.contains(x, y), "red pixel at ({x}, {y}) outside {a:?}");
                inside += 1;
            }
        }
    }
    assert!(inside > 2 * a.height as usize, "only {inside} red pixels");
}

#[test]
fn span_shades_exactly_the_columns_of_its_interval() {
    let panel = |w: f64| {
        bare_panel()
            .x_range(0.0, w)
            .y_range(0.0, 1.0)
            .span(Span::new("", 20.0, 40.0).color(TEAL).alpha(1.0))
    };
    // First pass: learn the plot width, then make one data unit one pixel column.
    let (_, geo) = render(&Figure::new().panel(panel(100.0)));
    let w = geo[0].plot_area.width;
    let (img, geo) = render(&Figure::new().panel(panel(f64::from(w - 1))));
    let a = geo[0].plot_area;
    assert_eq!(a.width, w);
    for y in [a.y, a.y + a.height / 2, a.bottom() - 1] {
        for x in a.x..a.right() {
            let expected = if (a.x + 20..=a.x + 40).contains(&x) {
                TEAL
            } else {
                Rgb::WHITE
            };
            assert_eq!(px(&img, x, y), expected, "column {} row {y}", x - a.x);
        }
    }
}

#[test]
fn decimation_keeps_a_single_sample_spike() {
    let n = 54_000;
    let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut y = vec![0.0; n];
    let k = 31_337;
    y[k] = 0.9;
    let fig = Figure::new().panel(
        bare_panel()
            .y_range(-1.0, 1.0)
            .line(Line::new("", x, y).color(RED)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    let col = g.x_to_px(k as f64).floor() as i32;
    let top = g.y_to_px(0.9).floor() as i32;
    assert!(reddish(px(&img, col, top)), "spike tip missing");
    assert!(
        reddish(px(&img, col, (top + g.y_to_px(0.0) as i32) / 2)),
        "spike body missing"
    );
    assert!(!reddish(px(&img, col + 6, top)), "spike smeared sideways");
}

#[test]
fn nan_gap_leaves_no_pixels() {
    let x: Vec<f64> = (0..=100).map(f64::from).collect();
    let y: Vec<f64> = x
        .iter()
        .map(|&v| {
            if (40.0..=60.0).contains(&v) {
                f64::NAN
            } else {
                0.5 * (v / 7.0).sin()
            }
        })
        .collect();
    let fig = Figure::new().panel(
        bare_panel()
            .x_range(0.0, 100.0)
            .y_range(-1.0, 1.0)
            .line(Line::new("", x, y).color(RED)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    let a = g.plot_area;
    let red_in = |c0: i32, c1: i32| {
        (c0..=c1)
            .flat_map(|x| (a.y..a.bottom()).map(move |y| (x, y)))
            .filter(|&(x, y)| reddish(px(&img, x, y)))
            .count()
    };
    let gap0 = g.x_to_px(39.0).floor() as i32 + 3;
    let gap1 = g.x_to_px(61.0).floor() as i32 - 3;
    assert_eq!(red_in(gap0, gap1), 0);
    assert!(red_in(a.x, gap0 - 4) > 0 && red_in(gap1 + 4, a.right() - 1) > 0);
}

#[test]
fn band_fills_between_curves_and_interpolates_sparse_points() {
    let fig = Figure::new().panel(
        bare_panel().x_range(0.0, 1.0).y_range(-1.0, 1.0).band(
            Band::new("", vec![0.0, 1.0], vec![-0.5, 0.0], vec![0.5, 0.6])
                .color(TEAL)
                .alpha(1.0),
        ),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    for xv in [0.1, 0.5, 0.9] {
        let c = g.x_to_px(xv).floor() as i32;
        let (lo, hi) = (-0.5 + 0.5 * xv, 0.5 + 0.1 * xv);
        let inside = g.y_to_px(0.5 * (lo + hi)).floor() as i32;
        assert_eq!(px(&img, c, inside), TEAL, "x = {xv}");
        assert_eq!(
            px(&img, c, g.y_to_px(hi + 0.05).floor() as i32),
            Rgb::WHITE,
            "above, x = {xv}"
        );
        assert_eq!(
            px(&img, c, g.y_to_px(lo - 0.05).floor() as i32),
            Rgb::WHITE,
            "below, x = {xv}"
        );
    }
}

#[test]
fn dashed_line_alternates_ink_and_gaps() {
    let fig = Figure::new().panel(
        bare_panel().x_range(0.0, 1.0).y_range(-1.0, 1.0).line(
            Line::new("", vec![0.0, 1.0], vec![0.0, 0.0])
                .color(RED)
                .dash_pattern_px(9.0, 6.0),
        ),
    );
    let (img, geo) = render(&fig);
    let a = geo[0].plot_area;
    let row = a.y + a.height / 2;
    let count =
        |f: &dyn Fn(Rgb) -> bool| (a.x..a.right()).filter(|&x| f(px(&img, x, row))).count() as f64;
    // Fully covered: 9 of every 15 px plus 0.5 px of each round cap (radius 1 px).
    let full = count(&|c| c == RED) / f64::from(a.width);
    assert!((0.6..0.74).contains(&full), "fully inked fraction {full}");
    // Any ink: 9 px plus the 1.5 px reach of each cap; the rest of the gap stays blank.
    let blank = count(&|c| c == Rgb::WHITE) / f64::from(a.width);
    assert!((0.15..0.25).contains(&blank), "blank fraction {blank}");
}

#[test]
fn marker_draws_a_vertical_line_at_its_x() {
    let fig = Figure::new().panel(
        bare_panel()
            .x_range(0.0, 10.0)
            .y_range(0.0, 1.0)
            .marker(Marker::new("fix", 2.5).color(RED)),
    );
    let (img, geo) = render(&fig);
    let g = &geo[0];
    let c = g.x_to_px(2.5).floor() as i32;
    let a = g.plot_area;
    for y in (a.y + 40..a.bottom()).step_by(7) {
        assert!(reddish(px(&img, c, y)), "row {y}");
        assert!(
            !reddish(px(&img, c - 3, y)) && !reddish(px(&img, c + 3, y)),
            "row {y}"
        );
    }
}

#[test]
fn shared_x_aligns_panels_and_uses_the_union_range() {
    let fig = Figure::new()
        .share_x(true)
        .panel(Panel::new("a").line(Line::new("a", vec![0.0, 5.0], vec![1.0, 2.0])))
        .panel(Panel::new("b").line(Line::new("b", vec![2.0, 15.0], vec![-1e6, 3e6])));
    let (img, geo) = render(&fig);
    assert_eq!(img.height(), 800);
    assert_eq!(geo[0].x_ticks, geo[1].x_ticks);
    assert_eq!((geo[0].x_ticks.lo, geo[0].x_ticks.hi), (0.0, 15.0));
    assert_eq!(geo[0].plot_area.x, geo[1].plot_area.x);
    assert_eq!(geo[0].plot_area.width, geo[1].plot_area.width);
    assert!(geo[0].plot_area.bottom() < geo[1].plot_area.y);
}
