//! `sweetspot bbcor`: the bat's BBCOR and BESR under the certification protocols implemented by the physics
//! core (documented in `physics::metrics`), with the protocol parameters printed.

pub use crate::answer::bbcor::*;
use anyhow::Result;
use clap::Args;

use super::common::{emit, print_json, BallArgs, BatArgs, NumericArgs, OutputArgs};
use crate::physics::metrics::BBCOR_BALL_SPEED;
use crate::physics::units::{INCH, MPH};
use crate::physics::Ball;
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
