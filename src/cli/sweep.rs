//! `sweetspot sweep`: exit speed (flexible and rigid) over impact points, the sweet-spot set, and a plot; or
//! (`--over undercut`) exit speed, launch angle and spin over the undercut at one impact point.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};

use super::common::{emit, finite_f64, print_json, BallArgs, BatArgs, NumericArgs, ObliqueArgs, OutputArgs, SwingArgs};
use super::simulate::{describe_inputs, describe_oblique};
use crate::answer::sweep::{check_flags, sweep, SweepDocument, SweepOver as Over};
use crate::physics::Ball;
use crate::report::figures::exit_speed_chart;
use crate::report::plot::{draw_line_chart, draw_panels, ImageFormat};
use crate::report::sweep::{undercut_charts, undercut_title, SweepJson, SweepRange, UndercutSweepJson};
use crate::report::table::{num, Table};

/// What a sweep varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SweepOver {
    /// The impact point along the bat (head-on).
    Z,
    /// The undercut at one impact point (oblique).
    Undercut,
}

/// Arguments of `sweetspot sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// The swept variable: the impact point z, or the undercut D at --impact-z.
    #[arg(long, value_enum, default_value_t = SweepOver::Z)]
    pub over: SweepOver,
    #[command(flatten)]
    pub bat: BatArgs,
    #[command(flatten)]
    pub ball: BallArgs,
    #[command(flatten)]
    pub swing: SwingArgs,
    #[command(flatten)]
    pub oblique: ObliqueArgs,
    /// Impact point of an undercut sweep, m from the knob [default: 0.15 m from the barrel end].
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_negative_numbers = true)]
    pub impact_z: Option<f64>,
    /// First impact point, m from the knob [default: 0.35 m before the barrel end]; with --over undercut the
    /// first undercut, m [default: −0.75 (ball + barrel radius)].
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_negative_numbers = true)]
    pub from: Option<f64>,
    /// Last impact point, m from the knob [default: 0.01 m before the barrel end]; with --over undercut the
    /// last undercut, m [default: +0.75 (ball + barrel radius)].
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_negative_numbers = true)]
    pub to: Option<f64>,
    /// Step between impact points (or undercuts), m [default 0.005; undercut: 37 points].
    #[arg(long, value_name = "M", value_parser = finite_f64, conflicts_with = "points")]
    pub step: Option<f64>,
    /// Number of evenly spaced impact points from --from to --to (instead of --step), 2..=100000.
    #[arg(long, value_name = "N")]
    pub points: Option<usize>,
    /// Also draw flexible and rigid exit speed against impact point into this file (.svg or .png); with
    /// --over undercut, exit speed, launch angle and spin against undercut (three panels).
    #[arg(long, value_name = "FILE.svg|FILE.png")]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    pub numeric: NumericArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

impl From<SweepOver> for Over {
    fn from(over: SweepOver) -> Over {
        match over {
            SweepOver::Z => Over::ImpactPoint,
            SweepOver::Undercut => Over::Undercut,
        }
    }
}

/// Runs `sweetspot sweep`.
pub fn run(args: SweepArgs) -> Result<()> {
    if let Some(path) = &args.plot {
        ImageFormat::from_path(path).context("--plot")?;
    }
    let flags = args.oblique.flags();
    check_flags(args.over.into(), &flags, args.impact_z)?;
    let bat = args.bat.load()?;
    if let Some(path) = &args.plot {
        // After the bat is read: its profile CSV, read through the bat file, is an input too.
        let inputs = [PathBuf::from(&args.bat.bat)];
        crate::files::refuse_clobber("--plot", path, &inputs, &[]).map_err(anyhow::Error::msg)?;
    }
    let ball = args.ball.apply(Ball::game())?;
    let options = args.numeric.options()?;
    let swing = args.swing.impact(f64::NAN);
    let range = SweepRange { from: args.from, to: args.to, step: args.step, points: args.points };
    match sweep(&bat, &ball, &swing, args.over.into(), &flags, args.impact_z, range, &options)? {
        SweepDocument::Undercut(mut doc) => {
            if let Some(path) = &args.plot {
                draw_panels(path, &undercut_charts(&doc), 3, Some(&undercut_title(&doc)))?;
                doc.plot = Some(path.clone());
            }
            if args.output.json {
                print_json(&doc)
            } else {
                emit(&render_undercut(&doc))
            }
        }
        SweepDocument::ImpactPoint(mut doc) => {
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

/// The human-readable report of an undercut sweep.
pub fn render_undercut(doc: &UndercutSweepJson) -> String {
    let mut out = describe_inputs(&doc.bat, &doc.ball, &doc.swing, &doc.options);
    let oblique = describe_oblique(&doc.oblique);
    // The undercut is swept: leave its fixed value out of the header.
    out.push_str(&oblique.replacen(&format!("undercut {} m, ", num(doc.oblique.undercut, 4)), "", 1));
    out.push_str(&format!(
        "impact z = {} m from the knob, barrel radius {} m\n\n",
        num(doc.impact_z, 4),
        num(doc.barrel_radius, 4)
    ));
    let mut t = Table::new([
        "undercut (mm)",
        "exit speed (m/s)",
        "launch angle (deg)",
        "spray (deg)",
        "spin (rpm)",
        "sidespin (rpm)",
        "total spin (rpm)",
        "normal (m/s)",
        "tangential (m/s)",
        "sliding",
    ]);
    for p in &doc.points {
        t.row([
            num(p.undercut * 1e3, 4),
            num(p.exit_speed, 5),
            num(p.launch_angle_deg, 4),
            num(p.flight.spray_angle_deg, 4),
            num(p.spin_rpm, 5),
            num(p.flight.sidespin_rpm, 5),
            num(p.flight.total_spin_rpm, 5),
            num(p.normal_exit_speed, 5),
            p.tangential_exit_speed.map(|v| num(v, 4)).unwrap_or_default(),
            if p.sliding { "yes" } else { "no" }.to_string(),
        ]);
    }
    out.push_str(&t.render());
    if let Some(best) = doc.points.iter().max_by(|a, b| a.spin_rpm.total_cmp(&b.spin_rpm)) {
        out.push_str(&format!(
            "most backspin: {} rpm at undercut {} mm (exit speed {} m/s, launch {}°)\n",
            num(best.spin_rpm, 5),
            num(best.undercut * 1e3, 4),
            num(best.exit_speed, 4),
            num(best.launch_angle_deg, 3)
        ));
    }
    if let Some(path) = &doc.plot {
        out.push_str(&format!("plot written to {}\n", path.display()));
    }
    out
}
