//! What only the node converts (the model's conversions are in [`crate::model::convert`]): its parameters to
//! the reference swing of SweetSpot, its health to a `/diagnostics` array, its statistics as the model's
//! mode-cache counter.

use crate::model::engine::ModeCacheStats;
use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus, KeyValue};
use crate::msgs::std_msgs::msg::Header;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
use crate::physics::Impact;

use super::settings::NodeSettings;
use super::stats::{HealthReport, NodeStats};

/// The reference swing of the settings, for [`crate::model::engine::summarize_bat`] (impact point filled in
/// by the sweet-spot search).
pub fn reference_swing(settings: &NodeSettings) -> Impact {
    Impact {
        ball_speed: settings.reference_ball_speed,
        bat_cm_speed: settings.reference_bat_cm_speed,
        bat_angular_speed: settings.reference_bat_angular_speed,
        impact_z: 0.0,
    }
}

/// One `/diagnostics` array holding the node's status.
pub fn diagnostic_array(report: &HealthReport, node_fqn: &str, stamp: Time) -> DiagnosticArray {
    DiagnosticArray {
        header: Header { stamp, frame_id: String::new() },
        status: vec![DiagnosticStatus {
            level: report.level as u8,
            name: format!("sweetspot: {node_fqn}"),
            message: report.message.clone(),
            hardware_id: node_fqn.to_string(),
            values: report.values.iter().map(|(k, v)| KeyValue { key: k.clone(), value: v.clone() }).collect(),
        }],
    }
}

impl ModeCacheStats for NodeStats {
    fn count_mode_lookup(&self, hit: bool) {
        NodeStats::bump(if hit { &self.mode_cache_hits } else { &self.mode_cache_misses });
    }
}

/// The answer to a swing the node could not take because `capacity` swings were already in flight: status
/// DROPPED, the swing's id, stamp and ids echoed, nothing computed (NaN).
pub fn dropped_answer(swing: &Swing, capacity: usize) -> ExitVelocity {
    let reason = format!(
        "dropped: {capacity} swings already in flight (queue_capacity); nothing was computed for this swing: \
         send it again, send slower, or raise queue_capacity or workers"
    );
    let mut ev = crate::model::convert::exit_velocity(swing, &swing.bat_id, &swing.ball_id, &Err(reason.clone()));
    ev.status = ExitVelocity::STATUS_DROPPED;
    ev.message = reason;
    ev
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dropped_swing_is_answered_dropped_with_its_identity_and_no_numbers() {
        let swing = Swing {
            header: Header { stamp: Time { sec: 7, nanosec: 9 }, frame_id: "cage".into() },
            swing_id: 42,
            bat_id: "r161".into(),
            // Even a swing that would be rejected is answered DROPPED: it was never looked at.
            ball_speed: f64::NAN,
            ..Swing::default()
        };
        let ev = dropped_answer(&swing, 16);
        assert_eq!(ev.status, ExitVelocity::STATUS_DROPPED);
        assert_eq!(ev.status, 2, "the constant documented in ExitVelocity.msg");
        assert_eq!((ev.swing_id, ev.header.stamp.sec, ev.header.stamp.nanosec), (42, 7, 9));
        assert_eq!((ev.bat_id.as_str(), ev.header.frame_id.as_str()), ("r161", "cage"));
        assert!(ev.exit_speed.is_nan() && ev.effective_cor.is_nan(), "{ev:?}");
        assert!(ev.message.contains("16 swings already in flight (queue_capacity)"), "{}", ev.message);
    }
}
