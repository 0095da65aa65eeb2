//! The imperative shell: DDS participant, topics, parameter services, the worker pipeline, recording and the
//! teardown around the receive loop ([`super::receive_loop`]). Everything it decides is delegated to the pure
//! modules.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use anyhow::Context as _;
use futures::stream::BoxStream;
use futures::StreamExt;
use ros2_client::qos::History;
use ros2_client::{NodeName, NodeOptions, ParameterValue};
use tokio::sync::mpsc::UnboundedSender;
use tokio::task::JoinHandle;

use crate::bag::{RecorderConfig, TopicInfo};
use crate::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use crate::msgs::visualization_msgs::msg::MarkerArray;
use crate::ros::edge::{publisher, subscription};
use crate::ros::{diagnostics_qos, params_qos, results_qos, sweet_spot_qos as latched_results_qos, swing_qos};

use super::live_settings::LiveSettings;
use super::outputs::{EnergiesListeners, Log, Outputs, PublishFailures};
use super::pipeline::{InlinePacing, Pipeline};
use super::receive_loop::{Event, Inputs, NodeLoop, ParticipantLiveness, Summaries, Warnings};
use super::recording::{recorded_qos, Recorded, Tape};
use super::ros_args::{NameResolver, NodeIdentity, RosArgs};
use super::settings::NodeSettings;
use super::stats::{GapCounter, NodeStats, StatsSnapshot};
use crate::model::engine::Registry;
use crate::msgs::sweetspot_msgs::srv::SimulateSwing_Event;

use crate::model::topics;

/// Default node name (`-r __node:=` changes it).
pub const DEFAULT_NODE_NAME: &str = "sweetspot";

/// How `sweetspot node` was asked to run.
#[derive(Debug, Clone, Default)]
pub struct NodeConfig {
    /// The `--ros-args` section.
    pub ros_args: RosArgs,
    /// `--no-record`: overrides the `record` parameter.
    pub no_record: bool,
    /// `--foxglove [ADDR:]PORT`: overrides the `foxglove_port` parameter.
    pub foxglove: Option<String>,
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
        if let Some(bind) = &self.foxglove {
            overrides.insert("foxglove_port".to_string(), ParameterValue::String(bind.clone()));
        }
        let settings = NodeSettings::with_overrides(&overrides).map_err(|e| anyhow::anyhow!(e))?;
        let names = self.ros_args.resolver(&identity);
        Ok(ResolvedConfig { identity, names, settings, rosout: self.ros_args.rosout_logs.unwrap_or(true) })
    }
}

/// Runs the node until SIGINT or SIGTERM, then finishes the bag and returns.
pub fn run(config: NodeConfig) -> anyhow::Result<()> {
    let resolved = config.resolve()?;
    // A file-size limit (RLIMIT_FSIZE) then fails the recorder's write with EFBIG, reported like a full disk
    // while the node keeps computing, instead of killing the node with SIGXFSZ.
    // SAFETY: sets this process's disposition of one signal to "ignore"; no handler code is involved.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
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

/// The node's topics resolved (namespace + remaps), handed to ros2-client as absolute names.
struct TopicNames(BTreeMap<&'static str, String>);

impl TopicNames {
    fn resolve(names: &NameResolver) -> TopicNames {
        let all = [
            topics::BAT_PARAMS,
            topics::BALL_PARAMS,
            topics::SWING,
            topics::EXIT_VELOCITY,
            topics::MODAL_ENERGIES,
            topics::SWEET_SPOT,
            topics::SWING_SCENE,
            topics::DIAGNOSTICS,
        ];
        TopicNames(all.into_iter().map(|t| (t, names.resolve(t))).collect())
    }

    fn get(&self, topic: &str) -> &str {
        &self.0[topic]
    }
}

async fn run_async(resolved: ResolvedConfig) -> anyhow::Result<()> {
    let ResolvedConfig { identity, names, settings, rosout } = resolved;
    let fqn = identity.fully_qualified_name();
    let started_utc = chrono::Utc::now();
    let live = LiveSettings::new(settings.clone());
    let (events_tx, events_rx) = tokio::sync::mpsc::unbounded_channel::<Event>();

    let options = node_options(&settings, &live, &events_tx, rosout);
    let (context, dds_config) = crate::ros::context_from_env().context("creating the DDS participant")?;
    let node_name =
        NodeName::new(&identity.namespace, &identity.name).map_err(|e| anyhow::anyhow!("node name {fqn}: {e:?}"))?;
    let mut node = context.new_node(node_name, options).map_err(|e| anyhow::anyhow!("creating node {fqn}: {e:?}"))?;
    let log = Log::new(node.logging_handle(), rosout);
    let topic_names = TopicNames::resolve(&names);
    let (inputs, outputs) = endpoints(&context, &mut node, &topic_names, &settings, &names)?;
    let (spinning, graph_events) = spin(&mut node)?;
    let type_descriptions = super::type_description::start(&mut node, &names, mapping_of(&settings))?;
    outputs.refresh_energies_listeners(&node);

    // Recording: every input as received and every output as published, and served live when asked.
    let tape =
        Arc::new(start_recording_and_serving(&settings, &identity, started_utc, &topic_names, &names, &log).await?);
    // From here on the node's log lines go to the Foxglove server's `/rosout` too.
    log.serve_on(Arc::clone(&tape));
    tape.note_settings(&settings);
    let stats = Arc::new(NodeStats::new());
    let publish_failures = PublishFailures::new(log.clone());
    let sink = outputs.sink(&tape, &stats, &publish_failures, settings.swing_scene_live_hz);
    let pipeline = Pipeline::start(settings.worker_count(), settings.queue_capacity, Arc::clone(&stats), sink)
        .context("starting the worker threads")?;
    let calls = start_service_calls(&inputs, &settings, &stats, &tape)?;
    announce(&log, &fqn, &dds_config, &settings, &topic_names, &tape);

    let registry = Registry::with_limits(settings.model.max_bats, settings.model.max_balls);
    let mut node_loop = NodeLoop {
        fqn,
        seen_usage: registry.usage(),
        registry,
        summaries: Summaries::new(live.clone(), Arc::clone(&stats), events_tx),
        settings: live,
        pipeline,
        inline_pacing: InlinePacing::new(),
        outputs,
        graph_events,
        events: events_rx,
        tape,
        stats,
        log,
        publish_failures,
        transport_gaps: GapCounter::new(),
        warnings: Warnings::default(),
        last_report: StatsSnapshot::default(),
        liveness: Box::new(ParticipantLiveness(context.clone())),
        own_participant: context.participant_entities_info().gid(),
        namesakes: Default::default(),
        calls,
        swings_empty_at: std::time::Instant::now(),
    };
    node_loop.start_default_bat();
    let outcome = node_loop.run(&inputs, &node).await;
    // The normal shutdown either way: the bag is closed with its summary before a DDS failure is returned.
    node_loop.finish().await?;

    // Entities before the participant: dropping the node stops the spinner, which must drop its parameter
    // services while `context` still holds the participant. `finish` already dropped the log handle (a
    // rosout writer clone) and the liveness probe (a context clone), so `context` is the last holder.
    type_descriptions.abort();
    let _ = type_descriptions.await;
    drop(inputs);
    drop(node);
    let _ = tokio::time::timeout(Duration::from_millis(500), spinning).await;
    drop(context);
    outcome.map_err(anyhow::Error::from)
}

/// The workers of `~/simulate_swing`, as many and as deep as the swings' (its events recorded when
/// `record_services`).
fn start_service_calls(
    inputs: &Inputs,
    settings: &NodeSettings,
    stats: &Arc<NodeStats>,
    tape: &Arc<Tape>,
) -> anyhow::Result<super::service::ServiceCalls<super::service::SimulateSwingServer>> {
    super::service::ServiceCalls::start(
        Arc::clone(&inputs.simulate_swing),
        settings.worker_count(),
        settings.queue_capacity,
        Arc::clone(stats),
        settings.record_services.then(|| Arc::clone(tape)),
    )
    .context("starting the simulate_swing workers")
}

/// The recording (every input as received and every output as published; a node told to record that cannot
/// record stops here rather than pretend to), with the service's events when `record_services`, and the live
/// Foxglove server on `foxglove_port` serving the same topics, schemas and CDR bytes.
async fn start_recording_and_serving(
    settings: &NodeSettings,
    identity: &NodeIdentity,
    started_utc: chrono::DateTime<chrono::Utc>,
    topic_names: &TopicNames,
    names: &NameResolver,
    log: &Log,
) -> anyhow::Result<Tape> {
    let mut tape = start_tape(settings, identity, started_utc, topic_names)?;
    if settings.record_services {
        // As rosbag2 records a service: its events on `<service>/_service_event`.
        let topic = format!("{}/_service_event", names.resolve(super::service::SERVICE_NAME));
        let qos = recorded_qos(&results_qos());
        tape.add_topic(Recorded::ServiceEvent, TopicInfo::of::<SimulateSwing_Event>(&topic, qos));
    }
    let bind = match settings.foxglove_port.as_str() {
        "" => return Ok(tape),
        bind => crate::foxglove::Bind::parse(bind).map_err(|e| anyhow::anyhow!("foxglove_port: {e}"))?,
    };
    let mut served = recorded_topics(topic_names, false);
    // The scene is always served: built only while a client subscribes to it.
    served.push(swing_scene_topic(topic_names));
    served.push(TopicInfo::of::<crate::msgs::diagnostic_msgs::msg::DiagnosticArray>(
        topic_names.get(topics::DIAGNOSTICS),
        recorded_qos(&diagnostics_qos()),
    ));
    // `/rosout` as ros2-client offers it (transient-local, keep-last 1000): a client that connects later gets
    // the lines logged before it, from the latch.
    served.push(TopicInfo::of::<crate::msgs::rcl_interfaces::msg::Log>(
        topics::ROSOUT,
        recorded_qos(&crate::ros::qos::rosout_qos()),
    ));
    let fqn = identity.fully_qualified_name();
    let limits = crate::foxglove::Limits { max_clients: settings.foxglove_max_clients, ..Default::default() };
    let live = crate::foxglove::LiveServer::start_with(&fqn, &bind, &served, None, limits)
        .await
        .map_err(|e| anyhow::anyhow!("{e} (pass another foxglove_port / --foxglove)"))?;
    log.info(&format!("Foxglove WebSocket server on {}", bind.url(live.port())));
    Ok(tape.with_live(live))
}

/// Starts the node's spinner (parameter services, discovery) and returns it with the node's discovery events.
fn spin(
    node: &mut ros2_client::Node,
) -> anyhow::Result<(JoinHandle<ros2_client::CreateResult<()>>, BoxStream<'static, ros2_client::NodeEvent>)> {
    let spinning = tokio::spawn(node.spinner().map_err(|e| anyhow::anyhow!("{e:?}"))?.spin());
    // Discovery events (after the spinner exists, else there are none); each one re-checks the listeners.
    let graph_events = match node.status_receiver() {
        Some(receiver) => receiver.boxed(),
        None => futures::stream::pending::<ros2_client::NodeEvent>().boxed(),
    };
    Ok((spinning, graph_events))
}

/// The start-up line: where the node listens and answers, how it computes and where it records.
fn announce(
    log: &Log,
    fqn: &str,
    dds_config: &crate::ros::DdsConfig,
    settings: &NodeSettings,
    topic_names: &TopicNames,
    tape: &Tape,
) {
    log.info(&format!(
        "{fqn} up on ROS_DOMAIN_ID {} (discovery {}): {} workers, queue {} swings, swing on {}, answers on {}, recording {}",
        dds_config.domain_id,
        dds_config.range,
        settings.worker_count(),
        settings.queue_capacity,
        topic_names.get(topics::SWING),
        topic_names.get(topics::EXIT_VELOCITY),
        tape.dir().map(|d| d.display().to_string()).unwrap_or_else(|| "off".into())
    ));
}

/// Parameters: declared with the start-up values and their descriptors (range, read-only, description, for
/// `ros2 param describe`), validated on every set, read-only ones refused later;
/// a set that changes the settings is reported to the receive loop.
fn node_options(
    settings: &NodeSettings,
    live: &LiveSettings,
    events: &UnboundedSender<Event>,
    rosout: bool,
) -> NodeOptions {
    let (validator, action, events) = (live.clone(), live.clone(), events.clone());
    let mut options = NodeOptions::new()
        .enable_rosout(rosout)
        .start_parameter_services(true)
        .parameter_service_mapping(mapping_of(settings))
        .parameter_validator(Box::new(move |name, value| validator.validate(name, value)))
        .parameter_set_action(Box::new(move |name, value| {
            if let Some(effect) = action.set(name, value)? {
                let _ = events.send(Event::ParameterChanged(effect));
            }
            Ok(())
        }));
    for parameter in super::settings::PARAMETERS {
        let value = parameter.value(settings);
        options = options.declare_parameter_with_descriptor(parameter.name, value, parameter.descriptor());
    }
    options
}

/// The request/reply mapping of the node's services (`service_mapping`, checked when it was set).
fn mapping_of(settings: &NodeSettings) -> ros2_client::ServiceMapping {
    super::settings::service_mapping(&settings.service_mapping).unwrap_or(ros2_client::ServiceMapping::Enhanced)
}

/// The node's subscriptions and publishers, with the project's QoS.
fn endpoints(
    context: &ros2_client::Context,
    node: &mut ros2_client::Node,
    topic_names: &TopicNames,
    settings: &NodeSettings,
    names: &NameResolver,
) -> anyhow::Result<(Inputs, Outputs)> {
    // DDS acknowledges a sample when it reaches the reader's cache, not when the node takes it, so a burst
    // faster than the node takes swings would overwrite a keep-last-1000 cache: size it like the pipeline.
    let swing_reader_qos = swing_qos().history(History::KeepLast { depth: settings.queue_capacity.max(1000) });
    let inputs = Inputs {
        bat_params: subscription(node, topic_names.get(topics::BAT_PARAMS), &params_qos(), None)?,
        ball_params: subscription(node, topic_names.get(topics::BALL_PARAMS), &params_qos(), None)?,
        swings: subscription(node, topic_names.get(topics::SWING), &swing_qos(), Some(swing_reader_qos))?,
        participants: crate::ros::edge::participants_reader(context, node, 64)?,
        simulate_swing: Arc::new(simulate_swing_server(node, names, settings)?),
    };
    // The topics' own QoS (ros::results_qos: deep window, bounded wait) is the writers' QoS.
    let outputs = Outputs {
        exit_velocity: Arc::new(publisher(
            node,
            topic_names.get(topics::EXIT_VELOCITY),
            &results_qos(),
            Some(results_qos()),
        )?),
        modal_energies: Arc::new(publisher(
            node,
            topic_names.get(topics::MODAL_ENERGIES),
            &results_qos(),
            Some(results_qos()),
        )?),
        sweet_spot: publisher(node, topic_names.get(topics::SWEET_SPOT), &latched_results_qos(), None)?,
        diagnostics: publisher(node, topic_names.get(topics::DIAGNOSTICS), &diagnostics_qos(), None)?,
        energies_listeners: EnergiesListeners::default(),
        swing_scene: if settings.swing_scene {
            Some(Arc::new(publisher(node, topic_names.get(topics::SWING_SCENE), &results_qos(), Some(results_qos()))?))
        } else {
            None
        },
    };
    Ok((inputs, outputs))
}

/// The `~/simulate_swing` server (see [`super::service`]): ROS 2's service QoS (reliable, volatile), the
/// request reader deep enough to hold a burst the loop has not taken yet, the reply writer as deep as the
/// answer topics' (every response is kept until acknowledged or its reader's lease expires).
fn simulate_swing_server(
    node: &mut ros2_client::Node,
    names: &NameResolver,
    settings: &NodeSettings,
) -> anyhow::Result<super::service::SimulateSwingServer> {
    let fq_name = names.resolve(super::service::SERVICE_NAME);
    let name = crate::ros::names::to_client_name(&fq_name).map_err(|e| anyhow::anyhow!("service {fq_name}: {e}"))?;
    let service_type = ros2_client::ServiceTypeName::new("sweetspot_msgs", "SimulateSwing");
    let requests = swing_qos().history(History::KeepLast { depth: settings.queue_capacity.max(10_000) });
    let replies = results_qos();
    node.create_server(mapping_of(settings), &name, &service_type, requests, replies)
        .map_err(|e| anyhow::anyhow!("service {fq_name}: {e:?}"))
}

fn start_tape(
    settings: &NodeSettings,
    identity: &NodeIdentity,
    started: chrono::DateTime<chrono::Utc>,
    topic_names: &TopicNames,
) -> anyhow::Result<Tape> {
    if !settings.record {
        return Ok(Tape::off());
    }
    let dir: PathBuf = settings.bag_dir(&identity.name, started);
    let config = RecorderConfig {
        dir: dir.clone(),
        max_file_size: (settings.record_max_file_size > 0).then_some(settings.record_max_file_size),
        max_file_duration: (settings.record_max_file_duration > 0.0)
            .then(|| crate::model::time::saturating_secs(settings.record_max_file_duration)),
        flush_interval: Duration::from_secs(1),
        queue_capacity: 65_536,
    };
    let topics = recorded_topics(topic_names, settings.swing_scene);
    // record_storage_preset, then record_compression over it (rosbag2's order). apply() refused any
    // combination that does not go together, so the error arm is for settings built some other way.
    let storage = settings.storage_options().map_err(|e| {
        anyhow::anyhow!(
            "record_storage_preset = '{}' with record_compression = '{}': {e}",
            settings.record_storage_preset,
            settings.record_compression
        )
    })?;
    // The default directory is named by the second the node started: a suffix when it is taken. An explicit
    // `record_path` is used as given (and refused if it exists).
    let started = if settings.record_path.is_empty() {
        super::recording::start_backend_unique(config, storage)
    } else {
        super::recording::start_backend(config, storage).map(|backend| (backend, dir.clone()))
    };
    match started {
        Ok((backend, dir)) => Ok(Tape::start(dir, backend, topics)),
        // The error names the directory (the default one when record_path is empty).
        Err(e) => Err(anyhow::anyhow!(
            "record_path = '{}': cannot record: {e} (pass another record_path, or record:=false)",
            settings.record_path
        )),
    }
}

/// The topics the node records and serves live, in [`super::recording::Recorded`] order: name, type, schema
/// and the QoS they are offered with; `swing_scene` only with `scene`.
fn recorded_topics(topic_names: &TopicNames, scene: bool) -> Vec<TopicInfo> {
    let mut topics = vec![
        TopicInfo::of::<BatParams>(topic_names.get(topics::BAT_PARAMS), recorded_qos(&params_qos())),
        TopicInfo::of::<BallParams>(topic_names.get(topics::BALL_PARAMS), recorded_qos(&params_qos())),
        TopicInfo::of::<Swing>(topic_names.get(topics::SWING), recorded_qos(&swing_qos())),
        TopicInfo::of::<ExitVelocity>(topic_names.get(topics::EXIT_VELOCITY), recorded_qos(&results_qos())),
        TopicInfo::of::<ModalEnergies>(topic_names.get(topics::MODAL_ENERGIES), recorded_qos(&results_qos())),
        TopicInfo::of::<SweetSpot>(topic_names.get(topics::SWEET_SPOT), recorded_qos(&latched_results_qos())),
    ];
    if scene {
        topics.push(swing_scene_topic(topic_names));
    }
    topics
}

/// `swing_scene` ([`super::recording::Recorded::SwingScene`]), offered with the answers' QoS.
fn swing_scene_topic(topic_names: &TopicNames) -> TopicInfo {
    TopicInfo::of::<MarkerArray>(topic_names.get(topics::SWING_SCENE), recorded_qos(&results_qos()))
}
