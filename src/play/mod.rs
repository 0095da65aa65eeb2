//! `bag play`: republish the recorded inputs (BatParams, BallParams, Swing) over DDS with their original
//! timing. The schedule is pure ([`schedule`]); [`play`] is the DDS shell around it. It lives beside the node,
//! above both [`crate::bag`] (reading) and [`crate::ros`] (DDS), so neither of those imports the other.
//!
//! Params recorded before the first swing go out first, at once, on transient-local (latched) writers, so a
//! node started later still gets them; params recorded later go out at their own time, so every swing meets
//! the bat and ball that were in force when it was recorded.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use crate::msgs::{decode_cdr, RosMessage};

use crate::bag::reader::read_bag;
use crate::bag::BagError;

/// One message to publish.
#[derive(Debug, Clone, PartialEq)]
pub struct PlayItem {
    /// When, after the start of a pass.
    pub at: Duration,
    /// Recorded topic name.
    pub topic: String,
    /// ROS type (one of the three inputs).
    pub type_name: String,
    /// CDR bytes as recorded.
    pub cdr: Vec<u8>,
}

/// The input types `play` republishes.
pub const INPUT_TYPES: [&str; 3] = [BatParams::TYPE_NAME, BallParams::TYPE_NAME, Swing::TYPE_NAME];

/// Builds the publication schedule of a bag: inputs only (or only `topics` if non-empty), in log-time order,
/// leading params at 0, the rest at (log_time − first non-leading log_time) / rate.
pub fn schedule(path: &Path, topics: &[String], rate: f64) -> Result<Vec<PlayItem>, BagError> {
    if !(rate > 0.0 && rate.is_finite()) {
        return Err(BagError::Format(format!("rate = {rate} is out of range: expected a finite value > 0")));
    }
    let mut recorded: Vec<(u64, PlayItem)> = Vec::new();
    let mut seen_topics: Vec<String> = Vec::new();
    read_bag(path, |m| {
        let topic = &m.channel.topic;
        if !seen_topics.contains(&topic.name) {
            seen_topics.push(topic.name.clone());
        }
        let wanted = if topics.is_empty() {
            INPUT_TYPES.contains(&topic.type_name.as_str())
        } else {
            topics.contains(&topic.name)
        };
        if wanted {
            recorded.push((
                m.log_time_ns,
                PlayItem {
                    at: Duration::ZERO,
                    topic: topic.name.clone(),
                    type_name: topic.type_name.clone(),
                    cdr: m.data.to_vec(),
                },
            ));
        }
    })?;
    for t in topics {
        if !seen_topics.contains(t) {
            return Err(BagError::Format(format!(
                "--topics: {t} is not in the bag (topics: {})",
                seen_topics.join(", ")
            )));
        }
    }
    for (_, item) in &recorded {
        if !INPUT_TYPES.contains(&item.type_name.as_str()) {
            return Err(BagError::Format(format!(
                "{} has type {}; play republishes only inputs ({})",
                item.topic,
                item.type_name,
                INPUT_TYPES.join(", ")
            )));
        }
    }
    recorded.sort_by_key(|(t, _)| *t);
    let is_param = |i: &PlayItem| i.type_name != Swing::TYPE_NAME;
    let leading = recorded.iter().take_while(|(_, i)| is_param(i)).count();
    let origin = recorded.get(leading).map(|(t, _)| *t).unwrap_or(0);
    Ok(recorded
        .into_iter()
        .enumerate()
        .map(|(k, (t, mut item))| {
            item.at =
                if k < leading { Duration::ZERO } else { Duration::from_nanos(t.saturating_sub(origin)).div_f64(rate) };
            item
        })
        .collect())
}

/// How to play.
#[derive(Debug, Clone)]
pub struct PlayOptions {
    /// Time scale (2 = twice as fast).
    pub rate: f64,
    /// Start over when done, until interrupted.
    pub repeat: bool,
    /// Only these topics (empty: every input topic).
    pub topics: Vec<String>,
    /// Wait until every writer matched this many subscriptions before starting.
    pub wait_subscribers: usize,
    /// Limit for waiting for subscribers and for acknowledgments at the end.
    pub timeout: Duration,
}

/// Counts of a play.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct PlayStats {
    /// Messages published.
    pub published: u64,
    /// Passes completed.
    pub passes: u64,
}

enum Writer {
    Bat(rustdds::no_key::DataWriterCdr<BatParams>),
    Ball(rustdds::no_key::DataWriterCdr<BallParams>),
    Swing(rustdds::no_key::DataWriterCdr<Swing>),
}

fn make_writer<T: RosMessage>(
    ctx: &ros2_client::Context,
    topic: &str,
    qos: &ros2_client::QosProfile,
) -> Result<rustdds::no_key::DataWriterCdr<T>, BagError> {
    crate::ros::edge::writer::<T>(ctx, topic, qos).map_err(|e| BagError::Format(e.to_string()))
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
                    return Err(BagError::Format(format!(
                        "{}: subscribers did not keep up (send window full)",
                        item.topic
                    )));
                }
                message = data;
            }
            Err(e) => return Err(BagError::Format(format!("{}: DDS write failed: {e}", item.topic))),
        }
    }
}

fn matched<T: RosMessage>(writer: &rustdds::no_key::DataWriterCdr<T>, current: &mut usize) {
    *current = crate::ros::edge::matched_subscriptions(writer, *current);
}

/// Publishes the schedule over DDS (participant from `crate::ros`, QoS of `crate::ros::qos`). Stops early when
/// `stop` is set. `on_item` is called after each publication (progress).
pub fn play(
    path: &Path,
    options: &PlayOptions,
    stop: &AtomicBool,
    mut on_item: impl FnMut(&PlayItem),
) -> Result<PlayStats, BagError> {
    let items = schedule(path, &options.topics, options.rate)?;
    if items.is_empty() {
        return Err(BagError::Format(format!("{}: no input messages to play", path.display())));
    }
    let (ctx, _config) = crate::ros::context_from_env().map_err(|e| BagError::Format(e.to_string()))?;
    let mut names: Vec<(String, String)> = Vec::new();
    for item in &items {
        if !names.iter().any(|(n, _)| *n == item.topic) {
            names.push((item.topic.clone(), item.type_name.clone()));
        }
    }
    let mut writers: Vec<(String, Writer, usize)> = Vec::new();
    for (topic, type_name) in names {
        let writer = match type_name.as_str() {
            BatParams::TYPE_NAME => Writer::Bat(make_writer(&ctx, &topic, &crate::ros::qos::params_qos())?),
            BallParams::TYPE_NAME => Writer::Ball(make_writer(&ctx, &topic, &crate::ros::qos::params_qos())?),
            _ => Writer::Swing(make_writer(&ctx, &topic, &crate::ros::qos::swing_qos())?),
        };
        writers.push((topic, writer, 0));
    }
    if options.wait_subscribers > 0 {
        let start = Instant::now();
        loop {
            for (_, writer, count) in writers.iter_mut() {
                match writer {
                    Writer::Bat(w) => matched(w, count),
                    Writer::Ball(w) => matched(w, count),
                    Writer::Swing(w) => matched(w, count),
                }
            }
            if writers.iter().all(|(_, _, c)| *c >= options.wait_subscribers) {
                break;
            }
            if stop.load(Ordering::Relaxed) {
                return Ok(PlayStats::default());
            }
            if start.elapsed() >= options.timeout {
                let missing: Vec<&str> = writers
                    .iter()
                    .filter(|(_, _, c)| *c < options.wait_subscribers)
                    .map(|(t, _, _)| t.as_str())
                    .collect();
                return Err(BagError::Format(format!(
                    "no {} subscription(s) on {} within {:.1} s",
                    options.wait_subscribers,
                    missing.join(", "),
                    options.timeout.as_secs_f64()
                )));
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        // Our side saw the match first; give the subscribers' side of the handshake a moment (see `pub`).
        std::thread::sleep(Duration::from_millis(300));
    }
    let mut stats = PlayStats::default();
    'passes: loop {
        let start = Instant::now();
        for item in &items {
            let due = start + item.at;
            while Instant::now() < due {
                if stop.load(Ordering::Relaxed) {
                    break 'passes;
                }
                std::thread::sleep((due - Instant::now()).min(Duration::from_millis(20)));
            }
            if stop.load(Ordering::Relaxed) {
                break 'passes;
            }
            let Some((_, writer, _)) = writers.iter().find(|(t, _, _)| *t == item.topic) else { continue };
            match writer {
                Writer::Bat(w) => write_one(w, item, options.timeout, stop)?,
                Writer::Ball(w) => write_one(w, item, options.timeout, stop)?,
                Writer::Swing(w) => write_one(w, item, options.timeout, stop)?,
            }
            stats.published += 1;
            on_item(item);
        }
        stats.passes += 1;
        if !options.repeat {
            break;
        }
    }
    for (topic, writer, _) in &writers {
        let acked = match writer {
            Writer::Bat(w) => w.wait_for_acknowledgments(options.timeout),
            Writer::Ball(w) => w.wait_for_acknowledgments(options.timeout),
            Writer::Swing(w) => w.wait_for_acknowledgments(options.timeout),
        };
        if !matches!(acked, Ok(true)) {
            tracing::warn!("not every subscription on {topic} acknowledged everything within {:?}", options.timeout);
        }
    }
    // Readers drop untaken samples of a writer whose participant left: linger a moment (as `pub` does).
    std::thread::sleep(Duration::from_millis(500));
    Ok(stats)
}
