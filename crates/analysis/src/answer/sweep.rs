//! `sweetspot sweep`'s answer: exit speed over impact points (head-on), or exit speed, launch angle and spin
//! over the undercut at one impact point (oblique), with the refusals of flags that do not belong to the
//! sweep asked for.

use anyhow::{bail, Result};
use serde::Serialize;

use super::inputs::ObliqueFlags;
use super::simulate::DEFAULT_IMPACT_FROM_TIP;
use crate::report::sweep::{run_sweep, run_undercut_sweep, ObliqueSwing, SweepJson, SweepRange, UndercutSweepJson};
use sweetspot_physics::{Ball, Bat, CollisionOptions, Impact};

/// What a sweep varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SweepOver {
    /// The impact point along the bat (head-on).
    ImpactPoint,
    /// The undercut at one impact point (oblique).
    Undercut,
}

/// The document of `sweetspot sweep --json`, as the sweep asked for has it.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum SweepDocument {
    /// Over impact points.
    ImpactPoint(SweepJson),
    /// Over the undercut.
    Undercut(UndercutSweepJson),
}

/// The oblique flags and `--impact-z` a sweep over `over` refuses, with the command line's message.
pub fn check_flags(over: SweepOver, oblique: &ObliqueFlags, impact_z: Option<f64>) -> Result<()> {
    let active = oblique.inputs()?.active;
    match over {
        SweepOver::ImpactPoint if active || impact_z.is_some() => bail!(
            "--undercut/--attack-angle/--pitch-angle/--pitch-spin/--tangential-cor/--friction/--bat-tilt/\
             --swing-direction/--batter-side and --impact-z belong to --over undercut (a sweep over z is head-on; `simulate` takes them at chosen points)"
        ),
        SweepOver::Undercut if oblique.undercut.is_some() => {
            bail!("--undercut is the swept variable of --over undercut: give its range with --from/--to")
        }
        _ => Ok(()),
    }
}

/// `sweetspot sweep`: `swing` (its impact point unused) over `range` of impact points, or of undercuts at
/// `impact_z` (m from the knob; default 0.15 m from the barrel end) with the other oblique inputs held.
#[allow(clippy::too_many_arguments)]
pub fn sweep(
    bat: &Bat,
    ball: &Ball,
    swing: &Impact,
    over: SweepOver,
    oblique: &ObliqueFlags,
    impact_z: Option<f64>,
    range: SweepRange,
    options: &CollisionOptions,
) -> Result<SweepDocument> {
    check_flags(over, oblique, impact_z)?;
    if over == SweepOver::ImpactPoint {
        return Ok(SweepDocument::ImpactPoint(run_sweep(bat, ball, swing, range, options)?));
    }
    let inputs = oblique.inputs()?;
    let impact_z = impact_z.unwrap_or(bat.length() - DEFAULT_IMPACT_FROM_TIP);
    let held = ObliqueSwing {
        attack_angle: inputs.attack_angle,
        pitch_angle: inputs.pitch_angle,
        pitch_spin: inputs.pitch_spin,
        contact: inputs.contact,
        bat_tilt: inputs.bat_tilt,
        swing_direction: inputs.swing_direction,
        batter_side: inputs.batter_side,
    };
    Ok(SweepDocument::Undercut(run_undercut_sweep(bat, ball, swing, &held, impact_z, range, options)?))
}
