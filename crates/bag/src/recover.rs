//! `bag recover`: a repaired copy of a bag whose files were cut off by a crash (no summary/footer) or are
//! damaged, written beside it; the original is never renamed, rewritten or deleted.
//!
//! Every message the streaming reader can vouch for is kept (every intact chunk; in an unchunked file every
//! complete message), in file order, in a file of the same layout (chunked or unchunked) with a fresh summary.
//! What could not be kept is reported per file: the damaged places (file, chunk, offset) and the messages
//! lost. Files that are finished and undamaged are linked (or copied) into the copy unchanged. A bag
//! directory's copy always gets a metadata.yaml rebuilt from the MCAP files alone (a directory that lacks one
//! is repaired for that reason alone). A bag with nothing to repair gets no copy at all. Anything that is not a regular MCAP file is refused before anything
//! is written.

use std::collections::BTreeMap;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use mcap::records::MessageHeader;

use super::info::metadata_of;
use super::reader::{
    bag_listing, damage_summary, mcap_files_in_dir, open_mcap, scan_file, Damage, FileReader, FileScan,
};
use super::writer::LIBRARY;
use super::{BagError, McapLayout};

/// `custom_data` key of a recovered bag: where it was recovered from and what was lost.
pub const CUSTOM_DATA_RECOVERED: &str = "sweetspot/recovered_from";

/// What recovery did with one file.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RecoveredFile {
    /// The original file (never modified).
    pub path: PathBuf,
    /// Where its messages are in the copy (None when no copy was written).
    pub output: Option<PathBuf>,
    /// Whether it was rebuilt (false: finished and undamaged, linked or copied as it is, or nothing written).
    pub rebuilt: bool,
    /// Whether the original ended properly (summary and footer).
    pub complete: bool,
    /// Messages kept.
    pub messages: u64,
    /// Intact chunks kept.
    pub chunks: u64,
    /// How the file holds its messages (None: it has none).
    pub layout: Option<McapLayout>,
    /// Bytes of cut-off tail dropped.
    pub dropped_tail_bytes: u64,
    /// Chunks dropped because they failed their checks.
    pub dropped_corrupt_chunks: u64,
    /// Messages dropped, as far as the file's indexes tell.
    pub lost_messages: u64,
    /// Whether some of the damage has an unknown message count (`lost_messages` is then a lower bound).
    pub lost_messages_unknown: bool,
    /// Every damaged place found.
    pub damage: Vec<Damage>,
}

/// What recovery did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Recovery {
    /// The repaired copy (a file for a file, a bag directory for a directory), or None when nothing needed
    /// repair and nothing was written.
    pub output: Option<PathBuf>,
    /// Per file of the original, in order.
    pub files: Vec<RecoveredFile>,
    /// Files the original's metadata.yaml lists that are not there (the copy's metadata.yaml leaves them out).
    pub missing_files: Vec<PathBuf>,
}

/// Where the copy goes by default: `NAME.recovered.mcap` beside `NAME.mcap`, `DIR.recovered/` beside `DIR/`.
pub fn default_output(path: &Path) -> PathBuf {
    let is_dir = path.is_dir();
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "bag".to_string());
    let parent = path.parent().unwrap_or_else(|| Path::new(""));
    if is_dir {
        parent.join(format!("{name}.recovered"))
    } else {
        let stem = name.strip_suffix(".mcap").unwrap_or(&name);
        parent.join(format!("{stem}.recovered.mcap"))
    }
}

/// Recovers a bag directory or a single `.mcap` file into `output` (default [`default_output`]), which must
/// not exist. `on_file` is called after each file (progress).
pub fn recover(
    path: &Path,
    output: Option<&Path>,
    mut on_file: impl FnMut(&RecoveredFile),
) -> Result<Recovery, BagError> {
    let is_dir = path.is_dir();
    let listed = ListedFiles::of(path, is_dir)?;
    for file in &listed.files {
        open_mcap(file)?;
    }
    let scans: Vec<FileScan> = listed.files.iter().map(|f| scan_file(f, |_| {})).collect::<Result<_, _>>()?;
    // A directory without metadata.yaml (the disk filled up before it was written) gets a copy with one
    // rebuilt from the MCAP files alone, even when every file is intact.
    // So does one whose metadata.yaml lists files that are gone: the copy lists what is there.
    let metadata_missing = is_dir && (listed.metadata_unreadable || !listed.missing.is_empty());
    if !metadata_missing && !scans.iter().any(needs_repair) {
        let report: Vec<RecoveredFile> = scans.iter().map(|s| recovered_file(s, None, false)).collect();
        report.iter().for_each(&mut on_file);
        return Ok(Recovery { output: None, files: report, missing_files: listed.missing });
    }
    let output = create_output(path, output, is_dir)?;
    let mut metadata = metadata_of(&scans);
    metadata
        .custom_data
        .insert(CUSTOM_DATA_RECOVERED.to_string(), format!("{}: {}", path.display(), damage_summary(&scans)));
    if !is_dir {
        if let (Some(file), Some(name)) = (metadata.files.first_mut(), output.file_name()) {
            file.path = name.to_string_lossy().into_owned();
        }
    }
    let rosbag2_yaml = metadata.to_yaml_body(0);
    let mut report = Vec::new();
    for scan in &scans {
        let name = scan.path.file_name().map(PathBuf::from).unwrap_or_default();
        let target = if is_dir { output.join(&name) } else { output.clone() };
        let file = copy_file(scan, target, &rosbag2_yaml)?;
        on_file(&file);
        report.push(file);
    }
    if is_dir {
        metadata.write_to_dir(&output)?;
    }
    Ok(Recovery { output: Some(output), files: report, missing_files: listed.missing })
}

/// The files of the bag to recover.
struct ListedFiles {
    files: Vec<PathBuf>,
    /// Whether metadata.yaml is missing or broken (the files are then every .mcap of the directory).
    metadata_unreadable: bool,
    /// Files metadata.yaml lists that are not there.
    missing: Vec<PathBuf>,
}

impl ListedFiles {
    /// The files metadata.yaml lists when it is readable, else every .mcap of the directory: a bag whose
    /// metadata.yaml is missing or broken is what recovery is for.
    fn of(path: &Path, is_dir: bool) -> Result<ListedFiles, BagError> {
        let listed = match bag_listing(path) {
            Ok(listing) => {
                let missing = listing.files.iter().filter(|f| !f.present).map(|f| f.path.clone()).collect();
                ListedFiles { files: listing.present(), metadata_unreadable: false, missing }
            }
            Err(_) if is_dir => {
                ListedFiles { files: mcap_files_in_dir(path)?, metadata_unreadable: true, missing: Vec::new() }
            }
            Err(e) => return Err(e),
        };
        if listed.files.is_empty() {
            return Err(BagError::Format(format!("{}: no .mcap files to recover", path.display())));
        }
        Ok(listed)
    }
}

fn needs_repair(scan: &FileScan) -> bool {
    !scan.complete || scan.damaged()
}

fn recovered_file(s: &FileScan, output: Option<PathBuf>, rebuilt: bool) -> RecoveredFile {
    RecoveredFile {
        path: s.path.clone(),
        output,
        rebuilt,
        complete: s.complete,
        messages: s.message_count(),
        chunks: s.chunks,
        layout: s.layout(),
        dropped_tail_bytes: s.truncated_bytes,
        dropped_corrupt_chunks: s.corrupt_chunks,
        lost_messages: s.lost_messages().0,
        lost_messages_unknown: s.lost_messages().1,
        damage: s.damage.clone(),
    }
}

/// Where the copy of `path` goes (`output`, else [`default_output`]), refused when something is there; for a
/// directory the copy's directory, created.
fn create_output(path: &Path, output: Option<&Path>, is_dir: bool) -> Result<PathBuf, BagError> {
    let output = output.map(Path::to_path_buf).unwrap_or_else(|| default_output(path));
    if std::fs::symlink_metadata(&output).is_ok() {
        return Err(BagError::Format(format!(
            "{} already exists: recovery never overwrites anything (remove it or pass --output)",
            output.display()
        )));
    }
    if is_dir {
        std::fs::create_dir(&output).map_err(|source| BagError::Io { path: output.clone(), source })?;
    }
    Ok(output)
}

/// One file of the copy at `target`: rebuilt when it needs repair, else linked (or copied) as it is.
fn copy_file(scan: &FileScan, target: PathBuf, rosbag2_yaml: &str) -> Result<RecoveredFile, BagError> {
    let rebuilt = needs_repair(scan);
    if rebuilt {
        rewrite(&scan.path, &target, scan, rosbag2_yaml)?;
    } else if std::fs::hard_link(&scan.path, &target).is_err() {
        std::fs::copy(&scan.path, &target).map_err(|source| BagError::Io { path: target.clone(), source })?;
    }
    Ok(recovered_file(scan, Some(target), rebuilt))
}

/// Writes every message the reader vouches for from `original` into a new file `target`, streaming.
fn rewrite(original: &Path, target: &Path, scan: &FileScan, rosbag2_yaml: &str) -> Result<(), BagError> {
    let io = |source| BagError::Io { path: target.to_path_buf(), source };
    let mcap = |e: mcap::McapError| BagError::Mcap(format!("{}: {e}", target.display()));
    let file = std::fs::OpenOptions::new().write(true).create_new(true).open(target).map_err(io)?;
    let profile = if scan.profile.is_empty() { "ros2" } else { scan.profile.as_str() };
    let mut writer = mcap::WriteOptions::new()
        .profile(profile)
        .library(format!("{LIBRARY}; recovered from {}", scan.library))
        .compression(Some(mcap::Compression::Zstd))
        // An unchunked file stays unchunked: whoever chose fastwrite chose its layout.
        .use_chunks(scan.layout() != Some(McapLayout::Unchunked))
        .compression_threads(1)
        .disable_seeking(true)
        .create(BufWriter::new(file))
        .map_err(mcap)?;
    let mut by_original: BTreeMap<u16, u16> = BTreeMap::new();
    let mut reader = FileReader::open(original)?;
    while reader.advance()? {
        let Some(m) = reader.message() else { continue };
        let channel_id = match by_original.get(&m.channel_id) {
            Some(&id) => id,
            None => {
                let channel = m.channel;
                let schema = writer
                    .add_schema(
                        &channel.topic.type_name,
                        &channel.schema_encoding,
                        channel.topic.schema_text.as_bytes(),
                    )
                    .map_err(mcap)?;
                let id = writer
                    .add_channel(schema, &channel.topic.name, &channel.message_encoding, &channel.metadata)
                    .map_err(mcap)?;
                by_original.insert(m.channel_id, id);
                id
            }
        };
        let header = MessageHeader {
            channel_id,
            sequence: m.sequence,
            log_time: m.log_time_ns,
            publish_time: m.publish_time_ns,
        };
        writer.write_to_known_channel(&header, m.data).map_err(mcap)?;
    }
    // Channels without a surviving message are kept too: a reader still sees every topic of the recording.
    let read = reader.finish()?;
    for (original_id, channel) in &read.channels {
        if by_original.contains_key(original_id) {
            continue;
        }
        let schema = writer
            .add_schema(&channel.topic.type_name, &channel.schema_encoding, channel.topic.schema_text.as_bytes())
            .map_err(mcap)?;
        writer.add_channel(schema, &channel.topic.name, &channel.message_encoding, &channel.metadata).map_err(mcap)?;
    }
    let record = mcap::records::Metadata {
        name: "rosbag2".to_string(),
        metadata: BTreeMap::from([("serialized_metadata".to_string(), rosbag2_yaml.to_string())]),
    };
    writer.write_metadata(&record).map_err(mcap)?;
    writer.finish().map_err(mcap)?;
    let mut inner = writer.into_inner();
    inner.flush().map_err(io)?;
    inner.get_ref().sync_all().map_err(io)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_complete_bag_without_metadata_yaml_gets_a_copy_with_one_rebuilt() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("bag");
        let recorder = crate::Recorder::start(crate::RecorderConfig::new(&dir)).unwrap();
        let topic = crate::TopicInfo {
            name: "/swing".to_string(),
            type_name: "sweetspot_msgs/msg/Swing".to_string(),
            schema_text: "uint64 swing_id\n".to_string(),
            type_hash: String::new(),
            qos: crate::RecordedQos { reliable: true, transient_local: false, depth: 1000 },
        };
        let id = recorder.register_topic(topic).unwrap();
        for i in 0..25u64 {
            assert!(recorder.record(id, vec![0, 1, 0, 0, i as u8], 1_000 + i, 1_000 + i));
        }
        recorder.finish().unwrap();
        let original = std::fs::read_to_string(dir.join("metadata.yaml")).unwrap();
        assert!(recover(&dir, None, |_| {}).unwrap().output.is_none(), "a complete bag needs no copy");

        std::fs::remove_file(dir.join("metadata.yaml")).unwrap();
        let recovery = recover(&dir, None, |_| {}).unwrap();
        let out = recovery.output.expect("a copy for the missing metadata.yaml");
        assert!(recovery.files.iter().all(|f| !f.rebuilt && f.complete), "intact files are linked, not rebuilt");
        let rebuilt = std::fs::read_to_string(out.join("metadata.yaml")).unwrap();
        // The same counts, times and topics as the recorder's own, from the MCAP alone.
        let body = |yaml: &str| -> Vec<String> {
            yaml.lines()
                .filter(|l| !l.contains("custom_data") && !l.contains(CUSTOM_DATA_RECOVERED))
                .map(String::from)
                .collect()
        };
        assert_eq!(body(&rebuilt), body(&original));
        assert!(!dir.join("metadata.yaml").exists(), "the original is left as it is");
    }

    #[test]
    fn the_copy_goes_beside_the_original() {
        assert_eq!(default_output(Path::new("/x/run_0.mcap")), PathBuf::from("/x/run_0.recovered.mcap"));
        assert_eq!(default_output(Path::new("/x/notes")), PathBuf::from("/x/notes.recovered.mcap"));
    }
}
