//! The node's receive loop: one [`NodeLoop`] owning what the loop owns, one handler per input (bat params,
//! ball params, swing, parameter change, SweetSpot ready, discovery event, diagnostics tick, shutdown).

use crate::model::time::RosTime;
use std::future::Future as _;
use std::pin::pin;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use futures::stream::BoxStream;
use futures::StreamExt;
use ros2_client::entities_info::ParticipantEntitiesInfo;
use ros2_client::{MessageInfo, NodeEvent, ReadResult, Subscription};
use tokio::sync::mpsc::{UnboundedReceiver, UnboundedSender};

use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::std_msgs::msg::Header;
use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use crate::ros::{shutdown_signal, topics};

use super::convert;
use super::live_settings::LiveSettings;
use super::outputs::{Log, Outputs, PublishFailures};
use super::pipeline::{InlinePacing, Pipeline};
use super::recording::{Recorded, Tape};
use super::settings::SettingEffect;
use super::stats::{
    flag_dds_stopped, flag_namesakes, health_report, GapCounter, NodeStats, RateLimiter, StatsSnapshot,
};
use crate::model::engine::{self, BatEntry, BatSummary, Registry, RegistryUsage};

/// Whether the DDS machinery under the node still runs: asked on every diagnostics tick. The node's own is
/// [`ParticipantLiveness`]; tests give the loop one that reports a dead stack.
pub trait Liveness: Send {
    /// False once the participant's background threads (RTPS event loop, Discovery) have stopped.
    fn dds_alive(&self) -> bool;
}

/// The liveness of a ros2-client context's DDS participant (RustDDS's `is_alive`, see patches/README.md).
pub struct ParticipantLiveness(pub ros2_client::Context);

impl Liveness for ParticipantLiveness {
    fn dds_alive(&self) -> bool {
        // The participant handle is a clone sharing the context's participant: dropped at once, so it never
        // outlives the context.
        let participant = self.0.domain_participant();
        let alive = participant.is_alive();
        drop(participant);
        alive
    }
}

/// Why the node stopped on its own: its DDS event loop is gone, so it can no longer send or receive.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{fqn}: the DDS event loop stopped: the node can no longer send or receive anything; shutting down (restart it)"
)]
pub struct DdsStopped {
    /// The node's fully-qualified name.
    pub fqn: String,
}

/// Asks `liveness` once: `Err` (the error to log and exit with) when the DDS machinery has stopped.
pub fn check_liveness(liveness: &dyn Liveness, fqn: &str) -> Result<(), DdsStopped> {
    if liveness.dds_alive() {
        Ok(())
    } else {
        Err(DdsStopped { fqn: fqn.to_string() })
    }
}

/// Messages from helper tasks back to the receive loop.
pub enum Event {
    /// A parameter was set through `ros2 param set`.
    ParameterChanged(SettingEffect),
    /// A bat's SweetSpot is ready (published only if the bat is still current).
    Summary(Arc<BatEntry>, Box<Result<BatSummary, String>>),
}

/// What woke the receive loop. One value per wake, moved straight into its handler: not worth boxing.
#[allow(clippy::large_enum_variant)]
enum Input {
    Shutdown(&'static str),
    Event(Event),
    Bat(BatSample),
    Ball(BallSample),
    Swing(SwingSample),
    Discovery,
    Participant(ReadResult<(ParticipantEntitiesInfo, MessageInfo)>),
    Tick,
    Call(ReadResult<(ros2_client::service::RmwRequestId, crate::msgs::sweetspot_msgs::srv::SimulateSwing_Request)>),
    MoreWaiting,
}

/// The node's subscriptions (borrowed by the loop's streams, so kept apart from [`NodeLoop`]).
pub struct Inputs {
    /// BatParams in.
    pub bat_params: Subscription<BatParams>,
    /// BallParams in.
    pub ball_params: Subscription<BallParams>,
    /// Swings in.
    pub swings: Subscription<Swing>,
    /// The `~/simulate_swing` service ([`super::service`]).
    pub simulate_swing: Arc<super::service::SimulateSwingServer>,
    /// Every participant's announcement of its ROS nodes (`ros_discovery_info`), to notice a namesake. A
    /// reader of its own rather than the spinner's discovery events: those go through a channel of 8 that
    /// drops what does not fit, and a burst of matches at start-up can drop the one announcement that counts.
    pub participants: Subscription<ParticipantEntitiesInfo>,
}

/// Rate-limited warnings, so a flood of the same problem does not flood /rosout.
pub struct Warnings {
    /// Bats or balls forgotten by the registry.
    eviction: RateLimiter,
    /// Swings dropped at a full pipeline.
    drop: RateLimiter,
    /// Swings lost between a publisher and the node.
    loss: RateLimiter,
}

impl Default for Warnings {
    fn default() -> Warnings {
        let every_5_s = || RateLimiter::new(Duration::from_secs(5));
        Warnings { eviction: every_5_s(), drop: every_5_s(), loss: every_5_s() }
    }
}

/// What the receive loop owns, and one handler per input.
pub struct NodeLoop {
    /// The node's fully-qualified name, for log lines and diagnostics.
    pub fqn: String,
    /// The current parameters.
    pub settings: LiveSettings,
    /// Bats and balls.
    pub registry: Registry,
    /// The registry's usage when evictions were last reported.
    pub seen_usage: RegistryUsage,
    /// Collision workers and in-order publication.
    pub pipeline: Pipeline<Swing>,
    /// How often a swing may be answered on the receive task itself.
    pub inline_pacing: InlinePacing,
    /// SweetSpot computations.
    pub summaries: Summaries,
    /// Publishers.
    pub outputs: Outputs,
    /// Discovery events of the node (each re-checks the ModalEnergies listeners).
    pub graph_events: BoxStream<'static, NodeEvent>,
    /// Events of the parameter services and the SweetSpot tasks.
    pub events: UnboundedReceiver<Event>,
    /// The recording.
    pub tape: Arc<Tape>,
    /// Counters.
    pub stats: Arc<NodeStats>,
    /// rosout + tracing.
    pub log: Log,
    /// Failed publishes of answers, reported rate-limited (shared with the pipeline's sink).
    pub publish_failures: PublishFailures,
    /// Gaps in each publisher's swing sequence numbers.
    pub transport_gaps: GapCounter<ros2_client::Gid>,
    /// Rate-limited warnings.
    pub warnings: Warnings,
    /// The counters at the previous diagnostics tick.
    pub last_report: StatsSnapshot,
    /// Whether DDS still runs (checked on every diagnostics tick).
    pub liveness: Box<dyn Liveness>,
    /// Our participant's gid, to tell other participants' nodes from our own.
    pub own_participant: ros2_client::Gid,
    /// Other participants that announce a node with our fully-qualified name.
    pub namesakes: std::collections::BTreeSet<ros2_client::Gid>,
    /// The workers of the `~/simulate_swing` service.
    pub calls: super::service::ServiceCalls<super::service::SimulateSwingServer>,
    /// The last moment the swing reader was seen empty (drained, or the loop idle): a swing taken later
    /// arrived after it, and its latency counts from it.
    pub swings_empty_at: Instant,
}

impl NodeLoop {
    /// Queues the SweetSpot of the default bat, which answers swings without any params.
    pub fn start_default_bat(&mut self) {
        let current = self.settings.snapshot();
        match self.registry.resolve_bat("", &current.model) {
            Ok((entry, _)) => self.summaries.spawn(entry, &self.registry),
            Err(e) => self.log.error(&format!("default_bat: {e}")),
        }
    }

    /// Handles inputs until SIGINT or SIGTERM (`Ok`), or until a diagnostics tick finds the DDS machinery
    /// stopped (`Err`, after an ERROR log line and a best-effort /diagnostics ERROR).
    pub async fn run(&mut self, inputs: &Inputs, node: &ros2_client::Node) -> Result<(), DdsStopped> {
        let diagnostics_period = self.settings.read(|s| s.diagnostics_period);
        let mut diagnostics = tokio::time::interval(Duration::from_secs_f64(diagnostics_period));
        diagnostics.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
        let mut bats = pin!(inputs.bat_params.async_stream());
        let mut balls = pin!(inputs.ball_params.async_stream());
        let mut swings = pin!(inputs.swings.async_stream());
        let mut participants = pin!(inputs.participants.async_stream());
        let mut calls = inputs.simulate_swing.receive_request_stream();
        let mut shutdown = pin!(shutdown_signal());
        // Bat params, ball params and swings taken from their readers but not yet handled.
        let mut arrivals = Arrivals::default();
        loop {
            // The select, and the last moment it found nothing to do (every reader empty): a swing taken
            // afterwards arrived after it.
            let (input, idle_at) = {
                let mut select = pin!(async {
                    tokio::select! {
                        biased;
                        signal = &mut shutdown => Input::Shutdown(signal),
                        Some(event) = self.events.recv() => Input::Event(event),
                        Some(received) = bats.next() => Input::Bat(received),
                        Some(received) = balls.next() => Input::Ball(received),
                        Some(_event) = self.graph_events.next() => Input::Discovery,
                        Some(received) = participants.next() => Input::Participant(received),
                        _ = diagnostics.tick() => Input::Tick,
                        Some(call) = calls.next() => Input::Call(call),
                        // A reader cut short at the drain cap: the rest of what was waiting, after the other
                        // inputs had their turn.
                        _ = std::future::ready(()), if arrivals.waiting() => Input::MoreWaiting,
                        Some(received) = swings.next() => Input::Swing(received),
                    }
                });
                let mut idle_at = None;
                let input = std::future::poll_fn(|cx| match select.as_mut().poll(cx) {
                    std::task::Poll::Pending => {
                        idle_at = Some(Instant::now());
                        std::task::Poll::Pending
                    }
                    ready => ready,
                })
                .await;
                (input, idle_at)
            };
            if let Some(idle_at) = idle_at {
                self.swings_empty_at = idle_at;
            }
            let arrival = matches!(input, Input::Bat(_) | Input::Ball(_) | Input::Swing(_) | Input::MoreWaiting);
            match input {
                Input::Shutdown(signal) => {
                    self.on_shutdown(signal);
                    return Ok(());
                }
                Input::Event(event) => self.on_event(event),
                Input::Bat(received) => arrivals.bats.push_back(Timed::of(received)),
                Input::Ball(received) => arrivals.balls.push_back(Timed::of(received)),
                Input::Swing(received) => arrivals.swings.push_back(Timed::of(received)),
                Input::Discovery => self.on_discovery(node),
                Input::Participant(received) => self.on_participant_info(received),
                Input::Tick => self.on_diagnostics_tick()?,
                Input::Call(call) => self.on_call(call),
                Input::MoreWaiting => {}
            }
            if arrival {
                self.handle_arrivals(&mut arrivals, &mut bats, &mut balls, &mut swings);
            }
        }
    }

    /// Takes what is already waiting on the bat, ball and swing readers (never waits; at most
    /// [`DRAIN_CAP`] more of each) and handles it in the order it was sent (see [`Arrivals::pop_next`]): a
    /// swing meets the params its publisher sent before it, whichever reader the loop happened to wake on,
    /// and params sent after a swing never overtake it.
    fn handle_arrivals<B, L, S>(
        &mut self,
        arrivals: &mut Arrivals<BatSample, BallSample, SwingSample>,
        bats: &mut std::pin::Pin<&mut B>,
        balls: &mut std::pin::Pin<&mut L>,
        swings: &mut std::pin::Pin<&mut S>,
    ) where
        B: futures::Stream<Item = BatSample>,
        L: futures::Stream<Item = BallSample>,
        S: futures::Stream<Item = SwingSample>,
    {
        // Every swing taken now arrived after the reader was last seen empty: their latency counts from there,
        // so a receive loop held up by other work is counted in the latency it reports.
        let arrived_after = self.swings_empty_at;
        arrivals.more[0] = top_up(&mut arrivals.bats, bats);
        arrivals.more[1] = top_up(&mut arrivals.balls, balls);
        arrivals.more[2] = top_up(&mut arrivals.swings, swings);
        if !arrivals.more[2] {
            self.swings_empty_at = Instant::now();
        }
        while let Some(next) = arrivals.pop_next() {
            match next {
                Next::Bat(received) => self.on_bat_params(received),
                Next::Ball(received) => self.on_ball_params(received),
                Next::Swing(received) => self.on_swing_sample(received, arrived_after),
            }
        }
    }

    fn on_shutdown(&self, signal: &str) {
        self.log.info(&format!("{signal}: shutting down"));
    }

    fn on_event(&mut self, event: Event) {
        match event {
            Event::ParameterChanged(effect) => self.on_parameter_changed(effect),
            Event::Summary(entry, result) => self.on_summary(&entry, *result),
        }
    }

    fn on_parameter_changed(&mut self, effect: SettingEffect) {
        let current = self.settings.snapshot();
        self.tape.note_settings(&current);
        self.registry.set_limits(&current.model);
        self.report_evictions();
        let refresh: Vec<Arc<BatEntry>> = match effect {
            SettingEffect::None => Vec::new(),
            SettingEffect::ModesChanged => self.registry.refresh_default_modes(&current.model),
            SettingEffect::SweetSpotsChanged => self.registry.bats(),
        };
        for entry in refresh {
            self.summaries.spawn(entry, &self.registry);
        }
    }

    fn on_summary(&self, entry: &Arc<BatEntry>, result: Result<BatSummary, String>) {
        // A summary of params that have since been replaced is stale.
        let current = self.registry.is_current(entry);
        match result {
            Ok(summary) if current => {
                let header = Header { stamp: Time::now(), frame_id: String::new() };
                let msg = crate::model::convert::sweet_spot(&summary, header);
                self.tape.record(Recorded::SweetSpot, &msg, crate::model::time::now_ns(), msg.header.stamp.unix_ns());
                if let Err(e) = self.outputs.sweet_spot.publish(msg) {
                    self.log.warn(&format!("publishing SweetSpot of '{}': {e:?}", summary.bat_id));
                }
            }
            Ok(_) => {}
            Err(e) => self.log.warn(&format!("SweetSpot not published: {e}")),
        }
    }

    fn on_bat_params(&mut self, received: ReadResult<(BatParams, MessageInfo)>) {
        let log_time = crate::model::time::now_ns();
        let params = match received {
            Ok((params, _info)) => params,
            Err(e) => return self.unreadable(topics::BAT_PARAMS, &e),
        };
        self.tape.record(Recorded::BatParams, &params, log_time, params.header.stamp.unix_ns());
        let current = self.settings.snapshot();
        // The slice cap is checked here, before any modes are solved; then the modes against the time step.
        let checked =
            crate::model::convert::bat_from_params_capped(&params, current.model.max_bat_slices).and_then(|built| {
                BatEntry::new_checked(&params.bat_id, built.bat, built.max_modes, &current.model, &*self.stats)
            });
        match checked {
            Ok(entry) => {
                NodeStats::bump(&self.stats.params_accepted);
                let entry = self.registry.set_bat(entry);
                self.settings.note_bat_params(&entry.bat_id);
                self.report_evictions();
                self.log
                    .info(&format!("bat '{}' set ({} modes); computing its SweetSpot", entry.bat_id, entry.max_modes));
                self.summaries.spawn(entry, &self.registry);
            }
            Err(reason) => {
                NodeStats::bump(&self.stats.params_rejected);
                let reason = format!(
                    "{reason}; the previous params of '{}' stay in force",
                    crate::model::limits::quote(&params.bat_id)
                );
                self.reject_params(&reason, &params.header, &params.bat_id, "");
            }
        }
    }

    fn on_ball_params(&mut self, received: ReadResult<(BallParams, MessageInfo)>) {
        let log_time = crate::model::time::now_ns();
        let params = match received {
            Ok((params, _info)) => params,
            Err(e) => return self.unreadable(topics::BALL_PARAMS, &e),
        };
        self.tape.record(Recorded::BallParams, &params, log_time, params.header.stamp.unix_ns());
        match crate::model::convert::ball_from_params(&params) {
            Ok(ball) => {
                NodeStats::bump(&self.stats.params_accepted);
                self.registry.set_ball(&params.ball_id, ball);
                self.settings.note_ball_params(&params.ball_id);
                self.report_evictions();
                self.log.info(&format!("ball '{}' set", params.ball_id));
            }
            Err(reason) => {
                NodeStats::bump(&self.stats.params_rejected);
                let reason = format!(
                    "{reason}; the previous params of '{}' stay in force",
                    crate::model::limits::quote(&params.ball_id)
                );
                self.reject_params(&reason, &params.header, "", &params.ball_id);
            }
        }
    }

    fn on_discovery(&self, node: &ros2_client::Node) {
        self.outputs.refresh_energies_listeners(node);
    }

    fn on_participant_info(&mut self, received: ReadResult<(ParticipantEntitiesInfo, MessageInfo)>) {
        match received {
            Ok((info, _)) => {
                self.on_participant_nodes(info.gid(), info.nodes().iter().map(|n| n.fully_qualified_name()))
            }
            Err(e) => tracing::debug!("unreadable ros_discovery_info sample: {e:?}"),
        }
    }

    /// A participant announced its nodes (each announcement replaces its previous one): warns when one of
    /// another participant's is named like us — two nodes of one name answer every swing twice.
    fn on_participant_nodes(&mut self, participant: ros2_client::Gid, mut names: impl Iterator<Item = String>) {
        if participant == self.own_participant {
            return;
        }
        if names.any(|name| name == self.fqn) {
            if self.namesakes.insert(participant) {
                self.log.warn(&namesake_warning(&self.fqn, self.namesakes.len()));
            }
        } else {
            self.namesakes.remove(&participant);
        }
    }

    /// Publishes /diagnostics, then checks that DDS still runs: when it does not, logs the ERROR and
    /// publishes an ERROR status (best effort: it can only go out if the writer still works) and ends the loop.
    fn on_diagnostics_tick(&mut self) -> Result<(), DdsStopped> {
        let liveness = check_liveness(self.liveness.as_ref(), &self.fqn);
        let mut now = self.stats.snapshot(self.pipeline.in_flight());
        let usage = self.registry.usage();
        now.bats_cached = usage.bats as u64;
        now.bats_evicted = usage.bats_evicted;
        now.balls_cached = usage.balls as u64;
        now.balls_evicted = usage.balls_evicted;
        let mut report = health_report(&now, &self.last_report, &self.tape.state());
        report.values.extend(self.calls.values());
        if !self.namesakes.is_empty() {
            flag_namesakes(&mut report, &namesake_warning(&self.fqn, self.namesakes.len()));
        }
        if let Err(stopped) = &liveness {
            self.log.error(&stopped.to_string());
            flag_dds_stopped(&mut report, &stopped.to_string());
        }
        let msg = convert::diagnostic_array(&report, &self.fqn, Time::now());
        self.tape.record(Recorded::Diagnostics, &msg, crate::model::time::now_ns(), msg.header.stamp.unix_ns());
        if let Err(e) = self.outputs.diagnostics.publish(msg) {
            tracing::debug!("publishing diagnostics: {e:?}");
        }
        self.last_report = now;
        liveness
    }

    fn on_swing_sample(&mut self, received: ReadResult<(Swing, MessageInfo)>, arrived_after: Instant) {
        let log_time = crate::model::time::now_ns();
        let (swing, info) = match received {
            Ok(sample) => sample,
            Err(e) => return self.unreadable(topics::SWING, &e),
        };
        let lost = self.transport_gaps.observe(info.publisher_gid(), info.sequence_number());
        if lost > 0 {
            self.stats.swings_lost_in_transport.fetch_add(lost, std::sync::atomic::Ordering::Relaxed);
            if let Some(suppressed) = self.warnings.loss.allow(Instant::now()) {
                self.log.warn(&format!(
                    "{lost} swings from one publisher never reached the node (DDS history overflow); {suppressed} more such reports suppressed"
                ));
            }
        }
        self.on_swing(swing, log_time, arrived_after);
        if self.registry.usage() != self.seen_usage {
            // A preset named by a swing pushed out another bat.
            self.report_evictions();
        }
    }

    /// A swing taken from DDS; `received` is the last moment its reader was seen empty (it arrived after it),
    /// from which its latency counts.
    fn on_swing(&mut self, swing: Swing, log_time: u64, received: Instant) {
        NodeStats::bump(&self.stats.swings_received);
        self.tape.record(Recorded::Swing, &swing, log_time, swing.header.stamp.unix_ns());
        // Planned under the read lock instead of cloning the settings (and their strings) for every swing.
        let registry = &mut self.registry;
        // One verdict per swing, here: a swing the answer would refuse is never computed, so nothing else of
        // it (ModalEnergies, scene) goes out and it counts as rejected.
        let (plan, new_bat) =
            self.settings.read(|settings| crate::model::convert::plan_swing_message(registry, &settings.model, &swing));
        if let Some(entry) = new_bat {
            self.summaries.spawn(entry, &self.registry);
        }
        // Idle and cheap: answered here, without waking a worker and the sequencer (see `Pipeline::answer_inline`).
        let (plan, swing) = if self.inline_pacing.allows(Instant::now()) {
            let started = Instant::now();
            match self.pipeline.answer_inline(received, plan, swing) {
                Ok(_) => {
                    self.inline_pacing.answered(started, Instant::now());
                    return;
                }
                Err(given_back) => given_back,
            }
        } else {
            (plan, swing)
        };
        if let Err((_plan, swing)) = self.pipeline.submit(received, plan, swing) {
            if let Some(suppressed) = self.warnings.drop.allow(Instant::now()) {
                self.log.warn(&format!(
                    "swing {} dropped: {} swings already in flight (queue_capacity); {suppressed} more dropped since the last warning",
                    swing.swing_id,
                    self.pipeline.capacity()
                ));
            }
            // Still exactly one answer per swing taken: a cheap DROPPED, at once (ahead of earlier swings still
            // in flight), recorded as published. Only if the send window has room now: waiting for a slow
            // reader here would stall the receive loop (every input) for up to the writer's blocking time. A
            // DROPPED answer that could not go out counts as unsent, so the summary still adds up.
            let ev = convert::dropped_answer(&swing, self.pipeline.capacity());
            self.tape.record(Recorded::ExitVelocity, &ev, crate::model::time::now_ns(), swing.header.stamp.unix_ns());
            match crate::ros::edge::try_publish(&self.outputs.exit_velocity, ev) {
                Ok(()) => NodeStats::bump(&self.stats.swings_dropped),
                Err(e) => {
                    NodeStats::bump(&self.stats.publish_failures);
                    self.publish_failures.report(&format!("the DROPPED answer of swing {}", swing.swing_id), &e);
                }
            }
        }
    }

    /// A `~/simulate_swing` call: planned here with the node's registry and settings (an inline bat only as far
    /// as its ball: the bat is built and solved on a worker), computed and answered by the service's workers
    /// (or answered DROPPED at once when they have `queue_capacity` calls).
    fn on_call(
        &mut self,
        call: ros2_client::ReadResult<(
            ros2_client::service::RmwRequestId,
            crate::msgs::sweetspot_msgs::srv::SimulateSwing_Request,
        )>,
    ) {
        let (id, request) = match call {
            Ok(call) => call,
            Err(e) => return self.unreadable(super::service::SERVICE_NAME, &e),
        };
        let registry = &mut self.registry;
        let (plan, new_bat) =
            self.settings.read(|settings| super::service::plan_call(registry, &settings.model, &request));
        if let Some(entry) = new_bat {
            self.summaries.spawn(entry, &self.registry);
        }
        if self.registry.usage() != self.seen_usage {
            self.report_evictions();
        }
        self.calls.submit(id, plan, request);
    }

    fn unreadable(&self, topic: &str, error: &ros2_client::ReadError) {
        NodeStats::bump(&self.stats.samples_unreadable);
        self.log.warn(&format!("{topic}: unreadable sample: {error:?}"));
    }

    /// Warns (rate-limited) when the registry forgot bats or balls since they were last reported.
    fn report_evictions(&mut self) {
        let now = self.registry.usage();
        let seen = std::mem::replace(&mut self.seen_usage, now);
        let (bats, balls) = (now.bats_evicted - seen.bats_evicted, now.balls_evicted - seen.balls_evicted);
        if bats + balls == 0 {
            return;
        }
        let Some(suppressed) = self.warnings.eviction.allow(Instant::now()) else { return };
        let (max_bats, max_balls) = self.settings.read(|s| (s.model.max_bats, s.model.max_balls));
        let mut parts = Vec::new();
        if bats > 0 {
            parts.push(format!(
                "{bats} bat(s) forgotten, latest '{}' (max_bats = {max_bats} held, least recently used first; {} in all)",
                self.registry.last_evicted_bat().unwrap_or_default(),
                now.bats_evicted
            ));
        }
        if balls > 0 {
            parts.push(format!(
                "{balls} ball(s) forgotten, latest '{}' (max_balls = {max_balls} held; {} in all)",
                self.registry.last_evicted_ball().unwrap_or_default(),
                now.balls_evicted
            ));
        }
        self.log.warn(&format!(
            "{}; swings naming them are REJECTED until their params are sent again (presets are re-solved); {suppressed} more such reports suppressed",
            parts.join("; ")
        ));
    }

    /// Answers params that cannot be used with an ExitVelocity REJECTED carrying `reason`.
    fn reject_params(&self, reason: &str, header: &Header, bat_id: &str, ball_id: &str) {
        self.log.error(reason);
        let probe = Swing { header: header.clone(), measured_exit_speed: f64::NAN, ..Swing::default() };
        let ev = crate::model::convert::exit_velocity(&probe, bat_id, ball_id, &Err(reason.to_string()));
        self.tape.record(Recorded::ExitVelocity, &ev, crate::model::time::now_ns(), header.stamp.unix_ns());
        if let Err(e) = self.outputs.exit_velocity.publish(ev) {
            self.publish_failures.report("the ExitVelocity rejecting params", &e);
        }
    }

    /// Stops taking swings, lets queued ones finish briefly, closes the bag and reports; then drops the
    /// discovery events and the publishers (before the caller drops the subscriptions and the node).
    pub async fn finish(self) -> anyhow::Result<()> {
        let NodeLoop { fqn, registry, pipeline, outputs, graph_events, tape, stats, log, liveness, calls, .. } = self;
        // Holds a clone of the context: gone before the caller drops the context.
        drop(liveness);
        let (pipeline_stats, tape_for_finish) = (Arc::clone(&stats), Arc::clone(&tape));
        let (bag_result, final_stats) = tokio::task::spawn_blocking(move || {
            let abandoned = pipeline.shutdown(Duration::from_millis(600));
            calls.shutdown();
            let bag = tape_for_finish.finish();
            (bag, pipeline_stats.snapshot(abandoned))
        })
        .await
        .context("joining the shutdown task")?;
        let summary = summary_line(&fqn, &final_stats, &registry.usage());
        // Printed once on the terminal whatever the log level, and on /rosout for ROS tools.
        log.info_to_ros(&summary);
        eprintln!("{summary}");
        match bag_result {
            Some(Ok(b)) => eprintln!(
                "{fqn}: bag {} closed: {} messages written, {} dropped, {} bytes",
                tape.dir().map(|d| d.display().to_string()).unwrap_or_default(),
                b.written,
                b.dropped,
                b.bytes
            ),
            Some(Err(e)) => eprintln!("{fqn}: closing the bag failed: {e}"),
            None => {}
        }
        // Every writer of the node (the log handle holds a rosout writer clone) goes before the caller drops
        // the node and then the context.
        drop(graph_events);
        drop(outputs);
        drop(log);
        Ok(())
    }
}

/// The node's last words: where every swing it took went (the parts add up to `swings received`: answered
/// OK, REJECTED, DROPPED, computed or dropped but not sent because publishing failed, still queued when it
/// stopped),
/// swings that never reached it, latency and caches. `s.in_flight` is what was left queued after the drain.
pub fn summary_line(fqn: &str, s: &StatsSnapshot, usage: &RegistryUsage) -> String {
    format!(
        "{fqn}: {} swings received = {} answered OK + {} rejected + {} dropped + {} unsent (publish failed) + {} \
         still queued at shutdown; {} lost in transport; latency p50 {} µs, p99 {} µs, max {} µs (queue wait and \
         compute: from the swing reader last seen empty to the answer published); mode cache {} \
         hits / {} misses; {} bats and {} balls evicted",
        s.swings_received,
        s.swings_ok,
        s.swings_rejected,
        s.swings_dropped,
        s.publish_failures,
        s.in_flight,
        s.swings_lost_in_transport,
        s.latency_p50_us,
        s.latency_p99_us,
        s.latency_max_us,
        s.mode_cache_hits,
        s.mode_cache_misses,
        usage.bats_evicted,
        usage.balls_evicted
    )
}

/// When a received sample was sent (its DDS source timestamp), if it says.
fn sent_at<M>(received: &ReadResult<(M, MessageInfo)>) -> Option<ros2_client::ROSTime> {
    received.as_ref().ok().and_then(|(_, info)| info.source_timestamp())
}

/// A bat params sample as the reader gives it.
type BatSample = ReadResult<(BatParams, MessageInfo)>;
/// A ball params sample as the reader gives it.
type BallSample = ReadResult<(BallParams, MessageInfo)>;
/// A swing sample as the reader gives it.
type SwingSample = ReadResult<(Swing, MessageInfo)>;

/// How many samples one wake of the loop takes from each reader at most, so a burst of swings still lets
/// shutdown, parameter changes and diagnostics in between.
const DRAIN_CAP: usize = 64;

/// Moves what `stream` already holds into `queue` without waiting, until `queue` holds [`DRAIN_CAP`]: true
/// when it stopped at the cap (more may be waiting).
fn top_up<T, S: futures::Stream<Item = ReadResult<(T, MessageInfo)>>>(
    queue: &mut std::collections::VecDeque<Timed<ReadResult<(T, MessageInfo)>, ros2_client::ROSTime>>,
    stream: &mut std::pin::Pin<&mut S>,
) -> bool {
    while queue.len() < DRAIN_CAP {
        match futures::FutureExt::now_or_never(stream.next()) {
            Some(Some(received)) => queue.push_back(Timed::of(received)),
            _ => return false,
        }
    }
    true
}

/// A sample and when it was sent (its DDS source timestamp), if it says.
struct Timed<T, K> {
    sent: Option<K>,
    item: T,
}

impl<M> Timed<ReadResult<(M, MessageInfo)>, ros2_client::ROSTime> {
    fn of(received: ReadResult<(M, MessageInfo)>) -> Self {
        Timed { sent: sent_at(&received), item: received }
    }
}

/// The next sample to handle.
#[derive(Debug, PartialEq)]
enum Next<B, L, S> {
    Bat(B),
    Ball(L),
    Swing(S),
}

/// Samples taken from the bat params, ball params and swing readers, each in arrival order, not yet handled.
struct Arrivals<B, L, S, K = ros2_client::ROSTime> {
    bats: std::collections::VecDeque<Timed<B, K>>,
    balls: std::collections::VecDeque<Timed<L, K>>,
    swings: std::collections::VecDeque<Timed<S, K>>,
    /// Per reader (bats, balls, swings): its last drain stopped at the cap, so it may hold more.
    more: [bool; 3],
}

impl<B, L, S, K> Default for Arrivals<B, L, S, K> {
    fn default() -> Self {
        Arrivals { bats: Default::default(), balls: Default::default(), swings: Default::default(), more: [false; 3] }
    }
}

impl<B, L, S, K: Ord + Copy> Arrivals<B, L, S, K> {
    /// Whether something is left to handle, or a reader cut short at the cap may hold more.
    fn waiting(&self) -> bool {
        !(self.bats.is_empty() && self.balls.is_empty() && self.swings.is_empty()) || self.more.contains(&true)
    }

    /// The sample sent first among the heads of the three queues (each queue keeps its arrival order). Params
    /// go first on a tie, and params that do not say when they were sent go before every swing; a swing that
    /// does not say goes after every params sample taken. `None` when all is handled, or when a reader cut
    /// short at the cap has run out here: what it still holds may have been sent before every other head.
    fn pop_next(&mut self) -> Option<Next<B, L, S>> {
        let queues_empty = [self.bats.is_empty(), self.balls.is_empty(), self.swings.is_empty()];
        if (0..3).any(|i| self.more[i] && queues_empty[i]) {
            return None;
        }
        // (rank, time): params without a time first, then everything with one by time, then swings without.
        let params_key = |sent: Option<K>| sent.map_or((0, None), |t| (1, Some(t)));
        let swing_key = |sent: Option<K>| sent.map_or((2, None), |t| (1, Some(t)));
        let candidates = [
            self.bats.front().map(|t| params_key(t.sent)),
            self.balls.front().map(|t| params_key(t.sent)),
            self.swings.front().map(|t| swing_key(t.sent)),
        ];
        // The earliest; on a tie the first in this order (bats, balls, swings).
        let (which, _) = candidates
            .iter()
            .enumerate()
            .filter_map(|(i, key)| key.map(|k| (i, k)))
            .min_by(|(i, a), (j, b)| a.cmp(b).then(i.cmp(j)))?;
        match which {
            0 => self.bats.pop_front().map(|t| Next::Bat(t.item)),
            1 => self.balls.pop_front().map(|t| Next::Ball(t.item)),
            _ => self.swings.pop_front().map(|t| Next::Swing(t.item)),
        }
    }
}

/// The warning when other participants announce a node with our fully-qualified name.
pub fn namesake_warning(fqn: &str, participants: usize) -> String {
    format!(
        "another node named {fqn} is on the graph ({participants} other participant(s)): every swing is answered \
         once per node; rename one (--ros-args -r __node:=NAME or -r __ns:=/NS)"
    )
}

/// Computes SweetSpots off the DDS thread, one at a time: a burst of BatParams (each a sweep of collisions,
/// and a modes solve of up to `max_bat_slices` slices) must not start a thread per message — tokio's blocking
/// pool would grow to 512 threads — nor compete with the swing workers on every core.
pub struct Summaries {
    settings: LiveSettings,
    stats: Arc<NodeStats>,
    events: UnboundedSender<Event>,
    one_at_a_time: Arc<tokio::sync::Semaphore>,
}

impl Summaries {
    /// Summaries computed with `settings`, counted in `stats`, reported on `events`.
    pub fn new(settings: LiveSettings, stats: Arc<NodeStats>, events: UnboundedSender<Event>) -> Summaries {
        Summaries { settings, stats, events, one_at_a_time: Arc::new(tokio::sync::Semaphore::new(1)) }
    }

    /// Queues the SweetSpot of `entry` against the registry's current ball.
    pub fn spawn(&self, entry: Arc<BatEntry>, registry: &Registry) {
        let settings = self.settings.snapshot();
        let Ok((ball_id, ball)) = registry.resolve_ball("", &settings.model) else {
            return;
        };
        let (stats, events, slot) = (Arc::clone(&self.stats), self.events.clone(), Arc::clone(&self.one_at_a_time));
        // Only the registry (and swings in flight) keep the entry alive: a bat replaced or forgotten before
        // its turn comes is not solved for a SweetSpot nobody would publish, so waiting jobs cost no solves.
        let entry = Arc::downgrade(&entry);
        tokio::spawn(async move {
            let Ok(_turn) = slot.acquire_owned().await else { return };
            let job = tokio::task::spawn_blocking(move || {
                let Some(entry) = entry.upgrade() else { return };
                let result = engine::summarize_bat(
                    &entry,
                    &ball_id,
                    &ball.ball,
                    convert::reference_swing(&settings),
                    &settings.model,
                    &*stats,
                );
                let _ = events.send(Event::Summary(entry, Box::new(result)));
            });
            let _ = job.await;
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};

    /// A DDS stack a test can stop.
    struct Switch(Arc<AtomicBool>);

    impl Liveness for Switch {
        fn dds_alive(&self) -> bool {
            self.0.load(Ordering::SeqCst)
        }
    }

    #[test]
    fn a_stopped_dds_ends_the_loop_with_an_error_naming_the_node() {
        let alive = Arc::new(AtomicBool::new(true));
        let liveness: Box<dyn Liveness> = Box::new(Switch(Arc::clone(&alive)));
        assert_eq!(check_liveness(liveness.as_ref(), "/rig3/sweetspot"), Ok(()));
        alive.store(false, Ordering::SeqCst);
        let stopped = check_liveness(liveness.as_ref(), "/rig3/sweetspot").unwrap_err();
        assert_eq!(stopped, DdsStopped { fqn: "/rig3/sweetspot".into() });
        let text = stopped.to_string();
        assert!(text.starts_with("/rig3/sweetspot: the DDS event loop stopped"), "{text}");
        assert!(text.contains("can no longer send or receive"), "{text}");
    }

    #[test]
    fn the_summary_line_adds_up_every_swing_received() {
        let s = StatsSnapshot {
            swings_received: 10,
            swings_ok: 4,
            swings_rejected: 1,
            swings_dropped: 2,
            publish_failures: 1,
            in_flight: 2,
            swings_lost_in_transport: 3,
            ..StatsSnapshot::default()
        };
        let line = summary_line("/sweetspot", &s, &RegistryUsage::default());
        assert!(
            line.starts_with(
                "/sweetspot: 10 swings received = 4 answered OK + 1 rejected + 2 dropped + 1 unsent (publish failed) \
                 + 2 still queued at shutdown; 3 lost in transport;"
            ),
            "{line}"
        );
    }

    /// Queues of (sent, label) and the labels in the order the loop handles them.
    fn handled(
        bats: &[(Option<i64>, &'static str)],
        balls: &[(Option<i64>, &'static str)],
        swings: &[(Option<i64>, &'static str)],
        more: [bool; 3],
    ) -> Vec<&'static str> {
        let timed = |q: &[(Option<i64>, &'static str)]| q.iter().map(|&(sent, item)| Timed { sent, item }).collect();
        let mut arrivals: Arrivals<&str, &str, &str, i64> =
            Arrivals { bats: timed(bats), balls: timed(balls), swings: timed(swings), more };
        std::iter::from_fn(|| arrivals.pop_next())
            .map(|next| match next {
                Next::Bat(x) | Next::Ball(x) | Next::Swing(x) => x,
            })
            .collect()
    }

    #[test]
    fn a_swing_meets_the_ball_params_sent_before_it_even_when_bat_params_sent_after_it_are_waiting() {
        // The review's case: ball params (t=1), then a swing (t=2), then bat params (t=3), all waiting when the
        // loop wakes. Taking the bat params first (the loop's old bias) answered the swing before the ball.
        let order = handled(&[(Some(3), "bat")], &[(Some(1), "ball")], &[(Some(2), "swing")], [false; 3]);
        assert_eq!(order, ["ball", "swing", "bat"]);
    }

    #[test]
    fn samples_go_in_sent_order_each_reader_keeping_its_own_order_params_first_on_a_tie() {
        let order = handled(
            &[(Some(10), "bat10"), (Some(30), "bat30")],
            &[(Some(20), "ball20"), (Some(40), "ball40")],
            &[(Some(5), "s5"), (Some(20), "s20"), (Some(35), "s35"), (Some(50), "s50")],
            [false; 3],
        );
        assert_eq!(order, ["s5", "bat10", "ball20", "s20", "bat30", "s35", "ball40", "s50"]);
        // A reader's own order is kept even when its clock disagrees (another publisher, another clock).
        let order = handled(&[], &[], &[(Some(9), "late-clock"), (Some(1), "early-clock")], [false; 3]);
        assert_eq!(order, ["late-clock", "early-clock"]);
    }

    #[test]
    fn samples_without_a_source_time_put_params_before_every_swing() {
        let order = handled(&[(None, "bat")], &[(Some(7), "ball")], &[(Some(1), "s1"), (None, "s?")], [false; 3]);
        assert_eq!(order, ["bat", "s1", "ball", "s?"]);
    }

    #[test]
    fn a_reader_cut_short_at_the_cap_stops_the_merge_where_its_unread_samples_could_come_first() {
        // Swings 1..=2 taken, more waiting: params sent at 5 must wait, the swings still unread may be earlier.
        let order = handled(&[(Some(5), "bat")], &[], &[(Some(1), "s1"), (Some(2), "s2")], [false, false, true]);
        assert_eq!(order, ["s1", "s2"]);
        // Everything taken: the params go in their place.
        let order = handled(&[(Some(5), "bat")], &[], &[(Some(1), "s1"), (Some(2), "s2")], [false; 3]);
        assert_eq!(order, ["s1", "s2", "bat"]);
    }

    #[test]
    fn the_namesake_warning_says_what_goes_wrong_and_how_to_fix_it() {
        let w = namesake_warning("/sweetspot", 1);
        assert!(w.contains("another node named /sweetspot"), "{w}");
        assert!(w.contains("__node:="), "{w}");
    }
}
