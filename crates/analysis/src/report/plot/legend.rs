//! Where a chart's legend goes, decided from the chart model before anything is drawn: the first corner of the
//! plot (the chart's preferred one first) whose box covers no plotted ink — line samples, points, error bars,
//! vertical markers. When every corner covers data, the y axis grows at the top until the data sits below
//! the legend's height, and the legend takes an upper corner of that headroom.

use super::{clip_polyline, inside, LegendAt, LineChart, LineKind};

/// Gap between the legend box and the plot's edge, px.
const INSET: f64 = 8.0;
/// Clearance kept between the legend box and any ink, px.
const CLEARANCE: f64 = 4.0;
/// Distance between samples along a drawn line, px.
const STEP: f64 = 2.0;

/// Size of the plotting area (inside the axes), px.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlotSize {
    /// Width, px.
    pub width: f64,
    /// Height, px.
    pub height: f64,
}

/// The legend's box in plot-area pixels (origin top left) and the ranges to draw the chart with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LegendPlacement {
    /// Left edge, px from the plot's left.
    pub left: f64,
    /// Top edge, px from the plot's top.
    pub top: f64,
    /// Width, px.
    pub width: f64,
    /// Height, px.
    pub height: f64,
    /// The y range to draw with (the chart's, or grown at the top to make room).
    pub y_range: (f64, f64),
    /// The top of the data's range: vertical markers stop there, below any headroom.
    pub marker_top: f64,
}

/// A disc of ink at a pixel position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ink {
    /// x, px from the plot's left.
    pub x: f64,
    /// y, px from the plot's top.
    pub y: f64,
    /// Radius, px.
    pub radius: f64,
}

/// Maps data coordinates to plot pixels.
#[derive(Debug, Clone, Copy)]
struct Frame {
    x: (f64, f64),
    y: (f64, f64),
    size: PlotSize,
}

impl Frame {
    fn pixel(&self, p: (f64, f64)) -> (f64, f64) {
        let fx = (p.0 - self.x.0) / (self.x.1 - self.x.0);
        let fy = (self.y.1 - p.1) / (self.y.1 - self.y.0);
        (fx * self.size.width, fy * self.size.height)
    }
}

/// Samples every `STEP` px along the polyline `points` (already clipped), each a disc of `radius`.
fn sample_line(frame: &Frame, points: &[(f64, f64)], radius: f64, out: &mut Vec<Ink>) {
    let pixels: Vec<(f64, f64)> = points.iter().map(|&p| frame.pixel(p)).collect();
    if let Some(&(x, y)) = pixels.first() {
        out.push(Ink { x, y, radius });
    }
    for pair in pixels.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let length = (b.0 - a.0).hypot(b.1 - a.1);
        let steps = (length / STEP).ceil().max(1.0) as usize;
        for k in 1..=steps {
            let t = k as f64 / steps as f64;
            out.push(Ink { x: a.0 + t * (b.0 - a.0), y: a.1 + t * (b.1 - a.1), radius });
        }
    }
}

/// The ink of `chart` drawn with ranges `x` × `y` into a plot of `size`; vertical markers run from the bottom
/// up to `marker_top`.
pub fn ink(chart: &LineChart, x: (f64, f64), y: (f64, f64), marker_top: f64, size: PlotSize) -> Vec<Ink> {
    let frame = Frame { x, y, size };
    let mut out = Vec::new();
    for series in &chart.series {
        match series.kind {
            LineKind::Solid | LineKind::Dashed => {
                for piece in clip_polyline(&series.points, x, y) {
                    sample_line(&frame, &piece, 1.5, &mut out);
                }
            }
            LineKind::Points | LineKind::Markers { .. } => {
                let radius = match series.kind {
                    LineKind::Markers { radius, .. } => f64::from(radius) + 1.0,
                    _ => 3.0,
                };
                for &p in series.points.iter().filter(|p| p.0.is_finite() && p.1.is_finite() && inside(**p, x, y)) {
                    let (px, py) = frame.pixel(p);
                    out.push(Ink { x: px, y: py, radius });
                }
            }
        }
    }
    for bars in &chart.error_bars {
        for &(c, low, high) in &bars.bars {
            let ends = if bars.horizontal { [(low, c), (high, c)] } else { [(c, low), (c, high)] };
            for piece in clip_polyline(&ends, x, y) {
                sample_line(&frame, &piece, 4.0, &mut out);
            }
        }
    }
    for marker in &chart.markers {
        for piece in clip_polyline(&[(marker.x, y.0), (marker.x, marker_top.min(y.1))], x, y) {
            sample_line(&frame, &piece, 1.5, &mut out);
        }
    }
    if chart.zero_line {
        for piece in clip_polyline(&[(x.0, 0.0), (x.1, 0.0)], x, y) {
            sample_line(&frame, &piece, 1.0, &mut out);
        }
    }
    out
}

/// How many discs of `ink` reach into the box (`left`, `top`, `width`, `height`) or its clearance.
pub fn covered(ink: &[Ink], left: f64, top: f64, width: f64, height: f64) -> usize {
    ink.iter()
        .filter(|i| {
            let reach = i.radius + CLEARANCE;
            i.x + reach > left && i.x - reach < left + width && i.y + reach > top && i.y - reach < top + height
        })
        .count()
}

/// The candidate corners, the preferred one first, as (left, top) of a `legend` box in a plot of `size`.
fn corners(preferred: LegendAt, legend: (f64, f64), size: PlotSize, upper_only: bool) -> Vec<(f64, f64)> {
    let (w, h) = legend;
    let right = (size.width - w - INSET).max(0.0);
    let middle = ((size.width - w) / 2.0).max(0.0);
    let bottom = (size.height - h - INSET).max(0.0);
    let at = |corner: LegendAt| match corner {
        LegendAt::UpperRight => (right, INSET),
        LegendAt::UpperLeft => (INSET, INSET),
        LegendAt::LowerRight => (right, bottom),
        LegendAt::LowerLeft => (INSET, bottom),
        LegendAt::LowerMiddle => (middle, bottom),
    };
    let mut order = vec![at(preferred)];
    for corner in [LegendAt::UpperRight, LegendAt::UpperLeft, LegendAt::LowerRight, LegendAt::LowerLeft] {
        order.push(at(corner));
    }
    order.push(at(LegendAt::LowerMiddle));
    order.push((middle, INSET));
    if upper_only {
        order.retain(|&(_, top)| top == INSET);
    }
    order.dedup();
    order
}

/// Places a legend of `legend` (width, height) px on `chart` drawn with ranges `x` × `y` into a plot of
/// `size`: the first clear corner, else an upper corner of headroom added above the data, else the corner
/// that covers the least.
pub fn place(chart: &LineChart, x: (f64, f64), y: (f64, f64), size: PlotSize, legend: (f64, f64)) -> LegendPlacement {
    let (w, h) = legend;
    let best = |y: (f64, f64), marker_top: f64, upper_only: bool| {
        let ink = ink(chart, x, y, marker_top, size);
        corners(chart.legend, legend, size, upper_only)
            .into_iter()
            .map(|(left, top)| (covered(&ink, left, top, w, h), left, top))
            .min_by_key(|c| c.0)
            .map(|(count, left, top)| {
                (count, LegendPlacement { left, top, width: w, height: h, y_range: y, marker_top })
            })
    };
    let Some((count, placement)) = best(y, y.1, false) else {
        return LegendPlacement { left: INSET, top: INSET, width: w, height: h, y_range: y, marker_top: y.1 };
    };
    if count == 0 {
        return placement;
    }
    // Headroom: the data's top stays where it is in data units and the axis grows so that the band above it
    // is as tall as the legend and its clearances.
    let ink_top_px = ink(chart, x, y, y.1, size).iter().map(|i| i.y - i.radius).fold(f64::INFINITY, f64::min);
    let data_top = y.1 - (ink_top_px.max(0.0) / size.height) * (y.1 - y.0);
    let room = (h + INSET + 2.0 * CLEARANCE + 4.0) / size.height;
    if room < 0.8 && data_top > y.0 {
        let grown = (y.0, y.0 + (data_top - y.0) / (1.0 - room));
        if let Some((0, clear)) = best(grown, data_top, true) {
            return clear;
        }
    }
    placement
}
