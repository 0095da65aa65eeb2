//! `bag play --foxglove [ADDR:]PORT`: serves a bag on a Foxglove WebSocket server ([`crate::foxglove`]) at
//! the recorded pace, with the protocol's playback controls (play, pause, seek, speed), so a recorded session
//! is watched in Foxglove's timeline.
//!
//! Every topic of the bag is served (or those of `--topics`, remapped as `--remap` says), with the schema and
//! CDR bytes the bag holds, each message at its log time. The server declares the bag's time range; a seek
//! goes on from the first message at or after the seek time, after re-sending, on each latched
//! (transient-local) topic, its last message before that time, so the bats and balls in force are there.
//! The position is sent to clients as the server's time (the `time` capability) about 20 times a second.
//!
//! Not every client can press play: `@foxglove/ws-protocol`'s client and Lichtblick have no playback
//! controls. A server started paused therefore starts playing by itself [`AUTOPLAY_AFTER`] after the first
//! subscription when no client has sent a playback request by then. `--delay` is waited before each pass and
//! `--loop` starts the bag over when it ends (a seek to the start: the latched topics' messages go out
//! again), until a client pauses or seeks.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

use foxglove::websocket::{PlaybackCommand, PlaybackControlRequest, PlaybackState, PlaybackStatus};

use crate::bag::reader::read_bag;
use crate::bag::{BagError, TopicInfo};
use crate::foxglove::{Bind, LiveServer, Playback, PlaybackHandler};

/// How often the position goes out as the server's time, and the longest the player sleeps.
pub const TICK: Duration = Duration::from_millis(50);

/// How long after the first subscription a paused server waits for a client to press play before it plays
/// by itself (for clients without playback controls).
pub const AUTOPLAY_AFTER: Duration = Duration::from_secs(2);

/// A bag's messages as served: topics (in first-seen order) and messages in log-time order.
#[derive(Debug, Clone, PartialEq)]
pub struct ServedBag {
    /// The served topics (remapped names), with the bag's schema and QoS.
    pub topics: Vec<TopicInfo>,
    /// (log time ns, index into `topics`, CDR bytes), sorted by log time (stable: recorded order kept).
    pub messages: Vec<(u64, usize, Vec<u8>)>,
}

impl ServedBag {
    /// Reads `path`: every topic, or only `only` (recorded names) when non-empty; each named as `rename` says.
    pub fn read(path: &Path, only: &[String], rename: impl Fn(&str) -> String) -> Result<ServedBag, BagError> {
        let mut topics: Vec<TopicInfo> = Vec::new();
        let mut recorded: Vec<String> = Vec::new();
        let mut messages = Vec::new();
        read_bag(path, |m| {
            let topic = &m.channel.topic;
            if !only.is_empty() && !only.contains(&topic.name) {
                return;
            }
            let index = match recorded.iter().position(|t| *t == topic.name) {
                Some(index) => index,
                None => {
                    recorded.push(topic.name.clone());
                    topics.push(TopicInfo { name: rename(&topic.name), ..topic.clone() });
                    topics.len() - 1
                }
            };
            messages.push((m.log_time_ns, index, m.data.to_vec()));
        })?;
        if let Some(missing) = only.iter().find(|t| !recorded.contains(t)) {
            return Err(BagError::Options(format!("--topics: {missing} is not in the bag")));
        }
        if messages.is_empty() {
            return Err(BagError::Format(format!("{}: no messages to serve", path.display())));
        }
        messages.sort_by_key(|(t, _, _)| *t);
        Ok(ServedBag { topics, messages })
    }

    /// First and last log time, ns since the Unix epoch.
    pub fn range(&self) -> (u64, u64) {
        let first = self.messages.first().map_or(0, |m| m.0);
        (first, self.messages.last().map_or(first, |m| m.0))
    }

    /// Index of the first message logged at or after `time_ns`.
    pub fn first_at(&self, time_ns: u64) -> usize {
        self.messages.partition_point(|(t, _, _)| *t < time_ns)
    }

    /// For each latched topic, its last message logged before `time_ns` (by index into `messages`).
    pub fn latched_before(&self, time_ns: u64) -> Vec<usize> {
        let end = self.first_at(time_ns);
        let mut last: Vec<Option<usize>> = vec![None; self.topics.len()];
        for (k, (_, topic, _)) in self.messages[..end].iter().enumerate() {
            if self.topics[*topic].qos.transient_local {
                last[*topic] = Some(k);
            }
        }
        let mut found: Vec<usize> = last.into_iter().flatten().collect();
        found.sort_unstable();
        found
    }
}

/// The playback position: bag time `anchor_bag` at wall time `anchor_wall`, advancing at `speed` while playing.
#[derive(Debug, Clone)]
pub struct Timeline {
    range: (u64, u64),
    playing: bool,
    speed: f64,
    anchor_wall: Instant,
    anchor_bag: u64,
    /// A seek not yet acted on by the player.
    seek: Option<u64>,
}

impl Timeline {
    /// At `start` (clamped to `range`), playing or paused, at `speed`.
    pub fn new(range: (u64, u64), start: u64, playing: bool, speed: f64) -> Timeline {
        let start = start.clamp(range.0, range.1);
        Timeline { range, playing, speed, anchor_wall: Instant::now(), anchor_bag: start, seek: Some(start) }
    }

    /// Bag time at wall time `now`, ns (never past the range's end).
    pub fn position(&self, now: Instant) -> u64 {
        if !self.playing {
            return self.anchor_bag;
        }
        let elapsed = crate::model::time::scaled(now.saturating_duration_since(self.anchor_wall), self.speed);
        self.anchor_bag.saturating_add(u64::try_from(elapsed.as_nanos()).unwrap_or(u64::MAX)).min(self.range.1)
    }

    /// Applies a client's request at wall time `now`; returns the state after it.
    pub fn apply(&mut self, request: &PlaybackControlRequest, now: Instant) -> PlaybackState {
        let mut position = self.position(now);
        if let Some(seek) = request.seek_time {
            position = seek.clamp(self.range.0, self.range.1);
            self.seek = Some(position);
        }
        let speed = f64::from(request.playback_speed);
        if speed > 0.0 && speed.is_finite() {
            self.speed = speed;
        }
        self.playing = request.playback_command == PlaybackCommand::Play;
        self.anchor_wall = now;
        self.anchor_bag = position;
        self.state(now, request.seek_time.is_some())
    }

    /// Stops at the end of the data.
    fn end(&mut self, now: Instant) {
        self.anchor_bag = self.position(now);
        self.anchor_wall = now;
        self.playing = false;
    }

    /// The protocol's playback state at `now`.
    pub fn state(&self, now: Instant, did_seek: bool) -> PlaybackState {
        let position = self.position(now);
        let status = if self.playing {
            PlaybackStatus::Playing
        } else if position >= self.range.1 {
            PlaybackStatus::Ended
        } else {
            PlaybackStatus::Paused
        };
        PlaybackState { status, current_time: position, playback_speed: self.speed as f32, did_seek, request_id: None }
    }
}

/// The timeline shared by the player and the server's control callback.
struct Controls {
    timeline: Mutex<Timeline>,
    changed: Condvar,
    /// Set by the first playback request: from then on a client drives playback.
    driven: AtomicBool,
}

impl PlaybackHandler for Controls {
    fn on_request(&self, request: PlaybackControlRequest) -> PlaybackState {
        self.driven.store(true, Ordering::Relaxed);
        let now = Instant::now();
        let state = match self.timeline.lock() {
            Ok(mut timeline) => timeline.apply(&request, now),
            Err(poisoned) => poisoned.into_inner().apply(&request, now),
        };
        self.changed.notify_all();
        state
    }
}

/// How to serve.
#[derive(Debug, Clone)]
pub struct ServeOptions {
    /// Where to listen.
    pub bind: Bind,
    /// Start playing at once (false: paused until a client presses play).
    pub playing: bool,
    /// Initial speed (the `-r` time scale).
    pub rate: f64,
    /// Start this far (recorded time) after the bag's first message.
    pub start_offset: Duration,
    /// Wait this long before each pass (`--delay`).
    pub delay: Duration,
    /// Start over at the end, until a client pauses or seeks (`--loop`).
    pub repeat: bool,
    /// Clients, handshakes and memory the server allows.
    pub limits: crate::foxglove::Limits,
}

/// Serves `bag` until `stop` is set; `on_ready` hears the port once the server listens. Returns the number of
/// messages handed to the server.
pub fn serve(
    bag: &ServedBag,
    options: &ServeOptions,
    stop: &AtomicBool,
    on_ready: impl FnOnce(u16),
) -> Result<u64, BagError> {
    let range = bag.range();
    crate::play::check_start_offset(options.start_offset, Duration::from_nanos(range.1 - range.0))?;
    let offset = u64::try_from(options.start_offset.as_nanos()).unwrap_or(u64::MAX);
    let start = range.0.saturating_add(offset);
    let controls = Arc::new(Controls {
        timeline: Mutex::new(Timeline::new(range, start, false, options.rate)),
        changed: Condvar::new(),
        driven: AtomicBool::new(false),
    });
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .map_err(|e| BagError::Options(format!("Foxglove server runtime: {e}")))?;
    let playback = Playback { range, handler: controls.clone() };
    let server = runtime
        .block_on(LiveServer::start_with(
            "sweetspot bag play",
            &options.bind,
            &bag.topics,
            Some(playback),
            options.limits,
        ))
        .map_err(BagError::Options)?;
    on_ready(server.port());
    let mut pacer = Pacer::new(bag, options, &controls, &server, start);
    while !stop.load(Ordering::Relaxed) && pacer.turn() {}
    let sent = pacer.sent;
    server.stop();
    Ok(sent)
}

/// Hands the bag's messages to the server at the pace of the shared timeline, and tells clients where it is.
struct Pacer<'a> {
    bag: &'a ServedBag,
    options: &'a ServeOptions,
    controls: &'a Controls,
    server: &'a LiveServer,
    range: (u64, u64),
    /// Where each pass starts (the start offset into the bag).
    start: u64,
    /// Index of the next message to send.
    next: usize,
    /// Messages handed to the server.
    sent: u64,
    last_tick: Instant,
    /// Whether clients were told of the end of the data (or a `--loop` pass already started over).
    ended_said: bool,
    /// When the next pass starts playing by itself: at once (after --delay) when playing, else once a
    /// subscription has waited AUTOPLAY_AFTER for a client to press play.
    autoplay_at: Option<Instant>,
    first_subscription: Option<Instant>,
}

impl<'a> Pacer<'a> {
    fn new(
        bag: &'a ServedBag,
        options: &'a ServeOptions,
        controls: &'a Controls,
        server: &'a LiveServer,
        start: u64,
    ) -> Pacer<'a> {
        Pacer {
            bag,
            options,
            controls,
            server,
            range: bag.range(),
            start,
            next: 0,
            sent: 0,
            last_tick: Instant::now() - TICK,
            ended_said: false,
            autoplay_at: options.playing.then(|| Instant::now() + options.delay),
            first_subscription: None,
        }
    }

    /// Sends what is due, then sleeps until the next message, the next tick or a control request; `false`
    /// once the timeline is unusable (its lock poisoned).
    fn turn(&mut self) -> bool {
        let now = Instant::now();
        let driven = self.controls.driven.load(Ordering::Relaxed);
        self.note_first_subscription(now);
        let controls = self.controls;
        let Ok(mut timeline) = controls.timeline.lock() else { return false };
        self.autoplay_when_due(&mut timeline, driven, now);
        let mut due = self.take_seek(&mut timeline);
        let position = timeline.position(now);
        if timeline.playing {
            while self.next < self.bag.messages.len() && self.bag.messages[self.next].0 <= position {
                due.push(self.next);
                self.next += 1;
            }
            self.ended_said = false;
        }
        self.stop_at_end(&mut timeline, position, now);
        let ended = self.unsaid_end(&timeline, position, now);
        let wait = self.until_next_message(&timeline, position);
        drop(timeline);
        self.send(due, ended, position, now);
        if let Ok(timeline) = controls.timeline.lock() {
            // Woken early by a control request.
            let _ = controls.changed.wait_timeout(timeline, wait.max(Duration::from_micros(200)));
        }
        true
    }

    fn note_first_subscription(&mut self, now: Instant) {
        if self.first_subscription.is_none() && self.server.counters().subscriptions > 0 {
            self.first_subscription = Some(now);
            if self.autoplay_at.is_none() {
                self.autoplay_at = Some(now + AUTOPLAY_AFTER + self.options.delay);
            }
        }
    }

    /// Starts playing when the autoplay time comes, unless a client drives playback by then.
    fn autoplay_when_due(&mut self, timeline: &mut Timeline, driven: bool, now: Instant) {
        if self.autoplay_at.is_some_and(|at| now >= at) {
            self.autoplay_at = None;
            if !driven {
                timeline.playing = true;
                timeline.anchor_wall = now;
            }
        }
    }

    /// Acts on a pending seek: goes on from there, after the latched topics' last messages before it
    /// (returned, to be sent).
    fn take_seek(&mut self, timeline: &mut Timeline) -> Vec<usize> {
        let mut due = Vec::new();
        if let Some(seek) = timeline.seek.take() {
            due.extend(self.bag.latched_before(seek));
            self.next = self.bag.first_at(seek);
            self.ended_said = false;
        }
        due
    }

    /// At the end of the data, stops; with `--loop` (until a client drives playback) seeks back to the start,
    /// to play again after --delay, no sooner than MIN_PASS after this pass started.
    fn stop_at_end(&mut self, timeline: &mut Timeline, position: u64, now: Instant) {
        if !(timeline.playing && self.next == self.bag.messages.len() && position >= self.range.1) {
            return;
        }
        timeline.end(now);
        if self.options.repeat && !self.controls.driven.load(Ordering::Relaxed) {
            // Over again from the start offset, after --delay, as `bag play -l` over DDS.
            let span = crate::model::time::scaled(
                Duration::from_nanos(self.range.1 - self.start.clamp(self.range.0, self.range.1)),
                1.0 / timeline.speed,
            );
            timeline.anchor_bag = self.start.clamp(self.range.0, self.range.1);
            timeline.seek = Some(timeline.anchor_bag);
            self.autoplay_at = Some(now + self.options.delay + crate::play::MIN_PASS.saturating_sub(span));
            self.ended_said = true;
        }
    }

    /// The "ended" state to tell clients, once, when paused at the end of the data.
    fn unsaid_end(&mut self, timeline: &Timeline, position: u64, now: Instant) -> Option<PlaybackState> {
        if !timeline.playing && position >= self.range.1 && !self.ended_said {
            self.ended_said = true;
            return Some(timeline.state(now, false));
        }
        None
    }

    /// Wall time until the next message is due (at most a tick).
    fn until_next_message(&self, timeline: &Timeline, position: u64) -> Duration {
        match self.bag.messages.get(self.next) {
            Some((t, _, _)) if timeline.playing => {
                let ahead = Duration::from_nanos(t.saturating_sub(position));
                crate::model::time::scaled(ahead, 1.0 / timeline.speed).min(TICK)
            }
            _ => TICK,
        }
    }

    /// Sends the `due` messages, the end of the data if `ended`, and the position once per tick.
    fn send(&mut self, due: Vec<usize>, ended: Option<PlaybackState>, position: u64, now: Instant) {
        for k in due {
            let (log_time, topic, cdr) = &self.bag.messages[k];
            self.server.send(*topic, cdr, *log_time);
            self.sent += 1;
        }
        if let Some(state) = ended {
            self.server.broadcast_playback_state(state);
        }
        if now.duration_since(self.last_tick) >= TICK {
            self.last_tick = now;
            self.server.broadcast_time(position);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(command: PlaybackCommand, speed: f32, seek: Option<u64>) -> PlaybackControlRequest {
        PlaybackControlRequest {
            playback_command: command,
            playback_speed: speed,
            seek_time: seek,
            request_id: "r".into(),
        }
    }

    #[test]
    fn the_timeline_pauses_seeks_and_scales_time() {
        let t0 = Instant::now();
        let mut line = Timeline::new((1_000, 11_000_000_000), 0, false, 1.0);
        assert_eq!(line.position(t0 + Duration::from_secs(5)), 1_000, "paused, clamped to the start");
        let state = line.apply(&request(PlaybackCommand::Play, 2.0, Some(5_000_000_000)), t0);
        assert_eq!((state.status, state.current_time, state.did_seek), (PlaybackStatus::Playing, 5_000_000_000, true));
        // 1 s of wall time at speed 2 is 2 s of bag time.
        assert_eq!(line.position(t0 + Duration::from_secs(1)), 7_000_000_000);
        let state = line.apply(&request(PlaybackCommand::Pause, 2.0, None), t0 + Duration::from_secs(1));
        assert_eq!((state.status, state.current_time), (PlaybackStatus::Paused, 7_000_000_000));
        assert_eq!(line.position(t0 + Duration::from_secs(9)), 7_000_000_000);
        // A speed of 0 (or NaN) keeps the last one; the position never passes the end.
        line.apply(&request(PlaybackCommand::Play, 0.0, None), t0 + Duration::from_secs(2));
        assert_eq!(line.position(t0 + Duration::from_secs(3)), 9_000_000_000);
        assert_eq!(line.position(t0 + Duration::from_secs(60)), 11_000_000_000);
        assert_eq!(line.apply(&request(PlaybackCommand::Play, 1.0, Some(u64::MAX)), t0).current_time, 11_000_000_000);
    }
}
