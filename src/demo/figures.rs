//! The demo's figures, written next to its bag.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context, Result};

use super::summary::Answers;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
use crate::physics::metrics::{linspace, sweep};
use crate::physics::units::MPH;
use crate::physics::Impact;
use crate::report::figures::{write_figures, FigureSettings, EXIT_SPEED_LABEL, Z_LABEL};
use crate::report::plot::{draw_panels, ImageFormat, LegendAt, LineChart, LineKind, Series, VerticalMarker};
use crate::rig::{RigBat, RigSwing, SessionGenerator};

/// Where the figures of the bag `bag` go: `figures/<bag's name>` beside it, so a glob for the bags
/// (`bags/demo_*/`) matches bags only.
pub fn figures_dir(bag: &Path) -> PathBuf {
    let name = bag.file_name().map(|n| n.to_os_string()).unwrap_or_else(|| "demo".into());
    bag.parent().unwrap_or(Path::new("")).join("figures").join(name)
}

/// The demo's figures: exit speed against impact point per bat (measured, model, and the model's curve for
/// the session's mean swing), then `sweetspot figures`' seed comparisons and mode shapes. Returns the files.
pub fn write_demo_figures(
    dir: &Path,
    rig: &SessionGenerator,
    truths: &BTreeMap<u64, (RigSwing, Swing)>,
    answers: &Answers,
    image: ImageFormat,
) -> Result<Vec<String>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create '{}'", dir.display()))?;
    let ext = image.extension();
    let mut panels = Vec::new();
    let mut all_swings: Vec<Impact> = Vec::new();
    for (i, bat) in rig.bats().iter().enumerate() {
        let swings: Vec<&(RigSwing, Swing)> = truths.values().filter(|(s, _)| s.bat_id == bat.bat_id).collect();
        if swings.is_empty() {
            continue;
        }
        let mean = mean_swing(swings.iter().map(|(s, _)| &s.measured));
        all_swings.push(mean);
        panels.push(exit_speed_panel(rig, i, bat, &swings, &mean, answers)?);
    }
    share_y_range(&mut panels);
    let mut files = Vec::new();
    if !panels.is_empty() {
        let file = format!("demo-exit-speed-vs-impact.{ext}");
        draw_panels(&dir.join(&file), &panels, 2, Some("Demo session: exit speed against impact point"))?;
        files.push(file);
    }
    // The seed's comparisons and the mode shapes, for the session's typical swing.
    let typical = mean_swing(all_swings.iter());
    let config = rig.config();
    let settings =
        FigureSettings { format: image, points: 60, swing: typical, ball: config.ball, options: config.options };
    let entries = write_figures(dir, &settings).map_err(|e| anyhow!("seed figures: {e:#}"))?;
    files.extend(entries.into_iter().map(|e| e.file));
    Ok(files)
}

/// The mean of each speed over `swings` (all zero when there are none), its impact point unset.
fn mean_swing<'a>(swings: impl Iterator<Item = &'a Impact> + Clone) -> Impact {
    let n = swings.clone().count().max(1) as f64;
    Impact {
        ball_speed: swings.clone().map(|s| s.ball_speed).sum::<f64>() / n,
        bat_cm_speed: swings.clone().map(|s| s.bat_cm_speed).sum::<f64>() / n,
        bat_angular_speed: swings.map(|s| s.bat_angular_speed).sum::<f64>() / n,
        impact_z: f64::NAN,
    }
}

/// The `color`th bat's panel: exit speed against impact point as the rig measured it and as the node answered
/// for the same swings, the model's curve for their `mean` swing, and the node's sweet spot.
fn exit_speed_panel(
    rig: &SessionGenerator,
    color: usize,
    bat: &RigBat,
    swings: &[&(RigSwing, Swing)],
    mean: &Impact,
    answers: &Answers,
) -> Result<LineChart> {
    let length = bat.modes.length();
    let zs = linspace(0.5 * length, length - 0.02, 60);
    let curve = sweep(&bat.modes, &rig.config().ball, mean, &zs, &rig.config().options)
        .with_context(|| format!("model curve of '{}'", bat.bat_id))?;
    let measured: Vec<(f64, f64)> = swings.iter().map(|(s, _)| (s.measured.impact_z, s.reading.exit_speed)).collect();
    let model: Vec<(f64, f64)> = swings
        .iter()
        .filter_map(|(s, m)| {
            answers
                .exits
                .get(&m.swing_id)
                .filter(|e| e.status == ExitVelocity::STATUS_OK)
                .map(|e| (s.measured.impact_z, e.exit_speed))
        })
        .collect();
    let mut chart = LineChart {
        title: format!("{} ({} swings)", bat.bat_id, swings.len()),
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series: vec![
            Series { label: "rig radar (measured)".into(), points: measured, color: 6, kind: LineKind::Points },
            Series {
                label: "node (model, same swing)".into(),
                points: model,
                color: color % 6,
                kind: LineKind::Points,
            },
            Series::solid(
                format!(
                    "model, mean swing ({:.0} mph pitch, ω {:.0} rad/s)",
                    mean.ball_speed / MPH,
                    mean.bat_angular_speed
                ),
                color % 6,
                curve.iter().map(|p| (p.impact_z, p.result.exit_speed)).collect(),
            ),
        ],
        legend: LegendAt::UpperLeft,
        ..Default::default()
    };
    if let Some(s) = answers.sweet_spots.get(&bat.bat_id) {
        chart.markers.push(VerticalMarker {
            x: s.max_exit_speed_z,
            label: "sweet spot (reference swing)".into(),
            color: 4,
            dashed: true,
        });
    }
    Ok(chart)
}

/// One y range for every panel (the bats' exit speeds are read against each other), with room above the data
/// for the legend, so it hides no curve.
fn share_y_range(panels: &mut [LineChart]) {
    let ys = panels.iter().flat_map(|c| c.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
    let (lo, hi) =
        ys.filter(|y| y.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| (a.min(y), b.max(y)));
    if lo < hi {
        let span = hi - lo;
        for chart in panels.iter_mut() {
            chart.y_range = Some((lo - 0.05 * span, hi + 0.45 * span));
        }
    }
}
