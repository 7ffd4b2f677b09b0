//! Renders a report-like 2-panel figure (4 series x 54 000 points, a +-3 sigma band, segment
//! spans, a marker), prints render and PNG-encoding times, writes the PNG.
//!
//! `cargo run --release -p sins-plot --example sample_figure -- [OUT.png]`
//! (default `/tmp/sins_plot_sample.png`).

use std::time::Instant;

use sins_plot::{Band, Figure, LegendPosition, Line, Marker, Panel, PlotError, Span};

/// Deterministic pseudo-random noise in [-1, 1) (xorshift64).
struct Noise(u64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

fn figure() -> Figure {
    let n = 54_000; // 15 h at 1 Hz
    let t_h: Vec<f64> = (0..n).map(|i| i as f64 / 3600.0).collect();
    let mut noise = Noise(0x9e37_79b9_7f4a_7c15);
    let schuler = |t: f64| (2.0 * std::f64::consts::PI * t * 60.0 / 84.4).sin();
    let err42: Vec<f64> = t_h
        .iter()
        .map(|&t| (0.05 * t + 0.12 * schuler(t).abs() + 0.004 * noise.next()).abs())
        .collect();
    let mut err30: Vec<f64> = t_h
        .iter()
        .map(|&t| (0.21 * t + 0.3 * schuler(t).abs() + 0.01 * noise.next()).abs())
        .collect();
    err30[30_000] = 4.8; // a one-sample outlier must stay visible
    for v in &mut err30[40_000..40_600] {
        *v = f64::NAN; // a gap in the record
    }
    let sigma: Vec<f64> = t_h.iter().map(|&t| 0.03 + 0.02 * t).collect();
    let lower: Vec<f64> = err42
        .iter()
        .zip(&sigma)
        .map(|(e, s)| (e - 3.0 * s).max(0.0))
        .collect();
    let upper: Vec<f64> = err42.iter().zip(&sigma).map(|(e, s)| e + 3.0 * s).collect();
    let temp = |t0: f64, k: f64, noise: &mut Noise| -> Vec<f64> {
        t_h.iter()
            .map(|&t| {
                t0 + k * (1.0 - (-t / 2.5).exp()) + 0.3 * (t * 1.3).sin() + 0.02 * noise.next()
            })
            .collect()
    };
    let temp_ax = temp(24.0, 17.0, &mut noise);
    let temp_az = temp(25.5, 14.0, &mut noise);
    let segments = [
        ("alignment", 0.0, 1.0 / 3.0),
        ("stationary", 1.0 / 3.0, 3.0),
        ("pattern1", 3.0, 6.5),
        ("pattern2", 6.5, 10.0),
        ("pattern3", 10.0, 13.0),
        ("stationary", 13.0, 15.0),
    ];
    let mut fig = Figure::new()
        .title("Experiment 1: navigation with calibrated parameters")
        .share_x(true);
    for (k, (label, a, b)) in segments.iter().enumerate() {
        fig = fig.span(Span::new(*label, *a, *b).color(sins_plot::span_color(k)));
    }
    fig.panel(
        Panel::new("Horizontal position error")
            .y_label("error [nmi]")
            .y_include(0.0)
            .band(Band::new(
                "42-state \u{b1}3\u{3c3}",
                t_h.clone(),
                lower,
                upper,
            ))
            .line(Line::new("42-state parameters", t_h.clone(), err42))
            .line(Line::new("30-state parameters", t_h.clone(), err30))
            .marker(Marker::new("heater off", 8.25).dashed()),
    )
    .panel(
        Panel::new("Accelerometer temperatures")
            .x_label("time [h]")
            .y_label("temperature [\u{b0}C]")
            .legend(LegendPosition::BottomRight)
            .line(Line::new("T ax", t_h.clone(), temp_ax))
            .line(Line::new("T az", t_h, temp_az).dashed()),
    )
}

fn main() -> Result<(), PlotError> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "/tmp/sins_plot_sample.png".into());
    let fig = figure();
    let runs = 10;
    let (mut render_ms, mut encode_ms) = (Vec::new(), Vec::new());
    let mut png = Vec::new();
    for _ in 0..runs {
        let t0 = Instant::now();
        let rendered = fig.render()?;
        let t1 = Instant::now();
        png = rendered.image.to_png_bytes()?;
        let t2 = Instant::now();
        render_ms.push((t1 - t0).as_secs_f64() * 1e3);
        encode_ms.push((t2 - t1).as_secs_f64() * 1e3);
    }
    render_ms.sort_by(f64::total_cmp);
    encode_ms.sort_by(f64::total_cmp);
    println!(
        "{}x{} px, 4 lines + 1 band x 54000 points: render median {:.1} ms (min {:.1}), PNG encode median {:.1} ms (min {:.1}), {} bytes, {runs} runs",
        1200,
        fig.total_height_px(),
        render_ms[runs / 2],
        render_ms[0],
        encode_ms[runs / 2],
        encode_ms[0],
        png.len()
    );
    if let Err(e) = std::fs::write(&out, &png) {
        eprintln!("cannot write {out}: {e}");
        std::process::exit(1);
    }
    println!("wrote {out}");
    Ok(())
}
