//! The node's `~/simulate_swing` service (`sweetspot_msgs/srv/SimulateSwing`): "what would this swing give?"
//! answered with one response per call, through ros2-client's service server.
//!
//! - **Same answer as the topics.** A call is planned by [`plan_call`] with the node's registry and settings
//!   ([`engine::plan_swing`], the function every swing goes through) and computed by [`engine::compute`]; the
//!   response carries the [`convert::exit_velocity`] and [`convert::modal_energies`] the node would publish
//!   for that swing. Optional inline `bat`/`ball` params are checked like BatParams/BallParams on their topics
//!   and used for that call only, in a scratch registry: the node's bats and balls are not changed (a preset
//!   named by a call is made in the node's registry, as a swing naming it would).
//! - **Not a swing of the session.** Nothing is published on `exit_velocity` or `modal_energies`; calls are
//!   counted apart on `/diagnostics` (`service_calls_*`).
//! - **Every call answered.** A bad request (NaN, unknown bat or ball id, bad inline params, ids that disagree)
//!   gets a REJECTED ExitVelocity whose message names the field. Calls are computed on `workers` threads of
//!   their own behind a queue of `queue_capacity` calls; a call that finds it full is answered at once with
//!   status DROPPED saying so (nothing computed), as a swing would be. The request reader keeps up to
//!   `max(queue_capacity, 10000)` requests, so a burst the receive loop has not taken yet is not overwritten.
//!   Only a request that cannot be decoded gets no response (it carries no usable request id); it is
//!   counted as `samples_unreadable`.
//! - **Wire.** ROS 2 names: `rq/<ns>/<node>/simulate_swingRequest` and `rr/<ns>/<node>/simulate_swingReply`,
//!   DDS types `sweetspot_msgs::srv::dds_::SimulateSwing_Request_` / `_Response_`, reliable and volatile. The
//!   "enhanced" request/reply mapping of RTI's RPC over DDS (rmw_fastrtps, Jazzy's default, and ros2-client's
//!   own parameter services): no header in the data; the reply names the request by its sample identity. A
//!   client that cannot send or read that identity (plain DDS, such as the Cyclone peer of the tests)
//!   matches replies by `exit_velocity.swing_id`. rmw_cyclonedds_cpp puts a `{uint64 guid; int64 seq}` header
//!   in the data instead: with `service_mapping:=cyclone` the node serves that mapping (ros2-client's
//!   `ServiceMapping::Cyclone`, its sequence number fixed in patches/ros2-client), and echoes the header.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;

use ros2_client::service::RmwRequestId;
use ros2_client::Server;

use crate::model::convert;
use crate::model::engine::{self, BatEntry, ModeCacheStats, Plan, Registry};
use crate::model::settings::ModelSettings;
use crate::model::time::RosTime as _;
use crate::msgs::service_msgs::msg::ServiceEventInfo;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
use crate::msgs::sweetspot_msgs::srv::{SimulateSwing_Event, SimulateSwing_Request, SimulateSwing_Response};

use super::recording::{Recorded, Tape};
use super::stats::NodeStats;

/// The service's name, private to the node (`/<ns>/<node>/simulate_swing`).
pub const SERVICE_NAME: &str = "~/simulate_swing";

/// The service's ros2-client server.
pub type SimulateSwingServer = Server<SimulateSwing_Request, SimulateSwing_Response>;

/// What a call becomes, and a bat the node's registry made from a preset for it (its SweetSpot is new).
///
/// Without inline params this is [`engine::plan_swing`] on the node's registry. With them, the inline bat
/// or ball (checked as on its topic; the swing's id must be empty or the same) and the node's other half go
/// into a scratch registry, and the swing is planned there.
pub fn plan_call(
    registry: &mut Registry,
    settings: &ModelSettings,
    request: &SimulateSwing_Request,
    stats: &impl ModeCacheStats,
) -> (Plan, Option<Arc<BatEntry>>) {
    let swing = &request.swing;
    let input = convert::swing_input(swing);
    if request.bat.is_empty() && request.ball.is_empty() {
        return engine::plan_swing(registry, settings, &swing.bat_id, &swing.ball_id, input);
    }
    let reject = |bat_id: &str, ball_id: &str, reason: String| Plan::Reject {
        bat_id: crate::model::limits::shorten(bat_id, crate::model::limits::MAX_STRING_BYTES).into_owned(),
        ball_id: crate::model::limits::shorten(ball_id, crate::model::limits::MAX_STRING_BYTES).into_owned(),
        reason,
    };
    let mut scratch = Registry::with_limits(1, 1);
    let mut new_bat = None;
    let bat_id = match request.bat.first() {
        Some(params) => {
            if let Err(reason) = same_id("bat_id", &swing.bat_id, "bat[0].bat_id", &params.bat_id) {
                return (reject(&swing.bat_id, &swing.ball_id, reason), None);
            }
            let checked = convert::bat_from_params_capped(params, settings.max_bat_slices)
                .and_then(|built| BatEntry::new_checked(&params.bat_id, built.bat, built.max_modes, settings, stats));
            match checked {
                Ok(entry) => scratch.set_bat(entry).bat_id.clone(),
                Err(reason) => return (reject(&params.bat_id, &swing.ball_id, format!("bat[0]: {reason}")), None),
            }
        }
        None => match registry.resolve_bat(&swing.bat_id, settings) {
            Ok((entry, created)) => {
                new_bat = created.then(|| Arc::clone(&entry));
                let id = entry.bat_id.clone();
                scratch.set_shared_bat(entry);
                id
            }
            Err(reason) => {
                let bat_id = registry.effective_bat_id(&swing.bat_id, settings);
                return (reject(&bat_id, &swing.ball_id, reason), None);
            }
        },
    };
    let ball_id = match request.ball.first() {
        Some(params) => {
            if let Err(reason) = same_id("ball_id", &swing.ball_id, "ball[0].ball_id", &params.ball_id) {
                return (reject(&bat_id, &swing.ball_id, reason), new_bat);
            }
            match convert::ball_from_params(params) {
                Ok(ball) => {
                    scratch.set_ball(&params.ball_id, ball);
                    params.ball_id.clone()
                }
                Err(reason) => return (reject(&bat_id, &params.ball_id, format!("ball[0]: {reason}")), new_bat),
            }
        }
        None => match registry.use_ball(&swing.ball_id) {
            Ok((id, ball)) => {
                scratch.set_ball(&id, ball);
                id
            }
            Err(reason) => return (reject(&bat_id, &swing.ball_id, reason), new_bat),
        },
    };
    let (plan, _) = engine::plan_swing(&mut scratch, settings, &bat_id, &ball_id, input);
    (plan, new_bat)
}

/// A swing's id must be empty or the inline params' own.
fn same_id(field: &str, in_swing: &str, inline_field: &str, inline: &str) -> Result<(), String> {
    if in_swing.is_empty() || in_swing == inline {
        return Ok(());
    }
    let quote = crate::model::limits::quote;
    Err(format!(
        "swing.{field} '{}' names another {} than {inline_field} '{}': leave swing.{field} empty or make them equal",
        quote(in_swing),
        if field == "bat_id" { "bat" } else { "ball" },
        quote(inline)
    ))
}

/// The response the topics would carry for the swing: its ExitVelocity, and its ModalEnergies when it was
/// computed (the node publishes those exactly then).
pub fn response(
    swing: &Swing,
    bat_id: &str,
    ball_id: &str,
    result: &Result<engine::Computed, String>,
) -> SimulateSwing_Response {
    SimulateSwing_Response {
        exit_velocity: convert::exit_velocity(swing, bat_id, ball_id, result),
        modal_energies: match result {
            Ok(computed) => vec![convert::modal_energies(swing, bat_id, computed)],
            Err(_) => Vec::new(),
        },
    }
}

/// The response to a call that found `capacity` calls in flight: status DROPPED, nothing computed.
pub fn dropped_response(swing: &Swing, capacity: usize) -> SimulateSwing_Response {
    let reason = format!(
        "dropped: {capacity} simulate_swing calls already in flight (queue_capacity); nothing was computed for \
         this call: call again, call slower, or raise queue_capacity or workers"
    );
    let mut exit_velocity = convert::exit_velocity(swing, &swing.bat_id, &swing.ball_id, &Err(reason.clone()));
    exit_velocity.status = ExitVelocity::STATUS_DROPPED;
    exit_velocity.message = reason;
    SimulateSwing_Response { exit_velocity, modal_energies: Vec::new() }
}

/// The service's counters, reported on `/diagnostics` apart from the swings'.
#[derive(Debug, Default)]
pub struct CallStats {
    /// Calls taken from DDS (decoded).
    pub received: AtomicU64,
    /// Answered with status OK.
    pub ok: AtomicU64,
    /// Answered REJECTED.
    pub rejected: AtomicU64,
    /// Answered DROPPED (the call queue was full).
    pub dropped: AtomicU64,
    /// Responses DDS refused to send.
    pub unsent: AtomicU64,
}

impl CallStats {
    /// The `/diagnostics` key/value pairs.
    pub fn values(&self) -> Vec<(String, String)> {
        let load = |c: &AtomicU64| c.load(Ordering::Relaxed).to_string();
        vec![
            ("service_calls_received".into(), load(&self.received)),
            ("service_calls_ok".into(), load(&self.ok)),
            ("service_calls_rejected".into(), load(&self.rejected)),
            ("service_calls_dropped".into(), load(&self.dropped)),
            ("service_responses_unsent".into(), load(&self.unsent)),
        ]
    }

    fn count(&self, response: &SimulateSwing_Response) {
        NodeStats::bump(match response.exit_velocity.status {
            ExitVelocity::STATUS_OK => &self.ok,
            ExitVelocity::STATUS_DROPPED => &self.dropped,
            _ => &self.rejected,
        });
    }
}

/// Where answers go: the server in the node, a list in tests.
pub trait Responder: Send + Sync + 'static {
    /// Sends `response` to the call `id`; false when it could not be sent.
    fn respond(&self, id: RmwRequestId, response: SimulateSwing_Response) -> bool;
}

impl Responder for SimulateSwingServer {
    fn respond(&self, id: RmwRequestId, response: SimulateSwing_Response) -> bool {
        match self.send_response(id, response) {
            Ok(()) => true,
            Err(e) => {
                tracing::warn!("simulate_swing: a response could not be sent: {e:?}");
                false
            }
        }
    }
}

/// The two events rosbag2 records of a call the server answered: REQUEST_RECEIVED with the request, then
/// RESPONSE_SENT with the response, both naming the client and its request's sequence number.
pub fn call_events(
    id: RmwRequestId,
    request: &SimulateSwing_Request,
    response: &SimulateSwing_Response,
) -> [SimulateSwing_Event; 2] {
    let info = |event_type: u8| ServiceEventInfo {
        event_type,
        stamp: crate::msgs::builtin_interfaces::msg::Time::now(),
        client_gid: id.writer_gid.to_bytes16(),
        sequence_number: id.sequence_number,
    };
    [
        SimulateSwing_Event {
            info: info(ServiceEventInfo::REQUEST_RECEIVED),
            request: vec![request.clone()],
            response: Vec::new(),
        },
        SimulateSwing_Event {
            info: info(ServiceEventInfo::RESPONSE_SENT),
            request: Vec::new(),
            response: vec![response.clone()],
        },
    ]
}

fn record_call(tape: &Tape, id: RmwRequestId, request: &SimulateSwing_Request, response: &SimulateSwing_Response) {
    for event in call_events(id, request, response) {
        let stamp = event.info.stamp.unix_ns();
        tape.record(Recorded::ServiceEvent, &event, crate::model::time::now_ns(), stamp);
    }
}

/// One planned call.
struct CallJob {
    id: RmwRequestId,
    plan: Plan,
    request: SimulateSwing_Request,
}

/// The service's workers and their bounded queue.
pub struct ServiceCalls<R: Responder> {
    responder: Arc<R>,
    jobs: Option<crossbeam_channel::Sender<CallJob>>,
    in_flight: Arc<AtomicUsize>,
    capacity: usize,
    workers: Vec<JoinHandle<()>>,
    /// The counters.
    pub stats: Arc<CallStats>,
    /// Where calls are recorded (`record_services`), if anywhere.
    tape: Option<Arc<Tape>>,
}

impl<R: Responder> ServiceCalls<R> {
    /// `workers` threads computing calls, at most `capacity` calls queued or computing; each call recorded on
    /// `tape` when given.
    pub fn start(
        responder: Arc<R>,
        workers: usize,
        capacity: usize,
        node_stats: Arc<NodeStats>,
        tape: Option<Arc<Tape>>,
    ) -> std::io::Result<ServiceCalls<R>> {
        let capacity = capacity.max(1);
        let (tx, rx) = crossbeam_channel::bounded::<CallJob>(capacity);
        let in_flight = Arc::new(AtomicUsize::new(0));
        let stats = Arc::new(CallStats::default());
        let mut handles = Vec::new();
        for i in 0..workers.max(1) {
            let (rx, responder, in_flight) = (rx.clone(), Arc::clone(&responder), Arc::clone(&in_flight));
            let (stats, node_stats, tape) = (Arc::clone(&stats), Arc::clone(&node_stats), tape.clone());
            handles.push(std::thread::Builder::new().name(format!("sweetspot-call-{i}")).spawn(move || {
                for job in rx {
                    let result = engine::compute(&job.plan, &*node_stats);
                    let answer = response(&job.request.swing, job.plan.bat_id(), job.plan.ball_id(), &result);
                    stats.count(&answer);
                    if let Some(tape) = &tape {
                        record_call(tape, job.id, &job.request, &answer);
                    }
                    if !responder.respond(job.id, answer) {
                        NodeStats::bump(&stats.unsent);
                    }
                    in_flight.fetch_sub(1, Ordering::AcqRel);
                }
            })?);
        }
        Ok(ServiceCalls { responder, jobs: Some(tx), in_flight, capacity, workers: handles, stats, tape })
    }

    /// Queues a planned call, or answers it DROPPED at once when `capacity` calls are in flight.
    pub fn submit(&self, id: RmwRequestId, plan: Plan, request: SimulateSwing_Request) {
        NodeStats::bump(&self.stats.received);
        let taken = self
            .in_flight
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| (n < self.capacity).then_some(n + 1))
            .is_ok();
        if taken {
            if let Some(jobs) = &self.jobs {
                match jobs.try_send(CallJob { id, plan, request }) {
                    Ok(()) => return,
                    Err(e) => {
                        self.in_flight.fetch_sub(1, Ordering::AcqRel);
                        let job = e.into_inner();
                        return self.answer_dropped(job.id, &job.request);
                    }
                }
            }
        }
        self.answer_dropped(id, &request);
    }

    fn answer_dropped(&self, id: RmwRequestId, request: &SimulateSwing_Request) {
        let answer = dropped_response(&request.swing, self.capacity);
        self.stats.count(&answer);
        if let Some(tape) = &self.tape {
            record_call(tape, id, request, &answer);
        }
        if !self.responder.respond(id, answer) {
            NodeStats::bump(&self.stats.unsent);
        }
    }

    /// Stops taking calls, lets the queued ones finish, and joins the workers.
    pub fn shutdown(mut self) {
        self.jobs = None;
        for worker in self.workers.drain(..) {
            let _ = worker.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams};
    use std::sync::Mutex;

    fn swing(bat_id: &str, ball_id: &str) -> Swing {
        Swing {
            swing_id: 3,
            bat_id: bat_id.into(),
            ball_id: ball_id.into(),
            ball_speed: 38.5,
            bat_cm_speed: 21.0,
            bat_angular_speed: 48.0,
            impact_z: 0.7,
            measured_exit_speed: f64::NAN,
            ..Swing::default()
        }
    }

    fn settings() -> ModelSettings {
        ModelSettings { default_modes: 2, ..ModelSettings::default() }
    }

    fn call(registry: &mut Registry, request: SimulateSwing_Request) -> SimulateSwing_Response {
        let (plan, _) = plan_call(registry, &settings(), &request, &());
        response(&request.swing, plan.bat_id(), plan.ball_id(), &engine::compute(&plan, &()))
    }

    #[test]
    fn a_call_without_inline_params_is_planned_like_the_swing() {
        let s = swing("r161", "");
        let mut registry = Registry::new();
        let answer = call(&mut registry, SimulateSwing_Request { swing: s.clone(), ..Default::default() });
        let mut other = Registry::new();
        let (plan, _) = engine::plan_swing(&mut other, &settings(), "r161", "", convert::swing_input(&s));
        let topic = convert::exit_velocity(&s, plan.bat_id(), plan.ball_id(), &engine::compute(&plan, &()));
        assert_eq!(answer.exit_velocity.status, ExitVelocity::STATUS_OK, "{}", answer.exit_velocity.message);
        assert_eq!(format!("{:?}", answer.exit_velocity), format!("{topic:?}"));
        assert_eq!(answer.modal_energies.len(), 1);
    }

    #[test]
    fn inline_params_are_used_for_the_call_only_and_a_mismatched_id_is_named() {
        let mut registry = Registry::new();
        let ball = BallParams {
            ball_id: "soft".into(),
            mass: 0.142,
            radius: 0.0365,
            cor: 0.4,
            stiffness: 4e7,
            exponent: 1.9,
            ..BallParams::default()
        };
        let request = SimulateSwing_Request { swing: swing("", ""), ball: vec![ball.clone()], ..Default::default() };
        let answer = call(&mut registry, request);
        assert_eq!(answer.exit_velocity.status, ExitVelocity::STATUS_OK, "{}", answer.exit_velocity.message);
        assert_eq!(answer.exit_velocity.ball_id, "soft");
        assert!(registry.resolve_ball("soft").is_err(), "the node's balls are unchanged");
        let request = SimulateSwing_Request { swing: swing("", "hard"), ball: vec![ball], ..Default::default() };
        let answer = call(&mut registry, request);
        assert_eq!(answer.exit_velocity.status, ExitVelocity::STATUS_REJECTED);
        assert!(answer.exit_velocity.message.contains("swing.ball_id 'hard'"), "{}", answer.exit_velocity.message);
        let bad_bat = BatParams { bat_id: "b".into(), ..BatParams::default() };
        let request = SimulateSwing_Request { swing: swing("", ""), bat: vec![bad_bat], ..Default::default() };
        let answer = call(&mut registry, request);
        assert_eq!(answer.exit_velocity.status, ExitVelocity::STATUS_REJECTED);
        assert!(answer.exit_velocity.message.starts_with("bat[0]: "), "{}", answer.exit_velocity.message);
        assert!(answer.modal_energies.is_empty());
    }

    /// Answers kept in order, each after `delay`.
    struct Slow(Mutex<Vec<u8>>, std::time::Duration);

    impl Responder for Slow {
        fn respond(&self, _: RmwRequestId, r: SimulateSwing_Response) -> bool {
            std::thread::sleep(self.1);
            self.0.lock().unwrap().push(r.exit_velocity.status);
            true
        }
    }

    #[test]
    fn a_flood_is_answered_or_refused_with_a_reason_none_lost() {
        let out = Arc::new(Slow(Mutex::new(Vec::new()), std::time::Duration::from_millis(2)));
        let calls = ServiceCalls::start(Arc::clone(&out), 1, 4, Arc::new(NodeStats::new()), None).unwrap();
        let mut registry = Registry::new();
        for _ in 0..50 {
            let request = SimulateSwing_Request { swing: swing("", ""), ..Default::default() };
            let (plan, _) = plan_call(&mut registry, &settings(), &request, &());
            calls.submit(RmwRequestId::default(), plan, request);
        }
        let stats = Arc::clone(&calls.stats);
        calls.shutdown();
        let statuses = out.0.lock().unwrap().clone();
        assert_eq!(statuses.len(), 50, "every call answered");
        let dropped = statuses.iter().filter(|s| **s == ExitVelocity::STATUS_DROPPED).count();
        assert!(dropped > 0 && dropped < 50, "{dropped} of 50 dropped");
        assert_eq!(stats.dropped.load(Ordering::Relaxed) as usize, dropped);
        assert_eq!((stats.ok.load(Ordering::Relaxed) as usize) + dropped, 50);
    }
}
