//! The imperative shell: DDS participant, topics, parameter services, the receive loop, the worker pipeline,
//! diagnostics, recording and signals. Everything it decides is delegated to the pure modules.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::pin::pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};
use std::time::{Duration, Instant};

use anyhow::Context as _;
use futures::{FutureExt as _, StreamExt};
use ros2_client::qos::History;
use ros2_client::ros2::LogLevel;
use ros2_client::rosout::RosoutRaw;
use ros2_client::{NodeLoggingHandle, NodeName, NodeOptions, ParameterValue, Publisher};

use crate::bag::{RecorderConfig, TopicInfo};
use crate::model::convert;
use crate::model::engine::{self, BatEntry, BatSummary, Registry, RegistryUsage};
use crate::model::time::{now_ns, RosTime};
use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::diagnostic_msgs::msg::DiagnosticArray;
use crate::msgs::std_msgs::msg::Header;
use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};

use super::pipeline::{InlinePacing, Outcome, Pipeline, ResultSink};
use super::recording::{recorded_qos, Recorded, Tape};
use super::ros_args::{NameResolver, NodeIdentity, RosArgs};
use super::settings::{NodeSettings, SettingEffect, READ_ONLY};
use super::stats::{health_report, GapCounter, NodeStats, RateLimiter, StatsSnapshot};

/// Default node name (`-r __node:=` changes it).
pub const DEFAULT_NODE_NAME: &str = "sweetspot";

/// The node's topics, relative so `-r __ns:=` moves them (except `/diagnostics`, absolute by convention).
pub use crate::model::topics;

/// How `sweetspot node` was asked to run.
#[derive(Debug, Clone, Default)]
pub struct NodeConfig {
    /// The `--ros-args` section.
    pub ros_args: RosArgs,
    /// `--no-record`: overrides the `record` parameter.
    pub no_record: bool,
}

/// Everything resolved before DDS starts: identity, topic names, parameter values.
#[derive(Debug, Clone)]
pub struct ResolvedConfig {
    /// Node name and namespace.
    pub identity: NodeIdentity,
    /// Topic name resolution (namespace + remaps).
    pub names: NameResolver,
    /// Parameter values after defaults, params files, `-p` and `--no-record`.
    pub settings: NodeSettings,
    /// Log to `/rosout` (`--disable-rosout-logs` turns it off).
    pub rosout: bool,
}

impl NodeConfig {
    /// Applies the ROS conventions (no DDS involved).
    pub fn resolve(&self) -> anyhow::Result<ResolvedConfig> {
        let identity = self.ros_args.identity(DEFAULT_NODE_NAME, "/");
        let mut overrides = self.ros_args.parameter_overrides(&identity)?;
        if self.no_record {
            overrides.insert("record".to_string(), ParameterValue::Boolean(false));
        }
        let settings = NodeSettings::with_overrides(&overrides).map_err(|e| anyhow::anyhow!(e))?;
        let names = self.ros_args.resolver(&identity);
        Ok(ResolvedConfig { identity, names, settings, rosout: self.ros_args.rosout_logs.unwrap_or(true) })
    }
}

/// Runs the node until SIGINT or SIGTERM, then finishes the bag and returns.
pub fn run(config: NodeConfig) -> anyhow::Result<()> {
    let resolved = config.resolve()?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .thread_name("sweetspot-dds")
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    let result = runtime.block_on(run_async(resolved));
    // DDS background tasks may still hold the runtime; do not let them delay the exit.
    runtime.shutdown_timeout(Duration::from_millis(200));
    result
}

use crate::ros::{diagnostics_qos, params_qos, results_qos, sweet_spot_qos as latched_results_qos, swing_qos};

/// rosout + tracing, from any thread.
#[derive(Clone)]
struct Log {
    handle: Arc<NodeLoggingHandle>,
    rosout: bool,
}

impl Log {
    fn log(&self, level: LogLevel, message: &str) {
        // Our own tracing line (target `sweetspot`), and the same text on /rosout for ROS tools.
        match level {
            LogLevel::Fatal | LogLevel::Error => tracing::error!("{message}"),
            LogLevel::Warn => tracing::warn!("{message}"),
            LogLevel::Info => tracing::info!("{message}"),
            LogLevel::Debug => tracing::debug!("{message}"),
        }
        if self.rosout {
            self.handle.rosout_raw(
                ros2_client::builtin_interfaces::Time::now(),
                level,
                self.handle.base_name(),
                message,
                file!(),
                "sweetspot::node",
                line!(),
            );
        }
    }
    fn info(&self, m: &str) {
        self.log(LogLevel::Info, m)
    }
    fn warn(&self, m: &str) {
        self.log(LogLevel::Warn, m)
    }
    fn error(&self, m: &str) {
        self.log(LogLevel::Error, m)
    }
}

/// Publishes and records results in swing order (on the pipeline's sequencer thread, or inline on the
/// receive task when the pipeline is idle).
struct DdsSink {
    exit_velocity: Arc<Publisher<ExitVelocity>>,
    modal_energies: Arc<Publisher<ModalEnergies>>,
    /// Whether `modal_energies` has a matched subscription (see [`EnergiesListeners`]).
    energies_listened: Arc<AtomicBool>,
    tape: Arc<Tape>,
    stats: Arc<NodeStats>,
}

impl ResultSink<Swing> for DdsSink {
    fn deliver(&mut self, outcome: &Outcome<Swing>) -> bool {
        let swing = &outcome.payload;
        let ev = convert::exit_velocity(swing, &outcome.bat_id, &outcome.ball_id, &outcome.result);
        let stamp_ns = swing.header.stamp.unix_ns();
        let mut delivered = true;
        if let Ok(computed) = &outcome.result {
            let me = convert::modal_energies(swing, &outcome.bat_id, computed);
            // Always recorded; published only when someone listens: a DDS write wakes RustDDS's event
            // loop thread even with no reader, which costs every answer latency for nothing.
            self.tape.record(Recorded::ModalEnergies, &me, now_ns(), stamp_ns);
            if self.energies_listened.load(Ordering::Relaxed) {
                let published = self.modal_energies.publish(me).is_ok();
                if published {
                    NodeStats::bump(&self.stats.modal_energies_published);
                }
                delivered &= published;
            }
        }
        // ExitVelocity last, so a listener that has the answer also has its energies.
        self.tape.record(Recorded::ExitVelocity, &ev, now_ns(), stamp_ns);
        delivered &= self.exit_velocity.publish(ev).is_ok();
        delivered
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
struct EnergiesListeners {
    flag: Arc<AtomicBool>,
}

impl EnergiesListeners {
    fn refresh(&self, publisher: &Publisher<ModalEnergies>, node: &ros2_client::Node) {
        // Resolves at once iff a reader is matched now; unlike `get_subscription_count` it does not log an
        // error for a writer that never had a reader.
        let matched = publisher.wait_for_subscription(node).now_or_never().is_some();
        self.flag.store(matched, Ordering::Relaxed);
    }
}

/// Messages from helper tasks back to the receive loop.
enum Event {
    /// A parameter was set through `ros2 param set`.
    ParameterChanged(SettingEffect),
    /// A bat's SweetSpot is ready (published only if the bat is still current).
    Summary(Arc<BatEntry>, Box<Result<BatSummary, String>>),
}

async fn run_async(resolved: ResolvedConfig) -> anyhow::Result<()> {
    let ResolvedConfig { identity, names, settings, rosout } = resolved;
    let fqn = identity.fully_qualified_name();
    let started_utc = chrono::Utc::now();
    let stats = Arc::new(NodeStats::new());
    let shared_settings = Arc::new(RwLock::new(settings.clone()));
    let (events_tx, mut events_rx) = tokio::sync::mpsc::unbounded_channel::<Event>();

    // Parameters: declared with the start-up values, validated on every set, read-only ones refused later.
    let validator_settings = Arc::clone(&shared_settings);
    let action_settings = Arc::clone(&shared_settings);
    let action_events = events_tx.clone();
    let mut options = NodeOptions::new()
        .enable_rosout(rosout)
        .start_parameter_services(true)
        .parameter_validator(Box::new(move |name, value| {
            let current = validator_settings.read().map_err(|_| "settings lock poisoned".to_string())?.clone();
            if READ_ONLY.contains(&name) {
                let unchanged = current.declarations().into_iter().any(|(n, v)| n == name && v == *value);
                return if unchanged {
                    Ok(())
                } else {
                    Err(format!("{name} is read-only while the node runs: restart with -p {name}:=…"))
                };
            }
            let mut probe = current;
            probe.apply(name, value).map(|_| ())
        }))
        .parameter_set_action(Box::new(move |name, value| {
            let mut settings = action_settings.write().map_err(|_| "settings lock poisoned".to_string())?;
            let before = settings.clone();
            let effect = settings.apply(name, value)?;
            if *settings != before {
                let _ = action_events.send(Event::ParameterChanged(effect));
            }
            Ok(())
        }));
    for (name, value) in settings.declarations() {
        options = options.declare_parameter(name, value);
    }

    let (context, dds_config) = crate::ros::context_from_env().context("creating the DDS participant")?;
    let node_name =
        NodeName::new(&identity.namespace, &identity.name).map_err(|e| anyhow::anyhow!("node name {fqn}: {e:?}"))?;
    let mut node = context.new_node(node_name, options).map_err(|e| anyhow::anyhow!("creating node {fqn}: {e:?}"))?;
    let log = Log { handle: Arc::new(node.logging_handle()), rosout };

    // Topics: resolved here (namespace + remaps), handed to ros2-client as absolute names.
    let topic_names: BTreeMap<&str, String> = [
        topics::BAT_PARAMS,
        topics::BALL_PARAMS,
        topics::SWING,
        topics::EXIT_VELOCITY,
        topics::MODAL_ENERGIES,
        topics::SWEET_SPOT,
        topics::DIAGNOSTICS,
    ]
    .into_iter()
    .map(|t| (t, names.resolve(t)))
    .collect();
    macro_rules! topic {
        ($key:expr, $ty:ty, $qos:expr) => {{
            crate::ros::create_topic::<$ty>(&node, &topic_names[$key], &$qos)?
        }};
    }
    let bat_topic = topic!(topics::BAT_PARAMS, BatParams, params_qos());
    let ball_topic = topic!(topics::BALL_PARAMS, BallParams, params_qos());
    let swing_topic = topic!(topics::SWING, Swing, swing_qos());
    let ev_topic = topic!(topics::EXIT_VELOCITY, ExitVelocity, results_qos());
    let me_topic = topic!(topics::MODAL_ENERGIES, ModalEnergies, results_qos());
    let ss_topic = topic!(topics::SWEET_SPOT, SweetSpot, latched_results_qos());
    let diag_topic = topic!(topics::DIAGNOSTICS, DiagnosticArray, diagnostics_qos());
    let dds = |e| anyhow::anyhow!("{e:?}");
    let bat_sub = node.create_subscription::<BatParams>(&bat_topic, None).map_err(dds)?;
    let ball_sub = node.create_subscription::<BallParams>(&ball_topic, None).map_err(dds)?;
    // DDS acknowledges a sample when it reaches the reader's cache, not when the node takes it, so a burst
    // faster than the node takes swings would overwrite a keep-last-1000 cache: size it like the pipeline.
    let swing_reader_qos = swing_qos().history(History::KeepLast { depth: settings.queue_capacity.max(1000) });
    let swing_sub = node.create_subscription::<Swing>(&swing_topic, Some(swing_reader_qos)).map_err(dds)?;
    // The topics' own QoS (ros::results_qos: deep window, bounded wait) is the writers' QoS.
    let ev_pub = Arc::new(node.create_publisher::<ExitVelocity>(&ev_topic, Some(results_qos())).map_err(dds)?);
    let me_pub = Arc::new(node.create_publisher::<ModalEnergies>(&me_topic, Some(results_qos())).map_err(dds)?);
    let ss_pub = node.create_publisher::<SweetSpot>(&ss_topic, None).map_err(dds)?;
    let diag_pub = node.create_publisher::<DiagnosticArray>(&diag_topic, None).map_err(dds)?;
    let spinner = node.spinner().map_err(dds)?;
    let spinning = tokio::spawn(spinner.spin());
    // Discovery events (after the spinner exists, else there are none); each one re-checks the listeners.
    let mut graph_events = match node.status_receiver() {
        Some(receiver) => receiver.boxed(),
        None => futures::stream::pending::<ros2_client::NodeEvent>().boxed(),
    };
    let energies_listeners = EnergiesListeners { flag: Arc::new(AtomicBool::new(false)) };
    energies_listeners.refresh(&me_pub, &node);

    // Recording: every input as received and every output as published.
    let tape = Arc::new(start_tape(&settings, &identity, started_utc, &topic_names, &log));
    tape.note_settings(&settings);

    let pipeline = Pipeline::start(
        settings.worker_count(),
        settings.queue_capacity,
        Arc::clone(&stats),
        DdsSink {
            exit_velocity: Arc::clone(&ev_pub),
            modal_energies: Arc::clone(&me_pub),
            energies_listened: Arc::clone(&energies_listeners.flag),
            tape: Arc::clone(&tape),
            stats: Arc::clone(&stats),
        },
    )
    .context("starting the worker threads")?;
    log.info(&format!(
        "{fqn} up on ROS_DOMAIN_ID {} (discovery {}): {} workers, queue {} swings, swing on {}, answers on {}, recording {}",
        dds_config.domain_id,
        dds_config.range,
        settings.worker_count(),
        settings.queue_capacity,
        topic_names[topics::SWING],
        topic_names[topics::EXIT_VELOCITY],
        tape.dir().map(|d| d.display().to_string()).unwrap_or_else(|| "off".into())
    ));

    let mut registry = Registry::with_limits(settings.model.max_bats, settings.model.max_balls);
    let summaries = Summaries {
        settings: Arc::clone(&shared_settings),
        stats: Arc::clone(&stats),
        events: events_tx.clone(),
        one_at_a_time: Arc::new(tokio::sync::Semaphore::new(1)),
    };
    let eviction_warning = RateLimiter::new(Duration::from_secs(5));
    let mut seen_usage = registry.usage();
    // The default bat answers swings without any params; its SweetSpot is published right away.
    match registry.resolve_bat("", &settings.model) {
        Ok((entry, _)) => summaries.spawn(entry, &registry),
        Err(e) => log.error(&format!("default_bat: {e}")),
    }

    let drop_warning = RateLimiter::new(Duration::from_secs(5));
    let loss_warning = RateLimiter::new(Duration::from_secs(5));
    let mut transport_gaps = GapCounter::new();
    let mut diagnostics = tokio::time::interval(Duration::from_secs_f64(settings.diagnostics_period));
    diagnostics.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut last_report = StatsSnapshot::default();
    let mut inline_pacing = InlinePacing::new();
    // The streams borrow the subscriptions; the block ends the borrows before the orderly teardown below.
    {
        let mut bats = pin!(bat_sub.async_stream());
        let mut balls = pin!(ball_sub.async_stream());
        let mut swings = pin!(swing_sub.async_stream());
        let mut shutdown = pin!(shutdown_signal());

        loop {
            tokio::select! {
                biased;
                signal = &mut shutdown => {
                    log.info(&format!("{signal}: shutting down"));
                    break;
                }
                Some(event) = events_rx.recv() => match event {
                    Event::ParameterChanged(effect) => {
                        let current = shared_settings.read().map(|s| s.clone()).unwrap_or_else(|_| settings.clone());
                        tape.note_settings(&current);
                        registry.set_limits(&current.model);
                        report_evictions(&registry, &mut seen_usage, &current, &log, &eviction_warning);
                        let refresh: Vec<Arc<BatEntry>> = match effect {
                            SettingEffect::None => Vec::new(),
                            SettingEffect::ModesChanged => registry.refresh_default_modes(&current.model),
                            SettingEffect::SweetSpotsChanged => registry.bats(),
                        };
                        for entry in refresh {
                            summaries.spawn(entry, &registry);
                        }
                    }
                    Event::Summary(entry, result) => {
                        // A summary of params that have since been replaced is stale.
                        let current = registry.is_current(&entry);
                        match *result {
                            Ok(summary) if current => {
                                let header = Header { stamp: Time::now(), frame_id: String::new() };
                                let msg = convert::sweet_spot(&summary, header);
                                tape.record(Recorded::SweetSpot, &msg, now_ns(), msg.header.stamp.unix_ns());
                                if let Err(e) = ss_pub.publish(msg) {
                                    log.warn(&format!("publishing SweetSpot of '{}': {e:?}", summary.bat_id));
                                }
                            }
                            Ok(_) => {}
                            Err(e) => log.warn(&format!("SweetSpot not published: {e}")),
                        }
                    }
                },
                Some(received) = bats.next() => {
                    let log_time = now_ns();
                    match received {
                        Ok((params, _info)) => {
                            tape.record(Recorded::BatParams, &params, log_time, params.header.stamp.unix_ns());
                            let current = shared_settings.read().map(|s| s.clone()).unwrap_or_else(|_| settings.clone());
                            // The slice cap is checked here, before any modes are solved (fuzz finding F4).
                            match convert::bat_from_params_capped(&params, current.model.max_bat_slices) {
                                Ok(built) => {
                                    NodeStats::bump(&stats.params_accepted);
                                    let entry = registry.set_bat(BatEntry::new(&params.bat_id, built.bat, built.max_modes, &current.model));
                                    report_evictions(&registry, &mut seen_usage, &current, &log, &eviction_warning);
                                    log.info(&format!("bat '{}' set ({} modes); computing its SweetSpot", entry.bat_id, entry.max_modes));
                                    summaries.spawn(entry, &registry);
                                }
                                Err(reason) => {
                                    NodeStats::bump(&stats.params_rejected);
                                    reject_params(&format!("{reason}; the previous params of '{}' stay in force", params.bat_id), &params.header, &params.bat_id, "", &ev_pub, &tape, &log);
                                }
                            }
                        }
                        Err(e) => {
                            NodeStats::bump(&stats.samples_unreadable);
                            log.warn(&format!("bat/params: unreadable sample: {e:?}"));
                        }
                    }
                }
                Some(received) = balls.next() => {
                    let log_time = now_ns();
                    match received {
                        Ok((params, _info)) => {
                            tape.record(Recorded::BallParams, &params, log_time, params.header.stamp.unix_ns());
                            match convert::ball_from_params(&params) {
                                Ok(ball) => {
                                    NodeStats::bump(&stats.params_accepted);
                                    registry.set_ball(&params.ball_id, ball);
                                    let current = shared_settings.read().map(|s| s.clone()).unwrap_or_else(|_| settings.clone());
                                    report_evictions(&registry, &mut seen_usage, &current, &log, &eviction_warning);
                                    log.info(&format!("ball '{}' set", params.ball_id));
                                }
                                Err(reason) => {
                                    NodeStats::bump(&stats.params_rejected);
                                    reject_params(&format!("{reason}; the previous params of '{}' stay in force", params.ball_id), &params.header, "", &params.ball_id, &ev_pub, &tape, &log);
                                }
                            }
                        }
                        Err(e) => {
                            NodeStats::bump(&stats.samples_unreadable);
                            log.warn(&format!("ball/params: unreadable sample: {e:?}"));
                        }
                    }
                }
                Some(_event) = graph_events.next() => {
                    energies_listeners.refresh(&me_pub, &node);
                }
                _ = diagnostics.tick() => {
                    let mut now = stats.snapshot(pipeline.in_flight());
                    let usage = registry.usage();
                    now.bats_cached = usage.bats as u64;
                    now.bats_evicted = usage.bats_evicted;
                    now.balls_cached = usage.balls as u64;
                    now.balls_evicted = usage.balls_evicted;
                    let report = health_report(&now, &last_report, &tape.state());
                    let msg = super::convert::diagnostic_array(&report, &fqn, Time::now());
                    if let Err(e) = diag_pub.publish(msg) {
                        tracing::debug!("publishing diagnostics: {e:?}");
                    }
                    last_report = now;
                }
                Some(received) = swings.next() => {
                    let log_time = now_ns();
                    match received {
                        Ok((swing, info)) => {
                        let lost = transport_gaps.observe(info.publisher_gid(), info.sequence_number());
                        if lost > 0 {
                            stats.swings_lost_in_transport.fetch_add(lost, std::sync::atomic::Ordering::Relaxed);
                            if let Some(suppressed) = loss_warning.allow(Instant::now()) {
                                log.warn(&format!(
                                    "{lost} swings from one publisher never reached the node (DDS history overflow); {suppressed} more such reports suppressed"
                                ));
                            }
                        }
                        on_swing(swing, log_time, &mut registry, &shared_settings, &settings, &pipeline, &mut inline_pacing, &stats, &tape, &log, &drop_warning, &summaries);
                        if registry.usage() != seen_usage {
                            // A preset named by a swing pushed out another bat.
                            let current = shared_settings.read().map(|s| s.clone()).unwrap_or_else(|_| settings.clone());
                            report_evictions(&registry, &mut seen_usage, &current, &log, &eviction_warning);
                        }
                    }
                        Err(e) => {
                            NodeStats::bump(&stats.samples_unreadable);
                            log.warn(&format!("swing: unreadable sample: {e:?}"));
                        }
                    }
                }
            }
        }
    }

    // Shutdown: stop taking swings, let queued ones finish briefly, close the bag, report.
    let pipeline_stats = Arc::clone(&stats);
    let tape_for_finish = Arc::clone(&tape);
    let (bag_result, final_stats) = tokio::task::spawn_blocking(move || {
        let in_flight = pipeline.in_flight();
        pipeline.shutdown(Duration::from_millis(600));
        let bag = tape_for_finish.finish();
        (bag, pipeline_stats.snapshot(in_flight))
    })
    .await
    .context("joining the shutdown task")?;
    let s = final_stats;
    let usage = registry.usage();
    let summary = format!(
        "{fqn}: {} swings received, {} answered OK, {} rejected, {} dropped, {} lost in transport; latency p50 {} µs, p99 {} µs, max {} µs; mode cache {} hits / {} misses; {} bats and {} balls evicted",
        s.swings_received, s.swings_ok, s.swings_rejected, s.swings_dropped, s.swings_lost_in_transport, s.latency_p50_us, s.latency_p99_us,
        s.latency_max_us, s.mode_cache_hits, s.mode_cache_misses, usage.bats_evicted, usage.balls_evicted
    );
    log.info(&summary);
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
    // Entities before the participant: dropping the node stops the spinner, which must drop its parameter
    // services while `context` still holds the participant (else RustDDS logs every removal as an error).
    drop(graph_events);
    drop((ss_pub, diag_pub, ev_pub, me_pub, bat_sub, ball_sub, swing_sub));
    drop(node);
    let _ = tokio::time::timeout(Duration::from_millis(500), spinning).await;
    drop(context);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn on_swing(
    swing: Swing,
    log_time: u64,
    registry: &mut Registry,
    shared_settings: &Arc<RwLock<NodeSettings>>,
    fallback: &NodeSettings,
    pipeline: &Pipeline<Swing>,
    inline_pacing: &mut InlinePacing,
    stats: &Arc<NodeStats>,
    tape: &Tape,
    log: &Log,
    drop_warning: &RateLimiter,
    summaries: &Summaries,
) {
    let received = Instant::now();
    NodeStats::bump(&stats.swings_received);
    tape.record(Recorded::Swing, &swing, log_time, swing.header.stamp.unix_ns());
    // Planned under the read lock instead of cloning the settings (and their strings) for every swing; the
    // guard is dropped before the summary takes the lock again.
    let guard = shared_settings.read().ok();
    let settings = guard.as_deref().unwrap_or(fallback);
    let (plan, new_bat) = engine::plan_swing(
        registry,
        &settings.model,
        &swing.bat_id,
        &swing.ball_id,
        convert::impact_from_swing(&swing),
    );
    drop(guard);
    if let Some(entry) = new_bat {
        summaries.spawn(entry, registry);
    }
    // Idle and cheap: answered here, without waking a worker and the sequencer (see `Pipeline::answer_inline`).
    let (plan, swing) = if inline_pacing.allows(received) {
        let started = Instant::now();
        match pipeline.answer_inline(received, plan, swing) {
            Ok(_) => {
                inline_pacing.answered(started, Instant::now());
                return;
            }
            Err(given_back) => given_back,
        }
    } else {
        (plan, swing)
    };
    if let Err((_plan, swing)) = pipeline.submit(received, plan, swing) {
        NodeStats::bump(&stats.swings_dropped);
        if let Some(suppressed) = drop_warning.allow(Instant::now()) {
            log.warn(&format!(
                "swing {} dropped: {} swings already in flight (queue_capacity); {suppressed} more dropped since the last warning",
                swing.swing_id,
                pipeline.capacity()
            ));
        }
    }
}

/// Warns (rate-limited) when the registry forgot bats or balls since `seen`, and moves `seen` on.
fn report_evictions(
    registry: &Registry,
    seen: &mut RegistryUsage,
    settings: &NodeSettings,
    log: &Log,
    warning: &RateLimiter,
) {
    let now = registry.usage();
    let (bats, balls) = (now.bats_evicted - seen.bats_evicted, now.balls_evicted - seen.balls_evicted);
    *seen = now;
    if bats + balls == 0 {
        return;
    }
    if let Some(suppressed) = warning.allow(Instant::now()) {
        let mut parts = Vec::new();
        if bats > 0 {
            parts.push(format!(
                "{bats} bat(s) forgotten, latest '{}' (max_bats = {} held, least recently used first; {} in all)",
                registry.last_evicted_bat().unwrap_or_default(),
                settings.model.max_bats,
                now.bats_evicted
            ));
        }
        if balls > 0 {
            parts.push(format!(
                "{balls} ball(s) forgotten, latest '{}' (max_balls = {} held; {} in all)",
                registry.last_evicted_ball().unwrap_or_default(),
                settings.model.max_balls,
                now.balls_evicted
            ));
        }
        log.warn(&format!(
            "{}; swings naming them are REJECTED until their params are sent again (presets are re-solved); {suppressed} more such reports suppressed",
            parts.join("; ")
        ));
    }
}

fn reject_params(
    reason: &str,
    header: &Header,
    bat_id: &str,
    ball_id: &str,
    ev_pub: &Publisher<ExitVelocity>,
    tape: &Tape,
    log: &Log,
) {
    log.error(reason);
    let probe = Swing { header: header.clone(), measured_exit_speed: f64::NAN, ..Swing::default() };
    let ev = convert::exit_velocity(&probe, bat_id, ball_id, &Err(reason.to_string()));
    tape.record(Recorded::ExitVelocity, &ev, now_ns(), header.stamp.unix_ns());
    if let Err(e) = ev_pub.publish(ev) {
        log.warn(&format!("publishing the params rejection: {e:?}"));
    }
}

/// Computes SweetSpots off the DDS thread, one at a time: a burst of BatParams (each a sweep of collisions,
/// and a modes solve of up to `max_bat_slices` slices) must not start a thread per message — tokio's blocking
/// pool would grow to 512 threads — nor compete with the swing workers on every core.
struct Summaries {
    settings: Arc<RwLock<NodeSettings>>,
    stats: Arc<NodeStats>,
    events: tokio::sync::mpsc::UnboundedSender<Event>,
    one_at_a_time: Arc<tokio::sync::Semaphore>,
}

impl Summaries {
    fn spawn(&self, entry: Arc<BatEntry>, registry: &Registry) {
        let Ok((ball_id, ball)) = registry.resolve_ball("") else {
            return;
        };
        let settings = self.settings.read().map(|s| s.clone()).unwrap_or_default();
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
                    &ball,
                    super::convert::reference_swing(&settings),
                    &settings.model,
                    &*stats,
                );
                let _ = events.send(Event::Summary(entry, Box::new(result)));
            });
            let _ = job.await;
        });
    }
}

fn start_tape(
    settings: &NodeSettings,
    identity: &NodeIdentity,
    started: chrono::DateTime<chrono::Utc>,
    topic_names: &BTreeMap<&str, String>,
    log: &Log,
) -> Tape {
    if !settings.record {
        return Tape::off();
    }
    let dir: PathBuf = settings.bag_dir(&identity.name, started);
    let config = RecorderConfig {
        dir: dir.clone(),
        max_file_size: (settings.record_max_file_size > 0).then_some(settings.record_max_file_size),
        max_file_duration: (settings.record_max_file_duration > 0.0)
            .then(|| Duration::from_secs_f64(settings.record_max_file_duration)),
        flush_interval: Duration::from_secs(1),
        queue_capacity: 65_536,
    };
    let topics = vec![
        TopicInfo::of::<BatParams>(&topic_names[topics::BAT_PARAMS], recorded_qos(&params_qos())),
        TopicInfo::of::<BallParams>(&topic_names[topics::BALL_PARAMS], recorded_qos(&params_qos())),
        TopicInfo::of::<Swing>(&topic_names[topics::SWING], recorded_qos(&swing_qos())),
        TopicInfo::of::<ExitVelocity>(&topic_names[topics::EXIT_VELOCITY], recorded_qos(&results_qos())),
        TopicInfo::of::<ModalEnergies>(&topic_names[topics::MODAL_ENERGIES], recorded_qos(&results_qos())),
        TopicInfo::of::<SweetSpot>(&topic_names[topics::SWEET_SPOT], recorded_qos(&latched_results_qos())),
    ];
    // record_storage_preset, then record_compression over it (rosbag2's order). apply() refused any
    // combination that does not go together, so the error arm is for settings built some other way.
    let storage = match settings.storage_options() {
        Ok(storage) => storage,
        Err(e) => {
            log.error(&format!(
                "record_storage_preset = {:?} with record_compression = {:?}: {e}; not recording",
                settings.record_storage_preset, settings.record_compression
            ));
            return Tape::failed(dir, e.to_string());
        }
    };
    match super::recording::start_backend(config, storage) {
        Ok(backend) => Tape::start(dir, backend, topics),
        Err(e) => {
            log.error(&format!("recording to {} failed: {e}; the node keeps computing and publishing", dir.display()));
            Tape::failed(dir, e.to_string())
        }
    }
}

/// Resolves on SIGINT or SIGTERM with the signal's name.
async fn shutdown_signal() -> &'static str {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{signal, SignalKind};
        match (signal(SignalKind::interrupt()), signal(SignalKind::terminate())) {
            (Ok(mut int), Ok(mut term)) => tokio::select! {
                _ = int.recv() => "SIGINT",
                _ = term.recv() => "SIGTERM",
            },
            _ => {
                let _ = tokio::signal::ctrl_c().await;
                "SIGINT"
            }
        }
    }
    #[cfg(not(unix))]
    {
        let _ = tokio::signal::ctrl_c().await;
        "Ctrl-C"
    }
}
