//! MCAP record / replay in the rosbag2 layout (`<dir>/metadata.yaml` + `<dir>/<name>_N.mcap`).
//!
//! The recorder is the contract between the node and the bag: the node encodes each message to CDR once; the
//! recorder copies it into a shared batch, and full batches go to a writer thread (`mcap::Writer` under it), so
//! recording never waits for the disk on the DDS receive path.

use std::path::PathBuf;
use std::time::Duration;

pub mod export;
pub mod info;
pub mod reader;
mod recorder;
pub mod recover;
pub mod replay;
pub mod reports;
pub mod rosbag2;
pub mod writer;

pub use recorder::Recorder;
pub use rosbag2::{default_bag_dir, BagMetadata};
pub use writer::Batch;

/// Errors of the bag layer.
#[derive(Debug, thiserror::Error)]
pub enum BagError {
    /// Any I/O failure, with the path involved.
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    /// An MCAP-level failure.
    #[error("mcap: {0}")]
    Mcap(String),
    /// The bag is not in the expected layout or format.
    #[error("bad bag: {0}")]
    Format(String),
    /// Storage options that do not name a compression or preset, or do not go together.
    #[error("{0}")]
    Options(String),
    /// A path that is not a regular file (after following symlinks): a FIFO, a device, a directory.
    #[error("{path}: {what}, not a regular file: refused (bags are regular .mcap files)")]
    NotRegularFile { path: PathBuf, what: String },
    /// A regular file that is not an MCAP file.
    #[error("{path}: not an MCAP file: {reason}")]
    NotMcap { path: PathBuf, reason: String },
    /// The bag is damaged and the caller did not ask to skip damage (each line names file, chunk and loss).
    #[error("{summary}:\n{details}\npass --skip-damaged to go on with everything intact around the damage")]
    Damaged { summary: String, details: String },
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
    /// RIHS01 type description hash (REP-2011) of the type, or empty if unknown; stored as rosbag2 Jazzy does, as
    /// `type_description_hash` in the metadata and `topic_type_hash` in the MCAP channel metadata.
    pub type_hash: String,
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
    /// Messages accepted but not yet written (batched or queued for the writer thread) at most; messages
    /// beyond it are dropped and counted.
    pub queue_capacity: usize,
}

/// How MCAP chunks are compressed (rosbag2's `--compression-format` is about whole files; inside MCAP,
/// compression is per chunk, as rosbag2's MCAP storage plugin does it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChunkCompression {
    /// zstd at `level`: 1..=22 (3 is zstd's own default), or -7..=-1, zstd's "fast" levels (`zstd --fast=N`).
    Zstd {
        /// zstd compression level.
        level: i32,
    },
    /// LZ4 frames: faster than zstd, larger files.
    Lz4,
    /// Uncompressed chunks: the fastest; files about 1.5× the message bytes (framing and indexes).
    None,
}

impl Default for ChunkCompression {
    /// zstd level 1: most of level 3's ratio on sensor-like CDR at a fraction of the CPU.
    ///
    /// rosbag2's MCAP plugin writes uncompressed chunks unless given a preset; that was measured here as the
    /// node's default and not kept: bags three times the size, and the node's p99 latency at 10,000 swings/s
    /// no better (1.6× raw vs 1.2× with zstd, medians of five interleaved runs; BENCHMARKS.md).
    fn default() -> Self {
        ChunkCompression::Zstd { level: 1 }
    }
}

impl std::str::FromStr for ChunkCompression {
    type Err = BagError;
    /// `zstd` (level 1), `zstd:LEVEL`, `lz4` or `none`.
    fn from_str(s: &str) -> Result<Self, BagError> {
        let bad = || {
            BagError::Options(format!(
                "compression {s:?}: expected zstd, zstd:LEVEL (-7..=-1 fast, 1..=22), lz4 or none"
            ))
        };
        match s.split_once(':') {
            None if s == "zstd" => Ok(ChunkCompression::default()),
            None if s == "lz4" => Ok(ChunkCompression::Lz4),
            None if s == "none" => Ok(ChunkCompression::None),
            Some(("zstd", level)) => match level.parse::<i32>() {
                Ok(level) if (-7..=22).contains(&level) && level != 0 => Ok(ChunkCompression::Zstd { level }),
                _ => Err(bad()),
            },
            _ => Err(bad()),
        }
    }
}

impl std::fmt::Display for ChunkCompression {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ChunkCompression::Zstd { level } => write!(f, "zstd:{level}"),
            ChunkCompression::Lz4 => f.write_str("lz4"),
            ChunkCompression::None => f.write_str("none"),
        }
    }
}

/// Where messages go in an MCAP file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum McapLayout {
    /// In chunks (compressed or not), each followed by its message indexes, with chunk indexes in the
    /// summary: what readers seek and filter by time with.
    #[default]
    Chunked,
    /// As top-level Message records straight from the batches: no chunks, no compression, no message or
    /// chunk indexes (rosbag2's `fastwrite` preset). Readers go through the file linearly.
    Unchunked,
}

impl std::fmt::Display for McapLayout {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            McapLayout::Chunked => "chunked",
            McapLayout::Unchunked => "unchunked",
        })
    }
}

/// How the MCAP files are laid out (besides the split limits of [`RecorderConfig`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StorageOptions {
    /// Chunk compression (default zstd level 1). Must be `None` for [`McapLayout::Unchunked`].
    pub compression: ChunkCompression,
    /// Target uncompressed chunk size, bytes (default 1 MiB). When splitting by size, chunks are at most a
    /// quarter of `max_file_size` (at least 1 KiB), so a file is seen growing before it closes.
    pub chunk_size: Option<u64>,
    /// zstd worker threads compressing each chunk beside the writer thread (`mcap::WriteOptions::
    /// compression_threads`; default 0: the writer thread compresses). Used with zstd chunks only.
    pub compression_threads: Option<usize>,
    /// Chunked (default) or unchunked.
    pub layout: McapLayout,
}

/// rosbag2's MCAP storage presets (`ros2 bag record -s mcap --storage-preset-profile NAME`), as
/// rosbag2_storage_mcap maps them onto the MCAP writer's options.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StoragePreset {
    /// `none`: rosbag2's own default: uncompressed 768 KiB chunks (the mcap C++ writer's chunk size).
    None,
    /// `fastwrite`: no chunks; messages as top-level records, no message or chunk indexes.
    Fastwrite,
    /// `zstd_fast`: zstd at the mcap C++ writer's `Fastest` level (-5), 768 KiB chunks.
    ZstdFast,
    /// `zstd_small`: zstd at the mcap C++ writer's `Slowest` level (19), 4 MiB chunks.
    ZstdSmall,
}

/// The mcap C++ writer's default chunk size, which rosbag2 keeps for `none` and `zstd_fast`.
pub const ROSBAG2_CHUNK_SIZE: u64 = 768 * 1024;

impl StoragePreset {
    /// Every preset, in rosbag2's order.
    pub const ALL: [StoragePreset; 4] =
        [StoragePreset::None, StoragePreset::Fastwrite, StoragePreset::ZstdFast, StoragePreset::ZstdSmall];

    /// The rosbag2 name.
    pub fn name(self) -> &'static str {
        match self {
            StoragePreset::None => "none",
            StoragePreset::Fastwrite => "fastwrite",
            StoragePreset::ZstdFast => "zstd_fast",
            StoragePreset::ZstdSmall => "zstd_small",
        }
    }

    /// What the preset writes. rosbag2 turns chunk CRCs off (and, for `fastwrite`, the summary CRC); the
    /// CRCs are kept here: crc32fast costs a fraction of the write, and they let readers verify the file.
    pub fn storage_options(self) -> StorageOptions {
        let chunked = |compression, chunk_size| StorageOptions {
            compression,
            chunk_size: Some(chunk_size),
            compression_threads: None,
            layout: McapLayout::Chunked,
        };
        match self {
            StoragePreset::None => chunked(ChunkCompression::None, ROSBAG2_CHUNK_SIZE),
            StoragePreset::Fastwrite => StorageOptions {
                compression: ChunkCompression::None,
                chunk_size: None,
                compression_threads: None,
                layout: McapLayout::Unchunked,
            },
            StoragePreset::ZstdFast => chunked(ChunkCompression::Zstd { level: -5 }, ROSBAG2_CHUNK_SIZE),
            StoragePreset::ZstdSmall => chunked(ChunkCompression::Zstd { level: 19 }, 4 * 1024 * 1024),
        }
    }
}

impl std::str::FromStr for StoragePreset {
    type Err = BagError;
    /// A rosbag2 preset name; the error lists the valid ones as rosbag2's does.
    fn from_str(s: &str) -> Result<Self, BagError> {
        StoragePreset::ALL.into_iter().find(|p| p.name() == s).ok_or_else(|| {
            BagError::Options(format!(
                "unknown MCAP storage preset profile (valid options are 'none', 'fastwrite', 'zstd_fast', \
                 'zstd_small'): {s:?}"
            ))
        })
    }
}

impl std::fmt::Display for StoragePreset {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl StorageOptions {
    /// The options of a rosbag2 preset by name (`none`, `fastwrite`, `zstd_fast`, `zstd_small`).
    pub fn preset(name: &str) -> Result<StorageOptions, BagError> {
        Ok(name.parse::<StoragePreset>()?.storage_options())
    }

    /// These options with `compression` instead: rosbag2 applies the preset first and lets the storage
    /// configuration override it. Unchunked files have nowhere to put compression, so anything but `none`
    /// is an error there rather than silently ignored.
    pub fn with_compression(self, compression: ChunkCompression) -> Result<StorageOptions, BagError> {
        if self.layout == McapLayout::Unchunked && compression != ChunkCompression::None {
            return Err(BagError::Options(format!(
                "compression {compression} needs chunks, and unchunked MCAP (the fastwrite preset) has none: \
                 use compression none or another preset"
            )));
        }
        Ok(StorageOptions { compression, ..self })
    }

    /// The node's `record_storage_preset` and `record_compression` parameters together: the preset (empty =
    /// sweetspot's default, zstd level 1 chunks), then the compression if one is given (empty = the
    /// preset's).
    pub fn from_parameters(preset: &str, compression: &str) -> Result<StorageOptions, BagError> {
        let base = if preset.is_empty() { StorageOptions::default() } else { StorageOptions::preset(preset)? };
        if compression.is_empty() {
            return Ok(base);
        }
        base.with_compression(compression.parse()?)
    }
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
    /// The topic description of a generated message type: its ROS type name, full `ros2msg` schema and RIHS01
    /// type hash.
    pub fn of<M: sweetspot_msgs::RosMessage>(name: impl Into<String>, qos: RecordedQos) -> TopicInfo {
        TopicInfo {
            name: name.into(),
            type_name: M::TYPE_NAME.to_string(),
            schema_text: M::SCHEMA_TEXT.to_string(),
            type_hash: M::TYPE_HASH.to_string(),
            qos,
        }
    }
}
