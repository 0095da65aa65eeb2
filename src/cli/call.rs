//! `sweetspot call simulate_swing '{…}'`: one call of a node's `~/simulate_swing` service, as
//! `ros2 service call /sweetspot/simulate_swing sweetspot_msgs/srv/SimulateSwing '{…}'` makes it.
//!
//! The request is YAML or JSON in the form `sweetspot pub` takes (fields left out keep their defaults, `null`
//! and `.nan` are NaN): `{swing: {…}, bat: [BatParams], ball: [BallParams]}`. The response is printed as one
//! JSON object (NaN as null). Exit status: 0 for an OK answer; 1 when the request does not fit the type, no node
//! serves the service within `--timeout`, or the node answered REJECTED or DROPPED (the answer is still
//! printed, and its message repeated on stderr). DDS discovery honours `ROS_DOMAIN_ID`,
//! `ROS_AUTOMATIC_DISCOVERY_RANGE` and `ROS_LOCALHOST_ONLY` as the other DDS commands do.

use anyhow::{anyhow, bail, Context as _};

use crate::msgs::json::{FromJson as _, ToJson as _};
use crate::msgs::sweetspot_msgs::msg::ExitVelocity;
use crate::msgs::sweetspot_msgs::srv::{SimulateSwing_Request, SimulateSwing_Response};
use crate::ros::{self, DdsConfig};

/// `sweetspot call`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  sweetspot call simulate_swing '{swing: {bat_id: r161, ball_speed: 40, bat_cm_speed: 25, impact_z: 0.7}}'
  sweetspot call simulate_swing '{\"swing\": {\"bat_id\": \"r161\", \"ball_speed\": 40, \"impact_z\": 0.7}}'
  sweetspot call /rig3/sweetspot/simulate_swing '{swing: {bat_id: aluminum, impact_z: 0.6}}' --timeout 30

The REQUEST is YAML (flow `{a: 1}` or block `a: 1`, as `ros2 service call` takes it) or JSON. Fields left out
keep their defaults; floats accept null/nan/.nan.")]
pub struct CallArgs {
    /// The service: `simulate_swing` (the node's `~/simulate_swing`, see --node and --ns) or its
    /// fully-qualified name, e.g. `/rig3/sweetspot/simulate_swing`.
    pub service: String,
    /// The request as YAML (as `ros2 service call` takes it) or JSON: `swing` (a Swing), and optionally
    /// `bat` / `ball` (a list of at most one BatParams / BallParams, for this call only), e.g.
    /// '{swing: {bat_id: r161, ball_speed: 40, bat_cm_speed: 25, bat_angular_speed: 45, impact_z: 0.7}}'.
    pub request: String,
    /// The node serving it (its name, for `simulate_swing`).
    #[arg(long, value_name = "NAME", default_value = crate::node::runtime::DEFAULT_NODE_NAME)]
    pub node: String,
    /// The node's namespace (for `simulate_swing`).
    #[arg(long, visible_alias = "namespace", value_name = "NS", default_value = "/")]
    pub ns: String,
    /// Give up after this many seconds without an answer (waiting for the service included).
    #[arg(long, value_name = "SECS", default_value = "10", value_parser = super::common::seconds_at_least_zero)]
    pub timeout: f64,
    /// The service's request/reply mapping, as the node's `service_mapping` parameter: `enhanced` (the
    /// node's default, rmw_fastrtps's) or `cyclone` (rmw_cyclonedds_cpp's).
    #[arg(long, value_name = "MAPPING", default_value = "enhanced", value_parser = ["enhanced", "cyclone"])]
    pub mapping: String,
}

/// The request a parsed argument stands for. A swing that leaves out `measured_exit_speed` did not measure it:
/// NaN, as `pub` reads the same swing (the message's 0 would be a measurement of 0 m/s).
fn request_from(mut value: serde_json::Value) -> anyhow::Result<SimulateSwing_Request> {
    if let Some(swing) = value.get_mut("swing").and_then(serde_json::Value::as_object_mut) {
        swing.entry("measured_exit_speed").or_insert(serde_json::Value::Null);
    }
    SimulateSwing_Request::from_json(&value, "request").map_err(|e| anyhow!("{e}"))
}

/// Resolves the service, sends the request, prints the response.
pub fn run(args: CallArgs) -> anyhow::Result<()> {
    let fq_name = service_name(&args.service, &args.ns, &args.node)?;
    let value = super::pubsub::parse_values(&args.request).with_context(|| format!("the request {}", args.request))?;
    let request = request_from(value)?;
    let config = DdsConfig::from_env()?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    let mapping = crate::node::settings::service_mapping(&args.mapping)
        .ok_or_else(|| anyhow!("--mapping {}: expected enhanced or cyclone", args.mapping))?;
    let response = runtime.block_on(call(&config, &fq_name, request, args.timeout, mapping))?;
    crate::outln!("{}", response.to_json())?;
    let ev = &response.exit_velocity;
    match ev.status {
        ExitVelocity::STATUS_OK => Ok(()),
        ExitVelocity::STATUS_DROPPED => bail!("{fq_name} answered DROPPED: {}", ev.message),
        _ => bail!("{fq_name} answered REJECTED: {}", ev.message),
    }
}

/// The fully-qualified service name of `service` for the node `node` in `ns`.
pub fn service_name(service: &str, ns: &str, node: &str) -> anyhow::Result<String> {
    if service.starts_with('/') {
        return Ok(ros::names::resolve_topic(service, "/", node)?);
    }
    match service {
        "simulate_swing" => Ok(ros::names::resolve_topic(crate::node::service::SERVICE_NAME, ns, node)?),
        other => bail!(
            "unknown service {other:?}: sweetspot serves simulate_swing (or give the fully-qualified name, \
             e.g. /sweetspot/simulate_swing)"
        ),
    }
}

async fn call(
    config: &DdsConfig,
    fq_name: &str,
    request: SimulateSwing_Request,
    timeout: f64,
    mapping: ros2_client::ServiceMapping,
) -> anyhow::Result<SimulateSwing_Response> {
    let context = ros::context(config)?;
    let node_name = ros2_client::NodeName::new("/", &format!("sweetspot_call_{}", std::process::id()))
        .map_err(|e| anyhow!("node name: {e:?}"))?;
    let mut node = context
        .new_node(node_name, ros2_client::NodeOptions::new().enable_rosout(false))
        .map_err(|e| anyhow!("creating the DDS node: {e:?}"))?;
    let name = ros::names::to_client_name(fq_name)?;
    let service_type = ros2_client::ServiceTypeName::new("sweetspot_msgs", "SimulateSwing");
    let client = node
        .create_client::<SimulateSwing_Request, SimulateSwing_Response>(
            mapping,
            &name,
            &service_type,
            ros::swing_qos(),
            ros::results_qos(),
        )
        .map_err(|e| anyhow!("service client of {fq_name}: {e:?}"))?;
    // The spinner keeps the graph that `wait_for_service` looks at.
    let spinner = node.spinner().map_err(|e| anyhow!("{e:?}"))?;
    let spinning = tokio::spawn(spinner.spin());
    let deadline = crate::model::time::saturating_secs(timeout);
    let started = std::time::Instant::now();
    let outcome = tokio::time::timeout(deadline, async {
        client.wait_for_service(&node).await;
        let id = client.async_send_request(request).await.map_err(|e| anyhow!("sending the request: {e:?}"))?;
        client.async_receive_response(id).await.map_err(|e| anyhow!("reading the response: {e:?}"))
    })
    .await;
    spinning.abort();
    // The two mappings share topic names, so a node on the other one matches but never answers.
    let other = match mapping {
        ros2_client::ServiceMapping::Cyclone => "a node on the default mapping is called without --mapping",
        _ => "a node started with -p service_mapping:=cyclone is called with --mapping cyclone",
    };
    if outcome.is_ok() {
        warn_of_namesakes(&context, fq_name);
    }
    match outcome {
        Ok(result) => result,
        Err(_) => bail!(
            "no answer from {fq_name} within {:.1} s (ROS_DOMAIN_ID {}, discovery {}): is a node serving it? \
             (`sweetspot node`; --node / --ns name another node; raise --timeout; {other})",
            started.elapsed().as_secs_f64(),
            config.domain_id,
            config.range
        ),
    }
}

/// Warns on stderr when more than one node serves `fq_service` (nodes sharing a name): the answer printed is
/// whichever came first.
pub(crate) fn warn_of_namesakes(context: &ros2_client::Context, fq_service: &str) {
    // One warning for a command, however many calls it makes (`param dump` makes two).
    static WARNED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
    let servers = super::graph::servers_of(context, fq_service);
    if servers > 1 && !WARNED.swap(true, std::sync::atomic::Ordering::Relaxed) {
        let node = fq_service.rsplit_once('/').map_or("/", |(node, _)| if node.is_empty() { "/" } else { node });
        eprintln!("warning: {}", super::graph::namesake_warning(node, servers, &format!("serve {fq_service}")));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_swing_that_leaves_out_the_measured_exit_speed_did_not_measure_it() {
        let parse =
            |text: &str| request_from(super::super::pubsub::parse_values(text).expect("parses")).expect("request");
        let omitted = parse("{swing: {bat_id: r161, ball_speed: 40, bat_cm_speed: 25, impact_z: 0.7}}");
        assert!(omitted.swing.measured_exit_speed.is_nan(), "{}", omitted.swing.measured_exit_speed);
        // A measurement given, even 0, is kept.
        let zero = parse("{swing: {bat_id: r161, measured_exit_speed: 0}}");
        assert_eq!(zero.swing.measured_exit_speed, 0.0);
        let given = parse("{swing: {measured_exit_speed: 41.5}}");
        assert_eq!(given.swing.measured_exit_speed, 41.5);
    }
}
