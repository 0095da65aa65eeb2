//! What only the node converts (the model's conversions are in [`crate::model::convert`]): its parameters to
//! the reference swing of SweetSpot, its health to a `/diagnostics` array, its statistics as the model's
//! mode-cache counter.

use crate::model::engine::ModeCacheStats;
use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus, KeyValue};
use crate::msgs::std_msgs::msg::Header;
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
