//! `bag recover`: rebuild files cut off by a crash (no summary/footer), keeping every complete chunk, or in
//! an unchunked file every complete message; a rebuilt file keeps its layout (chunked or unchunked).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use mcap::records::MessageHeader;

use super::info::metadata_of;
use super::reader::{bag_files, scan_file, FileScan};
use super::writer::LIBRARY;
use super::{BagError, McapLayout};

/// What recovery did to one file.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RecoveredFile {
    /// The file.
    pub path: PathBuf,
    /// Whether it needed rebuilding (false: it was complete and left untouched).
    pub rebuilt: bool,
    /// Messages kept.
    pub messages: u64,
    /// Complete chunks kept.
    pub chunks: u64,
    /// How the file holds its messages (None: it has none).
    pub layout: Option<McapLayout>,
    /// Bytes of cut-off tail dropped.
    pub dropped_tail_bytes: u64,
    /// Chunks dropped because they failed to decode.
    pub dropped_corrupt_chunks: u64,
    /// Where the original was kept (`<file>.broken`), if rebuilt.
    pub original_kept_as: Option<PathBuf>,
}

struct Kept {
    channel: u16,
    sequence: u32,
    log_time: u64,
    publish_time: u64,
    data: Vec<u8>,
}

/// Recovers a bag directory (every unfinished file, then `metadata.yaml`) or a single `.mcap` file.
/// `on_file` is called after each file (for progress).
pub fn recover(path: &Path, mut on_file: impl FnMut(&RecoveredFile)) -> Result<Vec<RecoveredFile>, BagError> {
    let is_dir = path.is_dir();
    let files = bag_files(path)?;
    let mut scans: Vec<FileScan> = Vec::new();
    let mut pending: Vec<(usize, Vec<Kept>)> = Vec::new();
    for file in &files {
        let mut kept = Vec::new();
        let scan = scan_file(file, |m| {
            kept.push(Kept {
                channel: m.channel_id,
                sequence: m.sequence,
                log_time: m.log_time_ns,
                publish_time: m.publish_time_ns,
                data: m.data.to_vec(),
            });
        })?;
        if !scan.complete {
            pending.push((scans.len(), kept));
        }
        scans.push(scan);
    }
    // The rosbag2 record of rebuilt files describes the bag as recovered.
    let metadata = metadata_of(&scans);
    let mut report = Vec::new();
    let mut pending = pending.into_iter().peekable();
    for (index, scan) in scans.iter().enumerate() {
        let rebuilt = pending.peek().is_some_and(|(i, _)| *i == index);
        let entry = if rebuilt {
            let (_, kept) = pending.next().ok_or_else(|| BagError::Format("internal: recovery queue".into()))?;
            let broken = with_suffix(&scan.path, ".broken");
            std::fs::rename(&scan.path, &broken).map_err(|source| BagError::Io { path: scan.path.clone(), source })?;
            rewrite(&scan.path, scan, &kept, &metadata.to_yaml_body(0))?;
            RecoveredFile {
                path: scan.path.clone(),
                rebuilt: true,
                messages: kept.len() as u64,
                chunks: scan.chunks,
                layout: scan.layout(),
                dropped_tail_bytes: scan.truncated_bytes,
                dropped_corrupt_chunks: scan.corrupt_chunks,
                original_kept_as: Some(broken),
            }
        } else {
            RecoveredFile {
                path: scan.path.clone(),
                rebuilt: false,
                messages: scan.message_count(),
                chunks: scan.chunks,
                layout: scan.layout(),
                dropped_tail_bytes: 0,
                dropped_corrupt_chunks: 0,
                original_kept_as: None,
            }
        };
        on_file(&entry);
        report.push(entry);
    }
    if is_dir {
        metadata.write_to_dir(path)?;
    }
    Ok(report)
}

fn with_suffix(path: &Path, suffix: &str) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(suffix);
    PathBuf::from(s)
}

fn rewrite(path: &Path, scan: &FileScan, kept: &[Kept], rosbag2_yaml: &str) -> Result<(), BagError> {
    let io = |source| BagError::Io { path: path.to_path_buf(), source };
    let mcap = |e: mcap::McapError| BagError::Mcap(format!("{}: {e}", path.display()));
    let file = File::create(path).map_err(io)?;
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
    for (&original_id, channel) in &scan.channels {
        let schema = writer
            .add_schema(&channel.topic.type_name, &channel.schema_encoding, channel.topic.schema_text.as_bytes())
            .map_err(mcap)?;
        let id = writer
            .add_channel(schema, &channel.topic.name, &channel.message_encoding, &channel.metadata)
            .map_err(mcap)?;
        by_original.insert(original_id, id);
    }
    for m in kept {
        let Some(&channel_id) = by_original.get(&m.channel) else { continue };
        let header =
            MessageHeader { channel_id, sequence: m.sequence, log_time: m.log_time, publish_time: m.publish_time };
        writer.write_to_known_channel(&header, &m.data).map_err(mcap)?;
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
