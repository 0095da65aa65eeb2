//! Counters and latency of a running node, shared by its threads, and their summary for `/diagnostics`.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use hdrhistogram::Histogram;

/// Everything the node counts. Cheap to update from any thread.
#[derive(Debug)]
pub struct NodeStats {
    /// Swings taken from DDS.
    pub swings_received: AtomicU64,
    /// Swings answered with status OK.
    pub swings_ok: AtomicU64,
    /// Swings answered with status REJECTED.
    pub swings_rejected: AtomicU64,
    /// Swings dropped because `queue_capacity` swings were already in flight, and answered DROPPED.
    pub swings_dropped: AtomicU64,
    /// Swings a publisher sent that never reached the node (gaps in its DDS sequence numbers: the reader's
    /// history overflowed, or the publisher's history replaced them before delivery).
    pub swings_lost_in_transport: AtomicU64,
    /// Samples on an input topic that could not be decoded (malformed CDR, another type).
    pub samples_unreadable: AtomicU64,
    /// BatParams/BallParams accepted.
    pub params_accepted: AtomicU64,
    /// BatParams/BallParams refused (the previous params stay in force).
    pub params_rejected: AtomicU64,
    /// Swings whose bat modes were already computed.
    pub mode_cache_hits: AtomicU64,
    /// Mode computations (first use of a bat, or after its params changed).
    pub mode_cache_misses: AtomicU64,
    /// Swings whose answer DDS refused to send: a computed one (send window full past its blocking time), or
    /// a DROPPED one (send window full at that moment: the receive loop does not wait).
    pub publish_failures: AtomicU64,
    /// Swings answered on the receive task because the pipeline was idle (no worker or sequencer hop).
    pub swings_answered_inline: AtomicU64,
    /// ModalEnergies published (they are recorded for every OK swing, published only while subscribed).
    pub modal_energies_published: AtomicU64,
    /// ModalEnergies DDS refused to send (their swing's ExitVelocity may still have gone out: the swing is
    /// counted by its answer, this apart).
    pub modal_energies_unsent: AtomicU64,
    /// Receive-to-publish latency, µs.
    latency_us: Mutex<Histogram<u64>>,
    started: Instant,
}

/// A consistent copy of the counters.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StatsSnapshot {
    /// See [`NodeStats`].
    pub swings_received: u64,
    /// See [`NodeStats`].
    pub swings_ok: u64,
    /// See [`NodeStats`].
    pub swings_rejected: u64,
    /// See [`NodeStats`].
    pub swings_dropped: u64,
    /// See [`NodeStats`].
    pub swings_lost_in_transport: u64,
    /// Undecodable input samples.
    pub samples_unreadable: u64,
    /// See [`NodeStats`].
    pub params_accepted: u64,
    /// See [`NodeStats`].
    pub params_rejected: u64,
    /// See [`NodeStats`].
    pub mode_cache_hits: u64,
    /// See [`NodeStats`].
    pub mode_cache_misses: u64,
    /// See [`NodeStats`].
    pub publish_failures: u64,
    /// Swings answered on the receive task, since start.
    pub swings_answered_inline: u64,
    /// ModalEnergies published, since start.
    pub modal_energies_published: u64,
    /// ModalEnergies that could not be published, since start.
    pub modal_energies_unsent: u64,
    /// Swings queued, computing or waiting for in-order publication.
    pub in_flight: u64,
    /// Bats held by the registry now (filled in by the runtime, which owns the registry).
    pub bats_cached: u64,
    /// Bats forgotten to stay within `max_bats`, since start.
    pub bats_evicted: u64,
    /// Balls held by the registry now.
    pub balls_cached: u64,
    /// Balls forgotten to stay within `max_balls`, since start.
    pub balls_evicted: u64,
    /// Median receive-to-publish latency, µs (0 before the first swing).
    pub latency_p50_us: u64,
    /// 99th-percentile latency, µs.
    pub latency_p99_us: u64,
    /// Largest latency, µs.
    pub latency_max_us: u64,
    /// Time since start, s.
    pub uptime_s: f64,
}

impl StatsSnapshot {
    /// Swings answered (OK or REJECTED).
    pub fn swings_answered(&self) -> u64 {
        self.swings_ok + self.swings_rejected
    }
}

impl Default for NodeStats {
    fn default() -> Self {
        NodeStats::new()
    }
}

impl NodeStats {
    /// All zero, uptime counted from now.
    pub fn new() -> NodeStats {
        NodeStats {
            swings_received: AtomicU64::new(0),
            swings_ok: AtomicU64::new(0),
            swings_rejected: AtomicU64::new(0),
            swings_dropped: AtomicU64::new(0),
            swings_lost_in_transport: AtomicU64::new(0),
            samples_unreadable: AtomicU64::new(0),
            params_accepted: AtomicU64::new(0),
            params_rejected: AtomicU64::new(0),
            mode_cache_hits: AtomicU64::new(0),
            mode_cache_misses: AtomicU64::new(0),
            publish_failures: AtomicU64::new(0),
            swings_answered_inline: AtomicU64::new(0),
            modal_energies_published: AtomicU64::new(0),
            modal_energies_unsent: AtomicU64::new(0),
            // 1 µs … 1 h at 3 significant digits: a fixed ~200 kB, never grows.
            latency_us: Mutex::new(Histogram::new_with_bounds(1, 3_600_000_000, 3).expect("static bounds are valid")),
            started: Instant::now(),
        }
    }

    /// Adds one to `counter`.
    pub fn bump(counter: &AtomicU64) {
        counter.fetch_add(1, Ordering::Relaxed);
    }

    /// Records one receive-to-publish latency.
    pub fn record_latency(&self, latency: Duration) {
        let us = (latency.as_micros() as u64).clamp(1, 3_600_000_000);
        if let Ok(mut h) = self.latency_us.lock() {
            // Clamped into the bounds above, so this cannot fail.
            let _ = h.record(us);
        }
    }

    /// How many latencies have been recorded (one per delivered swing).
    pub fn latency_count(&self) -> u64 {
        self.latency_us.lock().map(|h| h.len()).unwrap_or(0)
    }

    /// A copy of every counter; `in_flight` is supplied by the pipeline.
    pub fn snapshot(&self, in_flight: u64) -> StatsSnapshot {
        let load = |c: &AtomicU64| c.load(Ordering::Relaxed);
        let (p50, p99, max) = match self.latency_us.lock() {
            Ok(h) if !h.is_empty() => (h.value_at_quantile(0.5), h.value_at_quantile(0.99), h.max()),
            _ => (0, 0, 0),
        };
        StatsSnapshot {
            swings_received: load(&self.swings_received),
            swings_ok: load(&self.swings_ok),
            swings_rejected: load(&self.swings_rejected),
            swings_dropped: load(&self.swings_dropped),
            swings_lost_in_transport: load(&self.swings_lost_in_transport),
            samples_unreadable: load(&self.samples_unreadable),
            params_accepted: load(&self.params_accepted),
            params_rejected: load(&self.params_rejected),
            mode_cache_hits: load(&self.mode_cache_hits),
            mode_cache_misses: load(&self.mode_cache_misses),
            publish_failures: load(&self.publish_failures),
            swings_answered_inline: load(&self.swings_answered_inline),
            modal_energies_published: load(&self.modal_energies_published),
            modal_energies_unsent: load(&self.modal_energies_unsent),
            in_flight,
            bats_cached: 0,
            bats_evicted: 0,
            balls_cached: 0,
            balls_evicted: 0,
            latency_p50_us: p50,
            latency_p99_us: p99,
            latency_max_us: max,
            uptime_s: self.started.elapsed().as_secs_f64(),
        }
    }
}

/// State of the recorder as reported on `/diagnostics`.
#[derive(Debug, Clone, PartialEq)]
pub enum RecorderState {
    /// `record:=false` or `--no-record`.
    Off,
    /// Writing to this directory.
    Recording { dir: String, written: u64, dropped: u64, bytes: u64 },
    /// Could not start or stopped on an error; the node keeps computing and publishing.
    Failed { dir: String, error: String, written: u64, dropped: u64 },
}

/// What the node's outputs besides DDS report on `/diagnostics`: the recorder and the Foxglove server.
#[derive(Debug, Clone, PartialEq)]
pub struct TapeState {
    /// The recorder.
    pub recorder: RecorderState,
    /// The Foxglove server's counters, when one runs.
    pub live: Option<crate::foxglove::LiveCounters>,
}

impl From<RecorderState> for TapeState {
    fn from(recorder: RecorderState) -> TapeState {
        TapeState { recorder, live: None }
    }
}

/// Severity of a diagnostics report (values of diagnostic_msgs/DiagnosticStatus).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Health {
    /// Everything answered, nothing dropped since the last report.
    Ok = 0,
    /// Swings dropped or results unsent since the last report, or the recorder is dropping.
    Warn = 1,
    /// The recorder failed.
    Error = 2,
}

/// One `/diagnostics` status: level, one-line message, and key/value pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct HealthReport {
    /// Severity.
    pub level: Health,
    /// One-line summary.
    pub message: String,
    /// Key/value pairs, stable keys.
    pub values: Vec<(String, String)>,
}

/// Summarises `now` against the previous report `before` (for "since the last report" warnings).
pub fn health_report(now: &StatsSnapshot, before: &StatsSnapshot, tape: &TapeState) -> HealthReport {
    let (mut level, mut message) = since_last_report(now, before);
    let mut values = counter_values(now);
    if let Some(live) = &tape.live {
        // The SDK drops a slow client's oldest queued messages without counting them (see crate::foxglove):
        // what is reported is what the server sees, and the queue bound that limits what a client can lose.
        values.push(("foxglove_clients".into(), live.clients.to_string()));
        values.push(("foxglove_subscriptions".into(), live.subscriptions.to_string()));
        values.push(("foxglove_messages_served".into(), live.served.to_string()));
        values.push(("foxglove_client_backlog".into(), live.backlog.to_string()));
    }
    if let Some((worse, why)) = recorder_health(&tape.recorder, &mut values) {
        if worse == Health::Error || level == Health::Ok {
            (level, message) = (worse, why);
        }
    }
    HealthReport { level, message, values }
}

/// The level and message of what went wrong since the previous report (drops, losses, unsent results,
/// unreadable samples, evictions), or OK with the count of swings answered.
fn since_last_report(now: &StatsSnapshot, before: &StatsSnapshot) -> (Health, String) {
    let new_drops = now.swings_dropped.saturating_sub(before.swings_dropped);
    let new_losses = now.swings_lost_in_transport.saturating_sub(before.swings_lost_in_transport);
    let new_publish_failures = now.publish_failures.saturating_sub(before.publish_failures);
    let new_unreadable = now.samples_unreadable.saturating_sub(before.samples_unreadable);
    let new_evictions =
        (now.bats_evicted + now.balls_evicted).saturating_sub(before.bats_evicted + before.balls_evicted);
    let (mut level, mut message) = (Health::Ok, format!("{} swings answered", now.swings_answered()));
    if new_drops > 0 || new_publish_failures > 0 || new_losses > 0 || new_unreadable > 0 {
        level = Health::Warn;
        message = format!(
            "since the last report: {new_drops} swings dropped (queue full), {new_losses} lost in transport, \
             {new_publish_failures} results unsent, {new_unreadable} input samples unreadable"
        );
    }
    if new_evictions > 0 {
        // Swings naming a forgotten bat or ball are REJECTED (or a preset is solved again): worth a look.
        level = Health::Warn;
        let evicted = format!(
            "{} bats and {} balls forgotten (max_bats / max_balls reached)",
            now.bats_evicted.saturating_sub(before.bats_evicted),
            now.balls_evicted.saturating_sub(before.balls_evicted)
        );
        message = if message.starts_with("since the last report") {
            format!("{message}, {evicted}")
        } else {
            format!("since the last report: {evicted}")
        };
    }
    (level, message)
}

/// The counters as `/diagnostics` key/value pairs.
fn counter_values(now: &StatsSnapshot) -> Vec<(String, String)> {
    vec![
        ("swings_received".into(), now.swings_received.to_string()),
        ("swings_processed".into(), now.swings_ok.to_string()),
        ("swings_rejected".into(), now.swings_rejected.to_string()),
        ("swings_dropped".into(), now.swings_dropped.to_string()),
        ("swings_lost_in_transport".into(), now.swings_lost_in_transport.to_string()),
        ("samples_unreadable".into(), now.samples_unreadable.to_string()),
        ("swings_in_flight".into(), now.in_flight.to_string()),
        ("params_accepted".into(), now.params_accepted.to_string()),
        ("params_rejected".into(), now.params_rejected.to_string()),
        ("publish_failures".into(), now.publish_failures.to_string()),
        ("swings_answered_inline".into(), now.swings_answered_inline.to_string()),
        ("modal_energies_published".into(), now.modal_energies_published.to_string()),
        ("modal_energies_unsent".into(), now.modal_energies_unsent.to_string()),
        ("latency_p50_us".into(), now.latency_p50_us.to_string()),
        ("latency_p99_us".into(), now.latency_p99_us.to_string()),
        ("latency_max_us".into(), now.latency_max_us.to_string()),
        ("mode_cache_hits".into(), now.mode_cache_hits.to_string()),
        ("mode_cache_misses".into(), now.mode_cache_misses.to_string()),
        ("bats_cached".into(), now.bats_cached.to_string()),
        ("bats_evicted".into(), now.bats_evicted.to_string()),
        ("balls_cached".into(), now.balls_cached.to_string()),
        ("balls_evicted".into(), now.balls_evicted.to_string()),
        ("uptime_s".into(), format!("{:.1}", now.uptime_s)),
    ]
}

/// The recorder's values pushed onto `values`, and the level and message it calls for: WARN when it dropped
/// messages (only over an OK report), ERROR when it failed.
fn recorder_health(recorder: &RecorderState, values: &mut Vec<(String, String)>) -> Option<(Health, String)> {
    match recorder {
        RecorderState::Off => {
            values.push(("recorder_state".into(), "off".into()));
            None
        }
        RecorderState::Recording { dir, written, dropped, bytes } => {
            values.push(("recorder_state".into(), "recording".into()));
            values.push(("recorder_path".into(), dir.clone()));
            values.push(("recorder_written".into(), written.to_string()));
            values.push(("recorder_dropped".into(), dropped.to_string()));
            values.push(("recorder_bytes".into(), bytes.to_string()));
            (*dropped > 0).then(|| (Health::Warn, format!("recorder dropped {dropped} messages")))
        }
        RecorderState::Failed { dir, error, written, dropped } => {
            values.push(("recorder_state".into(), "failed".into()));
            values.push(("recorder_path".into(), dir.clone()));
            values.push(("recorder_error".into(), error.clone()));
            values.push(("recorder_written".into(), written.to_string()));
            values.push(("recorder_dropped".into(), dropped.to_string()));
            Some((Health::Error, format!("recording failed ({error}); still computing and publishing")))
        }
    }
}

/// Raises `report` to at least WARN for another node with our name on the graph, `warning` first in its message.
pub fn flag_namesakes(report: &mut HealthReport, warning: &str) {
    if report.level == Health::Ok {
        report.level = Health::Warn;
    }
    report.message = format!("{warning}; {}", report.message);
    report.values.push(("duplicate_node_name".into(), "true".into()));
}

/// Makes `report` an ERROR saying why: the DDS machinery stopped and the node is shutting down.
pub fn flag_dds_stopped(report: &mut HealthReport, error: &str) {
    report.level = Health::Error;
    report.message = format!("{error}; {}", report.message);
    report.values.push(("dds_alive".into(), "false".into()));
}

/// Counts gaps in each publisher's DDS sequence numbers: samples it wrote that never reached this reader.
/// Remembers at most `capacity` publishers (the least recently heard forgotten first), so publishers that come
/// and go cannot grow it for ever; a forgotten publisher that comes back starts afresh (its first sample
/// counts nothing, as for a late joiner).
#[derive(Debug)]
pub struct GapCounter<K> {
    last: std::collections::HashMap<K, (i64, u64)>,
    capacity: usize,
    clock: u64,
    forgotten: u64,
}

impl<K: std::hash::Hash + Eq + Clone> Default for GapCounter<K> {
    fn default() -> Self {
        GapCounter::new()
    }
}

impl<K: std::hash::Hash + Eq + Clone> GapCounter<K> {
    /// Publishers remembered by [`GapCounter::new`]: far more than a lab's writers on one topic.
    pub const DEFAULT_CAPACITY: usize = 1024;

    /// No publisher seen yet; remembers up to [`GapCounter::DEFAULT_CAPACITY`] publishers.
    pub fn new() -> Self {
        GapCounter::with_capacity(Self::DEFAULT_CAPACITY)
    }

    /// No publisher seen yet; remembers up to `capacity` (at least 1) publishers.
    pub fn with_capacity(capacity: usize) -> Self {
        GapCounter { last: std::collections::HashMap::new(), capacity: capacity.max(1), clock: 0, forgotten: 0 }
    }

    /// Notes sample `sequence` from `publisher`; returns how many of its samples were skipped since the last.
    /// The first sample of a publisher counts nothing (a late joiner cannot know what came before).
    pub fn observe(&mut self, publisher: K, sequence: i64) -> u64 {
        self.clock += 1;
        if !self.last.contains_key(&publisher) && self.last.len() >= self.capacity {
            // Full: forget the publisher heard from least recently (a linear scan, only when a new one arrives).
            if let Some(oldest) = self.last.iter().min_by_key(|(_, (_, used))| *used).map(|(k, _)| k.clone()) {
                self.last.remove(&oldest);
                self.forgotten += 1;
            }
        }
        match self.last.insert(publisher, (sequence, self.clock)) {
            Some((previous, _)) if sequence > previous + 1 => (sequence - previous - 1) as u64,
            _ => 0,
        }
    }

    /// Publishers remembered now.
    pub fn publishers(&self) -> usize {
        self.last.len()
    }

    /// Publishers forgotten to stay within the capacity, since creation.
    pub fn forgotten(&self) -> u64 {
        self.forgotten
    }
}

/// Lets a repeated warning through at most once per `period`, counting what it held back.
#[derive(Debug)]
pub struct RateLimiter {
    period: Duration,
    state: Mutex<(Option<Instant>, u64)>,
}

impl RateLimiter {
    /// At most one message per `period`.
    pub fn new(period: Duration) -> RateLimiter {
        RateLimiter { period, state: Mutex::new((None, 0)) }
    }

    /// `Some(n)` if a message may go out now, `n` being how many were suppressed since the last one.
    pub fn allow(&self, now: Instant) -> Option<u64> {
        let mut state = self.state.lock().ok()?;
        let (last, suppressed) = &mut *state;
        match last {
            Some(t) if now.duration_since(*t) < self.period => {
                *suppressed += 1;
                None
            }
            _ => {
                *last = Some(now);
                Some(std::mem::take(suppressed))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latency_percentiles_follow_recorded_values() {
        let s = NodeStats::new();
        assert_eq!(s.snapshot(0).latency_p50_us, 0);
        for us in 1..=100u64 {
            s.record_latency(Duration::from_micros(us * 10));
        }
        let snap = s.snapshot(3);
        assert!((495..=505).contains(&snap.latency_p50_us), "{}", snap.latency_p50_us);
        assert!((985..=995).contains(&snap.latency_p99_us), "{}", snap.latency_p99_us);
        assert!((999..=1001).contains(&snap.latency_max_us), "{}", snap.latency_max_us);
        assert_eq!(snap.in_flight, 3);
    }

    #[test]
    fn report_warns_on_new_drops_only_and_errors_on_recorder_failure() {
        let before = StatsSnapshot { swings_dropped: 5, ..Default::default() };
        let now = StatsSnapshot { swings_dropped: 5, swings_ok: 7, swings_rejected: 1, ..Default::default() };
        let r = health_report(&now, &before, &RecorderState::Off.into());
        assert_eq!(r.level, Health::Ok);
        assert!(r.values.contains(&("swings_processed".into(), "7".into())));
        assert!(r.values.contains(&("recorder_state".into(), "off".into())));
        let later = StatsSnapshot { swings_dropped: 9, ..now.clone() };
        let r = health_report(&later, &now, &RecorderState::Off.into());
        assert_eq!(r.level, Health::Warn);
        assert!(r.message.contains("4 swings dropped"), "{}", r.message);
        let lost = StatsSnapshot { swings_lost_in_transport: 2, ..now.clone() };
        let r = health_report(&lost, &now, &RecorderState::Off.into());
        assert_eq!(r.level, Health::Warn);
        assert!(r.message.contains("2 lost in transport"), "{}", r.message);
        let evicted = StatsSnapshot { bats_evicted: 3, bats_cached: 64, ..now.clone() };
        let r = health_report(&evicted, &now, &RecorderState::Off.into());
        assert_eq!(r.level, Health::Warn);
        assert!(r.message.contains("3 bats and 0 balls forgotten"), "{}", r.message);
        assert!(r.values.contains(&("bats_evicted".into(), "3".into())));
        assert!(r.values.contains(&("bats_cached".into(), "64".into())));
        assert_eq!(health_report(&evicted, &evicted, &RecorderState::Off.into()).level, Health::Ok);
        let failed = RecorderState::Failed { dir: "/x".into(), error: "disk full".into(), written: 3, dropped: 1 };
        let r = health_report(&now, &now, &failed.clone().into());
        assert_eq!(r.level, Health::Error);
        assert!(r.message.contains("disk full"));
    }

    #[test]
    fn a_namesake_warns_and_a_stopped_dds_is_an_error() {
        let quiet = StatsSnapshot::default();
        let mut r = health_report(&quiet, &quiet, &RecorderState::Off.into());
        assert_eq!(r.level, Health::Ok);
        flag_namesakes(&mut r, "another node named /sweetspot");
        assert_eq!(r.level, Health::Warn);
        assert!(r.message.starts_with("another node named /sweetspot"), "{}", r.message);
        assert!(r.values.contains(&("duplicate_node_name".into(), "true".into())));
        flag_dds_stopped(&mut r, "the DDS event loop stopped");
        assert_eq!((r.level, r.level as u8), (Health::Error, 2), "diagnostic_msgs ERROR = 2");
        assert!(r.message.starts_with("the DDS event loop stopped"), "{}", r.message);
        // A recorder failure is an ERROR already; a namesake does not lower it.
        let failed = RecorderState::Failed { dir: "/x".into(), error: "disk full".into(), written: 0, dropped: 0 };
        let mut r = health_report(&quiet, &quiet, &failed.clone().into());
        flag_namesakes(&mut r, "another node");
        assert_eq!(r.level, Health::Error);
    }

    #[test]
    fn gaps_in_sequence_numbers_are_counted_per_publisher() {
        let mut g = GapCounter::new();
        assert_eq!(g.observe("a", 5), 0, "first sample of a publisher");
        assert_eq!(g.observe("a", 6), 0);
        assert_eq!(g.observe("b", 1), 0);
        assert_eq!(g.observe("a", 10), 3);
        assert_eq!(g.observe("b", 2), 0);
        assert_eq!(g.observe("a", 10), 0, "a duplicate is not a gap");
    }

    #[test]
    fn gap_counter_remembers_a_bounded_number_of_publishers() {
        let mut g = GapCounter::with_capacity(4);
        for publisher in 0..1000u32 {
            assert_eq!(g.observe(publisher, 1), 0);
        }
        assert_eq!((g.publishers(), g.forgotten()), (4, 996));
        // The publishers heard from recently are still tracked; a returning forgotten one starts afresh.
        assert_eq!(g.observe(999, 5), 3);
        assert_eq!(g.observe(0, 9), 0);
        assert_eq!(g.publishers(), 4);
    }

    #[test]
    fn rate_limiter_counts_suppressed_messages() {
        let l = RateLimiter::new(Duration::from_secs(5));
        let t0 = Instant::now();
        assert_eq!(l.allow(t0), Some(0));
        assert_eq!(l.allow(t0 + Duration::from_secs(1)), None);
        assert_eq!(l.allow(t0 + Duration::from_secs(2)), None);
        assert_eq!(l.allow(t0 + Duration::from_secs(6)), Some(2));
    }
}
