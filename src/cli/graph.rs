//! `sweetspot topic list`, `service list`, `nodes` and `interface show|list`: their flags; the graph queries
//! are [`crate::client::graph`]'s.

use crate::client::graph;

/// `sweetspot topic`.
#[derive(Debug, clap::Subcommand)]
pub enum TopicCommand {
    /// Every topic with a publisher or a subscriber, as `ros2 topic list`.
    List(ListArgs),
}

/// `sweetspot service`.
#[derive(Debug, clap::Subcommand)]
pub enum ServiceCommand {
    /// Every service with a server, as `ros2 service list`.
    List(ListArgs),
}

/// `sweetspot interface`.
#[derive(Debug, clap::Subcommand)]
pub enum InterfaceCommand {
    /// A message or service definition sweetspot knows (`pkg/msg/Type`, `pkg/srv/Type`), as `ros2 interface
    /// show`.
    Show {
        /// The type, e.g. `sweetspot_msgs/msg/Swing` or `sweetspot_msgs/srv/SimulateSwing`.
        type_name: String,
    },
    /// Every type sweetspot knows, as `ros2 interface list`.
    List,
}

/// How to list.
#[derive(Debug, clap::Args)]
pub struct ListArgs {
    /// Show each one's type(s) too.
    #[arg(short = 't', long = "show-types")]
    pub show_types: bool,
    /// Seconds to listen to discovery before listing, 0 to 3600.
    #[arg(long, value_name = "SECS", default_value = "2", value_parser = super::common::spin_seconds)]
    pub spin_time: f64,
}

/// How to list nodes.
#[derive(Debug, clap::Args)]
pub struct NodesArgs {
    /// Seconds to listen to discovery before listing, 0 to 3600.
    #[arg(long, value_name = "SECS", default_value = "2", value_parser = super::common::spin_seconds)]
    pub spin_time: f64,
}

/// Runs `sweetspot topic …`.
pub fn run_topic(command: TopicCommand) -> anyhow::Result<()> {
    let TopicCommand::List(args) = command;
    graph::list_topics(args.spin_time, args.show_types)
}

/// Runs `sweetspot service …`.
pub fn run_service(command: ServiceCommand) -> anyhow::Result<()> {
    let ServiceCommand::List(args) = command;
    graph::list_services(args.spin_time, args.show_types)
}

/// Runs `sweetspot nodes`.
pub fn run_nodes(args: NodesArgs) -> anyhow::Result<()> {
    graph::list_nodes(args.spin_time)
}

/// Runs `sweetspot interface …`.
pub fn run_interface(command: InterfaceCommand) -> anyhow::Result<()> {
    match command {
        InterfaceCommand::Show { type_name } => graph::show_interface(&type_name),
        InterfaceCommand::List => graph::list_interfaces(),
    }
}
