//! `sweetspot locate BAG`: where on the bat each ball was hit (see [`crate::locate`]).

use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::{anyhow, Result};
use clap::Args;

use super::common::{finite_f64, print_json};
use crate::locate::figure::{batters_of, draw_figure, Grouping};
use crate::locate::{locate_bag_with_progress, BatSpeedFit, Direction, LocateOptions, LocateReport, Outcome, Side};
use crate::physics::oblique::rpm_to_rad_per_s;
use crate::report::plot::ImageFormat;

/// Arguments of `sweetspot locate`.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  sweetspot import trackman game.csv -o bags/game && sweetspot locate bags/game
  sweetspot locate bags/game --json > located.json
  sweetspot locate bags/game --figure located.svg
  sweetspot locate bags/game --fit-bat-speed

Every impact point (either side of the sweet spot) that reproduces the measured exit speed (and launch angle
and spin, where measured) is listed with its standard uncertainty; `*` marks the one the other measurements
favour. A swing faster than the sweet spot allows is reported with the excess; one whose closest fit misses
the measurements by more than tracker accuracy (χ² over 9 per degree of freedom) or leaves the impact point
uncertain by more than half the barrel is NOT REPRODUCIBLE, with the reason, and counted apart. Off a
terminal a progress line comes every 5 s. --figure draws the located
points on the bat's outline, one panel per batter (from the import's side table; per bat for a bag without
it), the favoured solution filled, the others hollow, the sweet spot and its ±2 cm band shaded.
A swing with a bat tilt or swing direction runs the 3-D collision; it and any swing with a measured spray
angle or spin axis also shows the model's spray angle and spin axis (Δ = measured − model).
--fit-bat-speed also fits the bat speed of swings whose bat speed the import assumed and whose spin is
measured (a factor on the assumed speed ± its uncertainty), or says per swing why it was not fitted.")]
pub struct LocateArgs {
    /// A bag of swings with measured exit speeds (from `sweetspot import`, or recorded from a rig).
    pub bag: PathBuf,
    /// Exit-speed accuracy of the tracker, m/s.
    #[arg(long, value_name = "M/S", default_value_t = 0.45, value_parser = finite_f64)]
    pub exit_speed_sigma: f64,
    /// Launch-angle accuracy of the tracker, degrees.
    #[arg(long, value_name = "DEG", default_value_t = 1.0, value_parser = finite_f64)]
    pub launch_angle_sigma: f64,
    /// Spin accuracy of the tracker, rpm.
    #[arg(long, value_name = "RPM", default_value_t = 100.0, value_parser = finite_f64)]
    pub spin_sigma: f64,
    /// Also fit the bat speed of swings whose bat speed the import assumed (TrackMan, Rapsodo, HitTrax) and
    /// whose exit speed, launch angle and spin are all measured: three measurements, three unknowns.
    #[arg(long)]
    pub fit_bat_speed: bool,
    /// Print one JSON document with a `swings` list instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also draw the located impact points on the bat's outline, one panel per batter (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub figure: Option<PathBuf>,
}

/// Runs `sweetspot locate`.
pub fn run(args: LocateArgs) -> Result<()> {
    let options = locate_options(&args)?;
    if let Some(path) = &args.figure {
        ImageFormat::from_path(path)?;
        crate::files::refuse_clobber("--figure", path, &[], std::slice::from_ref(&args.bag))
            .map_err(anyhow::Error::msg)?;
    }
    let report = locate_with_progress(&args.bag, &options)?;
    if let Some(path) = &args.figure {
        write_figure(path, &args.bag, &report)?;
    }
    if args.json {
        return print_json(&report);
    }
    print_table(&report)
}

/// The tracker's accuracies (each > 0) in SI units, and whether to fit bat speeds.
fn locate_options(args: &LocateArgs) -> Result<LocateOptions> {
    for (name, v) in [
        ("--exit-speed-sigma", args.exit_speed_sigma),
        ("--launch-angle-sigma", args.launch_angle_sigma),
        ("--spin-sigma", args.spin_sigma),
    ] {
        if v <= 0.0 {
            return Err(anyhow!("{name} = {v}: expected > 0"));
        }
    }
    Ok(LocateOptions {
        exit_speed_sigma: args.exit_speed_sigma,
        launch_angle_sigma: args.launch_angle_sigma.to_radians(),
        spin_sigma: rpm_to_rad_per_s(args.spin_sigma),
        fit_bat_speed: args.fit_bat_speed,
    })
}

/// Draws `--figure` and says on stderr what its panels are.
fn write_figure(path: &Path, bag: &Path, report: &LocateReport) -> Result<()> {
    let batters = batters_of(bag)?;
    let summary = draw_figure(path, report, batters.as_ref())?;
    let left_out = if summary.groups_left_out > 0 {
        format!(" ({} more with fewer located swings left out)", summary.groups_left_out)
    } else {
        String::new()
    };
    let per = match summary.grouping {
        Grouping::Batter => "batter",
        Grouping::Bat => "bat (the bag names no batters)",
    };
    eprintln!("wrote {}: {} panel(s), one per {per}{left_out}", path.display(), summary.panels.len());
    Ok(())
}

/// The table: a line per swing (and its bat-speed fit), then the counts.
fn print_table(report: &LocateReport) -> Result<()> {
    crate::outln!(
        "{:>8} {:>8} {:>7} {:>7}  {:<58}",
        "swing",
        "v (m/s)",
        "θ (°)",
        "ω (rpm)",
        "impact_z ± σ (m from knob), undercut ± σ (mm), side of the sweet spot"
    )?;
    for s in &report.swings {
        let [v, theta, omega] = s.measured;
        crate::outln!(
            "{:>8} {:>8.2} {:>7.1} {:>7.0}  {}",
            s.swing_id,
            v,
            theta.to_degrees(),
            omega * 60.0 / (2.0 * std::f64::consts::PI),
            outcome_text(&s.outcome)
        )?;
        if let Some(fit) = &s.bat_speed_fit {
            crate::outln!("{:>34}  bat speed fit: {}", "", bat_speed_text(fit))?;
        }
    }
    crate::outln!(
        "{} located, {} faster than the sweet spot allows, {} not reproducible within tracker accuracy, of {} \
         swings; squared up (±2 cm of the sweet spot): {:.0} % of those located",
        report.located,
        report.too_fast,
        report.not_reproducible,
        report.swings.len(),
        report.squared_up_share * 100.0
    )?;
    if let Some(n) = report.bat_speed_fitted {
        crate::outln!("bat speed fitted for {n} of {} swings", report.swings.len())?;
    }
    Ok(())
}

/// A swing's outcome as its column of the table: every solution (`*` on the favoured one), or why none.
fn outcome_text(outcome: &Outcome) -> String {
    match outcome {
        Outcome::Located { solutions, favoured, squared_up } => {
            let list: Vec<String> = solutions
                .iter()
                .enumerate()
                .map(|(i, x)| {
                    format!(
                        "{}{:.4} ± {:.4}, {:+.1} ± {:.1} mm, {} (sweet spot {:.3}){}",
                        if Some(i) == *favoured { "*" } else { "" },
                        x.impact_z,
                        x.impact_z_sigma,
                        x.undercut * 1e3,
                        x.undercut_sigma * 1e3,
                        match x.side {
                            Side::Handle => "handle side",
                            Side::End => "end side",
                        },
                        x.sweet_spot_z,
                        x.direction.as_ref().map_or(String::new(), direction_text)
                    )
                })
                .collect();
            format!("{}{}", list.join("  |  "), if *squared_up { "  squared up" } else { "" })
        }
        Outcome::TooFast { max_exit_speed, excess, sweet_spot_z } => format!(
            "FASTER than the sweet spot allows by {excess:.2} m/s (max {max_exit_speed:.2} m/s at z = {sweet_spot_z:.3} m)"
        ),
        Outcome::NotReproducible { reason, .. } => format!("NOT REPRODUCIBLE within tracker accuracy: {reason}"),
        Outcome::NotMeasured => "no exit speed measured".to_string(),
        Outcome::Failed { reason } => format!("not located: {reason}"),
    }
}

/// A solution's spray angle and spin axis, with measured − model where measured.
fn direction_text(d: &Direction) -> String {
    let residual = |r: f64| if r.is_finite() { format!(" (Δ {:+.1}°)", r.to_degrees()) } else { String::new() };
    format!(
        ", spray {:+.1}°{}, spin axis {:.0}°{}",
        d.spray_angle.to_degrees(),
        residual(d.spray_angle_residual),
        d.spin_axis.to_degrees(),
        residual(d.spin_axis_residual)
    )
}

/// One swing's bat-speed fit as a line of the table.
fn bat_speed_text(fit: &BatSpeedFit) -> String {
    match fit {
        BatSpeedFit::Fitted { solutions, not_separable } => {
            let list: Vec<String> = solutions
                .iter()
                .map(|x| {
                    format!(
                        "{:.4} ± {:.4}, {:+.1} ± {:.1} mm, bat speed × {:.3} ± {:.3} (V = {:.2} m/s, ω = {:.1} rad/s), {}",
                        x.impact_z,
                        x.impact_z_sigma,
                        x.undercut * 1e3,
                        x.undercut_sigma * 1e3,
                        x.scale,
                        x.scale_sigma,
                        x.bat_cm_speed,
                        x.bat_angular_speed,
                        match x.side {
                            Side::Handle => "handle side",
                            Side::End => "end side",
                        }
                    )
                })
                .collect();
            let more =
                if *not_separable > 0 { format!("  ({not_separable} more not separable)") } else { String::new() };
            format!("{}{more}", list.join("  |  "))
        }
        BatSpeedFit::NotSeparable { reason } => format!("not separable: {reason}"),
        BatSpeedFit::NotFitted { reason } => format!("not fitted: {reason}"),
        BatSpeedFit::Failed { reason } => format!("failed: {reason}"),
    }
}

/// Seconds between progress lines when stderr is not a terminal (a log or a pipe): a season of 10⁵–10⁶
/// swings takes minutes, and a line this often shows it is alive without filling the log.
const PROGRESS_LINE_EVERY: Duration = Duration::from_secs(5);

/// Locates the bag with progress on stderr: a bar on a terminal, a line every [`PROGRESS_LINE_EVERY`]
/// elsewhere (none for a bag done sooner, so scripts and tests of small bags get clean output).
fn locate_with_progress(bag: &Path, options: &LocateOptions) -> Result<LocateReport> {
    let on_terminal = std::io::stderr().is_terminal();
    let bar = crate::bag_tools::progress(0, "locating");
    let lines = Mutex::new(ProgressLines::new(Instant::now(), PROGRESS_LINE_EVERY));
    let progress = |done: usize, total: usize| {
        if on_terminal {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        } else if let Ok(mut lines) = lines.try_lock() {
            // Another worker holds it: the next swing done asks again.
            if let Some(line) = lines.line(done, total, Instant::now()) {
                eprintln!("{line}");
            }
        }
    };
    let report = locate_bag_with_progress(bag, options, &progress).map_err(|e| anyhow!("{}: {e}", bag.display()));
    bar.finish_and_clear();
    let lines = lines.into_inner().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let (Ok(report), true) = (&report, lines.printed) {
        eprintln!("locate: {} swings in {:.0} s", report.swings.len(), lines.started.elapsed().as_secs_f64());
    }
    report
}

/// When a progress line is due off a terminal, and what it says.
#[derive(Debug)]
struct ProgressLines {
    started: Instant,
    next: Instant,
    every: Duration,
    /// Whether any line was printed (then the run's end is said too).
    printed: bool,
}

impl ProgressLines {
    fn new(started: Instant, every: Duration) -> ProgressLines {
        ProgressLines { started, next: started + every, every, printed: false }
    }

    /// The line for `done` of `total` swings at `now`, if one is due (one per `every`, none before the first
    /// `every` has passed).
    fn line(&mut self, done: usize, total: usize, now: Instant) -> Option<String> {
        if now < self.next {
            return None;
        }
        self.next = now + self.every;
        self.printed = true;
        let elapsed = now.duration_since(self.started).as_secs_f64();
        let left = if done > 0 { elapsed * (total - done.min(total)) as f64 / done as f64 } else { f64::NAN };
        Some(format!(
            "locate: {done} of {total} swings ({:.0} %), {elapsed:.0} s, about {left:.0} s left",
            100.0 * done as f64 / total.max(1) as f64
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_progress_line_comes_once_per_interval_and_none_before_the_first() {
        let start = Instant::now();
        let every = Duration::from_secs(5);
        let mut lines = ProgressLines::new(start, every);
        let at = |s: f64| start + Duration::from_secs_f64(s);
        assert_eq!(lines.line(100, 1000, at(4.999)), None, "nothing in the first interval");
        assert!(!lines.printed);
        let first = lines.line(100, 1000, at(5.0)).expect("due at 5 s");
        // 100 of 1000 in 5 s: 10 %, 45 s left at that pace.
        assert_eq!(first, "locate: 100 of 1000 swings (10 %), 5 s, about 45 s left");
        assert!(lines.printed);
        assert_eq!(lines.line(150, 1000, at(9.9)), None, "one line per interval");
        assert!(lines.line(200, 1000, at(10.0)).is_some());
        assert_eq!(lines.line(201, 1000, at(10.1)), None);
    }
}
