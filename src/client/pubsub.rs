//! Publishing and echoing: what `ros2 topic pub` / `ros2 topic echo` do for sweetspot's topics, without a ROS
//! installation.
//!
//! Both honour `ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE` / `ROS_LOCALHOST_ONLY` and
//! `--ros-args -r __ns:=/rig3 -r from:=to` (see [`crate::ros`]).

use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context as _};
use serde_json::{Map, Value};

use super::kind::{with_type, Kind, QosOverrides, ALL_KINDS};
use super::values::read_inputs;
use super::{bounded_error, quoted};
use crate::model::time::{period_of, saturating_secs};
use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::json::ToJson;
use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use crate::msgs::RosMessage;
use crate::ros::args::{NameResolver, NodeIdentity};
use crate::ros::edge::{matched_subscriptions, reader, write_reliably, writer};
use crate::ros::{self, interrupt_flag, shutdown_signal, DdsConfig, RosArgs};
use rustdds::no_key::DataWriterCdr;

/// What `sweetspot pub` publishes, where and how (its flags, see `sweetspot pub --help`).
#[derive(Debug, Clone, Default)]
pub struct PubOptions {
    /// A message kind or a topic name.
    pub target: String,
    /// The positional after TARGET: a type, or the message when it looks like one.
    pub type_or_message: Option<String>,
    /// The message (YAML or JSON), after a positional type.
    pub message: Option<String>,
    /// `--type`.
    pub msg_type: Option<String>,
    /// `--file`: JSON lines, YAML or CSV.
    pub file: Option<PathBuf>,
    /// Messages per second (none: as fast as they are acknowledged).
    pub rate: Option<f64>,
    /// Messages in total, cycling through the input.
    pub count: Option<u64>,
    /// One message and exit.
    pub once: bool,
    /// Matching subscriptions to wait for before the first message.
    pub wait_subscribers: Option<usize>,
    /// Seconds to wait for subscriptions and for acknowledgments.
    pub timeout: f64,
    /// Seconds to stay up after the last acknowledgment.
    pub keep_alive: f64,
    /// QoS over the topic's own.
    pub qos: QosOverrides,
    /// Namespace for relative topic names.
    pub ns: Option<String>,
    /// Print nothing of what is published.
    pub quiet: bool,
    /// `--ros-args`.
    pub ros_args: Option<Vec<String>>,
}

/// What `sweetspot echo` listens to and how (its flags, see `sweetspot echo --help`).
#[derive(Debug, Clone, Default)]
pub struct EchoOptions {
    /// A topic or a message kind.
    pub topic: String,
    /// The positional TYPE.
    pub positional_type: Option<String>,
    /// `--type`.
    pub msg_type: Option<String>,
    /// One JSON object per line.
    pub json: bool,
    /// Exit after this many messages.
    pub count: Option<u64>,
    /// Exit after the first message.
    pub once: bool,
    /// Exit after this many seconds.
    pub timeout: Option<f64>,
    /// Subscribe volatile even on latched topics.
    pub no_latched: bool,
    /// QoS over the topic's own.
    pub qos: QosOverrides,
    /// Namespace for relative topic names.
    pub ns: Option<String>,
    /// `--ros-args`.
    pub ros_args: Option<Vec<String>>,
}

/// The tool's node identity (`__ns` over `--ns` over `/`; `__node` over `default_name`) and its topic-name
/// resolver, from the same `--ros-args` parser the node uses.
fn ros_context(
    ns: &Option<String>,
    ros_args: &Option<Vec<String>>,
    default_name: &str,
) -> anyhow::Result<(NodeIdentity, NameResolver)> {
    let parsed = RosArgs::parse(ros_args.as_deref().unwrap_or_default()).map_err(bounded_error)?;
    let namespace = match ns {
        Some(n) => ros::names::normalize_namespace(n).map_err(bounded_error)?,
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
                "unknown message type {:?}; known: {}",
                quoted(t),
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
    let fq = resolver.resolve(&ros::resolve_topic(&topic, &identity.namespace, &identity.name).map_err(bounded_error)?);
    let kind = match kind.or_else(|| Kind::from_topic(&fq)) {
        Some(k) => k,
        None => {
            bail!("cannot tell the message type of topic {}; pass --type (e.g. --type Swing)", quoted(&fq))
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

/// Whether a positional argument after TARGET is a message (YAML/JSON) rather than a type name: type names
/// (`Swing`, `sweetspot_msgs/msg/Swing`) have no braces, brackets, colons or line breaks.
fn looks_like_values(text: &str) -> bool {
    let t = text.trim();
    t.is_empty() || t.starts_with(['{', '[', '-', '"', '\'']) || t.contains([':', '\n'])
}

/// The type and the message from `TARGET [TYPE] [VALUES]` and `--type` (which must agree with TYPE).
pub fn split_positionals(args: &PubOptions) -> anyhow::Result<(Option<String>, Option<String>)> {
    let (positional_type, message) = match (&args.type_or_message, &args.message) {
        (Some(t), Some(m)) => (Some(t.clone()), Some(m.clone())),
        (Some(x), None) if looks_like_values(x) => (None, Some(x.clone())),
        (Some(t), None) => (Some(t.clone()), None),
        (None, m) => (None, m.clone()),
    };
    let msg_type = match (&args.msg_type, positional_type) {
        (Some(flag), Some(pos)) if Kind::from_word(flag) != Kind::from_word(&pos) => {
            bail!("the TYPE argument {:?} and --type {:?} disagree", quoted(&pos), quoted(flag))
        }
        (Some(flag), _) => Some(flag.clone()),
        (None, pos) => pos,
    };
    Ok((msg_type, message))
}

/// Publishes messages.
pub fn publish(args: PubOptions) -> anyhow::Result<()> {
    let (identity, resolver) = ros_context(&args.ns, &args.ros_args, "sweetspot_pub")?;
    let (msg_type, message) = split_positionals(&args)?;
    let (fq_topic, kind) = resolve_target(&args.target, &msg_type, &identity, &resolver)?;
    // --rate, --timeout and --keep-alive are checked by their value parsers (model::time): inf waits for ever.
    let inputs = read_inputs(message.as_deref(), args.file.as_deref())?;
    if inputs.is_empty() {
        bail!("no messages to publish");
    }
    let qos = args.qos.apply(kind.qos())?;
    with_type!(kind, T => publish_all::<T>(kind, &args, &qos, &fq_topic, &inputs))
}

fn publish_all<T: RosMessage>(
    kind: Kind,
    args: &PubOptions,
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
        wait_for_subscriptions(&writer, wait_for, fq_topic, args.timeout, config.domain_id, &interrupted)?;
    }

    let period = args.rate.map(period_of);
    let start = Instant::now();
    let mut sent: u64 = 0;
    while total.is_none_or(|t| sent < t) {
        // A closed stdout (`pub … | head`) ends the publishing as Ctrl-C does.
        if interrupted.load(std::sync::atomic::Ordering::Relaxed) || crate::report::stdout::closed() {
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

/// Waits until `wait_for` subscriptions on `fq_topic` matched `writer` (at most `timeout_secs`), then a moment
/// for their side of the handshake; an error (with a warning saying why) when too few appear in time.
fn wait_for_subscriptions<T: RosMessage>(
    writer: &DataWriterCdr<T>,
    wait_for: usize,
    fq_topic: &str,
    timeout_secs: f64,
    domain_id: u16,
    interrupted: &std::sync::atomic::AtomicBool,
) -> anyhow::Result<()> {
    let timeout = saturating_secs(timeout_secs);
    let start = Instant::now();
    let mut n: usize = 0;
    loop {
        n = matched_subscriptions(writer, n);
        if n >= wait_for {
            break;
        }
        if start.elapsed() >= timeout {
            eprintln!(
                "warning: {n} of {wait_for} matching subscription(s) on {fq_topic} ({}) within {:.1} s, so \
                 nothing was published: is the node running in this ROS_DOMAIN_ID ({}) and namespace? \
                 (-w 0 publishes without waiting, --timeout waits longer)",
                T::TYPE_NAME,
                timeout_secs,
                domain_id
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
pub fn default_wait(latched: bool, forever: bool) -> usize {
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
pub fn echo(args: EchoOptions) -> anyhow::Result<()> {
    let (identity, resolver) = ros_context(&args.ns, &args.ros_args, "sweetspot_echo")?;
    let msg_type = match (&args.msg_type, &args.positional_type) {
        (Some(flag), Some(pos)) if Kind::from_word(flag) != Kind::from_word(pos) => {
            bail!("the TYPE argument {:?} and --type {:?} disagree", quoted(pos), quoted(flag))
        }
        (flag, pos) => flag.clone().or_else(|| pos.clone()),
    };
    let (fq_topic, kind) = resolve_target(&args.topic, &msg_type, &identity, &resolver)?;
    // --timeout is checked by its value parser (model::time): inf waits for ever.
    with_type!(kind, T => echo_typed::<T>(kind, &args, &fq_topic))
}

/// The QoS `echo` subscribes with: the topic's own, a deep history, `--no-latched` and the overrides applied.
fn echo_qos(kind: Kind, args: &EchoOptions) -> anyhow::Result<ros2_client::QosProfile> {
    // A deep reader history: a KEEP_LAST reader cache silently drops its oldest untaken samples, and printing
    // is slower than DDS, so a burst of thousands of messages must be able to queue here. (History depth does
    // not affect QoS matching.)
    let mut qos = kind.qos().history(ros2_client::qos::History::KeepLast { depth: ECHO_DEPTH });
    if args.no_latched {
        qos = qos.durability(ros2_client::qos::Durability::Volatile);
    }
    args.qos.apply(qos)
}

/// A thread printing each message sent to it (as JSON lines, or readable with a `---` after each).
fn spawn_printer<T: RosMessage>(
    kind: Kind,
    json_output: bool,
) -> (std::sync::mpsc::Sender<T>, std::thread::JoinHandle<std::io::Result<()>>) {
    let (to_printer, printed) = std::sync::mpsc::channel::<T>();
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
    (to_printer, printer)
}

fn echo_typed<T: RosMessage>(kind: Kind, args: &EchoOptions, fq_topic: &str) -> anyhow::Result<()> {
    let config = DdsConfig::from_env()?;
    let ctx = ros::context(&config)?;
    let qos = echo_qos(kind, args)?;
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
    let (to_printer, printer) = spawn_printer::<T>(kind, args.json);
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
    fn the_quiet_topic_warning_names_the_namespaces_in_use() {
        let w = no_publisher_warning("/exit_velocity", Kind::ExitVelocity, &["/lab/exit_velocity".into()]);
        assert!(w.contains("/lab/exit_velocity (namespace /lab: --ns /lab)"), "{w}");
        let w = no_publisher_warning("/bat/params", Kind::BatParams, &["/rig3/bat/params".into(), "/bat2".into()]);
        assert!(w.contains("namespace /rig3:") && w.contains("/bat2 (namespace /:"), "{w}");
        let w = no_publisher_warning("/exit_velocity", Kind::ExitVelocity, &[]);
        assert!(w.contains("no publisher of that type"), "{w}");
    }
}
