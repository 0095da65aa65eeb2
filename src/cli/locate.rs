//! `sweetspot locate BAG`: where on the bat each ball was hit (see [`crate::locate`]).

use std::path::PathBuf;

use anyhow::{anyhow, Result};
use clap::Args;

use super::common::{finite_f64, print_json};
use crate::locate::figure::{batters_of, draw_figure, Grouping};
use crate::locate::{locate_bag, BatSpeedFit, LocateOptions, Outcome, Side};
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
favour. A swing faster than the sweet spot allows is reported with the excess. --figure draws the located
points on the bat's outline, one panel per batter (from the import's side table; per bat for a bag without
it), the favoured solution filled, the others hollow, the sweet spot and its ±2 cm band shaded.
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
    for (name, v) in [
        ("--exit-speed-sigma", args.exit_speed_sigma),
        ("--launch-angle-sigma", args.launch_angle_sigma),
        ("--spin-sigma", args.spin_sigma),
    ] {
        if v <= 0.0 {
            return Err(anyhow!("{name} = {v}: expected > 0"));
        }
    }
    let options = LocateOptions {
        exit_speed_sigma: args.exit_speed_sigma,
        launch_angle_sigma: args.launch_angle_sigma.to_radians(),
        spin_sigma: rpm_to_rad_per_s(args.spin_sigma),
        fit_bat_speed: args.fit_bat_speed,
    };
    if let Some(path) = &args.figure {
        ImageFormat::from_path(path)?;
        crate::files::refuse_clobber("--figure", path, &[], std::slice::from_ref(&args.bag))
            .map_err(anyhow::Error::msg)?;
    }
    let report = locate_bag(&args.bag, &options).map_err(|e| anyhow!("{}: {e}", args.bag.display()))?;
    if let Some(path) = &args.figure {
        let batters = batters_of(&args.bag)?;
        let summary = draw_figure(path, &report, batters.as_ref())?;
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
    }
    if args.json {
        return print_json(&report);
    }
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
        let text = match &s.outcome {
            Outcome::Located { solutions, favoured, squared_up } => {
                let list: Vec<String> = solutions
                    .iter()
                    .enumerate()
                    .map(|(i, x)| {
                        format!(
                            "{}{:.4} ± {:.4}, {:+.1} ± {:.1} mm, {} (sweet spot {:.3})",
                            if Some(i) == *favoured { "*" } else { "" },
                            x.impact_z,
                            x.impact_z_sigma,
                            x.undercut * 1e3,
                            x.undercut_sigma * 1e3,
                            match x.side {
                                Side::Handle => "handle side",
                                Side::End => "end side",
                            },
                            x.sweet_spot_z
                        )
                    })
                    .collect();
                format!("{}{}", list.join("  |  "), if *squared_up { "  squared up" } else { "" })
            }
            Outcome::TooFast { max_exit_speed, excess, sweet_spot_z } => format!(
                "FASTER than the sweet spot allows by {excess:.2} m/s (max {max_exit_speed:.2} m/s at z = {sweet_spot_z:.3} m)"
            ),
            Outcome::NotMeasured => "no exit speed measured".to_string(),
            Outcome::Failed { reason } => format!("not located: {reason}"),
        };
        crate::outln!(
            "{:>8} {:>8.2} {:>7.1} {:>7.0}  {text}",
            s.swing_id,
            v,
            theta.to_degrees(),
            omega * 60.0 / (2.0 * std::f64::consts::PI)
        )?;
        if let Some(fit) = &s.bat_speed_fit {
            crate::outln!("{:>34}  bat speed fit: {}", "", bat_speed_text(fit))?;
        }
    }
    crate::outln!(
        "{} located, {} faster than the sweet spot allows, of {} swings; squared up (±2 cm of the sweet spot): {:.0} %",
        report.located,
        report.too_fast,
        report.swings.len(),
        report.squared_up_share * 100.0
    )?;
    if let Some(n) = report.bat_speed_fitted {
        crate::outln!("bat speed fitted for {n} of {} swings", report.swings.len())?;
    }
    Ok(())
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
