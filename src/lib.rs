//! sweetspot: bat–ball collision physics (Nathan 2000) behind a pure-Rust ROS 2 node with MCAP recording.
//!
//! - [`physics`]: the pure, synchronous core (SI units, no I/O);
//! - [`msgs`]: Rust types generated at build time from `msgs/sweetspot_msgs/msg/*.msg`;
//! - [`node`]: the ROS 2 shell (topics, QoS, parameters, diagnostics);
//! - [`bag`]: MCAP record / replay in the rosbag2 layout;
//! - [`cli`]: the command line.
pub mod bag;
pub mod bench;
pub mod calibrate;
pub mod child;
pub mod cli;
pub mod demo;
pub mod msgs;
pub mod node;
pub mod physics;
pub mod report;
pub mod rig;
pub mod ros;
