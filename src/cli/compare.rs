//! `sweetspot compare`: bats compared as one batter swings them — at equal effort, not at equal bat speed.
//!
//! For each bat: swing weight (moment of inertia about the 6-in pivot), the bat speed the batter model
//! (`physics::batter`) predicts for it, the sweet spot and best exit speed for that swing, the exit speed at
//! the batter's usual impact point, BBCOR, the swing's duration and the reaction time gained against the
//! first bat (with the distance the pitch travels meanwhile).
//!
//! The batter file (`--batter FILE`, TOML; every key optional, the defaults are the Statcast average batter
//! of `Batter::typical`):
//!
//! ```toml
//! reference_bat = "r161"          # preset or bat file (relative to this file) the swing was measured with
//! bat_speed = 31.96               # m/s at the usual impact point of the reference bat
//! impact_from_barrel_end = 0.1524 # m: the usual impact point, the same distance from the end on every bat
//! pivot_z = 0.0                   # m from the knob: the swing's instantaneous centre at contact
//! exponent = 0.25                 # n of v ∝ I^(−n), 0 ≤ n ≤ 0.5
//! swing_length = 2.225            # m: arc of the impact point from the start of the swing to contact
//! shape = "same-pivot"            # or "same-ratio" (ω/V kept; with exponent 0, today's equal-speed comparison)
//! ```

// Negated comparisons (`!(a < b)`) are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub use crate::answer::compare::*;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use clap::Args;

use super::common::{emit, finite_f64, print_json, BallArgs, NumericArgs, OutputArgs, DEFAULT_BALL_SPEED};
use crate::physics::batter::Batter;
use crate::physics::{Ball, Bat, CollisionOptions};
use crate::report::figures::{equal_effort_chart, equal_effort_curves};
use crate::report::plot::{draw_line_chart, ImageFormat};
use crate::report::table::num;

/// Arguments of `sweetspot compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Comma-separated bats (presets r161, r161-corked, aluminum, torpedo, or bat files); the first is the
    /// baseline of the reaction time gained.
    #[arg(long, value_name = "BAT,BAT,...", default_value = DEFAULT_BATS)]
    pub bats: String,
    /// Batter file (TOML, every key optional): reference_bat, bat_speed, impact_from_barrel_end, pivot_z,
    /// exponent, swing_length, shape [default: the Statcast-average batter with the r161].
    #[arg(long, value_name = "FILE")]
    pub batter: Option<PathBuf>,
    /// Overrides the batter's exponent n of v ∝ I^(−n) (0 ≤ n ≤ 0.5; 0 = every bat at the same speed).
    #[arg(long, value_name = "N", value_parser = finite_f64, allow_negative_numbers = true)]
    pub exponent: Option<f64>,
    /// Writes a figure of exit speed along the barrel per bat at equal effort (SVG or PNG by extension).
    #[arg(long, value_name = "PATH")]
    pub figure: Option<PathBuf>,
    /// Pitch speed toward the bat, m/s.
    #[arg(long, value_name = "M/S", default_value_t = DEFAULT_BALL_SPEED, value_parser = finite_f64, allow_negative_numbers = true)]
    pub pitch_speed: f64,
    #[command(flatten)]
    pub ball: BallArgs,
    #[command(flatten)]
    pub numeric: NumericArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Runs `sweetspot compare`.
pub fn run(args: CompareArgs) -> Result<()> {
    let bats = parse_bats(&args.bats)?;
    let (mut batter, reference_name) = match &args.batter {
        Some(path) => load_batter_file(path)?,
        None => batter_from_spec(&BatterSpec::default(), None)?,
    };
    if let Some(n) = args.exponent {
        batter.exponent = n;
        batter.validate().context("--exponent")?;
    }
    let ball = args.ball.apply(Ball::game())?;
    let options = args.numeric.options()?;
    if !(args.pitch_speed > 0.0) {
        bail!("--pitch-speed = {} m/s is out of range: expected > 0", args.pitch_speed);
    }
    if let Some(path) = &args.figure {
        ImageFormat::from_path(path).context("--figure")?;
        let mut inputs: Vec<PathBuf> = args.bats.split(',').map(PathBuf::from).collect();
        inputs.extend(args.batter.clone());
        crate::files::refuse_clobber("--figure", path, &inputs, &[]).map_err(anyhow::Error::msg)?;
    }
    let doc = compare(&batter, &reference_name, &bats, &ball, args.pitch_speed, &options)?;
    if let Some(path) = &args.figure {
        write_figure(path, &batter, &bats, &ball, args.pitch_speed, &options)?;
    }
    if args.output.json {
        print_json(&doc)
    } else {
        let mut text = render(&doc);
        if let Some(path) = &args.figure {
            text.push_str(&format!("figure written to {}\n", path.display()));
        }
        emit(&text)
    }
}

/// Draws exit speed along the barrel of each of `bats` at `batter`'s equal effort into `path`.
pub fn write_figure(
    path: &Path,
    batter: &Batter,
    bats: &[Bat],
    ball: &Ball,
    pitch_speed: f64,
    options: &CollisionOptions,
) -> Result<()> {
    let curves = equal_effort_curves(batter, bats, ball, pitch_speed, options, FIGURE_POINTS)?;
    let title = format!(
        "Exit speed along the barrel at equal batter effort (pitch {} m/s, n = {})",
        num(pitch_speed, 3),
        num(batter.exponent, 4)
    );
    draw_line_chart(path, &equal_effort_chart(&title, &curves))
        .with_context(|| format!("--figure '{}'", path.display()))
}
