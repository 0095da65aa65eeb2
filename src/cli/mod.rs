//! The `sweetspot` command line (clap). Each subcommand's arguments and runner live in its own file.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub mod bag;
pub use crate::bat_file;
pub mod bbcor;
pub mod bench;
pub mod calibrate;
pub mod call;
pub mod case_file;
pub mod common;
pub mod compare;
pub mod demo;
pub mod figures;
pub mod graph;
pub mod import;
pub mod locate;
pub mod modes;
pub mod node;
pub mod param;
pub mod pubsub;
pub mod rig;
pub mod simulate;
pub mod sweep;
pub mod validate;

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
    /// The whole thing in one command: node, simulated rig and recorder over real DDS, then a report and figures.
    Demo(demo::DemoArgs),
    /// Run the ROS 2 node.
    Node(node::NodeArgs),
    /// Publish params and swings from the command line or a file.
    Pub(pubsub::PubArgs),
    /// Print what arrives on a topic.
    Echo(pubsub::EchoArgs),
    /// Call a node's service (`simulate_swing`), as `ros2 service call`.
    Call(call::CallArgs),
    /// A running node's parameters: list, get, set, describe, dump, as `ros2 param`.
    #[command(subcommand)]
    Param(param::ParamCommand),
    /// The topics in the ROS graph, as `ros2 topic list [-t]`.
    #[command(subcommand)]
    Topic(graph::TopicCommand),
    /// The services in the ROS graph, as `ros2 service list [-t]`.
    #[command(subcommand)]
    Service(graph::ServiceCommand),
    /// The nodes in the ROS graph, as `ros2 node list` (`sweetspot node list` works too).
    Nodes(graph::NodesArgs),
    /// Message and service definitions sweetspot knows, as `ros2 interface show|list`.
    #[command(subcommand)]
    Interface(graph::InterfaceCommand),
    /// Record, inspect, replay, play, recover and export bags.
    #[command(subcommand)]
    Bag(bag::BagCommand),
    /// Mass properties and vibrational modes (frequency, nodes, modal mass) of a bat.
    Modes(modes::ModesArgs),
    /// One bat–ball collision per impact point, from flags or a case file.
    Simulate(simulate::SimulateArgs),
    /// Exit speed (flexible and rigid) over impact points, the sweet spots, and an optional plot.
    Sweep(sweep::SweepArgs),
    /// BBCOR (and BESR) of a bat under the certification protocol.
    Bbcor(bbcor::BbcorArgs),
    /// Redraws the seed paper's Figures 2, 5 and 6 and the mode shapes into a directory.
    Figures(figures::FiguresArgs),
    /// A simulated batting rig publishing params and swings over DDS, as a real sensor rig would.
    Rig(rig::RigArgs),
    /// Measure latency against raw DDS, sustained rate, recorder throughput and memory.
    Bench(bench::BenchArgs),
    /// Compare bats as one batter swings them: equal effort, predicted bat speed, reaction time gained.
    Compare(compare::CompareArgs),
    /// Fit the ball's COR (and bat stiffness) to the measured exit speeds of a recorded session.
    Calibrate(calibrate::CalibrateArgs),
    /// The model against published measurements: model vs measured, ratio and verdict per row, figures.
    Validate(validate::ValidateArgs),
    /// Tracker exports (TrackMan, Statcast, HitTrax CSV, or any CSV through a --map file) into a bag of swings.
    Import(import::ImportArgs),
    /// Where on the bat each ball of a bag was hit, from its measured exit speed, launch angle and spin.
    Locate(locate::LocateArgs),
}

/// Parses the process arguments and runs the chosen subcommand; errors are printed with context.
pub fn main() -> ExitCode {
    // `ros2 node list`'s spelling: `sweetspot node list` is `sweetspot nodes` (`node` alone runs the node).
    let mut argv: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if argv.get(1).is_some_and(|a| a == "node") && argv.get(2).is_some_and(|a| a == "list") {
        argv.splice(1..3, [std::ffi::OsString::from("nodes")]);
    }
    let cli = Cli::parse_from(argv);
    let outcome = match cli.command {
        Command::Node(args) => node::run(args),
        Command::Pub(args) => pubsub::run_pub(args),
        Command::Echo(args) => pubsub::run_echo(args),
        Command::Call(args) => call::run(args),
        Command::Param(cmd) => param::run(cmd),
        Command::Topic(cmd) => graph::run_topic(cmd),
        Command::Service(cmd) => graph::run_service(cmd),
        Command::Nodes(args) => graph::run_nodes(args),
        Command::Interface(cmd) => graph::run_interface(cmd),
        Command::Bag(cmd) => bag::run(cmd),
        Command::Modes(args) => modes::run(args),
        Command::Simulate(args) => simulate::run(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Bbcor(args) => bbcor::run(args),
        Command::Figures(args) => figures::run(args),
        Command::Demo(args) => demo::run(args),
        Command::Rig(args) => rig::run(args),
        Command::Calibrate(args) => calibrate::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Validate(args) => validate::run(args),
        Command::Import(args) => import::run(args),
        Command::Locate(args) => locate::run(args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            // Interrupted (Ctrl-C) with a partial result: 128 + SIGINT, as a shell reports it.
            match err.is::<crate::demo::Interrupted>() {
                true => ExitCode::from(130),
                false => ExitCode::FAILURE,
            }
        }
    }
}
