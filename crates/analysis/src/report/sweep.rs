//! The exit-speed sweep as a document: flexible and rigid exit speed over impact points, the sweet-spot set
//! and the nodes of modes 1 and 2 (what `sweetspot sweep` prints and the figures draw); and the undercut
//! sweep: exit speed, launch angle and spin against the undercut at one impact point (the speed–spin
//! trade-off of an oblique impact).

// Negated comparisons (`!(a < b)`) are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use serde::Serialize;

use rayon::prelude::*;

use super::json::{
    BallJson, BatJson, CollisionJson, FlightJson, ObliqueInputsJson, OptionsJson, SweetSpotsJson, SwingJson,
};
use super::plot::{LineChart, Series};
use super::table::num;
use sweetspot_physics::metrics::{sweep, sweet_spots};
use sweetspot_physics::{
    collide_oblique, collide_spatial, Ball, Bat, BatterSide, CollisionOptions, Impact, ModeSet, ObliqueImpact,
    SpatialImpact, SweepPoint, TangentialContact,
};

/// Length of the default sweep range, ending 1 cm short of the barrel end, m.
pub const DEFAULT_BARREL_LENGTH: f64 = 0.35;
/// Default step between impact points, m.
pub const DEFAULT_STEP: f64 = 0.005;
/// Largest number of impact points in one sweep.
pub const MAX_POINTS: usize = 100_000;

/// The JSON document of `sweetspot sweep --json`.
#[derive(Debug, Serialize)]
pub struct SweepJson {
    /// The bat's mass properties (of the discretised beam).
    pub bat: BatJson,
    /// The ball.
    pub ball: BallJson,
    /// The swing.
    pub swing: SwingJson,
    /// Numerical options.
    pub options: OptionsJson,
    /// The sweet-spot set for this swing.
    pub sweet_spots: SweetSpotsJson,
    /// Node positions of vibrational modes 1 and 2, m from the knob.
    pub nodes: NodesJson,
    /// One collision per impact point, ascending z.
    pub points: Vec<CollisionJson>,
    /// The plot written, if any.
    pub plot: Option<PathBuf>,
}

/// Node positions of the first two vibrational modes, m from the knob.
#[derive(Debug, Clone, Serialize)]
pub struct NodesJson {
    /// Mode 1.
    pub mode1: Vec<f64>,
    /// Mode 2.
    pub mode2: Vec<f64>,
}

/// The impact points of a sweep from `from` to `to` (inclusive) by `step` or in `points` points.
pub fn impact_points(from: f64, to: f64, step: Option<f64>, points: Option<usize>) -> Result<Vec<f64>> {
    if !(from < to) {
        bail!("--from = {from} m must be less than --to = {to} m");
    }
    let count = match (step, points) {
        (_, Some(n)) => {
            if !(2..=MAX_POINTS).contains(&n) {
                bail!("--points = {n} is out of range: expected 2 ≤ points ≤ {MAX_POINTS}");
            }
            n
        }
        (step, None) => {
            let step = step.unwrap_or(DEFAULT_STEP);
            if !(step > 0.0) {
                bail!("--step = {step} m is out of range: expected step > 0");
            }
            let n = ((to - from) / step * (1.0 + 1e-9)).floor() as usize + 1;
            if n > MAX_POINTS {
                bail!("--step = {step} m gives {n} points: expected at most {MAX_POINTS}");
            }
            if n < 2 {
                return Ok(vec![from]);
            }
            return Ok((0..n).map(|i| from + i as f64 * step).collect());
        }
    };
    Ok((0..count).map(|i| from + (to - from) * i as f64 / (count - 1) as f64).collect())
}

/// Runs the sweep in chunks (for a progress bar when stderr is a terminal); each chunk is parallel.
pub fn sweep_with_progress(
    modes: &ModeSet,
    ball: &Ball,
    swing: &Impact,
    zs: &[f64],
    options: &CollisionOptions,
) -> Result<Vec<SweepPoint>> {
    if !std::io::stderr().is_terminal() || zs.len() < 64 {
        return Ok(sweep(modes, ball, swing, zs, options)?);
    }
    let bar = indicatif::ProgressBar::new(zs.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} impact points ({eta})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message("sweeping");
    let chunk = zs.len().div_ceil(20).max(rayon::current_num_threads() * 4);
    let mut out = Vec::with_capacity(zs.len());
    for part in zs.chunks(chunk) {
        out.extend(sweep(modes, ball, swing, part, options)?);
        bar.inc(part.len() as u64);
    }
    bar.finish_and_clear();
    Ok(out)
}

/// A complete sweep: modes, points, sweet spots, nodes.
pub fn run_sweep(
    bat: &Bat,
    ball: &Ball,
    swing: &Impact,
    range: SweepRange,
    options: &CollisionOptions,
) -> Result<SweepJson> {
    // At least two vibrational modes are solved so that the nodes of modes 1 and 2 exist even when fewer
    // (or none: the rigid bat) are integrated.
    let modes =
        ModeSet::compute(bat, options.modes.max(2)).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
    let props = modes.mass_properties();
    let from = range.from.unwrap_or((props.length - DEFAULT_BARREL_LENGTH).max(0.0));
    let to = range.to.unwrap_or(props.length - 0.01);
    let zs = impact_points(from, to, range.step, range.points)?;
    let points = sweep_with_progress(&modes, ball, swing, &zs, options).context("exit-speed sweep")?;
    let spots = sweet_spots(&modes, ball, swing, options).context("sweet spots")?;
    let nodes = NodesJson { mode1: modes.nodes(1), mode2: modes.nodes(2) };
    Ok(SweepJson {
        bat: BatJson::new(&bat.name, &props),
        ball: ball.into(),
        swing: swing.into(),
        options: options.into(),
        sweet_spots: (&spots).into(),
        nodes,
        points: points.iter().map(|p| CollisionJson::new(p.impact_z, &p.result)).collect(),
        plot: None,
    })
}

/// `--from`, `--to`, `--step`, `--points`.
#[derive(Debug, Clone, Copy, Default)]
pub struct SweepRange {
    /// First point, m.
    pub from: Option<f64>,
    /// Last point, m.
    pub to: Option<f64>,
    /// Step, m.
    pub step: Option<f64>,
    /// Point count.
    pub points: Option<usize>,
}

/// Default undercut range: ± this fraction of the reach R + R_k (ball plus barrel radius), past the onset of
/// sliding so that the spin's maximum shows.
pub const DEFAULT_UNDERCUT_REACH: f64 = 0.75;
/// Default number of undercut points (odd, so that the head-on D = 0 is one of them).
pub const DEFAULT_UNDERCUT_POINTS: usize = 37;

/// The oblique swing of an undercut sweep, everything but the undercut, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObliqueSwing {
    /// Attack angle, rad.
    pub attack_angle: f64,
    /// Pitch descent angle, rad.
    pub pitch_angle: f64,
    /// Pitch spin, rad/s, backspin positive.
    pub pitch_spin: f64,
    /// The tangential contact law.
    pub contact: TangentialContact,
    /// Tilt of the bat's long axis below the horizontal, rad (barrel below the hands positive).
    pub bat_tilt: f64,
    /// Horizontal direction of the bat's path, rad, positive toward the right-field side.
    pub swing_direction: f64,
    /// The batter's side.
    pub batter_side: BatterSide,
}

/// One point of an undercut sweep.
#[derive(Debug, Clone, Serialize)]
pub struct UndercutPointJson {
    /// Undercut D, m (ball centre above the bat's path positive).
    pub undercut: f64,
    /// Ball exit speed, m/s.
    pub exit_speed: f64,
    /// Launch angle above the horizontal, degrees.
    pub launch_angle_deg: f64,
    /// Outgoing backspin, rpm, topspin negative.
    pub spin_rpm: f64,
    /// Spray angle, spin components, total spin and spin axis.
    #[serde(flatten)]
    pub flight: FlightJson,
    /// Outgoing velocity along the line of centres, m/s.
    pub normal_exit_speed: f64,
    /// Outgoing velocity along the tangent, m/s (planar swings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential_exit_speed: Option<f64>,
    /// True when the ball slid throughout the contact.
    pub sliding: bool,
}

/// The JSON document of `sweetspot sweep --over undercut --json`.
#[derive(Debug, Serialize)]
pub struct UndercutSweepJson {
    /// Always "undercut".
    pub over: &'static str,
    /// The bat's mass properties.
    pub bat: BatJson,
    /// The ball.
    pub ball: BallJson,
    /// The swing along the bat's path.
    pub swing: SwingJson,
    /// Numerical options.
    pub options: OptionsJson,
    /// The oblique inputs held fixed (its `undercut` is 0: the swept undercut is in `points`).
    pub oblique: ObliqueInputsJson,
    /// Impact point, m from the knob.
    pub impact_z: f64,
    /// Barrel radius at the impact point, m.
    pub barrel_radius: f64,
    /// One oblique collision per undercut, ascending.
    pub points: Vec<UndercutPointJson>,
    /// The plot written, if any.
    pub plot: Option<PathBuf>,
}

/// Exit speed, launch angle and spin against the undercut at `impact_z` (m from the knob). The undercut
/// range (m) defaults to ± [`DEFAULT_UNDERCUT_REACH`] (R + R_k) in [`DEFAULT_UNDERCUT_POINTS`] points.
pub fn run_undercut_sweep(
    bat: &Bat,
    ball: &Ball,
    swing: &Impact,
    oblique: &ObliqueSwing,
    impact_z: f64,
    range: SweepRange,
    options: &CollisionOptions,
) -> Result<UndercutSweepJson> {
    let modes = ModeSet::compute(bat, options.modes).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
    let props = modes.mass_properties();
    if !(impact_z > 0.0 && impact_z < props.length) {
        bail!("--impact-z = {impact_z} m is out of range: expected 0 < impact_z < {} m", props.length);
    }
    let barrel_radius = bat.radii_at(impact_z).0;
    let reach = DEFAULT_UNDERCUT_REACH * (ball.radius + barrel_radius);
    let points = match (range.step, range.points) {
        (None, None) => Some(DEFAULT_UNDERCUT_POINTS),
        (_, points) => points,
    };
    let undercuts = impact_points(range.from.unwrap_or(-reach), range.to.unwrap_or(reach), range.step, points)?;
    let impact = Impact { impact_z, ..*swing };
    let points = undercuts
        .par_iter()
        .map(|&undercut| undercut_point(&modes, ball, impact, barrel_radius, undercut, oblique, options))
        .collect::<Result<Vec<_>>>()?;
    Ok(UndercutSweepJson {
        over: "undercut",
        bat: BatJson::new(&bat.name, &props),
        ball: ball.into(),
        swing: swing.into(),
        options: options.into(),
        oblique: ObliqueInputsJson::new(
            0.0,
            oblique.attack_angle,
            oblique.pitch_angle,
            oblique.pitch_spin,
            &oblique.contact,
        )
        .with_spatial(oblique.bat_tilt, oblique.swing_direction, oblique.batter_side),
        impact_z,
        barrel_radius,
        points,
        plot: None,
    })
}

/// One undercut's collision, planar when the swing is level and square, else in 3-D.
fn undercut_point(
    modes: &ModeSet,
    ball: &Ball,
    impact: Impact,
    barrel_radius: f64,
    undercut: f64,
    oblique: &ObliqueSwing,
    options: &CollisionOptions,
) -> Result<UndercutPointJson> {
    let planar = ObliqueImpact {
        impact,
        barrel_radius,
        undercut,
        attack_angle: oblique.attack_angle,
        pitch_angle: oblique.pitch_angle,
        pitch_spin: oblique.pitch_spin,
    };
    let context = || format!("oblique collision at undercut = {undercut} m");
    // A level square swing is collide_spatial's planar case, answered by collide_oblique itself.
    if oblique.bat_tilt == 0.0 && oblique.swing_direction == 0.0 {
        let r = collide_oblique(modes, ball, &planar, &oblique.contact, options).with_context(context)?;
        return Ok(UndercutPointJson {
            undercut,
            exit_speed: r.exit_speed,
            launch_angle_deg: r.launch_angle_deg(),
            spin_rpm: r.spin_rpm(),
            flight: FlightJson::planar(&r),
            normal_exit_speed: r.normal_exit_speed,
            tangential_exit_speed: Some(r.tangential_exit_speed),
            sliding: r.sliding,
        });
    }
    let spatial = SpatialImpact {
        oblique: planar,
        bat_tilt: oblique.bat_tilt,
        swing_direction: oblique.swing_direction,
        batter_side: oblique.batter_side,
    };
    let r = collide_spatial(modes, ball, &spatial, &oblique.contact, options).with_context(context)?;
    let flight = FlightJson::new(&r);
    Ok(UndercutPointJson {
        undercut,
        exit_speed: r.exit_speed,
        launch_angle_deg: r.launch_angle.to_degrees(),
        spin_rpm: flight.backspin_rpm,
        flight,
        normal_exit_speed: r.normal.exit_speed,
        tangential_exit_speed: None,
        sliding: r.sliding,
    })
}

/// The three panels of the speed–spin trade-off: exit speed, launch angle and spin against the undercut (mm).
pub fn undercut_charts(doc: &UndercutSweepJson) -> Vec<LineChart> {
    let series = |f: fn(&UndercutPointJson) -> f64| doc.points.iter().map(|p| (p.undercut * 1e3, f(p))).collect();
    let chart = |title: &str, y_label: &str, label: &str, color: usize, points: Vec<(f64, f64)>| LineChart {
        title: title.into(),
        x_label: "undercut D (mm, ball centre above the bat's path +)".into(),
        y_label: y_label.into(),
        series: vec![Series::solid(label, color, points)],
        zero_line: true,
        ..Default::default()
    };
    let mut spin_chart = chart("spin vs undercut", "spin (rpm, backspin +)", "spin", 2, series(|p| p.spin_rpm));
    // A three-dimensional swing's spin is more than its backspin: draw the total a radar reports beside it.
    if doc.points.iter().any(|p| p.tangential_exit_speed.is_none()) {
        spin_chart.y_label = "spin (rpm)".into();
        spin_chart.series[0].label = "backspin".into();
        spin_chart.series.push(Series::solid("total spin", 3, series(|p| p.flight.total_spin_rpm)));
    }
    vec![
        chart("exit speed vs undercut", "ball exit speed (m/s)", "exit speed", 0, series(|p| p.exit_speed)),
        chart("launch angle vs undercut", "launch angle (deg)", "launch angle", 1, series(|p| p.launch_angle_deg)),
        spin_chart,
    ]
}

/// The figure's overall title.
pub fn undercut_title(doc: &UndercutSweepJson) -> String {
    format!(
        "{} at z = {} m: the speed–spin trade-off (ball {} m/s, bat CM {} m/s, ω {} rad/s, e_T {}, μ {})",
        doc.bat.name,
        num(doc.impact_z, 3),
        num(doc.swing.ball_speed, 3),
        num(doc.swing.bat_cm_speed, 3),
        num(doc.swing.bat_angular_speed, 3),
        num(doc.oblique.tangential_cor, 3),
        num(doc.oblique.friction, 3),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_by_step_and_count() {
        let zs = impact_points(0.5, 0.6, Some(0.05), None).unwrap();
        assert_eq!(zs.len(), 3);
        assert!((zs[2] - 0.6).abs() < 1e-12);
        let zs = impact_points(0.5, 0.6, None, Some(5)).unwrap();
        assert_eq!(zs, vec![0.5, 0.525, 0.55, 0.575, 0.6]);
        assert!(impact_points(0.6, 0.5, None, None).is_err());
        assert!(impact_points(0.5, 0.6, Some(-1.0), None).is_err());
        assert!(impact_points(0.5, 0.6, None, Some(1)).is_err());
        assert!(impact_points(0.0, 1.0, Some(1e-9), None).is_err());
    }
}
