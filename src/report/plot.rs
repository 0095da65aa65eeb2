//! Reusable line charts (plotters) written as SVG or PNG by the file's extension.
//!
//! The charts take plain data series so that every command (sweep, figures, the demo) can draw with them:
//! build a [`LineChart`] (or several for [`draw_panels`]) and call [`draw_line_chart`]. PNG text is drawn
//! with an embedded DejaVu Sans font (plotters' `ab_glyph` feature), so no system fonts or fontconfig are
//! needed; SVG text is left to the viewer.

// Negated comparisons (`!(a < b)`) are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::path::Path;
use std::sync::Once;

use anyhow::{anyhow, bail, Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::crisp_text::CrispText;

/// Pixel size of a single chart.
pub const CHART_SIZE: (u32, u32) = (1000, 640);

/// The embedded font (Bitstream Vera licence, see `fonts/LICENSE-DejaVu.txt`).
pub(super) static FONT_BYTES: &[u8] = include_bytes!("fonts/DejaVuSans.ttf");

/// Okabe–Ito colour-blind-safe palette; [`Series::color`] indexes it (modulo its length).
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(0, 0, 0),       // black
    RGBColor(240, 228, 66),  // yellow
];

/// Image format of an output file, chosen by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// Scalable vector graphics.
    Svg,
    /// Portable network graphics.
    Png,
}

impl ImageFormat {
    /// The format implied by `path`'s extension (`.svg` or `.png`, any case).
    pub fn from_path(path: &Path) -> Result<ImageFormat> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("svg") => Ok(ImageFormat::Svg),
            Some("png") => Ok(ImageFormat::Png),
            _ => bail!("plot file '{}': the extension must be .svg or .png", path.display()),
        }
    }

    /// The file extension without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            ImageFormat::Svg => "svg",
            ImageFormat::Png => "png",
        }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineKind {
    /// A solid line.
    Solid,
    /// A dashed line.
    Dashed,
    /// Markers only (measured points).
    Points,
    /// Markers only, of a given radius (pixels), filled or hollow (a hollow ring is drawn 2 px wide).
    Markers {
        /// Radius, px.
        radius: u32,
        /// Filled disc (true) or ring (false).
        filled: bool,
    },
}

/// One named data series.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Index into [`PALETTE`].
    pub color: usize,
    /// Line style.
    pub kind: LineKind,
}

impl Series {
    /// A solid series.
    pub fn solid(label: impl Into<String>, color: usize, points: Vec<(f64, f64)>) -> Series {
        Series { label: label.into(), points, color, kind: LineKind::Solid }
    }

    /// A dashed series.
    pub fn dashed(label: impl Into<String>, color: usize, points: Vec<(f64, f64)>) -> Series {
        Series { label: label.into(), points, color, kind: LineKind::Dashed }
    }
}

/// A vertical line across the plot at `x`, labelled in the legend (e.g. a mode node or the sweet spot).
#[derive(Debug, Clone, PartialEq)]
pub struct VerticalMarker {
    /// Position on the x axis.
    pub x: f64,
    /// Legend label; markers sharing a label share one legend entry.
    pub label: String,
    /// Index into [`PALETTE`].
    pub color: usize,
    /// Drawn dashed when true, solid otherwise.
    pub dashed: bool,
}

/// A shaded band across the plot between two x values (e.g. a tolerance around the sweet spot).
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    /// Left edge on the x axis.
    pub from: f64,
    /// Right edge on the x axis.
    pub to: f64,
    /// Legend label; bands sharing a label share one legend entry.
    pub label: String,
    /// Index into [`PALETTE`] (drawn at 15 % opacity).
    pub color: usize,
}

/// A line chart: title, axis labels (with units), series and vertical markers.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LineChart {
    /// Title above the plot.
    pub title: String,
    /// x-axis label, with units.
    pub x_label: String,
    /// y-axis label, with units.
    pub y_label: String,
    /// Data series.
    pub series: Vec<Series>,
    /// Vertical markers.
    pub markers: Vec<VerticalMarker>,
    /// Fixed x range; by default the data's.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; by default the data's with a margin.
    pub y_range: Option<(f64, f64)>,
    /// Draws a horizontal line at y = 0 (mode shapes).
    pub zero_line: bool,
    /// Shaded bands, drawn behind the series.
    pub bands: Vec<Band>,
    /// Legend in the upper right corner instead of the lower right (leave room for it with `y_range`).
    pub legend_upper_right: bool,
}

fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        for family in ["sans-serif", "serif", "monospace"] {
            // The bytes are a known-good TrueType file compiled into the binary; a failure here would be a
            // build defect, and text then falls back to plotters' error path (reported, not a panic).
            let _ = plotters::style::register_font(family, FontStyle::Normal, FONT_BYTES);
        }
    });
}

/// Draws `chart` into `path` (SVG or PNG by extension), creating the parent directory if needed.
pub fn draw_line_chart(path: &Path, chart: &LineChart) -> Result<()> {
    draw_panels(path, std::slice::from_ref(chart), 1, None)
}

/// Draws several charts in a grid of `columns` columns into one file, with an optional overall title.
pub fn draw_panels(path: &Path, charts: &[LineChart], columns: usize, title: Option<&str>) -> Result<()> {
    if charts.is_empty() {
        bail!("nothing to plot into '{}'", path.display());
    }
    let format = ImageFormat::from_path(path)?;
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| format!("cannot create directory '{}'", parent.display()))?;
    }
    register_fonts();
    let columns = columns.clamp(1, charts.len());
    let rows = charts.len().div_ceil(columns);
    let (panel_w, panel_h) = if charts.len() == 1 { CHART_SIZE } else { (760, 460) };
    let title_h = if title.is_some() { 50 } else { 0 };
    let size = (panel_w * columns as u32, panel_h * rows as u32 + title_h);
    let outcome = match format {
        ImageFormat::Svg => {
            let root = SVGBackend::new(path, size).into_drawing_area();
            render(&root, charts, columns, rows, title)
        }
        ImageFormat::Png => {
            let root = CrispText::new(BitMapBackend::new(path, size)).into_drawing_area();
            render(&root, charts, columns, rows, title)
        }
    };
    outcome.with_context(|| format!("cannot draw '{}'", path.display()))
}

fn render<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    charts: &[LineChart],
    columns: usize,
    rows: usize,
    title: Option<&str>,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(plot_err)?;
    let body = match title {
        Some(text) => root.titled(text, ("sans-serif", 30)).map_err(plot_err)?,
        None => root.clone(),
    };
    let panels = body.split_evenly((rows, columns));
    for (panel, chart) in panels.iter().zip(charts) {
        render_chart(panel, chart)?;
    }
    root.present().map_err(plot_err)?;
    Ok(())
}

fn plot_err<E: std::error::Error + Send + Sync>(err: plotters::drawing::DrawingAreaErrorKind<E>) -> anyhow::Error {
    anyhow!("plotting failed: {err}")
}

/// The data range of `values` padded by `margin` of its span (a flat range gets a unit span).
fn padded_range(values: impl Iterator<Item = f64>, margin: f64) -> Option<(f64, f64)> {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return None;
    }
    let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    Some((lo - margin * span, hi + margin * span))
}

/// Decimals that resolve about ten ticks over `range`.
fn tick_decimals(range: (f64, f64)) -> usize {
    let step = (range.1 - range.0).abs() / 10.0;
    if !(step > 0.0) || !step.is_finite() {
        return 2;
    }
    (-step.log10().floor()).clamp(0.0, 8.0) as usize
}

/// A tick label with `decimals` decimals and no "-0".
fn tick_label(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}

fn render_chart<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, chart: &LineChart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let all_points = || chart.series.iter().flat_map(|s| s.points.iter().copied());
    let x_range = chart
        .x_range
        .or_else(|| {
            let edges = chart.bands.iter().flat_map(|b| [b.from, b.to]);
            padded_range(all_points().map(|p| p.0).chain(chart.markers.iter().map(|m| m.x)).chain(edges), 0.0)
        })
        .ok_or_else(|| anyhow!("chart '{}' has no finite data", chart.title))?;
    let y_range = chart
        .y_range
        .or_else(|| padded_range(all_points().map(|p| p.1), 0.08))
        .ok_or_else(|| anyhow!("chart '{}' has no finite data", chart.title))?;
    let mut ctx = ChartBuilder::on(area)
        .caption(&chart.title, ("sans-serif", 24))
        .margin(14)
        .x_label_area_size(48)
        .y_label_area_size(70)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(plot_err)?;
    let x_decimals = tick_decimals(x_range);
    let y_decimals = tick_decimals(y_range);
    let x_format = move |v: &f64| tick_label(*v, x_decimals);
    let y_format = move |v: &f64| tick_label(*v, y_decimals);
    ctx.configure_mesh()
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .x_desc(chart.x_label.as_str())
        .y_desc(chart.y_label.as_str())
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(plot_err)?;

    let mut band_labels: Vec<&str> = Vec::new();
    for band in &chart.bands {
        let color = PALETTE[band.color % PALETTE.len()];
        let rect = Rectangle::new([(band.from, y_range.0), (band.to, y_range.1)], color.mix(0.15).filled());
        let drawn = ctx.draw_series(std::iter::once(rect)).map_err(plot_err)?;
        if !band_labels.contains(&band.label.as_str()) {
            band_labels.push(band.label.as_str());
            drawn
                .label(band.label.as_str())
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 24, y + 5)], color.mix(0.3).filled()));
        }
    }

    if chart.zero_line {
        ctx.draw_series(LineSeries::new([(x_range.0, 0.0), (x_range.1, 0.0)], BLACK.mix(0.5))).map_err(plot_err)?;
    }

    for series in &chart.series {
        let color = PALETTE[series.color % PALETTE.len()];
        let style = color.stroke_width(2);
        let points: Vec<(f64, f64)> =
            series.points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
        let drawn = match series.kind {
            LineKind::Solid => ctx.draw_series(LineSeries::new(points, style)).map_err(plot_err)?,
            LineKind::Dashed => ctx.draw_series(DashedLineSeries::new(points, 9, 6, style)).map_err(plot_err)?,
            LineKind::Points => {
                ctx.draw_series(points.into_iter().map(|p| Circle::new(p, 3, color.filled()))).map_err(plot_err)?
            }
            LineKind::Markers { radius, filled } => {
                let style = if filled { color.filled() } else { color.stroke_width(2) };
                ctx.draw_series(points.into_iter().map(|p| Circle::new(p, radius, style))).map_err(plot_err)?
            }
        };
        let kind = series.kind;
        drawn.label(series.label.as_str()).legend(move |(x, y)| legend_glyph(x, y, color, kind));
    }

    let mut labelled: Vec<&str> = Vec::new();
    for marker in &chart.markers {
        let color = PALETTE[marker.color % PALETTE.len()];
        let style = color.mix(0.85).stroke_width(2);
        let segment = [(marker.x, y_range.0), (marker.x, y_range.1)];
        let drawn = if marker.dashed {
            ctx.draw_series(DashedLineSeries::new(segment, 6, 5, style)).map_err(plot_err)?
        } else {
            ctx.draw_series(LineSeries::new(segment, style)).map_err(plot_err)?
        };
        if !labelled.contains(&marker.label.as_str()) {
            labelled.push(marker.label.as_str());
            let kind = if marker.dashed { LineKind::Dashed } else { LineKind::Solid };
            drawn.label(marker.label.as_str()).legend(move |(x, y)| legend_glyph(x, y, color, kind));
        }
    }

    if !chart.series.is_empty() || !chart.markers.is_empty() {
        ctx.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .label_font(("sans-serif", 15))
            .position(if chart.legend_upper_right {
                SeriesLabelPosition::UpperRight
            } else {
                SeriesLabelPosition::LowerRight
            })
            .draw()
            .map_err(plot_err)?;
    }
    Ok(())
}

/// The legend sample of a series. Every kind is the same composite (two segments and a dot, the unused
/// parts transparent) because the legend closure must return one concrete type.
fn legend_glyph<'a, DB: DrawingBackend + 'a>(
    x: i32,
    y: i32,
    color: RGBColor,
    kind: LineKind,
) -> impl IntoDynElement<'a, DB, (i32, i32)> + 'a {
    let line = color.stroke_width(2);
    let hidden = color.mix(0.0).stroke_width(1);
    let (first, second, dot) = match kind {
        LineKind::Solid => (line, line, hidden),
        LineKind::Dashed => (line, line, hidden),
        LineKind::Points | LineKind::Markers { filled: true, .. } => (hidden, hidden, color.filled()),
        LineKind::Markers { filled: false, .. } => (hidden, hidden, color.stroke_width(1)),
    };
    let gap = if kind == LineKind::Dashed { 5 } else { 0 };
    EmptyElement::at((x, y))
        + PathElement::new(vec![(0, 0), (12 - gap, 0)], first)
        + PathElement::new(vec![(12, 0), (24, 0)], second)
        + Circle::new((12, 0), 3, dot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_follows_extension() {
        assert_eq!(ImageFormat::from_path(Path::new("a/b.SVG")).ok(), Some(ImageFormat::Svg));
        assert_eq!(ImageFormat::from_path(Path::new("b.png")).ok(), Some(ImageFormat::Png));
        assert!(ImageFormat::from_path(Path::new("b.jpg")).is_err());
        assert!(ImageFormat::from_path(Path::new("b")).is_err());
    }

    #[test]
    fn tick_labels_are_clean() {
        assert_eq!(tick_label(-0.0, 1), "0.0");
        assert_eq!(tick_label(-1e-17, 1), "0.0");
        assert_eq!(tick_label(-0.5, 1), "-0.5");
        assert_eq!(tick_decimals((0.0, 50.0)), 0);
        assert_eq!(tick_decimals((0.5, 0.84)), 2);
    }

    #[test]
    fn padded_range_handles_flat_and_empty_data() {
        assert_eq!(padded_range([2.0, 2.0].into_iter(), 0.5), Some((1.0, 3.0)));
        assert_eq!(padded_range(std::iter::empty(), 0.1), None);
        assert_eq!(padded_range([f64::NAN, 1.0, 3.0].into_iter(), 0.5), Some((0.0, 4.0)));
    }
}
