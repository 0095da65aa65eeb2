//! The seed paper's Figures 2, 5 and 6 redrawn twice — from its rigid Tables 1/2 (effective COR as printed)
//! and from the physical models (flexible beam, 18 modes) — plus the mode shapes of every preset, and an
//! index (`README.md`) with captions; and the exit-speed charts of a sweep.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use super::plot::{draw_panels, ImageFormat, LineChart, Series, VerticalMarker};
use super::sweep::{impact_points, SweepJson};
use super::table::num;
use crate::physics::metrics::sweep;
use crate::physics::rigid::{SEED_FIG6_BALL_SPEED, SEED_FIG6_BAT_SPEED};
use crate::physics::{Ball, Bat, CollisionOptions, Impact, ModeSet, RigidBat};

/// Axis label of impact point.
pub const Z_LABEL: &str = "impact point z (m from the knob)";
/// Axis label of exit speed.
pub const EXIT_SPEED_LABEL: &str = "ball exit speed (m/s)";
/// Number of vibrational modes drawn per preset in the mode-shape figure.
pub const SHAPES_PER_BAT: usize = 4;

/// What the figures are computed with.
#[derive(Debug, Clone)]
pub struct FigureSettings {
    /// Image format.
    pub format: ImageFormat,
    /// Impact points per curve.
    pub points: usize,
    /// Swing of Figures 2 and 5 (impact_z ignored).
    pub swing: Impact,
    /// Ball of the physical models (the seed's rigid tables use only its mass).
    pub ball: Ball,
    /// Numerical options of the physical models.
    pub options: CollisionOptions,
}

/// One figure written: its file name (relative to the directory) and caption.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureEntry {
    /// File name inside the directory.
    pub file: String,
    /// Caption (one paragraph, Markdown).
    pub caption: String,
}

/// A curve over impact points: flexible and rigid exit speed of one physical bat.
struct PhysicalCurve {
    flexible: Vec<(f64, f64)>,
    rigid: Vec<(f64, f64)>,
}

fn physical_curve(bat: &Bat, s: &FigureSettings, swing: &Impact, from: f64) -> Result<(PhysicalCurve, ModeSet)> {
    let modes = ModeSet::compute(bat, s.options.modes).with_context(|| format!("normal modes of '{}'", bat.name))?;
    let length = modes.length();
    let zs = impact_points(from, length - 0.005, None, Some(s.points))?;
    let points = sweep(&modes, &s.ball, swing, &zs, &s.options).with_context(|| format!("sweep of '{}'", bat.name))?;
    let curve = PhysicalCurve {
        flexible: points.iter().map(|p| (p.impact_z, p.result.exit_speed)).collect(),
        rigid: points.iter().map(|p| (p.impact_z, p.result.rigid_exit_speed)).collect(),
    };
    Ok((curve, modes))
}

/// The seed's rigid curve of a table bat; `bat_speed_at_impact` (Fig. 6) replaces the swing's rotation.
fn seed_curve(
    bat: &RigidBat,
    ball_mass: f64,
    swing: &Impact,
    bat_speed_at_impact: Option<f64>,
    from: f64,
    points: usize,
) -> Result<Vec<(f64, f64)>> {
    bat.validate().with_context(|| format!("seed bat '{}'", bat.name))?;
    let zs = impact_points(from, bat.length, None, Some(points))?;
    Ok(zs
        .into_iter()
        .map(|z| {
            let v = match bat_speed_at_impact {
                Some(v_bat) => bat.exit_speed_at(ball_mass, swing.ball_speed, v_bat, z),
                None => bat.exit_speed(ball_mass, &Impact { impact_z: z, ..*swing }),
            };
            (z, v)
        })
        .collect())
}

fn swing_text(swing: &Impact) -> String {
    format!(
        "ball {} m/s, bat CM {} m/s, ω {} rad/s",
        num(swing.ball_speed, 3),
        num(swing.bat_cm_speed, 3),
        num(swing.bat_angular_speed, 3)
    )
}

fn rigid_seed_bat(name: &str) -> Result<RigidBat> {
    RigidBat::preset(name).with_context(|| format!("seed table bat '{name}'"))
}

fn preset(name: &str) -> Result<Bat> {
    Bat::preset(name).with_context(|| format!("bat preset '{name}'"))
}

/// Writes every figure and `DIR/README.md`; returns the figures written.
pub fn write_figures(dir: &Path, s: &FigureSettings) -> Result<Vec<FigureEntry>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create '{}'", dir.display()))?;
    let ext = s.format.extension();
    let mut entries = Vec::new();
    let from = 0.25;
    let swing = s.swing;
    let m = s.ball.mass;

    // Figure 2: rigid exit speed against impact point.
    let normal = rigid_seed_bat("seed-table1-normal")?;
    let (r161, r161_modes) = physical_curve(&preset("r161")?, s, &swing, from)?;
    let seed_panel = LineChart {
        title: format!("Seed Table 1 bat, rigid, e_eff = {}", normal.effective_cor),
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series: vec![Series::solid(
            "seed Table 1 normal bat (rigid, eq. 4)",
            0,
            seed_curve(&normal, m, &swing, None, from, s.points)?,
        )],
        markers: vec![marker(normal.optimum_impact_z(m, &swing), "rigid optimum (eq. 6)", 6, false)],
        ..Default::default()
    };
    let mut model_panel = physical_panel("R161 (Nathan), physical model", &[("R161", &r161, 0)]);
    model_panel.markers.extend(node_markers(&r161_modes, from));
    let file = format!("fig2-rigid-exit-speed.{ext}");
    draw_panels(
        &dir.join(&file),
        &[seed_panel, model_panel],
        2,
        Some(&format!("Figure 2: exit speed vs impact point ({})", swing_text(&swing))),
    )?;
    entries.push(FigureEntry {
        file,
        caption: format!(
            "**Figure 2 — exit speed against impact point.** Left: the seed's rigid-bat model (its eq. 4) for the \
             Table 1 normal bat with its printed effective COR {}; the vertical line is the closed-form optimum \
             (eq. 6, re-derived). Right: the R161 wood bat as a flexible Timoshenko beam ({} modes, solid) and as a \
             rigid bat with the ball's e0 = {} (dashed), with the nodes of modes 1 and 2. Swing: {}.",
            normal.effective_cor,
            s.options.modes,
            s.ball.cor,
            swing_text(&swing)
        ),
    });

    // Figure 5: normal against corked.
    let corked = rigid_seed_bat("seed-table1-corked")?;
    let (r161c, _) = physical_curve(&preset("r161-corked")?, s, &swing, from)?;
    let seed_panel = LineChart {
        title: format!("Seed Table 1, rigid, e_eff = {}", normal.effective_cor),
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series: vec![
            Series::solid("normal bat", 0, seed_curve(&normal, m, &swing, None, from, s.points)?),
            Series::solid("corked bat", 1, seed_curve(&corked, m, &swing, None, from, s.points)?),
        ],
        ..Default::default()
    };
    let model_panel =
        physical_panel("Physical model: R161 vs R161 corked", &[("R161", &r161, 0), ("R161 corked", &r161c, 1)]);
    let file = format!("fig5-normal-vs-corked.{ext}");
    draw_panels(
        &dir.join(&file),
        &[seed_panel, model_panel],
        2,
        Some(&format!("Figure 5: normal vs corked bat ({})", swing_text(&swing))),
    )?;
    entries.push(FigureEntry {
        file,
        caption: format!(
            "**Figure 5 — normal against corked bat.** Left: the seed's Table 1 bats as printed (rigid, e_eff = {} \
             for both). Right: the R161 and the same bat with a 1-in, 10-in-deep cork-filled bore at the barrel end, \
             flexible (solid) and rigid with e0 (dashed). Swing: {}.",
            normal.effective_cor,
            swing_text(&swing)
        ),
    });

    // Figure 6: wood against aluminum at the seed's speeds (bat speed at the impact point, no rotation).
    let wood = rigid_seed_bat("seed-table2-wood")?;
    let alu = rigid_seed_bat("seed-table2-aluminum")?;
    let fig6_swing = Impact {
        ball_speed: SEED_FIG6_BALL_SPEED,
        bat_cm_speed: SEED_FIG6_BAT_SPEED,
        bat_angular_speed: 0.0,
        impact_z: f64::NAN,
    };
    let seed_panel = LineChart {
        title: "Seed Table 2, rigid, e_eff as printed".into(),
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series: vec![
            Series::solid(
                format!("wood (e_eff {})", wood.effective_cor),
                0,
                seed_curve(&wood, m, &fig6_swing, Some(SEED_FIG6_BAT_SPEED), from, s.points)?,
            ),
            Series::solid(
                format!("aluminum (e_eff {})", alu.effective_cor),
                1,
                seed_curve(&alu, m, &fig6_swing, Some(SEED_FIG6_BAT_SPEED), from, s.points)?,
            ),
        ],
        ..Default::default()
    };
    let (wood6, _) = physical_curve(&preset("r161")?, s, &fig6_swing, from)?;
    let (alu6, _) = physical_curve(&preset("aluminum")?, s, &fig6_swing, from)?;
    let model_panel =
        physical_panel("Physical model: R161 vs aluminum", &[("R161 wood", &wood6, 0), ("aluminum", &alu6, 1)]);
    let file = format!("fig6-wood-vs-aluminum.{ext}");
    let speeds = format!("v_ball = {SEED_FIG6_BALL_SPEED} m/s, v_bat = {SEED_FIG6_BAT_SPEED} m/s");
    draw_panels(
        &dir.join(&file),
        &[seed_panel, model_panel],
        2,
        Some(&format!("Figure 6: wood vs aluminum ({speeds})")),
    )?;
    entries.push(FigureEntry {
        file,
        caption: format!(
            "**Figure 6 — wood against aluminum** at the seed's {speeds}, taken as the bat's speed at the impact \
             point (no rotation, so the rigid optimum is the centre of mass). Left: the seed's Table 2 bats as \
             printed (rigid; e_eff {} and {}). Right: the R161 and the hollow aluminum preset (mass, length, CM and \
             I matched to Table 2), flexible (solid) and rigid with e0 (dashed).",
            wood.effective_cor, alu.effective_cor
        ),
    });

    // Mode shapes of every preset.
    let mut panels = Vec::new();
    for name in Bat::preset_names() {
        let bat = preset(name)?;
        let modes = ModeSet::compute(&bat, SHAPES_PER_BAT).with_context(|| format!("normal modes of '{name}'"))?;
        panels.push(mode_shapes_chart(name, &modes, SHAPES_PER_BAT));
    }
    let file = format!("mode-shapes.{ext}");
    draw_panels(&dir.join(&file), &panels, 2, Some("Free–free bending modes of the preset bats"))?;
    entries.push(FigureEntry {
        file,
        caption: format!(
            "**Mode shapes.** Transverse displacement of the first {SHAPES_PER_BAT} vibrational modes of each preset \
             (free–free Timoshenko beam), scaled to a peak of 1 and signed positive at the barrel end; legend gives \
             the frequencies. Zero crossings are the nodes."
        ),
    });

    std::fs::write(dir.join("README.md"), index_markdown(&entries, s))
        .with_context(|| format!("cannot write '{}'", dir.join("README.md").display()))?;
    Ok(entries)
}

fn marker(x: f64, label: &str, color: usize, dashed: bool) -> VerticalMarker {
    VerticalMarker { x, label: label.to_string(), color, dashed }
}

/// Nodes of modes 1 and 2 at or beyond `from`, as dashed markers.
fn node_markers(modes: &ModeSet, from: f64) -> Vec<VerticalMarker> {
    let mut out = Vec::new();
    for (n, color) in [(1usize, 2usize), (2, 3)] {
        if modes.vibrational_count() >= n {
            for z in modes.nodes(n).into_iter().filter(|z| *z >= from) {
                out.push(marker(z, &format!("node of mode {n}"), color, true));
            }
        }
    }
    out
}

fn physical_panel(title: &str, curves: &[(&str, &PhysicalCurve, usize)]) -> LineChart {
    let mut series = Vec::new();
    for (label, curve, color) in curves {
        series.push(Series::solid(format!("{label} flexible"), *color, curve.flexible.clone()));
        series.push(Series::dashed(format!("{label} rigid (e0)"), *color, curve.rigid.clone()));
    }
    LineChart {
        title: title.into(),
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series,
        ..Default::default()
    }
}

/// Flexible and rigid exit speed of a sweep with the nodes of modes 1 and 2 and the sweet spot marked.
pub fn exit_speed_chart(doc: &SweepJson) -> LineChart {
    let flexible = doc.points.iter().map(|p| (p.impact_z, p.exit_speed)).collect();
    let rigid = doc.points.iter().map(|p| (p.impact_z, p.rigid_exit_speed)).collect();
    let (lo, hi) = doc
        .points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.impact_z), hi.max(p.impact_z)));
    let within = |z: &f64| *z >= lo && *z <= hi;
    let mut markers = Vec::new();
    for z in doc.nodes.mode1.iter().filter(|z| within(z)) {
        markers.push(marker(*z, "node of mode 1", 2, true));
    }
    for z in doc.nodes.mode2.iter().filter(|z| within(z)) {
        markers.push(marker(*z, "node of mode 2", 3, true));
    }
    if within(&doc.sweet_spots.max_exit_speed_z) {
        markers.push(marker(
            doc.sweet_spots.max_exit_speed_z,
            &format!("sweet spot (max exit speed, {} m)", num(doc.sweet_spots.max_exit_speed_z, 3)),
            6,
            false,
        ));
    }
    LineChart {
        title: format!(
            "{}: exit speed vs impact point (ball {} m/s, bat CM {} m/s, ω {} rad/s)",
            doc.bat.name,
            num(doc.swing.ball_speed, 3),
            num(doc.swing.bat_cm_speed, 3),
            num(doc.swing.bat_angular_speed, 3)
        ),
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series: vec![
            Series::solid(format!("flexible bat ({} modes)", doc.options.modes), 0, flexible),
            Series::dashed(format!("rigid bat (e0 = {})", doc.ball.cor), 1, rigid),
        ],
        markers,
        ..Default::default()
    }
}

/// Flexible exit speed of several sweeps (e.g. one per bat) on one chart, each bat's sweet spot marked.
pub fn exit_speed_overlay_chart(title: &str, docs: &[SweepJson]) -> LineChart {
    let mut series = Vec::new();
    let mut markers = Vec::new();
    for (i, doc) in docs.iter().enumerate() {
        series.push(Series::solid(
            doc.bat.name.clone(),
            i,
            doc.points.iter().map(|p| (p.impact_z, p.exit_speed)).collect(),
        ));
        markers.push(marker(
            doc.sweet_spots.max_exit_speed_z,
            &format!("{} sweet spot ({} m)", doc.bat.name, num(doc.sweet_spots.max_exit_speed_z, 3)),
            i,
            true,
        ));
    }
    LineChart {
        title: title.to_string(),
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series,
        markers,
        ..Default::default()
    }
}

/// The first `count` vibrational mode shapes of `modes`, each scaled to a peak of 1, positive at the barrel.
pub fn mode_shapes_chart(title: &str, modes: &ModeSet, count: usize) -> LineChart {
    let length = modes.length();
    let samples = 200;
    let frequencies = modes.frequencies_hz();
    let mut series = Vec::new();
    for n in 1..=count.min(modes.vibrational_count()) {
        // Index 0 and 1 are the rigid modes in ModeSet's full list.
        let shape: Vec<(f64, f64)> =
            (0..=samples).map(|k| length * k as f64 / samples as f64).map(|z| (z, modes.shape_at(n + 1, z))).collect();
        let peak = shape.iter().fold(0.0f64, |acc, p| acc.max(p.1.abs()));
        let tip = shape.last().map(|p| p.1).unwrap_or(1.0);
        let scale = if peak > 0.0 { tip.signum() / peak } else { 1.0 };
        let frequency = frequencies.get(n - 1).copied().unwrap_or(f64::NAN);
        series.push(Series::solid(
            format!("mode {n}: {} Hz", num(frequency, 4)),
            n - 1,
            shape.into_iter().map(|(z, y)| (z, y * scale)).collect(),
        ));
    }
    LineChart {
        title: title.to_string(),
        x_label: "z (m from the knob)".into(),
        y_label: "displacement (peak = 1)".into(),
        series,
        x_range: Some((0.0, length)),
        y_range: Some((-1.15, 1.15)),
        zero_line: true,
        ..Default::default()
    }
}

/// The Markdown index of the figures.
pub fn index_markdown(entries: &[FigureEntry], s: &FigureSettings) -> String {
    let mut out = String::from("# sweetspot figures\n\n");
    let _ = writeln!(
        out,
        "Written by `sweetspot figures` ({} vibrational modes, RK4 step {} s, ball e0 = {}, {} impact points per \
         curve). The seed is the MCM 2010 paper the project started from; its Tables 1 and 2 are used as printed.\n",
        s.options.modes,
        num(s.options.time_step, 3),
        s.ball.cor,
        s.points
    );
    for e in entries {
        let _ = writeln!(out, "## {}\n\n![{}]({})\n\n{}\n", e.file, e.file, e.file, e.caption);
    }
    out
}
