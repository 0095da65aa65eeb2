//! The session's answers joined with the rig's bats: one row per bat, printed as the demo's table.

use std::collections::BTreeMap;

use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, SweetSpot};
use crate::physics::batter::{reaction_time_gained, swing_weight};
use crate::physics::units::{rad_per_s_to_rpm, INCH, MPH};
use crate::report::table::{num, Table};
use crate::rig::dds::Answer;
use crate::rig::{SessionGenerator, RIG_BALL_ID};

/// Everything the node answered, keyed the way the report needs it.
#[derive(Debug, Default)]
pub struct Answers {
    /// ExitVelocity by swing_id.
    pub exits: BTreeMap<u64, ExitVelocity>,
    /// ModalEnergies by swing_id.
    pub modals: BTreeMap<u64, ModalEnergies>,
    /// Latest SweetSpot per bat (the one computed with the rig's ball once it arrived).
    pub sweet_spots: BTreeMap<String, SweetSpot>,
    /// Undecodable samples.
    pub undecodable: u64,
}

impl Answers {
    pub(super) fn absorb(&mut self, (answers, bad): (Vec<Answer>, u64)) {
        self.undecodable += bad;
        for a in answers {
            match a {
                Answer::Exit(e) => {
                    self.exits.insert(e.swing_id, e);
                }
                Answer::Modal(m) => {
                    self.modals.insert(m.swing_id, m);
                }
                // Prefer the SweetSpot computed with the rig's ball; one with another ball stands in until then.
                Answer::SweetSpot(s) => {
                    let keep_old = self
                        .sweet_spots
                        .get(&s.bat_id)
                        .is_some_and(|old| old.ball_id == RIG_BALL_ID && s.ball_id != RIG_BALL_ID);
                    if !keep_old {
                        self.sweet_spots.insert(s.bat_id.clone(), s);
                    }
                }
            }
        }
    }
}

/// One row of the demo's table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BatRow {
    /// bat_id.
    pub bat_id: String,
    /// Swings answered OK.
    pub swings: usize,
    /// Swings rejected.
    pub rejected: usize,
    /// Mean predicted exit speed, m/s.
    pub mean_exit_speed: f64,
    /// Best predicted exit speed, m/s.
    pub best_exit_speed: f64,
    /// Sweet spot (maximum exit speed for the node's reference swing), m from the knob.
    pub sweet_spot_z: f64,
    /// Bat length, m.
    pub length: f64,
    /// Swing weight (moment of inertia about the 6-in pivot), kg·m².
    pub swing_weight: f64,
    /// The rig batter's bat speed at its usual impact point for this bat at the reference effort, m/s
    /// (NaN without a batter).
    pub predicted_bat_speed: f64,
    /// How much later than with the session's first bat the batter can start the swing, s (NaN without a
    /// batter).
    pub reaction_time_gained: f64,
    /// BBCOR.
    pub bbcor: f64,
    /// Mean share of the collision energy left in bat vibration.
    pub vibration_share: f64,
    /// Mean of measured − predicted, m/s.
    pub mean_error: f64,
    /// RMS of measured − predicted, m/s.
    pub rms_error: f64,
    /// Mean predicted launch angle, rad.
    pub mean_launch_angle: f64,
    /// Mean launch angle the rig's tracker measured, rad (NaN when it measured none).
    pub mean_measured_launch_angle: f64,
    /// Mean predicted spin, rad/s, backspin positive.
    pub mean_spin: f64,
    /// Mean spin the rig's tracker measured, rad/s (NaN when it measured none).
    pub mean_measured_spin: f64,
}

/// Mean of the finite values (NaN when there are none).
fn finite_mean(values: impl Iterator<Item = f64>) -> f64 {
    let (sum, n) = values.filter(|v| v.is_finite()).fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 {
        f64::NAN
    } else {
        sum / n as f64
    }
}

/// The per-bat summary of a session: answers joined with the rig's bats.
pub fn summarize(rig: &SessionGenerator, answers: &Answers) -> Vec<BatRow> {
    let first_swing = rig.bats().first().and_then(|b| b.swing);
    rig.bats()
        .iter()
        .map(|b| {
            let exits: Vec<&ExitVelocity> = answers.exits.values().filter(|e| e.bat_id == b.bat_id).collect();
            let ok: Vec<&&ExitVelocity> = exits.iter().filter(|e| e.status == ExitVelocity::STATUS_OK).collect();
            let n = ok.len().max(1) as f64;
            let speeds = ok.iter().map(|e| e.exit_speed);
            let errors: Vec<f64> =
                ok.iter().map(|e| e.measured_exit_speed - e.exit_speed).filter(|r| r.is_finite()).collect();
            let ne = errors.len().max(1) as f64;
            let shares: Vec<f64> = answers
                .modals
                .values()
                .filter(|m| m.bat_id == b.bat_id)
                .map(|m| m.fraction.iter().sum::<f64>())
                .filter(|v| v.is_finite())
                .collect();
            let spot = answers.sweet_spots.get(&b.bat_id);
            BatRow {
                bat_id: b.bat_id.clone(),
                swings: ok.len(),
                rejected: exits.len() - ok.len(),
                mean_exit_speed: speeds.clone().sum::<f64>() / n,
                best_exit_speed: speeds.fold(f64::NAN, f64::max),
                sweet_spot_z: spot.map(|s| s.max_exit_speed_z).unwrap_or(f64::NAN),
                length: b.modes.length(),
                swing_weight: swing_weight(&b.modes.mass_properties()),
                predicted_bat_speed: b.swing.map(|s| s.bat_speed).unwrap_or(f64::NAN),
                reaction_time_gained: match (first_swing, b.swing) {
                    (Some(first), Some(this)) => reaction_time_gained(&first, &this),
                    _ => f64::NAN,
                },
                bbcor: spot.map(|s| s.bbcor).unwrap_or(f64::NAN),
                vibration_share: shares.iter().sum::<f64>() / shares.len().max(1) as f64,
                mean_error: errors.iter().sum::<f64>() / ne,
                rms_error: (errors.iter().map(|r| r * r).sum::<f64>() / ne).sqrt(),
                mean_launch_angle: finite_mean(ok.iter().map(|e| e.launch_angle)),
                // The answers carry measured − model, so measured = model + residual (NaN when not measured).
                mean_measured_launch_angle: finite_mean(ok.iter().map(|e| e.launch_angle + e.launch_angle_residual)),
                mean_spin: finite_mean(ok.iter().map(|e| e.spin)),
                mean_measured_spin: finite_mean(ok.iter().map(|e| e.spin + e.spin_residual)),
            }
        })
        .collect()
}

/// The table of [`summarize`] as text.
pub fn table(rows: &[BatRow]) -> String {
    let mut t = Table::new([
        "bat",
        "swings",
        "swing weight",
        "bat speed",
        "time gained",
        "mean exit",
        "best exit",
        "sweet spot",
        "BBCOR",
        "vibration",
        "measured − model",
        "launch angle",
        "spin",
    ]);
    t.row([
        "",
        "",
        "kg·m² (6-in pivot)",
        "m/s (mph), equal effort",
        "ms vs first bat",
        "m/s (mph)",
        "m/s (mph)",
        "m from knob (in from end)",
        "",
        "energy share",
        "mean ± RMS m/s",
        "deg, model / measured",
        "rpm, model / measured",
    ]);
    for r in rows {
        t.row([
            if r.rejected > 0 { format!("{} ({} rejected)", r.bat_id, r.rejected) } else { r.bat_id.clone() },
            r.swings.to_string(),
            format!("{:.4}", r.swing_weight),
            format!("{:.1} ({:.1})", r.predicted_bat_speed, r.predicted_bat_speed / MPH),
            format!("{:+.2}", 1e3 * r.reaction_time_gained),
            format!("{:.1} ({:.1})", r.mean_exit_speed, r.mean_exit_speed / MPH),
            format!("{:.1} ({:.1})", r.best_exit_speed, r.best_exit_speed / MPH),
            format!("{:.3} ({:.1})", r.sweet_spot_z, (r.length - r.sweet_spot_z) / INCH),
            num(r.bbcor, 3),
            format!("{:.1} %", 100.0 * r.vibration_share),
            format!("{:+.2} ± {:.2}", r.mean_error, r.rms_error),
            format!("{:.1} / {:.1}", r.mean_launch_angle.to_degrees(), r.mean_measured_launch_angle.to_degrees()),
            format!("{:.0} / {:.0}", rad_per_s_to_rpm(r.mean_spin), rad_per_s_to_rpm(r.mean_measured_spin)),
        ]);
    }
    t.render()
}
