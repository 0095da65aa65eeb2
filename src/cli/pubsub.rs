//! `sweetspot pub` and `sweetspot echo`: what `ros2 topic pub` / `ros2 topic echo` do for sweetspot's topics,
//! without a ROS installation.
//!
//! Both honour `ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE` / `ROS_LOCALHOST_ONLY` and
//! `--ros-args -r __ns:=/rig3 -r from:=to` (see [`crate::ros`]).

use std::io::{BufRead, Read as _, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context as _};
use serde_json::{Map, Value};

use crate::model::time::{period_of, saturating_secs};
use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus};
use crate::msgs::json::ToJson;
use crate::msgs::rcl_interfaces::msg::Log;
use crate::msgs::rosgraph_msgs::msg::Clock;
use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use crate::msgs::RosMessage;
use crate::ros::args::{NameResolver, NodeIdentity};
use crate::ros::edge::{matched_subscriptions, reader, write_reliably, writer};
use crate::ros::{self, interrupt_flag, shutdown_signal, topics, DdsConfig, RosArgs};

/// Arguments of `sweetspot pub`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  sweetspot pub swing '{swing_id: 1, bat_id: r161, ball_speed: 40, bat_cm_speed: 20, impact_z: 0.7}'
  sweetspot pub /swing sweetspot_msgs/msg/Swing '{bat_id: r161, ball_speed: 40, bat_cm_speed: 25, impact_z: 0.62}' -1
  sweetspot pub bat '{\"bat_id\": \"mine\", \"preset\": \"aluminum\"}' --keep-alive 5
  sweetspot pub swing '{ball_speed: 40, bat_cm_speed: 25, impact_z: 0.7}' -r 10 -t 30
  sweetspot pub swing --file swings.csv --rate 100 -w 1
  sweetspot pub /lab/swing --type Swing --file swings.jsonl --ros-args -r __ns:=/rig3

VALUES are YAML (flow `{a: 1}` or block `a: 1`, as `ros2 topic pub` takes them) or JSON; a list publishes
each item. Fields left out keep their defaults; header.stamp defaults to the publish time, a Swing's
swing_id to 1, 2, 3… and its measured_exit_speed to NaN (not measured). Floats accept null/nan/.nan.

Like `ros2 topic pub --once/--times`, pub waits for a matching subscription (-w, default 1) before the first
message and exits non-zero with a warning if none appears within --timeout; on a latched topic (bat, ball)
it does not wait (late joiners get the message), nor when one message repeats forever at --rate.")]
pub struct PubArgs {
    /// What to publish: a message kind (bat, ball, swing, or a type such as BatParams or
    /// sweetspot_msgs/msg/Swing) on its default topic, or a topic name (relative names are resolved in the
    /// namespace).
    pub target: String,
    /// `TYPE VALUES` or `VALUES` (the `ros2 topic pub TOPIC TYPE VALUES` form): a type when it is not a
    /// message, e.g. `sweetspot_msgs/msg/Swing`.
    #[arg(value_name = "TYPE|VALUES")]
    pub type_or_message: Option<String>,
    /// The message as YAML or JSON: an object, or a list of objects.
    #[arg(value_name = "VALUES")]
    pub message: Option<String>,
    /// Message type when TARGET is a topic whose type cannot be told from its name.
    #[arg(long = "type", value_name = "TYPE")]
    pub msg_type: Option<String>,
    /// Read messages from a file: JSON lines (one object per line; `-` = stdin), YAML (`.yaml`/`.yml`: a list
    /// or `---`-separated documents) or CSV (`.csv`, one column per field, nested fields as `header.frame_id`,
    /// arrays as `[1,2]` or `1;2`).
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Publish at this rate (messages per second); without it messages go out as fast as they are acknowledged.
    #[arg(short = 'r', long, value_name = "HZ", value_parser = super::common::rate_hz)]
    pub rate: Option<f64>,
    /// Publish this many messages in total, cycling through the input (default: each input message once, or
    /// forever when a single message is repeated with --rate).
    #[arg(short = 't', long = "times", visible_alias = "count", value_name = "N")]
    pub count: Option<u64>,
    /// Publish one message and exit (same as `--times 1`).
    #[arg(short = '1', long, conflicts_with = "count")]
    pub once: bool,
    /// Before the first message, wait until this many subscriptions on the topic have matched this publisher
    /// (default 1; 0 on latched topics and when repeating forever at --rate).
    #[arg(short = 'w', long = "wait-matching-subscriptions", visible_alias = "wait-subscribers", value_name = "N")]
    pub wait_subscribers: Option<usize>,
    /// Seconds to wait for matching subscriptions, and for subscribers to acknowledge everything at the end
    /// (inf: no limit).
    #[arg(long, visible_alias = "max-wait-time-secs", value_name = "SECS", default_value_t = 10.0,
          value_parser = super::common::seconds_at_least_zero)]
    pub timeout: f64,
    /// Stay up this many seconds after every subscription acknowledged the last message: readers need a moment
    /// to take what they acknowledged (a RustDDS reader drops the untaken samples of a writer whose participant
    /// has left), and late joiners get latched params only while we are up (inf: until Ctrl-C).
    #[arg(long, value_name = "SECS", default_value_t = 0.5, value_parser = super::common::seconds_at_least_zero)]
    pub keep_alive: f64,
    /// QoS over the topic's own.
    #[command(flatten)]
    pub qos: QosArgs,
    /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
    #[arg(long, visible_alias = "namespace", value_name = "NS")]
    pub ns: Option<String>,
    /// Do not print what is published.
    #[arg(long, short)]
    pub quiet: bool,
    /// ROS arguments (`-r __ns:=/rig3`, `-r from:=to`), as for any ROS 2 node; must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
    pub ros_args: Option<Vec<String>>,
}

/// Arguments of `sweetspot echo`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  sweetspot echo exit_velocity
  sweetspot echo /exit_velocity --ns /lab --once
  sweetspot echo /rig3/modal_energies --json --count 10 --timeout 30
  sweetspot echo /lab/thing sweetspot_msgs/msg/Swing --qos-reliability best_effort
  sweetspot echo /diagnostics
  sweetspot echo /clock --once                # the bag time `bag play --clock` publishes

When nothing publishes on the topic after a few seconds, echo says so on stderr and names the topics (and so
the namespaces) where that message type is published, then keeps listening.")]
pub struct EchoArgs {
    /// Topic to print (relative names are resolved in the namespace), or a message kind (bat, ball, swing,
    /// exit_velocity, modal_energies, sweet_spot, diagnostics, rosout, clock) for its default topic.
    pub topic: String,
    /// Message type (the `ros2 topic echo TOPIC TYPE` form), same as --type.
    #[arg(value_name = "TYPE")]
    pub positional_type: Option<String>,
    /// Message type when the topic's type cannot be told from its name.
    #[arg(long = "type", value_name = "TYPE")]
    pub msg_type: Option<String>,
    /// One JSON object per line (NaN as null) instead of the readable form.
    #[arg(long)]
    pub json: bool,
    /// Exit after this many messages (exit status 1 if --timeout ends the wait first).
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
    /// Print the first message received and exit (same as `--count 1`).
    #[arg(long, conflicts_with = "count")]
    pub once: bool,
    /// Exit after this many seconds (inf: no limit, as without it).
    #[arg(long, value_name = "SECS", value_parser = super::common::seconds_at_least_zero)]
    pub timeout: Option<f64>,
    /// Subscribe volatile even on latched topics (params, sweet_spot): only messages published from now on.
    #[arg(long)]
    pub no_latched: bool,
    /// QoS over the topic's own.
    #[command(flatten)]
    pub qos: QosArgs,
    /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
    #[arg(long, visible_alias = "namespace", value_name = "NS")]
    pub ns: Option<String>,
    /// ROS arguments (`-r __ns:=/rig3`, `-r from:=to`), as for any ROS 2 node; must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
    pub ros_args: Option<Vec<String>>,
}

/// `--qos-*` overrides of a topic's QoS, as `ros2 topic pub/echo` take them.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct QosArgs {
    /// Reliability: reliable, best_effort, or system_default (the topic's own).
    #[arg(long, value_name = "POLICY", value_parser = ["reliable", "best_effort", "system_default"])]
    pub qos_reliability: Option<String>,
    /// Durability: volatile, transient_local, or system_default (the topic's own).
    #[arg(long, value_name = "POLICY", value_parser = ["volatile", "transient_local", "system_default"])]
    pub qos_durability: Option<String>,
    /// History depth (keep last N).
    #[arg(long, value_name = "N")]
    pub qos_depth: Option<usize>,
}

impl QosArgs {
    /// `qos` with these overrides.
    pub fn apply(&self, qos: ros2_client::QosProfile) -> anyhow::Result<ros2_client::QosProfile> {
        use ros2_client::qos::{Durability, History, Reliability, WhenFull};
        let mut qos = qos;
        match self.qos_reliability.as_deref() {
            Some("best_effort") => qos = qos.reliability(Reliability::BestEffort),
            Some("reliable") if qos.reliability == Reliability::BestEffort => {
                qos = qos.reliability(Reliability::Reliable { when_full: WhenFull::DEFAULT })
            }
            _ => {}
        }
        match self.qos_durability.as_deref() {
            Some("volatile") => qos = qos.durability(Durability::Volatile),
            Some("transient_local") => qos = qos.durability(Durability::TransientLocal),
            _ => {}
        }
        if let Some(depth) = self.qos_depth {
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

const ALL_KINDS: [Kind; 9] = [
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
            Kind::BatParams => {
                type $T = BatParams;
                $body
            }
            Kind::BallParams => {
                type $T = BallParams;
                $body
            }
            Kind::Swing => {
                type $T = Swing;
                $body
            }
            Kind::ExitVelocity => {
                type $T = ExitVelocity;
                $body
            }
            Kind::ModalEnergies => {
                type $T = ModalEnergies;
                $body
            }
            Kind::SweetSpot => {
                type $T = SweetSpot;
                $body
            }
            Kind::Diagnostics => {
                type $T = DiagnosticArray;
                $body
            }
            Kind::Rosout => {
                type $T = Log;
                $body
            }
            Kind::Clock => {
                type $T = Clock;
                $body
            }
        }
    };
}

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

/// The tool's node identity (`__ns` over `--ns` over `/`; `__node` over `default_name`) and its topic-name
/// resolver, from the same `--ros-args` parser the node uses.
fn ros_context(
    ns: &Option<String>,
    ros_args: &Option<Vec<String>>,
    default_name: &str,
) -> anyhow::Result<(NodeIdentity, NameResolver)> {
    let parsed = RosArgs::parse(ros_args.as_deref().unwrap_or_default())?;
    let namespace = match ns {
        Some(n) => ros::names::normalize_namespace(n)?,
        None => "/".to_string(),
    };
    let identity = parsed.identity(default_name, &namespace);
    let resolver = parsed.resolver(&identity);
    Ok((identity, resolver))
}

/// The topic and kind of `target` (a kind word or a topic), honouring `--type`.
fn resolve_target(
    target: &str,
    msg_type: &Option<String>,
    identity: &NodeIdentity,
    resolver: &NameResolver,
) -> anyhow::Result<(String, Kind)> {
    let explicit = match msg_type {
        Some(t) => Some(Kind::from_word(t).ok_or_else(|| {
            anyhow!(
                "unknown message type {t:?}; known: {}",
                ALL_KINDS.iter().map(|k| k.type_name()).collect::<Vec<_>>().join(", ")
            )
        })?),
        None => None,
    };
    let (topic, kind) = match (explicit, Kind::from_word(target)) {
        (None, Some(k)) => (k.default_topic().to_string(), Some(k)),
        (e, _) => (target.to_string(), e),
    };
    // Validated and expanded by the ROS naming rules first, then remapped.
    let fq = resolver.resolve(&ros::resolve_topic(&topic, &identity.namespace, &identity.name)?);
    let kind = match kind.or_else(|| Kind::from_topic(&fq)) {
        Some(k) => k,
        None => {
            bail!("cannot tell the message type of topic {fq}; pass --type (e.g. --type Swing)")
        }
    };
    Ok((fq, kind))
}

fn now_time() -> Time {
    let d = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
    Time { sec: i32::try_from(d.as_secs()).unwrap_or(i32::MAX), nanosec: d.subsec_nanos() }
}

/// Fills what the user left out: header.stamp (publish time), and for a Swing swing_id (a sequence number)
/// and measured_exit_speed (NaN, "not measured").
fn complete(kind: Kind, template: &Value, input: &Value, sequence: u64, stamp: &Time) -> Value {
    let mut v = input.clone();
    if let Value::Object(obj) = &mut v {
        if template.get("header").is_some() {
            let header = obj.entry("header").or_insert_with(|| Value::Object(Map::new()));
            if let Value::Object(h) = header {
                h.entry("stamp").or_insert_with(|| stamp.to_json());
            }
        }
        if kind == Kind::Swing {
            obj.entry("swing_id").or_insert_with(|| Value::from(sequence));
            obj.entry("measured_exit_speed").or_insert(Value::Null);
        }
    }
    v
}

/// The input messages as JSON values, with a description of where each came from (for errors).
fn read_inputs(message: Option<&str>, args: &PubArgs) -> anyhow::Result<Vec<(String, Value)>> {
    let mut out = Vec::new();
    if let Some(text) = message {
        match parse_values(text)? {
            Value::Array(items) => {
                for (i, item) in items.into_iter().enumerate() {
                    out.push((format!("message[{i}]"), item));
                }
            }
            other => out.push(("message".into(), other)),
        }
    }
    if let Some(path) = &args.file {
        let is_csv = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        let is_yaml = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("yaml") || e.eq_ignore_ascii_case("yml"));
        if is_csv {
            out.extend(read_csv(path)?);
        } else if is_yaml {
            out.extend(read_yaml_file(path)?);
        } else {
            out.extend(read_json_lines(path)?);
        }
    }
    if message.is_none() && args.file.is_none() {
        // Like `ros2 topic pub` with no values: a message with every default.
        out.push(("defaults".into(), Value::Object(Map::new())));
    }
    Ok(out)
}

/// A message given on the command line (`pub`, `call`) or a case file: JSON, else YAML (flow `{a: 1, b: x}` or block `a: 1`), as
/// `ros2 topic pub` takes it. JSON goes first so that its numbers (e.g. a u64 above i64) keep their exact value.
pub(crate) fn parse_values(text: &str) -> anyhow::Result<Value> {
    parse_document(text, "the message")
}

/// `text` as JSON, else YAML; `what` names it in errors ("the message", "the case").
pub(crate) fn parse_document(text: &str, what: &str) -> anyhow::Result<Value> {
    if let Ok(v) = serde_json::from_str::<Value>(text) {
        return Ok(v);
    }
    let docs = crate::yaml::load(text).map_err(|e| match e {
        e if e.is_syntax() => anyhow!("{what} is not valid JSON or YAML: {e}"),
        e => anyhow!("{what}: {e}"),
    })?;
    match docs.len() {
        0 => bail!("{what} is empty"),
        1 => yaml_to_json(&docs[0]).map_err(|e| anyhow!("{what}: {e}")),
        _ => Ok(Value::Array(docs.iter().map(yaml_to_json).collect::<Result<_, _>>()?)),
    }
}

/// A YAML file: one list of messages, or one message per `---` document.
fn read_yaml_file(path: &Path) -> anyhow::Result<Vec<(String, Value)>> {
    let text = crate::files::read_text(path, "--file")?;
    let docs = crate::yaml::load(&text).map_err(|e| match e {
        e if e.is_syntax() => anyhow!("{}: invalid YAML: {e}", path.display()),
        e => anyhow!("{}: {e}", path.display()),
    })?;
    let mut out = Vec::new();
    for (d, doc) in docs.iter().enumerate() {
        match yaml_to_json(doc).map_err(|e| anyhow!("{}: document {}: {e}", path.display(), d + 1))? {
            Value::Array(items) => {
                out.extend(items.into_iter().enumerate().map(|(i, v)| (format!("{}[{i}]", path.display()), v)))
            }
            other => out.push((format!("{}: document {}", path.display(), d + 1), other)),
        }
    }
    Ok(out)
}

/// YAML as the JSON the message decoder reads: `.nan`/`.inf` become the strings it accepts for floats, and
/// scalar keys become strings.
fn yaml_to_json(y: &yaml_rust2::Yaml) -> anyhow::Result<Value> {
    use yaml_rust2::Yaml;
    Ok(match y {
        Yaml::Null => Value::Null,
        Yaml::Boolean(b) => Value::Bool(*b),
        Yaml::Integer(i) => Value::from(*i),
        Yaml::Real(text) => match y.as_f64() {
            Some(x) if x.is_finite() => serde_json::Number::from_f64(x).map(Value::Number).unwrap_or(Value::Null),
            Some(x) if x.is_nan() => Value::String("nan".into()),
            Some(x) if x > 0.0 => Value::String("inf".into()),
            Some(_) => Value::String("-inf".into()),
            None => Value::String(text.clone()),
        },
        Yaml::String(s) => Value::String(s.clone()),
        Yaml::Array(items) => Value::Array(items.iter().map(yaml_to_json).collect::<Result<_, _>>()?),
        Yaml::Hash(map) => {
            let mut obj = Map::new();
            for (k, v) in map {
                let key = match k {
                    Yaml::String(s) | Yaml::Real(s) => s.clone(),
                    Yaml::Integer(i) => i.to_string(),
                    Yaml::Boolean(b) => b.to_string(),
                    other => bail!("a field name must be a word, found {other:?}"),
                };
                obj.insert(key, yaml_to_json(v)?);
            }
            Value::Object(obj)
        }
        Yaml::Alias(_) | Yaml::BadValue => bail!("unsupported YAML value {y:?}"),
    })
}

/// Whether a positional argument after TARGET is a message (YAML/JSON) rather than a type name: type names
/// (`Swing`, `sweetspot_msgs/msg/Swing`) have no braces, brackets, colons or line breaks.
fn looks_like_values(text: &str) -> bool {
    let t = text.trim();
    t.is_empty() || t.starts_with(['{', '[', '-', '"', '\'']) || t.contains([':', '\n'])
}

/// The type and the message from `TARGET [TYPE] [VALUES]` and `--type` (which must agree with TYPE).
fn split_positionals(args: &PubArgs) -> anyhow::Result<(Option<String>, Option<String>)> {
    let (positional_type, message) = match (&args.type_or_message, &args.message) {
        (Some(t), Some(m)) => (Some(t.clone()), Some(m.clone())),
        (Some(x), None) if looks_like_values(x) => (None, Some(x.clone())),
        (Some(t), None) => (Some(t.clone()), None),
        (None, m) => (None, m.clone()),
    };
    let msg_type = match (&args.msg_type, positional_type) {
        (Some(flag), Some(pos)) if Kind::from_word(flag) != Kind::from_word(&pos) => {
            bail!("the TYPE argument {pos:?} and --type {flag:?} disagree")
        }
        (Some(flag), _) => Some(flag.clone()),
        (None, pos) => pos,
    };
    Ok((msg_type, message))
}

fn read_json_lines(path: &Path) -> anyhow::Result<Vec<(String, Value)>> {
    use crate::files::MAX_INPUT_BYTES;
    let reader: Box<dyn BufRead> = if path == Path::new("-") {
        Box::new(std::io::BufReader::new(std::io::stdin().take(MAX_INPUT_BYTES + 1)))
    } else {
        Box::new(std::io::Cursor::new(crate::files::read_limited(path, "--file", MAX_INPUT_BYTES)?))
    };
    let mut out = Vec::new();
    let mut lines = Vec::new();
    let mut bytes = 0u64;
    for line in reader.lines() {
        let line = line.with_context(|| format!("cannot read {}", path.display()))?;
        bytes += line.len() as u64 + 1;
        if bytes > MAX_INPUT_BYTES + 1 {
            bail!("{}: over the limit of {MAX_INPUT_BYTES} bytes for an input: refused", path.display());
        }
        lines.push(line);
    }
    // A file holding one JSON array is accepted too.
    let whole = lines.join("\n");
    if whole.trim_start().starts_with('[') {
        let v: Value = serde_json::from_str(&whole).with_context(|| format!("{}: invalid JSON", path.display()))?;
        if let Value::Array(items) = v {
            for (i, item) in items.into_iter().enumerate() {
                out.push((format!("{}[{i}]", path.display()), item));
            }
        }
        return Ok(out);
    }
    for (i, line) in lines.iter().enumerate() {
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') || t.starts_with("//") {
            continue;
        }
        let v: Value =
            serde_json::from_str(t).with_context(|| format!("{}:{}: invalid JSON", path.display(), i + 1))?;
        out.push((format!("{}:{}", path.display(), i + 1), v));
    }
    Ok(out)
}

fn read_csv(path: &Path) -> anyhow::Result<Vec<(String, Value)>> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(std::io::Cursor::new(crate::files::read_limited(path, "--file", crate::files::MAX_INPUT_BYTES)?));
    let headers = reader.headers().with_context(|| format!("{}: no header row", path.display()))?.clone();
    let mut out = Vec::new();
    for (i, record) in reader.records().enumerate() {
        let record = record.with_context(|| format!("{}: bad CSV record {}", path.display(), i + 1))?;
        let mut obj = Map::new();
        for (name, cell) in headers.iter().zip(record.iter()) {
            if cell.is_empty() {
                continue; // an empty cell keeps the field's default
            }
            insert_dotted(&mut obj, name, Value::String(cell.to_string()));
        }
        out.push((format!("{}:{}", path.display(), i + 2), Value::Object(obj)));
    }
    Ok(out)
}

/// `header.stamp.sec` = v → {"header": {"stamp": {"sec": v}}}.
fn insert_dotted(obj: &mut Map<String, Value>, dotted: &str, value: Value) {
    match dotted.split_once('.') {
        None => {
            obj.insert(dotted.to_string(), value);
        }
        Some((head, rest)) => {
            let child = obj.entry(head.to_string()).or_insert_with(|| Value::Object(Map::new()));
            if let Value::Object(m) = child {
                insert_dotted(m, rest, value);
            }
        }
    }
}

/// Publishes messages.
pub fn run_pub(args: PubArgs) -> anyhow::Result<()> {
    let (identity, resolver) = ros_context(&args.ns, &args.ros_args, "sweetspot_pub")?;
    let (msg_type, message) = split_positionals(&args)?;
    let (fq_topic, kind) = resolve_target(&args.target, &msg_type, &identity, &resolver)?;
    // --rate, --timeout and --keep-alive are checked by their value parsers (model::time): inf waits for ever.
    let inputs = read_inputs(message.as_deref(), &args)?;
    if inputs.is_empty() {
        bail!("no messages to publish");
    }
    let qos = args.qos.apply(kind.qos())?;
    with_type!(kind, T => publish_all::<T>(kind, &args, &qos, &fq_topic, &inputs))
}

fn publish_all<T: RosMessage>(
    kind: Kind,
    args: &PubArgs,
    qos: &ros2_client::QosProfile,
    fq_topic: &str,
    inputs: &[(String, Value)],
) -> anyhow::Result<()> {
    // Check every input before touching the network, so a typo in line 900 fails fast.
    let template = T::default().to_json();
    let zero = Time::default();
    for (i, (origin, value)) in inputs.iter().enumerate() {
        let v = complete(kind, &template, value, i as u64 + 1, &zero);
        let message = T::from_json(&v, "").map_err(|e| anyhow!("{origin}: {e}"))?;
        refuse_undeliverable(kind, &message).map_err(|e| anyhow!("{origin}: {e}; nothing was published"))?;
    }
    let total = match (args.once.then_some(1).or(args.count), args.rate, inputs.len()) {
        (Some(n), _, _) => Some(n),
        (None, Some(_), 1) => None, // one message repeated at a rate: until interrupted
        (None, _, n) => Some(n as u64),
    };

    let config = DdsConfig::from_env()?;
    let ctx = ros::context(&config)?;
    let writer = writer::<T>(&ctx, fq_topic, qos)?;

    let interrupted = interrupt_flag();
    let timeout = saturating_secs(args.timeout);
    let latched = qos.durability == ros2_client::qos::Durability::TransientLocal;
    let wait_for = args.wait_subscribers.unwrap_or(default_wait(latched, total.is_none()));
    if wait_for > 0 {
        let start = Instant::now();
        let mut n: usize = 0;
        loop {
            n = matched_subscriptions(&writer, n);
            if n >= wait_for {
                break;
            }
            if start.elapsed() >= timeout {
                eprintln!(
                    "warning: {n} of {wait_for} matching subscription(s) on {fq_topic} ({}) within {:.1} s, so \
                     nothing was published: is the node running in this ROS_DOMAIN_ID ({}) and namespace? \
                     (-w 0 publishes without waiting, --timeout waits longer)",
                    T::TYPE_NAME,
                    args.timeout,
                    config.domain_id
                );
                bail!("no matching subscription on {fq_topic}");
            }
            if interrupted.load(std::sync::atomic::Ordering::Relaxed) {
                bail!("interrupted while waiting for subscribers");
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        // We see the match when the subscription's announcement reaches us; the subscriber sees it when ours
        // reaches it, which may be a moment later. A volatile reader drops samples from a writer it has not
        // matched yet (they are history to it), so give its side of the handshake time to complete.
        std::thread::sleep(MATCH_SETTLE);
    }

    let period = args.rate.map(period_of);
    let start = Instant::now();
    let mut sent: u64 = 0;
    while total.is_none_or(|t| sent < t) {
        // A closed stdout (`pub … | head`) ends the publishing as Ctrl-C does.
        if interrupted.load(std::sync::atomic::Ordering::Relaxed) || super::common::stdout_closed() {
            break;
        }
        if let Some(p) = period {
            let due = start + crate::model::time::scaled(p, sent as f64);
            let now = Instant::now();
            if due > now {
                std::thread::sleep(due - now);
            }
        }
        let (origin, value) = &inputs[(sent % inputs.len() as u64) as usize];
        let v = complete(kind, &template, value, sent + 1, &now_time());
        let message = T::from_json(&v, "").map_err(|e| anyhow!("{origin}: {e}"))?;
        if !args.quiet {
            crate::outln!("publishing #{} to {fq_topic}: {}", sent + 1, message.to_json())?;
        }
        write_reliably(&writer, message, timeout, &interrupted)
            .with_context(|| format!("publishing message #{} to {fq_topic}", sent + 1))?;
        sent += 1;
    }

    // Reliable delivery: wait until every matched subscription acknowledged everything.
    match writer.wait_for_acknowledgments(timeout) {
        Ok(true) => {}
        Ok(false) => eprintln!(
            "warning: not every subscription on {fq_topic} acknowledged all {sent} messages within {:.1} s",
            args.timeout
        ),
        Err(e) => eprintln!("warning: waiting for acknowledgments on {fq_topic}: {e}"),
    }
    let linger_until = Instant::now() + saturating_secs(args.keep_alive);
    while Instant::now() < linger_until && !interrupted.load(std::sync::atomic::Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(20));
    }
    if !args.quiet {
        eprintln!("published {sent} message(s) to {fq_topic} ({})", T::TYPE_NAME);
    }
    Ok(())
}

/// Largest message `pub` sends, bytes of CDR. RustDDS sends a larger sample in 256-byte fragments, and a
/// reader asks again for at most 256 missing fragments (64 KiB) per round trip, so a sample of many megabytes
/// on a loaded loopback never completes: the subscriber drops it while `pub` would report it published. The
/// largest message the node takes (a BatParams of 4,096 stations, ~100 KB) fits many times over.
pub const MAX_SAMPLE_BYTES: usize = 1024 * 1024;

/// Why `message` (a `kind`) cannot be delivered, if it cannot: larger than DDS carries
/// ([`MAX_SAMPLE_BYTES`]), or over a size bound that the node checks before anything else (strings of
/// [`crate::model::limits::MAX_STRING_BYTES`], profiles of [`crate::model::limits::MAX_STATIONS`] stations),
/// so that it would only be refused. Values the node judges (speeds, physics) are its to reject.
fn refuse_undeliverable<T: RosMessage>(kind: Kind, message: &T) -> Result<(), String> {
    use crate::model::limits::{check_string, MAX_STATIONS};
    let cdr = crate::msgs::encode_cdr(message).map_err(|e| e.to_string())?;
    if cdr.len() > MAX_SAMPLE_BYTES {
        return Err(format!(
            "the message is {} bytes serialized, over the {MAX_SAMPLE_BYTES} bytes DDS carries here",
            cdr.len()
        ));
    }
    let node_refuses = |e: String| format!("{e}: the node refuses it");
    match kind {
        Kind::Swing => {
            let swing: Swing = crate::msgs::decode_cdr(&cdr).map_err(|e| e.to_string())?;
            check_string("header.frame_id", &swing.header.frame_id)
                .and_then(|()| check_string("bat_id", &swing.bat_id))
                .and_then(|()| check_string("ball_id", &swing.ball_id))
                .map_err(node_refuses)
        }
        Kind::BallParams => {
            let ball: BallParams = crate::msgs::decode_cdr(&cdr).map_err(|e| e.to_string())?;
            check_string("header.frame_id", &ball.header.frame_id)
                .and_then(|()| check_string("ball_id", &ball.ball_id))
                .map_err(node_refuses)
        }
        Kind::BatParams => {
            let bat: BatParams = crate::msgs::decode_cdr(&cdr).map_err(|e| e.to_string())?;
            check_string("header.frame_id", &bat.header.frame_id)
                .and_then(|()| check_string("bat_id", &bat.bat_id))
                .and_then(|()| check_string("preset", &bat.preset))
                .map_err(node_refuses)?;
            match bat.station_z.len().max(bat.outer_radius.len()).max(bat.inner_radius.len()) {
                n if n > MAX_STATIONS => {
                    Err(node_refuses(format!("the profile has {n} stations, over the limit of {MAX_STATIONS}")))
                }
                _ => Ok(()),
            }
        }
        _ => Ok(()),
    }
}

/// Matching subscriptions to wait for when `-w` is not given: one, as `ros2 topic pub --once/--times`, except
/// on a latched topic (a late joiner still gets the message) and when one message repeats forever.
fn default_wait(latched: bool, forever: bool) -> usize {
    if latched || forever {
        0
    } else {
        1
    }
}

/// Samples `echo` can queue between DDS and the terminal.
const ECHO_DEPTH: usize = 100_000;

/// How long echo listens before saying that nothing publishes on its topic.
const NO_PUBLISHER_WARNING: Duration = Duration::from_secs(3);

/// The ROS topics on which discovery has seen a writer of `T` (sorted, each once).
fn writers_of<T: RosMessage>(participant: &rustdds::DomainParticipant) -> Vec<String> {
    let dds_type = ros::message_type_name::<T>().dds_msg_type();
    let mut topics: Vec<String> = participant
        .discovered_writers()
        .into_iter()
        .filter(|w| w.publication_topic_data.type_name == dds_type)
        .filter_map(|w| w.publication_topic_data.topic_name.strip_prefix("rt").map(str::to_string))
        .collect();
    topics.sort();
    topics.dedup();
    topics
}

/// The warning when nothing publishes on `fq_topic`, naming the namespaces where its type is published.
fn no_publisher_warning(fq_topic: &str, kind: Kind, published_on: &[String]) -> String {
    let seconds = NO_PUBLISHER_WARNING.as_secs();
    let type_name = kind.type_name();
    let relative = format!("/{}", kind.default_topic().trim_start_matches('/'));
    if published_on.is_empty() {
        return format!(
            "warning: nothing publishes {fq_topic} ({type_name}) after {seconds} s, and no publisher of that \
             type was discovered in this ROS_DOMAIN_ID; still listening"
        );
    }
    let elsewhere: Vec<String> = published_on
        .iter()
        .map(|topic| {
            // The node's topics sit under its namespace; other names say only where they are.
            let namespace = match topic.strip_suffix(&relative).or_else(|| topic.rsplit_once('/').map(|(ns, _)| ns)) {
                Some("") | None => "/",
                Some(ns) => ns,
            };
            format!("{topic} (namespace {namespace}: --ns {namespace})")
        })
        .collect();
    format!(
        "warning: nothing publishes {fq_topic} ({type_name}) after {seconds} s, but that type is published on {}; \
         still listening",
        elsewhere.join(", ")
    )
}

/// Pause between seeing a subscription match and publishing to it (see its use).
const MATCH_SETTLE: Duration = Duration::from_millis(300);

/// Prints what arrives on a topic.
pub fn run_echo(args: EchoArgs) -> anyhow::Result<()> {
    let (identity, resolver) = ros_context(&args.ns, &args.ros_args, "sweetspot_echo")?;
    let msg_type = match (&args.msg_type, &args.positional_type) {
        (Some(flag), Some(pos)) if Kind::from_word(flag) != Kind::from_word(pos) => {
            bail!("the TYPE argument {pos:?} and --type {flag:?} disagree")
        }
        (flag, pos) => flag.clone().or_else(|| pos.clone()),
    };
    let (fq_topic, kind) = resolve_target(&args.topic, &msg_type, &identity, &resolver)?;
    // --timeout is checked by its value parser (model::time): inf waits for ever.
    with_type!(kind, T => echo::<T>(kind, &args, &fq_topic))
}

fn echo<T: RosMessage>(kind: Kind, args: &EchoArgs, fq_topic: &str) -> anyhow::Result<()> {
    let config = DdsConfig::from_env()?;
    let ctx = ros::context(&config)?;
    // A deep reader history: a KEEP_LAST reader cache silently drops its oldest untaken samples, and printing
    // is slower than DDS, so a burst of thousands of messages must be able to queue here. (History depth does
    // not affect QoS matching.)
    let mut qos = kind.qos().history(ros2_client::qos::History::KeepLast { depth: ECHO_DEPTH });
    if args.no_latched {
        qos = qos.durability(ros2_client::qos::Durability::Volatile);
    }
    let qos = args.qos.apply(qos)?;
    let count = if args.once { Some(1) } else { args.count };
    let reader = reader::<T>(&ctx, fq_topic, &qos)?;
    if !args.json {
        eprintln!(
            "listening on {fq_topic} ({}, domain {}, discovery {})",
            T::TYPE_NAME,
            config.domain_id,
            config.range
        );
    }

    let deadline = args.timeout.map(|t| tokio::time::Instant::now() + saturating_secs(t));
    // Take samples as soon as they arrive and print on another thread: a RustDDS reader loses the untaken
    // samples of a writer whose participant leaves, so a slow terminal must not leave them sitting in DDS.
    let (to_printer, printed) = std::sync::mpsc::channel::<T>();
    let json_output = args.json;
    let printer = std::thread::spawn(move || -> std::io::Result<()> {
        let stdout = std::io::stdout();
        for message in printed {
            let json = message.to_json();
            let mut out = stdout.lock();
            if json_output {
                writeln!(out, "{json}")?;
            } else {
                writeln!(out, "{}---", crate::msgs::json::to_readable_named(&json, kind.constant_names()))?;
            }
            out.flush()?;
        }
        Ok(())
    });
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build()?;
    let taken = runtime.block_on(async {
        use futures::StreamExt;
        let samples = reader.as_async_stream();
        tokio::pin!(samples);
        let interrupted = shutdown_signal();
        tokio::pin!(interrupted);
        let mut received: u64 = 0;
        let quiet_check = tokio::time::sleep(NO_PUBLISHER_WARNING);
        tokio::pin!(quiet_check);
        let mut checked = false;
        loop {
            if count.is_some_and(|c| received >= c) {
                return Ok(());
            }
            let sleep = async {
                match deadline {
                    Some(d) => tokio::time::sleep_until(d).await,
                    None => std::future::pending::<()>().await,
                }
            };
            tokio::select! {
                _ = &mut interrupted => return Ok(()),
                _ = &mut quiet_check, if !checked => {
                    checked = true;
                    if received == 0 {
                        let published_on = writers_of::<T>(&ctx.domain_participant());
                        if !published_on.iter().any(|t| t == fq_topic) {
                            eprintln!("{}", no_publisher_warning(fq_topic, kind, &published_on));
                        }
                    }
                }
                _ = sleep => {
                    return match count {
                        Some(c) => Err(anyhow!("timed out on {fq_topic} after {received} of {c} messages")),
                        None => Ok(()),
                    };
                }
                item = samples.next() => match item {
                    Some(Ok(sample)) => {
                        if to_printer.send(sample.into_value()).is_err() {
                            return Ok(()); // the printer stopped (stdout closed)
                        }
                        received += 1;
                    }
                    Some(Err(e)) => eprintln!("warning: dropped an undecodable sample on {fq_topic}: {e}"),
                    None => return Err(anyhow!("the DDS reader on {fq_topic} closed")),
                },
            }
        }
    });
    drop(to_printer);
    let printed = printer.join().map_err(|_| anyhow!("the output thread panicked"))?;
    match printed {
        // A closed pipe (`sweetspot echo … | head`) is a normal way to stop.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
        other => other.context("writing to stdout")?,
    }
    taken
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msgs::json::FromJson;

    #[test]
    fn kinds_from_words_and_topics() {
        assert_eq!(Kind::from_word("bat"), Some(Kind::BatParams));
        assert_eq!(Kind::from_word("Swing"), Some(Kind::Swing));
        assert_eq!(Kind::from_word("sweetspot_msgs/msg/ExitVelocity"), Some(Kind::ExitVelocity));
        assert_eq!(Kind::from_word("sweetspot_msgs/ModalEnergies"), Some(Kind::ModalEnergies));
        assert_eq!(Kind::from_word("diagnostic_msgs/msg/DiagnosticArray"), Some(Kind::Diagnostics));
        assert_eq!(Kind::from_word("/rig3/swing"), None);
        assert_eq!(Kind::from_topic("/rig3/bat/params"), Some(Kind::BatParams));
        assert_eq!(Kind::from_topic("/swing"), Some(Kind::Swing));
        assert_eq!(Kind::from_topic("/diagnostics"), Some(Kind::Diagnostics));
        assert_eq!(Kind::from_topic("/lab/other"), None);
    }

    #[test]
    fn completes_missing_fields() {
        let template = Swing::default().to_json();
        let stamp = Time { sec: 5, nanosec: 6 };
        let v = complete(Kind::Swing, &template, &serde_json::json!({"ball_speed": 40}), 7, &stamp);
        let s = Swing::from_json(&v, "").unwrap();
        assert_eq!((s.swing_id, s.header.stamp.sec, s.ball_speed), (7, 5, 40.0));
        assert!(s.measured_exit_speed.is_nan());
        let v =
            complete(Kind::Swing, &template, &serde_json::json!({"swing_id": 3, "measured_exit_speed": 41}), 7, &stamp);
        let s = Swing::from_json(&v, "").unwrap();
        assert_eq!((s.swing_id, s.measured_exit_speed), (3, 41.0));
    }

    #[test]
    fn csv_cells_become_nested_fields() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.csv");
        std::fs::write(&path, "swing_id,header.frame_id,ball_speed,measured_exit_speed\n1,rig,40.5,\n2,rig,nan,44\n")
            .unwrap();
        let rows = read_csv(&path).unwrap();
        assert_eq!(rows.len(), 2);
        let template = Swing::default().to_json();
        let s1 = Swing::from_json(&complete(Kind::Swing, &template, &rows[0].1, 1, &Time::default()), "").unwrap();
        assert_eq!((s1.swing_id, s1.header.frame_id.as_str(), s1.ball_speed), (1, "rig", 40.5));
        assert!(s1.measured_exit_speed.is_nan());
        let s2 = Swing::from_json(&complete(Kind::Swing, &template, &rows[1].1, 2, &Time::default()), "").unwrap();
        assert!(s2.ball_speed.is_nan());
        assert_eq!(s2.measured_exit_speed, 44.0);
    }

    fn parse_pub(line: &[&str]) -> PubArgs {
        use clap::Parser;
        let argv = std::iter::once("sweetspot").chain(std::iter::once("pub")).chain(line.iter().copied());
        match crate::cli::Cli::try_parse_from(argv).unwrap().command {
            crate::cli::Command::Pub(args) => args,
            other => panic!("parsed as {other:?}"),
        }
    }

    #[test]
    fn yaml_flow_and_block_values_read_like_json() {
        let want =
            serde_json::json!({"swing_id": 1, "bat_id": "r161", "ball_speed": 40.5, "header": {"frame_id": "cage"}});
        let flow = parse_values("{swing_id: 1, bat_id: r161, ball_speed: 40.5, header: {frame_id: cage}}").unwrap();
        let block = parse_values("swing_id: 1\nbat_id: r161\nball_speed: 40.5\nheader:\n  frame_id: cage\n").unwrap();
        let json =
            parse_values(r#"{"swing_id": 1, "bat_id": "r161", "ball_speed": 40.5, "header": {"frame_id": "cage"}}"#)
                .unwrap();
        assert_eq!((&flow, &block, &json), (&want, &want, &want));
        let s = Swing::from_json(&parse_values("{measured_exit_speed: .nan, ball_speed: .inf}").unwrap(), "").unwrap();
        assert!(s.measured_exit_speed.is_nan() && s.ball_speed == f64::INFINITY);
        assert_eq!(parse_values("[{a: 1}, {a: 2}]").unwrap(), serde_json::json!([{"a": 1}, {"a": 2}]));
        assert_eq!(parse_values(r#"{"swing_id": 18446744073709551615}"#).unwrap()["swing_id"], u64::MAX);
        let e = parse_values("{not json").unwrap_err().to_string();
        assert!(e.contains("not valid JSON or YAML"), "{e}");
    }

    #[test]
    fn the_ros2_topic_pub_forms_parse() {
        let a = parse_pub(&[
            "/swing",
            "sweetspot_msgs/msg/Swing",
            "{bat_id: r161}",
            "-1",
            "-w",
            "2",
            "--namespace",
            "/lab",
        ]);
        assert_eq!(
            split_positionals(&a).unwrap(),
            (Some("sweetspot_msgs/msg/Swing".into()), Some("{bat_id: r161}".into()))
        );
        assert!(a.once);
        assert_eq!((a.wait_subscribers, a.ns.as_deref()), (Some(2), Some("/lab")));
        let a = parse_pub(&["swing", "bat_id: r161", "-r", "5", "-t", "3"]);
        assert_eq!(split_positionals(&a).unwrap(), (None, Some("bat_id: r161".into())));
        assert_eq!((a.rate, a.count), (Some(5.0), Some(3)));
        let a = parse_pub(&["/lab/thing", "Swing", "--count", "2", "--wait-subscribers", "0", "--ns", "/x"]);
        assert_eq!(split_positionals(&a).unwrap(), (Some("Swing".into()), None));
        assert_eq!((a.count, a.wait_subscribers), (Some(2), Some(0)));
        let a = parse_pub(&["/lab/thing", "Swing", "{}", "--type", "ExitVelocity"]);
        assert!(split_positionals(&a).is_err(), "TYPE and --type disagree");
        let a = parse_pub(&[
            "swing",
            "--qos-reliability",
            "best_effort",
            "--qos-durability",
            "transient_local",
            "--qos-depth",
            "7",
        ]);
        let q = a.qos.apply(Kind::Swing.qos()).unwrap();
        assert_eq!(q.reliability, ros2_client::qos::Reliability::BestEffort);
        assert_eq!(q.durability, ros2_client::qos::Durability::TransientLocal);
        assert_eq!(q.history, ros2_client::qos::History::KeepLast { depth: 7 });
        assert_eq!(default_wait(false, false), 1, "ros2 topic pub --once waits for one subscription");
        assert_eq!(default_wait(true, false), 0);
        assert_eq!(default_wait(false, true), 0);
    }

    #[test]
    fn the_quiet_topic_warning_names_the_namespaces_in_use() {
        let w = no_publisher_warning("/exit_velocity", Kind::ExitVelocity, &["/lab/exit_velocity".into()]);
        assert!(w.contains("/lab/exit_velocity (namespace /lab: --ns /lab)"), "{w}");
        let w = no_publisher_warning("/bat/params", Kind::BatParams, &["/rig3/bat/params".into(), "/bat2".into()]);
        assert!(w.contains("namespace /rig3:") && w.contains("/bat2 (namespace /:"), "{w}");
        let w = no_publisher_warning("/exit_velocity", Kind::ExitVelocity, &[]);
        assert!(w.contains("no publisher of that type"), "{w}");
    }
}
