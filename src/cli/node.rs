//! `sweetspot node`: arguments and runner (owned by the node work).

use crate::node::ros_args::RosArgs;
use crate::node::runtime::NodeConfig;
use crate::node::settings::parameter_names;

/// Arguments of `sweetspot node`.
///
/// Everything after `--ros-args` follows the ROS 2 conventions:
/// `-r __ns:=/rig3`, `-r __node:=name`, `-r swing:=/other/swing`, `-p default_modes:=12`,
/// `--params-file params.yaml`, `--log-level debug`.
#[derive(Debug, Clone, clap::Args)]
#[command(after_help = after_help())]
pub struct NodeArgs {
    /// Do not record a bag (same as `--ros-args -p record:=false`).
    #[arg(long)]
    pub no_record: bool,

    /// Serve the session live to Foxglove (WebSocket) on [ADDR:]PORT, 127.0.0.1 unless ADDR is given
    /// (same as `--ros-args -p foxglove_port:=[ADDR:]PORT`).
    #[arg(long, value_name = "[ADDR:]PORT")]
    pub foxglove: Option<String>,

    /// ROS 2 arguments (remaps, parameters, params files); must come last.
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, action = clap::ArgAction::Append, value_name = "ROS_ARGS")]
    pub ros_args: Option<Vec<String>>,
}

impl NodeArgs {
    /// The node configuration these arguments describe.
    pub fn config(&self) -> anyhow::Result<NodeConfig> {
        let ros_args = RosArgs::parse(self.ros_args.as_deref().unwrap_or_default())?;
        Ok(NodeConfig { ros_args, no_record: self.no_record, foxglove: self.foxglove.clone() })
    }
}

/// The examples and the parameter list (from the node's parameter table) under `sweetspot node --help`.
fn after_help() -> String {
    let mut text = String::from(
        "Examples:\n  sweetspot node\n  sweetspot node --no-record --ros-args -r __ns:=/rig3 -p default_modes:=12\n  \
         sweetspot node --ros-args --params-file params.yaml\n  sweetspot node --foxglove 8765\n\n",
    );
    let mut line = String::from("The node's parameters (see `ros2 param list /sweetspot`):");
    let names = parameter_names();
    for (i, name) in names.iter().enumerate() {
        let word = format!("{name}{}", if i + 1 == names.len() { "." } else { "," });
        // Wrapped at 100 columns, like the rest of the help.
        if line.len() + 1 + word.len() > 100 {
            text.push_str(&line);
            text.push('\n');
            line = word;
        } else {
            line.push(' ');
            line.push_str(&word);
        }
    }
    text.push_str(&line);
    text.push_str("\nDDS: ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE (LOCALHOST, SUBNET, OFF), ROS_LOCALHOST_ONLY.");
    text
}

/// Runs the node until SIGINT/SIGTERM.
pub fn run(args: NodeArgs) -> anyhow::Result<()> {
    let config = args.config()?;
    init_logging(config.ros_args.log_level.as_deref());
    crate::node::runtime::run(config)
}

/// The node's log filter without `RUST_LOG` or `--log-level`: info, but only errors from the DDS libraries —
/// except the one warning ros2-client logs per parameter request refused for its size (docs/node.md, Limits).
pub(crate) const DEFAULT_LOG_FILTER: &str = "info,rustdds=error,ros2_client=error,ros2_client::parameter_services=warn";

pub(crate) fn init_logging(level: Option<&str>) {
    use tracing_subscriber::EnvFilter;
    let filter = match level {
        Some(level) => EnvFilter::new(level),
        None => EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new(DEFAULT_LOG_FILTER)),
    };
    // Another subscriber may already be set (tests); that one wins.
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .try_init();
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use crate::cli::{Cli, Command};

    fn parse(line: &str) -> super::NodeArgs {
        let argv: Vec<&str> = std::iter::once("sweetspot").chain(line.split_whitespace()).collect();
        match Cli::try_parse_from(argv).unwrap().command {
            Command::Node(args) => args,
            other => panic!("parsed as {other:?}"),
        }
    }

    #[test]
    fn ros_args_take_everything_after_them() {
        let a = parse("node --no-record --ros-args -r __ns:=/rig3 -p default_modes:=12 --params-file p.yaml");
        assert!(a.no_record);
        let c = a.config().unwrap();
        assert_eq!(c.ros_args.identity("sweetspot", "/").namespace, "/rig3");
        assert_eq!(c.ros_args.params.len(), 1);
        assert_eq!(c.ros_args.params_files.len(), 1);
        let a = parse("node");
        assert!(!a.no_record);
        assert_eq!(a.config().unwrap().ros_args, Default::default());
    }

    #[test]
    fn repeated_ros_args_sections_are_merged() {
        let a = parse("node --ros-args -r __node:=lab --ros-args -p record:=false");
        let c = a.config().unwrap();
        assert_eq!(c.ros_args.identity("sweetspot", "/").name, "lab");
        assert_eq!(c.ros_args.params.len(), 1);
    }

    #[test]
    fn the_help_lists_every_node_parameter() {
        use clap::CommandFactory;
        let mut cli = Cli::command();
        let help = cli.find_subcommand_mut("node").expect("a node subcommand").render_long_help().to_string();
        let after = help.split("The node's parameters").nth(1).expect("a parameter list in the help");
        // "… (see `ros2 param list /sweetspot`): a, b,\nc.\nDDS: …"
        let list = after.split(':').nth(1).unwrap_or_default().split("DDS").next().unwrap_or_default();
        let listed: Vec<&str> = list.split([',', '.', ' ', '\n']).filter(|w| !w.is_empty()).collect();
        assert_eq!(listed, crate::node::settings::parameter_names(), "the list in `sweetspot node --help`");
    }

    #[test]
    fn bad_ros_args_are_errors_not_panics() {
        let a = parse("node --ros-args -p novalue");
        assert!(a.config().is_err());
    }
}
