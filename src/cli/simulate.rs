//! `sweetspot simulate`: one collision per impact point, from flags or a case file.

pub use crate::answer::simulate::*;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::case_file::load_case;
use super::common::{
    emit, finite_f64, print_json, BallArgs, BatArgs, NumericArgs, ObliqueArgs, ObliqueInputs, OutputArgs, SwingArgs,
};
use crate::physics::{Ball, Bat, CollisionOptions, Impact};

/// Arguments of `sweetspot simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// A case file (JSON or YAML; bat and ball by preset name or inline, see docs/file-formats.md) instead of
    /// the bat, ball and swing flags.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["bat", "ball_preset", "ball_mass", "ball_radius", "ball_cor",
        "ball_stiffness", "ball_exponent", "ball_speed", "bat_cm_speed", "bat_angular_speed", "impact_z", "modes", "dt",
        "undercut", "attack_angle", "pitch_angle", "pitch_spin", "tangential_cor", "friction", "bat_tilt",
        "swing_direction", "batter_side"])]
    pub case: Option<PathBuf>,
    #[command(flatten)]
    pub bat: BatArgs,
    #[command(flatten)]
    pub ball: BallArgs,
    #[command(flatten)]
    pub swing: SwingArgs,
    #[command(flatten)]
    pub oblique: ObliqueArgs,
    /// Impact point(s), m from the knob; repeat the flag or give a comma list [default: 0.15 m from the barrel end].
    #[arg(long, value_name = "M", value_delimiter = ',', value_parser = finite_f64, allow_negative_numbers = true)]
    pub impact_z: Vec<f64>,
    #[command(flatten)]
    pub numeric: NumericArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Everything one run needs.
struct Run {
    bat: Bat,
    ball: Ball,
    swing: Impact,
    oblique: ObliqueInputs,
    impact_zs: Vec<f64>,
    options: CollisionOptions,
}

/// Runs `sweetspot simulate`.
pub fn run(args: SimulateArgs) -> Result<()> {
    let run = match &args.case {
        Some(path) => {
            let case = load_case(path)?;
            Run {
                bat: case.bat,
                ball: case.ball,
                swing: case.swing,
                oblique: case.oblique,
                impact_zs: case.impact_zs,
                options: case.options,
            }
        }
        None => Run {
            bat: args.bat.load()?,
            ball: args.ball.apply(Ball::game())?,
            swing: args.swing.impact(f64::NAN),
            oblique: args.oblique.inputs()?,
            impact_zs: args.impact_z.clone(),
            options: args.numeric.options()?,
        },
    };
    let document = simulate(&run.bat, &run.ball, &run.swing, &run.oblique, &run.impact_zs, &run.options)?;
    if args.output.json {
        print_json(&document)
    } else {
        emit(&render(&document))
    }
}
