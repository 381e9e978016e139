//! Line plots written as PNG (plotters on an in-memory bitmap, encoded with `image`), on linear
//! axes ([`save_panels`]) or logarithmic ones ([`save_log_log`]).

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

use crate::error::{Error, Result};

/// One curve.
#[derive(Clone, Debug, Default)]
pub struct Line {
    /// Legend text.
    pub label: String,
    /// Points `(x, y)`.
    pub points: Vec<(f64, f64)>,
    /// Index into the palette.
    pub color: usize,
    /// Draw a dot at every point (for curves of a few points).
    pub markers: bool,
}

/// Where a chart's legend goes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Legend {
    /// Lower left corner.
    #[default]
    LowerLeft,
    /// Lower right corner.
    LowerRight,
    /// Upper right corner.
    UpperRight,
}

/// One chart of a figure.
#[derive(Clone, Debug, Default)]
pub struct Panel {
    /// Caption above the chart.
    pub title: String,
    /// Axis labels.
    pub x_label: String,
    /// Axis labels.
    pub y_label: String,
    /// The curves.
    pub lines: Vec<Line>,
    /// Legend position.
    pub legend: Legend,
}

const PALETTE: [RGBColor; 11] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(0, 0, 0),
];

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        // The bundled font is valid; if registration failed, text would be missing, not wrong.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../../assets/fonts/DejaVuSans.ttf"),
        );
    });
}

fn plot_error(e: impl std::fmt::Display) -> Error {
    Error::Report(format!("plotting: {e}"))
}

/// Writes `text` onto `img` with its top left corner at `(x, y)` (px), `size` px tall, in dark
/// grey on a light box: the labels of side-by-side images.
pub fn label(img: &mut image::RgbaImage, (x, y): (i32, i32), text: &str, size: f64) -> Result<()> {
    register_font();
    let (w, h) = img.dimensions();
    let mut rgb: Vec<u8> = img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect();
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        let font = ("sans-serif", size).into_font().color(&RGBColor(25, 25, 30));
        let (tw, th) = root.estimate_text_size(text, &font).map_err(plot_error)?;
        let pad = (size / 4.0).ceil() as i32;
        let corner = (x + tw as i32 + 2 * pad, y + th as i32 + 2 * pad);
        root.draw(&Rectangle::new([(x, y), corner], RGBColor(245, 245, 245).mix(0.85).filled())).map_err(plot_error)?;
        root.draw_text(text, &font, (x + pad, y + pad)).map_err(plot_error)?;
        root.present().map_err(plot_error)?;
    }
    for (p, c) in img.pixels_mut().zip(rgb.chunks_exact(3)) {
        p.0[..3].copy_from_slice(c);
    }
    Ok(())
}

/// Writes `panels` as a grid of `cols` columns, each chart `panel_size` pixels, to `path`.
pub fn save_panels(path: &Path, title: &str, panels: &[Panel], cols: usize, panel_size: (u32, u32)) -> Result<()> {
    register_font();
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let (w, h) = (panel_size.0 * cols as u32, panel_size.1 * rows as u32 + 40);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        let root = root.titled(title, ("sans-serif", 22)).map_err(plot_error)?;
        let areas = root.split_evenly((rows, cols));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            draw_panel(panel, area)?;
        }
        root.present().map_err(plot_error)?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).ok_or_else(|| plot_error("buffer size"))?;
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) })
}

fn draw_panel<DB: DrawingBackend>(panel: &Panel, area: &DrawingArea<DB, plotters::coord::Shift>) -> Result<()> {
    let pts = panel.lines.iter().flat_map(|l| l.points.iter()).filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let pad = ((y1 - y0) * 0.05).max(1e-9);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(32)
        .y_label_area_size(56)
        .build_cartesian_2d(x0..x1.max(x0 + 1e-9), (y0 - pad)..(y1 + pad))
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(plot_error)?;
    for line in &panel.lines {
        let color = PALETTE[line.color % PALETTE.len()];
        let points = line.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite());
        chart
            .draw_series(LineSeries::new(points, color.stroke_width(2)))
            .map_err(plot_error)?
            .label(line.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
        if line.markers {
            let points = line.points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite());
            chart.draw_series(points.map(|p| Circle::new(p, 4, color.filled()))).map_err(plot_error)?;
        }
    }
    draw_legend(&mut chart, panel.legend)
}

/// Writes one chart with logarithmic axes (both positive; other points are left out) to `path`,
/// `size` pixels: for costs that span decades, such as time per frame against problem size.
pub fn save_log_log(path: &Path, panel: &Panel, size: (u32, u32)) -> Result<()> {
    register_font();
    let (w, h) = size;
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_error)?;
        draw_log_log(panel, &root)?;
        root.present().map_err(plot_error)?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).ok_or_else(|| plot_error("buffer size"))?;
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) })
}

fn draw_log_log<DB: DrawingBackend>(panel: &Panel, area: &DrawingArea<DB, plotters::coord::Shift>) -> Result<()> {
    let positive = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && p.0 > 0.0 && p.1 > 0.0;
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in panel.lines.iter().flat_map(|l| l.points.iter()).filter(|p| positive(p)) {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (1.0, 10.0, 1.0, 10.0);
    }
    // A margin of a fifth of a decade (×1.58) on each side.
    let (mx, my) = (10f64.powf(0.2), 10f64.powf(0.2));
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(64)
        .build_cartesian_2d((x0 / mx..x1 * mx).log_scale(), (y0 / my..y1 * my).log_scale())
        .map_err(plot_error)?;
    chart
        .configure_mesh()
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .x_label_formatter(&log_label)
        .y_label_formatter(&log_label)
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(plot_error)?;
    for line in &panel.lines {
        let color = PALETTE[line.color % PALETTE.len()];
        let points: Vec<(f64, f64)> = line.points.iter().copied().filter(positive).collect();
        chart
            .draw_series(LineSeries::new(points.iter().copied(), color.stroke_width(2)))
            .map_err(plot_error)?
            .label(line.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
        if line.markers {
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled()))).map_err(plot_error)?;
        }
    }
    draw_legend(&mut chart, panel.legend)
}

/// A logarithmic axis label: 1, 2 and 5 times a power of ten, compact (`20k`, `1M`, `0.5`);
/// other ticks unlabelled.
fn log_label(v: &f64) -> String {
    if !(v.is_finite() && *v > 0.0) {
        return String::new();
    }
    let e = v.log10().floor();
    let m = v / 10f64.powf(e);
    if ![1.0, 2.0, 5.0].iter().any(|k| (m - k).abs() < 1e-6 * k) {
        return String::new();
    }
    let (scaled, suffix) = if *v >= 1e6 {
        (v / 1e6, "M")
    } else if *v >= 1e3 {
        (v / 1e3, "k")
    } else {
        (*v, "")
    };
    let text = format!("{scaled:.3}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    format!("{text}{suffix}")
}

/// The series labels of `chart`, boxed, at the panel's legend corner.
fn draw_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    legend: Legend,
) -> Result<()> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .position(match legend {
            Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
            Legend::LowerRight => SeriesLabelPosition::LowerRight,
            Legend::UpperRight => SeriesLabelPosition::UpperRight,
        })
        .draw()
        .map_err(plot_error)
}

#[cfg(test)]
mod tests {
    use super::log_label;

    #[test]
    fn log_labels_name_one_two_five_only() {
        assert_eq!(log_label(&20_000.0), "20k");
        assert_eq!(log_label(&1_000_000.0), "1M");
        assert_eq!(log_label(&0.5), "0.5");
        assert_eq!(log_label(&100.0), "100");
        assert_eq!(log_label(&30_000.0), "");
    }
}
