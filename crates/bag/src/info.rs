//! `bag info`: what is in a bag, from a full scan of its files (works on unfinished files too).

use std::path::Path;

use serde::Serialize;

use super::reader::{read_bag, Damage, FileScan};
use super::rosbag2::{BagMetadata, FileEntry};
use super::{BagError, McapLayout, TopicInfo};

/// One topic of a bag.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TopicSummary {
    /// Topic name.
    pub name: String,
    /// ROS type.
    pub type_name: String,
    /// RIHS01 type description hash from the channel metadata (empty if the bag has none).
    pub type_hash: String,
    /// Messages.
    pub count: u64,
    /// Serialization format: the channel's MCAP message encoding as the file has it (`cdr` for ROS 2).
    pub serialization_format: String,
    /// Offered QoS: reliable?
    pub reliable: bool,
    /// Offered QoS: transient local?
    pub transient_local: bool,
    /// Offered QoS: KEEP_LAST depth.
    pub depth: u32,
}

/// One file of a bag.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FileSummary {
    /// File name.
    pub path: String,
    /// Size, bytes.
    pub size: u64,
    /// Messages.
    pub messages: u64,
    /// Complete chunks.
    pub chunks: u64,
    /// `chunked`, `unchunked` (messages outside chunks, no indexes: rosbag2's fastwrite), or null when the
    /// file holds no message.
    pub layout: Option<McapLayout>,
    /// Has summary + footer (false: cut off, run `sweetspot bag recover`).
    pub complete: bool,
    /// Bytes after the last complete record.
    pub truncated_bytes: u64,
    /// Chunks skipped because they failed their checks.
    pub corrupt_chunks: u64,
    /// Messages the file's statistics say it holds (finished files with an intact summary), else null.
    pub expected_messages: Option<u64>,
    /// Messages lost to damage, as far as the file's indexes tell.
    pub lost_messages: u64,
    /// Whether some damage has an unknown message count (lost_messages is then a lower bound).
    pub lost_messages_unknown: bool,
    /// Every damaged place: offset, chunk index, kind, messages lost.
    pub damage: Vec<Damage>,
}

/// Everything `bag info` prints.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BagInfo {
    /// The files in order.
    pub files: Vec<FileSummary>,
    /// Total size, bytes.
    pub size: u64,
    /// Storage identifier (`mcap`).
    pub storage_identifier: String,
    /// MCAP profile of the first file.
    pub profile: String,
    /// MCAP library of the first file.
    pub library: String,
    /// Chunk compression(s) in use.
    pub compression: Vec<String>,
    /// Layouts of the files holding messages (`chunked`, `unchunked`), first-seen order.
    pub layout: Vec<McapLayout>,
    /// Earliest log time, ns since the Unix epoch.
    pub start_ns: u64,
    /// Latest log time, ns since the Unix epoch.
    pub end_ns: u64,
    /// end - start, ns.
    pub duration_ns: u64,
    /// Messages.
    pub messages: u64,
    /// Topics in first-seen order.
    pub topics: Vec<TopicSummary>,
    /// Attachment records, over all files.
    pub attachments: u64,
    /// Metadata records, over all files (rosbag2's own `rosbag2` record included).
    pub metadata: u64,
    /// Whether any file is damaged (see each file's `damage`).
    pub damaged: bool,
}

impl BagInfo {
    /// Whether every file ended properly.
    pub fn complete(&self) -> bool {
        self.files.iter().all(|f| f.complete)
    }
}

/// Topics (first-seen order) with their counts, merged over files by name.
pub fn topics_of(scans: &[FileScan]) -> Vec<(TopicInfo, u64)> {
    let mut topics: Vec<(TopicInfo, u64)> = Vec::new();
    for scan in scans {
        for (id, channel) in &scan.channels {
            let count = scan.counts.get(id).copied().unwrap_or(0);
            match topics.iter_mut().find(|(t, _)| t.name == channel.topic.name) {
                Some((_, c)) => *c += count,
                None => topics.push((channel.topic.clone(), count)),
            }
        }
    }
    topics
}

/// rosbag2 metadata describing the scanned files.
pub fn metadata_of(scans: &[FileScan]) -> BagMetadata {
    BagMetadata {
        topics: topics_of(scans),
        files: scans
            .iter()
            .map(|s| {
                let (start, end) = s.time_range.unwrap_or((0, 0));
                FileEntry {
                    path: s.path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
                    start_ns: start,
                    duration_ns: end - start,
                    message_count: s.message_count(),
                }
            })
            .collect(),
        compression_format: String::new(),
        ros_distro: ros_distro_of(scans),
        custom_data: custom_data_of(scans),
    }
}

/// The `ros_distro` of the last `rosbag2` record found in the files, else this machine's (see
/// [`super::rosbag2::ros_distro`]).
pub fn ros_distro_of(scans: &[FileScan]) -> String {
    scans
        .iter()
        .rev()
        .find_map(|s| s.rosbag2_metadata.as_deref())
        .and_then(super::rosbag2::parse_ros_distro)
        .unwrap_or_else(super::rosbag2::ros_distro)
}

/// The `custom_data` of the last `rosbag2` record found in the files (the most complete one).
pub fn custom_data_of(scans: &[FileScan]) -> std::collections::BTreeMap<String, String> {
    scans
        .iter()
        .rev()
        .find_map(|s| s.rosbag2_metadata.as_deref())
        .map(super::rosbag2::parse_custom_data)
        .unwrap_or_default()
}

/// Scans a bag (directory or single `.mcap`) and summarizes it.
pub fn bag_info(path: &Path) -> Result<BagInfo, BagError> {
    let scans = read_bag(path, |_| {})?;
    Ok(info_of(&scans))
}

/// Summarizes already scanned files.
pub fn info_of(scans: &[FileScan]) -> BagInfo {
    let start = scans.iter().filter_map(|s| s.time_range).map(|r| r.0).min().unwrap_or(0);
    let end = scans.iter().filter_map(|s| s.time_range).map(|r| r.1).max().unwrap_or(0);
    let mut compression: Vec<String> = Vec::new();
    for s in scans {
        for c in &s.compressions {
            if !compression.contains(c) {
                compression.push(c.clone());
            }
        }
    }
    BagInfo {
        files: scans
            .iter()
            .map(|s| FileSummary {
                path: s.path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
                size: s.size,
                messages: s.message_count(),
                chunks: s.chunks,
                layout: s.layout(),
                complete: s.complete,
                truncated_bytes: s.truncated_bytes,
                corrupt_chunks: s.corrupt_chunks,
                expected_messages: s.expected_messages,
                lost_messages: s.lost_messages().0,
                lost_messages_unknown: s.lost_messages().1,
                damage: s.damage.clone(),
            })
            .collect(),
        size: scans.iter().map(|s| s.size).sum(),
        storage_identifier: "mcap".to_string(),
        profile: scans.iter().find(|s| s.size > 0).map(|s| s.profile.clone()).unwrap_or_default(),
        library: scans.iter().find(|s| s.size > 0).map(|s| s.library.clone()).unwrap_or_default(),
        compression,
        layout: {
            let mut layouts = Vec::new();
            for layout in scans.iter().filter_map(FileScan::layout) {
                if !layouts.contains(&layout) {
                    layouts.push(layout);
                }
            }
            layouts
        },
        start_ns: start,
        end_ns: end,
        duration_ns: end - start,
        messages: scans.iter().map(|s| s.message_count()).sum(),
        topics: topics_of(scans)
            .into_iter()
            .map(|(t, count)| TopicSummary {
                serialization_format: message_encoding_of(scans, &t.name),
                name: t.name,
                type_name: t.type_name,
                type_hash: t.type_hash,
                count,
                reliable: t.qos.reliable,
                transient_local: t.qos.transient_local,
                depth: t.qos.depth,
            })
            .collect(),
        attachments: scans.iter().map(|s| s.attachments).sum(),
        metadata: scans.iter().map(|s| s.metadata).sum(),
        damaged: scans.iter().any(FileScan::damaged),
    }
}

/// The message encoding of the first channel named `topic` (what the file says, e.g. `cdr`, `json`).
fn message_encoding_of(scans: &[FileScan], topic: &str) -> String {
    scans
        .iter()
        .flat_map(|s| s.channels.values())
        .find(|c| c.topic.name == topic)
        .map(|c| c.message_encoding.clone())
        .unwrap_or_default()
}

fn human_size(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["B", "KiB", "MiB", "GiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit < UNITS.len() - 1 {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

fn stamp(ns: u64) -> String {
    let secs = (ns / 1_000_000_000) as i64;
    let nanos = (ns % 1_000_000_000) as u32;
    let when = chrono::DateTime::from_timestamp(secs, nanos)
        .map(|t| t.format("%b %e %Y %H:%M:%S%.9f UTC").to_string())
        .unwrap_or_default();
    format!("{when} ({secs}.{nanos:09})")
}

impl std::fmt::Display for BagInfo {
    /// The layout of `ros2 bag info`, plus compression and completeness.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let files: Vec<&str> = self.files.iter().map(|x| x.path.as_str()).collect();
        writeln!(f, "Files:             {}", files.join("\n                   "))?;
        writeln!(f, "Bag size:          {}", human_size(self.size))?;
        writeln!(f, "Storage id:        {}", self.storage_identifier)?;
        writeln!(f, "Profile / library: {} / {}", self.profile, self.library)?;
        let compression =
            if self.compression.is_empty() { "none".to_string() } else { self.compression.join(", ") + " (chunks)" };
        writeln!(f, "Compression:       {compression}")?;
        let chunks: u64 = self.files.iter().map(|x| x.chunks).sum();
        let layout = match self.layout.as_slice() {
            [] => "no messages".to_string(),
            [McapLayout::Unchunked] => "none (unchunked: messages outside chunks, no message indexes)".to_string(),
            [McapLayout::Chunked] => format!("{chunks}"),
            _ => format!("{chunks} (some files unchunked)"),
        };
        writeln!(f, "Chunks:            {layout}")?;
        writeln!(
            f,
            "Duration:          {}.{:09}s",
            self.duration_ns / 1_000_000_000,
            self.duration_ns % 1_000_000_000
        )?;
        writeln!(f, "Start:             {}", stamp(self.start_ns))?;
        writeln!(f, "End:               {}", stamp(self.end_ns))?;
        writeln!(f, "Messages:          {}", self.messages)?;
        if self.attachments > 0 || self.metadata > 0 {
            writeln!(f, "Attachments:       {}", self.attachments)?;
            writeln!(f, "Metadata records:  {}", self.metadata)?;
        }
        let width = self.topics.iter().map(|t| t.name.len()).max().unwrap_or(0);
        for (i, t) in self.topics.iter().enumerate() {
            let label = if i == 0 { "Topic information: " } else { "                   " };
            let hash = if t.type_hash.is_empty() { String::new() } else { format!(" | Type Hash: {}", t.type_hash) };
            writeln!(
                f,
                "{label}Topic: {:width$} | Type: {} | Count: {} | Serialization Format: {} | QoS: {}, {}, depth \
                 {}{hash}",
                t.name,
                t.type_name,
                t.count,
                t.serialization_format,
                if t.reliable { "reliable" } else { "best_effort" },
                if t.transient_local { "transient_local" } else { "volatile" },
                t.depth
            )?;
        }
        for file in &self.files {
            for damage in &file.damage {
                writeln!(f, "DAMAGED: {damage}")?;
            }
            let missing = file.damage.iter().any(|d| d.kind == super::reader::DamageKind::MissingFile);
            if file.damage.is_empty() && file.complete || missing {
                continue;
            }
            let lost = match (file.lost_messages, file.lost_messages_unknown) {
                (0, false) => "no message lost".to_string(),
                (n, false) => format!("{n} messages lost"),
                (n, true) => format!("at least {n} messages lost"),
            };
            let state = if file.complete { "finished, damaged" } else { "unfinished (no summary)" };
            let expected =
                file.expected_messages.map(|n| format!(" of the {n} its statistics list")).unwrap_or_default();
            writeln!(
                f,
                "WARNING: {} is {state}: {} messages read{expected}, {lost}, {} bytes cut off, {} chunks skipped — \
                 `sweetspot bag recover` writes a repaired copy beside it",
                file.path, file.messages, file.truncated_bytes, file.corrupt_chunks
            )?;
        }
        Ok(())
    }
}
