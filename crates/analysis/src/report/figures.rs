//! The seed paper's Figures 2, 5 and 6 redrawn twice — from its rigid Tables 1/2 (effective COR as printed)
//! and from the physical models (flexible beam, 18 modes, the hollow barrel's hoop mode) — Figures 5 and 6
//! also at equal batter effort (each bat at the speed [`sweetspot_physics::batter`] predicts for its swing
//! weight), exit speed along the barrel of the `compare` bats at equal effort, exit speed, BBCOR and hoop
//! frequency against the alloy barrel's wall thickness, the mode shapes of every preset, and an index
//! (`README.md`) with captions; and the exit-speed charts of a sweep.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use super::plot::{draw_panels, ImageFormat, LegendAt, LineChart, LineKind, Series, VerticalMarker};
use super::sweep::{impact_points, SweepJson};
use super::table::num;
use sweetspot_physics::batter::{
    speed_ratio, swing_weight, Batter, ReferenceSwing, SwingPrediction, SwingShape, DEFAULT_EXPONENT,
    DEFAULT_IMPACT_FROM_BARREL_END, DEFAULT_SWING_LENGTH,
};
use sweetspot_physics::metrics::{bbcor, linspace, sweep};
use sweetspot_physics::rigid::{SEED_FIG6_BALL_SPEED, SEED_FIG6_BAT_SPEED};
use sweetspot_physics::{collide, Ball, Bat, CollisionOptions, Impact, MassProperties, ModeSet, RigidBat};

/// Axis label of impact point.
pub const Z_LABEL: &str = "impact point z (m from the knob)";
/// What "e0" on a chart means.
pub const E0_NOTE: &str =
    "e0: the ball's coefficient of restitution against a rigid wall (what the ball alone returns)";
/// What a "rigid" curve on a chart is.
pub const RIGID_NOTE: &str =
    "rigid (e0): the same bat as one rigid body, the collision losing only the ball's e0; flexible: vibrations too";
/// What "e_eff" on the seed's panels means.
pub const E_EFF_NOTE: &str =
    "e_eff: the seed paper's effective bat-ball COR, one number for the whole collision, as its tables print it";
/// Axis label of exit speed.
pub const EXIT_SPEED_LABEL: &str = "ball exit speed (m/s)";
/// Number of vibrational modes drawn per preset in the mode-shape figure.
pub const SHAPES_PER_BAT: usize = 4;
/// The bats of the equal-effort comparison figure (the first is the batter's reference bat).
pub const EQUAL_EFFORT_BATS: [&str; 4] = ["r161", "r161-corked", "aluminum", "torpedo"];
/// Barrel wall thicknesses of the wall-thickness figure, m: from 1.5 mm (thinner than any alloy barrel) to
/// 8 mm (h/a ≈ 0.25, where the hoop compliance has all but vanished).
pub const WALL_THICKNESS_RANGE: (f64, f64) = (0.0015, 0.008);
/// Number of wall thicknesses drawn.
pub const WALL_THICKNESS_POINTS: usize = 14;
/// Where the wall-thickness figure's exit speed and hoop frequency are taken: this far from the barrel
/// end, m (6 in, the batter's usual impact point).
pub const WALL_FIGURE_IMPACT_FROM_END: f64 = DEFAULT_IMPACT_FROM_BARREL_END;

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

/// Where the seed figures' curves start, m from the knob.
const CURVES_FROM: f64 = 0.25;

/// The seed's panel of a figure: exit speed against impact point at its printed effective COR.
fn seed_panel(title: String, series: Vec<Series>) -> LineChart {
    LineChart {
        notes: vec![E_EFF_NOTE.into()],
        title,
        x_label: Z_LABEL.into(),
        y_label: EXIT_SPEED_LABEL.into(),
        series,
        ..Default::default()
    }
}

/// Fig. 6's swing: the bat translating at `v_bat` into the seed's ball, no rotation.
fn fig6_swing(v_bat: f64) -> Impact {
    Impact { ball_speed: SEED_FIG6_BALL_SPEED, bat_cm_speed: v_bat, bat_angular_speed: 0.0, impact_z: f64::NAN }
}

/// What every figure of [`write_figures`] shares: the directory it lands in and the settings it is drawn with.
struct FigureWriter<'a> {
    dir: &'a Path,
    s: &'a FigureSettings,
}

impl FigureWriter<'_> {
    /// The seed's rigid curve of a table bat over the figures' impact points.
    fn seed(&self, bat: &RigidBat, swing: &Impact, bat_speed_at_impact: Option<f64>) -> Result<Vec<(f64, f64)>> {
        seed_curve(bat, self.s.ball.mass, swing, bat_speed_at_impact, CURVES_FROM, self.s.points)
    }

    /// The physical model's curve of a bat over the figures' impact points.
    fn physical(&self, bat: &Bat, swing: &Impact) -> Result<(PhysicalCurve, ModeSet)> {
        physical_curve(bat, self.s, swing, CURVES_FROM)
    }

    /// Draws the seed's panel beside the model's into `STEM.EXT` under `title`.
    fn seed_beside_model(
        &self,
        stem: &str,
        panels: [LineChart; 2],
        title: &str,
        caption: String,
    ) -> Result<FigureEntry> {
        let file = format!("{stem}.{}", self.s.format.extension());
        draw_panels(&self.dir.join(&file), &panels, 2, Some(title))?;
        Ok(FigureEntry { file, caption })
    }

    /// Figure 2: rigid exit speed against impact point.
    fn figure2(&self, normal: &RigidBat, r161: &PhysicalCurve, r161_modes: &ModeSet) -> Result<FigureEntry> {
        let (s, swing, m) = (self.s, &self.s.swing, self.s.ball.mass);
        let seed = LineChart {
            markers: vec![marker(normal.optimum_impact_z(m, swing), "rigid optimum (eq. 6)", 6, false)],
            ..seed_panel(
                format!("Seed Table 1 bat, rigid, e_eff = {}", normal.effective_cor),
                vec![Series::solid("seed Table 1 normal bat (rigid, eq. 4)", 0, self.seed(normal, swing, None)?)],
            )
        };
        let mut model = physical_panel("R161 (Nathan), physical model", &[("R161", r161, 0)]);
        model.markers.extend(node_markers(r161_modes, CURVES_FROM));
        self.seed_beside_model(
            "fig2-rigid-exit-speed",
            [seed, model],
            &format!("Figure 2: exit speed vs impact point ({})", swing_text(swing)),
            format!(
                "**Figure 2 — exit speed against impact point.** Left: the seed's rigid-bat model (its eq. 4) for \
                 the Table 1 normal bat with its printed effective COR {}; the vertical line is the closed-form \
                 optimum (eq. 6, re-derived). Right: the R161 wood bat as a flexible Timoshenko beam ({} modes, \
                 solid) and as a rigid bat with the ball's e0 = {} (dashed), with the nodes of modes 1 and 2. \
                 Swing: {}.",
                normal.effective_cor,
                s.options.modes,
                s.ball.cor,
                swing_text(swing)
            ),
        )
    }

    /// Figure 5: normal against corked.
    fn figure5(&self, normal: &RigidBat, corked: &RigidBat, r161: &PhysicalCurve) -> Result<FigureEntry> {
        let swing = &self.s.swing;
        let (r161c, _) = self.physical(&preset("r161-corked")?, swing)?;
        let seed = seed_panel(
            format!("Seed Table 1, rigid, e_eff = {}", normal.effective_cor),
            vec![
                Series::solid("normal bat", 0, self.seed(normal, swing, None)?),
                Series::solid("corked bat", 1, self.seed(corked, swing, None)?),
            ],
        );
        let model =
            physical_panel("Physical model: R161 vs R161 corked", &[("R161", r161, 0), ("R161 corked", &r161c, 1)]);
        self.seed_beside_model(
            "fig5-normal-vs-corked",
            [seed, model],
            &format!("Figure 5: normal vs corked bat ({})", swing_text(swing)),
            format!(
                "**Figure 5 — normal against corked bat.** Left: the seed's Table 1 bats as printed (rigid, e_eff = \
                 {} for both). Right: the R161 and the same bat with a 1-in, 10-in-deep cork-filled bore at the \
                 barrel end, flexible (solid) and rigid with e0 (dashed). Swing: {}.",
                normal.effective_cor,
                swing_text(swing)
            ),
        )
    }

    /// Figure 6: wood against aluminum at the seed's speeds (bat speed at the impact point, no rotation).
    fn figure6(&self, wood: &RigidBat, alu: &RigidBat) -> Result<FigureEntry> {
        let swing = fig6_swing(SEED_FIG6_BAT_SPEED);
        let seed = seed_panel(
            "Seed Table 2, rigid, e_eff as printed".into(),
            vec![
                Series::solid(
                    format!("wood (e_eff {})", wood.effective_cor),
                    0,
                    self.seed(wood, &swing, Some(SEED_FIG6_BAT_SPEED))?,
                ),
                Series::solid(
                    format!("aluminum (e_eff {})", alu.effective_cor),
                    1,
                    self.seed(alu, &swing, Some(SEED_FIG6_BAT_SPEED))?,
                ),
            ],
        );
        let (wood6, _) = self.physical(&preset("r161")?, &swing)?;
        let (alu6, alu_modes6) = self.physical(&preset("aluminum")?, &swing)?;
        let alu_hoop = hoop_text(&alu_modes6);
        let model = physical_panel(
            "Physical model: R161 wood vs hollow aluminum (with its hoop mode)",
            &[("R161 wood", &wood6, 0), ("aluminum + trampoline", &alu6, 1)],
        );
        let speeds = format!("v_ball = {SEED_FIG6_BALL_SPEED} m/s, v_bat = {SEED_FIG6_BAT_SPEED} m/s");
        self.seed_beside_model(
            "fig6-wood-vs-aluminum",
            [seed, model],
            &format!("Figure 6: wood vs aluminum ({speeds})"),
            format!(
                "**Figure 6 — wood against aluminum** at the seed's {speeds}, taken as the bat's speed at the impact \
                 point (no rotation, so the rigid optimum is the centre of mass). Left: the seed's Table 2 bats as \
                 printed (rigid; e_eff {} and {}). Right: the R161 and the hollow aluminum preset (mass, length, CM \
                 and I matched to Table 2), flexible with the barrel wall's hoop (trampoline) mode in the collision \
                 (solid; {alu_hoop}) and rigid with e0 (dashed; no trampoline). The wood bat has no hoop mode.",
                wood.effective_cor, alu.effective_cor
            ),
        )
    }

    /// Figure 5 at equal batter effort: the seed's Table 1 bats and the R161 pair, each pair's batter measured
    /// with the normal bat.
    fn figure5_equal_effort(&self, normal: &RigidBat, corked: &RigidBat) -> Result<FigureEntry> {
        let swing = &self.s.swing;
        let seed_batter = batter_with_swing(seed_props(normal), swing)?;
        let seed_corked = seed_batter.predict(&seed_props(corked))?;
        let r161 = preset("r161")?;
        let r161c = preset("r161-corked")?;
        let batter = batter_with_swing(r161.mass_properties(), swing)?;
        let corked_swing = batter.predict(&r161c.mass_properties())?;
        let corked_impact = swing_of(&corked_swing, swing.ball_speed);
        let (normal_curve, _) = self.physical(&r161, swing)?;
        let (corked_curve, _) = self.physical(&r161c, &corked_impact)?;
        let seed = seed_panel(
            format!("Seed Table 1, rigid, e_eff = {}, equal effort", normal.effective_cor),
            vec![
                Series::solid("normal bat (reference swing)", 0, self.seed(normal, swing, None)?),
                Series::solid(
                    format!("corked bat (×{} speed)", num(seed_corked.speed_ratio, 4)),
                    1,
                    self.seed(corked, &swing_of(&seed_corked, swing.ball_speed), None)?,
                ),
            ],
        );
        let model = physical_panel(
            "Physical model at equal effort: R161 vs R161 corked",
            &[
                ("R161", &normal_curve, 0),
                (&format!("R161 corked (×{} speed)", num(corked_swing.speed_ratio, 4)), &corked_curve, 1),
            ],
        );
        self.seed_beside_model(
            "fig5-normal-vs-corked-equal-effort",
            [seed, model],
            &format!("Figure 5 at equal batter effort (normal bat: {})", swing_text(swing)),
            format!(
                "**Figure 5 at equal batter effort.** As Figure 5, but the corked bat is swung as the same batter \
                 would swing it: the normal bat at the figure's swing, the corked bat {}× faster in the seed's \
                 Table 1 (swing weight {} vs {} kg·m² about the 6-in pivot) and {}× faster for the R161 pair ({} vs \
                 {} kg·m²), from v ∝ I^(−{DEFAULT_EXPONENT}) with the swing's pivot kept (`physics::batter`).",
                num(seed_corked.speed_ratio, 4),
                num(seed_corked.swing_weight, 4),
                num(seed_batter.reference_swing_weight(), 4),
                num(corked_swing.speed_ratio, 4),
                num(corked_swing.swing_weight, 4),
                num(batter.reference_swing_weight(), 4),
            ),
        )
    }

    /// Figure 6 at equal batter effort: the seed's translation-only swing of the wood bat; the aluminum bat's
    /// speed scaled by the speed ratio of the two swing weights (the swing has no rotation, so there is no
    /// pivot to keep).
    fn figure6_equal_effort(&self, wood: &RigidBat, alu: &RigidBat) -> Result<FigureEntry> {
        let seed_ratio =
            speed_ratio(swing_weight(&seed_props(alu)), swing_weight(&seed_props(wood)), DEFAULT_EXPONENT)?;
        let wood_bat = preset("r161")?;
        let alu_bat = preset("aluminum")?;
        let ratio = speed_ratio(
            swing_weight(&alu_bat.mass_properties()),
            swing_weight(&wood_bat.mass_properties()),
            DEFAULT_EXPONENT,
        )?;
        let seed_alu_speed = SEED_FIG6_BAT_SPEED * seed_ratio;
        let alu_speed = SEED_FIG6_BAT_SPEED * ratio;
        let seed = seed_panel(
            "Seed Table 2, rigid, e_eff as printed, equal effort".into(),
            vec![
                Series::solid(
                    format!("wood (e_eff {}, {} m/s)", wood.effective_cor, SEED_FIG6_BAT_SPEED),
                    0,
                    self.seed(wood, &fig6_swing(SEED_FIG6_BAT_SPEED), Some(SEED_FIG6_BAT_SPEED))?,
                ),
                Series::solid(
                    format!("aluminum (e_eff {}, {} m/s)", alu.effective_cor, num(seed_alu_speed, 3)),
                    1,
                    self.seed(alu, &fig6_swing(seed_alu_speed), Some(seed_alu_speed))?,
                ),
            ],
        );
        let (wood_curve, _) = self.physical(&wood_bat, &fig6_swing(SEED_FIG6_BAT_SPEED))?;
        let (alu_curve, alu_modes) = self.physical(&alu_bat, &fig6_swing(alu_speed))?;
        let model = physical_panel(
            "Physical model at equal effort: R161 wood vs hollow aluminum",
            &[
                ("R161 wood", &wood_curve, 0),
                (&format!("aluminum + trampoline ({} m/s)", num(alu_speed, 3)), &alu_curve, 1),
            ],
        );
        self.seed_beside_model(
            "fig6-wood-vs-aluminum-equal-effort",
            [seed, model],
            &format!(
                "Figure 6 at equal batter effort (v_ball = {SEED_FIG6_BALL_SPEED} m/s, wood v_bat = \
                 {SEED_FIG6_BAT_SPEED} m/s)"
            ),
            format!(
                "**Figure 6 at equal batter effort.** As Figure 6, but the aluminum bat's speed at the impact point \
                 is the wood bat's {SEED_FIG6_BAT_SPEED} m/s times the batter model's speed ratio of the two swing \
                 weights (n = {DEFAULT_EXPONENT}): {} m/s for the seed's Table 2 bats, {} m/s for the R161 and the \
                 aluminum preset ({hoop}).",
                num(seed_alu_speed, 4),
                num(alu_speed, 4),
                hoop = hoop_text(&alu_modes),
            ),
        )
    }

    /// Mode shapes of every preset.
    fn mode_shapes(&self) -> Result<FigureEntry> {
        let mut panels = Vec::new();
        for name in Bat::preset_names() {
            let bat = preset(name)?;
            let modes = ModeSet::compute(&bat, SHAPES_PER_BAT).with_context(|| format!("normal modes of '{name}'"))?;
            panels.push(mode_shapes_chart(name, &modes, SHAPES_PER_BAT));
        }
        let file = format!("mode-shapes.{}", self.s.format.extension());
        draw_panels(&self.dir.join(&file), &panels, 2, Some("Free–free bending modes of the preset bats"))?;
        Ok(FigureEntry {
            file,
            caption: format!(
                "**Mode shapes.** Transverse displacement of the first {SHAPES_PER_BAT} vibrational modes of each \
                 preset (free–free Timoshenko beam), scaled to a peak of 1 and signed positive at the barrel end; \
                 legend gives the frequencies. Zero crossings are the nodes."
            ),
        })
    }
}

/// Writes every figure and `DIR/README.md`; returns the figures written.
pub fn write_figures(dir: &Path, s: &FigureSettings) -> Result<Vec<FigureEntry>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create '{}'", dir.display()))?;
    let figures = FigureWriter { dir, s };
    let normal = rigid_seed_bat("seed-table1-normal")?;
    let (r161, r161_modes) = figures.physical(&preset("r161")?, &s.swing)?;
    let mut entries = vec![figures.figure2(&normal, &r161, &r161_modes)?];
    let corked = rigid_seed_bat("seed-table1-corked")?;
    entries.push(figures.figure5(&normal, &corked, &r161)?);
    let wood = rigid_seed_bat("seed-table2-wood")?;
    let alu = rigid_seed_bat("seed-table2-aluminum")?;
    entries.push(figures.figure6(&wood, &alu)?);
    entries.push(figures.figure5_equal_effort(&normal, &corked)?);
    entries.push(figures.figure6_equal_effort(&wood, &alu)?);
    entries.push(write_compare_figure(dir, s)?);
    entries.push(write_wall_thickness_figure(dir, s)?);
    entries.push(figures.mode_shapes()?);
    std::fs::write(dir.join("README.md"), index_markdown(&entries, s))
        .with_context(|| format!("cannot write '{}'", dir.join("README.md").display()))?;
    Ok(entries)
}

fn hoop_text(modes: &ModeSet) -> String {
    let z = modes.length() - WALL_FIGURE_IMPACT_FROM_END;
    match modes.hoop_frequency_at(z) {
        Some(f) => format!("hoop frequency {} Hz 6 in from the end", num(f, 4)),
        None => "no hoop mode".to_string(),
    }
}

fn seed_props(bat: &RigidBat) -> MassProperties {
    MassProperties::from_totals(bat.mass, bat.length, bat.center_of_mass, bat.moment_of_inertia)
}

/// A batter who swings `bat` with `swing` (its centre-of-mass and angular speeds; impact_z ignored), with
/// the default exponent, usual impact point and swing length, keeping the swing's pivot on other bats.
pub fn batter_with_swing(bat: MassProperties, swing: &Impact) -> Result<Batter> {
    let reference =
        ReferenceSwing { bat, bat_cm_speed: swing.bat_cm_speed, bat_angular_speed: swing.bat_angular_speed };
    Ok(Batter::new(
        reference,
        DEFAULT_EXPONENT,
        DEFAULT_IMPACT_FROM_BARREL_END,
        DEFAULT_SWING_LENGTH,
        SwingShape::SamePivot,
    )?)
}

fn swing_of(prediction: &SwingPrediction, ball_speed: f64) -> Impact {
    Impact {
        ball_speed,
        bat_cm_speed: prediction.bat_cm_speed,
        bat_angular_speed: prediction.bat_angular_speed,
        impact_z: f64::NAN,
    }
}

/// One bat's exit speed along the barrel as a batter swings it at the reference effort.
#[derive(Debug, Clone)]
pub struct EqualEffortCurve {
    /// Bat name.
    pub name: String,
    /// The batter's swing of this bat.
    pub swing: SwingPrediction,
    /// (impact point m from the knob, exit speed m/s) along the barrel.
    pub points: Vec<(f64, f64)>,
}

/// Exit speed along the barrel (from the middle of the bat to 1 cm from its end, `points` impact points) of
/// each of `bats` as `batter` swings it at the reference effort against a pitch at `pitch_speed` (m/s).
pub fn equal_effort_curves(
    batter: &Batter,
    bats: &[Bat],
    ball: &Ball,
    pitch_speed: f64,
    options: &CollisionOptions,
    points: usize,
) -> Result<Vec<EqualEffortCurve>> {
    let mut curves = Vec::with_capacity(bats.len());
    for bat in bats {
        let modes = ModeSet::compute(bat, options.modes).with_context(|| format!("normal modes of '{}'", bat.name))?;
        let swing =
            batter.predict(&modes.mass_properties()).with_context(|| format!("batter swinging '{}'", bat.name))?;
        let length = modes.length();
        let zs = linspace(0.5 * length, length - 0.01, points.max(2));
        let sweep = sweep(&modes, ball, &swing.impact(pitch_speed), &zs, options)
            .with_context(|| format!("exit speed along '{}'", bat.name))?;
        curves.push(EqualEffortCurve {
            name: bat.name.clone(),
            swing,
            points: sweep.iter().map(|p| (p.impact_z, p.result.exit_speed)).collect(),
        });
    }
    Ok(curves)
}

/// The chart of [`equal_effort_curves`]: one line per bat, labelled with its swing weight and bat speed, its
/// usual impact point marked.
pub fn equal_effort_chart(title: &str, curves: &[EqualEffortCurve]) -> LineChart {
    let mut series = Vec::new();
    let mut markers = Vec::new();
    for (i, c) in curves.iter().enumerate() {
        series.push(Series::solid(
            format!(
                "{} (swing weight {} kg·m², {} m/s)",
                c.name,
                num(c.swing.swing_weight, 4),
                num(c.swing.bat_speed, 4)
            ),
            i,
            c.points.clone(),
        ));
        markers.push(marker(c.swing.impact_z, &format!("{} usual impact point", c.name), i, true));
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

fn write_compare_figure(dir: &Path, s: &FigureSettings) -> Result<FigureEntry> {
    let bats = EQUAL_EFFORT_BATS.iter().map(|n| preset(n)).collect::<Result<Vec<_>>>()?;
    let batter = Batter::typical(bats[0].mass_properties())?;
    let curves = equal_effort_curves(&batter, &bats, &s.ball, s.swing.ball_speed, &s.options, s.points)?;
    let file = format!("fig-compare-equal-effort.{}", s.format.extension());
    let title = format!(
        "Exit speed along the barrel at equal batter effort (pitch {} m/s, n = {})",
        num(s.swing.ball_speed, 3),
        batter.exponent
    );
    super::plot::draw_line_chart(&dir.join(&file), &equal_effort_chart(&title, &curves))?;
    Ok(FigureEntry {
        file,
        caption: format!(
            "**Bats at equal batter effort** (`sweetspot compare`'s figure). The Statcast-average batter ({} m/s \
             6 in from the end of the R161, swinging about the knob) swings each bat at the speed v ∝ I^(−{}) \
             predicts for its swing weight; exit speed along the barrel against a {} m/s pitch; dashed lines: the \
             batter's usual impact point (6 in from the end) on each bat.",
            num(batter.reference_speed(), 4),
            batter.exponent,
            num(s.swing.ball_speed, 3)
        ),
    })
}

/// One barrel wall of the alloy profile: its exit speed, BBCOR and hoop frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallPoint {
    /// Barrel wall thickness, m.
    pub wall: f64,
    /// Bat mass, kg (the wall's own mass changes it).
    pub mass: f64,
    /// Exit speed at the impact point for the figure's swing, m/s.
    pub exit_speed: f64,
    /// BBCOR under the certification protocol.
    pub bbcor: f64,
    /// Hoop frequency at the impact point, Hz (`None` without a hoop mode).
    pub hoop_frequency: Option<f64>,
    /// Contact time of the collision at the impact point, s.
    pub contact_time: f64,
}

/// Exit speed (the swing `swing` meeting the ball `from_end` m from the barrel end), BBCOR and hoop frequency
/// of `Bat::alloy_profile` for each barrel wall in `walls` (m).
pub fn wall_thickness_sweep(
    walls: &[f64],
    ball: &Ball,
    swing: &Impact,
    from_end: f64,
    options: &CollisionOptions,
) -> Result<Vec<WallPoint>> {
    walls
        .iter()
        .map(|&wall| {
            let bat = Bat::alloy_profile("alloy", wall).with_context(|| format!("alloy profile, wall {wall} m"))?;
            let modes = ModeSet::compute(&bat, options.modes).with_context(|| format!("modes, wall {wall} m"))?;
            let z = modes.length() - from_end;
            let result = collide(&modes, ball, &Impact { impact_z: z, ..*swing }, options)
                .with_context(|| format!("collision, wall {wall} m"))?;
            Ok(WallPoint {
                wall,
                mass: modes.mass_properties().mass,
                exit_speed: result.exit_speed,
                bbcor: bbcor(&modes, options).with_context(|| format!("BBCOR, wall {wall} m"))?,
                hoop_frequency: modes.hoop_frequency_at(z),
                contact_time: result.contact_time,
            })
        })
        .collect()
}

fn write_wall_thickness_figure(dir: &Path, s: &FigureSettings) -> Result<FigureEntry> {
    let walls = linspace(WALL_THICKNESS_RANGE.0, WALL_THICKNESS_RANGE.1, WALL_THICKNESS_POINTS);
    let data = wall_thickness_sweep(&walls, &s.ball, &s.swing, WALL_FIGURE_IMPACT_FROM_END, &s.options)?;
    let mm = |w: f64| w * 1e3;
    let x_label = "barrel wall thickness (mm)".to_string();
    let exit = LineChart {
        title: format!("Exit speed 6 in from the end ({})", swing_text(&s.swing)),
        x_label: x_label.clone(),
        y_label: EXIT_SPEED_LABEL.into(),
        series: vec![Series::solid("exit speed", 0, data.iter().map(|p| (mm(p.wall), p.exit_speed)).collect())],
        markers: vec![marker(mm(sweetspot_physics::bat::ALUMINUM_BARREL_WALL), "aluminum preset wall", 6, true)],
        ..Default::default()
    };
    let bbcor_chart = LineChart {
        title: "BBCOR (NCAA limit 0.50)".into(),
        x_label: x_label.clone(),
        y_label: "BBCOR".into(),
        series: vec![
            Series::solid("BBCOR", 1, data.iter().map(|p| (mm(p.wall), p.bbcor)).collect()),
            Series::dashed("NCAA limit 0.50", 6, data.iter().map(|p| (mm(p.wall), 0.5)).collect()),
        ],
        ..Default::default()
    };
    let hoop = LineChart {
        title: "Hoop frequency 6 in from the end, and 2/contact time".into(),
        x_label,
        y_label: "frequency (Hz)".into(),
        series: vec![
            Series::solid(
                "hoop frequency",
                2,
                data.iter().filter_map(|p| p.hoop_frequency.map(|f| (mm(p.wall), f))).collect(),
            ),
            Series::dashed(
                "2/contact time",
                3,
                data.iter().filter(|p| p.contact_time > 0.0).map(|p| (mm(p.wall), 2.0 / p.contact_time)).collect(),
            ),
        ],
        ..Default::default()
    };
    let file = format!("fig-wall-thickness.{}", s.format.extension());
    draw_panels(
        &dir.join(&file),
        &[exit, bbcor_chart, hoop],
        1,
        Some("Alloy barrel: exit speed, BBCOR and hoop frequency against wall thickness"),
    )?;
    Ok(FigureEntry {
        file,
        caption: format!(
            "**Wall thickness.** The `aluminum` profile (`Bat::alloy_profile`) with barrel walls from {} to {} mm: \
             exit speed 6 in from the end for the figure's swing, BBCOR under the NCAA protocol, and the barrel's \
             hoop (n = 2) frequency there on a shared wall-thickness axis, with 2/contact time — the frequency \
             whose period is half the contact — for comparison. {} The exit speed keeps rising with the wall \
             because the bat gets heavier (same swing speed).",
            mm(WALL_THICKNESS_RANGE.0),
            mm(WALL_THICKNESS_RANGE.1),
            bbcor_trend(&data),
        ),
    })
}

/// What the BBCOR panel shows, read off its data: where BBCOR is largest, and where the hoop frequency
/// crosses 2/contact time.
fn bbcor_trend(data: &[WallPoint]) -> String {
    let Some(top) = data.iter().max_by(|a, b| a.bbcor.total_cmp(&b.bbcor)) else { return String::new() };
    let thinnest = data.first().is_some_and(|p| p.wall == top.wall);
    let largest = if thinnest {
        format!("BBCOR is largest at the thinnest wall drawn ({:.1} mm, {:.3}) and falls as the wall thickens: a stiffer wall stores less and gives less back.", top.wall * 1e3, top.bbcor)
    } else {
        format!("BBCOR is largest inside the range drawn ({:.1} mm, {:.3}).", top.wall * 1e3, top.bbcor)
    };
    let crossing = data.windows(2).find_map(|pair| {
        let gap = |p: &WallPoint| Some(p.hoop_frequency? - 2.0 / p.contact_time);
        let (a, b) = (gap(&pair[0])?, gap(&pair[1])?);
        (a < 0.0 && b >= 0.0).then(|| pair[0].wall + (pair[1].wall - pair[0].wall) * a / (a - b))
    });
    match crossing {
        Some(wall) => format!("{largest} The hoop frequency passes 2/contact time at a {:.1} mm wall.", wall * 1e3),
        None => largest,
    }
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
        notes: vec![E0_NOTE.into(), RIGID_NOTE.into()],
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
    // The sweet spot often lies within a centimetre of the first mode's node: the node is a dashed line, the
    // sweet spot a solid one and a ring on the curve's maximum, each labelled with its position.
    let mut markers = Vec::new();
    for z in doc.nodes.mode1.iter().filter(|z| within(z)) {
        markers.push(marker(*z, &format!("node of mode 1 ({} m)", num(*z, 3)), 2, true));
    }
    for z in doc.nodes.mode2.iter().filter(|z| within(z)) {
        markers.push(marker(*z, &format!("node of mode 2 ({} m)", num(*z, 3)), 3, true));
    }
    let mut series = vec![
        Series::solid(format!("flexible bat ({} modes)", doc.options.modes), 0, flexible),
        Series::dashed(format!("rigid bat (e0 = {})", doc.ball.cor), 1, rigid),
    ];
    let spot = &doc.sweet_spots;
    if within(&spot.max_exit_speed_z) {
        let line = format!("sweet spot ({} m)", num(spot.max_exit_speed_z, 3));
        markers.push(marker(spot.max_exit_speed_z, &line, 6, false));
        series.push(Series {
            label: format!("max exit speed {} m/s", num(spot.max_exit_speed, 4)),
            points: vec![(spot.max_exit_speed_z, spot.max_exit_speed)],
            color: 6,
            kind: LineKind::Markers { radius: 7, filled: false },
        });
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
        series,
        markers,
        // The curves leave the bottom middle free (they rise to the sweet spot and fall beyond it).
        legend: LegendAt::LowerMiddle,
        notes: vec![E0_NOTE.into(), RIGID_NOTE.into()],
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The README's caption of the wall-thickness figure says where BBCOR is largest as the plot shows it.
    #[test]
    fn the_wall_thickness_caption_names_the_largest_bbcor_the_plot_shows() {
        let options = CollisionOptions { modes: 6, ..CollisionOptions::default() };
        let swing = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: f64::NAN };
        let walls = linspace(WALL_THICKNESS_RANGE.0, WALL_THICKNESS_RANGE.1, WALL_THICKNESS_POINTS);
        let data = wall_thickness_sweep(&walls, &Ball::default(), &swing, WALL_FIGURE_IMPACT_FROM_END, &options)
            .expect("sweep");
        let top = data.iter().max_by(|a, b| a.bbcor.total_cmp(&b.bbcor)).expect("points");
        let dir = tempfile::tempdir().unwrap();
        let settings = FigureSettings { format: ImageFormat::Svg, points: 20, swing, ball: Ball::default(), options };
        let entry = write_wall_thickness_figure(dir.path(), &settings).expect("figure");
        let said = format!("{:.1} mm, {:.3}", top.wall * 1e3, top.bbcor);
        assert!(entry.caption.contains(&said), "the caption does not name {said}: {}", entry.caption);
    }

    /// Every chart `sweetspot figures` draws (the seed's figures, their equal-effort twins, the bats compared,
    /// the wall thickness, the mode shapes) keeps its legend off the data.
    #[test]
    fn no_legend_of_the_figures_covers_a_plotted_point() {
        let dir = tempfile::tempdir().unwrap();
        let swing = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: f64::NAN };
        let settings = FigureSettings {
            format: ImageFormat::Svg,
            points: 150,
            swing,
            ball: Ball::default(),
            options: CollisionOptions::default(),
        };
        super::super::plot::DRAWN.with(|d| d.borrow_mut().clear());
        write_figures(dir.path(), &settings).expect("figures");
        let drawn = super::super::plot::DRAWN.with(|d| d.take());
        assert!(drawn.len() >= 15, "{} charts", drawn.len());
        let covered: Vec<_> = drawn.iter().flat_map(super::super::plot::points_under_legend).collect();
        assert!(covered.is_empty(), "legends over data: {covered:?}");
    }

    /// Physics of a thin alloy barrel: the hoop frequency rises with the wall (∝ h for a thin ring), the bat
    /// gets heavier, and beyond the wall of the largest BBCOR (about 3 mm, where the hoop period is about
    /// half the contact time) the trampoline — and with it BBCOR — fades as the wall thickens.
    #[test]
    fn wall_thickness_data_is_monotone_where_the_physics_says_so() {
        let options = CollisionOptions { modes: 4, ..CollisionOptions::default() };
        let swing = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: f64::NAN };
        let walls = [0.003, 0.004, 0.005, 0.0075];
        let data = wall_thickness_sweep(&walls, &Ball::default(), &swing, WALL_FIGURE_IMPACT_FROM_END, &options)
            .expect("sweep");
        for pair in data.windows(2) {
            let (thin, thick) = (&pair[0], &pair[1]);
            assert!(thick.mass > thin.mass, "{pair:?}");
            let (f_thin, f_thick) = (thin.hoop_frequency.expect("hoop"), thick.hoop_frequency.expect("hoop"));
            assert!(f_thick > f_thin, "{pair:?}");
            assert!(thick.bbcor < thin.bbcor, "BBCOR should fall toward a thick wall: {pair:?}");
        }
        // Thin-ring scaling f ∝ h/a² (a the mid-surface radius, outer radius 2⅝ in / 2 fixed).
        let outer = 2.625 / 2.0 * sweetspot_physics::units::INCH;
        let ring = |h: f64| h / (outer - 0.5 * h).powi(2);
        let ratio = data[3].hoop_frequency.unwrap() / data[0].hoop_frequency.unwrap();
        let expected = ring(0.0075) / ring(0.003);
        assert!((ratio / expected - 1.0).abs() < 1e-6, "f(7.5 mm)/f(3 mm) = {ratio}, thin ring {expected}");
    }
}
