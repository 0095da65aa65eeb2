//! The `sweetspot` command line (clap). Each subcommand's arguments and runner live in its own file.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod bag;
pub mod node;
pub mod pubsub;

/// sweetspot: bat–ball collision physics as a ROS 2 node, with MCAP recording.
#[derive(Debug, Parser)]
#[command(name = "sweetspot", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// Every subcommand.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the ROS 2 node.
    Node(node::NodeArgs),
    /// Publish params and swings from the command line or a file.
    Pub(pubsub::PubArgs),
    /// Print what arrives on a topic.
    Echo(pubsub::EchoArgs),
    /// Inspect, replay, play, recover and export recorded bags.
    #[command(subcommand)]
    Bag(bag::BagCommand),
}

/// Parses the process arguments and runs the chosen subcommand; errors are printed with context.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Node(args) => node::run(args),
        Command::Pub(args) => pubsub::run_pub(args),
        Command::Echo(args) => pubsub::run_echo(args),
        Command::Bag(cmd) => bag::run(cmd),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
