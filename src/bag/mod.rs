//! MCAP record / replay in the rosbag2 layout (`<dir>/metadata.yaml` + `<dir>/<name>_N.mcap`).
//!
//! The recorder is the contract between the node and the bag: the node encodes each message to CDR once and
//! hands the bytes over a bounded channel to a writer thread, so recording never blocks the DDS receive path.

use std::path::PathBuf;
use std::time::Duration;

pub mod export;
pub mod info;
pub mod play;
pub mod reader;
pub mod replay;
pub mod recover;
mod recorder;
pub mod rosbag2;
pub mod writer;

pub use recorder::Recorder;
pub use rosbag2::{default_bag_dir, BagMetadata};

/// Errors of the bag layer.
#[derive(Debug, thiserror::Error)]
pub enum BagError {
    /// Any I/O failure, with the path involved.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// An MCAP-level failure.
    #[error("mcap: {0}")]
    Mcap(String),
    /// The bag is not in the expected layout or format.
    #[error("bad bag: {0}")]
    Format(String),
}

/// QoS a topic was offered with, as recorded in the channel metadata `offered_qos_profiles`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RecordedQos {
    /// RELIABLE (true) or BEST_EFFORT (false).
    pub reliable: bool,
    /// TRANSIENT_LOCAL (true) or VOLATILE (false).
    pub transient_local: bool,
    /// KEEP_LAST depth.
    pub depth: u32,
}

/// A topic to record.
#[derive(Debug, Clone, PartialEq)]
pub struct TopicInfo {
    /// Fully qualified topic name, e.g. `/rig3/swing`.
    pub name: String,
    /// ROS type name, e.g. `sweetspot_msgs/msg/Swing`.
    pub type_name: String,
    /// Full `ros2msg` schema text with dependencies concatenated the way rosbag2 stores them.
    pub schema_text: String,
    /// The QoS it was offered with.
    pub qos: RecordedQos,
}

/// Handle of a registered topic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TopicId(pub u16);

/// How and where to record.
#[derive(Debug, Clone)]
pub struct RecorderConfig {
    /// The rosbag2 directory to create (must not exist yet).
    pub dir: PathBuf,
    /// Split to a new `_N.mcap` file after this many bytes.
    pub max_file_size: Option<u64>,
    /// Split to a new file after this much recorded time.
    pub max_file_duration: Option<Duration>,
    /// Close the open chunk at least this often, so a crash loses at most this much.
    pub flush_interval: Duration,
    /// Capacity of the channel to the writer thread; messages beyond it are dropped and counted.
    pub queue_capacity: usize,
}

/// Counters of a recorder, readable at any time (`bytes` counts message payload bytes, CDR included).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RecorderStats {
    /// Messages written to disk.
    pub written: u64,
    /// Messages dropped because the channel was full.
    pub dropped: u64,
    /// Bytes written.
    pub bytes: u64,
    /// The last error, if recording failed (the node keeps running).
    pub error: Option<String>,
}

impl TopicInfo {
    /// The topic description of a generated message type: its ROS type name and full `ros2msg` schema.
    pub fn of<M: crate::msgs::RosMessage>(name: impl Into<String>, qos: RecordedQos) -> TopicInfo {
        TopicInfo { name: name.into(), type_name: M::TYPE_NAME.to_string(), schema_text: M::SCHEMA_TEXT.to_string(), qos }
    }
}
