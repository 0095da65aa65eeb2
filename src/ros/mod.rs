//! DDS plumbing shared by the node and the command-line tools: network-safe participants, QoS, topic names
//! ([`topics`]) and naming rules, and the edge kit ([`edge`]: writers, readers, the shutdown signal).
//!
//! # Discovery range, and what RustDDS really does with it
//!
//! [`DiscoveryRange`] is read from the environment exactly as ROS 2 (Iron and later) does, and mapped onto
//! RustDDS 0.15's `DomainParticipantBuilder` as follows. This was checked by reading the RustDDS 0.15.1 source
//! (`src/dds/participant.rs`, `src/network/{util,udp_sender,udp_listener}.rs`, `src/rtps/dp_event_loop.rs`):
//!
//! - `SUBNET` and `SYSTEM_DEFAULT`: the builder's defaults. RustDDS joins the SPDP/user multicast group
//!   239.255.0.1 on, sends multicast out of, and advertises unicast locators of every IPv4 interface.
//! - `LOCALHOST`: `with_only_networks([127.0.0.1])` + `same_host_loopback(true)`. `with_only_networks` filters
//!   *all three* interface lists RustDDS builds: the interfaces whose multicast group it joins
//!   (`UDPListener::new_multicast_with_buf_size`), the interfaces it creates multicast **send** sockets on
//!   (`UDPSender::new_with_networks`, each socket bound to its interface address with `IP_MULTICAST_IF`), and
//!   the unicast locators it advertises in SPDP/SEDP (`get_local_unicast_locators_filtered`). Multicast is
//!   only ever sent through those per-interface sockets (`send_to_locator` fans a multicast locator out over
//!   `multicast_sockets` only), so SPDP multicast leaves through `lo` or not at all (if `lo` lacks the
//!   MULTICAST flag RustDDS creates no multicast socket, and `same_host_loopback` still finds same-host peers
//!   by unicasting SPDP to 127.0.0.1 on the well-known ports). What `with_only_networks` is **not**: a
//!   firewall. RustDDS still binds its unicast listeners to 0.0.0.0 and sends unicast to whatever locators a
//!   discovered peer advertises. A remote participant can therefore only reach us if it already knows our
//!   address and port and unicasts SPDP to us (we never announce ourselves off-host); for a hard guarantee
//!   run inside a private network namespace, as `scripts/test` does.
//! - `OFF`: `with_only_networks([])` + `same_host_loopback(false)`: no multicast socket, no multicast join,
//!   no advertised locator, no localhost SPDP peers — the participant discovers nobody and nobody discovers
//!   it, not even on the same host (ROS 2's meaning of OFF; `ROS_STATIC_PEERS` is not supported by RustDDS
//!   and is ignored with a warning).
//!
//! `ROS_LOCALHOST_ONLY=1` (deprecated in ROS 2) forces `LOCALHOST` whatever `ROS_AUTOMATIC_DISCOVERY_RANGE`
//! says, as rcl does. `ROS_DOMAIN_ID` must be an integer in 0..=232 (empty or unset = 0).
//!
//! # RustDDS 0.15.1 behaviours every user of this module should know
//!
//! Found while building `sweetspot pub` / `echo` (each checked in the RustDDS source):
//! - A reliable reader can never take the samples it received but had not taken yet from a writer whose
//!   participant has left: `DDSCache::forget_reliable_writer` drops the writer's "received reliably before"
//!   marker, and `get_changes_in_range_reliable` then yields an empty range for that writer. Take samples as
//!   soon as they arrive (into an application queue) rather than leaving them in DDS.
//! - A KEEP_LAST reader cache silently evicts its oldest *untaken* samples; acknowledgement happens on
//!   reception, so the writer does not slow down for a reader that does not take.
//! - `DataWriter::get_matched_subscriptions` is a placeholder that panics; count matches from the writer's
//!   `PublicationMatched` status events (`StatusEvented::try_recv_status`).
//! - A writer sees a match when the subscription's announcement reaches it, the reader a moment later when
//!   the writer's does; a volatile reader ignores samples written before *its* side matched. Pause briefly
//!   after the writer-side match before publishing what must not be missed.
//!
//! # Network guard
//!
//! Tests must never put DDS traffic on a shared network. [`network_guard`] errors unless the process runs in
//! a private network namespace (only `lo` in `/proc/self/net/dev` — not `/sys/class/net`, which keeps showing
//! the host's interfaces after `unshare --net` because sysfs reflects the namespace that mounted it). Every
//! participant this module creates checks it first when `SWEETSPOT_TEST_NETNS` is set (as `scripts/test`
//! does), so a test binary or a `sweetspot` process spawned by a test refuses to start DDS outside the
//! namespace.

use std::net::{IpAddr, Ipv4Addr};

pub mod args;
pub mod edge;
pub mod names;
pub mod qos;
pub use crate::model::topics;

pub use args::{NameResolver, NodeIdentity, RosArgs, RosArgsError};
pub use edge::{interrupt_flag, shutdown_signal, write_reliably, WriteError};
pub use names::{dds_topic_name, resolve_topic, NameError};
pub use qos::{
    diagnostics_qos, params_qos, results_qos, rosout_qos, sweet_spot_qos, swing_qos, PARAMS_DEPTH, RESULTS_DEPTH,
    RESULTS_MAX_BLOCKING, SWING_DEPTH,
};

/// Environment variable selecting how far discovery reaches (ROS 2 Iron+).
pub const ENV_DISCOVERY_RANGE: &str = "ROS_AUTOMATIC_DISCOVERY_RANGE";
/// Deprecated ROS 2 switch: `1` means localhost only.
pub const ENV_LOCALHOST_ONLY: &str = "ROS_LOCALHOST_ONLY";
/// The DDS domain.
pub const ENV_DOMAIN_ID: &str = "ROS_DOMAIN_ID";
/// Static peers (not supported by RustDDS; ignored with a warning).
pub const ENV_STATIC_PEERS: &str = "ROS_STATIC_PEERS";
/// Set by `scripts/test`: every participant must then be inside a private network namespace.
pub const ENV_TEST_NETNS: &str = "SWEETSPOT_TEST_NETNS";
/// Largest valid ROS domain id (the RTPS port formula overflows beyond it).
pub const MAX_DOMAIN_ID: u16 = 232;

/// Errors of the DDS layer.
#[derive(Debug, thiserror::Error)]
pub enum RosError {
    /// `ROS_DOMAIN_ID` is not an integer in 0..=232.
    #[error("ROS_DOMAIN_ID={value:?} is invalid: expected an integer in 0..=232")]
    InvalidDomainId { value: String },
    /// `ROS_AUTOMATIC_DISCOVERY_RANGE` has an unknown value.
    #[error("ROS_AUTOMATIC_DISCOVERY_RANGE={value:?} is invalid: expected SUBNET, LOCALHOST, OFF or SYSTEM_DEFAULT")]
    InvalidDiscoveryRange { value: String },
    /// A DDS participant was requested in a test outside a private network namespace.
    #[error("refusing to start DDS: {reason}")]
    NotIsolated { reason: String },
    /// A ROS name (topic, namespace, node) is malformed.
    #[error(transparent)]
    Name(#[from] NameError),
    /// `--ros-args` could not be parsed.
    #[error("--ros-args: {0}")]
    Args(String),
    /// A DDS topic could not be created.
    #[error("cannot create topic {topic}: {reason}")]
    CreateTopic { topic: String, reason: String },
    /// A writer (or publisher) could not be created on a topic.
    #[error("cannot create a writer on {topic}: {reason}")]
    CreateWriter { topic: String, reason: String },
    /// A reader (or subscription) could not be created on a topic.
    #[error("cannot subscribe to {topic}: {reason}")]
    CreateReader { topic: String, reason: String },
    /// RustDDS / ros2-client failed to create an entity.
    #[error("DDS: {0}")]
    Dds(String),
}

/// How far DDS discovery reaches, as ROS 2's `ROS_AUTOMATIC_DISCOVERY_RANGE`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DiscoveryRange {
    /// Discover participants on every attached network (ROS 2's default).
    Subnet,
    /// Only participants on this host; nothing is announced or multicast off 127.0.0.1.
    Localhost,
    /// No automatic discovery at all, not even on this host.
    Off,
    /// The middleware's own default (for RustDDS: the same as `Subnet`).
    SystemDefault,
}

impl DiscoveryRange {
    /// Reads `ROS_AUTOMATIC_DISCOVERY_RANGE` and `ROS_LOCALHOST_ONLY` from the environment.
    pub fn from_env() -> Result<Self, RosError> {
        let range = std::env::var(ENV_DISCOVERY_RANGE).ok();
        let localhost_only = std::env::var(ENV_LOCALHOST_ONLY).ok();
        Self::from_vars(range.as_deref(), localhost_only.as_deref())
    }

    /// The range given the two variables' values (`None` = unset), following rcl: `ROS_LOCALHOST_ONLY=1`
    /// forces LOCALHOST; an unset or empty range means SUBNET; anything else must be one of the four names.
    pub fn from_vars(range: Option<&str>, localhost_only: Option<&str>) -> Result<Self, RosError> {
        let parsed = match range.map(str::trim) {
            None | Some("") => DiscoveryRange::Subnet,
            Some(v) => match v.to_ascii_uppercase().as_str() {
                "SUBNET" => DiscoveryRange::Subnet,
                "LOCALHOST" => DiscoveryRange::Localhost,
                "OFF" => DiscoveryRange::Off,
                "SYSTEM_DEFAULT" => DiscoveryRange::SystemDefault,
                _ => return Err(RosError::InvalidDiscoveryRange { value: v.to_string() }),
            },
        };
        if localhost_only.map(str::trim) == Some("1") {
            return Ok(DiscoveryRange::Localhost);
        }
        Ok(parsed)
    }

    /// The ROS spelling, e.g. `LOCALHOST`.
    pub fn as_str(&self) -> &'static str {
        match self {
            DiscoveryRange::Subnet => "SUBNET",
            DiscoveryRange::Localhost => "LOCALHOST",
            DiscoveryRange::Off => "OFF",
            DiscoveryRange::SystemDefault => "SYSTEM_DEFAULT",
        }
    }
}

impl std::fmt::Display for DiscoveryRange {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Parses `ROS_DOMAIN_ID` (`None` or empty = 0).
pub fn parse_domain_id(value: Option<&str>) -> Result<u16, RosError> {
    match value.map(str::trim) {
        None | Some("") => Ok(0),
        Some(v) => match v.parse::<u16>() {
            Ok(id) if id <= MAX_DOMAIN_ID => Ok(id),
            _ => Err(RosError::InvalidDomainId { value: v.to_string() }),
        },
    }
}

/// Where and how a participant discovers others.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DdsConfig {
    /// DDS domain id, 0..=232.
    pub domain_id: u16,
    /// Discovery range.
    pub range: DiscoveryRange,
}

impl DdsConfig {
    /// From `ROS_DOMAIN_ID`, `ROS_AUTOMATIC_DISCOVERY_RANGE` and `ROS_LOCALHOST_ONLY`.
    pub fn from_env() -> Result<Self, RosError> {
        Ok(DdsConfig {
            domain_id: parse_domain_id(std::env::var(ENV_DOMAIN_ID).ok().as_deref())?,
            range: DiscoveryRange::from_env()?,
        })
    }
}

/// Whether this process runs in a network namespace whose only interface is loopback.
pub fn in_private_network_namespace() -> std::io::Result<bool> {
    let dev = std::fs::read_to_string("/proc/self/net/dev")?;
    let mut interfaces = dev.lines().skip(2).filter_map(|l| l.split(':').next()).map(str::trim);
    Ok(interfaces.all(|name| name == "lo"))
}

/// Errors unless this process is in a private network namespace with only `lo`: call it first in every test
/// that starts DDS (directly or through a spawned `sweetspot`).
pub fn network_guard() -> Result<(), RosError> {
    match in_private_network_namespace() {
        Ok(true) => Ok(()),
        Ok(false) => Err(RosError::NotIsolated {
            reason: "this process can reach network interfaces other than lo; run DDS tests through \
                     scripts/test (a private network namespace) so no packet leaves the machine"
                .into(),
        }),
        Err(e) => Err(RosError::NotIsolated { reason: format!("cannot read /proc/self/net/dev: {e}") }),
    }
}

/// Creates a RustDDS participant honouring `config` (see the module docs for what each range does).
pub fn domain_participant(config: &DdsConfig) -> Result<rustdds::DomainParticipant, RosError> {
    if std::env::var_os(ENV_TEST_NETNS).is_some() {
        network_guard()?;
    }
    if std::env::var(ENV_STATIC_PEERS).is_ok_and(|v| !v.trim().is_empty()) {
        tracing::warn!("{ENV_STATIC_PEERS} is set but not supported by RustDDS; ignoring it");
    }
    let builder = rustdds::DomainParticipantBuilder::new(config.domain_id);
    let builder = match config.range {
        DiscoveryRange::Subnet | DiscoveryRange::SystemDefault => builder,
        DiscoveryRange::Localhost => {
            builder.with_only_networks([IpAddr::V4(Ipv4Addr::LOCALHOST)]).same_host_loopback(true)
        }
        DiscoveryRange::Off => builder.with_only_networks(Vec::<IpAddr>::new()).same_host_loopback(false),
    };
    builder.build().map_err(|e| RosError::Dds(format!("cannot create the DDS participant: {e}")))
}

/// A ros2-client context over a participant made by [`domain_participant`].
pub fn context(config: &DdsConfig) -> Result<ros2_client::Context, RosError> {
    let participant = domain_participant(config)?;
    ros2_client::Context::from_domain_participant(participant)
        .map_err(|e| RosError::Dds(format!("cannot create the ROS 2 context: {e}")))
}

/// [`context`] configured from the environment.
pub fn context_from_env() -> Result<(ros2_client::Context, DdsConfig), RosError> {
    let config = DdsConfig::from_env()?;
    Ok((context(&config)?, config))
}

/// The ros2-client type name of a generated message, e.g. `sweetspot_msgs` / `Swing`.
pub fn message_type_name<T: crate::msgs::RosMessage>() -> ros2_client::MessageTypeName {
    let info = T::INFO;
    ros2_client::MessageTypeName::new(info.package(), info.name())
}

/// The DDS USER_DATA ROS 2 Jazzy gives every DataWriter and DataReader of `T`: `typehash=RIHS01_…;`
/// (rmw_dds_common's `encode_type_hash_for_user_data_qos`), from which peers learn the type's hash.
pub fn type_hash_user_data<T: crate::msgs::RosMessage>() -> Vec<u8> {
    format!("typehash={};", T::TYPE_HASH).into_bytes()
}

/// `qos` as DDS policies with `T`'s [`type_hash_user_data`]. Every writer and reader created on a topic made
/// with these announces it (RustDDS merges the topic's policies into the endpoint's, and ros2-client's own
/// QoS profile has no USER_DATA to override it).
pub fn topic_qos<T: crate::msgs::RosMessage>(qos: &ros2_client::QosProfile) -> rustdds::QosPolicies {
    rustdds::QosPolicies::from(qos).with_user_data(type_hash_user_data::<T>())
}

/// Creates a DDS topic for `T` under the fully-qualified ROS name `fq_topic` (e.g. `/rig3/swing`), with `T`'s
/// type hash in the USER_DATA of the endpoints created on it ([`topic_qos`]).
pub fn create_topic<T: crate::msgs::RosMessage>(
    node: &ros2_client::Node,
    fq_topic: &str,
    qos: &ros2_client::QosProfile,
) -> Result<rustdds::Topic, RosError> {
    use rustdds::TopicDescription as _;
    let name = names::to_client_name(fq_topic)?;
    let err = |e: String| RosError::Dds(format!("cannot create topic {fq_topic}: {e}"));
    // ros2-client names the topic; the node exposes no participant, the topic does.
    let plain = node.create_topic(&name, message_type_name::<T>(), qos).map_err(|e| err(e.to_string()))?;
    let participant = plain.participant().ok_or_else(|| err("the DDS participant is gone".to_string()))?;
    participant
        .create_topic(
            plain.name(),
            plain.get_type().name().to_string(),
            &topic_qos::<T>(qos),
            rustdds::TopicKind::NoKey,
        )
        .map_err(|e| err(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discovery_range_follows_rcl() {
        use DiscoveryRange::*;
        assert_eq!(DiscoveryRange::from_vars(None, None).unwrap(), Subnet);
        assert_eq!(DiscoveryRange::from_vars(Some(""), None).unwrap(), Subnet);
        assert_eq!(DiscoveryRange::from_vars(Some("LOCALHOST"), None).unwrap(), Localhost);
        assert_eq!(DiscoveryRange::from_vars(Some("OFF"), None).unwrap(), Off);
        assert_eq!(DiscoveryRange::from_vars(Some("SYSTEM_DEFAULT"), None).unwrap(), SystemDefault);
        assert_eq!(DiscoveryRange::from_vars(Some("SUBNET"), Some("1")).unwrap(), Localhost);
        assert_eq!(DiscoveryRange::from_vars(None, Some("1")).unwrap(), Localhost);
        assert_eq!(DiscoveryRange::from_vars(None, Some("0")).unwrap(), Subnet);
        assert!(matches!(
            DiscoveryRange::from_vars(Some("LAN"), None),
            Err(RosError::InvalidDiscoveryRange { value }) if value == "LAN"
        ));
    }

    #[test]
    fn domain_id_range() {
        assert_eq!(parse_domain_id(None).unwrap(), 0);
        assert_eq!(parse_domain_id(Some("")).unwrap(), 0);
        assert_eq!(parse_domain_id(Some("42")).unwrap(), 42);
        assert_eq!(parse_domain_id(Some("232")).unwrap(), 232);
        for bad in ["233", "-1", "x", "1.5", "70000"] {
            assert!(matches!(parse_domain_id(Some(bad)), Err(RosError::InvalidDomainId { .. })), "{bad}");
        }
    }
}
