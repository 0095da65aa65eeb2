//! `sweetspot call`: its flags; the call is [`crate::client::call`]'s.

use crate::client::call::CallOptions;

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
    /// Give up after this many seconds without an answer (waiting for the service included), 0 to 86400.
    #[arg(long, value_name = "SECS", default_value = "10", value_parser = super::common::call_timeout_seconds)]
    pub timeout: f64,
    /// The service's request/reply mapping, as the node's `service_mapping` parameter: `enhanced` (the
    /// node's default, rmw_fastrtps's) or `cyclone` (rmw_cyclonedds_cpp's).
    #[arg(long, value_name = "MAPPING", default_value = "enhanced", value_parser = ["enhanced", "cyclone"])]
    pub mapping: String,
}

/// Resolves the service, sends the request, prints the response.
pub fn run(args: CallArgs) -> anyhow::Result<()> {
    let CallArgs { service, request, node, ns, timeout, mapping } = args;
    crate::client::call::call(CallOptions { service, request, node, ns, timeout, mapping })
}
