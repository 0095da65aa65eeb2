//! The rosbag2 side of the format: `metadata.yaml`, the `rosbag2` MCAP metadata record and the
//! `offered_qos_profiles` text, written the way rosbag2 (Humble through Jazzy) reads them.
//!
//! Why metadata version 8: rosbag2 decodes QoS enums as integers for version <= 8 and as strings from 9
//! on, while Humble only ever decodes integers. Version 8 with integer enums is therefore the one form
//! both Humble and Jazzy (and `rosbags`, which accepts up to 9) read. Version 8 requires the
//! `type_description_hash`, `custom_data` and `ros_distro` keys, which we write: each topic's RIHS01 type hash
//! (also the `topic_type_hash` of its MCAP channel, as rosbag2_storage_mcap writes it) and [`ros_distro`], which
//! rosbag2 also keeps in the `rosbag2` MCAP metadata record (the same text).
//!
//! Reading is another matter: the metadata text and QoS profiles of bags other tools wrote (rosbag2, rosbags,
//! in their own key order and quoting, QoS enums as integers or as Jazzy's strings) are parsed as YAML with
//! [`sweetspot_model::yaml`] ([`parse_custom_data`], [`parse_ros_distro`], [`parse_offered_qos`]); only the emitter is
//! hand-written, for its exact layout.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use yaml_rust2::Yaml;

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

/// The body of a rosbag2 metadata text, parsed: the `rosbag2_bagfile_information` mapping of a
/// `metadata.yaml`, or the top-level mapping of a `rosbag2` MCAP record's `serialized_metadata` (rosbag2 writes
/// it without the wrapper; sweetspot's [`BagMetadata::to_yaml_body`] too). Any layout, quoting and key order
/// YAML allows; None if the text is not YAML or holds no mapping.
fn metadata_body(yaml: &str) -> Option<Yaml> {
    let doc = sweetspot_model::yaml::load(yaml).ok()?.into_iter().next()?;
    let body = match &doc["rosbag2_bagfile_information"] {
        Yaml::Hash(_) => doc["rosbag2_bagfile_information"].clone(),
        _ => doc,
    };
    body.as_hash().is_some().then_some(body)
}

/// A YAML scalar as the text rosbag2 means by it (`custom_data` and `ros_distro` are strings to rosbag2,
/// which yaml-cpp may write unquoted: `5`, `true`, `1.5`).
fn scalar_text(value: &Yaml) -> Option<String> {
    match value {
        Yaml::String(s) | Yaml::Real(s) => Some(s.clone()),
        Yaml::Integer(n) => Some(n.to_string()),
        Yaml::Boolean(b) => Some(b.to_string()),
        _ => None,
    }
}

/// Reads `custom_data` back from rosbag2 metadata text (the `rosbag2` record or `metadata.yaml`, whoever
/// wrote it); empty when there is none (`custom_data: ~`) or the text is not understood.
pub fn parse_custom_data(yaml: &str) -> std::collections::BTreeMap<String, String> {
    let Some(body) = metadata_body(yaml) else { return Default::default() };
    let Some(entries) = body["custom_data"].as_hash() else { return Default::default() };
    entries.iter().filter_map(|(key, value)| Some((scalar_text(key)?, scalar_text(value)?))).collect()
}

/// Reads `ros_distro` back from rosbag2 metadata text (`None` if absent or empty).
pub fn parse_ros_distro(yaml: &str) -> Option<String> {
    let distro = scalar_text(&metadata_body(yaml)?["ros_distro"])?;
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

/// Parses an `offered_qos_profiles` text (a YAML list of profiles, the first one counting) into a
/// [`RecordedQos`]: integer enums as rosbag2 writes them up to metadata version 8 (reliability RELIABLE=1,
/// durability TRANSIENT_LOCAL=1) or string enums as from version 9 (`reliable`, `transient_local`); a
/// missing depth is 1. Returns `None` if it is not understood (not YAML, no reliability or durability).
pub fn parse_offered_qos(text: &str) -> Option<RecordedQos> {
    let doc = sweetspot_model::yaml::load(text).ok()?.into_iter().next()?;
    let profile = match &doc {
        Yaml::Array(profiles) => profiles.first()?,
        _ => &doc,
    };
    let is = |key: &str, number: i64, name: &str| match &profile[key] {
        Yaml::Integer(n) => Some(*n == number),
        Yaml::String(s) => Some(s.eq_ignore_ascii_case(name) || s.trim() == number.to_string()),
        _ => None,
    };
    let depth = match &profile["depth"] {
        Yaml::Integer(n) => u32::try_from(*n).ok(),
        Yaml::String(s) => s.trim().parse().ok(),
        _ => None,
    };
    Some(RecordedQos {
        reliable: is("reliability", 1, "reliable")?,
        transient_local: is("durability", 1, "transient_local")?,
        depth: depth.unwrap_or(1),
    })
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
    fn custom_data_reads_back_whatever_it_holds() {
        let mut metadata = BagMetadata::default();
        for (key, value) in [("a: b", "c: d"), ("quote\"s", "new\nline"), ("é", "'single'"), ("n", "42"), ("e", "")] {
            metadata.custom_data.insert(key.to_string(), value.to_string());
        }
        assert_eq!(parse_custom_data(&metadata.to_metadata_yaml()), metadata.custom_data);
        assert_eq!(parse_custom_data(&metadata.to_yaml_body(0)), metadata.custom_data);
        metadata.custom_data.clear();
        assert!(parse_custom_data(&metadata.to_metadata_yaml()).is_empty(), "custom_data: ~");
        assert!(parse_custom_data("not: [yaml").is_empty());
    }

    #[test]
    fn qos_reads_in_any_yaml_form_and_refuses_what_it_cannot_tell() {
        let latched = RecordedQos { reliable: true, transient_local: true, depth: 1 };
        assert_eq!(parse_offered_qos(&offered_qos_profiles_yaml(&latched)), Some(latched));
        // Flow style, string enums in capitals, depth quoted: YAML all the same.
        let flow = "- {durability: TRANSIENT_LOCAL, reliability: best_effort, depth: '12'}";
        let want = RecordedQos { reliable: false, transient_local: true, depth: 12 };
        assert_eq!(parse_offered_qos(flow), Some(want));
        assert_eq!(parse_offered_qos("[]"), None, "no profile");
        assert_eq!(parse_offered_qos("- depth: 3"), None, "no reliability nor durability");
        assert_eq!(parse_offered_qos("- reliability: [1"), None, "not YAML");
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
