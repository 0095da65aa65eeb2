//! `sweetspot locate BAG`: where on the bat each ball was hit (see [`crate::locate`]).

use std::io::IsTerminal as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::{anyhow, Result};
use clap::Args;

use super::common::{finite_f64, print_json};
use crate::locate::figure::{batters_of, draw_figure, Grouping};
use crate::locate::{locate_bag_with_progress, LocateOptions, LocateReport};
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

/// The table ([`crate::locate::text::table`]) on stdout.
fn print_table(report: &LocateReport) -> Result<()> {
    for line in crate::locate::text::table(report) {
        crate::outln!("{line}")?;
    }
    Ok(())
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
