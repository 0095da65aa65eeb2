//! How results leave the node: its publishers, its log lines (rosout + tracing), the sink that publishes and
//! records answers in swing order, and whether anyone listens to ModalEnergies.

use crate::model::time::RosTime;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use futures::FutureExt as _;
use ros2_client::ros2::LogLevel;
use ros2_client::rosout::RosoutRaw;
use ros2_client::{NodeLoggingHandle, Publisher};

use crate::msgs::diagnostic_msgs::msg::DiagnosticArray;
use crate::msgs::rcl_interfaces::msg::Log as RosoutLine;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, SweetSpot, Swing};
use crate::msgs::visualization_msgs::msg::MarkerArray;

use super::pipeline::{Outcome, ResultSink};
use super::recording::{Recorded, Tape};
use super::stats::{NodeStats, RateLimiter};

/// The node's publishers.
pub struct Outputs {
    /// ExitVelocity out (shared with the pipeline's sink).
    pub exit_velocity: Arc<Publisher<ExitVelocity>>,
    /// ModalEnergies out (shared with the pipeline's sink).
    pub modal_energies: Arc<Publisher<ModalEnergies>>,
    /// Whether `modal_energies` has a listener.
    pub energies_listeners: EnergiesListeners,
    /// swing_scene out, with the `swing_scene` parameter only.
    pub swing_scene: Option<Arc<Publisher<MarkerArray>>>,
    /// SweetSpot out.
    pub sweet_spot: Publisher<SweetSpot>,
    /// DiagnosticArray out.
    pub diagnostics: Publisher<DiagnosticArray>,
}

impl Outputs {
    /// The sink that publishes answers (and records them on `tape`) for the pipeline.
    pub fn sink(
        &self,
        tape: &Arc<Tape>,
        stats: &Arc<NodeStats>,
        failures: &PublishFailures,
        live_scene_hz: f64,
    ) -> DdsSink {
        let out = DdsAnswers {
            exit_velocity: Arc::clone(&self.exit_velocity),
            modal_energies: Arc::clone(&self.modal_energies),
            energies_listened: Arc::clone(&self.energies_listeners.flag),
            swing_scene: self.swing_scene.clone(),
            failures: failures.clone(),
        };
        DdsSink {
            out,
            tape: Arc::clone(tape),
            stats: Arc::clone(stats),
            live_scenes: SceneThrottle::per_second(live_scene_hz),
        }
    }

    /// Re-checks whether `modal_energies` has a matched subscription (see [`EnergiesListeners`]).
    pub fn refresh_energies_listeners(&self, node: &ros2_client::Node) {
        self.energies_listeners.refresh(&self.modal_energies, node);
    }
}

/// rosout + tracing (+ the Foxglove server's `/rosout`), from any thread.
#[derive(Clone)]
pub struct Log {
    handle: Arc<NodeLoggingHandle>,
    rosout: bool,
    /// Where the lines are also served live once the Foxglove server runs (shared by every clone).
    live: Arc<OnceLock<Arc<Tape>>>,
}

impl Log {
    /// Logs to rosout (the node's handle; `rosout` false: tracing only) and tracing.
    pub fn new(handle: NodeLoggingHandle, rosout: bool) -> Log {
        Log { handle: Arc::new(handle), rosout, live: Arc::new(OnceLock::new()) }
    }

    /// Also serves every later line, as rcl_interfaces/Log, on `tape`'s Foxglove server (if it has one);
    /// `--disable-rosout-logs` turns off the DDS topic only.
    pub fn serve_on(&self, tape: Arc<Tape>) {
        if tape.live_port().is_some() {
            let _ = self.live.set(tape);
        }
    }

    fn log(&self, level: LogLevel, message: &str) {
        // Our own tracing line (target `sweetspot`), and the same text on /rosout for ROS tools.
        match level {
            LogLevel::Fatal | LogLevel::Error => tracing::error!("{message}"),
            LogLevel::Warn => tracing::warn!("{message}"),
            LogLevel::Info => tracing::info!("{message}"),
            LogLevel::Debug => tracing::debug!("{message}"),
        }
        self.to_ros(level, message);
    }

    /// The line on `/rosout` (and the Foxglove server's) only, not on the terminal.
    fn to_ros(&self, level: LogLevel, message: &str) {
        let stamp = ros2_client::builtin_interfaces::Time::now();
        let (file, line) = (file!(), line!());
        if let Some(tape) = self.live.get() {
            // The message ros2-client's rosout_raw publishes below, field for field.
            let ns = u64::try_from(stamp.to_nanos()).unwrap_or(0);
            let line = RosoutLine {
                stamp: crate::msgs::builtin_interfaces::msg::Time::from_unix_ns(ns),
                level: level as u8,
                name: self.handle.base_name().to_string(),
                msg: message.to_string(),
                file: file.to_string(),
                function: "sweetspot::node".to_string(),
                line,
            };
            tape.record(Recorded::Rosout, &line, ns, ns);
        }
        if self.rosout {
            self.handle.rosout_raw(stamp, level, self.handle.base_name(), message, file, "sweetspot::node", line);
        }
    }

    /// An info line.
    pub fn info(&self, m: &str) {
        self.log(LogLevel::Info, m)
    }

    /// An info line for ROS tools only (`/rosout`, the Foxglove server): the caller prints it on the terminal
    /// itself, once, whatever the log level.
    pub fn info_to_ros(&self, m: &str) {
        self.to_ros(LogLevel::Info, m)
    }

    /// A warning.
    pub fn warn(&self, m: &str) {
        self.log(LogLevel::Warn, m)
    }

    /// An error.
    pub fn error(&self, m: &str) {
        self.log(LogLevel::Error, m)
    }
}

/// Logs failed publishes of answers (rate-limited: at most one line every 5 s, with the count of those
/// suppressed), naming what could not be sent and why.
#[derive(Clone)]
pub struct PublishFailures {
    log: Log,
    limiter: Arc<RateLimiter>,
}

impl PublishFailures {
    /// Reports through `log`.
    pub fn new(log: Log) -> PublishFailures {
        PublishFailures { log, limiter: Arc::new(RateLimiter::new(Duration::from_secs(5))) }
    }

    /// `what` (e.g. "the ExitVelocity of swing 12") could not be published because of `error`.
    pub fn report<D>(&self, what: &str, error: &ros2_client::WriteError<D>) {
        if let Some(suppressed) = self.limiter.allow(Instant::now()) {
            self.log.warn(&publish_failure_text(what, error, suppressed));
        }
    }
}

/// The warning for a failed publish: what, DDS's reason, and what it usually means.
pub fn publish_failure_text<D>(what: &str, error: &ros2_client::WriteError<D>, suppressed: u64) -> String {
    use ros2_client::WriteError;
    let meaning = match error {
        WriteError::WouldBlock { .. } => {
            ": the reliable send window stayed full (a subscriber that does not acknowledge, or a send socket \
             that cannot drain)"
        }
        WriteError::Poisoned { .. } | WriteError::Internal { .. } => ": the DDS machinery is failing",
        WriteError::Serialization { .. } | WriteError::Io(_) | WriteError::Middleware { .. } => "",
    };
    format!("{what} could not be published: {error}{meaning}; {suppressed} more publish failures since the last such report")
}

/// Where the sink sends answers: the node's publishers ([`DdsAnswers`]), or a test's.
pub trait AnswerOut: Send + 'static {
    /// Whether ModalEnergies has a listener (published only then).
    fn energies_listened(&self) -> bool;
    /// Publishes a swing's ModalEnergies.
    fn publish_energies(&self, message: ModalEnergies) -> Result<(), ros2_client::WriteError<()>>;
    /// Publishes a swing's ExitVelocity (its answer).
    fn publish_answer(&self, message: ExitVelocity) -> Result<(), ros2_client::WriteError<()>>;
    /// Reports (rate-limited) that `what` could not be published.
    fn report_failure(&self, what: &str, error: &ros2_client::WriteError<()>);
    /// Whether swing scenes go out over DDS (the `swing_scene` parameter).
    fn scenes_published(&self) -> bool {
        false
    }
    /// Publishes a swing's scene.
    fn publish_scene(&self, _message: MarkerArray) -> Result<(), ros2_client::WriteError<()>> {
        Ok(())
    }
}

/// The node's answer publishers.
pub struct DdsAnswers {
    /// ExitVelocity out.
    exit_velocity: Arc<Publisher<ExitVelocity>>,
    /// ModalEnergies out.
    modal_energies: Arc<Publisher<ModalEnergies>>,
    /// Whether `modal_energies` has a matched subscription (see [`EnergiesListeners`]).
    energies_listened: Arc<AtomicBool>,
    /// swing_scene out, with the `swing_scene` parameter only.
    swing_scene: Option<Arc<Publisher<MarkerArray>>>,
    /// Where failed publishes are reported.
    failures: PublishFailures,
}

impl AnswerOut for DdsAnswers {
    fn energies_listened(&self) -> bool {
        self.energies_listened.load(Ordering::Relaxed)
    }

    fn publish_energies(&self, message: ModalEnergies) -> Result<(), ros2_client::WriteError<()>> {
        self.modal_energies.publish(message).map_err(ros2_client::WriteError::forget_data)
    }

    fn publish_answer(&self, message: ExitVelocity) -> Result<(), ros2_client::WriteError<()>> {
        self.exit_velocity.publish(message).map_err(ros2_client::WriteError::forget_data)
    }

    fn report_failure(&self, what: &str, error: &ros2_client::WriteError<()>) {
        self.failures.report(what, error);
    }

    fn scenes_published(&self) -> bool {
        self.swing_scene.is_some()
    }

    fn publish_scene(&self, message: MarkerArray) -> Result<(), ros2_client::WriteError<()>> {
        match &self.swing_scene {
            Some(publisher) => publisher.publish(message).map_err(ros2_client::WriteError::forget_data),
            None => Ok(()),
        }
    }
}

/// Publishes and records results in swing order (on the pipeline's sequencer thread, or inline on the
/// receive task when the pipeline is idle).
pub struct DdsSink<O: AnswerOut = DdsAnswers> {
    /// The publishers.
    out: O,
    /// The recording.
    tape: Arc<Tape>,
    /// The node's counters.
    stats: Arc<NodeStats>,
    /// When a scene is next due to live clients.
    live_scenes: SceneThrottle,
}

/// At most one event per period: the live view's scenes (`swing_scene_live_hz`).
#[derive(Debug, Clone, Copy, Default)]
pub struct SceneThrottle {
    /// None: every event.
    period: Option<Duration>,
    /// When the last one went out.
    last: Option<Instant>,
}

impl SceneThrottle {
    /// At most `hz` events per second; 0 (or anything not positive and finite) = every event.
    pub fn per_second(hz: f64) -> SceneThrottle {
        let period = (hz.is_finite() && hz > 0.0).then(|| Duration::from_secs_f64(1.0 / hz));
        SceneThrottle { period, last: None }
    }

    /// Whether an event at `now` may go out; if so, it counts as the last one.
    pub fn due(&mut self, now: Instant) -> bool {
        let due = match (self.period, self.last) {
            (Some(period), Some(last)) => now.saturating_duration_since(last) >= period,
            _ => true,
        };
        if due {
            self.last = Some(now);
        }
        due
    }
}

impl<O: AnswerOut> ResultSink<Swing> for DdsSink<O> {
    /// Delivered = the ExitVelocity (the swing's answer) went out. A ModalEnergies that could not go out is
    /// reported and counted on its own (`modal_energies_unsent`): the swing was still answered.
    fn deliver(&mut self, outcome: &Outcome<Swing>) -> bool {
        let swing = &outcome.payload;
        let ev = crate::model::convert::exit_velocity(swing, &outcome.bat_id, &outcome.ball_id, &outcome.result);
        let stamp_ns = swing.header.stamp.unix_ns();
        if let Ok(computed) = &outcome.result {
            let me = crate::model::convert::modal_energies(swing, &outcome.bat_id, computed);
            // Always recorded; published only when someone listens: a DDS write wakes RustDDS's event
            // loop thread even with no reader, which costs every answer latency for nothing.
            self.tape.record(Recorded::ModalEnergies, &me, crate::model::time::now_ns(), stamp_ns);
            self.draw(outcome, &ev, &me, stamp_ns);
            if self.out.energies_listened() {
                match self.out.publish_energies(me) {
                    Ok(()) => NodeStats::bump(&self.stats.modal_energies_published),
                    Err(e) => {
                        NodeStats::bump(&self.stats.modal_energies_unsent);
                        self.out.report_failure(&format!("the ModalEnergies of swing {}", swing.swing_id), &e);
                    }
                }
            }
        }
        // ExitVelocity last, so a listener that has the answer also has its energies.
        self.tape.record(Recorded::ExitVelocity, &ev, crate::model::time::now_ns(), stamp_ns);
        match self.out.publish_answer(ev) {
            Ok(()) => true,
            Err(e) => {
                self.out.report_failure(&format!("the ExitVelocity of swing {}", swing.swing_id), &e);
                false
            }
        }
    }
}

impl<O: AnswerOut> DdsSink<O> {
    /// The swing's scene ([`crate::model::scene`]), built only when it goes somewhere: over DDS (the
    /// `swing_scene` parameter, which also records it) or to a Foxglove client subscribed to it, at most
    /// `swing_scene_live_hz` times a second there. A scene that could not be published is reported; the swing
    /// is still answered.
    fn draw(&mut self, outcome: &Outcome<Swing>, ev: &ExitVelocity, me: &ModalEnergies, stamp: u64) {
        let published = self.out.scenes_published();
        let recorded = self.tape.records(Recorded::SwingScene);
        // Only a drawable (OK) swing takes the live view's turn.
        let live = outcome.drawn_from.is_some()
            && self.tape.serves(Recorded::SwingScene)
            && self.live_scenes.due(Instant::now());
        if !(published || recorded || live) {
            return;
        }
        let Some((bat, ball_radius)) = &outcome.drawn_from else { return };
        let Ok(modes) = bat.modes(&()) else { return };
        let swing = &outcome.payload;
        let scene = crate::model::scene::swing_scene(&crate::model::scene::SceneInput {
            answer: ev,
            energies: me,
            bat: &bat.bat,
            modes: &modes,
            ball_radius: *ball_radius,
            undercut: swing.undercut,
            attack_angle: swing.attack_angle,
            bat_tilt: swing.bat_tilt,
            swing_direction: swing.swing_direction,
            batter_side: crate::model::convert::swing_input(swing).batter_side,
        });
        self.tape.record_to(Recorded::SwingScene, &scene, crate::model::time::now_ns(), stamp, live);
        if published {
            if let Err(e) = self.out.publish_scene(scene) {
                self.out.report_failure(&format!("the swing_scene of swing {}", swing.swing_id), &e);
            }
        }
    }
}

/// Whether the ModalEnergies writer has a matched subscription, kept in an atomic the sink reads per answer
/// (no lock on the hot path). Refreshed on every discovery event the node's spinner reports: the spinner
/// updates its match table, then sends the event, so the re-check sees the change. (Its event channel holds
/// 8 and drops what does not fit — only when unread events wait, whose re-checks come later and see the
/// later state, so no change goes unnoticed; no periodic re-check is needed, and none is made: each check
/// registers a listener with the node that only the next event clears.) So a subscriber gets the
/// ModalEnergies of every swing answered from the moment its match reaches the node's receive loop —
/// microseconds to a few milliseconds after DDS matched it (the first or second swing after, in
/// tests/node_modal_energies.rs); as the topic is volatile, nothing before the match was ever delivered
/// anyway — and a node nobody listens to spends no DDS writes on it.
pub struct EnergiesListeners {
    flag: Arc<AtomicBool>,
}

impl Default for EnergiesListeners {
    /// Nobody listening yet.
    fn default() -> EnergiesListeners {
        EnergiesListeners { flag: Arc::new(AtomicBool::new(false)) }
    }
}

impl EnergiesListeners {
    fn refresh(&self, publisher: &Publisher<ModalEnergies>, node: &ros2_client::Node) {
        // Resolves at once iff a reader is matched now; unlike `get_subscription_count` it does not log an
        // error for a writer that never had a reader.
        let matched = publisher.wait_for_subscription(node).now_or_never().is_some();
        self.flag.store(matched, Ordering::Relaxed);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::engine::{self, Registry};
    use crate::model::settings::ModelSettings;
    use std::sync::Mutex;

    /// Publishers that fail on demand and keep what they sent.
    #[derive(Default)]
    struct Fake {
        energies_fail: bool,
        answer_fails: bool,
        scenes: bool,
        sent: Arc<Mutex<Vec<String>>>,
    }

    impl AnswerOut for Fake {
        fn energies_listened(&self) -> bool {
            true
        }
        fn publish_energies(&self, m: ModalEnergies) -> Result<(), ros2_client::WriteError<()>> {
            if self.energies_fail {
                return Err(ros2_client::WriteError::WouldBlock { data: () });
            }
            self.sent.lock().unwrap().push(format!("ModalEnergies {}", m.swing_id));
            Ok(())
        }
        fn publish_answer(&self, m: ExitVelocity) -> Result<(), ros2_client::WriteError<()>> {
            if self.answer_fails {
                return Err(ros2_client::WriteError::WouldBlock { data: () });
            }
            self.sent.lock().unwrap().push(format!("ExitVelocity {}", m.swing_id));
            Ok(())
        }
        fn report_failure(&self, what: &str, _: &ros2_client::WriteError<()>) {
            self.sent.lock().unwrap().push(format!("failed: {what}"));
        }
        fn scenes_published(&self) -> bool {
            self.scenes
        }
        fn publish_scene(&self, m: MarkerArray) -> Result<(), ros2_client::WriteError<()>> {
            let ns: Vec<&str> = m.markers.iter().map(|m| m.ns.as_str()).collect();
            self.sent.lock().unwrap().push(format!("MarkerArray {}", ns.join(",")));
            Ok(())
        }
    }

    /// An OK outcome of swing 7 on the built-in default bat and ball (a real, coarse collision).
    fn ok_outcome() -> Outcome<Swing> {
        let settings = ModelSettings { default_modes: 2, ..ModelSettings::default() };
        let swing = Swing {
            swing_id: 7,
            ball_speed: 40.0,
            bat_cm_speed: 25.0,
            bat_angular_speed: 45.0,
            impact_z: 0.7,
            ..Swing::default()
        };
        let mut registry = Registry::new();
        let (plan, _) =
            engine::plan_swing(&mut registry, &settings, "", "", crate::model::convert::swing_input(&swing));
        let result = engine::compute(&plan, &());
        assert!(result.is_ok(), "{result:?}");
        let (bat_id, ball_id) = (plan.bat_id().to_string(), plan.ball_id().to_string());
        let drawn_from = match &plan {
            engine::Plan::Collide { bat, ball, .. } => Some((Arc::clone(bat), ball.radius)),
            engine::Plan::Reject { .. } => None,
        };
        Outcome { seq: 0, received: Instant::now(), bat_id, ball_id, result, drawn_from, payload: swing }
    }

    #[test]
    fn a_modal_energies_failure_leaves_the_swing_answered_and_is_counted_on_its_own() {
        let stats = Arc::new(NodeStats::new());
        let out = Fake { energies_fail: true, ..Fake::default() };
        let sent = Arc::clone(&out.sent);
        let mut sink = DdsSink {
            out,
            tape: Arc::new(Tape::off()),
            stats: Arc::clone(&stats),
            live_scenes: SceneThrottle::default(),
        };
        assert!(sink.deliver(&ok_outcome()), "the ExitVelocity went out: the swing is answered");
        assert_eq!(*sent.lock().unwrap(), ["failed: the ModalEnergies of swing 7", "ExitVelocity 7"]);
        let s = stats.snapshot(0);
        assert_eq!((s.modal_energies_unsent, s.modal_energies_published), (1, 0));
    }

    #[test]
    fn a_scene_is_drawn_only_when_it_goes_somewhere_and_before_the_answer() {
        for scenes in [false, true] {
            let out = Fake { scenes, ..Fake::default() };
            let sent = Arc::clone(&out.sent);
            let mut sink = DdsSink {
                out,
                tape: Arc::new(Tape::off()),
                stats: Arc::new(NodeStats::new()),
                live_scenes: SceneThrottle::default(),
            };
            assert!(sink.deliver(&ok_outcome()));
            let mut want = vec!["ModalEnergies 7", "ExitVelocity 7"];
            if scenes {
                want.insert(
                    0,
                    "MarkerArray bat_outline,bat_outline,ball,exit_velocity,deflection x20,label,spin_axis,spin_axis",
                );
            }
            assert_eq!(*sent.lock().unwrap(), want);
            // A rejection is not drawn.
            let rejected = Outcome { result: Err("no".into()), drawn_from: None, ..ok_outcome() };
            sent.lock().unwrap().clear();
            assert!(sink.deliver(&rejected));
            assert_eq!(*sent.lock().unwrap(), ["ExitVelocity 7"]);
        }
    }

    #[test]
    fn the_live_scene_throttle_lets_one_through_per_period_and_zero_means_every_one() {
        let t0 = Instant::now();
        let ms = |n: u64| t0 + Duration::from_millis(n);
        // 30 Hz: a period of 33.3 ms. A burst at 0–10 ms lets the first through; 33 ms is still early, 34 is due
        // (counted from the last one that went out, not from the ones held back).
        let mut throttle = SceneThrottle::per_second(30.0);
        let went: Vec<u64> = [0, 1, 5, 10, 33, 34, 40, 67, 68].into_iter().filter(|&n| throttle.due(ms(n))).collect();
        assert_eq!(went, [0, 34, 68]);
        for every in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let mut throttle = SceneThrottle::per_second(every);
            assert!((0..100).all(|n| throttle.due(ms(n / 10))), "{every}");
        }
    }

    #[test]
    fn an_exit_velocity_failure_is_the_swing_unsent() {
        let stats = Arc::new(NodeStats::new());
        let out = Fake { answer_fails: true, ..Fake::default() };
        let sent = Arc::clone(&out.sent);
        let mut sink = DdsSink {
            out,
            tape: Arc::new(Tape::off()),
            stats: Arc::clone(&stats),
            live_scenes: SceneThrottle::default(),
        };
        assert!(!sink.deliver(&ok_outcome()));
        assert_eq!(*sent.lock().unwrap(), ["ModalEnergies 7", "failed: the ExitVelocity of swing 7"]);
        let s = stats.snapshot(0);
        assert_eq!((s.modal_energies_unsent, s.modal_energies_published), (0, 1));
    }

    #[test]
    fn a_publish_failure_names_what_failed_and_why() {
        let full = ros2_client::WriteError::WouldBlock { data: () };
        let text = publish_failure_text("the ExitVelocity of swing 7", &full, 3);
        assert!(text.starts_with("the ExitVelocity of swing 7 could not be published: "), "{text}");
        assert!(text.contains("would block / timed out"), "the DDS layer's own reason: {text}");
        assert!(text.contains("does not acknowledge"), "{text}");
        assert!(text.contains("3 more publish failures"), "{text}");
        let broken = ros2_client::WriteError::<()>::Internal { reason: "lost".into() };
        assert!(publish_failure_text("x", &broken, 0).contains("lost"));
    }
}
