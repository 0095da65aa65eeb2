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

use super::graph::warn_of_namesakes;
use super::values::parse_values;
use super::{bounded_error, quoted};
use crate::msgs::json::{FromJson as _, ToJson as _};
use crate::msgs::sweetspot_msgs::msg::ExitVelocity;
use crate::msgs::sweetspot_msgs::srv::{SimulateSwing_Request, SimulateSwing_Response};
use crate::ros::{self, DdsConfig};

/// One call: the service, the request and how to reach the node (`sweetspot call`'s flags).
#[derive(Debug, Clone)]
pub struct CallOptions {
    /// `simulate_swing` or a fully-qualified service name.
    pub service: String,
    /// The request as YAML or JSON.
    pub request: String,
    /// The node serving `simulate_swing`.
    pub node: String,
    /// The node's namespace.
    pub ns: String,
    /// Seconds to wait for an answer, waiting for the service included.
    pub timeout: f64,
    /// `enhanced` or `cyclone`.
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
pub fn call(args: CallOptions) -> anyhow::Result<()> {
    let fq_name = service_name(&args.service, &args.ns, &args.node)?;
    let value = parse_values(&args.request).with_context(|| format!("the request {}", quoted(&args.request)))?;
    let request = request_from(value)?;
    let config = DdsConfig::from_env()?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .context("starting the async runtime")?;
    let mapping = crate::node::settings::service_mapping(&args.mapping)
        .ok_or_else(|| anyhow!("--mapping {}: expected enhanced or cyclone", args.mapping))?;
    let response = runtime.block_on(call_service(&config, &fq_name, request, args.timeout, mapping))?;
    crate::outln!("{}", response.to_json())?;
    let ev = &response.exit_velocity;
    match ev.status {
        ExitVelocity::STATUS_OK => Ok(()),
        ExitVelocity::STATUS_DROPPED => bail!("{} answered DROPPED: {}", quoted(&fq_name), ev.message),
        _ => bail!("{} answered REJECTED: {}", quoted(&fq_name), ev.message),
    }
}

/// The fully-qualified service name of `service` for the node `node` in `ns`.
pub fn service_name(service: &str, ns: &str, node: &str) -> anyhow::Result<String> {
    if service.starts_with('/') {
        return ros::names::resolve_topic(service, "/", node).map_err(bounded_error);
    }
    match service {
        "simulate_swing" => {
            ros::names::resolve_topic(crate::node::service::SERVICE_NAME, ns, node).map_err(bounded_error)
        }
        other => bail!(
            "unknown service {:?}: sweetspot serves simulate_swing (or give the fully-qualified name, \
             e.g. /sweetspot/simulate_swing)",
            quoted(other)
        ),
    }
}

async fn call_service(
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
        warn_of_namesakes(&context, fq_name, started).await;
    }
    match outcome {
        Ok(result) => result,
        Err(_) => bail!(
            "no answer from {} within {:.1} s (ROS_DOMAIN_ID {}, discovery {}): is a node serving it? \
             (`sweetspot node`; --node / --ns name another node; raise --timeout; {other})",
            quoted(fq_name),
            started.elapsed().as_secs_f64(),
            config.domain_id,
            config.range
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_swing_that_leaves_out_the_measured_exit_speed_did_not_measure_it() {
        let parse = |text: &str| request_from(parse_values(text).expect("parses")).expect("request");
        let omitted = parse("{swing: {bat_id: r161, ball_speed: 40, bat_cm_speed: 25, impact_z: 0.7}}");
        assert!(omitted.swing.measured_exit_speed.is_nan(), "{}", omitted.swing.measured_exit_speed);
        // A measurement given, even 0, is kept.
        let zero = parse("{swing: {bat_id: r161, measured_exit_speed: 0}}");
        assert_eq!(zero.swing.measured_exit_speed, 0.0);
        let given = parse("{swing: {measured_exit_speed: 41.5}}");
        assert_eq!(given.swing.measured_exit_speed, 41.5);
    }
}
