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

pub mod legend;

use super::crisp_text::{CrispText, FONT_BYTES};
use legend::PlotSize;

/// Pixel size of a single chart.
pub const CHART_SIZE: (u32, u32) = (1000, 640);

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

/// Bars from `low` to `high` (an interquartile range, a ± σ), with caps, in one legend entry: vertical at x,
/// or horizontal at y.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ErrorBars {
    /// Legend label.
    pub label: String,
    /// Index into [`PALETTE`].
    pub color: usize,
    /// (x, low y, high y) of each vertical bar, or (y, low x, high x) of each horizontal one.
    pub bars: Vec<(f64, f64, f64)>,
    /// Horizontal bars (an uncertainty in x).
    pub horizontal: bool,
}

/// Where the legend sits inside the plot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendAt {
    /// Lower right corner.
    #[default]
    LowerRight,
    /// Upper right corner.
    UpperRight,
    /// Upper left corner.
    UpperLeft,
    /// Lower left corner.
    LowerLeft,
    /// Bottom, centred.
    LowerMiddle,
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
    /// The legend's corner (leave room for it with `y_range`).
    pub legend: LegendAt,
    /// Error bars, drawn over the series.
    pub error_bars: Vec<ErrorBars>,
    /// Lines of explanation printed under the plot (what a label such as "e0" means).
    pub notes: Vec<String>,
}

/// Height of one line of [`LineChart::notes`], px.
const NOTE_LINE: u32 = 20;

/// The parts of the polyline `points` inside the rectangle `x` × `y`: each segment is clipped to it
/// (Liang–Barsky), so a line leaving the plot ends at its edge where it crossed, instead of running along it;
/// non-finite points break the line.
pub fn clip_polyline(points: &[(f64, f64)], x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    for pair in points.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let clipped = if finite(&a) && finite(&b) { clip_segment(a, b, x, y) } else { None };
        match clipped {
            Some((p, q)) => {
                if current.last() != Some(&p) {
                    if !current.is_empty() {
                        pieces.push(std::mem::take(&mut current));
                    }
                    current.push(p);
                }
                current.push(q);
            }
            None => {
                if !current.is_empty() {
                    pieces.push(std::mem::take(&mut current));
                }
            }
        }
    }
    if !current.is_empty() {
        pieces.push(current);
    }
    // A lone point inside the plot is still data.
    if points.len() == 1 && finite(&points[0]) && inside(points[0], x, y) {
        pieces.push(vec![points[0]]);
    }
    pieces
}

/// Whether `p` is inside the rectangle `x` × `y` (edges included).
pub fn inside(p: (f64, f64), x: (f64, f64), y: (f64, f64)) -> bool {
    p.0 >= x.0.min(x.1) && p.0 <= x.0.max(x.1) && p.1 >= y.0.min(y.1) && p.1 <= y.0.max(y.1)
}

/// The part of segment a–b inside the rectangle, if any (Liang–Barsky).
fn clip_segment(a: (f64, f64), b: (f64, f64), x: (f64, f64), y: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in
        [(-dx, a.0 - x.0.min(x.1)), (dx, x.0.max(x.1) - a.0), (-dy, a.1 - y.0.min(y.1)), (dy, y.0.max(y.1) - a.1)]
    {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
            if t0 > t1 {
                return None;
            }
        }
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
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
        Some(text) => {
            let size = fitted_font_size(text, 30.0, f64::from(root.dim_in_pixel().0) - 20.0);
            root.titled(text, ("sans-serif", size)).map_err(plot_err)?
        }
        None => root.clone(),
    };
    let panels = body.split_evenly((rows, columns));
    // Every panel reserves room for as many note lines as the most-annotated one, so their plots line up.
    let note_lines = charts.iter().map(|c| c.notes.len()).max().unwrap_or(0);
    for (panel, chart) in panels.iter().zip(charts) {
        render_chart(panel, chart, note_lines)?;
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

/// A chart as drawn: its model, the x range and plot size it got, and where its legend went.
#[cfg(test)]
#[derive(Debug, Clone)]
pub(crate) struct DrawnChart {
    pub chart: LineChart,
    pub x_range: (f64, f64),
    pub size: PlotSize,
    pub placement: legend::LegendPlacement,
}

#[cfg(test)]
thread_local! {
    /// Every chart drawn on this thread, for tests that check the figures' layout.
    pub(crate) static DRAWN: std::cell::RefCell<Vec<DrawnChart>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The data points of `drawn` (every series point, and points every tenth of each line segment between them)
/// that fall inside its legend box, as (chart title, point): what a reader would see covered.
#[cfg(test)]
pub(crate) fn points_under_legend(drawn: &DrawnChart) -> Vec<(String, (f64, f64))> {
    let p = &drawn.placement;
    let (x, y) = (drawn.x_range, p.y_range);
    let to_px =
        |q: (f64, f64)| ((q.0 - x.0) / (x.1 - x.0) * drawn.size.width, (y.1 - q.1) / (y.1 - y.0) * drawn.size.height);
    let covered = |q: (f64, f64)| {
        let (px, py) = to_px(q);
        inside(q, x, y) && px > p.left && px < p.left + p.width && py > p.top && py < p.top + p.height
    };
    let mut found = Vec::new();
    for series in &drawn.chart.series {
        let line = matches!(series.kind, LineKind::Solid | LineKind::Dashed);
        for (i, &a) in series.points.iter().enumerate() {
            let mut along = vec![a];
            if let (true, Some(&b)) = (line, series.points.get(i + 1)) {
                along.extend((1..10).map(|k| {
                    let t = f64::from(k) / 10.0;
                    (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
                }));
            }
            found.extend(along.into_iter().filter(|&q| covered(q)).map(|q| (drawn.chart.title.clone(), q)));
        }
    }
    for bars in &drawn.chart.error_bars {
        for &(c, low, high) in &bars.bars {
            for k in 0..=10 {
                let v = low + f64::from(k) / 10.0 * (high - low);
                let q = if bars.horizontal { (v, c) } else { (c, v) };
                if covered(q) {
                    found.push((drawn.chart.title.clone(), q));
                }
            }
        }
    }
    found
}

/// Space around the plot, px.
const MARGIN: u32 = 14;
/// Height of the x axis's tick labels and description, px.
const X_LABEL_AREA: u32 = 48;
/// Width of the y axis's tick labels and description, px.
const Y_LABEL_AREA: u32 = 70;
/// Font size of legend entries, px.
const LEGEND_FONT: f64 = 15.0;
/// Padding inside the legend box, px.
const LEGEND_PADDING: u32 = 10;
/// Width of a legend entry's sample, px.
const LEGEND_GLYPH: u32 = 30;

/// Series drawn as separate marks (points, markers, error bars) rather than curves.
fn has_discrete_marks(chart: &LineChart) -> bool {
    !chart.error_bars.is_empty()
        || chart.series.iter().any(|s| matches!(s.kind, LineKind::Points | LineKind::Markers { .. }))
}

/// The largest font size up to `max` (px) at which `text` fits in `width` px (at least 10).
fn fitted_font_size(text: &str, max: f64, width: f64) -> f64 {
    let mut size = max;
    while size > 10.0 {
        match ("sans-serif", size).into_font().box_size(text) {
            Ok((w, _)) if f64::from(w) > width => size -= 1.0,
            _ => break,
        }
    }
    size
}

/// The legend's entries in drawing order: bands and markers once per label, every series and error bar set.
pub fn legend_labels(chart: &LineChart) -> Vec<&str> {
    let mut labels: Vec<&str> = Vec::new();
    let mut bands: Vec<&str> = Vec::new();
    for band in &chart.bands {
        if !bands.contains(&band.label.as_str()) {
            bands.push(band.label.as_str());
            labels.push(band.label.as_str());
        }
    }
    labels.extend(chart.series.iter().map(|s| s.label.as_str()));
    labels.extend(chart.error_bars.iter().map(|b| b.label.as_str()));
    let mut markers: Vec<&str> = Vec::new();
    for marker in &chart.markers {
        if !markers.contains(&marker.label.as_str()) {
            markers.push(marker.label.as_str());
            labels.push(marker.label.as_str());
        }
    }
    labels
}

/// The legend box's size (width, height) px, as plotters lays it out (text block, sample area, padding).
pub fn legend_size(chart: &LineChart) -> Result<(f64, f64)> {
    let labels = legend_labels(chart);
    if labels.is_empty() || (chart.series.is_empty() && chart.markers.is_empty()) {
        return Ok((0.0, 0.0));
    }
    register_fonts();
    let font: TextStyle = ("sans-serif", LEGEND_FONT).into_font().into();
    let mut text = MultiLineText::<_, &str>::new((0, 0), &font);
    for label in labels {
        text.push_line(label);
    }
    let (w, h) = text.estimate_dimension().map_err(|e| anyhow!("cannot measure the legend: {e:?}"))?;
    let padding = 2 * LEGEND_PADDING as i32;
    Ok((f64::from(w + LEGEND_GLYPH as i32 + padding), f64::from(h + padding)))
}

/// Dashes of a vertical line at `x` from `from` to `to` (data units): `dash` drawn, `gap` skipped.
fn dashes(x: f64, from: f64, to: f64, dash: f64, gap: f64) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut y = from;
    while dash > 0.0 && y < to {
        out.push(vec![(x, y), (x, (y + dash).min(to))]);
        y += dash + gap;
    }
    out
}

fn render_chart<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, chart: &LineChart, note_lines: usize) -> Result<()>
where
    DB::ErrorType: 'static,
{
    if *chart == LineChart::default() {
        return Ok(()); // an empty cell of a grid
    }
    let all_points = || chart.series.iter().flat_map(|s| s.points.iter().copied());
    let x_range = chart
        .x_range
        .or_else(|| {
            let edges = chart.bands.iter().flat_map(|b| [b.from, b.to]);
            // Measured points and bars get a margin, so none sits on an axis; curves run edge to edge.
            let margin = if has_discrete_marks(chart) { 0.03 } else { 0.0 };
            padded_range(all_points().map(|p| p.0).chain(chart.markers.iter().map(|m| m.x)).chain(edges), margin)
        })
        .ok_or_else(|| anyhow!("chart '{}' has no finite data", chart.title))?;
    let y_range = chart
        .y_range
        .or_else(|| padded_range(all_points().map(|p| p.1), 0.08))
        .ok_or_else(|| anyhow!("chart '{}' has no finite data", chart.title))?;
    let (_, h) = area.dim_in_pixel();
    let notes_h = NOTE_LINE * note_lines as u32;
    let (plot_area, notes_area) = area.split_vertically(h.saturating_sub(notes_h + if notes_h > 0 { 6 } else { 0 }));
    for (k, note) in chart.notes.iter().enumerate() {
        let style = ("sans-serif", 14).into_font().color(&RGBColor(80, 80, 80));
        notes_area.draw(&Text::new(note.as_str(), (14, NOTE_LINE as i32 * k as i32), style)).map_err(plot_err)?;
    }
    let (area_w, _) = plot_area.dim_in_pixel();
    let title_size = fitted_font_size(&chart.title, 24.0, f64::from(area_w) - 2.0 * f64::from(MARGIN));
    let inner = plot_area.margin(MARGIN, 0, 0, 0).titled(&chart.title, ("sans-serif", title_size)).map_err(plot_err)?;
    let (inner_w, inner_h) = inner.dim_in_pixel();
    let size = PlotSize {
        width: f64::from(inner_w.saturating_sub(MARGIN + Y_LABEL_AREA + MARGIN).max(1)),
        height: f64::from(inner_h.saturating_sub(MARGIN + X_LABEL_AREA).max(1)),
    };
    let placement = legend::place(chart, x_range, y_range, size, legend_size(chart)?);
    let y_range = placement.y_range;
    #[cfg(test)]
    DRAWN.with(|drawn| drawn.borrow_mut().push(DrawnChart { chart: chart.clone(), x_range, size, placement }));
    let mut ctx = ChartBuilder::on(&inner)
        .margin_left(MARGIN)
        .margin_right(MARGIN)
        .margin_bottom(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)
        .map_err(plot_err)?;
    debug_assert_eq!(
        ctx.plotting_area().dim_in_pixel(),
        (size.width as u32, size.height as u32),
        "the legend was placed for the plot's real size"
    );
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
        // One faint minor line between major ones: a guide for the eye that does not compete with the data.
        .x_max_light_lines(1)
        .y_max_light_lines(1)
        .light_line_style(RGBColor(244, 244, 244))
        .bold_line_style(RGBColor(218, 218, 218))
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
        // Lines are clipped to the plot (plotters would pin points beyond it to its edge); markers outside it
        // are left out.
        let points: Vec<(f64, f64)> = series
            .points
            .iter()
            .copied()
            .filter(|&p| p.0.is_finite() && p.1.is_finite() && inside(p, x_range, y_range))
            .collect();
        let pieces = clip_polyline(&series.points, x_range, y_range);
        let drawn = match series.kind {
            LineKind::Solid => {
                ctx.draw_series(pieces.into_iter().map(|piece| PathElement::new(piece, style))).map_err(plot_err)?
            }
            LineKind::Dashed => ctx
                .draw_series(pieces.into_iter().flat_map(|piece| DashedLineSeries::new(piece, 9, 6, style)))
                .map_err(plot_err)?,
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

    for bars in &chart.error_bars {
        let color = PALETTE[bars.color % PALETTE.len()];
        let style = color.stroke_width(2);
        let (xr, yr) = (x_range, y_range);
        let horizontal = bars.horizontal;
        // (x, y) of a point given along the bar (`along`) and across it (`across`).
        let at = move |along: f64, across: f64| if horizontal { (along, across) } else { (across, along) };
        let cap = 0.006 * if horizontal { (yr.1 - yr.0).abs() * 1.6 } else { (xr.1 - xr.0).abs() };
        let mut elements: Vec<PathElement<(f64, f64)>> = Vec::new();
        for &(c, low, high) in &bars.bars {
            if !(c.is_finite() && low.is_finite() && high.is_finite()) {
                continue;
            }
            for piece in clip_polyline(&[at(low, c), at(high, c)], xr, yr) {
                elements.push(PathElement::new(piece, style));
            }
            for end in [low, high] {
                for piece in clip_polyline(&[at(end, c - cap), at(end, c + cap)], xr, yr) {
                    elements.push(PathElement::new(piece, style));
                }
            }
        }
        ctx.draw_series(elements).map_err(plot_err)?.label(bars.label.as_str()).legend(move |(x, y)| {
            EmptyElement::at((x, y))
                + PathElement::new(vec![(12, -6), (12, 6)], style)
                + PathElement::new(vec![(8, -6), (16, -6)], style)
                + PathElement::new(vec![(8, 6), (16, 6)], style)
        });
    }

    let mut labelled: Vec<&str> = Vec::new();
    let x_per_px = (x_range.1 - x_range.0) / size.width;
    for (k, marker) in chart.markers.iter().enumerate() {
        let color = PALETTE[marker.color % PALETTE.len()];
        let style = color.mix(0.85).stroke_width(2);
        let top = placement.marker_top.min(y_range.1);
        // Markers at the same place (two bats' usual impact points) share the line: their dashes alternate, so
        // neither hides the other.
        let same_place: Vec<usize> =
            (0..chart.markers.len()).filter(|&j| ((chart.markers[j].x - marker.x) / x_per_px).abs() < 2.0).collect();
        let (rank, sharing) = (same_place.iter().position(|&j| j == k).unwrap_or(0), same_place.len());
        let drawn = if marker.dashed || sharing > 1 {
            let (dash, gap) =
                if sharing > 1 { (7.0, 7.0 * (sharing as f64 - 1.0) + 3.0 * sharing as f64) } else { (6.0, 5.0) };
            let y_per_px = (y_range.1 - y_range.0) / size.height;
            let start = y_range.0 + rank as f64 * (dash + 3.0) * y_per_px;
            let pieces = dashes(marker.x, start, top, dash * y_per_px, gap * y_per_px);
            ctx.draw_series(pieces.into_iter().map(|piece| PathElement::new(piece, style))).map_err(plot_err)?
        } else {
            ctx.draw_series(LineSeries::new([(marker.x, y_range.0), (marker.x, top)], style)).map_err(plot_err)?
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
            .margin(LEGEND_PADDING)
            .legend_area_size(LEGEND_GLYPH)
            .position(SeriesLabelPosition::Coordinate(placement.left.round() as i32, placement.top.round() as i32))
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

/// A spin-axis clock face: each point at the clock position of its spin axis (TrackMan's HitSpinAxis a, deg, at
/// (a/30 + 6) o'clock as seen from behind the plate: 180° pure backspin at 12:00, 90° hook toward left field at
/// 9:00, 270° slice at 3:00, 0° topspin at 6:00), its distance from the centre proportional to its radius
/// value (e.g. total spin), the outermost ring at `max_radius`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ClockChart {
    /// Title.
    pub title: String,
    /// What the distance from the centre measures (with its unit), e.g. "total spin (rpm)".
    pub radius_label: String,
    /// The value drawn at the clock face's rim.
    pub max_radius: f64,
    /// Values at which rings are drawn and labelled (the rim is always drawn).
    pub rings: Vec<f64>,
    /// The data.
    pub series: Vec<ClockSeries>,
    /// Lines of text under the legend.
    pub notes: Vec<String>,
}

/// One set of points on a [`ClockChart`]: (spin axis deg, radius value).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ClockSeries {
    /// Legend entry.
    pub label: String,
    /// Index into [`PALETTE`].
    pub color: usize,
    /// (spin axis deg, radius value).
    pub points: Vec<(f64, f64)>,
    /// True to join the points in order with a line (a model curve), false for markers only.
    pub joined: bool,
}

/// Centre and rim radius of the clock face in a [`CHART_SIZE`] image, pixels.
const CLOCK_CENTRE: (i32, i32) = (330, 335);
const CLOCK_RIM: f64 = 245.0;

/// The pixel at which a [`ClockChart`] draws spin axis `axis_deg` at `radius` (rim at `max_radius`): the hour
/// hand of (a/30 + 6) o'clock, i.e. θ = a + 180° clockwise from 12.
fn clock_pixel(axis_deg: f64, radius: f64, max_radius: f64) -> (i32, i32) {
    let rho = CLOCK_RIM * radius / max_radius;
    let theta = (axis_deg + 180.0).to_radians();
    let (x, y) = (CLOCK_CENTRE.0 as f64 + rho * theta.sin(), CLOCK_CENTRE.1 as f64 - rho * theta.cos());
    (x.round() as i32, y.round() as i32)
}

/// Draws `chart` into `path` (SVG or PNG by extension), creating the parent directory if needed.
pub fn draw_clock_chart(path: &Path, chart: &ClockChart) -> Result<()> {
    if !(chart.max_radius.is_finite() && chart.max_radius > 0.0) {
        bail!("clock chart '{}' needs a positive max_radius, not {}", chart.title, chart.max_radius);
    }
    let format = ImageFormat::from_path(path)?;
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| format!("cannot create directory '{}'", parent.display()))?;
    }
    register_fonts();
    let outcome = match format {
        ImageFormat::Svg => render_clock(&SVGBackend::new(path, CHART_SIZE).into_drawing_area(), chart),
        ImageFormat::Png => {
            render_clock(&CrispText::new(BitMapBackend::new(path, CHART_SIZE)).into_drawing_area(), chart)
        }
    };
    outcome.with_context(|| format!("cannot draw '{}'", path.display()))
}

fn render_clock<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, chart: &ClockChart) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(plot_err)?;
    root.draw(&Text::new(chart.title.as_str(), (20, 12), ("sans-serif", 24))).map_err(plot_err)?;
    let grey = RGBColor(170, 170, 170);
    let (cx, cy) = CLOCK_CENTRE;
    let mut rings: Vec<f64> = chart.rings.iter().copied().filter(|r| *r > 0.0 && *r < chart.max_radius).collect();
    rings.push(chart.max_radius);
    for ring in rings {
        let r = (CLOCK_RIM * ring / chart.max_radius).round() as i32;
        root.draw(&Circle::new((cx, cy), r, grey.stroke_width(1))).map_err(plot_err)?;
        let style = ("sans-serif", 12).into_font().color(&RGBColor(110, 110, 110));
        root.draw(&Text::new(format!("{ring:.0}"), (cx + 3, cy - r - 13), style)).map_err(plot_err)?;
    }
    for hour in 1..=12 {
        let axis = (hour as f64 - 6.0) * 30.0;
        let inner = clock_pixel(axis, 0.97 * chart.max_radius, chart.max_radius);
        let outer = clock_pixel(axis, chart.max_radius, chart.max_radius);
        root.draw(&PathElement::new(vec![inner, outer], grey.stroke_width(2))).map_err(plot_err)?;
        let (x, y) = clock_pixel(axis, 1.08 * chart.max_radius, chart.max_radius);
        let style = ("sans-serif", 16).into_font().color(&BLACK).pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Center,
            plotters::style::text_anchor::VPos::Center,
        ));
        root.draw(&Text::new(hour.to_string(), (x, y), style)).map_err(plot_err)?;
    }
    let caption = format!("distance from the centre: {}; seen from behind the plate", chart.radius_label);
    root.draw(&Text::new(caption, (20, 618), ("sans-serif", 14))).map_err(plot_err)?;
    for (k, series) in chart.series.iter().enumerate() {
        let color = PALETTE[series.color % PALETTE.len()];
        let pixels: Vec<(i32, i32)> = series
            .points
            .iter()
            .filter(|(a, r)| a.is_finite() && r.is_finite())
            .map(|&(a, r)| clock_pixel(a, r, chart.max_radius))
            .collect();
        if series.joined {
            root.draw(&PathElement::new(pixels.clone(), color.stroke_width(2))).map_err(plot_err)?;
        }
        for p in &pixels {
            root.draw(&Circle::new(*p, if series.joined { 2 } else { 4 }, color.filled())).map_err(plot_err)?;
        }
        let y = 80 + 26 * k as i32;
        root.draw(&Circle::new((660, y), 5, color.filled())).map_err(plot_err)?;
        root.draw(&Text::new(series.label.as_str(), (675, y - 8), ("sans-serif", 15))).map_err(plot_err)?;
    }
    let top = 80 + 26 * chart.series.len() as i32 + 14;
    for (k, note) in chart.notes.iter().enumerate() {
        let style = ("sans-serif", 13).into_font().color(&RGBColor(80, 80, 80));
        root.draw(&Text::new(note.as_str(), (650, top + NOTE_LINE as i32 * k as i32), style)).map_err(plot_err)?;
    }
    root.present().map_err(plot_err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Draws `chart` into a temporary SVG and returns how it was laid out.
    fn drawn(chart: &LineChart) -> DrawnChart {
        let dir = tempfile::tempdir().unwrap();
        DRAWN.with(|d| d.borrow_mut().clear());
        draw_line_chart(&dir.path().join("c.svg"), chart).unwrap();
        DRAWN.with(|d| d.borrow().last().cloned()).expect("the chart was drawn")
    }

    #[test]
    fn the_legend_covers_no_point_wherever_the_data_lies() {
        let line = |label: &str, c: usize, f: &dyn Fn(f64) -> f64| {
            Series::solid(label, c, (0..=100).map(|k| (f64::from(k), f(f64::from(k)))).collect())
        };
        let long = "a label long enough to take a fair share of the plot's width";
        let cases = [
            // Data through all four corners: no corner is free until the axis grows.
            vec![line(long, 0, &|x| x), line("falling", 1, &|x| 100.0 - x)],
            // A curve high on both sides and a flat line low across the plot.
            vec![line(long, 0, &|x| (x - 50.0).powi(2) / 25.0), line("flat", 1, &|_| 0.0)],
            // Points at the axes' very ends.
            vec![
                Series {
                    label: long.into(),
                    points: vec![(0.0, 0.0), (100.0, 100.0), (0.0, 100.0), (100.0, 0.0)],
                    color: 0,
                    kind: LineKind::Points,
                },
                line("middle", 1, &|x| 50.0 + x / 10.0),
            ],
        ];
        for (i, series) in cases.into_iter().enumerate() {
            for legend in [LegendAt::LowerRight, LegendAt::UpperLeft, LegendAt::LowerMiddle] {
                let chart =
                    LineChart { title: format!("case {i}"), series: series.clone(), legend, ..Default::default() };
                let layout = drawn(&chart);
                assert!(layout.placement.width > 100.0 && layout.placement.height > 30.0, "{:?}", layout.placement);
                assert_eq!(points_under_legend(&layout), [], "case {i}, {legend:?}: {:?}", layout.placement);
            }
        }
    }

    #[test]
    fn measured_points_keep_off_the_axes_and_a_preferred_free_corner_is_kept() {
        let chart = LineChart {
            title: "COR".into(),
            series: vec![
                Series::solid("model", 0, vec![(5.0, 0.58), (70.0, 0.51)]),
                Series {
                    label: "measured".into(),
                    points: vec![(1.0, 0.66), (26.0, 0.55)],
                    color: 1,
                    kind: LineKind::Points,
                },
            ],
            legend: LegendAt::UpperRight,
            ..Default::default()
        };
        let layout = drawn(&chart);
        assert!(layout.x_range.0 < 1.0 - 0.02 * 69.0, "the 1 m/s point is inside the axes: {:?}", layout.x_range);
        assert_eq!(points_under_legend(&layout), []);
        assert_eq!(layout.placement.y_range.1, drawn(&chart).placement.y_range.1);
        assert!(layout.placement.left > layout.size.width / 2.0 && layout.placement.top < 10.0, "upper right");
    }

    #[test]
    fn a_title_wider_than_its_panel_is_set_smaller_to_fit() {
        register_fonts();
        let title = "Exit speed 6 in from the end (ball 40.0 m/s, bat CM 25.0 m/s, ω 45.0 rad/s) and more";
        let size = fitted_font_size(title, 24.0, 700.0);
        assert!(size < 24.0);
        let (w, _) = ("sans-serif", size).into_font().box_size(title).unwrap();
        assert!(w <= 700, "{w} px at {size}");
        assert_eq!(fitted_font_size("BBCOR", 24.0, 700.0), 24.0);
    }

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
    fn lines_are_clipped_where_they_cross_the_edge() {
        let (x, y) = ((0.0, 10.0), (0.0, 10.0));
        // Rising through the top edge at x = 5 (y = 2x): the piece ends there, not pinned along the edge.
        assert_eq!(
            clip_polyline(&[(0.0, 0.0), (4.0, 8.0), (6.0, 12.0), (8.0, 16.0)], x, y),
            vec![vec![(0.0, 0.0), (4.0, 8.0), (5.0, 10.0)]]
        );
        // Out and back in: two pieces.
        let pieces = clip_polyline(&[(1.0, 5.0), (3.0, 15.0), (5.0, 5.0)], x, y);
        assert_eq!(pieces, vec![vec![(1.0, 5.0), (2.0, 10.0)], vec![(4.0, 10.0), (5.0, 5.0)]]);
        // Wholly outside, and a NaN gap.
        assert!(clip_polyline(&[(11.0, 1.0), (12.0, 2.0)], x, y).is_empty());
        assert_eq!(clip_polyline(&[(1.0, 1.0), (2.0, 2.0), (f64::NAN, 3.0), (4.0, 4.0), (5.0, 5.0)], x, y).len(), 2);
    }

    #[test]
    fn padded_range_handles_flat_and_empty_data() {
        assert_eq!(padded_range([2.0, 2.0].into_iter(), 0.5), Some((1.0, 3.0)));
        assert_eq!(padded_range(std::iter::empty(), 0.1), None);
        assert_eq!(padded_range([f64::NAN, 1.0, 3.0].into_iter(), 0.5), Some((0.0, 4.0)));
    }
}
