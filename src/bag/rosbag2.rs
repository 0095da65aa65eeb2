//! The rosbag2 side of the format: `metadata.yaml`, the `rosbag2` MCAP metadata record and the
//! `offered_qos_profiles` text, written the way rosbag2 (Humble through Jazzy) reads them.
//!
//! Why metadata version 8: rosbag2 decodes QoS enums as integers for version <= 8 and as strings from 9
//! on, while Humble only ever decodes integers. Version 8 with integer enums is therefore the one form
//! both Humble and Jazzy (and `rosbags`, which accepts up to 9) read. Version 8 requires the
//! `type_description_hash`, `custom_data` and `ros_distro` keys, which we write: each topic's RIHS01 type hash
//! (also the `topic_type_hash` of its MCAP channel, as rosbag2_storage_mcap writes it) and [`ros_distro`], which
//! rosbag2 also keeps in the `rosbag2` MCAP metadata record (the same text).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{RecordedQos, TopicInfo};

/// The rosbag2 metadata version written (see the module docs for why 8).
pub const METADATA_VERSION: u32 = 8;

/// The ROS distribution written when `$ROS_DISTRO` is not set: the type hashes in the bags are RIHS01, which
/// ROS 2 uses from Iron on, computed from the Jazzy interface definitions.
pub const DEFAULT_ROS_DISTRO: &str = "jazzy";

/// The `ros_distro` of new bags: `$ROS_DISTRO` as rosbag2 takes it (a sourced ROS 2 sets it), else
/// [`DEFAULT_ROS_DISTRO`] — sweetspot needs no ROS installation, and rosbag2 would leave it empty, which tools
/// show as "unknown" although the bag's type hashes are Jazzy's.
pub fn ros_distro() -> String {
    match std::env::var("ROS_DISTRO") {
        Ok(distro) if !distro.trim().is_empty() => distro.trim().to_string(),
        _ => DEFAULT_ROS_DISTRO.to_string(),
    }
}

/// rosbag2's "infinite" duration (RMW_DURATION_INFINITE) as `sec`/`nsec`.
const INFINITE_SEC: u64 = 9_223_372_036;
const INFINITE_NSEC: u64 = 854_775_807;

/// One closed or open file of a bag, as listed under `files:`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FileEntry {
    /// File name relative to the bag directory, e.g. `run_0.mcap`.
    pub path: String,
    /// Earliest log time in the file, ns since the Unix epoch (0 if empty).
    pub start_ns: u64,
    /// Latest minus earliest log time, ns.
    pub duration_ns: u64,
    /// Messages in the file.
    pub message_count: u64,
}

/// Everything rosbag2 keeps about a bag (the body of `rosbag2_bagfile_information`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BagMetadata {
    /// Topics in registration order with their message counts.
    pub topics: Vec<(TopicInfo, u64)>,
    /// The files in order.
    pub files: Vec<FileEntry>,
    /// `compression_format` (empty: MCAP chunk compression is internal to the file, as rosbag2 writes it).
    pub compression_format: String,
    /// ROS distribution name: [`ros_distro`] when recording.
    pub ros_distro: String,
    /// rosbag2's free-form `custom_data` (string → string), e.g. the node settings a replay needs.
    pub custom_data: std::collections::BTreeMap<String, String>,
}

impl BagMetadata {
    /// Earliest log time over all files, ns (0 for an empty bag).
    pub fn start_ns(&self) -> u64 {
        self.files.iter().filter(|f| f.message_count > 0).map(|f| f.start_ns).min().unwrap_or(0)
    }

    /// Latest log time over all files, ns.
    pub fn end_ns(&self) -> u64 {
        self.files.iter().filter(|f| f.message_count > 0).map(|f| f.start_ns + f.duration_ns).max().unwrap_or(0)
    }

    /// Total message count.
    pub fn message_count(&self) -> u64 {
        self.files.iter().map(|f| f.message_count).sum()
    }

    /// The mapping body (no `rosbag2_bagfile_information:` wrapper), indented by `indent` spaces.
    /// This exact text is also what goes into the `rosbag2` MCAP metadata record.
    pub fn to_yaml_body(&self, indent: usize) -> String {
        let pad = " ".repeat(indent);
        let mut out = String::new();
        let start = self.start_ns();
        let duration = self.end_ns().saturating_sub(start);
        // `write!` into a String cannot fail; the results are ignored deliberately.
        let _ = writeln!(out, "{pad}version: {METADATA_VERSION}");
        let _ = writeln!(out, "{pad}storage_identifier: mcap");
        let _ = writeln!(out, "{pad}duration:\n{pad}  nanoseconds: {duration}");
        let _ = writeln!(out, "{pad}starting_time:\n{pad}  nanoseconds_since_epoch: {start}");
        let _ = writeln!(out, "{pad}message_count: {}", self.message_count());
        if self.topics.is_empty() {
            let _ = writeln!(out, "{pad}topics_with_message_count: []");
        } else {
            let _ = writeln!(out, "{pad}topics_with_message_count:");
            for (topic, count) in &self.topics {
                let _ = writeln!(out, "{pad}  - topic_metadata:");
                let _ = writeln!(out, "{pad}      name: {}", yaml_string(&topic.name));
                let _ = writeln!(out, "{pad}      type: {}", yaml_string(&topic.type_name));
                let _ = writeln!(out, "{pad}      serialization_format: cdr");
                let _ = writeln!(
                    out,
                    "{pad}      offered_qos_profiles: {}",
                    yaml_string(&offered_qos_profiles_yaml(&topic.qos))
                );
                let _ = writeln!(out, "{pad}      type_description_hash: {}", yaml_string(&topic.type_hash));
                let _ = writeln!(out, "{pad}    message_count: {count}");
            }
        }
        let _ = writeln!(out, "{pad}compression_format: {}", yaml_string(&self.compression_format));
        let _ = writeln!(out, "{pad}compression_mode: \"\"");
        if self.files.is_empty() {
            let _ = writeln!(out, "{pad}relative_file_paths: []\n{pad}files: []");
        } else {
            let _ = writeln!(out, "{pad}relative_file_paths:");
            for file in &self.files {
                let _ = writeln!(out, "{pad}  - {}", yaml_string(&file.path));
            }
            let _ = writeln!(out, "{pad}files:");
            for file in &self.files {
                let _ = writeln!(out, "{pad}  - path: {}", yaml_string(&file.path));
                let _ = writeln!(out, "{pad}    starting_time:\n{pad}      nanoseconds_since_epoch: {}", file.start_ns);
                let _ = writeln!(out, "{pad}    duration:\n{pad}      nanoseconds: {}", file.duration_ns);
                let _ = writeln!(out, "{pad}    message_count: {}", file.message_count);
            }
        }
        if self.custom_data.is_empty() {
            let _ = writeln!(out, "{pad}custom_data: ~");
        } else {
            let _ = writeln!(out, "{pad}custom_data:");
            for (key, value) in &self.custom_data {
                let _ = writeln!(out, "{pad}  {}: {}", yaml_string(key), yaml_string(value));
            }
        }
        let _ = writeln!(out, "{pad}ros_distro: {}", yaml_string(&self.ros_distro));
        out
    }

    /// The whole `metadata.yaml` text.
    pub fn to_metadata_yaml(&self) -> String {
        format!("rosbag2_bagfile_information:\n{}", self.to_yaml_body(2))
    }

    /// Writes `metadata.yaml` into `dir` atomically (temp file + rename), so a crash never leaves half a file.
    pub fn write_to_dir(&self, dir: &Path) -> Result<(), super::BagError> {
        let path = dir.join("metadata.yaml");
        let tmp = dir.join(".metadata.yaml.tmp");
        let written = std::fs::write(&tmp, self.to_metadata_yaml())
            .map_err(|source| super::BagError::Io { path: tmp.clone(), source })
            .and_then(|()| std::fs::rename(&tmp, &path).map_err(|source| super::BagError::Io { path, source }));
        if written.is_err() {
            // On a full disk the previous metadata.yaml stays as it was; no half-written temp file beside it.
            let _ = std::fs::remove_file(&tmp);
        }
        written
    }
}

/// Reads `custom_data` back from metadata text written by [`BagMetadata::to_yaml_body`] (the `rosbag2`
/// record or `metadata.yaml`). Only this writer's own layout (double-quoted keys and values) is understood.
pub fn parse_custom_data(yaml: &str) -> std::collections::BTreeMap<String, String> {
    let mut out = std::collections::BTreeMap::new();
    let mut lines = yaml.lines().skip_while(|l| l.trim_start() != "custom_data:");
    let Some(first) = lines.next() else { return out };
    let indent = first.len() - first.trim_start().len();
    for line in lines {
        let depth = line.len() - line.trim_start().len();
        if depth <= indent {
            break;
        }
        let entry = line.trim();
        // `"key": "value"`: the key is a JSON string, so parse it to find where it ends.
        let mut stream = serde_json::Deserializer::from_str(entry).into_iter::<String>();
        let Some(Ok(key)) = stream.next() else { continue };
        let rest = entry[stream.byte_offset()..].trim_start();
        if let Some(value) = rest.strip_prefix(':') {
            if let Ok(value) = serde_json::from_str::<String>(value.trim()) {
                out.insert(key, value);
            }
        }
    }
    out
}

/// Reads `ros_distro` back from metadata text written by [`BagMetadata::to_yaml_body`] (`None` if absent or
/// empty).
pub fn parse_ros_distro(yaml: &str) -> Option<String> {
    let value = yaml.lines().find_map(|l| l.trim_start().strip_prefix("ros_distro:"))?.trim();
    let distro = serde_json::from_str::<String>(value).unwrap_or_else(|_| value.to_string());
    (!distro.is_empty()).then_some(distro)
}

/// The `offered_qos_profiles` text of a topic: a YAML list with one profile, integer enums (rmw values:
/// history KEEP_LAST=1, reliability RELIABLE=1/BEST_EFFORT=2, durability TRANSIENT_LOCAL=1/VOLATILE=2,
/// liveliness AUTOMATIC=1) and infinite durations, exactly the keys rosbag2 writes.
pub fn offered_qos_profiles_yaml(qos: &RecordedQos) -> String {
    let reliability = if qos.reliable { 1 } else { 2 };
    let durability = if qos.transient_local { 1 } else { 2 };
    let inf = format!("\n    sec: {INFINITE_SEC}\n    nsec: {INFINITE_NSEC}");
    format!(
        "- history: 1\n  depth: {depth}\n  reliability: {reliability}\n  durability: {durability}\n  \
         deadline:{inf}\n  lifespan:{inf}\n  liveliness: 1\n  liveliness_lease_duration:{inf}\n  \
         avoid_ros_namespace_conventions: false",
        depth = qos.depth
    )
}

/// Parses the integer-enum or string-enum `offered_qos_profiles` text back into a [`RecordedQos`]
/// (first profile). Returns `None` if it is not understood.
pub fn parse_offered_qos(text: &str) -> Option<RecordedQos> {
    let mut reliable = None;
    let mut transient_local = None;
    let mut depth = None;
    for line in text.lines() {
        let line = line.trim_start_matches(['-', ' ']);
        if let Some((key, value)) = line.split_once(':') {
            let value = value.trim().trim_matches('"').to_ascii_lowercase();
            match key.trim() {
                "reliability" => reliable = Some(value == "1" || value == "reliable"),
                "durability" => transient_local = Some(value == "1" || value == "transient_local"),
                "depth" => depth = value.parse().ok(),
                _ => {}
            }
            if reliable.is_some() && transient_local.is_some() && depth.is_some() {
                break;
            }
        }
    }
    Some(RecordedQos { reliable: reliable?, transient_local: transient_local?, depth: depth.unwrap_or(1) })
}

/// A YAML double-quoted scalar (JSON string syntax is a subset of YAML's double-quoted style).
pub fn yaml_string(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".to_string())
}

/// The default bag directory `<root>/<node>_<UTC YYYY_MM_DD-HH_MM_SS>` (rosbag2's own timestamp style).
pub fn default_bag_dir(root: &Path, node_name: &str, now: std::time::SystemTime) -> PathBuf {
    let utc: chrono::DateTime<chrono::Utc> = now.into();
    let safe: String = node_name
        .trim_start_matches('/')
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '_' || c == '-' { c } else { '_' })
        .collect();
    root.join(format!("{}_{}", if safe.is_empty() { "sweetspot" } else { &safe }, utc.format("%Y_%m_%d-%H_%M_%S")))
}

/// Candidate `attempt` (1, 2, …) for a bag directory named `base`: `base` itself first, then `base_2`,
/// `base_3`, … — so bags started within the same second (two nodes of one name) never share a directory.
pub fn numbered_bag_dir(base: &Path, attempt: u32) -> PathBuf {
    if attempt <= 1 {
        return base.to_path_buf();
    }
    let mut name = base.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    name.push(format!("_{attempt}"));
    base.with_file_name(name)
}

/// The name of split file `index` of the bag in `dir`: `<dirname>_<index>.mcap`.
pub fn file_name(dir: &Path, index: usize) -> String {
    let base = dir.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "bag".to_string());
    format!("{base}_{index}.mcap")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ros_distro_reads_back_from_the_metadata_text() {
        let mut metadata = BagMetadata { ros_distro: "humble".to_string(), ..Default::default() };
        assert_eq!(parse_ros_distro(&metadata.to_yaml_body(0)).as_deref(), Some("humble"));
        assert_eq!(parse_ros_distro(&metadata.to_metadata_yaml()).as_deref(), Some("humble"));
        metadata.ros_distro.clear();
        assert_eq!(parse_ros_distro(&metadata.to_yaml_body(0)), None, "rosbag2 writes an empty one without ROS");
    }

    #[test]
    fn numbered_bag_dirs_keep_the_base_first_then_add_a_suffix() {
        let base = Path::new("bags/sweetspot_2026_11_24-08_00_00");
        assert_eq!(numbered_bag_dir(base, 1), base);
        assert_eq!(numbered_bag_dir(base, 2), Path::new("bags/sweetspot_2026_11_24-08_00_00_2"));
        assert_eq!(numbered_bag_dir(base, 13), Path::new("bags/sweetspot_2026_11_24-08_00_00_13"));
        // The split files of a suffixed bag still end in their own index.
        assert_eq!(file_name(&numbered_bag_dir(base, 2), 0), "sweetspot_2026_11_24-08_00_00_2_0.mcap");
    }
}
