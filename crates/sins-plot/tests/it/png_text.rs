//! PNG round trip, built-in font rendering, and error reporting.

use sins_plot::{
    Figure, Line, Panel, PlotError, Rgb, RgbImage, font_data::GLYPH_WIDTH_PX, text_width_px,
};

#[test]
fn png_decodes_to_the_rendered_pixels() {
    let fig = Figure::new()
        .size_px(640, 300)
        .title("round trip")
        .panel(Panel::new("p").line(Line::new("s", vec![0.0, 1.0, 2.0], vec![0.0, 1.0, 0.5])));
    let rendered = fig.render().unwrap_or_else(|e| panic!("{e}"));
    let bytes = fig.to_png_bytes().unwrap_or_else(|e| panic!("{e}"));
    let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
    let mut reader = decoder.read_info().unwrap_or_else(|e| panic!("{e}"));
    let size = reader
        .output_buffer_size()
        .unwrap_or_else(|| panic!("no buffer size"));
    let mut buf = vec![0; size];
    let info = reader
        .next_frame(&mut buf)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((info.width, info.height), (640, fig.total_height_px()));
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    assert_eq!(&buf[..info.buffer_size()], rendered.image.as_rgb_bytes());
}

#[test]
fn text_draws_the_glyph_bitmap() {
    let mut img = RgbImage::new(40, 30, Rgb::WHITE);
    img.draw_text(3, 2, "A", Rgb::BLACK, 1);
    // 'A' is ".###." then "#...#" from glyph row 1 (image row 3).
    let ink = |x, y| img.pixel(x, y) == Some(Rgb::BLACK);
    let row1: Vec<bool> = (3..8).map(|x| ink(x, 3)).collect();
    let row2: Vec<bool> = (3..8).map(|x| ink(x, 4)).collect();
    assert_eq!(row1, [false, true, true, true, false]);
    assert_eq!(row2, [true, false, false, false, true]);
    let crossbar: Vec<bool> = (3..8).map(|x| ink(x, 6)).collect();
    assert_eq!(crossbar, [true; 5]);
    let total = (0..40)
        .flat_map(|x| (0..30).map(move |y| (x, y)))
        .filter(|&(x, y)| ink(x, y))
        .count();
    assert_eq!(total, 3 + 2 * 2 + 5 + 3 * 2); // the 18 set bits of 'A'

    let mut big = RgbImage::new(40, 30, Rgb::WHITE);
    big.draw_text(3, 2, "A", Rgb::BLACK, 2);
    let big_total = (0..40)
        .flat_map(|x| (0..30).map(move |y| (x, y)))
        .filter(|&(x, y)| big.pixel(x, y) == Some(Rgb::BLACK))
        .count();
    assert_eq!(big_total, 4 * total);

    let mut blank = RgbImage::new(40, 30, Rgb::WHITE);
    blank.draw_text(3, 2, "   ", Rgb::BLACK, 1);
    assert!(blank.as_rgb_bytes().iter().all(|&b| b == 255));
    assert_eq!(text_width_px("abc", 1), 3 * GLYPH_WIDTH_PX - 1);
}

#[test]
fn every_printable_glyph_has_ink_and_glyphs_differ() {
    let mut seen = std::collections::HashSet::new();
    for code in 33u8..=126 {
        let mut img = RgbImage::new(8, 12, Rgb::WHITE);
        img.draw_text(1, 1, &char::from(code).to_string(), Rgb::BLACK, 1);
        assert!(
            img.as_rgb_bytes().contains(&0),
            "glyph {:?} is empty",
            char::from(code)
        );
        assert!(
            seen.insert(img.as_rgb_bytes().to_vec()),
            "glyph {:?} duplicates another",
            char::from(code)
        );
    }
}

#[test]
fn figure_title_renders_text_in_the_title_strip() {
    let panel = || Panel::new("").line(Line::new("", vec![0.0, 1.0], vec![0.0, 1.0]));
    let dark_rows = |fig: Figure| {
        let r = fig.render().unwrap_or_else(|e| panic!("{e}"));
        let top = r.panels[0].plot_area.y - 30; // above the panel title row
        (0..top)
            .flat_map(|y| (0..1200).map(move |x| (x, y)))
            .filter(|&(x, y)| r.image.pixel(x, y).is_some_and(|c| c.r < 100))
            .count()
    };
    assert_eq!(dark_rows(Figure::new().panel(panel())), 0);
    assert!(dark_rows(Figure::new().title("Horizontal error").panel(panel())) > 100);
}

#[test]
fn invalid_inputs_are_reported() {
    assert!(matches!(Figure::new().render(), Err(PlotError::NoPanels)));
    let mismatched =
        Figure::new().panel(Panel::new("p").line(Line::new("s", vec![0.0, 1.0], vec![0.0])));
    match mismatched.render() {
        Err(PlotError::LengthMismatch {
            x_len: 2,
            other_len: 1,
            ..
        }) => {}
        other => panic!("expected a length mismatch, got {other:?}"),
    }
    let inverted = Figure::new().panel(Panel::new("p").y_range(1.0, -1.0));
    assert!(matches!(
        inverted.render(),
        Err(PlotError::InvalidRange { axis: "y", .. })
    ));
    let tiny = Figure::new().size_px(50, 400).panel(Panel::new("p"));
    assert!(matches!(tiny.render(), Err(PlotError::InvalidSize { .. })));
    let wide = Figure::new()
        .panel(Panel::new("p").line(Line::new("s", vec![0.0], vec![0.0]).width_px(f32::NAN)));
    assert!(matches!(wide.render(), Err(PlotError::InvalidStyle { .. })));
}
