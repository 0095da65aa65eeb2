//! `sweetspot figures DIR`: the seed paper's figures (Figures 5 and 6 also at equal batter effort), the bats at
//! equal effort, the alloy wall-thickness figure and the mode shapes, drawn by [`crate::report::figures`].

use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::common::{emit, BallArgs, NumericArgs, SwingArgs};
use crate::physics::Ball;
use crate::report::figures::{write_figures, FigureSettings};
use crate::report::plot::ImageFormat;

/// Output format of `sweetspot figures`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FigureFormat {
    /// Scalable vector graphics.
    Svg,
    /// Portable network graphics.
    Png,
}

impl From<FigureFormat> for ImageFormat {
    fn from(f: FigureFormat) -> ImageFormat {
        match f {
            FigureFormat::Svg => ImageFormat::Svg,
            FigureFormat::Png => ImageFormat::Png,
        }
    }
}

/// Arguments of `sweetspot figures`.
#[derive(Debug, Args)]
pub struct FiguresArgs {
    /// Directory the figures and their index (README.md) are written to (created if missing).
    pub dir: PathBuf,
    /// Image format.
    #[arg(long, value_enum, default_value_t = FigureFormat::Svg)]
    pub format: FigureFormat,
    /// Impact points per curve, 10..=2000.
    #[arg(long, value_name = "N", default_value_t = 150)]
    pub points: usize,
    /// Swing of Figures 2 and 5 (Figure 6 uses the seed's 8 m/s ball and 4 m/s bat).
    #[command(flatten)]
    pub swing: SwingArgs,
    #[command(flatten)]
    pub ball: BallArgs,
    #[command(flatten)]
    pub numeric: NumericArgs,
}

/// Runs `sweetspot figures`.
pub fn run(args: FiguresArgs) -> Result<()> {
    if !(10..=2000).contains(&args.points) {
        anyhow::bail!("--points = {} is out of range: expected 10 ≤ points ≤ 2000", args.points);
    }
    let settings = FigureSettings {
        format: args.format.into(),
        points: args.points,
        swing: args.swing.impact(f64::NAN),
        // The seed paper's figures keep the paper's ball, Nathan's constant-COR `baseball`, unless --ball says.
        ball: args.ball.apply(Ball::default())?,
        options: args.numeric.options()?,
    };
    let entries = write_figures(&args.dir, &settings)?;
    let mut out = String::new();
    for entry in &entries {
        out.push_str(&format!("{}\n", args.dir.join(&entry.file).display()));
    }
    out.push_str(&format!("{}\n", args.dir.join("README.md").display()));
    emit(&out)
}
