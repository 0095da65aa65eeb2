//! The message kinds `pub` and `echo` know: each one's type, default topic, QoS and constant names, and the
//! `--qos-*` overrides of a topic's QoS.

use anyhow::bail;

use crate::msgs::diagnostic_msgs::msg::DiagnosticStatus;
use crate::msgs::rcl_interfaces::msg::Log;
use crate::msgs::sweetspot_msgs::msg::ExitVelocity;
use crate::msgs::RosMessage;
use crate::ros::{self, topics};

/// Overrides of a topic's QoS, as `ros2 topic pub/echo` take them (`--qos-*`).
#[derive(Debug, Clone, Default)]
pub struct QosOverrides {
    /// Reliability: reliable, best_effort, or system_default (the topic's own).
    pub reliability: Option<String>,
    /// Durability: volatile, transient_local, or system_default (the topic's own).
    pub durability: Option<String>,
    /// History depth (keep last N).
    pub depth: Option<usize>,
}

impl QosOverrides {
    /// `qos` with these overrides.
    pub fn apply(&self, qos: ros2_client::QosProfile) -> anyhow::Result<ros2_client::QosProfile> {
        use ros2_client::qos::{Durability, History, Reliability, WhenFull};
        let mut qos = qos;
        match self.reliability.as_deref() {
            Some("best_effort") => qos = qos.reliability(Reliability::BestEffort),
            Some("reliable") if qos.reliability == Reliability::BestEffort => {
                qos = qos.reliability(Reliability::Reliable { when_full: WhenFull::DEFAULT })
            }
            _ => {}
        }
        match self.durability.as_deref() {
            Some("volatile") => qos = qos.durability(Durability::Volatile),
            Some("transient_local") => qos = qos.durability(Durability::TransientLocal),
            _ => {}
        }
        if let Some(depth) = self.depth {
            if depth == 0 {
                bail!("--qos-depth must be at least 1");
            }
            qos = qos.history(History::KeepLast { depth });
        }
        Ok(qos)
    }
}

/// `/clock`: absolute, as rclcpp's time source subscribes it.
const CLOCK_TOPIC: &str = "/clock";

/// The message types `pub` and `echo` know.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `sweetspot_msgs/msg/BatParams` on `bat/params`.
    BatParams,
    /// `sweetspot_msgs/msg/BallParams` on `ball/params`.
    BallParams,
    /// `sweetspot_msgs/msg/Swing` on `swing`.
    Swing,
    /// `sweetspot_msgs/msg/ExitVelocity` on `exit_velocity`.
    ExitVelocity,
    /// `sweetspot_msgs/msg/ModalEnergies` on `modal_energies`.
    ModalEnergies,
    /// `sweetspot_msgs/msg/SweetSpot` on `sweet_spot`.
    SweetSpot,
    /// `diagnostic_msgs/msg/DiagnosticArray` on `/diagnostics`.
    Diagnostics,
    /// `rcl_interfaces/msg/Log` on `/rosout`.
    Rosout,
    /// `rosgraph_msgs/msg/Clock` on `/clock` (what `bag play --clock` publishes).
    Clock,
}

pub const ALL_KINDS: [Kind; 9] = [
    Kind::BatParams,
    Kind::BallParams,
    Kind::Swing,
    Kind::ExitVelocity,
    Kind::ModalEnergies,
    Kind::SweetSpot,
    Kind::Diagnostics,
    Kind::Rosout,
    Kind::Clock,
];

/// Runs `$body` with `$T` bound to the message type of `$kind`.
macro_rules! with_type {
    ($kind:expr, $T:ident => $body:expr) => {
        match $kind {
            $crate::client::kind::Kind::BatParams => {
                type $T = $crate::msgs::sweetspot_msgs::msg::BatParams;
                $body
            }
            $crate::client::kind::Kind::BallParams => {
                type $T = $crate::msgs::sweetspot_msgs::msg::BallParams;
                $body
            }
            $crate::client::kind::Kind::Swing => {
                type $T = $crate::msgs::sweetspot_msgs::msg::Swing;
                $body
            }
            $crate::client::kind::Kind::ExitVelocity => {
                type $T = $crate::msgs::sweetspot_msgs::msg::ExitVelocity;
                $body
            }
            $crate::client::kind::Kind::ModalEnergies => {
                type $T = $crate::msgs::sweetspot_msgs::msg::ModalEnergies;
                $body
            }
            $crate::client::kind::Kind::SweetSpot => {
                type $T = $crate::msgs::sweetspot_msgs::msg::SweetSpot;
                $body
            }
            $crate::client::kind::Kind::Diagnostics => {
                type $T = $crate::msgs::diagnostic_msgs::msg::DiagnosticArray;
                $body
            }
            $crate::client::kind::Kind::Rosout => {
                type $T = $crate::msgs::rcl_interfaces::msg::Log;
                $body
            }
            $crate::client::kind::Kind::Clock => {
                type $T = $crate::msgs::rosgraph_msgs::msg::Clock;
                $body
            }
        }
    };
}
pub(crate) use with_type;

impl Kind {
    /// The ROS type name, e.g. `sweetspot_msgs/msg/Swing`.
    pub fn type_name(self) -> &'static str {
        with_type!(self, T => T::TYPE_NAME)
    }

    /// The topic the node uses for it (relative names move with the namespace).
    pub fn default_topic(self) -> &'static str {
        match self {
            Kind::BatParams => topics::BAT_PARAMS,
            Kind::BallParams => topics::BALL_PARAMS,
            Kind::Swing => topics::SWING,
            Kind::ExitVelocity => topics::EXIT_VELOCITY,
            Kind::ModalEnergies => topics::MODAL_ENERGIES,
            Kind::SweetSpot => topics::SWEET_SPOT,
            Kind::Diagnostics => topics::DIAGNOSTICS,
            Kind::Rosout => topics::ROSOUT,
            Kind::Clock => CLOCK_TOPIC,
        }
    }

    /// The QoS the node offers/requests on it.
    pub fn qos(self) -> ros2_client::QosProfile {
        match self {
            Kind::BatParams | Kind::BallParams => ros::params_qos(),
            Kind::Swing => ros::swing_qos(),
            Kind::ExitVelocity | Kind::ModalEnergies => ros::results_qos(),
            Kind::SweetSpot => ros::sweet_spot_qos(),
            Kind::Diagnostics => ros::diagnostics_qos(),
            Kind::Rosout => ros::rosout_qos(),
            Kind::Clock => crate::play::clock_qos(),
        }
    }

    /// The names of the constants a field's value stands for, field by field (the readable form of `echo`
    /// shows `status: 0 (OK)`).
    pub fn constant_names(self) -> &'static [(&'static str, &'static [(u64, &'static str)])] {
        match self {
            Kind::ExitVelocity => &[(
                "status",
                &[
                    (ExitVelocity::STATUS_OK as u64, "OK"),
                    (ExitVelocity::STATUS_REJECTED as u64, "REJECTED"),
                    (ExitVelocity::STATUS_DROPPED as u64, "DROPPED"),
                ],
            )],
            Kind::Diagnostics => &[(
                "level",
                &[
                    (DiagnosticStatus::OK as u64, "OK"),
                    (DiagnosticStatus::WARN as u64, "WARN"),
                    (DiagnosticStatus::ERROR as u64, "ERROR"),
                    (DiagnosticStatus::STALE as u64, "STALE"),
                ],
            )],
            Kind::Rosout => &[(
                "level",
                &[
                    (Log::DEBUG as u64, "DEBUG"),
                    (Log::INFO as u64, "INFO"),
                    (Log::WARN as u64, "WARN"),
                    (Log::ERROR as u64, "ERROR"),
                    (Log::FATAL as u64, "FATAL"),
                ],
            )],
            _ => &[],
        }
    }

    /// Whether the topic is latched (transient-local).
    pub fn latched(self) -> bool {
        matches!(self, Kind::BatParams | Kind::BallParams | Kind::SweetSpot | Kind::Rosout)
    }

    /// A kind from a word: `bat`, `ball`, `swing`, a topic's default name, or a type name in any spelling.
    pub fn from_word(word: &str) -> Option<Kind> {
        let w = word.trim();
        let short = match w {
            "bat" | "bat_params" => return Some(Kind::BatParams),
            "ball" | "ball_params" => return Some(Kind::BallParams),
            "diagnostics" => return Some(Kind::Diagnostics),
            "rosout" | "log" => return Some(Kind::Rosout),
            "clock" => return Some(Kind::Clock),
            _ => w,
        };
        ALL_KINDS.iter().copied().find(|k| {
            let t = k.type_name();
            let bare = t.rsplit('/').next().unwrap_or(t);
            let no_msg = t.replace("/msg/", "/");
            short == t || short == bare || short == no_msg || short == k.default_topic()
        })
    }

    /// The kind of a fully-qualified topic from its trailing name, e.g. `/rig3/bat/params` → BatParams.
    pub fn from_topic(fq_topic: &str) -> Option<Kind> {
        ALL_KINDS.iter().copied().find(|k| {
            let d = k.default_topic().trim_start_matches('/');
            fq_topic == format!("/{d}") || fq_topic.ends_with(&format!("/{d}"))
        })
    }
}
