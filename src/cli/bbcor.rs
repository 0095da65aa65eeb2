//! `sweetspot bbcor`: the bat's BBCOR and BESR under the certification protocols implemented by the physics
//! core (documented in `physics::metrics`), with the protocol parameters printed.

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;

use super::common::{emit, print_json, BallArgs, BatArgs, NumericArgs, OutputArgs};
use crate::physics::metrics::{
    bbcor_report, besr, besr_scan, BBCOR_BALL_SPEED, BESR_BALL_SPEED, BESR_BAT_SPEED, PIVOT_Z,
};
use crate::physics::units::{INCH, MPH};
use crate::physics::{Ball, Bat, CollisionOptions, ModeSet};
use crate::report::json::{BallJson, BatJson, OptionsJson};
use crate::report::table::{num, Table};

/// Arguments of `sweetspot bbcor`.
#[derive(Debug, Args)]
pub struct BbcorArgs {
    #[command(flatten)]
    pub bat: BatArgs,
    /// Overrides of the protocol ball (default: the baseball with e0 = 0.50).
    #[command(flatten)]
    pub ball: BallArgs,
    #[command(flatten)]
    pub numeric: NumericArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

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

/// Runs `sweetspot bbcor`.
pub fn run(args: BbcorArgs) -> Result<()> {
    let bat = args.bat.load()?;
    let ball = args.ball.apply(Ball::bbcor_protocol())?;
    let options = args.numeric.options()?;
    let doc = bbcor_document(&bat, &ball, &options)?;
    if args.output.json {
        return print_json(&doc);
    }
    let mut out = doc.bat.table().render();
    out.push_str(&format!(
        "\nball   mass {} kg, radius {} m, k1 {} N/m^α, α {}, e0 {} (protocol ball)\nmodel  {} vibrational modes, RK4 step {} s\n\n",
        num(doc.ball.mass, 4),
        num(doc.ball.radius, 4),
        num(doc.ball.stiffness, 4),
        num(doc.ball.exponent, 4),
        super::common::cor_text(&doc.ball),
        doc.options.modes,
        num(doc.options.time_step, 3)
    ));
    let b = &doc.bbcor;
    let mut t = Table::new(["BBCOR (NCAA / ASTM F2219, as modelled)", ""]);
    t.row(["BBCOR".to_string(), num(b.bbcor, 4)]);
    t.row(["at impact point (m from knob)".to_string(), num(b.impact_z, 4)]);
    t.row(["collision efficiency e_A there".to_string(), num(b.collision_efficiency, 4)]);
    t.row([
        "ball speed (m/s)".to_string(),
        format!("{} ({} mph)", num(b.ball_speed, 4), num(BBCOR_BALL_SPEED / MPH, 4)),
    ]);
    t.row(["bat".to_string(), "at rest, free (pivot 6 in from knob in the lab)".to_string()]);
    t.row([
        "impact search (m from knob)".to_string(),
        format!("{} … {} (9 in … 3 in from the barrel end)", num(b.search_from_z, 4), num(b.search_to_z, 4)),
    ]);
    out.push_str(&t.render());
    out.push('\n');
    let e = &doc.besr;
    let mut t = Table::new(["BESR (ASTM F2219 ball exit speed ratio, as modelled)", ""]);
    t.row(["BESR = e_A + 1/2".to_string(), num(e.besr, 4)]);
    t.row(["exit speed (m/s)".to_string(), num(e.exit_speed, 4)]);
    t.row(["impact point (m from knob)".to_string(), format!("{} (6 in from the barrel end)", num(e.impact_z, 4))]);
    t.row(["pitch speed (m/s)".to_string(), format!("{} (70 mph)", num(e.ball_speed, 4))]);
    t.row([
        "bat speed at impact (m/s)".to_string(),
        format!("{} (66 mph, turning about {} m from the knob)", num(e.bat_speed, 4), num(e.pivot_z, 4)),
    ]);
    t.row(["largest BESR, 9 in … 3 in from the end".to_string(), num(e.best_besr, 4)]);
    t.row([
        "  exit speed there (m/s)".to_string(),
        format!("{} ({} mph)", num(e.best_exit_speed, 4), num(e.best_exit_speed / MPH, 4)),
    ]);
    t.row([
        "  at impact point (m from knob)".to_string(),
        format!(
            "{} ({} in from the barrel end)",
            num(e.best_impact_z, 4),
            num((doc.bat.length - e.best_impact_z) / INCH, 3)
        ),
    ]);
    out.push_str(&t.render());
    emit(&out)
}
