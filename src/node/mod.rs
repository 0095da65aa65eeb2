//! The ROS 2 shell: topics, QoS, parameters, diagnostics.
//!
//! Data flows one way: message → physics → result → publish + record. The pure parts (ROS argument parsing,
//! parameters, statistics, message ↔ physics conversion) are plain functions tested without DDS; the DDS
//! wiring lives in `runtime`.

pub mod convert;
pub mod engine;
pub mod pipeline;
pub mod recording;
pub mod ros_args;
pub mod runtime;
pub mod settings;
pub mod stats;
