//! QoS profiles of sweetspot's topics, shared by the node, `sweetspot pub` / `echo` and the rig (the node's
//! recording stores them through `node::recording::recorded_qos`).
//!
//! A subscription matches a publication only if the offered QoS is at least as strong as the requested one
//! (reliable ≥ best effort, transient-local ≥ volatile); depth does not affect matching. The profiles here are
//! used on both sides, so every sweetspot pair matches, and an rclcpp/rclpy peer using the ROS defaults
//! (reliable, volatile) matches all of them; a late-joining reader gets the latched topics only if it asks for
//! transient-local itself (as `ros2 topic echo --qos-durability transient_local` does).

use std::time::Duration;

use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::QosProfile;

/// Params kept for late joiners on `bat/params` / `ball/params`: more than one, so a node started late still
/// receives every bat of a rig that publishes several from one process, not only the last.
pub const PARAMS_DEPTH: usize = 16;
/// Swings queued per reader on `swing`.
pub const SWING_DEPTH: usize = 1000;
/// Results kept per writer (and queued per reader) on `exit_velocity` / `modal_energies`.
pub const RESULTS_DEPTH: usize = 1000;
/// How long a results writer waits for a slow reliable reader to acknowledge before it reports the write
/// failed (counted by the node), rather than overwriting results that reader still lacks. A reader that has
/// acknowledged nothing for 2 s is not waited for (the RustDDS patch, fix 5 in `patches/README.md`).
pub const RESULTS_MAX_BLOCKING: Duration = Duration::from_millis(500);

fn reliable(depth: usize, durability: Durability) -> QosProfile {
    QosProfile::publisher_default()
        .reliability(Reliability::Reliable { when_full: WhenFull::DEFAULT })
        .durability(durability)
        .history(History::KeepLast { depth })
}

/// `bat/params`, `ball/params`: reliable, transient-local (latched), keep-last [`PARAMS_DEPTH`].
pub fn params_qos() -> QosProfile {
    reliable(PARAMS_DEPTH, Durability::TransientLocal)
}

/// `swing`: reliable, volatile, keep-last [`SWING_DEPTH`].
pub fn swing_qos() -> QosProfile {
    reliable(SWING_DEPTH, Durability::Volatile)
}

/// `exit_velocity`, `modal_energies`: reliable (writers wait up to [`RESULTS_MAX_BLOCKING`]), volatile,
/// keep-last [`RESULTS_DEPTH`]. The node's writers, `sweetspot pub` and the recorded QoS all use this one
/// profile: a reliable writer never overwrites results a responsive reader lacks, and the wide window and the
/// wait keep a briefly slow listener from costing results (beyond that: counted failures); a reader that
/// stopped acknowledging loses the old results instead of stalling everyone else.
pub fn results_qos() -> QosProfile {
    reliable(RESULTS_DEPTH, Durability::Volatile)
        .reliability(Reliability::Reliable { when_full: WhenFull::Wait(RESULTS_MAX_BLOCKING) })
}

/// `sweet_spot`: reliable, transient-local, keep-last [`PARAMS_DEPTH`] (one per bat, latched).
pub fn sweet_spot_qos() -> QosProfile {
    reliable(PARAMS_DEPTH, Durability::TransientLocal)
}

/// `/diagnostics`: reliable, volatile, keep-last 10 (the ROS 2 default profile diagnostic tools use).
pub fn diagnostics_qos() -> QosProfile {
    reliable(10, Durability::Volatile)
}

/// `/rosout`: reliable, transient-local, keep-last 1000, lifespan 10 s (rcl's `rosout` default).
pub fn rosout_qos() -> QosProfile {
    reliable(1000, Durability::TransientLocal).lifespan(Some(Duration::from_secs(10)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles() {
        assert!(matches!(
            results_qos().reliability,
            Reliability::Reliable { when_full: WhenFull::Wait(d) } if d == RESULTS_MAX_BLOCKING
        ));
        assert!(matches!(sweet_spot_qos().durability, Durability::TransientLocal));
        assert_eq!(rosout_qos().lifespan, Some(Duration::from_secs(10)));
    }
}
