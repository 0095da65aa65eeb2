//! The node's ROS parameters: names, defaults, validation and which may change while the node runs.
//!
//! [`PARAMETERS`] is the one table of them (name, unit, meaning, default, read-only, numeric range, other
//! constraints, how a value is checked and stored); [`NodeSettings`] is the typed view. Each parameter is
//! declared to ros2-client with its value and [`Parameter::descriptor`] (so `ros2 param list/get/set/describe`
//! see them, `describe` with the range and read-only flag) and [`NodeSettings::apply`] is the one place a
//! value is checked — against that same range first —, used for `-p`/`--params-file` overrides at start-up
//! and for `ros2 param set` later.

use std::collections::BTreeMap;
use std::path::PathBuf;

use ros2_client::parameters::{NumericRange, ParameterDescriptor};
use ros2_client::ParameterValue;

use crate::model::settings::ModelSettings;
use crate::physics::{Ball, Bat};

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
    /// Also record `~/simulate_swing` calls (as rosbag2 records services: `<service>/_service_event`).
    pub record_services: bool,
    /// Request/reply mapping of the node's services: `enhanced` (rmw_fastrtps, Jazzy's default) or `cyclone`
    /// (clients on rmw_cyclonedds_cpp).
    pub service_mapping: String,
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
    /// Foxglove WebSocket server, `[ADDR:]PORT` (address 127.0.0.1 unless given); empty = off.
    pub foxglove_port: String,
    /// Most Foxglove connections served at once; more are closed as they arrive.
    pub foxglove_max_clients: usize,
    /// Publish (and record) each answered swing's scene on `swing_scene` over DDS.
    pub swing_scene: bool,
    /// Most scenes per second served to Foxglove clients, Hz (0 = every answered swing).
    pub swing_scene_live_hz: f64,
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

/// One of the node's parameters.
pub struct Parameter {
    /// The ROS parameter name.
    pub name: &'static str,
    /// Its unit (empty for counts, names and switches).
    pub unit: &'static str,
    /// What it means, for `describe` output and docs/node.md's table.
    pub description: &'static str,
    /// Only takes effect at start-up: setting it on a running node is refused.
    pub read_only: bool,
    /// What a value must satisfy beyond its type and range, in words (empty if nothing); the descriptor's
    /// `additional_constraints`.
    pub constraints: &'static str,
    rule: Rule,
    get: fn(&NodeSettings) -> ParameterValue,
}

/// A parameter's type, default, and how a value of that type is checked and stored. A numeric `range` (both
/// ends allowed) is checked before `set` runs and is what `ros2 param describe` shows; `set` checks what a
/// range cannot say, named in the parameter's `constraints`.
enum Rule {
    Text { default: &'static str, set: fn(&mut NodeSettings, &str) -> Checked },
    Integer { default: i64, range: Option<(i64, i64)>, set: fn(&mut NodeSettings, i64) -> Checked },
    Double { default: f64, range: Option<(f64, f64)>, set: fn(&mut NodeSettings, f64) -> Checked },
    Boolean { default: bool, set: fn(&mut NodeSettings, bool) -> Checked },
}

/// What a setter says about a value of the right type.
type Checked = Result<SettingEffect, Refusal>;

/// Why a value of the right type is refused.
enum Refusal {
    /// Outside the allowed values (described here); the error names the parameter and the value.
    OutOfRange(String),
    /// The whole error text.
    Refused(String),
}

/// `Ok` if `ok`, else out of range with `allowed` as the expectation.
fn within(ok: bool, allowed: &str) -> Result<(), Refusal> {
    if ok {
        Ok(())
    } else {
        Err(Refusal::OutOfRange(allowed.to_string()))
    }
}

const STORED: Checked = Ok(SettingEffect::None);

// Constraints a range cannot say: the descriptor's text and the refusal's expectation.
const REFERENCE_BALL_SPEED_POSITIVE: &str = "reference_ball_speed > 0 m/s";
const SPLIT_SIZE: &str = "0 (never split) or ≥ 4096 bytes";
const SPLIT_DURATION: &str = "0 (never split) or a positive number of seconds";

/// Every parameter of the node, in declaration order.
pub static PARAMETERS: &[Parameter] = &[
    Parameter {
        name: "default_bat",
        unit: "",
        description: "bat_id used by swings with an empty bat_id before any BatParams arrived (a preset name)",
        read_only: false,
        constraints: "",
        rule: Rule::Text {
            default: "r161",
            set: |s, v| {
                if !Bat::preset_names().contains(&v) {
                    return Err(Refusal::Refused(format!(
                        "default_bat = '{}' is not a bat preset (presets: {})",
                        crate::model::limits::quote(v),
                        Bat::preset_names().join(", ")
                    )));
                }
                s.model.default_bat = v.to_string();
                STORED
            },
        },
        get: |s| ParameterValue::String(s.model.default_bat.clone()),
    },
    Parameter {
        name: "default_ball",
        unit: "",
        description: "ball_id used by swings with an empty ball_id before any BallParams arrived (a ball preset \
                      name; mlb2024 is the game ball fitted to the 2024 MLB season)",
        read_only: false,
        constraints: "",
        rule: Rule::Text {
            default: crate::model::engine::DEFAULT_BALL_ID,
            set: |s, v| {
                if !Ball::preset_names().contains(&v) {
                    return Err(Refusal::Refused(format!(
                        "default_ball = '{}' is not a ball preset (presets: {})",
                        crate::model::limits::quote(v),
                        Ball::preset_names().join(", ")
                    )));
                }
                s.model.default_ball = v.to_string();
                STORED
            },
        },
        get: |s| ParameterValue::String(s.model.default_ball.clone()),
    },
    Parameter {
        name: "default_modes",
        unit: "",
        description: "vibrational modes integrated when BatParams.max_modes is 0",
        read_only: false,
        constraints: "",
        rule: Rule::Integer {
            default: 18,
            range: Some((1, 200)),
            set: |s, n| {
                let changed = s.model.default_modes != n as usize;
                s.model.default_modes = n as usize;
                Ok(if changed { SettingEffect::ModesChanged } else { SettingEffect::None })
            },
        },
        get: |s| ParameterValue::Integer(s.model.default_modes as i64),
    },
    Parameter {
        name: "time_step",
        unit: "s",
        description: "RK4 time step of every collision",
        read_only: false,
        constraints: "",
        rule: Rule::Double {
            default: 5e-6,
            range: Some((1e-8, 1e-4)),
            set: |s, x| {
                s.model.time_step = x;
                Ok(SettingEffect::SweetSpotsChanged)
            },
        },
        get: |s| ParameterValue::Double(s.model.time_step),
    },
    // The reference swing is a hard-hit ball: 40 m/s pitch (≈ 90 mph), the bat's centre of mass at 20 m/s
    // turning at 50 rad/s (barrel ≈ 30 m/s at the sweet spot of a 33-in bat).
    Parameter {
        name: "reference_ball_speed",
        unit: "m/s",
        description: "ball speed of the reference swing used for SweetSpot",
        read_only: false,
        constraints: REFERENCE_BALL_SPEED_POSITIVE,
        rule: Rule::Double {
            default: 40.0,
            range: Some((0.0, 100.0)),
            set: |s, x| {
                within(x > 0.0, REFERENCE_BALL_SPEED_POSITIVE)?;
                s.reference_ball_speed = x;
                Ok(SettingEffect::SweetSpotsChanged)
            },
        },
        get: |s| ParameterValue::Double(s.reference_ball_speed),
    },
    Parameter {
        name: "reference_bat_cm_speed",
        unit: "m/s",
        description: "bat centre-of-mass speed of the reference swing",
        read_only: false,
        constraints: "",
        rule: Rule::Double {
            default: 20.0,
            range: Some((0.0, 100.0)),
            set: |s, x| {
                s.reference_bat_cm_speed = x;
                Ok(SettingEffect::SweetSpotsChanged)
            },
        },
        get: |s| ParameterValue::Double(s.reference_bat_cm_speed),
    },
    Parameter {
        name: "reference_bat_angular_speed",
        unit: "rad/s",
        description: "bat angular speed of the reference swing",
        read_only: false,
        constraints: "",
        rule: Rule::Double {
            default: 50.0,
            range: Some((-500.0, 500.0)),
            set: |s, x| {
                s.reference_bat_angular_speed = x;
                Ok(SettingEffect::SweetSpotsChanged)
            },
        },
        get: |s| ParameterValue::Double(s.reference_bat_angular_speed),
    },
    // A lab uses a handful of bats; 64 leaves room for a whole team's and bounds the worst case (each entry at
    // most max_bat_slices slices × 200 modes of shapes, ~4 MB) to a few hundred MB.
    Parameter {
        name: "max_bats",
        unit: "",
        description: "bats kept with their solved modes; beyond it the least recently used is forgotten \
                      (never the latest received); a swing naming a forgotten bat is REJECTED until its BatParams \
                      is sent again, a preset is re-solved on demand",
        read_only: false,
        constraints: "",
        rule: Rule::Integer {
            default: 64,
            range: Some((2, 100_000)),
            set: |s, n| {
                s.model.max_bats = n as usize;
                STORED
            },
        },
        get: |s| ParameterValue::Integer(s.model.max_bats as i64),
    },
    // A ball is 40 bytes; the cap only stops a publisher inventing ids without end.
    Parameter {
        name: "max_balls",
        unit: "",
        description: "balls kept; beyond it the least recently used is forgotten (never the latest \
                      received); a swing naming a forgotten ball is REJECTED until its BallParams is sent again",
        read_only: false,
        constraints: "",
        rule: Rule::Integer {
            default: 1024,
            range: Some((2, 100_000)),
            set: |s, n| {
                s.model.max_balls = n as usize;
                STORED
            },
        },
        get: |s| ParameterValue::Integer(s.model.max_balls as i64),
    },
    Parameter {
        name: "max_bat_slices",
        unit: "",
        description: "largest slice count (bat length / slice_length) a BatParams may ask for; finer \
                      bats are REJECTED before their modes are solved",
        read_only: false,
        constraints: "",
        rule: Rule::Integer {
            default: crate::model::settings::DEFAULT_MAX_BAT_SLICES as i64,
            range: Some((100, crate::physics::bat::SLICE_COUNT_RANGE.1 as i64)),
            set: |s, n| {
                s.model.max_bat_slices = n as usize;
                STORED
            },
        },
        get: |s| ParameterValue::Integer(s.model.max_bat_slices as i64),
    },
    // Covers a burst of 10,000 swings at a few hundred bytes each (≈ 5 MB worst case).
    Parameter {
        name: "queue_capacity",
        unit: "",
        description: "swings in flight (queued, computing or awaiting in-order publication) before new ones are \
                      dropped",
        read_only: true,
        constraints: "",
        rule: Rule::Integer {
            default: 16_384,
            range: Some((1, 1_000_000)),
            set: |s, n| {
                s.queue_capacity = n as usize;
                STORED
            },
        },
        get: |s| ParameterValue::Integer(s.queue_capacity as i64),
    },
    Parameter {
        name: "workers",
        unit: "",
        description: "collision worker threads; 0 = one per CPU core",
        read_only: true,
        constraints: "",
        rule: Rule::Integer {
            default: 0,
            range: Some((0, 256)),
            set: |s, n| {
                s.workers = n as usize;
                STORED
            },
        },
        get: |s| ParameterValue::Integer(s.workers as i64),
    },
    Parameter {
        name: "record",
        unit: "",
        description: "record every input and output to MCAP",
        read_only: true,
        constraints: "",
        rule: Rule::Boolean {
            default: true,
            set: |s, b| {
                s.record = b;
                STORED
            },
        },
        get: |s| ParameterValue::Boolean(s.record),
    },
    Parameter {
        name: "record_services",
        unit: "",
        description: "also record ~/simulate_swing calls (request and response events on <service>/_service_event)",
        read_only: true,
        constraints: "",
        rule: Rule::Boolean {
            default: false,
            set: |s, b| {
                s.record_services = b;
                STORED
            },
        },
        get: |s| ParameterValue::Boolean(s.record_services),
    },
    // A ROS 2 service is not interoperable across RMW vendors: rmw_fastrtps (and ros2-client) use RPC over
    // DDS's "enhanced" mapping (no header in the data), rmw_cyclonedds_cpp puts its own header in front of
    // the request. One mapping per node, chosen at start-up for all its services, parameters included.
    Parameter {
        name: "service_mapping",
        unit: "",
        description: "request/reply wire mapping of ~/simulate_swing and the parameter services: enhanced \
                      (rmw_fastrtps, Jazzy's default; ros2-client) or cyclone (clients on rmw_cyclonedds_cpp)",
        read_only: true,
        constraints: "enhanced or cyclone",
        rule: Rule::Text { default: "enhanced", set: set_service_mapping },
        get: |s| ParameterValue::String(s.service_mapping.clone()),
    },
    Parameter {
        name: "record_path",
        unit: "",
        description: "rosbag2 directory to create; empty = bags/<node>_<UTC time>",
        read_only: true,
        constraints: "",
        rule: Rule::Text {
            default: "",
            set: |s, v| {
                s.record_path = v.to_string();
                STORED
            },
        },
        get: |s| ParameterValue::String(s.record_path.clone()),
    },
    Parameter {
        name: "record_max_file_size",
        unit: "bytes",
        description: "split the bag after this many bytes; 0 = never",
        read_only: true,
        constraints: SPLIT_SIZE,
        rule: Rule::Integer {
            default: 0,
            range: None,
            set: |s, n| {
                within(n == 0 || n >= 4096, SPLIT_SIZE)?;
                s.record_max_file_size = n as u64;
                STORED
            },
        },
        get: |s| ParameterValue::Integer(s.record_max_file_size as i64),
    },
    Parameter {
        name: "record_max_file_duration",
        unit: "s",
        description: "split the bag after this much time; 0 = never",
        read_only: true,
        constraints: SPLIT_DURATION,
        rule: Rule::Double {
            default: 0.0,
            range: None,
            set: |s, x| {
                within(x.is_finite() && x >= 0.0, SPLIT_DURATION)?;
                s.record_max_file_duration = x;
                STORED
            },
        },
        get: |s| ParameterValue::Double(s.record_max_file_duration),
    },
    Parameter {
        name: "record_storage_preset",
        unit: "",
        description: "MCAP layout as rosbag2's --storage-preset-profile: none (rosbag2's default: uncompressed \
                      chunks), fastwrite (no chunks, no indexes, uncompressed), zstd_fast (zstd -5), zstd_small \
                      (zstd 19, 4 MiB chunks); empty = zstd level 1 chunks",
        read_only: true,
        constraints: "",
        rule: Rule::Text { default: "", set: set_record_storage_preset },
        get: |s| ParameterValue::String(s.record_storage_preset.clone()),
    },
    Parameter {
        name: "record_compression",
        unit: "",
        description: "chunk compression, overriding the preset's: zstd (level 1), zstd:LEVEL (-7..=-1 fast, \
                      1..=22), lz4 or none; empty = the preset's (zstd level 1 without one); with fastwrite only \
                      none or empty",
        read_only: true,
        constraints: "",
        rule: Rule::Text { default: "", set: set_record_compression },
        get: |s| ParameterValue::String(s.record_compression.clone()),
    },
    Parameter {
        name: "diagnostics_period",
        unit: "s",
        description: "period of /diagnostics",
        read_only: true,
        constraints: "",
        rule: Rule::Double {
            default: 1.0,
            range: Some((0.1, 60.0)),
            set: |s, x| {
                s.diagnostics_period = x;
                STORED
            },
        },
        get: |s| ParameterValue::Double(s.diagnostics_period),
    },
    Parameter {
        name: "foxglove_port",
        unit: "",
        description: "serve the session live to Foxglove on [ADDR:]PORT (WebSocket; 127.0.0.1 unless ADDR is \
                      given); empty = off",
        read_only: true,
        constraints: "",
        rule: Rule::Text {
            default: "",
            set: |s, v| {
                if !v.is_empty() {
                    crate::foxglove::Bind::parse(v).map_err(|e| {
                        Refusal::Refused(format!(
                            "foxglove_port = '{}' is REJECTED: {e}",
                            crate::model::limits::quote(v)
                        ))
                    })?;
                }
                s.foxglove_port = v.to_string();
                STORED
            },
        },
        get: |s| ParameterValue::String(s.foxglove_port.clone()),
    },
    Parameter {
        name: "foxglove_max_clients",
        unit: "",
        description: "most Foxglove connections served at once (handshaking or connected); more are closed as \
                      they arrive, the refusal logged once",
        read_only: true,
        constraints: "",
        rule: Rule::Integer {
            default: crate::foxglove::DEFAULT_MAX_CLIENTS as i64,
            range: Some((1, 10_000)),
            set: |s, n| {
                s.foxglove_max_clients = n as usize;
                STORED
            },
        },
        get: |s| ParameterValue::Integer(s.foxglove_max_clients as i64),
    },
    // Off by default: a scene is ~45 times an answer's bytes (the bat's outline and deflection), which a
    // node answering tens of thousands of swings a second should not write unasked.
    Parameter {
        name: "swing_scene",
        unit: "",
        description: "publish and record each answered swing drawn (visualization_msgs/MarkerArray on \
                      swing_scene, frame bat); the Foxglove server serves it to its subscribers either way",
        read_only: true,
        constraints: "",
        rule: Rule::Boolean {
            default: false,
            set: |s, b| {
                s.swing_scene = b;
                STORED
            },
        },
        get: |s| ParameterValue::Boolean(s.swing_scene),
    },
    // A scene is ~11.5 KB and costs the node its drawing: at tens of thousands of swings a second a Foxglove
    // client subscribed to it would cost more than the answers (measured: the sustained rate fell from
    // 40,000 to 20,000/s). A 3D panel redraws at display rate, so the live view is rate-limited; DDS and the
    // bag (`swing_scene`) still get every scene.
    Parameter {
        name: "swing_scene_live_hz",
        unit: "Hz",
        description: "most swing scenes per second served to Foxglove clients (the newest answered swing when one \
                      is due); 0 = every answered swing; DDS and the bag (swing_scene) get every one",
        read_only: true,
        constraints: "",
        rule: Rule::Double {
            default: 30.0,
            range: Some((0.0, 1000.0)),
            set: |s, x| {
                s.swing_scene_live_hz = x;
                STORED
            },
        },
        get: |s| ParameterValue::Double(s.swing_scene_live_hz),
    },
];

fn set_service_mapping(s: &mut NodeSettings, mapping: &str) -> Checked {
    if service_mapping(mapping).is_none() {
        return Err(Refusal::Refused(format!("service_mapping = {mapping:?}: expected enhanced or cyclone")));
    }
    s.service_mapping = mapping.to_string();
    STORED
}

/// The ros2-client mapping a `service_mapping` value names (None for anything else).
pub fn service_mapping(name: &str) -> Option<ros2_client::ServiceMapping> {
    match name {
        "enhanced" => Some(ros2_client::ServiceMapping::Enhanced),
        "cyclone" => Some(ros2_client::ServiceMapping::Cyclone),
        _ => None,
    }
}

fn set_record_storage_preset(s: &mut NodeSettings, preset: &str) -> Checked {
    if !preset.is_empty() {
        if let Err(err) = preset.parse::<crate::bag::StoragePreset>() {
            return Err(Refusal::Refused(format!("record_storage_preset = {preset:?} is REJECTED: {err}")));
        }
    }
    if let Err(err) = crate::bag::StorageOptions::from_parameters(preset, &s.record_compression) {
        return Err(Refusal::Refused(format!(
            "record_storage_preset = {preset:?} is REJECTED with record_compression = {:?}: {err}",
            s.record_compression
        )));
    }
    s.record_storage_preset = preset.to_string();
    STORED
}

fn set_record_compression(s: &mut NodeSettings, compression: &str) -> Checked {
    if !compression.is_empty() {
        if let Err(err) = compression.parse::<crate::bag::ChunkCompression>() {
            return Err(Refusal::Refused(format!("record_compression = {compression:?} is not a compression: {err}")));
        }
    }
    if let Err(err) = crate::bag::StorageOptions::from_parameters(&s.record_storage_preset, compression) {
        return Err(Refusal::Refused(format!(
            "record_compression = {compression:?} is REJECTED with record_storage_preset = {:?}: {err}",
            s.record_storage_preset
        )));
    }
    s.record_compression = compression.to_string();
    STORED
}

impl Parameter {
    /// Its value when no `-p` sets it.
    pub fn default_value(&self) -> ParameterValue {
        match &self.rule {
            Rule::Text { default, .. } => ParameterValue::String(default.to_string()),
            Rule::Integer { default, .. } => ParameterValue::Integer(*default),
            Rule::Double { default, .. } => ParameterValue::Double(*default),
            Rule::Boolean { default, .. } => ParameterValue::Boolean(*default),
        }
    }

    /// Its value in `settings`.
    pub fn value(&self, settings: &NodeSettings) -> ParameterValue {
        (self.get)(settings)
    }

    /// What `ros2 param describe` shows: the description (with the unit), the range or constraints, and
    /// whether it is fixed at start-up. The range is the one [`NodeSettings::apply`] checks.
    pub fn descriptor(&self) -> ParameterDescriptor {
        let range = match self.rule {
            Rule::Integer { range: Some((from_value, to_value)), .. } => {
                NumericRange::IntegerRange { from_value, to_value, step: 0 }
            }
            Rule::Double { range: Some((from_value, to_value)), .. } => {
                NumericRange::FloatingPointRange { from_value, to_value, step: 0.0 }
            }
            _ => NumericRange::NotSpecified,
        };
        let description = match self.unit {
            "" => self.description.to_string(),
            unit => format!("{} [{unit}]", self.description),
        };
        ParameterDescriptor {
            description,
            additional_constraints: self.constraints.to_string(),
            read_only: self.read_only,
            range,
            ..ParameterDescriptor::from_value(self.name, &self.default_value())
        }
    }

    /// "lo ≤ name ≤ hi unit" for a value outside `range`, `None` inside it (NaN is outside any range).
    fn outside<T: PartialOrd + std::fmt::Display>(&self, range: Option<(T, T)>, x: T) -> Option<Refusal> {
        let (lo, hi) = range?;
        let unit = if self.unit.is_empty() { String::new() } else { format!(" {}", self.unit) };
        (!(lo <= x && x <= hi)).then(|| Refusal::OutOfRange(format!("{lo} ≤ {} ≤ {hi}{unit}", self.name)))
    }

    /// Checks a value of its type (its range first) and stores it in `settings`; a value of another type is
    /// `Err(None)`.
    fn set(&self, settings: &mut NodeSettings, value: &ParameterValue) -> Result<SettingEffect, Option<Refusal>> {
        use ParameterValue as V;
        match (&self.rule, value) {
            (Rule::Text { set, .. }, V::String(v)) => set(settings, v).map_err(Some),
            (Rule::Integer { range, set, .. }, V::Integer(n)) => match self.outside(*range, *n) {
                Some(refusal) => Err(Some(refusal)),
                None => set(settings, *n).map_err(Some),
            },
            (Rule::Double { range, set, .. }, V::Double(x)) => {
                match self.outside(range.map(|(lo, hi)| (Short(lo), Short(hi))), Short(*x)) {
                    Some(refusal) => Err(Some(refusal)),
                    None => set(settings, *x).map_err(Some),
                }
            }
            (Rule::Boolean { set, .. }, V::Boolean(b)) => set(settings, *b).map_err(Some),
            _ => Err(None),
        }
    }

    /// "a string", "an integer", … for type errors.
    fn type_name(&self) -> &'static str {
        match self.rule {
            Rule::Text { .. } => "a string",
            Rule::Integer { .. } => "an integer",
            Rule::Double { .. } => "a double",
            Rule::Boolean { .. } => "a boolean",
        }
    }
}

/// The parameter called `name`, if the node has one.
pub fn parameter(name: &str) -> Option<&'static Parameter> {
    PARAMETERS.iter().find(|p| p.name == name)
}

/// Whether `name` only takes effect at start-up (setting it on a running node is refused).
pub fn is_read_only(name: &str) -> bool {
    parameter(name).is_some_and(|p| p.read_only)
}

impl Default for NodeSettings {
    /// Every parameter's default from [`PARAMETERS`].
    fn default() -> Self {
        let mut settings = NodeSettings {
            model: ModelSettings::default(),
            reference_ball_speed: 0.0,
            reference_bat_cm_speed: 0.0,
            reference_bat_angular_speed: 0.0,
            queue_capacity: 0,
            workers: 0,
            record: false,
            record_services: false,
            service_mapping: "enhanced".to_string(),
            record_path: String::new(),
            record_max_file_size: 0,
            record_max_file_duration: 0.0,
            record_storage_preset: String::new(),
            record_compression: String::new(),
            diagnostics_period: 0.0,
            foxglove_port: String::new(),
            foxglove_max_clients: 0,
            swing_scene: false,
            swing_scene_live_hz: 30.0,
        };
        for parameter in PARAMETERS {
            let stored = parameter.set(&mut settings, &parameter.default_value());
            assert!(stored.is_ok(), "the default of {} is refused by its own rule", parameter.name);
        }
        settings
    }
}

impl NodeSettings {
    /// The parameters as ros2-client declarations, in a stable order.
    pub fn declarations(&self) -> Vec<(&'static str, ParameterValue)> {
        PARAMETERS.iter().map(|p| (p.name, p.value(self))).collect()
    }

    /// The current value of the parameter `name`, if the node has one.
    pub fn value_of(&self, name: &str) -> Option<ParameterValue> {
        parameter(name).map(|p| p.value(self))
    }

    /// Defaults overridden by `-p`/`--params-file` values; an integer given for a double parameter is
    /// accepted as that double (YAML writes `40` for 40.0), and an integer `foxglove_port` as that port. Unknown names and bad values are errors.
    pub fn with_overrides(overrides: &BTreeMap<String, ParameterValue>) -> Result<NodeSettings, String> {
        let mut settings = NodeSettings::default();
        for (name, value) in overrides {
            if name == "use_sim_time" {
                continue; // ros2-client's own parameter
            }
            let parameter = parameter(name).ok_or_else(|| unknown_parameter(name))?;
            let value = match (&parameter.rule, value) {
                (Rule::Double { .. }, ParameterValue::Integer(i)) => ParameterValue::Double(*i as f64),
                // `-p foxglove_port:=8765` is a YAML integer, as ROS users write a port.
                (Rule::Text { .. }, ParameterValue::Integer(port)) if name == "foxglove_port" => {
                    ParameterValue::String(port.to_string())
                }
                _ => value.clone(),
            };
            settings.apply(name, &value)?;
        }
        Ok(settings)
    }

    /// Checks and stores one value; the error names the parameter and its allowed range.
    pub fn apply(&mut self, name: &str, value: &ParameterValue) -> Result<SettingEffect, String> {
        let parameter = parameter(name).ok_or_else(|| unknown_parameter(name))?;
        parameter.set(self, value).map_err(|refusal| match refusal {
            None => format!("{} must be {}, got {}", parameter.name, parameter.type_name(), show(value)),
            Some(Refusal::OutOfRange(allowed)) => {
                format!("{} = {} is out of range: expected {allowed}", parameter.name, show(value))
            }
            Some(Refusal::Refused(message)) => message,
        })
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

/// A double in messages (a range end, a refused value), printed by the one number formatter of rejection
/// texts ([`crate::model::limits::number`]): `1e-8` rather than `0.00000001`, `100` rather than `100.0`,
/// `1e300` rather than 301 digits.
#[derive(Clone, Copy, PartialEq, PartialOrd)]
struct Short(f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&crate::model::limits::number(self.0))
    }
}

/// Names of all the node's own parameters.
pub fn parameter_names() -> Vec<&'static str> {
    PARAMETERS.iter().map(|p| p.name).collect()
}

fn unknown_parameter(name: &str) -> String {
    format!("unknown parameter '{}' (known: {})", crate::model::limits::quote(name), parameter_names().join(", "))
}

fn show(value: &ParameterValue) -> String {
    match value {
        ParameterValue::NotSet => "<not set>".to_string(),
        ParameterValue::Boolean(b) => b.to_string(),
        ParameterValue::Integer(i) => i.to_string(),
        ParameterValue::Double(x) => crate::model::limits::number(*x),
        ParameterValue::String(s) => format!("'{}'", crate::model::limits::quote(s)),
        other => format!("{other:?}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_bat_must_name_a_preset() {
        let mut s = NodeSettings::default();
        for preset in ["r161", "r161-corked", "aluminum", "torpedo"] {
            assert!(s.apply("default_bat", &ParameterValue::String(preset.into())).is_ok(), "{preset}");
            assert_eq!(s.model.default_bat, preset);
        }
        for bad in ["alumnium", "", " r161", "R161"] {
            let err = s.apply("default_bat", &ParameterValue::String(bad.into())).unwrap_err();
            assert!(err.starts_with("default_bat") && err.contains("aluminum"), "{bad}: {err}");
        }
        assert_eq!(s.model.default_bat, "torpedo", "a refused value leaves the last good one");
        let overrides = BTreeMap::from([("default_bat".to_string(), ParameterValue::String("alumnium".into()))]);
        assert!(NodeSettings::with_overrides(&overrides).unwrap_err().contains("not a bat preset"));
    }

    #[test]
    fn default_ball_must_name_a_preset() {
        let mut s = NodeSettings::default();
        assert_eq!(s.model.default_ball, "mlb2024", "the game ball");
        for preset in ["baseball", "bbcor", "mlb", "mlb2024"] {
            assert!(s.apply("default_ball", &ParameterValue::String(preset.into())).is_ok(), "{preset}");
            assert_eq!(s.model.default_ball, preset);
        }
        for bad in ["softball", "", "MLB2024"] {
            let err = s.apply("default_ball", &ParameterValue::String(bad.into())).unwrap_err();
            assert!(err.starts_with("default_ball") && err.contains("mlb2024"), "{bad}: {err}");
        }
        assert_eq!(s.model.default_ball, "mlb2024", "a refused value leaves the last good one");
    }

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
        assert!(is_read_only("record_compression"), "a bag keeps one compression");
    }

    #[test]
    fn record_storage_preset_takes_rosbag2_names_and_the_compression_overrides_it() {
        use crate::bag::{ChunkCompression, McapLayout, StorageOptions};
        let mut s = NodeSettings::default();
        assert_eq!(s.record_storage_preset, "");
        assert_eq!(s.storage_options().unwrap(), StorageOptions::default(), "no preset: sweetspot's zstd level 1");
        assert!(is_read_only("record_storage_preset"), "a bag keeps one layout");
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
    fn every_parameter_is_described_and_accepts_its_default() {
        let defaults = NodeSettings::default();
        for (name, value) in defaults.declarations() {
            let parameter = parameter(name).unwrap_or_else(|| panic!("{name} is not in the table"));
            assert!(!parameter.description.is_empty(), "{name} has no description");
            assert_eq!(parameter.default_value(), value, "{name}");
            let mut s = defaults.clone();
            s.apply(name, &value).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(s, defaults);
        }
        assert_eq!(PARAMETERS.len(), defaults.declarations().len());
    }

    #[test]
    fn a_described_range_is_what_apply_checks() {
        use ros2_client::parameters::{NumericRange, ParameterType};
        let mut ranged = 0;
        for p in PARAMETERS {
            let d = p.descriptor();
            assert_eq!((d.name.as_str(), d.read_only), (p.name, p.read_only));
            assert_eq!(d.param_type, p.default_value().to_parameter_type());
            assert!(d.description.starts_with(p.description) && d.description.contains(p.unit), "{}", p.name);
            assert_eq!(d.additional_constraints, p.constraints);
            // Each end accepted unless a constraint excludes it; the next value past an end refused.
            let (probes, lower_constrained): (Vec<ParameterValue>, bool) = match d.range {
                NumericRange::IntegerRange { from_value, to_value, step } => {
                    assert_eq!(step, 0);
                    let probes = [from_value - 1, from_value, to_value, to_value + 1].map(ParameterValue::Integer);
                    (probes.to_vec(), !p.constraints.is_empty())
                }
                NumericRange::FloatingPointRange { from_value, to_value, step } => {
                    assert_eq!(step, 0.0);
                    let ends = [from_value.next_down(), from_value, to_value, to_value.next_up()];
                    (ends.map(ParameterValue::Double).to_vec(), !p.constraints.is_empty())
                }
                NumericRange::NotSpecified => {
                    let numeric = matches!(d.param_type, ParameterType::Integer | ParameterType::Double);
                    assert!(!numeric || !p.constraints.is_empty(), "{}: a number with no range or constraint", p.name);
                    continue;
                }
            };
            ranged += 1;
            for (value, accepted) in probes.iter().zip([false, !lower_constrained, true, false]) {
                let result = NodeSettings::default().apply(p.name, value);
                assert_eq!(result.is_ok(), accepted, "{} = {value:?}: {result:?}", p.name);
                if let Err(reason) = result {
                    let named = if accepted || value != &probes[1] { "≤" } else { p.constraints };
                    assert!(reason.contains(p.name) && reason.contains(named), "{reason}");
                }
            }
        }
        assert_eq!(ranged, 13, "the numeric parameters with a range");
    }

    #[test]
    fn defaults_and_read_only_parameters_are_the_documented_ones() {
        use ParameterValue::*;
        // docs/node.md's parameter table: name, default, `*` = fixed at start-up.
        let documented = [
            ("default_bat", String("r161".into()), false),
            ("default_ball", String("mlb2024".into()), false),
            ("default_modes", Integer(18), false),
            ("time_step", Double(5e-6), false),
            ("reference_ball_speed", Double(40.0), false),
            ("reference_bat_cm_speed", Double(20.0), false),
            ("reference_bat_angular_speed", Double(50.0), false),
            ("max_bats", Integer(64), false),
            ("max_balls", Integer(1024), false),
            ("max_bat_slices", Integer(1200), false),
            ("queue_capacity", Integer(16384), true),
            ("workers", Integer(0), true),
            ("record", Boolean(true), true),
            ("record_services", Boolean(false), true),
            ("service_mapping", String("enhanced".into()), true),
            ("record_path", String("".into()), true),
            ("record_max_file_size", Integer(0), true),
            ("record_max_file_duration", Double(0.0), true),
            ("record_storage_preset", String("".into()), true),
            ("record_compression", String("".into()), true),
            ("diagnostics_period", Double(1.0), true),
            ("foxglove_port", String("".into()), true),
            ("foxglove_max_clients", Integer(64), true),
            ("swing_scene", Boolean(false), true),
            ("swing_scene_live_hz", Double(30.0), true),
        ];
        let declared = NodeSettings::default().declarations();
        assert_eq!(declared.len(), documented.len());
        for ((name, value), (doc_name, doc_value, doc_read_only)) in declared.into_iter().zip(documented) {
            assert_eq!((name, &value), (doc_name, &doc_value));
            assert_eq!(is_read_only(name), doc_read_only, "{name}");
        }
        assert!(!is_read_only("frobs"));
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
    fn an_integer_foxglove_port_is_the_port_as_ros_users_write_it() {
        let args = crate::ros::args::RosArgs::parse(&["-p".to_string(), "foxglove_port:=8765".to_string()]);
        let args = args.expect("--ros-args");
        let overrides = args.parameter_overrides(&args.identity("sweetspot", "/")).expect("overrides");
        assert_eq!(overrides.get("foxglove_port"), Some(&ParameterValue::Integer(8765)), "YAML reads a number");
        assert_eq!(NodeSettings::with_overrides(&overrides).unwrap().foxglove_port, "8765");
        let mut o = BTreeMap::new();
        o.insert("foxglove_port".to_string(), ParameterValue::Integer(70000));
        let e = NodeSettings::with_overrides(&o).unwrap_err();
        assert!(e.contains("foxglove_port") && e.contains("70000"), "{e}");
        // Other text parameters still want text.
        o.clear();
        o.insert("default_bat".to_string(), ParameterValue::Integer(3));
        assert!(NodeSettings::with_overrides(&o).unwrap_err().contains("must be a string"));
    }

    #[test]
    fn refused_values_print_in_scientific_form_outside_1e_minus_4_to_1e6() {
        let mut s = NodeSettings::default();
        let e = s.apply("reference_ball_speed", &ParameterValue::Double(1e300)).unwrap_err();
        assert!(e.starts_with("reference_ball_speed = 1e300 is out of range"), "{e}");
        let e = s.apply("reference_ball_speed", &ParameterValue::Double(-5e-324)).unwrap_err();
        assert!(e.starts_with("reference_ball_speed = -5e-324 is out of range"), "{e}");
        let e = s.apply("time_step", &ParameterValue::Double(1.0)).unwrap_err();
        assert!(e.contains("1e-8 ≤ time_step ≤ 0.0001 s"), "{e}");
        assert!(e.len() < 200, "{e}");
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
