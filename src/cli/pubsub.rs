//! `sweetspot pub` and `sweetspot echo`: what `ros2 topic pub` / `ros2 topic echo` do for sweetspot's topics,
//! without a ROS installation.
//!
//! Both honour `ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE` / `ROS_LOCALHOST_ONLY` and
//! `--ros-args -r __ns:=/rig3 -r from:=to` (see [`crate::ros`]).

use std::io::{BufRead, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context as _};
use serde_json::{Map, Value};

use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::diagnostic_msgs::msg::DiagnosticArray;
use crate::msgs::json::ToJson;
use crate::msgs::rcl_interfaces::msg::Log;
use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use crate::msgs::RosMessage;
use crate::ros::args::{NameResolver, NodeIdentity};
use crate::ros::edge::{matched_subscriptions, reader, write_reliably, writer};
use crate::ros::{self, interrupt_flag, shutdown_signal, topics, DdsConfig, RosArgs};

/// Arguments of `sweetspot pub`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  sweetspot pub bat '{\"bat_id\": \"r161\", \"preset\": \"r161\"}' --keep-alive 5
  sweetspot pub swing '{\"bat_id\": \"r161\", \"ball_speed\": 40, \"bat_cm_speed\": 20, \"bat_angular_speed\": 50, \"impact_z\": 0.7}'
  sweetspot pub swing --file swings.csv --rate 100 --wait-subscribers 1
  sweetspot pub /lab/swing --type Swing --file swings.jsonl --ros-args -r __ns:=/rig3

Fields left out keep their defaults; header.stamp defaults to the publish time, a Swing's swing_id to 1, 2, 3…
and its measured_exit_speed to NaN (not measured). Floats accept null/\"nan\" for NaN.")]
pub struct PubArgs {
    /// What to publish: a message kind (bat, ball, swing, or a type such as BatParams or
    /// sweetspot_msgs/msg/Swing) on its default topic, or a topic name (relative names are resolved in the
    /// namespace).
    pub target: String,
    /// The message as a JSON object (or a JSON array of objects).
    pub message: Option<String>,
    /// Message type when TARGET is a topic whose type cannot be told from its name.
    #[arg(long = "type", value_name = "TYPE")]
    pub msg_type: Option<String>,
    /// Read messages from a file: JSON lines (one object per line; `-` = stdin) or CSV (`.csv`, one column per
    /// field, nested fields as `header.frame_id`, arrays as `[1,2]` or `1;2`).
    #[arg(long, value_name = "PATH")]
    pub file: Option<PathBuf>,
    /// Publish at this rate (messages per second); without it messages go out as fast as they are acknowledged.
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// Publish this many messages in total, cycling through the input (default: each input message once, or
    /// forever when a single message is repeated with --rate).
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
    /// Before publishing, wait until this many subscriptions on the topic have matched this publisher.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub wait_subscribers: usize,
    /// Seconds to wait for --wait-subscribers, and for subscribers to acknowledge everything at the end.
    #[arg(long, value_name = "SECS", default_value_t = 10.0)]
    pub timeout: f64,
    /// Stay up this many seconds after every subscription acknowledged the last message: readers need a moment
    /// to take what they acknowledged (a RustDDS reader drops the untaken samples of a writer whose participant
    /// has left), and late joiners get latched params only while we are up.
    #[arg(long, value_name = "SECS", default_value_t = 0.5)]
    pub keep_alive: f64,
    /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
    #[arg(long, value_name = "NS")]
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
  sweetspot echo /rig3/modal_energies --json --count 10 --timeout 30
  sweetspot echo /diagnostics")]
pub struct EchoArgs {
    /// Topic to print (relative names are resolved in the namespace), or a message kind (bat, ball, swing,
    /// exit_velocity, modal_energies, sweet_spot, diagnostics, rosout) for its default topic.
    pub topic: String,
    /// Message type when the topic's type cannot be told from its name.
    #[arg(long = "type", value_name = "TYPE")]
    pub msg_type: Option<String>,
    /// One JSON object per line (NaN as null) instead of the readable form.
    #[arg(long)]
    pub json: bool,
    /// Exit after this many messages (exit status 1 if --timeout ends the wait first).
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
    /// Exit after this many seconds.
    #[arg(long, value_name = "SECS")]
    pub timeout: Option<f64>,
    /// Subscribe volatile even on latched topics (params, sweet_spot): only messages published from now on.
    #[arg(long)]
    pub no_latched: bool,
    /// Namespace for relative topic names (same as `--ros-args -r __ns:=NS`).
    #[arg(long, value_name = "NS")]
    pub ns: Option<String>,
    /// ROS arguments (`-r __ns:=/rig3`, `-r from:=to`), as for any ROS 2 node; must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS")]
    pub ros_args: Option<Vec<String>>,
}

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
}

const ALL_KINDS: [Kind; 8] = [
    Kind::BatParams,
    Kind::BallParams,
    Kind::Swing,
    Kind::ExitVelocity,
    Kind::ModalEnergies,
    Kind::SweetSpot,
    Kind::Diagnostics,
    Kind::Rosout,
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
    let namespace = match (&parsed.namespace, ns) {
        (Some(n), _) => n.clone(),
        (None, Some(n)) => ros::names::normalize_namespace(n)?,
        (None, None) => "/".to_string(),
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
fn read_inputs(args: &PubArgs) -> anyhow::Result<Vec<(String, Value)>> {
    let mut out = Vec::new();
    if let Some(text) = &args.message {
        let v: Value = serde_json::from_str(text).context("the message is not valid JSON")?;
        match v {
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
        if is_csv {
            out.extend(read_csv(path)?);
        } else {
            out.extend(read_json_lines(path)?);
        }
    }
    if args.message.is_none() && args.file.is_none() {
        // Like `ros2 topic pub` with no values: a message with every default.
        out.push(("defaults".into(), Value::Object(Map::new())));
    }
    Ok(out)
}

fn read_json_lines(path: &Path) -> anyhow::Result<Vec<(String, Value)>> {
    let reader: Box<dyn BufRead> = if path == Path::new("-") {
        Box::new(std::io::BufReader::new(std::io::stdin()))
    } else {
        Box::new(std::io::BufReader::new(
            std::fs::File::open(path).with_context(|| format!("cannot open {}", path.display()))?,
        ))
    };
    let mut out = Vec::new();
    let mut lines = Vec::new();
    for line in reader.lines() {
        lines.push(line.with_context(|| format!("cannot read {}", path.display()))?);
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
        .from_path(path)
        .with_context(|| format!("cannot open {}", path.display()))?;
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
    let (fq_topic, kind) = resolve_target(&args.target, &args.msg_type, &identity, &resolver)?;
    if let Some(rate) = args.rate {
        if !(rate.is_finite() && rate > 0.0) {
            bail!("--rate must be a positive number of messages per second, got {rate}");
        }
    }
    let non_negative = |v: f64| v.is_finite() && v >= 0.0;
    if !non_negative(args.timeout) || !non_negative(args.keep_alive) {
        bail!("--timeout and --keep-alive must be non-negative seconds");
    }
    let inputs = read_inputs(&args)?;
    if inputs.is_empty() {
        bail!("no messages to publish");
    }
    with_type!(kind, T => publish_all::<T>(kind, &args, &fq_topic, &inputs))
}

fn publish_all<T: RosMessage>(
    kind: Kind,
    args: &PubArgs,
    fq_topic: &str,
    inputs: &[(String, Value)],
) -> anyhow::Result<()> {
    // Check every input before touching the network, so a typo in line 900 fails fast.
    let template = T::default().to_json();
    let zero = Time::default();
    for (i, (origin, value)) in inputs.iter().enumerate() {
        let v = complete(kind, &template, value, i as u64 + 1, &zero);
        T::from_json(&v, "").map_err(|e| anyhow!("{origin}: {e}"))?;
    }
    let total = match (args.count, args.rate, inputs.len()) {
        (Some(n), _, _) => Some(n),
        (None, Some(_), 1) => None, // one message repeated at a rate: until interrupted
        (None, _, n) => Some(n as u64),
    };

    let config = DdsConfig::from_env()?;
    let ctx = ros::context(&config)?;
    let writer = writer::<T>(&ctx, fq_topic, &kind.qos())?;

    let interrupted = interrupt_flag();
    let timeout = Duration::from_secs_f64(args.timeout);
    if args.wait_subscribers > 0 {
        let start = Instant::now();
        let mut n: usize = 0;
        loop {
            n = matched_subscriptions(&writer, n);
            if n >= args.wait_subscribers {
                break;
            }
            if start.elapsed() >= timeout {
                bail!(
                    "only {n} of {} subscriptions on {fq_topic} appeared within {:.1} s",
                    args.wait_subscribers,
                    args.timeout
                );
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

    let period = args.rate.map(|r| Duration::from_secs_f64(1.0 / r));
    let start = Instant::now();
    let mut sent: u64 = 0;
    let stdout = std::io::stdout();
    while total.is_none_or(|t| sent < t) {
        if interrupted.load(std::sync::atomic::Ordering::Relaxed) {
            break;
        }
        if let Some(p) = period {
            let due = start + p.mul_f64(sent as f64);
            let now = Instant::now();
            if due > now {
                std::thread::sleep(due - now);
            }
        }
        let (origin, value) = &inputs[(sent % inputs.len() as u64) as usize];
        let v = complete(kind, &template, value, sent + 1, &now_time());
        let message = T::from_json(&v, "").map_err(|e| anyhow!("{origin}: {e}"))?;
        if !args.quiet {
            let mut out = stdout.lock();
            let _ = writeln!(out, "publishing #{} to {fq_topic}: {}", sent + 1, message.to_json());
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
    let linger_until = Instant::now() + Duration::from_secs_f64(args.keep_alive);
    while Instant::now() < linger_until && !interrupted.load(std::sync::atomic::Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(20));
    }
    if !args.quiet {
        eprintln!("published {sent} message(s) to {fq_topic} ({})", T::TYPE_NAME);
    }
    Ok(())
}

/// Samples `echo` can queue between DDS and the terminal.
const ECHO_DEPTH: usize = 100_000;

/// Pause between seeing a subscription match and publishing to it (see its use).
const MATCH_SETTLE: Duration = Duration::from_millis(300);

/// Prints what arrives on a topic.
pub fn run_echo(args: EchoArgs) -> anyhow::Result<()> {
    let (identity, resolver) = ros_context(&args.ns, &args.ros_args, "sweetspot_echo")?;
    let (fq_topic, kind) = resolve_target(&args.topic, &args.msg_type, &identity, &resolver)?;
    if let Some(t) = args.timeout {
        if !(t.is_finite() && t >= 0.0) {
            bail!("--timeout must be non-negative seconds, got {t}");
        }
    }
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
    let reader = reader::<T>(&ctx, fq_topic, &qos)?;
    if !args.json {
        eprintln!(
            "listening on {fq_topic} ({}, domain {}, discovery {})",
            T::TYPE_NAME,
            config.domain_id,
            config.range
        );
    }

    let deadline = args.timeout.map(|t| tokio::time::Instant::now() + Duration::from_secs_f64(t));
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
                writeln!(out, "{}---", crate::msgs::json::to_readable(&json))?;
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
        loop {
            if args.count.is_some_and(|c| received >= c) {
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
                _ = sleep => {
                    return match args.count {
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
}
