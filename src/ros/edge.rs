//! The DDS edge every sweetspot program shares: creating writers and readers on a fully-qualified topic with
//! the project's QoS ([`super::qos`]), counting a writer's matched subscriptions, writing through a full
//! reliable send window (or, for the node, not waiting for room: [`try_publish`]), and the one shutdown signal (SIGINT/SIGTERM).
//!
//! Two kinds of endpoint: raw RustDDS writers/readers on a bare participant ([`writer`], [`reader`]) for the
//! tools that publish or listen without being a ROS node (`pub`, `echo`, the rig, `bag play`), and
//! ros2-client publishers/subscriptions of a [`ros2_client::Node`] ([`publisher`], [`subscription`]) for the
//! node itself.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use ros2_client::QosProfile;
use rustdds::no_key::{DataWriterCdr, SimpleDataReaderCdr};

use super::{create_topic, dds_topic_name, message_type_name, RosError};
use crate::msgs::RosMessage;

/// A reliable write that could not complete.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The readers did not take samples for `timeout` while the send window was full.
    #[error("the subscribers did not keep up for {:.1} s (send window full)", timeout.as_secs_f64())]
    Stalled { timeout: Duration },
    /// SIGINT/SIGTERM arrived while waiting for room in the send window.
    #[error("interrupted while the send window was full")]
    Interrupted,
    /// RustDDS refused the sample.
    #[error("DDS write failed: {0}")]
    Dds(String),
}

fn dds_topic<T: RosMessage>(
    ctx: &ros2_client::Context,
    fq_topic: &str,
    qos: &QosProfile,
) -> Result<rustdds::Topic, RosError> {
    ctx.domain_participant()
        .create_topic(
            dds_topic_name(fq_topic),
            message_type_name::<T>().dds_msg_type(),
            &super::topic_qos::<T>(qos),
            rustdds::TopicKind::NoKey,
        )
        .map_err(|e| RosError::CreateTopic { topic: fq_topic.to_string(), reason: e.to_string() })
}

/// A raw DDS writer of `T` on the fully-qualified ROS topic `fq_topic` (e.g. `/rig3/swing`), on a publisher
/// of its own, with `qos` for the topic and the writer.
pub fn writer<T: RosMessage>(
    ctx: &ros2_client::Context,
    fq_topic: &str,
    qos: &QosProfile,
) -> Result<DataWriterCdr<T>, RosError> {
    let topic = dds_topic::<T>(ctx, fq_topic, qos)?;
    let dds_qos = rustdds::QosPolicies::from(qos);
    ctx.domain_participant()
        .create_publisher(&dds_qos)
        .and_then(|p| p.create_datawriter_no_key_cdr::<T>(&topic, Some(dds_qos.clone())))
        .map_err(|e| RosError::CreateWriter { topic: fq_topic.to_string(), reason: e.to_string() })
}

/// A raw DDS reader of `T` on the fully-qualified ROS topic `fq_topic`, on a subscriber of its own, with
/// `qos` for the topic and the reader.
pub fn reader<T: RosMessage>(
    ctx: &ros2_client::Context,
    fq_topic: &str,
    qos: &QosProfile,
) -> Result<SimpleDataReaderCdr<T>, RosError> {
    let topic = dds_topic::<T>(ctx, fq_topic, qos)?;
    let dds_qos = rustdds::QosPolicies::from(qos);
    ctx.domain_participant()
        .create_subscriber(&dds_qos)
        .and_then(|s| {
            s.create_simple_datareader_no_key::<T, rustdds::CDRDeserializerAdapter<T>>(&topic, Some(dds_qos.clone()))
        })
        .map_err(|e| RosError::CreateReader { topic: fq_topic.to_string(), reason: e.to_string() })
}

/// The number of subscriptions matched with `writer`: `current` (the count last returned) updated from the
/// writer's status events. RustDDS 0.15 offers no direct query (`get_matched_subscriptions` is a placeholder
/// that panics).
pub fn matched_subscriptions<T: RosMessage>(writer: &DataWriterCdr<T>, mut current: usize) -> usize {
    use rustdds::StatusEvented;
    while let Some(status) = writer.try_recv_status() {
        if let rustdds::dds::statusevents::DataWriterStatus::PublicationMatched { current: c, .. } = status {
            current = usize::try_from(c.count()).unwrap_or(0);
        }
    }
    current
}

/// Writes one sample, retrying while the reliable send window is full (the readers are slower than us),
/// for at most `timeout`, and giving up early once `interrupted` is set.
pub fn write_reliably<T: RosMessage>(
    writer: &DataWriterCdr<T>,
    message: T,
    timeout: Duration,
    interrupted: &AtomicBool,
) -> Result<(), WriteError> {
    let start = Instant::now();
    let mut message = message;
    loop {
        match writer.write(message, Some(rustdds::Timestamp::now())) {
            Ok(()) => return Ok(()),
            Err(rustdds::dds::WriteError::WouldBlock { data }) => {
                if interrupted.load(Ordering::Relaxed) {
                    return Err(WriteError::Interrupted);
                }
                if start.elapsed() >= timeout {
                    return Err(WriteError::Stalled { timeout });
                }
                message = data;
                std::thread::sleep(Duration::from_millis(1));
            }
            Err(e) => return Err(WriteError::Dds(e.to_string())),
        }
    }
}

/// A ros2-client publisher of `T` on the fully-qualified ROS topic `fq_topic`: the topic with `qos`, the
/// writer with `writer_qos` over it (`None`: the topic's).
pub fn publisher<T: RosMessage>(
    node: &mut ros2_client::Node,
    fq_topic: &str,
    qos: &QosProfile,
    writer_qos: Option<QosProfile>,
) -> Result<ros2_client::Publisher<T>, RosError> {
    let topic = create_topic::<T>(node, fq_topic, qos)?;
    node.create_publisher::<T>(&topic, writer_qos)
        .map_err(|e| RosError::CreateWriter { topic: fq_topic.to_string(), reason: format!("{e:?}") })
}

/// Publishes `message` only if the reliable send window has room now: never waits (the publisher's
/// `publish` waits up to the writer's `max_blocking_time` for a slow reader). A full window gives back the
/// message in `WouldBlock`. For callers that must not stall, such as the node's receive loop.
pub fn try_publish<T: RosMessage>(
    publisher: &ros2_client::Publisher<T>,
    message: T,
) -> Result<(), ros2_client::WriteError<()>> {
    // The first poll of RustDDS's asynchronous write admits the sample if the window has room and is
    // otherwise pending; dropping the pending future leaves nothing behind (the sample was never admitted).
    match futures::FutureExt::now_or_never(publisher.async_publish(message)) {
        Some(Ok(())) => Ok(()),
        Some(Err(e)) => Err(e.forget_data()),
        None => Err(ros2_client::WriteError::WouldBlock { data: () }),
    }
}

/// A ros2-client subscription of `T` on the fully-qualified ROS topic `fq_topic`: the topic with `qos`, the
/// reader with `reader_qos` over it (`None`: the topic's).
pub fn subscription<T: RosMessage>(
    node: &mut ros2_client::Node,
    fq_topic: &str,
    qos: &QosProfile,
    reader_qos: Option<QosProfile>,
) -> Result<ros2_client::Subscription<T>, RosError> {
    let topic = create_topic::<T>(node, fq_topic, qos)?;
    node.create_subscription::<T>(&topic, reader_qos)
        .map_err(|e| RosError::CreateReader { topic: fq_topic.to_string(), reason: format!("{e:?}") })
}

/// Resolves on SIGINT or SIGTERM with the signal's name: the one way every sweetspot program learns it
/// should stop (async loops await it; synchronous ones read [`interrupt_flag`], which is set by it).
pub async fn shutdown_signal() -> &'static str {
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

/// The process-wide flag set by [`shutdown_signal`], so synchronous loops end cleanly and DDS says goodbye
/// to its peers. The first call starts the listener (on a small thread of its own); later calls share the
/// same flag.
pub fn interrupt_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let set = Arc::clone(&flag);
        std::thread::spawn(move || {
            let Ok(rt) = tokio::runtime::Builder::new_current_thread().enable_all().build() else {
                return;
            };
            rt.block_on(shutdown_signal());
            set.store(true, Ordering::Relaxed);
        });
        flag
    })
    .clone()
}

/// A sample as it travelled: the 4-byte encapsulation header (representation identifier, options `00 00`)
/// followed by the serialized body, undecoded. This is what rosbag2 stores, so a recorder can keep messages
/// of types it has no definition for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RawCdr(pub Vec<u8>);

/// The [`RawCdr`] "decoder": keeps the bytes of any plain or XCDR2 encapsulation as they are.
pub struct RawCdrAdapter;

/// The decoder object of [`RawCdrAdapter`].
#[derive(Clone, Copy)]
pub struct RawCdrDecoder;

/// [`RawCdrAdapter`] never fails; RustDDS's adapter traits still want an error type.
#[derive(Debug, thiserror::Error)]
#[error("raw CDR cannot fail")]
pub struct RawCdrError;

const RAW_ENCODINGS: [rustdds::RepresentationIdentifier; 6] = [
    rustdds::RepresentationIdentifier::CDR_LE,
    rustdds::RepresentationIdentifier::CDR_BE,
    rustdds::RepresentationIdentifier::CDR2_LE,
    rustdds::RepresentationIdentifier::CDR2_BE,
    rustdds::RepresentationIdentifier::D_CDR2_LE,
    rustdds::RepresentationIdentifier::D_CDR2_BE,
];

impl rustdds::no_key::DeserializerAdapter<RawCdr> for RawCdrAdapter {
    type Error = RawCdrError;
    type Decoded = RawCdr;

    fn supported_encodings() -> &'static [rustdds::RepresentationIdentifier] {
        &RAW_ENCODINGS
    }

    fn transform_decoded(decoded: RawCdr) -> RawCdr {
        decoded
    }
}

impl rustdds::no_key::DefaultDecoder<RawCdr> for RawCdrAdapter {
    type Decoder = RawCdrDecoder;
    const DECODER: RawCdrDecoder = RawCdrDecoder;
}

impl<'de> rustdds::no_key::Decode<'de, RawCdr> for RawCdrDecoder {
    type Error = RawCdrError;

    fn decode_bytes(
        self,
        input_bytes: &'de [u8],
        encoding: rustdds::RepresentationIdentifier,
    ) -> Result<RawCdr, RawCdrError> {
        let mut bytes = Vec::with_capacity(input_bytes.len() + 4);
        bytes.extend_from_slice(&encoding.to_bytes());
        bytes.extend_from_slice(&[0, 0]);
        bytes.extend_from_slice(input_bytes);
        Ok(RawCdr(bytes))
    }
}

/// A raw DDS reader of whatever is published on the fully-qualified ROS topic `fq_topic` with the DDS type
/// name `dds_type_name` (as discovery reports it, e.g. `std_msgs::msg::dds_::String_`), on a subscriber of
/// its own: samples come as [`RawCdr`], never decoded.
pub fn raw_reader(
    ctx: &ros2_client::Context,
    fq_topic: &str,
    dds_type_name: &str,
    qos: &QosProfile,
) -> Result<rustdds::no_key::SimpleDataReader<RawCdr, RawCdrAdapter>, RosError> {
    let dds_qos = rustdds::QosPolicies::from(qos);
    let topic = ctx
        .domain_participant()
        .create_topic(dds_topic_name(fq_topic), dds_type_name.to_string(), &dds_qos, rustdds::TopicKind::NoKey)
        .map_err(|e| RosError::CreateTopic { topic: fq_topic.to_string(), reason: e.to_string() })?;
    ctx.domain_participant()
        .create_subscriber(&dds_qos)
        .and_then(|s| s.create_simple_datareader_no_key::<RawCdr, RawCdrAdapter>(&topic, Some(dds_qos.clone())))
        .map_err(|e| RosError::CreateReader { topic: fq_topic.to_string(), reason: e.to_string() })
}

/// A reader of ROS 2's `ros_discovery_info` (rmw_dds_common/ParticipantEntitiesInfo: which nodes each
/// participant hosts), with the writers' QoS (reliable, transient-local: a late joiner gets every
/// participant's latest) and room for `depth` participants' announcements between two takes.
pub fn participants_reader(
    context: &ros2_client::Context,
    node: &mut ros2_client::Node,
    depth: usize,
) -> Result<ros2_client::Subscription<ros2_client::entities_info::ParticipantEntitiesInfo>, RosError> {
    use ros2_client::builtin_topics::ros_discovery;
    let participant = context.domain_participant();
    let topic = participant.create_topic(
        ros_discovery::TOPIC_NAME.to_string(),
        ros_discovery::TYPE_NAME.to_string(),
        &ros_discovery::QOS_PUB,
        rustdds::TopicKind::NoKey,
    );
    drop(participant);
    let topic = topic.map_err(|e| RosError::CreateTopic {
        topic: ros_discovery::TOPIC_NAME.to_string(),
        reason: format!("{e:?}"),
    })?;
    let qos = QosProfile::publisher_default()
        .durability(ros2_client::qos::Durability::TransientLocal)
        .history(ros2_client::qos::History::KeepLast { depth });
    node.create_subscription(&topic, Some(qos))
        .map_err(|e| RosError::CreateReader { topic: ros_discovery::TOPIC_NAME.to_string(), reason: format!("{e:?}") })
}
