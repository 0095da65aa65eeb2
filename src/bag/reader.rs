//! Reading bags back: a lenient linear scan that keeps every complete chunk (and, in unchunked files, every
//! complete top-level message), so finished files and files cut off by a crash (no summary, no footer) are
//! read the same way.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use mcap::records::Record;
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::rosbag2::parse_offered_qos;
use super::{BagError, McapLayout, RecordedQos, TopicInfo};

/// Largest uncompressed chunk the reader accepts (sweetspot writes chunks of a few MiB at most).
const MAX_CHUNK_UNCOMPRESSED_SIZE: u64 = 256 * 1024 * 1024;

/// A channel as found in a file, with its topic description.
#[derive(Debug, Clone, PartialEq)]
pub struct ChannelInfo {
    /// The topic (name, type, schema text, QoS parsed from `offered_qos_profiles`).
    pub topic: TopicInfo,
    /// MCAP schema encoding (`ros2msg` for our bags).
    pub schema_encoding: String,
    /// MCAP message encoding (`cdr`).
    pub message_encoding: String,
    /// Raw channel metadata.
    pub metadata: BTreeMap<String, String>,
}

/// One message read from a bag.
#[derive(Debug, Clone, Copy)]
pub struct MessageRef<'a> {
    /// Its channel.
    pub channel: &'a ChannelInfo,
    /// The MCAP channel id in this file.
    pub channel_id: u16,
    /// Per-channel sequence number.
    pub sequence: u32,
    /// Log (receive/publish) time, ns since the Unix epoch.
    pub log_time_ns: u64,
    /// Publish time (header stamp), ns since the Unix epoch.
    pub publish_time_ns: u64,
    /// CDR bytes with the encapsulation header.
    pub data: &'a [u8],
}

/// What a scan of one file found.
#[derive(Debug, Clone, Default)]
pub struct FileScan {
    /// The file.
    pub path: PathBuf,
    /// Its size, bytes.
    pub size: u64,
    /// MCAP profile from the header.
    pub profile: String,
    /// MCAP library from the header.
    pub library: String,
    /// Channels by MCAP id.
    pub channels: BTreeMap<u16, ChannelInfo>,
    /// Messages read, per channel id.
    pub counts: BTreeMap<u16, u64>,
    /// Complete chunks read.
    pub chunks: u64,
    /// Messages read from top-level Message records, outside any chunk (unchunked files).
    pub unchunked_messages: u64,
    /// Chunk compressions seen (e.g. `zstd`).
    pub compressions: Vec<String>,
    /// Whether the file ended properly (data end, summary, footer, magic).
    pub complete: bool,
    /// Chunks that were complete on disk but failed to decode (CRC or decompression), skipped.
    pub corrupt_chunks: u64,
    /// Bytes at the end that did not form a complete record (cut off by a crash).
    pub truncated_bytes: u64,
    /// Earliest and latest log time, ns.
    pub time_range: Option<(u64, u64)>,
    /// The last `rosbag2` metadata record's `serialized_metadata`, if any.
    pub rosbag2_metadata: Option<String>,
}

impl FileScan {
    /// Total messages read.
    pub fn message_count(&self) -> u64 {
        self.counts.values().sum()
    }

    /// How the file holds its messages: chunked if it has any chunk, unchunked if it has messages outside
    /// chunks only, None if it has no message (yet) to tell by.
    pub fn layout(&self) -> Option<McapLayout> {
        if self.chunks > 0 || self.corrupt_chunks > 0 {
            Some(McapLayout::Chunked)
        } else if self.unchunked_messages > 0 {
            Some(McapLayout::Unchunked)
        } else {
            None
        }
    }
}

/// The MCAP files of a bag: the `*.mcap` of a directory in split order (`_0`, `_1`, …), or the file itself.
pub fn bag_files(path: &Path) -> Result<Vec<PathBuf>, BagError> {
    let meta = std::fs::metadata(path).map_err(|source| BagError::Io { path: path.to_path_buf(), source })?;
    if !meta.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let entries = std::fs::read_dir(path).map_err(|source| BagError::Io { path: path.to_path_buf(), source })?;
    let mut files: Vec<(u64, PathBuf)> = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|source| BagError::Io { path: path.to_path_buf(), source })?;
        let file = entry.path();
        if file.extension().is_some_and(|e| e == "mcap") {
            let index = file
                .file_stem()
                .and_then(|s| s.to_str())
                .and_then(|s| s.rsplit('_').next())
                .and_then(|n| n.parse::<u64>().ok())
                .unwrap_or(u64::MAX);
            files.push((index, file));
        }
    }
    files.sort();
    if files.is_empty() {
        return Err(BagError::Format(format!("{}: no .mcap files in this directory", path.display())));
    }
    Ok(files.into_iter().map(|(_, f)| f).collect())
}

/// Scans one MCAP file from start to end, calling `on_message` for every message of every complete
/// chunk (or unchunked message). A file cut off mid-record is read up to its last complete record.
pub fn scan_file(path: &Path, mut on_message: impl FnMut(MessageRef<'_>)) -> Result<FileScan, BagError> {
    let bytes = std::fs::read(path).map_err(|source| BagError::Io { path: path.to_path_buf(), source })?;
    let mut scan = FileScan { path: path.to_path_buf(), size: bytes.len() as u64, ..FileScan::default() };
    let mut schemas: BTreeMap<u16, (String, String, String)> = BTreeMap::new();
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_emit_chunks(true)
            .with_skip_end_magic(false)
            // No record can be longer than the file; a longer length is a torn tail, not an allocation.
            .with_record_length_limit(bytes.len()),
    );
    let mut offset = 0usize;
    let mut consumed_records_end = 0u64;
    let mut fed_all = false;
    while let Some(event) = reader.next_event() {
        let event = match event {
            Ok(event) => event,
            // A broken tail (e.g. garbage after a crash) ends the scan; everything before it is kept.
            Err(_) => break,
        };
        match event {
            LinearReadEvent::ReadRequest(need) => {
                if offset >= bytes.len() {
                    fed_all = true;
                    break;
                }
                let n = need.min(bytes.len() - offset).max(1).min(bytes.len() - offset);
                reader.insert(n).copy_from_slice(&bytes[offset..offset + n]);
                reader.notify_read(n);
                offset += n;
            }
            LinearReadEvent::Record { data, opcode } => {
                consumed_records_end += 9 + data.len() as u64;
                let record = match mcap::parse_record(opcode, data) {
                    Ok(record) => record,
                    // A record that does not parse means the framing can no longer be trusted: stop.
                    Err(_) => {
                        consumed_records_end -= 9 + data.len() as u64;
                        break;
                    }
                };
                match record {
                    Record::Header(h) => {
                        scan.profile = h.profile;
                        scan.library = h.library;
                    }
                    Record::Chunk { header, data } => {
                        let compression = header.compression.clone();
                        let Ok(inner) = chunk_records(&header, &data) else {
                            scan.corrupt_chunks += 1;
                            continue;
                        };
                        scan.chunks += 1;
                        if !compression.is_empty() && !scan.compressions.contains(&compression) {
                            scan.compressions.push(compression);
                        }
                        for rec in inner {
                            handle_record(rec, &mut scan, &mut schemas, &mut on_message);
                        }
                    }
                    Record::Footer(_) => scan.complete = true,
                    other => {
                        if handle_record(other, &mut scan, &mut schemas, &mut on_message) {
                            scan.unchunked_messages += 1;
                        }
                    }
                }
            }
        }
    }
    let _ = fed_all;
    // Magic (8) + records; anything beyond the last complete record is a cut-off tail.
    let accounted = 8 + consumed_records_end + if scan.complete { 8 } else { 0 };
    scan.truncated_bytes = scan.size.saturating_sub(accounted);
    Ok(scan)
}

/// The records inside one chunk, decompressed and framed by hand so that no length a corrupt file claims is
/// ever allocated before it is checked: mcap's ChunkReader reserves the sizes it reads up front, which aborts
/// the process on a header claiming exabytes. Err = the chunk is corrupt.
fn chunk_records(header: &mcap::records::ChunkHeader, data: &[u8]) -> Result<Vec<Record<'static>>, ()> {
    use std::io::Read;
    let claimed = header.uncompressed_size;
    if claimed > MAX_CHUNK_UNCOMPRESSED_SIZE {
        return Err(());
    }
    let decompressed: std::borrow::Cow<'_, [u8]> = match header.compression.as_str() {
        "" => std::borrow::Cow::Borrowed(data),
        "zstd" => std::borrow::Cow::Owned(zstd::bulk::decompress(data, claimed as usize).map_err(|_| ())?),
        "lz4" => {
            let mut out = Vec::new();
            lz4::Decoder::new(data).map_err(|_| ())?.take(claimed + 1).read_to_end(&mut out).map_err(|_| ())?;
            std::borrow::Cow::Owned(out)
        }
        _ => return Err(()),
    };
    if decompressed.len() as u64 != claimed {
        return Err(());
    }
    let bytes = &decompressed[..];
    let mut records = Vec::new();
    let mut offset = 0usize;
    while offset < bytes.len() {
        let frame = bytes.get(offset..offset + 9).ok_or(())?;
        let opcode = frame[0];
        let mut length = [0u8; 8];
        length.copy_from_slice(&frame[1..9]);
        let length = usize::try_from(u64::from_le_bytes(length)).map_err(|_| ())?;
        let body_start = offset + 9;
        let body = bytes.get(body_start..body_start.checked_add(length).ok_or(())?).ok_or(())?;
        records.push(mcap::parse_record(opcode, body).map_err(|_| ())?.into_owned());
        offset = body_start + length;
    }
    Ok(records)
}

/// Takes in one record; true if it was a message handed to `on_message`.
fn handle_record(
    record: Record<'_>,
    scan: &mut FileScan,
    schemas: &mut BTreeMap<u16, (String, String, String)>,
    on_message: &mut impl FnMut(MessageRef<'_>),
) -> bool {
    match record {
        Record::Schema { header, data } => {
            let text = String::from_utf8_lossy(&data).into_owned();
            schemas.insert(header.id, (header.name, header.encoding, text));
        }
        Record::Channel(channel) => {
            let (type_name, schema_encoding, schema_text) =
                schemas.get(&channel.schema_id).cloned().unwrap_or_default();
            let qos = channel
                .metadata
                .get("offered_qos_profiles")
                .and_then(|q| parse_offered_qos(q))
                .unwrap_or(RecordedQos { reliable: true, transient_local: false, depth: 10 });
            scan.channels.entry(channel.id).or_insert(ChannelInfo {
                topic: TopicInfo { name: channel.topic, type_name, schema_text, qos },
                schema_encoding,
                message_encoding: channel.message_encoding,
                metadata: channel.metadata,
            });
        }
        Record::Message { header, data } => {
            if let Some(channel) = scan.channels.get(&header.channel_id) {
                on_message(MessageRef {
                    channel,
                    channel_id: header.channel_id,
                    sequence: header.sequence,
                    log_time_ns: header.log_time,
                    publish_time_ns: header.publish_time,
                    data: &data,
                });
                *scan.counts.entry(header.channel_id).or_insert(0) += 1;
                scan.time_range = Some(match scan.time_range {
                    None => (header.log_time, header.log_time),
                    Some((a, b)) => (a.min(header.log_time), b.max(header.log_time)),
                });
                return true;
            }
        }
        Record::Metadata(m) if m.name == "rosbag2" => {
            if let Some(text) = m.metadata.get("serialized_metadata") {
                scan.rosbag2_metadata = Some(text.clone());
            }
        }
        _ => {}
    }
    false
}

/// Reads every message of a bag (directory or file), in file order then record order.
pub fn read_bag(path: &Path, mut on_message: impl FnMut(MessageRef<'_>)) -> Result<Vec<FileScan>, BagError> {
    let mut scans = Vec::new();
    for file in bag_files(path)? {
        scans.push(scan_file(&file, &mut on_message)?);
    }
    Ok(scans)
}
