//! `locate --figure FILE`: the located impact points on the bat's outline, one panel per batter.
//!
//! Each panel draws the bat's outline (outer radius ±r(z) against z from the knob, the bat most of the
//! panel's swings used), every located solution at (impact_z, −undercut) — the line of the ball's centre,
//! below the bat's axis for a positive undercut — the favoured solution (or the only one) filled and the
//! others hollow, the sweet spot (the median of the panel's solutions' sweet spots at their undercuts) dashed,
//! and the "squared up" band ±[`SQUARED_UP`] around it shaded. Batters come from the side table
//! [`ROWS_TABLE`] that `sweetspot import` writes into the bag; a bag without it (recorded from a rig) is drawn
//! per bat id. At most [`MAX_PANELS`] panels: the batters with the most located swings.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Result;

use super::{LocateReport, Outcome, SQUARED_UP};
use crate::import::ROWS_TABLE;
use crate::report::plot::{draw_panels, Band, LineChart, LineKind, Series, VerticalMarker};

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

/// One panel's content.
#[derive(Default)]
struct Group {
    favoured: Vec<(f64, f64)>,
    others: Vec<(f64, f64)>,
    sweet_spots: Vec<f64>,
    bats: BTreeMap<String, usize>,
}

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
            let point = (s.impact_z, -s.undercut);
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
    let mut markers = (0, 0);
    for (name, mut group) in order {
        let bat_id = group.bats.iter().max_by_key(|(_, n)| **n).map(|(id, _)| id.clone()).unwrap_or_default();
        let mut series = Vec::new();
        if let Some(outline) = report.outlines.get(&bat_id) {
            // One closed path: along the top edge to the end, back along the bottom edge.
            let mut points: Vec<(f64, f64)> = outline.clone();
            points.extend(outline.iter().rev().map(|&(z, r)| (z, -r)));
            points.push(outline[0]);
            series.push(Series::solid(format!("{bat_id} outline (±radius)"), 6, points));
        }
        markers.0 += group.favoured.len();
        markers.1 += group.others.len();
        series.push(Series {
            label: "favoured solution".into(),
            points: group.favoured,
            color: 0,
            kind: LineKind::Markers { radius: MARKER_RADIUS, filled: true },
        });
        series.push(Series {
            label: "other solution".into(),
            points: group.others,
            color: 1,
            kind: LineKind::Markers { radius: MARKER_RADIUS, filled: false },
        });
        // The legend goes above the bat: room for it on top of the data's span.
        let ys = series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).filter(|y| y.is_finite());
        let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| (lo.min(y), hi.max(y)));
        let span = (hi - lo).max(1e-3);
        group.sweet_spots.sort_by(f64::total_cmp);
        let sweet = group.sweet_spots[group.sweet_spots.len() / 2];
        charts.push(LineChart {
            title: match grouping {
                Grouping::Batter => format!("{name}, bat {bat_id}"),
                Grouping::Bat => format!("bat {name}"),
            },
            x_label: "z from the knob (m)".into(),
            y_label: "−undercut (m); outline ±radius".into(),
            series,
            markers: vec![VerticalMarker { x: sweet, label: "sweet spot (median)".into(), color: 2, dashed: true }],
            bands: vec![Band {
                from: sweet - SQUARED_UP,
                to: sweet + SQUARED_UP,
                label: "squared up (±2 cm)".into(),
                color: 2,
            }],
            y_range: Some((lo - 0.08 * span, hi + 0.65 * span)),
            legend_upper_right: true,
            ..Default::default()
        });
    }
    let panels: Vec<String> = charts.iter().map(|c| c.title.clone()).collect();
    let columns = if charts.len() > 1 { 2 } else { 1 };
    draw_panels(path, &charts, columns, Some("Located impact points"))?;
    Ok(FigureSummary { grouping, panels, groups_left_out, markers })
}
