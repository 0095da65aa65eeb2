//! `bag record`: a recorder for the whole rig, like `ros2 bag record`. It watches DDS discovery for
//! publications, subscribes to the ROS topics it is asked for (all, a list, a regular expression) and writes
//! every sample into a rosbag2 MCAP bag through the node's own [`Recorder`], so the bag is exactly what the
//! node would have written.
//!
//! Samples are kept as they travelled ([`RawCdr`]), never decoded: a type sweetspot generates from `msgs/`
//! gets its `ros2msg` schema; any other type is recorded all the same, with an empty schema (Jazzy publishes
//! type descriptions only through a service, which RustDDS does not query), and the user is told so. It sits
//! beside [`crate::play`], above both [`crate::bag`] and [`crate::ros`].

pub mod console;
pub mod qos_overrides;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use ros2_client::qos::{Durability, History, Reliability, WhenFull};
use ros2_client::QosProfile;
use rustdds::no_key::SimpleDataReader;

use crate::bag::{BagError, RecordedQos, Recorder, RecorderConfig, StorageOptions, TopicId, TopicInfo};
use crate::ros::edge::{raw_reader, RawCdr, RawCdrAdapter};
use crate::ros::RosError;
pub use qos_overrides::{QosOverride, QosOverrides};

/// What went wrong while recording.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The bag could not be created or written.
    #[error(transparent)]
    Bag(#[from] BagError),
    /// DDS could not be set up.
    #[error(transparent)]
    Ros(#[from] RosError),
}

/// Which topics to record: any that `all` admits, is listed in `topics`, or matches `regex`.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    /// Every ROS topic (hidden ones only with `include_hidden`).
    pub all: bool,
    /// These fully-qualified topics.
    pub topics: Vec<String>,
    /// Topics whose fully-qualified name matches this (hidden ones only with `include_hidden`).
    pub regex: Option<regex::Regex>,
    /// Also record hidden topics (a name token starting with `_`) with `all` or `regex`.
    pub include_hidden: bool,
}

impl Selection {
    /// Whether `topic` is to be recorded, or why not.
    fn admits(&self, topic: &str) -> Result<(), String> {
        if self.topics.iter().any(|t| t == topic) {
            return Ok(());
        }
        let by_pattern = self.all || self.regex.as_ref().is_some_and(|r| r.is_match(topic));
        if !by_pattern {
            return Err("not selected".to_string());
        }
        if !self.include_hidden && topic.split('/').any(|token| token.starts_with('_')) {
            return Err("a hidden topic (pass --include-hidden-topics to record it)".to_string());
        }
        Ok(())
    }
}

/// How and where to record.
#[derive(Debug, Clone)]
pub struct RecordOptions {
    /// The bag directory to create (must not exist).
    pub output: PathBuf,
    /// Which topics.
    pub selection: Selection,
    /// Chunking and compression (a rosbag2 MCAP storage preset).
    pub storage: StorageOptions,
    /// Start a new file after this many bytes.
    pub max_bag_size: Option<u64>,
    /// Start a new file after this much recorded time.
    pub max_bag_duration: Option<Duration>,
    /// Subscription QoS per topic, over the one adapted to the publishers.
    pub qos_overrides: QosOverrides,
    /// How often discovery is looked at for new topics.
    pub polling_interval: Duration,
}

impl RecordOptions {
    /// All topics into `output`, rosbag2's defaults otherwise (no splitting, the `none` storage preset,
    /// discovery every 100 ms).
    pub fn new(output: impl Into<PathBuf>) -> RecordOptions {
        RecordOptions {
            output: output.into(),
            selection: Selection { all: true, ..Selection::default() },
            storage: crate::bag::StoragePreset::None.storage_options(),
            max_bag_size: None,
            max_bag_duration: None,
            qos_overrides: QosOverrides::default(),
            polling_interval: Duration::from_millis(100),
        }
    }
}

/// Something the recorder wants the user to know.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RecordEvent {
    /// The bag directory was created: recording has started.
    Started { dir: PathBuf },
    /// Recording `topic` from now on; `schema` is false for a type sweetspot has no definition of.
    Subscribed { topic: String, type_name: String, schema: bool },
    /// Not recording `topic` (a DDS topic name for what is not a ROS topic), and why.
    Skipped { topic: String, reason: String },
}

/// What a recording wrote.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RecordStats {
    /// Messages recorded per topic (every subscribed topic, zero included).
    pub per_topic: BTreeMap<String, u64>,
    /// Messages the bag writer could not keep up with.
    pub dropped: u64,
    /// Messages taken from DDS more than [`REORDER_WINDOW`] after they were received, later than a message
    /// already written with a later receive time: written with that later log time, so that the bag stays in
    /// log-time order (0 unless the recorder stalled).
    pub late: u64,
}

/// How long a received message is held before it is written, so that the messages of all subscriptions go
/// into the bag in receive-time order: the recorder takes each subscription's samples in turn, so without
/// it an answer received after its swing could be written before it (and log times would go backwards in
/// file order, which `rosbags` refuses in an unchunked bag).
pub const REORDER_WINDOW: Duration = Duration::from_millis(100);
/// Messages held for reordering at most: beyond it the oldest are written at once (a burst bigger than a
/// window's worth then costs order only if one subscription lags by more than this many messages).
pub const REORDER_CAPACITY: usize = 65_536;

/// One received message waiting in the reorder window, ordered by (log time, arrival).
struct Held {
    log_time: u64,
    arrival: u64,
    publish_time: u64,
    id: TopicId,
    cdr: Vec<u8>,
}

impl PartialEq for Held {
    fn eq(&self, other: &Self) -> bool {
        (self.log_time, self.arrival) == (other.log_time, other.arrival)
    }
}
impl Eq for Held {}
impl PartialOrd for Held {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Held {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        (self.log_time, self.arrival).cmp(&(other.log_time, other.arrival))
    }
}

/// The reorder window: messages go in in any order and come out in log-time order once they are older than
/// the window (or the window is full, or at the end); a message that comes out earlier than one already out
/// takes that one's log time, so what comes out never goes backwards.
#[derive(Default)]
pub struct Reorder {
    heap: std::collections::BinaryHeap<std::cmp::Reverse<Held>>,
    arrivals: u64,
    last_out: u64,
    late: u64,
}

impl Reorder {
    /// Holds one message (log time = its receive time, ns since the Unix epoch).
    pub fn push(&mut self, id: TopicId, cdr: Vec<u8>, log_time: u64, publish_time: u64) {
        self.arrivals += 1;
        let arrival = self.arrivals;
        self.heap.push(std::cmp::Reverse(Held { log_time, arrival, publish_time, id, cdr }));
    }

    /// Hands out, in log-time order, every message received at or before `until_ns`, and the oldest ones
    /// beyond [`REORDER_CAPACITY`]: `out(id, cdr, log_time, publish_time)`.
    pub fn release(&mut self, until_ns: u64, mut out: impl FnMut(TopicId, Vec<u8>, u64, u64)) {
        while let Some(std::cmp::Reverse(first)) = self.heap.peek() {
            if first.log_time > until_ns && self.heap.len() <= REORDER_CAPACITY {
                break;
            }
            let Some(std::cmp::Reverse(held)) = self.heap.pop() else { break };
            let log_time = if held.log_time < self.last_out {
                self.late += 1;
                self.last_out
            } else {
                held.log_time
            };
            self.last_out = log_time;
            out(held.id, held.cdr, log_time, held.publish_time);
        }
    }

    /// Messages that came out with a raised log time so far.
    pub fn late(&self) -> u64 {
        self.late
    }

    /// Messages held.
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    /// Whether nothing is held.
    pub fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }
}

/// The ROS type name of a DDS type name: `pkg::msg::dds_::Type_` → `pkg/msg/Type`.
pub fn ros_type_name(dds_type_name: &str) -> Option<String> {
    let parts: Vec<&str> = dds_type_name.split("::").collect();
    match parts.as_slice() {
        [pkg, kind, "dds_", name] if !pkg.is_empty() && !kind.is_empty() => {
            let name = name.strip_suffix('_').filter(|n| !n.is_empty())?;
            Some(format!("{pkg}/{kind}/{name}"))
        }
        _ => None,
    }
}

/// The ROS topic of a DDS topic name, or why it is not one to record: `rt/lab/swing` → `/lab/swing`.
pub fn ros_topic_name(dds_topic: &str) -> Result<String, String> {
    if let Some(rest) = dds_topic.strip_prefix("rt/") {
        return Ok(format!("/{rest}"));
    }
    if dds_topic.starts_with("rq/") || dds_topic.starts_with("rr/") {
        return Err("a service's request or reply topic (services are not recorded)".to_string());
    }
    Err("not a ROS topic (no rt/ prefix)".to_string())
}

/// Nanoseconds since the Unix epoch of an RTPS timestamp.
fn unix_ns(t: rustdds::Timestamp) -> u64 {
    let ticks = t.to_ticks();
    let (seconds, fraction) = (ticks >> 32, ticks & 0xFFFF_FFFF);
    seconds * 1_000_000_000 + ((fraction * 1_000_000_000) >> 32)
}

/// The publishers of one topic as discovery reports them.
#[derive(Debug, Default)]
struct Publications {
    type_names: Vec<String>,
    all_reliable: bool,
    all_transient_local: bool,
    count: usize,
}

fn discovered_publications(ctx: &ros2_client::Context) -> BTreeMap<String, Publications> {
    use rustdds::policy;
    let mut out: BTreeMap<String, Publications> = BTreeMap::new();
    for writer in ctx.domain_participant().discovered_writers() {
        let data = &writer.publication_topic_data;
        let entry = out.entry(data.topic_name.clone()).or_insert_with(|| Publications {
            all_reliable: true,
            all_transient_local: true,
            ..Default::default()
        });
        if !entry.type_names.contains(&data.type_name) {
            entry.type_names.push(data.type_name.clone());
        }
        // DDS defaults when not announced: writers are reliable, volatile.
        entry.all_reliable &= !matches!(data.reliability, Some(policy::Reliability::BestEffort));
        entry.all_transient_local &= matches!(data.durability, Some(policy::Durability::TransientLocal));
        entry.count += 1;
    }
    out
}

/// The subscription QoS rosbag2 would use for these publishers: reliable if every publisher is, transient
/// local if every publisher is (so latched messages are recorded), a deep queue so bursts are not lost.
fn adapted_qos(publications: &Publications) -> QosProfile {
    let reliability = if publications.all_reliable {
        Reliability::Reliable { when_full: WhenFull::DEFAULT }
    } else {
        Reliability::BestEffort
    };
    let durability = if publications.all_transient_local { Durability::TransientLocal } else { Durability::Volatile };
    QosProfile::subscription_default()
        .reliability(reliability)
        .durability(durability)
        .history(History::KeepLast { depth: 1000 })
}

struct Subscribed {
    topic: String,
    id: TopicId,
    reader: SimpleDataReader<RawCdr, RawCdrAdapter>,
    count: u64,
}

/// Records until `stop` is set, then finishes the bag. `on_event` hears of every topic subscribed or skipped
/// (once per topic).
pub fn record(
    options: &RecordOptions,
    stop: &AtomicBool,
    mut on_event: impl FnMut(&RecordEvent),
) -> Result<RecordStats, RecordError> {
    let (ctx, _config) = crate::ros::context_from_env()?;
    let config = RecorderConfig {
        max_file_size: options.max_bag_size,
        max_file_duration: options.max_bag_duration,
        ..RecorderConfig::new(&options.output)
    };
    let recorder = Recorder::start_with(config, options.storage)?;
    on_event(&RecordEvent::Started { dir: options.output.clone() });
    let mut session = Session {
        ctx: &ctx,
        options,
        recorder,
        subscribed: Vec::new(),
        reorder: Reorder::default(),
        decided: std::collections::BTreeSet::new(),
    };
    let mut next_discovery = Instant::now();
    while !stop.load(Ordering::Relaxed) {
        if Instant::now() >= next_discovery {
            next_discovery = Instant::now() + options.polling_interval;
            session.subscribe_to_discovered(&mut on_event)?;
        }
        let took = session.take_available();
        session.release_settled();
        if !took {
            std::thread::sleep(Duration::from_millis(2));
        }
    }
    session.finish()
}

impl Subscribed {
    /// Takes one sample into `reorder`, if there is one; whether there was.
    fn take_one(&mut self, reorder: &mut Reorder) -> rustdds::dds::ReadResult<bool> {
        let Some(sample) = self.reader.try_take_one()? else { return Ok(false) };
        let log_time = unix_ns(sample.receive_instant);
        let publish_time = sample.source_timestamp().map(unix_ns).unwrap_or(log_time);
        let RawCdr(bytes) = sample.into_value();
        reorder.push(self.id, bytes, log_time, publish_time);
        self.count += 1;
        Ok(true)
    }
}

/// A recording under way: the bag, the subscriptions and the messages held for reordering.
struct Session<'a> {
    ctx: &'a ros2_client::Context,
    options: &'a RecordOptions,
    recorder: Recorder,
    subscribed: Vec<Subscribed>,
    reorder: Reorder,
    /// DDS topics already subscribed to or skipped.
    decided: std::collections::BTreeSet<String>,
}

impl Session<'_> {
    /// Subscribes to every topic discovery shows that was not decided on yet and is selected.
    fn subscribe_to_discovered(&mut self, on_event: &mut impl FnMut(&RecordEvent)) -> Result<(), RecordError> {
        for (dds_topic, publications) in discovered_publications(self.ctx) {
            if !self.decided.contains(&dds_topic) {
                self.decide(dds_topic, &publications, on_event)?;
            }
        }
        Ok(())
    }

    /// Subscribes to `dds_topic` if it is a selected ROS topic of one ROS type; else says why not (unless it
    /// is merely not selected).
    fn decide(
        &mut self,
        dds_topic: String,
        publications: &Publications,
        on_event: &mut impl FnMut(&RecordEvent),
    ) -> Result<(), RecordError> {
        let topic = match ros_topic_name(&dds_topic) {
            Ok(topic) => topic,
            Err(reason) => {
                // Only worth a word when the user asked for everything.
                if self.options.selection.all {
                    on_event(&RecordEvent::Skipped { topic: dds_topic.clone(), reason });
                }
                self.decided.insert(dds_topic);
                return Ok(());
            }
        };
        if let Err(reason) = self.options.selection.admits(&topic) {
            if reason != "not selected" {
                on_event(&RecordEvent::Skipped { topic, reason });
            }
            self.decided.insert(dds_topic);
            return Ok(());
        }
        self.decided.insert(dds_topic);
        let dds_type = match publications.type_names.as_slice() {
            [one] => one.clone(),
            several => {
                let reason = format!("published with several types ({})", several.join(", "));
                on_event(&RecordEvent::Skipped { topic, reason });
                return Ok(());
            }
        };
        let Some(type_name) = ros_type_name(&dds_type) else {
            let reason = format!("DDS type {dds_type} is not a ROS message type (pkg::msg::dds_::Type_)");
            on_event(&RecordEvent::Skipped { topic, reason });
            return Ok(());
        };
        self.subscribe(topic, &dds_type, type_name, publications, on_event)
    }

    /// Registers `topic` in the bag and subscribes to it with QoS adapted to its publishers.
    fn subscribe(
        &mut self,
        topic: String,
        dds_type: &str,
        type_name: String,
        publications: &Publications,
        on_event: &mut impl FnMut(&RecordEvent),
    ) -> Result<(), RecordError> {
        let known = crate::msgs::ALL_TYPES.iter().find(|t| t.dds_type_name == dds_type);
        let qos = self.options.qos_overrides.apply(&topic, adapted_qos(publications));
        let reader = raw_reader(self.ctx, &topic, dds_type, &qos)?;
        let info = TopicInfo {
            name: topic.clone(),
            type_name: type_name.clone(),
            schema_text: known.map(|t| t.schema_text.to_string()).unwrap_or_default(),
            // What the publishers offered, as far as discovery tells (it does not carry the depth).
            qos: RecordedQos {
                reliable: publications.all_reliable,
                transient_local: publications.all_transient_local,
                depth: 0,
            },
            // Known types carry the hash build.rs computed; for others it stays empty, as rosbag2
            // writes it when the publisher announced none.
            type_hash: known.map(|t| t.type_hash.to_string()).unwrap_or_default(),
        };
        let id = self.recorder.register_topic(info)?;
        on_event(&RecordEvent::Subscribed { topic: topic.clone(), type_name, schema: known.is_some() });
        self.subscribed.push(Subscribed { topic, id, reader, count: 0 });
        Ok(())
    }

    /// Drains every subscription into the reorder window; whether anything was taken.
    fn take_available(&mut self) -> bool {
        let mut took = false;
        for sub in &mut self.subscribed {
            loop {
                match sub.take_one(&mut self.reorder) {
                    Ok(true) => took = true,
                    Ok(false) => break,
                    Err(e) => {
                        tracing::warn!("{}: {e}", sub.topic);
                        break;
                    }
                }
            }
        }
        took
    }

    /// Writes what has been held for the reorder window.
    fn release_settled(&mut self) {
        // Every sample received before now − window has been taken by now (each subscription was just
        // drained), so what is released comes out in receive order across topics.
        let window = u64::try_from(REORDER_WINDOW.as_nanos()).unwrap_or(u64::MAX);
        let until = unix_ns(rustdds::Timestamp::now()).saturating_sub(window);
        let recorder = &self.recorder;
        self.reorder.release(until, |id, cdr, log_time, publish_time| {
            recorder.record(id, cdr, log_time, publish_time);
        });
    }

    /// Takes what is left, writes everything held in order and finishes the bag.
    fn finish(mut self) -> Result<RecordStats, RecordError> {
        // One last look at every subscription, then everything held goes out in order.
        for sub in &mut self.subscribed {
            while let Ok(true) = sub.take_one(&mut self.reorder) {}
        }
        let recorder = self.recorder;
        self.reorder.release(u64::MAX, |id, cdr, log_time, publish_time| {
            recorder.record(id, cdr, log_time, publish_time);
        });
        let finished = recorder.finish()?;
        Ok(RecordStats {
            per_topic: self.subscribed.into_iter().map(|s| (s.topic, s.count)).collect(),
            dropped: finished.dropped,
            late: self.reorder.late(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reorder_releases_in_log_time_order_and_never_goes_backwards() {
        let mut r = Reorder::default();
        // Two subscriptions drained one after the other: the answers (topic 1) first, then the swings.
        for t in [20, 40, 60] {
            r.push(TopicId(1), vec![t as u8], t + 5, t);
        }
        for t in [20, 40, 60] {
            r.push(TopicId(0), vec![t as u8], t, t);
        }
        let mut out = Vec::new();
        r.release(50, |id, _, log, _| out.push((id.0, log)));
        assert_eq!(out, [(0, 20), (1, 25), (0, 40), (1, 45)]);
        assert_eq!(r.len(), 2);
        // A message received before what already went out (a stall longer than the window) is raised.
        r.push(TopicId(0), vec![], 30, 30);
        r.release(u64::MAX, |id, _, log, _| out.push((id.0, log)));
        assert_eq!(&out[4..], [(0, 45), (0, 60), (1, 65)]);
        assert_eq!(r.late(), 1);
        assert!(r.is_empty());
        let logs: Vec<u64> = out.iter().map(|o| o.1).collect();
        assert!(logs.windows(2).all(|w| w[0] <= w[1]), "{logs:?}");
    }

    #[test]
    fn dds_names_map_to_ros_names() {
        // The DDS forms rmw implementations use (ROS 2 design: "Topic and Service name mapping to DDS").
        assert_eq!(ros_type_name("std_msgs::msg::dds_::String_").as_deref(), Some("std_msgs/msg/String"));
        assert_eq!(
            ros_type_name("rcl_interfaces::msg::dds_::ParameterEvent_").as_deref(),
            Some("rcl_interfaces/msg/ParameterEvent")
        );
        assert_eq!(ros_type_name("DCPSParticipant"), None);
        assert_eq!(ros_type_name("std_msgs::msg::String"), None);
        assert_eq!(ros_topic_name("rt/lab/swing").as_deref(), Ok("/lab/swing"));
        assert!(ros_topic_name("rq/lab/sweetspot/get_parametersRequest").unwrap_err().contains("service"));
        assert!(ros_topic_name("ros_discovery_info").is_err());
        // 1.5 s in RTPS ticks: seconds in the high word, 2^31 / 2^32 of a second in the low one.
        let ticks = (1u64 << 32) | (1u64 << 31);
        assert_eq!(unix_ns(rustdds::Timestamp::from_ticks(ticks)), 1_500_000_000);
    }

    #[test]
    fn selection_admits_listed_matching_and_visible_topics() {
        let all = Selection { all: true, ..Selection::default() };
        assert!(all.admits("/lab/swing").is_ok());
        assert!(all.admits("/lab/_hidden/x").unwrap_err().contains("hidden"));
        let listed = Selection { topics: vec!["/lab/_hidden/x".into()], ..Selection::default() };
        assert!(listed.admits("/lab/_hidden/x").is_ok());
        assert!(listed.admits("/lab/swing").is_err());
        let regex = Selection { regex: Some(regex::Regex::new("^/rig[0-9]+/").unwrap()), ..Selection::default() };
        assert!(regex.admits("/rig3/swing").is_ok());
        assert!(regex.admits("/lab/swing").is_err());
    }
}
