//! `sweetspot sweep`: exit speed (flexible and rigid) over impact points, the sweet-spot set, and a plot.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;

use super::common::{emit, finite_f64, print_json, BallArgs, BatArgs, NumericArgs, OutputArgs, SwingArgs};
use super::simulate::describe_inputs;
use crate::physics::Ball;
use crate::report::figures::exit_speed_chart;
use crate::report::plot::{draw_line_chart, ImageFormat};
use crate::report::sweep::{run_sweep, SweepJson, SweepRange};
use crate::report::table::{num, Table};

/// Arguments of `sweetspot sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub bat: BatArgs,
    #[command(flatten)]
    pub ball: BallArgs,
    #[command(flatten)]
    pub swing: SwingArgs,
    /// First impact point, m from the knob [default: 0.35 m before the barrel end].
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_negative_numbers = true)]
    pub from: Option<f64>,
    /// Last impact point, m from the knob [default: 0.01 m before the barrel end].
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_negative_numbers = true)]
    pub to: Option<f64>,
    /// Step between impact points, m [default 0.005].
    #[arg(long, value_name = "M", value_parser = finite_f64, conflicts_with = "points")]
    pub step: Option<f64>,
    /// Number of evenly spaced impact points from --from to --to (instead of --step), 2..=100000.
    #[arg(long, value_name = "N")]
    pub points: Option<usize>,
    /// Also draw flexible and rigid exit speed against impact point into this file (.svg or .png).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub numeric: NumericArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Runs `sweetspot sweep`.
pub fn run(args: SweepArgs) -> Result<()> {
    if let Some(path) = &args.plot {
        ImageFormat::from_path(path).context("--plot")?;
    }
    let bat = args.bat.load()?;
    let ball = args.ball.apply(Ball::default())?;
    let options = args.numeric.options()?;
    let swing = args.swing.impact(f64::NAN);
    let range = SweepRange { from: args.from, to: args.to, step: args.step, points: args.points };
    let mut doc = run_sweep(&bat, &ball, &swing, range, &options)?;
    if let Some(path) = &args.plot {
        draw_line_chart(path, &exit_speed_chart(&doc))?;
        doc.plot = Some(path.clone());
    }
    if args.output.json {
        print_json(&doc)
    } else {
        emit(&render(&doc))
    }
}

/// The human-readable report.
pub fn render(doc: &SweepJson) -> String {
    let mut out = describe_inputs(&doc.bat, &doc.ball, &doc.swing, &doc.options);
    out.push('\n');
    let mut t =
        Table::new(["z (m)", "exit speed (m/s)", "rigid (m/s)", "e_eff", "e_A", "vibration (J)", "contact (ms)"]);
    for p in &doc.points {
        t.row([
            num(p.impact_z, 4),
            num(p.exit_speed, 5),
            num(p.rigid_exit_speed, 5),
            num(p.effective_cor, 4),
            num(p.collision_efficiency, 4),
            num(p.energy.vibration, 4),
            num(p.contact_time * 1e3, 4),
        ]);
    }
    out.push_str(&t.render());
    out.push('\n');
    out.push_str(&doc.sweet_spots.table().render());
    let list = |v: &[f64]| v.iter().map(|z| num(*z, 4)).collect::<Vec<_>>().join(", ");
    out.push_str(&format!(
        "nodes of mode 1 (m): {}\nnodes of mode 2 (m): {}\n",
        list(&doc.nodes.mode1),
        list(&doc.nodes.mode2)
    ));
    if let Some(path) = &doc.plot {
        out.push_str(&format!("plot written to {}\n", path.display()));
    }
    out
}
