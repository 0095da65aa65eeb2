//! `sweetspot param list|get|set|describe|dump NODE …`: their flags; the calls of the node's parameter
//! services are [`crate::client::param`]'s.

use crate::client::param::{ParamRequest, ParamTarget};

/// `sweetspot param`.
#[derive(Debug, clap::Subcommand)]
pub enum ParamCommand {
    /// The node's parameter names, as `ros2 param list NODE`.
    List(NodeArg),
    /// One parameter's value, as `ros2 param get NODE NAME`.
    Get {
        #[command(flatten)]
        node: NodeArg,
        /// The parameter.
        name: String,
        /// Print the value only, without its type.
        #[arg(long)]
        hide_type: bool,
    },
    /// Sets a parameter on the running node, as `ros2 param set NODE NAME VALUE`.
    Set {
        #[command(flatten)]
        node: NodeArg,
        /// The parameter.
        name: String,
        /// Its new value, as YAML (`12` integer, `12.0` double, `true` bool, otherwise a string).
        value: String,
    },
    /// Parameters' type, description and constraints, as `ros2 param describe NODE NAME...`.
    Describe {
        #[command(flatten)]
        node: NodeArg,
        /// The parameters.
        #[arg(required = true)]
        names: Vec<String>,
    },
    /// Every parameter as a `--params-file` YAML, as `ros2 param dump NODE`.
    Dump(NodeArg),
}

/// The node asked and how.
#[derive(Debug, clap::Args)]
pub struct NodeArg {
    /// The node's fully-qualified name, e.g. `/sweetspot` or `/rig3/sweetspot`.
    pub node: String,
    /// Give up after this many seconds without an answer (waiting for the service included), 0 to 86400.
    #[arg(long, value_name = "SECS", default_value = "10", value_parser = super::common::call_timeout_seconds)]
    pub timeout: f64,
    /// The services' request/reply mapping: `enhanced` (rmw_fastrtps's, the default) or `cyclone`
    /// (rmw_cyclonedds_cpp's, a node started with `-p service_mapping:=cyclone`).
    #[arg(long, value_name = "MAPPING", default_value = "enhanced", value_parser = ["enhanced", "cyclone"])]
    pub mapping: String,
}

/// Runs `sweetspot param …`.
pub fn run(command: ParamCommand) -> anyhow::Result<()> {
    let (node, request) = match command {
        ParamCommand::List(node) => (node, ParamRequest::List),
        ParamCommand::Get { node, name, hide_type } => (node, ParamRequest::Get { name, hide_type }),
        ParamCommand::Set { node, name, value } => (node, ParamRequest::Set { name, value }),
        ParamCommand::Describe { node, names } => (node, ParamRequest::Describe { names }),
        ParamCommand::Dump(node) => (node, ParamRequest::Dump),
    };
    let NodeArg { node, timeout, mapping } = node;
    crate::client::param::param(ParamTarget { node, timeout, mapping }, request)
}
