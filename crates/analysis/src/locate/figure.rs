//! `locate --figure FILE`: the located impact points, two panels per batter, one above the other on the same z
//! axis (m from the knob).
//!
//! The upper panel is the bat: its outline (outer radius ±r(z) in mm, the bat most of the batter's swings
//! used) and each located impact point on its axis with its ± σ along the bat. The lower panel is the
//! undercut D (mm) of every solution at its impact point, with its ± σ: the favoured solution (or the only
//! one) filled, the others hollow. Both show the sweet spot (the median of the solutions' sweet spots at their
//! undercuts) dashed and the "squared up" band ±[`SQUARED_UP`] around it shaded; the legends sit over the
//! handle, where no ball is located. Batters come from the side table
//! [`ROWS_TABLE`] that `sweetspot import` writes into the bag; a bag without it (recorded from a rig) is drawn
//! per bat id. At most [`MAX_PANELS`] panels: the batters with the most located swings.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Result;

use super::{LocateReport, Outcome, SQUARED_UP};
use crate::import::ROWS_TABLE;
use crate::report::plot::{draw_panels, Band, ErrorBars, LegendAt, LineChart, LineKind, Series, VerticalMarker};

/// Most panels in one figure.
pub const MAX_PANELS: usize = 12;
/// Radius of a solution's marker, px.
pub const MARKER_RADIUS: u32 = 5;

/// How the panels are grouped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Grouping {
    /// By the batter of the import side table.
    Batter,
    /// By bat id (no side table).
    Bat,
}

/// What the figure shows.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureSummary {
    /// How swings were grouped into panels.
    pub grouping: Grouping,
    /// Panel names, in drawing order.
    pub panels: Vec<String>,
    /// Groups with located swings left out (beyond [`MAX_PANELS`]).
    pub groups_left_out: usize,
    /// Markers drawn: (filled, hollow).
    pub markers: (usize, usize),
}

/// The batter of each swing id from the bag's import side table, if the bag has one.
pub fn batters_of(bag: &Path) -> Result<Option<BTreeMap<u64, String>>> {
    let path = bag.join(ROWS_TABLE);
    if !path.is_file() {
        return Ok(None);
    }
    // Through the import's own table reader: a regular file, each line at most MAX_LINE_BYTES (a side table
    // edited to hold a 50 MB name is refused, not read whole).
    let mut table = crate::import::table::Table::open(&path).map_err(|e| anyhow::anyhow!("{e}"))?;
    let (Some(id_col), Some(batter_col)) = (table.column("swing_id"), table.column("batter")) else {
        anyhow::bail!("'{}': expected columns swing_id and batter", path.display());
    };
    let mut batters = BTreeMap::new();
    while table.next_row().map_err(|e| anyhow::anyhow!("{e}"))? {
        let row = table.row();
        let Ok(id) = row.text(Some(id_col)).parse::<u64>() else {
            anyhow::bail!("'{}' line {}: swing_id is not a number", path.display(), row.line());
        };
        let name = crate::import::spreadsheet_unescaped(row.text(Some(batter_col)));
        batters.insert(id, name.chars().take(MAX_BATTER_NAME_CHARS).collect());
    }
    Ok(Some(batters))
}

/// Longest batter name shown on a panel, characters (a longer one is cut).
pub const MAX_BATTER_NAME_CHARS: usize = 80;

/// One batter's content: solutions as (impact_z, σ_z, undercut, σ_D), m.
#[derive(Default)]
struct Group {
    favoured: Vec<[f64; 4]>,
    others: Vec<[f64; 4]>,
    sweet_spots: Vec<f64>,
    bats: BTreeMap<String, usize>,
}

/// Millimetres in a metre.
const MM: f64 = 1e3;

/// Draws the figure of `report` into `path` (SVG or PNG by extension); `batters` from [`batters_of`].
pub fn draw_figure(
    path: &Path,
    report: &LocateReport,
    batters: Option<&BTreeMap<u64, String>>,
) -> Result<FigureSummary> {
    let grouping = if batters.is_some() { Grouping::Batter } else { Grouping::Bat };
    let mut groups: BTreeMap<String, Group> = BTreeMap::new();
    for swing in &report.swings {
        let Outcome::Located { solutions, favoured, .. } = &swing.outcome else { continue };
        let name = match batters {
            Some(map) => match map.get(&swing.swing_id).map(String::as_str) {
                Some("") | None => "batter not named".to_string(),
                Some(name) => name.to_string(),
            },
            None => swing.bat_id.clone(),
        };
        let group = groups.entry(name).or_default();
        *group.bats.entry(swing.bat_id.clone()).or_default() += 1;
        for (i, s) in solutions.iter().enumerate() {
            let point = [s.impact_z, s.impact_z_sigma, s.undercut, s.undercut_sigma];
            // With no favoured solution every one explains the measurements equally: all drawn hollow.
            if *favoured == Some(i) {
                group.favoured.push(point);
            } else {
                group.others.push(point);
            }
            group.sweet_spots.push(s.sweet_spot_z);
        }
    }
    anyhow::ensure!(!groups.is_empty(), "no swing was located: nothing to draw into '{}'", path.display());
    let mut order: Vec<(String, Group)> = groups.into_iter().collect();
    // Most located swings first; names break ties.
    order.sort_by_key(|(name, g)| (std::cmp::Reverse(g.favoured.len() + g.others.len()), name.clone()));
    let groups_left_out = order.len().saturating_sub(MAX_PANELS);
    order.truncate(MAX_PANELS);
    let mut charts = Vec::new();
    let mut panels = Vec::new();
    let mut markers = (0, 0);
    let columns = if order.len() > 1 { 2 } else { 1 };
    // Row-major grid: each row of batters' bat panels above the same batters' undercut panels.
    for row in order.chunks_mut(columns) {
        let mut lower = Vec::new();
        for (name, group) in row.iter_mut() {
            let bat_id = group.bats.iter().max_by_key(|(_, n)| **n).map(|(id, _)| id.clone()).unwrap_or_default();
            let title = match grouping {
                Grouping::Batter => format!("{name}, bat {bat_id}"),
                Grouping::Bat => format!("bat {name}"),
            };
            panels.push(title.clone());
            markers.0 += group.favoured.len();
            markers.1 += group.others.len();
            group.sweet_spots.sort_by(f64::total_cmp);
            let sweet = group.sweet_spots[group.sweet_spots.len() / 2];
            let (upper_chart, lower_chart) = batter_panels(&title, &bat_id, report.outlines.get(&bat_id), group, sweet);
            charts.push(upper_chart);
            lower.push(lower_chart);
        }
        // A lone batter in the last row of two columns: an empty cell keeps the grid's rows paired.
        while lower.len() < columns && charts.len() % columns != 0 {
            charts.push(LineChart::default());
        }
        charts.extend(lower);
    }
    draw_panels(path, &charts, columns, Some("Located impact points"))?;
    Ok(FigureSummary { grouping, panels, groups_left_out, markers })
}

/// The two panels of one batter: the bat with the impact points on it, and the undercut at each.
fn batter_panels(
    title: &str,
    bat_id: &str,
    outline: Option<&Vec<(f64, f64)>>,
    group: &Group,
    sweet: f64,
) -> (LineChart, LineChart) {
    let x_range = outline.and_then(|o| Some((o.first()?.0, o.last()?.0))).unwrap_or_else(|| {
        let (lo, hi) =
            group.solutions().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
        (lo - 0.05, hi + 0.05)
    });
    let panels = BatterPanels { title, group, sweet, x_range };
    (panels.bat(bat_id, outline), panels.undercut())
}

impl Group {
    /// Every solution, the favoured first.
    fn solutions(&self) -> impl Iterator<Item = &[f64; 4]> {
        self.favoured.iter().chain(&self.others)
    }
}

/// What a batter's two panels share: the title, the solutions, the sweet spot and the z range.
struct BatterPanels<'a> {
    title: &'a str,
    group: &'a Group,
    sweet: f64,
    x_range: (f64, f64),
}

impl BatterPanels<'_> {
    fn squared_up_band(&self) -> Band {
        Band {
            from: self.sweet - SQUARED_UP,
            to: self.sweet + SQUARED_UP,
            label: "squared up (±2 cm)".into(),
            color: 2,
        }
    }

    fn sweet_spot_marker(&self) -> VerticalMarker {
        VerticalMarker { x: self.sweet, label: "sweet spot (median)".into(), color: 2, dashed: true }
    }

    /// The bat: outline ±r in mm, impact points on its axis with ± σ along it.
    fn bat(&self, bat_id: &str, outline: Option<&Vec<(f64, f64)>>) -> LineChart {
        let mut bat_series = Vec::new();
        let mut r_max: f64 = 0.0;
        if let Some(outline) = outline {
            // One closed path: along the top edge to the end, back along the bottom edge.
            let mut points: Vec<(f64, f64)> = outline.iter().map(|&(z, r)| (z, r * MM)).collect();
            points.extend(outline.iter().rev().map(|&(z, r)| (z, -r * MM)));
            points.push((outline[0].0, outline[0].1 * MM));
            r_max = outline.iter().fold(0.0, |m, p| m.max(p.1 * MM));
            bat_series.push(Series::solid(format!("{bat_id} outline (±radius)"), 6, points));
        }
        let r_max = if r_max > 0.0 { r_max } else { 35.0 };
        bat_series.push(Series {
            label: "impact point".into(),
            points: self.group.solutions().map(|p| (p[0], 0.0)).collect(),
            color: 0,
            kind: LineKind::Markers { radius: 3, filled: true },
        });
        LineChart {
            title: self.title.to_string(),
            x_label: "z from the knob (m)".into(),
            y_label: "bat radius (mm)".into(),
            series: bat_series,
            markers: vec![self.sweet_spot_marker()],
            bands: vec![self.squared_up_band()],
            error_bars: vec![ErrorBars {
                label: "impact point ± σ".into(),
                color: 0,
                bars: self.group.solutions().map(|p| (0.0, p[0] - p[1], p[0] + p[1])).collect(),
                horizontal: true,
            }],
            x_range: Some(self.x_range),
            // Room above the barrel for the legend, over the handle.
            y_range: Some((-1.3 * r_max, 2.6 * r_max)),
            legend: LegendAt::UpperLeft,
            ..Default::default()
        }
    }

    /// The undercut of every solution, with its ± σ.
    fn undercut(&self) -> LineChart {
        let to_point = |p: &[f64; 4]| (p[0], p[2] * MM);
        let series = vec![
            Series {
                label: "favoured solution".into(),
                points: self.group.favoured.iter().map(to_point).collect(),
                color: 0,
                kind: LineKind::Markers { radius: MARKER_RADIUS, filled: true },
            },
            Series {
                label: "other solution".into(),
                points: self.group.others.iter().map(to_point).collect(),
                color: 1,
                kind: LineKind::Markers { radius: MARKER_RADIUS, filled: false },
            },
        ];
        let all = || self.group.solutions();
        let bars = all().filter(|p| p[3] > 0.0).map(|p| (p[0], (p[2] - p[3]) * MM, (p[2] + p[3]) * MM)).collect();
        let (lo, hi) = all()
            .flat_map(|p| [(p[2] - p[3]) * MM, (p[2] + p[3]) * MM])
            .filter(|y| y.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| (lo.min(y), hi.max(y)));
        let (lo, hi) = if lo.is_finite() { (lo.min(0.0), hi.max(0.0)) } else { (-10.0, 10.0) };
        let span = (hi - lo).max(2.0);
        LineChart {
            title: format!("{}: undercut", self.title),
            x_label: "z from the knob (m)".into(),
            y_label: "undercut D (mm, ball centre above the bat's path +)".into(),
            series,
            markers: vec![self.sweet_spot_marker()],
            bands: vec![self.squared_up_band()],
            error_bars: vec![ErrorBars { label: "± σ".into(), color: 0, bars, horizontal: false }],
            x_range: Some(self.x_range),
            y_range: Some((lo - 0.1 * span, hi + 0.9 * span)),
            zero_line: true,
            legend: LegendAt::UpperLeft,
            ..Default::default()
        }
    }
}
