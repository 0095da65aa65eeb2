//! sweetspot: bat–ball collision physics (Nathan 2000) behind a pure-Rust ROS 2 node with MCAP recording.
//!
//! Layers, each importing only those above it in this list. The first ones build without DDS, tokio or a
//! server and are crates of their own under `crates/` (re-exported here under their module names, so
//! `sweetspot::physics` is `sweetspot_physics`); the rest is this crate, the ROS 2 shell:
//!
//! - [`physics`]: the pure, synchronous core (SI units, no I/O);
//! - [`msgs`]: Rust types generated at build time from `msgs/sweetspot_msgs/msg/*.msg`;
//! - [`model`]: messages ↔ physics, the bat/ball registry, swing planning and computing, the model settings a
//!   bag records — the one place the node, replay, calibration, the rig and the fuzz targets decide alike;
//! - [`bag`]: MCAP record, read, export and replay in the rosbag2 layout;
//!   [`ros`]: the DDS edge (names, `--ros-args`, QoS, the participant);
//! - [`foxglove`]: the Foxglove WebSocket server the node and `bag play` serve topics on;
//! - [`node`]: the ROS 2 node (topics, parameters, diagnostics, recording); [`play`]: `bag play` over DDS
//!   and Foxglove; [`record`]: `bag record` over DDS; [`client`]: the ROS 2 command-line client (`pub`,
//!   `echo`, `param`, `call`, the graph's lists);
//! - [`report`]: tables, JSON documents, plots and the seed's figures, for the tools below; [`child`]: the
//!   node (or any tool) as a child process;
//! - [`import`]: tracker exports (TrackMan, Statcast) into bags of swings; [`locate`]: where on the bat each
//!   recorded ball was hit;
//! - [`calibrate`]: fitting the ball's COR (and bats' Young's moduli) to recorded swings; [`rig`]: a simulated
//!   test rig publishing swings; [`demo`]: a scripted run of node and rig; [`bench`]: end-to-end benchmarks;
//!   [`validate`]: the model against published measurements;
//! - [`files`]: the rules for the files a user names (regular inputs under a size cap; no output onto an
//!   input), used by every layer that opens one; [`yaml`]: every YAML text loaded under a depth and
//!   alias-expansion budget;
//! - [`cli`]: the command line (argument parsing; the work lives in the layers above).
pub use sweetspot_analysis::{answer, bat_file, calibrate, import, locate, report, validate};
pub use sweetspot_bag as bag;
pub use sweetspot_model as model;
pub use sweetspot_model::{files, yaml};
pub use sweetspot_msgs as msgs;
pub use sweetspot_physics as physics;

pub mod bag_tools;
pub mod bench;
pub mod child;
pub mod cli;
pub mod client;
pub mod demo;
pub mod foxglove;
pub mod node;
pub mod play;
pub mod record;
pub mod rig;
pub mod ros;
