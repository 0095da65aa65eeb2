//! `sweetspot locate`'s table as text: what a user reads of a [`LocateReport`] on a terminal.

use super::{BatSpeedFit, Direction, LocateReport, Outcome, Side};

/// The table `sweetspot locate` prints: a header, a line per swing (and one for its bat-speed fit), then the
/// counts.
pub fn table(report: &LocateReport) -> Vec<String> {
    let mut lines = Vec::with_capacity(report.swings.len() + 3);
    lines.push(format!(
        "{:>8} {:>8} {:>7} {:>7}  {:<58}",
        "swing", "v (m/s)", "θ (°)", "ω (rpm)", "impact_z ± σ (m from knob), undercut ± σ (mm), side of the sweet spot"
    ));
    for s in &report.swings {
        let [v, theta, omega] = s.measured;
        lines.push(format!(
            "{:>8} {:>8.2} {:>7.1} {:>7.0}  {}",
            s.swing_id,
            v,
            theta.to_degrees(),
            omega * 60.0 / (2.0 * std::f64::consts::PI),
            outcome_text(&s.outcome)
        ));
        if let Some(fit) = &s.bat_speed_fit {
            lines.push(format!("{:>34}  bat speed fit: {}", "", bat_speed_text(fit)));
        }
    }
    lines.push(format!(
        "{} located, {} faster than the sweet spot allows, {} not reproducible within tracker accuracy, of {} \
         swings; squared up (±2 cm of the sweet spot): {:.0} % of those located",
        report.located,
        report.too_fast,
        report.not_reproducible,
        report.swings.len(),
        report.squared_up_share * 100.0
    ));
    if let Some(n) = report.bat_speed_fitted {
        lines.push(format!("bat speed fitted for {n} of {} swings", report.swings.len()));
    }
    lines
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
