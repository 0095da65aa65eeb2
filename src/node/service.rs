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
//!   status DROPPED saying so (nothing computed), as a swing would be. An inline bat is built and its modes
//!   solved on those workers, never on the receive loop, and kept by content ([`InlineBats`], the last
//!   [`INLINE_BATS_KEPT`]): identical inline bats are solved once (`service_inline_bats_built` /
//!   `service_inline_bats_reused` on `/diagnostics`).
//! - **Bounded replies.** A call whose swing is refused (a `header.frame_id` over 256 bytes, say) is REJECTED
//!   before anything is computed; every string a response echoes is at most 256 bytes, so no request can
//!   make a response too large to send, and one hostile call cannot stall the replies to other clients. The request reader keeps up to
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
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use ros2_client::service::RmwRequestId;
use ros2_client::Server;

use crate::model::convert;
use crate::model::convert::BallModel;
use crate::model::engine::{self, BatEntry, ModeCacheStats, Plan, Registry};
use crate::model::limits::echo;
use crate::model::lru::LruMap;
use crate::model::settings::ModelSettings;
use crate::model::time::RosTime as _;
use crate::msgs::service_msgs::msg::ServiceEventInfo;
use crate::msgs::sweetspot_msgs::msg::{BatParams, ExitVelocity, Swing};
use crate::msgs::sweetspot_msgs::srv::{SimulateSwing_Event, SimulateSwing_Request, SimulateSwing_Response};

use super::recording::{Recorded, Tape};
use super::stats::NodeStats;

/// The service's name, private to the node (`/<ns>/<node>/simulate_swing`).
pub const SERVICE_NAME: &str = "~/simulate_swing";

/// The service's ros2-client server.
pub type SimulateSwingServer = Server<SimulateSwing_Request, SimulateSwing_Response>;

/// What the receive loop makes of a call: a plan ready to compute, or a call with an inline bat, whose bat is
/// built, solved and checked on the service's workers ([`InlineBats`]) — never on the receive loop, where a
/// 1,200-slice bat would hold every other input for a solve.
#[derive(Debug)]
pub enum CallPlan {
    /// Planned: compute it.
    Ready(Plan),
    /// The inline bat still to be made; the ball already resolved.
    InlineBat(Box<InlineBatCall>),
}

/// A call with an inline bat as the receive loop leaves it: its ball resolved (inline or the node's), the
/// settings of the moment, the swing's input.
#[derive(Debug)]
pub struct InlineBatCall {
    ball_id: String,
    ball: BallModel,
    settings: ModelSettings,
    input: engine::SwingInput,
}

/// What a call becomes, and a bat the node's registry made from a preset for it (its SweetSpot is new).
///
/// A call whose swing [`convert::check_swing_message`] refuses (a `header.frame_id` over 256 bytes, say)
/// is REJECTED here, before anything is computed. Without inline params this is [`engine::plan_swing`] on the
/// node's registry. With an inline ball only, that ball and the node's bat go into a scratch registry and the
/// swing is planned there. With an inline bat (checked as on its topic; the swing's id must be empty or the
/// same) only the cheap part happens here: the ball is resolved, and the bat is left to [`plan_inline_bat`] on
/// a worker.
pub fn plan_call(
    registry: &mut Registry,
    settings: &ModelSettings,
    request: &SimulateSwing_Request,
) -> (CallPlan, Option<Arc<BatEntry>>) {
    let swing = &request.swing;
    let reject = |bat_id: &str, ball_id: &str, reason: String| {
        CallPlan::Ready(Plan::Reject { bat_id: echo(bat_id).into_owned(), ball_id: echo(ball_id).into_owned(), reason })
    };
    if let Err(reason) = convert::check_swing_message(swing) {
        return (reject(&swing.bat_id, &swing.ball_id, reason), None);
    }
    let input = convert::swing_input(swing);
    if request.bat.is_empty() && request.ball.is_empty() {
        let (plan, new_bat) = engine::plan_swing(registry, settings, &swing.bat_id, &swing.ball_id, input);
        return (CallPlan::Ready(plan), new_bat);
    }
    let inline_bat = request.bat.first();
    if let Some(params) = inline_bat {
        if let Err(reason) = same_id("bat_id", &swing.bat_id, "bat[0].bat_id", &params.bat_id) {
            return (reject(&swing.bat_id, &swing.ball_id, reason), None);
        }
    }
    let bat_id_for_rejections = inline_bat.map_or(swing.bat_id.as_str(), |p| p.bat_id.as_str());
    // The node's bat, when the call brings none: resolved here (a preset is made in the node's registry).
    let mut new_bat = None;
    let node_bat = match inline_bat {
        Some(_) => None,
        None => match registry.resolve_bat(&swing.bat_id, settings) {
            Ok((entry, created)) => {
                new_bat = created.then(|| Arc::clone(&entry));
                Some(entry)
            }
            Err(reason) => {
                let bat_id = registry.effective_bat_id(&swing.bat_id, settings);
                return (reject(&bat_id, &swing.ball_id, reason), None);
            }
        },
    };
    let bat_id = node_bat.as_ref().map_or(bat_id_for_rejections, |entry| entry.bat_id.as_str()).to_string();
    let (ball_id, ball) = match request.ball.first() {
        Some(params) => {
            if let Err(reason) = same_id("ball_id", &swing.ball_id, "ball[0].ball_id", &params.ball_id) {
                return (reject(&bat_id, &swing.ball_id, reason), new_bat);
            }
            match convert::ball_from_params(params) {
                Ok(ball) => (params.ball_id.clone(), ball),
                Err(reason) => return (reject(&bat_id, &params.ball_id, format!("ball[0]: {reason}")), new_bat),
            }
        }
        None => match registry.use_ball(&swing.ball_id, settings) {
            Ok(found) => found,
            Err(reason) => return (reject(&bat_id, &swing.ball_id, reason), new_bat),
        },
    };
    match node_bat {
        Some(entry) => (CallPlan::Ready(plan_in_scratch(entry, &ball_id, ball, settings, input)), new_bat),
        None => {
            let call = InlineBatCall { ball_id, ball, settings: settings.clone(), input };
            (CallPlan::InlineBat(Box::new(call)), new_bat)
        }
    }
}

/// The swing planned against one bat and one ball only, in a scratch registry: the node's are not changed.
fn plan_in_scratch(
    bat: Arc<BatEntry>,
    ball_id: &str,
    ball: BallModel,
    settings: &ModelSettings,
    input: engine::SwingInput,
) -> Plan {
    let mut scratch = Registry::with_limits(1, 1);
    let bat_id = bat.bat_id.clone();
    scratch.set_shared_bat(bat);
    scratch.set_ball(ball_id, ball);
    engine::plan_swing(&mut scratch, settings, &bat_id, ball_id, input).0
}

/// The plan of a call with an inline bat, on a worker: the bat built from `params` (or found in `bats` when
/// the same params came before), its modes solved once and checked against the time step, then the swing
/// planned with the ball [`plan_call`] resolved.
pub fn plan_inline_bat(
    call: InlineBatCall,
    params: &BatParams,
    bats: &InlineBats,
    stats: &impl ModeCacheStats,
) -> Plan {
    let InlineBatCall { ball_id, ball, settings, input } = call;
    let reject = |reason: String| Plan::Reject {
        bat_id: echo(&params.bat_id).into_owned(),
        ball_id: echo(&ball_id).into_owned(),
        reason: format!("bat[0]: {reason}"),
    };
    let entry = match bats.get_or_build(params, &settings) {
        Ok(entry) => entry,
        Err(reason) => return reject(reason),
    };
    if let Err(reason) = entry.check_modes(&settings, stats) {
        return reject(reason);
    }
    plan_in_scratch(entry, &ball_id, ball, &settings, input)
}

/// How many inline bats the service keeps, by content: a rig calling with the same few bats solves each once.
pub const INLINE_BATS_KEPT: usize = 16;

/// One kept inline bat: its content key and what building it gave (the entry, or the refusal's reason).
type KeptBat = (Vec<u8>, Result<Arc<BatEntry>, String>);

/// The inline bats of recent calls, by their content (every field of the BatParams but its header, and the
/// settings a bat entry depends on): identical params give the same entry, so its modes are solved once.
/// Shared by the service's workers; at most [`INLINE_BATS_KEPT`], least recently used forgotten first.
pub struct InlineBats {
    hasher: std::collections::hash_map::RandomState,
    kept: Mutex<LruMap<KeptBat>>,
    /// Inline bats built (not found by content).
    pub built: AtomicU64,
    /// Inline bats found by content.
    pub reused: AtomicU64,
}

impl Default for InlineBats {
    fn default() -> InlineBats {
        InlineBats {
            hasher: Default::default(),
            kept: Mutex::new(LruMap::new(INLINE_BATS_KEPT)),
            built: AtomicU64::new(0),
            reused: AtomicU64::new(0),
        }
    }
}

impl InlineBats {
    /// The entry of `params` under `settings`: the kept one when the same content came before, else built
    /// (checked as on the BatParams topic, modes not yet solved) and kept. A bat that cannot be built is kept
    /// with its reason.
    pub fn get_or_build(&self, params: &BatParams, settings: &ModelSettings) -> Result<Arc<BatEntry>, String> {
        use std::hash::BuildHasher as _;
        let content = bat_content(params, settings);
        let key = format!("{:016x}", self.hasher.hash_one(&content));
        let mut kept = self.kept.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some((same, entry)) = kept.get(&key) {
            if *same == content {
                NodeStats::bump(&self.reused);
                return entry.clone();
            }
        }
        NodeStats::bump(&self.built);
        // Building slices a profile (cheap); the modes are solved by the caller, outside this lock, once per
        // entry (the entry's own once-cell makes a second caller wait for the first's solve).
        let entry = convert::bat_from_params_capped(params, settings.max_bat_slices)
            .map(|built| Arc::new(BatEntry::new(&params.bat_id, built.bat, built.max_modes, settings)));
        kept.insert(key, (content, entry.clone()), false, None);
        entry
    }
}

/// The plan of a [`CallPlan::InlineBat`] whose request lost its bat: cannot happen ([`plan_call`] makes one
/// only from a request with a bat), answered REJECTED rather than trusted.
fn unreachable_plan(swing: &Swing) -> Plan {
    Plan::Reject {
        bat_id: echo(&swing.bat_id).into_owned(),
        ball_id: echo(&swing.ball_id).into_owned(),
        reason: "bat[0]: missing from the request".into(),
    }
}

/// Every field of a BatParams but its header, and the settings its entry depends on, as bytes.
fn bat_content(p: &BatParams, settings: &ModelSettings) -> Vec<u8> {
    let mut out = Vec::with_capacity(64 + 24 * p.station_z.len());
    let mut put = |bytes: &[u8]| {
        out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        out.extend_from_slice(bytes);
    };
    put(p.bat_id.as_bytes());
    put(p.preset.as_bytes());
    for list in [&p.station_z, &p.outer_radius, &p.inner_radius] {
        put(&list.iter().flat_map(|v| v.to_bits().to_le_bytes()).collect::<Vec<u8>>());
    }
    let scalars = [
        p.density,
        p.youngs_modulus,
        p.shear_modulus,
        p.core_density,
        p.core_youngs_modulus,
        p.core_shear_modulus,
        p.core_z_start,
        p.core_z_end,
        p.slice_length,
        settings.time_step,
    ];
    put(&scalars.iter().flat_map(|v| v.to_bits().to_le_bytes()).collect::<Vec<u8>>());
    let counts = [u64::from(p.max_modes), settings.default_modes as u64, settings.max_bat_slices as u64];
    put(&counts.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>());
    out
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

/// The response the topics would carry for the swing: its ExitVelocity, and its ModalEnergies when that
/// answer is OK (the node publishes those exactly then). Every string echoed is at most 256 bytes, so no
/// request can make a response too large to send.
pub fn response(
    swing: &Swing,
    bat_id: &str,
    ball_id: &str,
    result: &Result<engine::Computed, String>,
) -> SimulateSwing_Response {
    let exit_velocity = convert::exit_velocity(swing, bat_id, ball_id, result);
    // One verdict: the ModalEnergies goes with an OK answer only.
    let modal_energies = match result {
        Ok(computed) if exit_velocity.status == ExitVelocity::STATUS_OK => {
            vec![convert::modal_energies(swing, bat_id, computed)]
        }
        _ => Vec::new(),
    };
    SimulateSwing_Response { exit_velocity, modal_energies }
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
    plan: CallPlan,
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
    /// The inline bats of recent calls, by content.
    pub bats: Arc<InlineBats>,
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
        let bats = Arc::new(InlineBats::default());
        let mut handles = Vec::new();
        for i in 0..workers.max(1) {
            let (rx, responder, in_flight) = (rx.clone(), Arc::clone(&responder), Arc::clone(&in_flight));
            let (stats, node_stats, tape) = (Arc::clone(&stats), Arc::clone(&node_stats), tape.clone());
            let bats = Arc::clone(&bats);
            handles.push(std::thread::Builder::new().name(format!("sweetspot-call-{i}")).spawn(move || {
                for job in rx {
                    let plan = match job.plan {
                        CallPlan::Ready(plan) => plan,
                        CallPlan::InlineBat(call) => match job.request.bat.first() {
                            Some(params) => plan_inline_bat(*call, params, &bats, &*node_stats),
                            None => unreachable_plan(&job.request.swing),
                        },
                    };
                    let result = engine::compute(&plan, &*node_stats);
                    let answer = response(&job.request.swing, plan.bat_id(), plan.ball_id(), &result);
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
        Ok(ServiceCalls { responder, jobs: Some(tx), in_flight, capacity, workers: handles, stats, bats, tape })
    }

    /// The `/diagnostics` key/value pairs: [`CallStats::values`] and the inline bats built and reused.
    pub fn values(&self) -> Vec<(String, String)> {
        let mut values = self.stats.values();
        let load = |c: &AtomicU64| c.load(Ordering::Relaxed).to_string();
        values.push(("service_inline_bats_built".into(), load(&self.bats.built)));
        values.push(("service_inline_bats_reused".into(), load(&self.bats.reused)));
        values
    }

    /// Queues a planned call, or answers it DROPPED at once when `capacity` calls are in flight.
    pub fn submit(&self, id: RmwRequestId, plan: CallPlan, request: SimulateSwing_Request) {
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
        let (plan, _) = plan_call(registry, &settings(), &request);
        let plan = match plan {
            CallPlan::Ready(plan) => plan,
            CallPlan::InlineBat(call) => plan_inline_bat(*call, &request.bat[0], &InlineBats::default(), &()),
        };
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
    fn a_call_refuses_a_batter_side_as_the_topic_does() {
        let s = Swing { batter_side: 7, ..swing("r161", "") };
        let answer = call(&mut Registry::new(), SimulateSwing_Request { swing: s.clone(), ..Default::default() });
        let (plan, _) = convert::plan_swing_message(&mut Registry::new(), &settings(), &s);
        let topic = convert::exit_velocity(&s, plan.bat_id(), plan.ball_id(), &engine::compute(&plan, &()));
        assert_eq!(answer.exit_velocity.status, ExitVelocity::STATUS_REJECTED);
        assert!(answer.exit_velocity.message.starts_with("batter_side = 7 is out of range"), "{answer:?}");
        assert_eq!(format!("{:?}", answer.exit_velocity), format!("{topic:?}"));
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
        assert!(registry.resolve_ball("soft", &ModelSettings::default()).is_err(), "the node's balls are unchanged");
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
            let (plan, _) = plan_call(&mut registry, &settings(), &request);
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

    /// Every response the workers sent, whole.
    #[derive(Default)]
    struct Kept(Mutex<Vec<SimulateSwing_Response>>);

    impl Responder for Kept {
        fn respond(&self, _: RmwRequestId, r: SimulateSwing_Response) -> bool {
            self.0.lock().unwrap().push(r);
            true
        }
    }

    /// Calls `requests` through the workers as the receive loop does (planned, submitted, computed, answered).
    fn through_the_workers(
        requests: Vec<SimulateSwing_Request>,
        workers: usize,
    ) -> (Vec<SimulateSwing_Response>, Arc<NodeStats>, Arc<InlineBats>) {
        let out = Arc::new(Kept::default());
        let node_stats = Arc::new(NodeStats::new());
        let n = requests.len();
        let calls = ServiceCalls::start(Arc::clone(&out), workers, n, Arc::clone(&node_stats), None).unwrap();
        let bats = Arc::clone(&calls.bats);
        let mut registry = Registry::new();
        for request in requests {
            let (plan, _) = plan_call(&mut registry, &settings(), &request);
            calls.submit(RmwRequestId::default(), plan, request);
        }
        calls.shutdown();
        let answers = std::mem::take(&mut *out.0.lock().unwrap());
        assert_eq!(answers.len(), n, "every call answered");
        (answers, node_stats, bats)
    }

    #[test]
    fn the_worker_answers_with_the_swing_s_own_bat_and_ball_ids_in_their_fields() {
        let requests = vec![
            SimulateSwing_Request { swing: swing("aluminum", "baseball"), ..Default::default() },
            SimulateSwing_Request { swing: swing("aluminum", "no-such-ball"), ..Default::default() },
        ];
        let (answers, _, _) = through_the_workers(requests, 1);
        let ok = &answers[0];
        assert_eq!(ok.exit_velocity.status, ExitVelocity::STATUS_OK, "{}", ok.exit_velocity.message);
        assert_eq!((ok.exit_velocity.bat_id.as_str(), ok.exit_velocity.ball_id.as_str()), ("aluminum", "baseball"));
        assert_eq!(ok.modal_energies[0].bat_id, "aluminum");
        let rejected = &answers[1];
        assert_eq!(rejected.exit_velocity.status, ExitVelocity::STATUS_REJECTED);
        let ids = (rejected.exit_velocity.bat_id.as_str(), rejected.exit_velocity.ball_id.as_str());
        assert_eq!(ids, ("aluminum", "no-such-ball"));
    }

    #[test]
    fn a_huge_frame_id_is_rejected_before_computing_and_no_answer_echoes_more_than_256_bytes_of_it() {
        let mut requests = Vec::new();
        for (k, bytes) in [300, 70_000, 10 << 20].into_iter().enumerate() {
            let mut s = swing("r161", "");
            s.swing_id = k as u64;
            s.header.frame_id = "f".repeat(bytes);
            requests.push(SimulateSwing_Request { swing: s, ..Default::default() });
        }
        let (answers, node_stats, _) = through_the_workers(requests, 1);
        for answer in &answers {
            let ev = &answer.exit_velocity;
            assert_eq!(ev.status, ExitVelocity::STATUS_REJECTED, "{}", ev.message);
            assert!(ev.message.contains("header.frame_id is"), "{}", ev.message);
            assert!(ev.header.frame_id.len() <= 256, "{} bytes echoed", ev.header.frame_id.len());
            assert!(answer.modal_energies.is_empty(), "one verdict: no ModalEnergies with a REJECTED answer");
            let bytes = crate::msgs::encode_cdr(answer).unwrap().len();
            assert!(bytes < 8 * 1024, "a response of {bytes} bytes");
        }
        assert_eq!(node_stats.snapshot(0).mode_cache_misses, 0, "nothing computed");
    }

    #[test]
    fn identical_inline_bats_are_built_and_solved_once_on_the_workers() {
        let bat = convert::params_of_preset("mine", "r161", Default::default());
        let requests: Vec<SimulateSwing_Request> = (0..300)
            .map(|k| {
                let mut s = swing("", "");
                s.swing_id = k;
                SimulateSwing_Request { swing: s, bat: vec![bat.clone()], ..Default::default() }
            })
            .collect();
        let (answers, node_stats, bats) = through_the_workers(requests, 2);
        assert!(answers
            .iter()
            .all(|a| a.exit_velocity.status == ExitVelocity::STATUS_OK && a.exit_velocity.bat_id == "mine"));
        assert_eq!(bats.built.load(Ordering::Relaxed), 1);
        assert_eq!(bats.reused.load(Ordering::Relaxed), 299);
        assert_eq!(node_stats.snapshot(0).mode_cache_misses, 1, "one solve for 300 identical bats");
        // Another bat (one field differs) is another entry.
        let mut other = bat.clone();
        other.density *= 1.01;
        let request = SimulateSwing_Request { swing: swing("", ""), bat: vec![other], ..Default::default() };
        let (answers, node_stats, bats) = through_the_workers(vec![request.clone(), request], 1);
        assert_eq!(answers[0].exit_velocity.status, ExitVelocity::STATUS_OK);
        assert_eq!((bats.built.load(Ordering::Relaxed), node_stats.snapshot(0).mode_cache_misses), (1, 1));
    }

    #[test]
    fn an_inline_bat_is_not_solved_on_the_receive_loop() {
        let bat = convert::params_of_preset("mine", "r161", Default::default());
        let request = SimulateSwing_Request { swing: swing("", ""), bat: vec![bat], ..Default::default() };
        let (plan, _) = plan_call(&mut Registry::new(), &settings(), &request);
        assert!(matches!(plan, CallPlan::InlineBat(_)), "left to a worker: {plan:?}");
    }
}
