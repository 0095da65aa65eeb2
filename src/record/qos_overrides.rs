//! `--qos-profile-overrides-path`: rosbag2's YAML file of per-topic subscription QoS, e.g.
//!
//! ```yaml
//! /lab/swing:
//!   reliability: best_effort
//!   durability: volatile
//!   history: keep_last
//!   depth: 100
//! ```
//!
//! `history`, `depth`, `reliability` and `durability` are applied; the other keys rosbag2 knows (`deadline`,
//! `lifespan`, `liveliness`, `liveliness_lease_duration`, `avoid_ros_namespace_conventions`) are accepted and
//! reported as not applied; anything else is an error naming the key.

use std::collections::BTreeMap;
use std::path::Path;

use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::QosProfile;
use yaml_rust2::Yaml;

/// Keys rosbag2 accepts that do not change what is recorded here.
const NOT_APPLIED: [&str; 5] =
    ["deadline", "lifespan", "liveliness", "liveliness_lease_duration", "avoid_ros_namespace_conventions"];

/// The overrides of one topic (`None`: keep the adapted value).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct QosOverride {
    /// RELIABLE (true) or BEST_EFFORT (false).
    pub reliable: Option<bool>,
    /// TRANSIENT_LOCAL (true) or VOLATILE (false).
    pub transient_local: Option<bool>,
    /// KEEP_ALL (true) or KEEP_LAST (false).
    pub keep_all: Option<bool>,
    /// KEEP_LAST depth.
    pub depth: Option<usize>,
    /// Keys given that are not applied (see the module doc).
    pub ignored: Vec<String>,
}

/// Per-topic overrides by fully-qualified topic name.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct QosOverrides {
    /// The overrides of each topic named in the file.
    pub topics: BTreeMap<String, QosOverride>,
}

/// A file that is not rosbag2's QoS override layout.
#[derive(Debug, thiserror::Error)]
#[error("--qos-profile-overrides-path {path}: {reason}")]
pub struct QosOverridesError {
    /// The file.
    pub path: String,
    /// What is wrong, naming the topic and key.
    pub reason: String,
}

impl QosOverrides {
    /// Reads and checks a rosbag2 QoS override file.
    pub fn load(path: &Path) -> Result<QosOverrides, QosOverridesError> {
        let fail = |reason: String| QosOverridesError { path: path.display().to_string(), reason };
        let text = crate::files::read_text(path, "QoS override file").map_err(|e| fail(e.to_string()))?;
        QosOverrides::parse(&text).map_err(fail)
    }

    /// Parses the YAML text of a rosbag2 QoS override file.
    pub fn parse(text: &str) -> Result<QosOverrides, String> {
        let docs =
            crate::yaml::load(text)
                .map_err(|e| if e.is_syntax() { format!("not YAML: {e}") } else { e.to_string() })?;
        let mut out = QosOverrides::default();
        let Some(doc) = docs.first() else { return Ok(out) };
        let Yaml::Hash(topics) = doc else {
            return Err("expected a mapping of topic names to QoS profiles".to_string());
        };
        for (topic, profile) in topics {
            let Some(topic) = topic.as_str() else {
                return Err(format!("topic name {topic:?} is not a string"));
            };
            if !topic.starts_with('/') {
                return Err(format!("{topic}: topic names must be fully qualified (start with '/')"));
            }
            let Yaml::Hash(keys) = profile else {
                return Err(format!("{topic}: expected a mapping of QoS policies"));
            };
            let mut one = QosOverride::default();
            for (key, value) in keys {
                let key = key.as_str().unwrap_or_default();
                let word = || value.as_str().unwrap_or_default();
                let bad = |expected: &str| format!("{topic}: {key}: {value:?} is not one of {expected}");
                match key {
                    "reliability" => {
                        one.reliable = match word() {
                            "reliable" => Some(true),
                            "best_effort" => Some(false),
                            "system_default" => None,
                            _ => return Err(bad("reliable, best_effort, system_default")),
                        }
                    }
                    "durability" => {
                        one.transient_local = match word() {
                            "transient_local" => Some(true),
                            "volatile" => Some(false),
                            "system_default" => None,
                            _ => return Err(bad("transient_local, volatile, system_default")),
                        }
                    }
                    "history" => {
                        one.keep_all = match word() {
                            "keep_all" => Some(true),
                            "keep_last" => Some(false),
                            "system_default" => None,
                            _ => return Err(bad("keep_last, keep_all, system_default")),
                        }
                    }
                    "depth" => match value.as_i64() {
                        Some(d) if d >= 1 => one.depth = usize::try_from(d).ok(),
                        _ => return Err(format!("{topic}: depth: {value:?} is not an integer ≥ 1")),
                    },
                    k if NOT_APPLIED.contains(&k) => one.ignored.push(k.to_string()),
                    k => {
                        return Err(format!(
                            "{topic}: unknown QoS policy {k:?} (known: history, depth, reliability, durability, {})",
                            NOT_APPLIED.join(", ")
                        ))
                    }
                }
            }
            out.topics.insert(topic.to_string(), one);
        }
        Ok(out)
    }

    /// `qos` with the overrides of `topic`, if any.
    pub fn apply(&self, topic: &str, qos: QosProfile) -> QosProfile {
        let Some(one) = self.topics.get(topic) else { return qos };
        let mut qos = qos;
        if let Some(reliable) = one.reliable {
            qos = qos.reliability(if reliable {
                Reliability::Reliable { when_full: WhenFull::DEFAULT }
            } else {
                Reliability::BestEffort
            });
        }
        if let Some(transient_local) = one.transient_local {
            qos = qos.durability(if transient_local { Durability::TransientLocal } else { Durability::Volatile });
        }
        match (one.keep_all, one.depth) {
            // RustDDS caps a KeepAll reader without resource limits at 64 samples: a deep KeepLast keeps more.
            (Some(true), _) => qos = qos.history(History::KeepLast { depth: 100_000 }),
            (_, Some(depth)) => qos = qos.history(History::KeepLast { depth }),
            _ => {}
        }
        qos
    }

    /// Every `(topic, key)` given in the file that is not applied.
    pub fn ignored(&self) -> Vec<(String, String)> {
        self.topics.iter().flat_map(|(t, o)| o.ignored.iter().map(move |k| (t.clone(), k.clone()))).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_rosbag2_layout() {
        // The example of rosbag2's README (ros2/rosbag2, "Overriding QoS Policies").
        let text =
            "/talker:\n  reliability: best_effort\n  durability: volatile\n  history: keep_last\n  depth: 10\n  \
                    deadline:\n    sec: 2\n    nsec: 0\n";
        let o = QosOverrides::parse(text).unwrap();
        let t = &o.topics["/talker"];
        assert_eq!(
            (t.reliable, t.transient_local, t.keep_all, t.depth),
            (Some(false), Some(false), Some(false), Some(10))
        );
        assert_eq!(o.ignored(), vec![("/talker".to_string(), "deadline".to_string())]);
        let qos = o.apply("/talker", QosProfile::subscription_default());
        assert_eq!(qos.reliability, Reliability::BestEffort);
        assert_eq!(qos.history, History::KeepLast { depth: 10 });
        assert_eq!(o.apply("/other", QosProfile::subscription_default()), QosProfile::subscription_default());
    }

    #[test]
    fn names_what_is_wrong() {
        let e = QosOverrides::parse("/t:\n  reliability: sometimes\n").unwrap_err();
        assert!(e.contains("/t: reliability") && e.contains("best_effort"), "{e}");
        let e = QosOverrides::parse("/t:\n  relability: reliable\n").unwrap_err();
        assert!(e.contains("unknown QoS policy \"relability\""), "{e}");
        assert!(QosOverrides::parse("t:\n  depth: 1\n").unwrap_err().contains("fully qualified"));
        assert!(QosOverrides::parse("/t:\n  depth: 0\n").unwrap_err().contains("depth"));
    }
}
