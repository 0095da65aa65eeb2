//! `bag play`: republish the recorded inputs (BatParams, BallParams, Swing) over DDS with their original
//! timing. The schedule is pure ([`schedule`]); [`play`] is the DDS shell around it. It lives beside the node,
//! above both [`crate::bag`] (reading) and [`crate::ros`] (DDS), so neither of those imports the other.
//!
//! Params recorded before the first swing go out first, at once, on transient-local (latched) writers, so a
//! node started later still gets them; params recorded later go out at their own time, so every swing meets
//! the bat and ball that were in force when it was recorded.
//!
//! Beyond that it follows `ros2 bag play`: a time scale, looping, a topic filter, topic remaps, a start offset
//! into the bag, a delay before each pass, `/clock` with the bag's time, and pause/resume from the terminal
//! ([`keys`]). `import --pub` plays an imported bag through the same path, with a fixed interval between the
//! swings instead of the recorded pace when asked ([`PlayOptions::interval`]).

pub mod console;
pub mod foxglove;
pub mod keys;

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use std::sync::Arc;

use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::rosgraph_msgs::msg::Clock;
use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use crate::msgs::{decode_cdr, RosMessage};

use crate::bag::reader::read_bag;
use crate::bag::BagError;

/// One message to publish.
#[derive(Debug, Clone, PartialEq)]
pub struct PlayItem {
    /// When, after the start of a pass.
    pub at: Duration,
    /// When it was recorded (the MCAP log time), ns since the Unix epoch.
    pub log_time_ns: u64,
    /// Recorded topic name.
    pub topic: String,
    /// ROS type (one of the three inputs).
    pub type_name: String,
    /// CDR bytes as recorded.
    pub cdr: Vec<u8>,
}

/// The input types `play` republishes.
pub const INPUT_TYPES: [&str; 3] = [BatParams::TYPE_NAME, BallParams::TYPE_NAME, Swing::TYPE_NAME];

/// The publication schedule of a bag and the recorded time its pass starts from.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule {
    /// The messages, in publication order.
    pub items: Vec<PlayItem>,
    /// The log time (ns since the Unix epoch) that a pass's time 0 stands for: `/clock` reads
    /// `origin_ns + elapsed × rate`.
    pub origin_ns: u64,
}

/// Builds the publication schedule of a bag: inputs only (or only `topics` if non-empty), in log-time order,
/// leading params at 0, the rest at (log_time − first non-leading log_time) / rate.
pub fn schedule(path: &Path, topics: &[String], rate: f64) -> Result<Vec<PlayItem>, BagError> {
    schedule_from(path, topics, rate, Duration::ZERO).map(|s| s.items)
}

/// [`schedule`] starting `start_offset` (recorded time) after the bag's first message, as `ros2 bag play
/// --start-offset` does: swings recorded before that point are skipped; params recorded before it are still
/// published first (latched), so the swings that remain meet the bat and ball in force when they were
/// recorded.
pub fn schedule_from(path: &Path, topics: &[String], rate: f64, start_offset: Duration) -> Result<Schedule, BagError> {
    if !(rate > 0.0 && rate.is_finite()) {
        return Err(BagError::Options(format!("-r/--rate {rate} is out of range: expected a finite value > 0")));
    }
    let mut recorded: Vec<PlayItem> = Vec::new();
    let mut seen_topics: Vec<String> = Vec::new();
    let mut bag_start_ns = u64::MAX;
    let mut bag_end_ns = 0;
    read_bag(path, |m| {
        let topic = &m.channel.topic;
        bag_start_ns = bag_start_ns.min(m.log_time_ns);
        bag_end_ns = bag_end_ns.max(m.log_time_ns);
        if !seen_topics.contains(&topic.name) {
            seen_topics.push(topic.name.clone());
        }
        let wanted = if topics.is_empty() {
            INPUT_TYPES.contains(&topic.type_name.as_str())
        } else {
            topics.contains(&topic.name)
        };
        if wanted {
            recorded.push(PlayItem {
                at: Duration::ZERO,
                log_time_ns: m.log_time_ns,
                topic: topic.name.clone(),
                type_name: topic.type_name.clone(),
                cdr: m.data.to_vec(),
            });
        }
    })?;
    for t in topics {
        if !seen_topics.contains(t) {
            return Err(BagError::Options(format!(
                "--topics: {t} is not in the bag (topics: {})",
                seen_topics.join(", ")
            )));
        }
    }
    for item in &recorded {
        if !INPUT_TYPES.contains(&item.type_name.as_str()) {
            return Err(BagError::Options(format!(
                "--topics: {} has type {}; play republishes only inputs ({})",
                item.topic,
                item.type_name,
                INPUT_TYPES.join(", ")
            )));
        }
    }
    recorded.sort_by_key(|i| i.log_time_ns);
    let offset_ns = u64::try_from(start_offset.as_nanos()).unwrap_or(u64::MAX);
    let start_ns = bag_start_ns.saturating_add(offset_ns);
    if bag_start_ns <= bag_end_ns {
        check_start_offset(start_offset, Duration::from_nanos(bag_end_ns - bag_start_ns))?;
    }
    let is_param = |i: &PlayItem| i.type_name != Swing::TYPE_NAME;
    recorded.retain(|i| i.log_time_ns >= start_ns || is_param(i));
    let leading = recorded.iter().take_while(|i| is_param(i)).count();
    let origin_ns = recorded.get(leading).map(|i| i.log_time_ns).unwrap_or(start_ns);
    let items = recorded
        .into_iter()
        .enumerate()
        .map(|(k, mut item)| {
            item.at = if k < leading {
                Duration::ZERO
            } else {
                crate::model::time::saturating_secs(
                    Duration::from_nanos(item.log_time_ns.saturating_sub(origin_ns)).as_secs_f64() / rate,
                )
            };
            item
        })
        .collect();
    Ok(Schedule { items, origin_ns })
}

/// Refuses a `--start-offset` past the end of a bag lasting `span` (first to last message), naming both.
pub fn check_start_offset(start_offset: Duration, span: Duration) -> Result<(), BagError> {
    if start_offset > span {
        return Err(BagError::Options(format!(
            "--start-offset {} s is past the bag's end: its messages span {} s",
            start_offset.as_secs_f64(),
            span.as_secs_f64()
        )));
    }
    Ok(())
}

/// The shortest pass of `--loop`: a bag whose messages span less (one message, or all at one log time) is
/// played once per this period instead of over and over without pause.
pub const MIN_PASS: Duration = Duration::from_secs(1);

/// How to play.
#[derive(Debug, Clone)]
pub struct PlayOptions {
    /// Time scale (2 = twice as fast).
    pub rate: f64,
    /// Start over when done, until interrupted.
    pub repeat: bool,
    /// Only these topics (empty: every input topic).
    pub topics: Vec<String>,
    /// Wait until every writer matched this many subscriptions before starting (0: see `wait_discovered`).
    pub wait_subscribers: usize,
    /// With `wait_subscribers` 0: before playing, wait (at most `timeout`) until every subscription that
    /// discovery shows on a played topic has matched, and warn of topics with none (see [`play`]).
    pub wait_discovered: bool,
    /// Limit for waiting for subscribers and for acknowledgments at the end.
    pub timeout: Duration,
    /// Publish on the second topic what was recorded on the first (fully qualified names).
    pub remaps: Vec<(String, String)>,
    /// Start this far (recorded time) into the bag (see [`schedule_from`]).
    pub start_offset: Duration,
    /// Wait this long before each pass.
    pub delay: Duration,
    /// Publish rosgraph_msgs/Clock with the bag's time on `/clock` at this rate, Hz.
    pub clock_hz: Option<f64>,
    /// While set, playback time stands still (the space bar toggles it, see [`keys`]).
    pub paused: Option<Arc<AtomicBool>>,
    /// Publish the swings this far apart, s, instead of at their recorded pace (`import --pub --rate`): an
    /// export's rows can be minutes apart. Params after the leading ones go out just before the next swing.
    pub interval: Option<Duration>,
}

impl PlayOptions {
    /// `rate` scale, every other option at `ros2 bag play`'s default.
    pub fn new(rate: f64) -> PlayOptions {
        PlayOptions {
            rate,
            repeat: false,
            topics: Vec::new(),
            wait_subscribers: 0,
            wait_discovered: true,
            timeout: Duration::from_secs(10),
            remaps: Vec::new(),
            start_offset: Duration::ZERO,
            delay: Duration::ZERO,
            clock_hz: None,
            paused: None,
            interval: None,
        }
    }

    /// The topic a message recorded on `topic` is published on.
    pub fn remapped<'a>(&'a self, topic: &'a str) -> &'a str {
        self.remaps.iter().find(|(from, _)| from == topic).map(|(_, to)| to.as_str()).unwrap_or(topic)
    }

    /// The schedule these options play from `path`, remaps applied. A remap that puts two types on one
    /// topic (one recorded topic onto another's of a different type) is refused: a DDS topic has one type.
    pub fn schedule(&self, path: &Path) -> Result<Schedule, BagError> {
        let mut schedule = schedule_from(path, &self.topics, self.rate, self.start_offset)?;
        if let Some(interval) = self.interval {
            retime(&mut schedule.items, interval);
        }
        let mut types: Vec<(String, String, String)> = Vec::new();
        for item in &mut schedule.items {
            let recorded = std::mem::take(&mut item.topic);
            item.topic = self.remapped(&recorded).to_string();
            match types.iter().find(|(topic, _, _)| *topic == item.topic) {
                Some((topic, type_name, from)) if *type_name != item.type_name => {
                    return Err(BagError::Options(format!(
                        "--remap: {recorded} ({}) would be published on {topic}, where {from} ({type_name}) goes: \
                         one topic carries one type",
                        item.type_name
                    )));
                }
                Some(_) => {}
                None => types.push((item.topic.clone(), item.type_name.clone(), recorded.clone())),
            }
        }
        Ok(schedule)
    }
}

/// Puts the swings of `items` `interval` apart, the first at 0, and every other message after the leading
/// params at the time of the swing that follows it (so it still goes out before that swing).
fn retime(items: &mut [PlayItem], interval: Duration) {
    let leading = items.iter().take_while(|i| i.type_name != Swing::TYPE_NAME).count();
    let mut swings: u32 = 0;
    for item in items.iter_mut().skip(leading) {
        item.at = interval.saturating_mul(swings);
        if item.type_name == Swing::TYPE_NAME {
            swings = swings.saturating_add(1);
        }
    }
}

/// `/clock`'s QoS as rosbag2's player publishes it (rclcpp's `ClockQoS`): best effort, volatile, keep last 1.
pub fn clock_qos() -> ros2_client::QosProfile {
    use ros2_client::qos::{Durability, History, Reliability};
    ros2_client::QosProfile::publisher_default()
        .reliability(Reliability::BestEffort)
        .durability(Durability::Volatile)
        .history(History::KeepLast { depth: 1 })
}

/// A recorded time (ns since the Unix epoch) as builtin_interfaces/Time.
pub fn time_of(ns: u64) -> Time {
    Time { sec: i32::try_from(ns / 1_000_000_000).unwrap_or(i32::MAX), nanosec: (ns % 1_000_000_000) as u32 }
}

/// Playback time of one pass: wall time since its start, less the time spent paused.
struct PassClock {
    start: Instant,
    paused_at: Option<Instant>,
    paused_for: Duration,
}

impl PassClock {
    fn start() -> PassClock {
        PassClock { start: Instant::now(), paused_at: None, paused_for: Duration::ZERO }
    }

    fn elapsed(&mut self, paused: bool) -> Duration {
        let now = Instant::now();
        match (paused, self.paused_at) {
            (true, None) => self.paused_at = Some(now),
            (false, Some(since)) => {
                self.paused_for += now - since;
                self.paused_at = None;
            }
            _ => {}
        }
        self.paused_at.unwrap_or(now).saturating_duration_since(self.start).saturating_sub(self.paused_for)
    }
}

/// The `/clock` publisher: the bag's time at the playback position, every `period` of wall time.
struct ClockOut {
    writer: rustdds::no_key::DataWriterCdr<Clock>,
    period: Duration,
    next: Instant,
}

impl ClockOut {
    fn tick(&mut self, origin_ns: u64, position: Duration, rate: f64) {
        let now = Instant::now();
        if now < self.next {
            return;
        }
        self.next = (self.next + self.period).max(now);
        let bag_ns = origin_ns
            .saturating_add(u64::try_from(crate::model::time::scaled(position, rate).as_nanos()).unwrap_or(u64::MAX));
        let message = Clock { clock: time_of(bag_ns) };
        // Best effort, like rosbag2's: a lost tick is replaced by the next one.
        if let Err(e) = self.writer.write(message, Some(rustdds::Timestamp::now())) {
            tracing::debug!("/clock: {e}");
        }
    }

    fn until_next(&self) -> Duration {
        self.next.saturating_duration_since(Instant::now())
    }
}

/// Counts of a play.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PlayStats {
    /// Messages published.
    pub published: u64,
    /// Passes completed.
    pub passes: u64,
    /// Whether any played topic had a matched subscription at some point of the play: if not, every message
    /// went to nobody.
    pub heard: bool,
}

enum Writer {
    Bat(rustdds::no_key::DataWriterCdr<BatParams>),
    Ball(rustdds::no_key::DataWriterCdr<BallParams>),
    Swing(rustdds::no_key::DataWriterCdr<Swing>),
}

impl Writer {
    /// Brings `count`, this writer's matched subscriptions, up to date.
    fn update_matched(&self, count: &mut usize) {
        match self {
            Writer::Bat(w) => matched(w, count),
            Writer::Ball(w) => matched(w, count),
            Writer::Swing(w) => matched(w, count),
        }
    }

    fn write(&self, item: &PlayItem, timeout: Duration, stop: &AtomicBool) -> Result<(), BagError> {
        match self {
            Writer::Bat(w) => write_one(w, item, timeout, stop),
            Writer::Ball(w) => write_one(w, item, timeout, stop),
            Writer::Swing(w) => write_one(w, item, timeout, stop),
        }
    }

    /// Whether every matched subscription acknowledged everything within `timeout`.
    fn wait_for_acknowledgments(&self, timeout: Duration) -> bool {
        let acked = match self {
            Writer::Bat(w) => w.wait_for_acknowledgments(timeout),
            Writer::Ball(w) => w.wait_for_acknowledgments(timeout),
            Writer::Swing(w) => w.wait_for_acknowledgments(timeout),
        };
        matches!(acked, Ok(true))
    }
}

fn make_writer<T: RosMessage>(
    ctx: &ros2_client::Context,
    topic: &str,
    qos: &ros2_client::QosProfile,
) -> Result<rustdds::no_key::DataWriterCdr<T>, BagError> {
    crate::ros::edge::writer::<T>(ctx, topic, qos).map_err(|e| BagError::Options(format!("DDS: {e}")))
}

fn write_one<T: RosMessage + serde::de::DeserializeOwned + serde::Serialize>(
    writer: &rustdds::no_key::DataWriterCdr<T>,
    item: &PlayItem,
    timeout: Duration,
    stop: &AtomicBool,
) -> Result<(), BagError> {
    let mut message: T = decode_cdr(&item.cdr).map_err(|e| BagError::Format(format!("{}: {e}", item.topic)))?;
    let start = Instant::now();
    loop {
        match writer.write(message, Some(rustdds::Timestamp::now())) {
            Ok(()) => return Ok(()),
            Err(rustdds::dds::WriteError::WouldBlock { data }) => {
                if start.elapsed() >= timeout || stop.load(Ordering::Relaxed) {
                    return Err(BagError::Options(format!(
                        "{}: subscribers did not keep up (send window full)",
                        item.topic
                    )));
                }
                message = data;
            }
            Err(e) => return Err(BagError::Options(format!("{}: DDS write failed: {e}", item.topic))),
        }
    }
}

fn matched<T: RosMessage>(writer: &rustdds::no_key::DataWriterCdr<T>, current: &mut usize) {
    *current = crate::ros::edge::matched_subscriptions(writer, *current);
}

/// Brings each writer's count of matched subscriptions up to date; whether any has one.
fn any_matched(writers: &mut [(String, Writer, usize)]) -> bool {
    for (_, writer, count) in writers.iter_mut() {
        writer.update_matched(count);
    }
    writers.iter().any(|(_, _, count)| *count > 0)
}

/// Something `play` wants the user to know, besides each message published.
#[derive(Debug, Clone, PartialEq)]
pub enum PlayEvent<'a> {
    /// A message went out.
    Published(&'a PlayItem),
    /// Waiting for the subscriptions discovery shows to match (said once, when the wait starts).
    Waiting(String),
    /// A topic nobody subscribes to, a wait that ran out, a subscription of another type.
    Warning(String),
}

/// How long `play` looks at discovery before taking what it shows as the subscribers there are: a new
/// participant hears of the others within a few hundred ms on a LAN (SPDP then SEDP); a topic with no
/// subscription after this is warned of.
pub const DISCOVERY_WINDOW: Duration = Duration::from_millis(1500);
/// Pause between seeing the last subscription match and the first publication: the subscriber's side of the
/// handshake completes a moment after ours, and a volatile reader drops what comes before (as `pub` does).
pub const MATCH_SETTLE: Duration = Duration::from_millis(300);

/// Subscriptions discovery shows on a ROS topic: (how many of type `dds_type`, the other types seen).
fn discovered_subscriptions(ctx: &ros2_client::Context, fq_topic: &str, dds_type: &str) -> (usize, Vec<String>) {
    let dds_topic = crate::ros::names::dds_topic_name(fq_topic);
    let mut count = 0;
    let mut others = Vec::new();
    for reader in ctx.domain_participant().discovered_readers() {
        let data = &reader.subscription_topic_data;
        if data.topic_name != dds_topic {
            continue;
        }
        if data.type_name() == dds_type {
            count += 1;
        } else if !others.contains(data.type_name()) {
            others.push(data.type_name().clone());
        }
    }
    (count, others)
}

/// The DDS type name of one of the input types.
fn dds_type_of(type_name: &str) -> &'static str {
    match type_name {
        BatParams::TYPE_NAME => BatParams::DDS_TYPE_NAME,
        BallParams::TYPE_NAME => BallParams::DDS_TYPE_NAME,
        _ => Swing::DDS_TYPE_NAME,
    }
}

/// Waits (at most `timeout`) until every subscription discovery shows on each played topic has matched its
/// writer: at once when every topic has matched subscriptions and none unmatched, else once discovery has
/// had [`DISCOVERY_WINDOW`] and every subscription it shows has matched. Warns of topics nobody subscribes
/// to and of a wait that ran out; refuses a topic whose subscriptions are of another type.
fn wait_for_discovered(
    ctx: &ros2_client::Context,
    writers: &mut [(String, Writer, usize)],
    types: &[(String, String)],
    timeout: Duration,
    stop: &AtomicBool,
    on_event: &mut impl FnMut(PlayEvent<'_>),
) -> Result<(), BagError> {
    let start = Instant::now();
    let mut said = false;
    loop {
        let mut status: Vec<(String, usize, usize)> = Vec::new();
        for (topic, writer, count) in writers.iter_mut() {
            writer.update_matched(count);
            let type_name = types.iter().find(|(t, _)| t == topic).map_or("", |(_, ty)| ty.as_str());
            let dds_type = dds_type_of(type_name);
            let (discovered, others) = discovered_subscriptions(ctx, topic, dds_type);
            if !others.is_empty() {
                return Err(BagError::Options(format!(
                    "{topic}: its subscribers take {} and this bag's messages there are {type_name} ({dds_type}): \
                     refused before publishing anything (--remap them to another topic)",
                    others.join(", ")
                )));
            }
            status.push((topic.clone(), *count, discovered));
        }
        let all_matched = status.iter().all(|(_, matched, discovered)| matched >= discovered);
        let everyone_there = status.iter().all(|(_, matched, _)| *matched > 0);
        let elapsed = start.elapsed();
        if all_matched && (everyone_there || elapsed >= DISCOVERY_WINDOW) {
            for (topic, matched, _) in &status {
                if *matched == 0 {
                    on_event(PlayEvent::Warning(format!(
                        "no subscriber on {topic}: its messages go to nobody (start the node first, or wait for \
                         it with --wait-subscribers 1)"
                    )));
                }
            }
            if status.iter().any(|(_, matched, _)| *matched > 0) {
                std::thread::sleep(MATCH_SETTLE);
            }
            return Ok(());
        }
        if elapsed >= timeout {
            let late: Vec<String> = status
                .iter()
                .filter(|(_, matched, discovered)| matched < discovered)
                .map(|(topic, matched, discovered)| format!("{topic} {matched}/{discovered}"))
                .collect();
            on_event(PlayEvent::Warning(format!(
                "not every subscriber discovery shows had matched within {:.1} s ({}): playing anyway, and those \
                 may miss the first messages",
                timeout.as_secs_f64(),
                late.join(", ")
            )));
            return Ok(());
        }
        if !said && elapsed >= Duration::from_millis(500) {
            said = true;
            let shown: Vec<String> =
                status.iter().map(|(topic, matched, discovered)| format!("{topic} {matched}/{discovered}")).collect();
            on_event(PlayEvent::Waiting(format!(
                "waiting (at most {:.0} s, --timeout) for the subscribers discovery shows to match (matched/seen: \
                 {})",
                timeout.as_secs_f64(),
                shown.join(", ")
            )));
        }
        if stop.load(Ordering::Relaxed) {
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Publishes the schedule over DDS (participant from `crate::ros`, QoS of `crate::ros::qos`). Stops early when
/// `stop` is set. `on_event` hears of each publication (progress, with the topic it went out on) and of the
/// wait before it.
///
/// Before the first message, unless `wait_subscribers` asks for a number of subscriptions per topic or
/// `wait_discovered` is off, it waits (at most `timeout`) until the subscriptions discovery shows on each
/// played topic have matched: a node already running gets every swing, where `ros2 bag play` starts at once
/// and loses what goes out before the match (its users learn `--delay`, which still works here, after the
/// wait).
pub fn play(
    path: &Path,
    options: &PlayOptions,
    stop: &AtomicBool,
    mut on_event: impl FnMut(PlayEvent<'_>),
) -> Result<PlayStats, BagError> {
    check_clock_rate(options.clock_hz)?;
    let Schedule { items, origin_ns } = options.schedule(path)?;
    if items.is_empty() {
        return Err(BagError::Format(format!("{}: no input messages to play", path.display())));
    }
    let (ctx, _config) = crate::ros::context_from_env().map_err(|e| BagError::Options(format!("DDS: {e}")))?;
    let names = topic_types(&items);
    let mut writers = open_writers(&ctx, &names)?;
    let clock = open_clock(&ctx, options.clock_hz)?;
    if options.wait_subscribers > 0 {
        if !wait_for_subscribers(&mut writers, options, stop)? {
            return Ok(PlayStats::default());
        }
    } else if options.wait_discovered {
        wait_for_discovered(&ctx, &mut writers, &names, options.timeout, stop, &mut on_event)?;
    }
    let mut player = Player { writers, clock, origin_ns, options, stop };
    let stats = player.play_passes(&items, &mut on_event)?;
    player.wait_for_acknowledgments();
    // Readers drop untaken samples of a writer whose participant left: linger a moment (as `pub` does).
    std::thread::sleep(Duration::from_millis(500));
    Ok(stats)
}

/// Refuses a `--clock` rate that is not a finite rate > 0.
fn check_clock_rate(clock_hz: Option<f64>) -> Result<(), BagError> {
    if let Some(hz) = clock_hz {
        if !(hz > 0.0 && hz.is_finite()) {
            return Err(BagError::Options(format!("--clock {hz} is out of range: expected a finite rate > 0 Hz")));
        }
    }
    Ok(())
}

/// The (topic, type) pairs of a schedule, in order of first appearance.
fn topic_types(items: &[PlayItem]) -> Vec<(String, String)> {
    let mut names: Vec<(String, String)> = Vec::new();
    for item in items {
        if !names.iter().any(|(n, _)| *n == item.topic) {
            names.push((item.topic.clone(), item.type_name.clone()));
        }
    }
    names
}

/// A writer per (topic, type), with the QoS of its type, none matched yet.
fn open_writers(
    ctx: &ros2_client::Context,
    names: &[(String, String)],
) -> Result<Vec<(String, Writer, usize)>, BagError> {
    let mut writers: Vec<(String, Writer, usize)> = Vec::new();
    for (topic, type_name) in names {
        let writer = match type_name.as_str() {
            BatParams::TYPE_NAME => Writer::Bat(make_writer(ctx, topic, &crate::ros::qos::params_qos())?),
            BallParams::TYPE_NAME => Writer::Ball(make_writer(ctx, topic, &crate::ros::qos::params_qos())?),
            _ => Writer::Swing(make_writer(ctx, topic, &crate::ros::qos::swing_qos())?),
        };
        writers.push((topic.clone(), writer, 0));
    }
    Ok(writers)
}

/// The `/clock` publisher `--clock` asks for, if it does.
fn open_clock(ctx: &ros2_client::Context, clock_hz: Option<f64>) -> Result<Option<ClockOut>, BagError> {
    Ok(match clock_hz {
        Some(hz) => Some(ClockOut {
            writer: make_writer::<Clock>(ctx, "/clock", &clock_qos())?,
            period: crate::model::time::period_of(hz),
            next: Instant::now(),
        }),
        None => None,
    })
}

/// Waits (at most `timeout`) until every writer matched `wait_subscribers` subscriptions; `false` if
/// stopped first. Refuses, naming the topics short of them, when the time runs out.
fn wait_for_subscribers(
    writers: &mut [(String, Writer, usize)],
    options: &PlayOptions,
    stop: &AtomicBool,
) -> Result<bool, BagError> {
    let start = Instant::now();
    loop {
        for (_, writer, count) in writers.iter_mut() {
            writer.update_matched(count);
        }
        if writers.iter().all(|(_, _, c)| *c >= options.wait_subscribers) {
            break;
        }
        if stop.load(Ordering::Relaxed) {
            return Ok(false);
        }
        if start.elapsed() >= options.timeout {
            let missing: Vec<&str> =
                writers.iter().filter(|(_, _, c)| *c < options.wait_subscribers).map(|(t, _, _)| t.as_str()).collect();
            return Err(BagError::Options(format!(
                "no {} subscription(s) on {} within {:.1} s",
                options.wait_subscribers,
                missing.join(", "),
                options.timeout.as_secs_f64()
            )));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    // Our side saw the match first; give the subscribers' side of the handshake a moment (see `pub`).
    std::thread::sleep(MATCH_SETTLE);
    Ok(true)
}

/// The publishing side of a play, once the writers are open and matched: the passes over the schedule.
struct Player<'a> {
    writers: Vec<(String, Writer, usize)>,
    clock: Option<ClockOut>,
    /// The recorded time a pass starts from (see [`Schedule::origin_ns`]).
    origin_ns: u64,
    options: &'a PlayOptions,
    stop: &'a AtomicBool,
}

impl Player<'_> {
    fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    fn is_paused(&self) -> bool {
        self.options.paused.as_ref().is_some_and(|p| p.load(Ordering::Relaxed))
    }

    /// Plays `items` once, or over and over with `repeat`, each pass after the delay, until done or stopped.
    fn play_passes(
        &mut self,
        items: &[PlayItem],
        on_event: &mut impl FnMut(PlayEvent<'_>),
    ) -> Result<PlayStats, BagError> {
        let mut stats = PlayStats { heard: any_matched(&mut self.writers), ..PlayStats::default() };
        loop {
            if !self.sit_out_delay() {
                break;
            }
            let mut pass = PassClock::start();
            if !self.play_pass(items, &mut pass, &mut stats, on_event)? {
                break;
            }
            stats.passes += 1;
            if !self.options.repeat || !self.sit_out_min_pass(&mut pass) {
                break;
            }
        }
        Ok(stats)
    }

    /// Waits out the delay before a pass; `false` if stopped meanwhile.
    fn sit_out_delay(&self) -> bool {
        let delay_end = Instant::now() + self.options.delay;
        while Instant::now() < delay_end {
            if self.stopped() {
                return false;
            }
            std::thread::sleep((delay_end - Instant::now()).min(Duration::from_millis(20)));
        }
        true
    }

    /// The next pass follows the bag's own timing: it starts when this one's span is over, and no sooner
    /// than MIN_PASS after this one started. `false` if stopped meanwhile.
    fn sit_out_min_pass(&self, pass: &mut PassClock) -> bool {
        while pass.elapsed(self.is_paused()) < MIN_PASS {
            if self.stopped() {
                return false;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        true
    }

    /// Publishes each item at its time; `false` if stopped before the end.
    fn play_pass(
        &mut self,
        items: &[PlayItem],
        pass: &mut PassClock,
        stats: &mut PlayStats,
        on_event: &mut impl FnMut(PlayEvent<'_>),
    ) -> Result<bool, BagError> {
        for item in items {
            if !self.wait_until_due(item, pass) {
                return Ok(false);
            }
            let Some((_, writer, _)) = self.writers.iter().find(|(t, _, _)| *t == item.topic) else { continue };
            writer.write(item, self.options.timeout, self.stop)?;
            stats.published += 1;
            stats.heard = stats.heard || any_matched(&mut self.writers);
            on_event(PlayEvent::Published(item));
        }
        Ok(true)
    }

    /// Waits until the pass reaches `item`'s time and is not paused, ticking `/clock` meanwhile; `false` if
    /// stopped first.
    fn wait_until_due(&mut self, item: &PlayItem, pass: &mut PassClock) -> bool {
        loop {
            if self.stopped() {
                return false;
            }
            let position = pass.elapsed(self.is_paused());
            if let Some(clock) = self.clock.as_mut() {
                clock.tick(self.origin_ns, position, self.options.rate);
            }
            if position >= item.at && !self.is_paused() {
                return true;
            }
            let mut nap = item.at.saturating_sub(position).min(Duration::from_millis(20));
            if let Some(clock) = &self.clock {
                nap = nap.min(clock.until_next());
            }
            std::thread::sleep(nap.max(Duration::from_micros(200)));
        }
    }

    /// Waits (at most `timeout` per topic) until every subscription acknowledged everything; warns of those
    /// that did not.
    fn wait_for_acknowledgments(&self) {
        for (topic, writer, _) in &self.writers {
            if !writer.wait_for_acknowledgments(self.options.timeout) {
                tracing::warn!(
                    "not every subscription on {topic} acknowledged everything within {:?}",
                    self.options.timeout
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_offset_past_the_end_names_the_bags_span() {
        assert!(check_start_offset(Duration::from_secs(3), Duration::from_secs(3)).is_ok());
        let refused = check_start_offset(Duration::from_secs(40), Duration::from_millis(2500)).unwrap_err();
        let text = refused.to_string();
        assert!(text.contains("--start-offset 40 s is past the bag's end") && text.contains("2.5 s"), "{text}");
        assert!(!text.contains("bad bag"), "{text}");
    }
}
