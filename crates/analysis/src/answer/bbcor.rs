//! The answer of `sweetspot bbcor` (and Python's `bbcor`): the bat's BBCOR and BESR under the certification protocols implemented by the physics
//! core (documented in `physics::metrics`), with the protocol parameters printed.

use anyhow::{Context, Result};
use serde::Serialize;

use crate::report::json::{BallJson, BatJson, OptionsJson};
use sweetspot_physics::metrics::{bbcor_report, besr, besr_scan, BESR_BALL_SPEED, BESR_BAT_SPEED, PIVOT_Z};
use sweetspot_physics::units::INCH;
use sweetspot_physics::{Ball, Bat, CollisionOptions, ModeSet};

/// BBCOR result and protocol (NCAA / ASTM F2219 as modelled).
#[derive(Debug, Clone, Serialize)]
pub struct BbcorResultJson {
    /// Bat–ball COR, dimensionless.
    pub bbcor: f64,
    /// Impact point where the maximum was found, m from the knob.
    pub impact_z: f64,
    /// Collision efficiency e_A = v_out/v_in there.
    pub collision_efficiency: f64,
    /// Test ball speed, m/s.
    pub ball_speed: f64,
    /// Bat speed before impact, m/s (at rest).
    pub bat_speed: f64,
    /// Pivot of the test stand, m from the knob (the bat is modelled as free).
    pub pivot_z: f64,
    /// Start of the impact search range, m from the knob (9 in from the barrel end).
    pub search_from_z: f64,
    /// End of the impact search range, m from the knob (3 in from the barrel end).
    pub search_to_z: f64,
}

/// BESR result and protocol (ASTM F2219 ball exit speed ratio as modelled).
#[derive(Debug, Clone, Serialize)]
pub struct BesrJson {
    /// Ball exit speed ratio e_A + ½, dimensionless.
    pub besr: f64,
    /// Impact point, m from the knob (6 in from the barrel end).
    pub impact_z: f64,
    /// Ball exit speed, m/s.
    pub exit_speed: f64,
    /// Pitch speed, m/s (70 mph).
    pub ball_speed: f64,
    /// Bat speed at the impact point, m/s (66 mph), turning about the pivot.
    pub bat_speed: f64,
    /// Pivot, m from the knob.
    pub pivot_z: f64,
    /// BESR at the point of largest exit speed 3–9 in from the barrel end, the bat turning as above so the
    /// point 6 in from the end moves at 66 mph: the value the certification test judged.
    pub best_besr: f64,
    /// Where that largest exit speed was found, m from the knob.
    pub best_impact_z: f64,
    /// That largest exit speed, m/s.
    pub best_exit_speed: f64,
}

/// The JSON document of `sweetspot bbcor --json`.
#[derive(Debug, Serialize)]
pub struct BbcorJson {
    /// The bat's mass properties.
    pub bat: BatJson,
    /// The protocol ball.
    pub ball: BallJson,
    /// Numerical options.
    pub options: OptionsJson,
    /// BBCOR.
    pub bbcor: BbcorResultJson,
    /// BESR.
    pub besr: BesrJson,
}

/// Computes the document for `sweetspot bbcor`.
pub fn bbcor_document(bat: &Bat, ball: &Ball, options: &CollisionOptions) -> Result<BbcorJson> {
    let modes = ModeSet::compute(bat, options.modes).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
    let props = modes.mass_properties();
    let b = bbcor_report(&modes, ball, options).context("BBCOR")?;
    let e = besr(&modes, ball, options).context("BESR")?;
    let best = besr_scan(&modes, ball, options).context("BESR over the barrel")?;
    Ok(BbcorJson {
        bat: BatJson::new(&bat.name, &props),
        ball: ball.into(),
        options: options.into(),
        bbcor: BbcorResultJson {
            bbcor: b.bbcor,
            impact_z: b.impact_z,
            collision_efficiency: b.collision_efficiency,
            ball_speed: b.ball_speed,
            bat_speed: 0.0,
            pivot_z: PIVOT_Z,
            search_from_z: props.length - 9.0 * INCH,
            search_to_z: props.length - 3.0 * INCH,
        },
        besr: BesrJson {
            besr: e.besr,
            impact_z: e.impact_z,
            exit_speed: e.exit_speed,
            ball_speed: BESR_BALL_SPEED,
            bat_speed: BESR_BAT_SPEED,
            pivot_z: PIVOT_Z,
            best_besr: best.besr,
            best_impact_z: best.impact_z,
            best_exit_speed: best.exit_speed,
        },
    })
}
