//! The node's ROS parameters: names, defaults, validation and which may change while the node runs.
//!
//! [`NodeSettings`] is the typed view; [`NodeSettings::declarations`] is what the node declares to ros2-client
//! (so `ros2 param list/get/set/describe` see them) and [`NodeSettings::apply`] is the one place a value is
//! checked, used for `-p`/`--params-file` overrides at start-up and for `ros2 param set` later.

use std::collections::BTreeMap;
use std::path::PathBuf;

use ros2_client::ParameterValue;

use crate::model::settings::ModelSettings;

/// Parameters that only take effect at start-up; setting them on a running node is refused.
pub const READ_ONLY: &[&str] = &[
    "queue_capacity",
    "workers",
    "record",
    "record_path",
    "record_max_file_size",
    "record_max_file_duration",
    "record_storage_preset",
    "record_compression",
    "diagnostics_period",
];

/// Every parameter with its meaning, for `describe` output and the README table: (name, unit, meaning).
pub const DESCRIPTIONS: &[(&str, &str, &str)] = &[
    ("default_bat", "", "bat_id used by swings with an empty bat_id before any BatParams arrived (a preset name)"),
    ("default_modes", "", "vibrational modes integrated when BatParams.max_modes is 0 (1..=200)"),
    ("time_step", "s", "RK4 time step of every collision (1e-8..=1e-4)"),
    ("reference_ball_speed", "m/s", "ball speed of the reference swing used for SweetSpot (> 0)"),
    ("reference_bat_cm_speed", "m/s", "bat centre-of-mass speed of the reference swing (>= 0)"),
    ("reference_bat_angular_speed", "rad/s", "bat angular speed of the reference swing"),
    (
        "max_bats",
        "",
        "bats kept with their solved modes (2..=100000); beyond it the least recently used is forgotten (never the \
         latest received); a swing naming a forgotten bat is REJECTED until its BatParams is sent again, a preset \
         is re-solved on demand",
    ),
    (
        "max_balls",
        "",
        "balls kept (2..=100000); beyond it the least recently used is forgotten (never the latest received); a \
         swing naming a forgotten ball is REJECTED until its BallParams is sent again",
    ),
    (
        "max_bat_slices",
        "",
        "largest slice count (bat length / slice_length) a BatParams may ask for (100..=4000); finer bats are \
         REJECTED before their modes are solved",
    ),
    (
        "queue_capacity",
        "",
        "swings in flight (queued, computing or awaiting in-order publication) before new ones are dropped",
    ),
    ("workers", "", "collision worker threads; 0 = one per CPU core"),
    ("record", "", "record every input and output to MCAP"),
    ("record_path", "", "rosbag2 directory to create; empty = bags/<node>_<UTC time>"),
    ("record_max_file_size", "bytes", "split the bag after this many bytes; 0 = never"),
    ("record_max_file_duration", "s", "split the bag after this much time; 0 = never"),
    (
        "record_storage_preset",
        "",
        "MCAP layout as rosbag2's --storage-preset-profile: none (rosbag2's default: uncompressed chunks), fastwrite (no chunks, no \
         indexes, uncompressed), zstd_fast (zstd -5), zstd_small (zstd 19, 4 MiB chunks); empty = zstd level 1 \
         chunks",
    ),
    (
        "record_compression",
        "",
        "chunk compression, overriding the preset's: zstd (level 1), zstd:LEVEL (-7..=-1 fast, 1..=22), lz4 or \
         none; empty = the preset's (zstd level 1 without one); with fastwrite only none or empty",
    ),
    ("diagnostics_period", "s", "period of /diagnostics (0.1..=60)"),
];

/// The node's parameters, typed. Defaults are what `sweetspot node` uses without `-p`.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeSettings {
    /// The settings of the model (default bat and modes, time step, registry limits), recorded with a bag.
    pub model: ModelSettings,
    /// Reference swing's ball speed toward the bat, m/s.
    pub reference_ball_speed: f64,
    /// Reference swing's bat centre-of-mass speed, m/s.
    pub reference_bat_cm_speed: f64,
    /// Reference swing's bat angular speed, rad/s.
    pub reference_bat_angular_speed: f64,
    /// Swings in flight before new ones are dropped.
    pub queue_capacity: usize,
    /// Worker threads; 0 = one per core.
    pub workers: usize,
    /// Record to MCAP.
    pub record: bool,
    /// Bag directory; empty = `bags/<node>_<UTC time>`.
    pub record_path: String,
    /// Split size, bytes; 0 = never.
    pub record_max_file_size: u64,
    /// Split duration, s; 0 = never.
    pub record_max_file_duration: f64,
    /// rosbag2 storage preset: `none`, `fastwrite`, `zstd_fast`, `zstd_small`, or empty for sweetspot's
    /// default (checked by [`crate::bag::StoragePreset`]).
    pub record_storage_preset: String,
    /// Chunk compression overriding the preset's: `zstd`, `zstd:LEVEL`, `lz4` or `none`, or empty for the
    /// preset's (checked by [`crate::bag::ChunkCompression`]).
    pub record_compression: String,
    /// Diagnostics period, s.
    pub diagnostics_period: f64,
}

impl Default for NodeSettings {
    fn default() -> Self {
        NodeSettings {
            model: ModelSettings::default(),
            // A hard-hit ball: 40 m/s pitch (≈ 90 mph), the bat's centre of mass at 20 m/s turning at 50 rad/s
            // (barrel ≈ 30 m/s at the sweet spot of a 33-in bat).
            reference_ball_speed: 40.0,
            reference_bat_cm_speed: 20.0,
            reference_bat_angular_speed: 50.0,
            // Covers a burst of 10,000 swings at a few hundred bytes each (≈ 5 MB worst case).
            queue_capacity: 16_384,
            workers: 0,
            record: true,
            record_path: String::new(),
            record_max_file_size: 0,
            record_max_file_duration: 0.0,
            record_storage_preset: String::new(),
            record_compression: String::new(),
            diagnostics_period: 1.0,
        }
    }
}

/// What changing a parameter on a running node requires of the engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SettingEffect {
    /// Nothing beyond storing it (read at the next use).
    None,
    /// Cached modes computed with the default mode count are stale.
    ModesChanged,
    /// Every SweetSpot must be recomputed (reference swing, time step).
    SweetSpotsChanged,
}

impl NodeSettings {
    /// The parameters as ros2-client declarations, in a stable order.
    pub fn declarations(&self) -> Vec<(&'static str, ParameterValue)> {
        use ParameterValue::*;
        vec![
            ("default_bat", String(self.model.default_bat.clone())),
            ("default_modes", Integer(self.model.default_modes as i64)),
            ("time_step", Double(self.model.time_step)),
            ("reference_ball_speed", Double(self.reference_ball_speed)),
            ("reference_bat_cm_speed", Double(self.reference_bat_cm_speed)),
            ("reference_bat_angular_speed", Double(self.reference_bat_angular_speed)),
            ("max_bats", Integer(self.model.max_bats as i64)),
            ("max_balls", Integer(self.model.max_balls as i64)),
            ("max_bat_slices", Integer(self.model.max_bat_slices as i64)),
            ("queue_capacity", Integer(self.queue_capacity as i64)),
            ("workers", Integer(self.workers as i64)),
            ("record", Boolean(self.record)),
            ("record_path", String(self.record_path.clone())),
            ("record_max_file_size", Integer(self.record_max_file_size as i64)),
            ("record_max_file_duration", Double(self.record_max_file_duration)),
            ("record_storage_preset", String(self.record_storage_preset.clone())),
            ("record_compression", String(self.record_compression.clone())),
            ("diagnostics_period", Double(self.diagnostics_period)),
        ]
    }

    /// Defaults overridden by `-p`/`--params-file` values; an integer given for a double parameter is
    /// accepted as that double (YAML writes `40` for 40.0). Unknown names and bad values are errors.
    pub fn with_overrides(overrides: &BTreeMap<String, ParameterValue>) -> Result<NodeSettings, String> {
        let mut settings = NodeSettings::default();
        for (name, value) in overrides {
            if name == "use_sim_time" {
                continue; // ros2-client's own parameter
            }
            let declared = settings
                .declarations()
                .into_iter()
                .find(|(n, _)| n == name)
                .map(|(_, v)| v)
                .ok_or_else(|| format!("unknown parameter '{name}' (known: {})", parameter_names().join(", ")))?;
            let value = match (&declared, value) {
                (ParameterValue::Double(_), ParameterValue::Integer(i)) => ParameterValue::Double(*i as f64),
                _ => value.clone(),
            };
            settings.apply(name, &value)?;
        }
        Ok(settings)
    }

    /// Checks and stores one value; the error names the parameter and its allowed range.
    pub fn apply(&mut self, name: &str, value: &ParameterValue) -> Result<SettingEffect, String> {
        use ParameterValue as V;
        let range = |ok: bool, allowed: &str| {
            if ok {
                Ok(())
            } else {
                Err(format!("{name} = {} is out of range: expected {allowed}", show(value)))
            }
        };
        let wrong_type = |expected: &str| Err(format!("{name} must be {expected}, got {}", show(value)));
        match (name, value) {
            ("default_bat", V::String(s)) => {
                range(!s.trim().is_empty(), "a non-empty bat_id or preset name")?;
                self.model.default_bat = s.clone();
                Ok(SettingEffect::None)
            }
            ("default_modes", V::Integer(n)) => {
                range((1..=200).contains(n), "1 ≤ default_modes ≤ 200")?;
                let changed = self.model.default_modes != *n as usize;
                self.model.default_modes = *n as usize;
                Ok(if changed { SettingEffect::ModesChanged } else { SettingEffect::None })
            }
            ("time_step", V::Double(x)) => {
                range(x.is_finite() && (1e-8..=1e-4).contains(x), "1e-8 ≤ time_step ≤ 1e-4 s")?;
                self.model.time_step = *x;
                Ok(SettingEffect::SweetSpotsChanged)
            }
            ("reference_ball_speed", V::Double(x)) => {
                range(x.is_finite() && *x > 0.0 && *x <= 100.0, "0 < reference_ball_speed ≤ 100 m/s")?;
                self.reference_ball_speed = *x;
                Ok(SettingEffect::SweetSpotsChanged)
            }
            ("reference_bat_cm_speed", V::Double(x)) => {
                range(x.is_finite() && (0.0..=100.0).contains(x), "0 ≤ reference_bat_cm_speed ≤ 100 m/s")?;
                self.reference_bat_cm_speed = *x;
                Ok(SettingEffect::SweetSpotsChanged)
            }
            ("reference_bat_angular_speed", V::Double(x)) => {
                range(x.is_finite() && x.abs() <= 500.0, "|reference_bat_angular_speed| ≤ 500 rad/s")?;
                self.reference_bat_angular_speed = *x;
                Ok(SettingEffect::SweetSpotsChanged)
            }
            ("max_bats", V::Integer(n)) => {
                range((2..=100_000).contains(n), "2 ≤ max_bats ≤ 100000")?;
                self.model.max_bats = *n as usize;
                Ok(SettingEffect::None)
            }
            ("max_balls", V::Integer(n)) => {
                range((2..=100_000).contains(n), "2 ≤ max_balls ≤ 100000")?;
                self.model.max_balls = *n as usize;
                Ok(SettingEffect::None)
            }
            ("max_bat_slices", V::Integer(n)) => {
                let physics_max = crate::physics::bat::SLICE_COUNT_RANGE.1 as i64;
                range((100..=physics_max).contains(n), &format!("100 ≤ max_bat_slices ≤ {physics_max}"))?;
                self.model.max_bat_slices = *n as usize;
                Ok(SettingEffect::None)
            }
            ("queue_capacity", V::Integer(n)) => {
                range((1..=1_000_000).contains(n), "1 ≤ queue_capacity ≤ 1000000")?;
                self.queue_capacity = *n as usize;
                Ok(SettingEffect::None)
            }
            ("workers", V::Integer(n)) => {
                range((0..=256).contains(n), "0 (one per core) ≤ workers ≤ 256")?;
                self.workers = *n as usize;
                Ok(SettingEffect::None)
            }
            ("record", V::Boolean(b)) => {
                self.record = *b;
                Ok(SettingEffect::None)
            }
            ("record_path", V::String(s)) => {
                self.record_path = s.clone();
                Ok(SettingEffect::None)
            }
            ("record_max_file_size", V::Integer(n)) => {
                range(*n == 0 || *n >= 4096, "0 (never split) or ≥ 4096 bytes")?;
                self.record_max_file_size = *n as u64;
                Ok(SettingEffect::None)
            }
            ("record_max_file_duration", V::Double(x)) => {
                range(x.is_finite() && *x >= 0.0, "0 (never split) or a positive number of seconds")?;
                self.record_max_file_duration = *x;
                Ok(SettingEffect::None)
            }
            ("record_storage_preset", V::String(s)) => {
                if !s.is_empty() {
                    if let Err(err) = s.parse::<crate::bag::StoragePreset>() {
                        return Err(format!("record_storage_preset = {s:?} is REJECTED: {err}"));
                    }
                }
                if let Err(err) = crate::bag::StorageOptions::from_parameters(s, &self.record_compression) {
                    return Err(format!(
                        "record_storage_preset = {s:?} is REJECTED with record_compression = {:?}: {err}",
                        self.record_compression
                    ));
                }
                self.record_storage_preset = s.clone();
                Ok(SettingEffect::None)
            }
            ("record_compression", V::String(s)) => {
                if !s.is_empty() {
                    if let Err(err) = s.parse::<crate::bag::ChunkCompression>() {
                        return Err(format!("record_compression = {s:?} is not a compression: {err}"));
                    }
                }
                if let Err(err) = crate::bag::StorageOptions::from_parameters(&self.record_storage_preset, s) {
                    return Err(format!(
                        "record_compression = {s:?} is REJECTED with record_storage_preset = {:?}: {err}",
                        self.record_storage_preset
                    ));
                }
                self.record_compression = s.clone();
                Ok(SettingEffect::None)
            }
            ("diagnostics_period", V::Double(x)) => {
                range(x.is_finite() && (0.1..=60.0).contains(x), "0.1 ≤ diagnostics_period ≤ 60 s")?;
                self.diagnostics_period = *x;
                Ok(SettingEffect::None)
            }
            ("default_bat" | "record_path" | "record_storage_preset" | "record_compression", _) => {
                wrong_type("a string")
            }
            (
                "default_modes"
                | "max_bats"
                | "max_balls"
                | "max_bat_slices"
                | "queue_capacity"
                | "workers"
                | "record_max_file_size",
                _,
            ) => wrong_type("an integer"),
            ("record", _) => wrong_type("a boolean"),
            (
                "time_step"
                | "reference_ball_speed"
                | "reference_bat_cm_speed"
                | "reference_bat_angular_speed"
                | "record_max_file_duration"
                | "diagnostics_period",
                _,
            ) => wrong_type("a double"),
            _ => Err(format!("unknown parameter '{name}' (known: {})", parameter_names().join(", "))),
        }
    }

    /// Worker threads to start: `workers`, or one per core when 0.
    pub fn worker_count(&self) -> usize {
        if self.workers > 0 {
            self.workers
        } else {
            std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)
        }
    }

    /// The bag's storage options: `record_storage_preset`, then `record_compression` over it (rosbag2's
    /// order: the preset first, the storage configuration overriding it). Both were checked together by
    /// [`Self::apply`], so this only fails for settings built by hand.
    pub fn storage_options(&self) -> Result<crate::bag::StorageOptions, crate::bag::BagError> {
        crate::bag::StorageOptions::from_parameters(&self.record_storage_preset, &self.record_compression)
    }

    /// The bag directory for `node_name` started at `started` (UTC).
    pub fn bag_dir(&self, node_name: &str, started: chrono::DateTime<chrono::Utc>) -> PathBuf {
        if self.record_path.is_empty() {
            crate::bag::default_bag_dir(std::path::Path::new("bags"), node_name, started.into())
        } else {
            PathBuf::from(&self.record_path)
        }
    }
}

/// Names of all the node's own parameters.
pub fn parameter_names() -> Vec<&'static str> {
    NodeSettings::default().declarations().into_iter().map(|(n, _)| n).collect()
}

fn show(value: &ParameterValue) -> String {
    match value {
        ParameterValue::NotSet => "<not set>".to_string(),
        ParameterValue::Boolean(b) => b.to_string(),
        ParameterValue::Integer(i) => i.to_string(),
        ParameterValue::Double(x) => x.to_string(),
        ParameterValue::String(s) => format!("'{s}'"),
        other => format!("{other:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn record_compression_takes_the_rosbag2_style_names_and_refuses_others() {
        let mut s = NodeSettings::default();
        assert_eq!(s.record_compression, "", "empty: the preset's compression");
        for ok in ["zstd", "zstd:9", "zstd:-3", "lz4", "none", ""] {
            assert!(s.apply("record_compression", &ParameterValue::String(ok.into())).is_ok(), "{ok}");
            assert_eq!(s.record_compression, ok);
        }
        s.apply("record_compression", &ParameterValue::String("none".into())).unwrap();
        for bad in ["gzip", "zstd:0", "zstd:23", " "] {
            let err = s.apply("record_compression", &ParameterValue::String(bad.into())).unwrap_err();
            assert!(err.contains("record_compression") && err.contains("lz4 or none"), "{bad}: {err}");
        }
        assert_eq!(s.record_compression, "none", "a refused value leaves the last good one");
        assert!(READ_ONLY.contains(&"record_compression"), "a bag keeps one compression");
    }

    #[test]
    fn record_storage_preset_takes_rosbag2_names_and_the_compression_overrides_it() {
        use crate::bag::{ChunkCompression, McapLayout, StorageOptions};
        let mut s = NodeSettings::default();
        assert_eq!(s.record_storage_preset, "");
        assert_eq!(s.storage_options().unwrap(), StorageOptions::default(), "no preset: sweetspot's zstd level 1");
        assert!(READ_ONLY.contains(&"record_storage_preset"), "a bag keeps one layout");
        for name in ["none", "fastwrite", "zstd_fast", "zstd_small"] {
            s.apply("record_storage_preset", &ParameterValue::String(name.into())).unwrap();
            assert_eq!(s.storage_options().unwrap(), StorageOptions::preset(name).unwrap(), "{name}");
        }
        // rosbag2's none: uncompressed chunks, unlike sweetspot's preset-less default.
        s.apply("record_storage_preset", &ParameterValue::String("none".into())).unwrap();
        let none = s.storage_options().unwrap();
        assert_eq!((none.compression, none.layout), (ChunkCompression::None, McapLayout::Chunked));
        // An explicit compression overrides the preset's, as rosbag2's storage config does.
        s.apply("record_compression", &ParameterValue::String("lz4".into())).unwrap();
        assert_eq!(s.storage_options().unwrap().compression, ChunkCompression::Lz4);
        assert_eq!(s.storage_options().unwrap().chunk_size, none.chunk_size, "the rest stays the preset's");

        for bad in ["fast_write", "zstd", "None", " "] {
            let err = s.apply("record_storage_preset", &ParameterValue::String(bad.into())).unwrap_err();
            assert!(err.contains("record_storage_preset") && err.contains("REJECTED"), "{bad}: {err}");
            assert!(err.contains("valid options are 'none', 'fastwrite', 'zstd_fast', 'zstd_small'"), "{bad}: {err}");
        }
        assert_eq!(s.record_storage_preset, "none", "a refused value leaves the last good one");
        let e = s.apply("record_storage_preset", &ParameterValue::Integer(1)).unwrap_err();
        assert!(e.contains("string"), "{e}");
    }

    #[test]
    fn fastwrite_refuses_a_compression_it_cannot_apply_whichever_comes_first() {
        // Overrides are applied in name order (record_compression first); the preset is then refused.
        let mut o = BTreeMap::new();
        o.insert("record_storage_preset".to_string(), ParameterValue::String("fastwrite".into()));
        o.insert("record_compression".to_string(), ParameterValue::String("zstd".into()));
        let err = NodeSettings::with_overrides(&o).unwrap_err();
        for part in ["record_storage_preset", "record_compression", "REJECTED", "fastwrite", "zstd"] {
            assert!(err.contains(part), "{part}: {err}");
        }
        // The other way round (ros2 param set order, or a settings value already holding the preset).
        let mut s = NodeSettings::default();
        s.apply("record_storage_preset", &ParameterValue::String("fastwrite".into())).unwrap();
        for compression in ["zstd", "zstd:3", "lz4"] {
            let err = s.apply("record_compression", &ParameterValue::String(compression.into())).unwrap_err();
            assert!(err.contains("REJECTED with record_storage_preset = \"fastwrite\""), "{err}");
            assert!(err.contains("needs chunks"), "{err}");
        }
        // `none` and empty are what fastwrite writes anyway.
        for compression in ["none", ""] {
            s.apply("record_compression", &ParameterValue::String(compression.into())).unwrap();
            let options = s.storage_options().unwrap();
            assert_eq!(options.layout, crate::bag::McapLayout::Unchunked);
            assert_eq!(options.compression, crate::bag::ChunkCompression::None);
        }
        o.insert("record_compression".to_string(), ParameterValue::String("none".into()));
        assert!(NodeSettings::with_overrides(&o).is_ok());
    }

    #[test]
    fn every_declared_parameter_is_described_and_accepts_its_default() {
        let defaults = NodeSettings::default();
        for (name, value) in defaults.declarations() {
            assert!(DESCRIPTIONS.iter().any(|(n, _, _)| *n == name), "{name} has no description");
            let mut s = defaults.clone();
            s.apply(name, &value).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(s, defaults);
        }
        assert_eq!(DESCRIPTIONS.len(), defaults.declarations().len());
        for name in READ_ONLY {
            assert!(parameter_names().contains(name));
        }
    }

    #[test]
    fn overrides_coerce_integers_to_doubles_and_report_effects() {
        let mut o = BTreeMap::new();
        o.insert("reference_ball_speed".to_string(), ParameterValue::Integer(35));
        o.insert("record".to_string(), ParameterValue::Boolean(false));
        o.insert("default_modes".to_string(), ParameterValue::Integer(12));
        let s = NodeSettings::with_overrides(&o).unwrap();
        assert_eq!(s.reference_ball_speed, 35.0);
        assert!(!s.record);
        assert_eq!(s.model.default_modes, 12);
        let mut t = s.clone();
        assert_eq!(t.apply("default_modes", &ParameterValue::Integer(12)).unwrap(), SettingEffect::None);
        assert_eq!(t.apply("default_modes", &ParameterValue::Integer(10)).unwrap(), SettingEffect::ModesChanged);
        assert_eq!(t.apply("time_step", &ParameterValue::Double(1e-6)).unwrap(), SettingEffect::SweetSpotsChanged);
    }

    #[test]
    fn bad_values_are_refused_naming_the_parameter_and_range() {
        let mut s = NodeSettings::default();
        let e = s.apply("time_step", &ParameterValue::Double(f64::NAN)).unwrap_err();
        assert!(e.contains("time_step") && e.contains("1e-8"), "{e}");
        let e = s.apply("default_modes", &ParameterValue::Integer(0)).unwrap_err();
        assert!(e.contains("default_modes") && e.contains("200"), "{e}");
        let e = s.apply("max_bats", &ParameterValue::Integer(1)).unwrap_err();
        assert!(e.contains("max_bats = 1") && e.contains("2 ≤ max_bats"), "{e}");
        let e = s.apply("max_bat_slices", &ParameterValue::Integer(5000)).unwrap_err();
        assert!(e.contains("max_bat_slices ≤ 4000"), "{e}");
        let e = s.apply("max_balls", &ParameterValue::Double(3.0)).unwrap_err();
        assert!(e.contains("integer"), "{e}");
        let e = s.apply("record", &ParameterValue::Integer(1)).unwrap_err();
        assert!(e.contains("boolean"), "{e}");
        let e = s.apply("frobs", &ParameterValue::Integer(1)).unwrap_err();
        assert!(e.contains("unknown parameter 'frobs'"), "{e}");
        assert_eq!(s, NodeSettings::default(), "a refused value changes nothing");
        let mut o = BTreeMap::new();
        o.insert("queue_capacity".to_string(), ParameterValue::Integer(0));
        assert!(NodeSettings::with_overrides(&o).is_err());
    }

    #[test]
    fn default_bag_dir_is_named_after_node_and_utc_time() {
        use chrono::TimeZone;
        let t = chrono::Utc.with_ymd_and_hms(2026, 11, 21, 5, 6, 7).unwrap();
        assert_eq!(
            NodeSettings::default().bag_dir("sweetspot", t),
            PathBuf::from("bags/sweetspot_2026_11_21-05_06_07")
        );
        let s = NodeSettings { record_path: "/tmp/run1".into(), ..Default::default() };
        assert_eq!(s.bag_dir("sweetspot", t), PathBuf::from("/tmp/run1"));
    }
}
