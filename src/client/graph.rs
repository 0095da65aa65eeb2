//! The ROS graph as `ros2` lists it, for a user without ROS: `sweetspot topic list [-t]`, `sweetspot service
//! list [-t]`, `sweetspot nodes` (`ros2 node list`), and `sweetspot interface show TYPE` for the types
//! sweetspot knows.
//!
//! The lists come from DDS discovery (every participant on `ROS_DOMAIN_ID`, with `ROS_AUTOMATIC_DISCOVERY_RANGE`
//! / `ROS_LOCALHOST_ONLY` as for the other DDS commands), gathered for `--spin-time` seconds as `ros2 …
//! --no-daemon --spin-time` does: topics are the `rt/…` endpoints, services the `rq/…Request` readers of their
//! servers, nodes what each participant announces on `ros_discovery_info`. This command's own participant is
//! left out. Output as `ros2`'s: one name a line, sorted, `-t` adding `[pkg/msg/Type]`; nodes that share a name
//! are listed once each, with a warning on stderr (as `ros2 node list` warns).

use std::collections::{BTreeMap, BTreeSet};

use anyhow::{anyhow, bail, Context as _};

use crate::ros::{self, DdsConfig};

/// `topic list [-t]`: every topic with a publisher or a subscriber, after `spin_time` seconds of discovery.
pub fn list_topics(spin_time: f64, show_types: bool) -> anyhow::Result<()> {
    let graph = discover(spin_time)?;
    crate::report::stdout::emit(&listing(&graph.topics, show_types))
}

/// `service list [-t]`: every service with a server, after `spin_time` seconds of discovery.
pub fn list_services(spin_time: f64, show_types: bool) -> anyhow::Result<()> {
    let graph = discover(spin_time)?;
    crate::report::stdout::emit(&listing(&graph.services, show_types))
}

/// `nodes`: every node on the graph, namesakes warned of on stderr.
pub fn list_nodes(spin_time: f64) -> anyhow::Result<()> {
    let graph = discover(spin_time)?;
    for node in &graph.nodes {
        crate::outln!("{node}")?;
    }
    for (name, count) in namesakes(&graph.nodes) {
        eprintln!("warning: {}", namesake_warning(&name, count, "are on the graph"));
    }
    Ok(())
}

/// `interface show TYPE`: the definition of a type sweetspot knows.
pub fn show_interface(type_name: &str) -> anyhow::Result<()> {
    crate::report::stdout::emit(&show(type_name)?)
}

/// `interface list`: every type sweetspot knows.
pub fn list_interfaces() -> anyhow::Result<()> {
    for name in known_types() {
        crate::outln!("    {name}")?;
    }
    Ok(())
}

/// One discovery snapshot: topics and services with their types, and node names.
#[derive(Debug, Default)]
struct Graph {
    topics: BTreeMap<String, BTreeSet<String>>,
    services: BTreeMap<String, BTreeSet<String>>,
    /// Sorted, a name once per node that has it (as `ros2 node list` lists namesakes).
    nodes: Vec<String>,
}

/// The names more than one node has, with how many have it.
fn namesakes(sorted_nodes: &[String]) -> Vec<(String, usize)> {
    sorted_nodes
        .chunk_by(|a, b| a == b)
        .filter(|same| same.len() > 1)
        .map(|same| (same[0].clone(), same.len()))
        .collect()
}

/// What a CLI says of `count` nodes named `node` (`what` they do: "answer", "are on the graph"): each gets
/// every swing and every call, and a client takes whichever answer comes first.
pub fn namesake_warning(node: &str, count: usize, what: &str) -> String {
    format!(
        "{count} nodes named {node} {what}; each answers every call and swing, and a client takes the first          answer, from either: rename one (--ros-args -r __node:=NAME or -r __ns:=/NS)"
    )
}

/// Participants other than this one's that serve `fq_service` (read its `rq/…Request` topic, as both
/// service mappings name it): two nodes of one name are two servers.
pub fn servers_of(context: &ros2_client::Context, fq_service: &str) -> usize {
    let request_topic = format!("rq{fq_service}Request");
    let participant = context.domain_participant();
    let own = rustdds::RTPSEntity::guid(&participant).prefix;
    let servers: BTreeSet<_> = participant
        .discovered_readers()
        .into_iter()
        .filter(|r| *r.subscription_topic_data.topic_name() == request_topic)
        .map(|r| r.reader_proxy.remote_reader_guid.prefix)
        .filter(|prefix| *prefix != own)
        .collect();
    servers.len()
}

/// How long after its participant started a client looks, at most, for a second server of a service before it
/// concludes there is one: the first server's answer often arrives before discovery has shown the others.
const NAMESAKE_SETTLE: std::time::Duration = std::time::Duration::from_secs(1);

/// Warns on stderr when more than one node serves `fq_service` (nodes sharing a name): the answer printed is
/// whichever came first. `discovering_since` is when the client's participant started.
pub async fn warn_of_namesakes(
    context: &ros2_client::Context,
    fq_service: &str,
    discovering_since: std::time::Instant,
) {
    // One warning for a command, however many calls it makes (`param dump` makes two).
    static WARNED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
    let mut servers = servers_of(context, fq_service);
    while servers < 2 && discovering_since.elapsed() < NAMESAKE_SETTLE {
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
        servers = servers_of(context, fq_service);
    }
    if servers > 1 && !WARNED.swap(true, std::sync::atomic::Ordering::Relaxed) {
        let node = fq_service.rsplit_once('/').map_or("/", |(node, _)| if node.is_empty() { "/" } else { node });
        eprintln!("warning: {}", namesake_warning(node, servers, &format!("serve {fq_service}")));
    }
}

fn discover(spin_time: f64) -> anyhow::Result<Graph> {
    let config = DdsConfig::from_env()?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    runtime.block_on(async {
        let context = ros::context(&config)?;
        let node_name = ros2_client::NodeName::new("/", &format!("_sweetspot_graph_{}", std::process::id()))
            .map_err(|e| anyhow!("node name: {e:?}"))?;
        let mut node = context
            .new_node(node_name, ros2_client::NodeOptions::new().enable_rosout(false))
            .map_err(|e| anyhow!("creating the DDS node: {e:?}"))?;
        let participants = crate::ros::edge::participants_reader(&context, &mut node, 1024)?;
        tokio::time::sleep(crate::model::time::saturating_secs(spin_time)).await;

        let participant = context.domain_participant();
        let own = rustdds::RTPSEntity::guid(&participant).prefix;
        let mut graph = Graph::default();
        let mut endpoints: Vec<(String, String)> = Vec::new();
        for w in participant.discovered_writers() {
            if w.writer_proxy.remote_writer_guid.prefix != own {
                let t = &w.publication_topic_data;
                endpoints.push((t.topic_name.clone(), t.type_name.clone()));
            }
        }
        let mut servers: Vec<(String, String)> = Vec::new();
        for r in participant.discovered_readers() {
            if r.reader_proxy.remote_reader_guid.prefix != own {
                let t = &r.subscription_topic_data;
                endpoints.push((t.topic_name().clone(), t.type_name().clone()));
                servers.push((t.topic_name().clone(), t.type_name().clone()));
            }
        }
        for (topic, dds_type) in endpoints {
            if let Some(name) = topic.strip_prefix("rt/") {
                graph.topics.entry(format!("/{name}")).or_default().insert(ros_type_name(&dds_type));
            }
        }
        for (topic, dds_type) in servers {
            if let Some(name) = topic.strip_prefix("rq/").and_then(|n| n.strip_suffix("Request")) {
                let service_type = ros_type_name(&dds_type);
                let service_type = service_type.strip_suffix("_Request").unwrap_or(&service_type).to_string();
                graph.services.entry(format!("/{name}")).or_default().insert(service_type);
            }
        }
        let own_gid = context.participant_entities_info().gid();
        let mut latest: BTreeMap<ros2_client::Gid, Vec<String>> = BTreeMap::new();
        while let Ok(Some((info, _))) = participants.take() {
            if info.gid() != own_gid {
                latest.insert(info.gid(), info.nodes().iter().map(|n| n.fully_qualified_name()).collect());
            }
        }
        graph.nodes = latest.into_values().flatten().collect();
        graph.nodes.sort();
        drop(participant);
        drop(participants);
        drop(node);
        Ok(graph)
    })
}

/// `pkg::msg::dds_::Type_` → `pkg/msg/Type` (anything else unchanged).
fn ros_type_name(dds: &str) -> String {
    let parts: Vec<&str> = dds.split("::").collect();
    match parts.as_slice() {
        [pkg, kind, "dds_", name] => format!("{pkg}/{kind}/{}", name.strip_suffix('_').unwrap_or(name)),
        _ => dds.to_string(),
    }
}

fn listing(entries: &BTreeMap<String, BTreeSet<String>>, show_types: bool) -> String {
    let mut out = String::new();
    for (name, types) in entries {
        match show_types {
            true => out += &format!("{name} [{}]\n", types.iter().cloned().collect::<Vec<_>>().join(", ")),
            false => out += &format!("{name}\n"),
        }
    }
    out
}

/// Every message and service type sweetspot was built with.
fn known_types() -> Vec<String> {
    use crate::msgs::RosService;
    let mut names: Vec<String> =
        crate::msgs::ALL_TYPES.iter().map(|t| t.type_name.to_string()).filter(|n| !n.contains("/srv/")).collect();
    names.push(crate::msgs::sweetspot_msgs::srv::SimulateSwing::TYPE_NAME.to_string());
    names.push(crate::msgs::type_description_interfaces::srv::GetTypeDescription::TYPE_NAME.to_string());
    names.sort();
    names
}

/// The definition of a known type, as its `.msg`/`.srv` file has it.
fn show(type_name: &str) -> anyhow::Result<String> {
    use crate::msgs::RosService;
    let services = [
        (
            crate::msgs::sweetspot_msgs::srv::SimulateSwing::TYPE_NAME,
            crate::msgs::sweetspot_msgs::srv::SimulateSwing::SRV_TEXT,
        ),
        (
            crate::msgs::type_description_interfaces::srv::GetTypeDescription::TYPE_NAME,
            crate::msgs::type_description_interfaces::srv::GetTypeDescription::SRV_TEXT,
        ),
    ];
    if let Some((_, text)) = services.iter().find(|(name, _)| *name == type_name) {
        return Ok(text.to_string());
    }
    match crate::msgs::type_info(type_name) {
        Some(info) if info.type_name == type_name || !type_name.contains("/srv/") => Ok(info.msg_text.to_string()),
        _ => bail!("Unknown interface '{}' (sweetspot knows: `sweetspot interface list`)", super::quoted(type_name)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dds_type_names_read_as_ros_names() {
        assert_eq!(ros_type_name("sweetspot_msgs::msg::dds_::Swing_"), "sweetspot_msgs/msg/Swing");
        assert_eq!(
            ros_type_name("rcl_interfaces::srv::dds_::SetParameters_Request_"),
            "rcl_interfaces/srv/SetParameters_Request"
        );
    }

    #[test]
    fn show_prints_the_definition_files() {
        let swing =
            std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/msgs/sweetspot_msgs/msg/Swing.msg")).unwrap();
        assert_eq!(show("sweetspot_msgs/msg/Swing").unwrap(), swing);
        let srv =
            std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/msgs/sweetspot_msgs/srv/SimulateSwing.srv"))
                .unwrap();
        assert_eq!(show("sweetspot_msgs/srv/SimulateSwing").unwrap(), srv);
        assert!(show("nav_msgs/msg/Odometry").is_err());
    }
}
