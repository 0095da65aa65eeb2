//! The ROS 2 shell: topics, QoS, parameters, diagnostics.
//!
//! Data flows one way: message → physics → result → publish + record. The pure parts (ROS argument parsing,
//! parameters, statistics, message ↔ physics conversion) are plain functions tested without DDS; the DDS
//! wiring lives in `runtime`.

pub mod ros_args;
pub mod settings;
pub mod stats;
pub mod engine;
pub mod pipeline;
pub mod convert;
pub mod recording;
pub mod runtime;
