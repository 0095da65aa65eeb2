//! Reading bags back, streaming: one pass from the start of each file to the end of its data section, one
//! chunk in memory at a time, so finished files and files cut off by a crash (no summary, no footer) are read
//! the same way, and a bag of any size is read in bounded memory.
//!
//! Nothing is hidden. Every chunk is checked (its CRC, its records against the size it claims, every
//! record inside it) before any of its messages is handed on; a chunk that fails is skipped and recorded as
//! [`Damage`] naming the file, the chunk (index and offset) and how many messages it held (from the message
//! indexes that follow it, or the summary's chunk index). A finished file is checked against its own
//! summary: the data-section and summary CRCs, and the message count of its statistics. Records that do not
//! frame are skipped to the next chunk the summary knows, or end the read where there is none.
//!
//! Damage is what contradicts the file, never what it leaves out: every layout the MCAP specification allows
//! reads (no chunks, chunks without message indexes or without chunk indexes, no statistics, no summary,
//! padded records; the official conformance corpus is in tests/mcap_conformance.rs). A count the file does
//! not give is unknown, not 0: a chunk index whose message-index offsets are empty means "no message
//! indexing available" (the specification), so the chunk's count is then checked against nothing.
//!
//! Channels are defined by the Schema and Channel records of the data section, which a file cut off by a crash
//! has alone. When those are damaged in a finished file, the intact summary's copies define the channels
//! instead, so the messages of intact chunks are still read; the damage report says so
//! ([`DamageKind::DefinitionsFromSummary`]).
//!
//! Inputs that are not MCAP files are refused before anything is read: anything that is not a regular file
//! (after following symlinks: a FIFO, a device such as /dev/zero, a directory) and anything that does not start
//! with the MCAP magic. Limits on what a file may make the reader hold are the constants below
//! (docs/file-formats.md, "MCAP reading limits").
//!
//! MCAP parsing, but for the footer read to find the summary, is the `mcap` crate's
//! `sans_io::LinearReader`: one frames the data section's top-level
//! records (fed the file up to the end of the data section, whole chunk records included, the data-section
//! CRC checked from the magic on), another decodes each chunk (decompression, CRC checked over the whole
//! chunk before any record is taken, record framing; kept from chunk to chunk), a third reads the summary
//! section (framing, summary CRC). What the crate lacks is here: it reports no offsets (every record is 9
//! bytes of frame and its body, so the reader counts them) and stops at the first error, so where it stops
//! the record's frame is read from the file to say what is wrong (cut off by the end of the file, claiming
//! more than the data section, an invalid opcode, over the size limit) and reading goes on with a new
//! reader after the record, or at the next chunk the summary knows (the data-section CRC is then no longer
//! checked); and the chunk limits below are checked on the chunk header before the chunk is decoded (the
//! crate has no expansion ratio).
//!
//! Memory: one top-level record (at most [`MAX_RECORD_SIZE`]: a chunk's compressed records, an attachment,
//! which is read and dropped, or an unchunked message) held by the framing reader; for a chunk, the
//! decoder's copy of it, the decompressed chunk (at most [`MAX_CHUNK_UNCOMPRESSED_SIZE`]) twice (the
//! decoder's and the reader's, whose messages are handed out) and the decompressor's window (at most
//! 2^[`ZSTD_WINDOW_LOG_MAX`] bytes for zstd, 4 MiB for LZ4); the channels (twice: the data section's and the
//! summary's), and 24 bytes per chunk of the summary's chunk index. For the bags sweetspot writes (chunks of
//! 1–4 MiB) that is a few MiB whatever the bag's size.
//!
//! Order: messages come in file order, files in the order `metadata.yaml` lists them (split order). File
//! order is the order in which the recorder received them (inputs) or published them (outputs); in the node's
//! bags log times, taken on several threads, can go backwards by microseconds within a file (`bag record`
//! writes in log-time order).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::ops::ControlFlow;
use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use mcap::records::{op, Record};
use mcap::sans_io::{LinearReadEvent, LinearReader, LinearReaderOptions};

use super::rosbag2::parse_offered_qos;
use super::{BagError, McapLayout, RecordedQos, TopicInfo};
use sweetspot_model::files::not_regular;

/// Largest uncompressed chunk the reader decompresses, bytes (sweetspot writes chunks of 4 MiB at most;
/// rosbag2 and the mcap writers default to well under 1 MiB).
pub const MAX_CHUNK_UNCOMPRESSED_SIZE: u64 = 256 * 1024 * 1024;
/// A chunk may claim up to this many uncompressed bytes whatever its compressed size.
pub const CHUNK_EXPANSION_FREE_SIZE: u64 = 16 * 1024 * 1024;
/// Beyond [`CHUNK_EXPANSION_FREE_SIZE`], a chunk may claim at most this many times its compressed size: more is
/// a decompression bomb, refused before anything is allocated (zstd and LZ4 reach ~10× on CDR; a chunk of a
/// few MiB of identical images may reach more and stays under the free size).
pub const MAX_CHUNK_EXPANSION: u64 = 1024;
/// Largest top-level record (a chunk, schema, channel, metadata record, attachment, message of an unchunked
/// file, or summary record) read into memory, bytes. Attachments and message indexes over it are skipped
/// unread; a chunk over it is a damaged chunk, anything else damage read around.
pub const MAX_RECORD_SIZE: u64 = 256 * 1024 * 1024;
/// Largest zstd window the decoder accepts, as a power of two: the `mcap` crate's zstd decoder keeps zstd's own
/// decoding default (`ZSTD_WINDOWLOG_LIMIT_DEFAULT`, 128 MiB), which this names.
pub const ZSTD_WINDOW_LOG_MAX: u32 = 27;
/// The MCAP magic, at the start and the end of every MCAP file.
pub const MCAP_MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";

/// Opcode + record length in front of every record.
const FRAME: u64 = 9;
/// Footer record (frame + 20 bytes) and the closing magic.
const FOOTER_AND_MAGIC: u64 = FRAME + 20 + 8;

/// A top-level record the sans-io reader yielded: its opcode, its length without the frame, and for a chunk
/// the decoding's outcome (the library that wrote it, or its damage).
struct TopLevelRecord {
    opcode: u8,
    length: u64,
    chunk: Option<Result<String, DamageKind>>,
}
/// Channel id, sequence, log time, publish time at the start of a Message record.
const MESSAGE_HEADER: usize = 22;

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

/// What is wrong with a damaged part of a file.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum DamageKind {
    /// The chunk's records do not match the CRC stored with them.
    ChunkCrc {
        /// CRC in the chunk record.
        stored: u32,
        /// CRC of the decompressed records.
        computed: u32,
    },
    /// The chunk does not decompress to what it claims, or holds records that do not parse.
    ChunkUndecodable {
        /// What failed.
        reason: String,
    },
    /// The chunk claims more uncompressed bytes than the reader's limits allow; refused unread.
    ChunkTooLarge {
        /// Uncompressed size the chunk claims, bytes.
        uncompressed_size: u64,
        /// Its compressed size, bytes.
        compressed_size: u64,
        /// The most this chunk may claim, bytes.
        limit: u64,
    },
    /// The file ends inside a record: cut off by a crash, or still being written.
    Truncated {
        /// Bytes of the incomplete record present in the file.
        cut_bytes: u64,
    },
    /// A record does not frame or parse; the read went on at `resumed_at`, or stopped there if None.
    Unparsable {
        /// What failed.
        reason: String,
        /// Where reading resumed (the next chunk the summary knows), if anywhere.
        resumed_at: Option<u64>,
        /// Chunks of the summary's chunk index skipped over.
        chunks_skipped: u64,
    },
    /// Messages on a channel no Channel record declares.
    UnknownChannel {
        /// The channel id.
        channel_id: u16,
    },
    /// Channels whose Schema and Channel records could not be read in the data section (they were in damaged
    /// bytes): their definitions came from the file's intact summary, and their messages were read with them.
    DefinitionsFromSummary {
        /// The channel ids.
        channel_ids: Vec<u16>,
        /// Their topics, in the same order.
        topics: Vec<String>,
    },
    /// Fewer (or more) messages were read than the file's own index or statistics say it holds.
    CountMismatch {
        /// What the file says.
        expected: u64,
        /// What was read.
        read: u64,
        /// `message index` (one chunk) or `statistics` (the whole file).
        source: String,
    },
    /// The data section does not match its CRC in the DataEnd record.
    DataSectionCrc {
        /// CRC in the DataEnd record.
        stored: u32,
        /// CRC of the bytes read.
        computed: u32,
    },
    /// The summary section is damaged (CRC or records); its chunk index and statistics are not used.
    Summary {
        /// What failed.
        reason: String,
    },
    /// A file that the bag's `metadata.yaml` lists is not there.
    MissingFile,
}

/// One damaged place in a file: what, where, and how many messages it cost.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Damage {
    /// The file.
    pub file: PathBuf,
    /// Offset in the file of the damaged record (or of the section checked).
    pub offset: u64,
    /// Index of the damaged chunk among the file's chunks (0-based), when a chunk is damaged.
    pub chunk: Option<u64>,
    /// What is wrong.
    #[serde(flatten)]
    pub kind: DamageKind,
    /// Messages lost, when the file's indexes or statistics tell; None = unknown.
    pub lost_messages: Option<u64>,
}

impl std::fmt::Display for DamageKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DamageKind::ChunkCrc { stored, computed } => {
                write!(f, "CRC mismatch (stored {stored:#010x}, computed {computed:#010x})")
            }
            DamageKind::ChunkUndecodable { reason } => write!(f, "does not decode: {reason}"),
            DamageKind::ChunkTooLarge { uncompressed_size, compressed_size, limit } => write!(
                f,
                "refused unread: claims {uncompressed_size} uncompressed bytes from {compressed_size} compressed, \
                 more than the limit of {limit} bytes for this chunk (docs/file-formats.md, MCAP reading limits)"
            ),
            DamageKind::Truncated { cut_bytes } => write!(
                f,
                "the file ends inside a record ({cut_bytes} bytes of it present): cut off by a crash, or still \
                 being written"
            ),
            DamageKind::Unparsable { reason, resumed_at: Some(at), chunks_skipped } => {
                write!(
                    f,
                    "{reason}; skipped to the next indexed chunk at offset {at} ({chunks_skipped} chunks not read)"
                )
            }
            DamageKind::Unparsable { reason, resumed_at: None, .. } => {
                write!(f, "{reason}; the rest of the data section is not read")
            }
            DamageKind::UnknownChannel { channel_id } => {
                write!(f, "messages on channel {channel_id}, which no Channel record declares")
            }
            DamageKind::DefinitionsFromSummary { channel_ids, topics } => {
                let channels: Vec<String> =
                    channel_ids.iter().zip(topics).map(|(id, topic)| format!("{id} ({topic})")).collect();
                write!(
                    f,
                    "no readable Schema or Channel record in the data section for channel(s) {}; their definitions \
                     came from the summary, and their messages were read with them",
                    channels.join(", ")
                )
            }
            DamageKind::CountMismatch { expected, read, source } => {
                write!(f, "{read} messages read where the {source} says {expected}")
            }
            DamageKind::DataSectionCrc { stored, computed } => write!(
                f,
                "data section CRC mismatch (stored {stored:#010x}, computed {computed:#010x}): bytes outside the \
                 checked chunks changed (an unchunked message, a message index, a channel)"
            ),
            DamageKind::Summary { reason } => {
                write!(f, "summary damaged ({reason}); its chunk index and statistics are not used")
            }
            DamageKind::MissingFile => write!(f, "listed in metadata.yaml but missing"),
        }
    }
}

impl std::fmt::Display for Damage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: ", self.file.display())?;
        match self.chunk {
            Some(index) => write!(f, "chunk {index} at offset {}: ", self.offset)?,
            None => write!(f, "at offset {}: ", self.offset)?,
        }
        write!(f, "{}; ", self.kind)?;
        match self.lost_messages {
            Some(n) => write!(f, "{n} messages lost"),
            None => write!(f, "messages lost: unknown (no index tells)"),
        }
    }
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
    /// Complete, undamaged chunks read.
    pub chunks: u64,
    /// Messages read from top-level Message records, outside any chunk (unchunked files).
    pub unchunked_messages: u64,
    /// Chunk compressions seen (e.g. `zstd`).
    pub compressions: Vec<String>,
    /// Whether the file ended properly (summary, footer, closing magic).
    pub complete: bool,
    /// Chunks skipped because they failed their checks (each is also in `damage`).
    pub corrupt_chunks: u64,
    /// Bytes at the end that did not form a complete record (cut off by a crash).
    pub truncated_bytes: u64,
    /// Earliest and latest log time, ns.
    pub time_range: Option<(u64, u64)>,
    /// The last `rosbag2` metadata record's `serialized_metadata`, if any.
    pub rosbag2_metadata: Option<String>,
    /// Attachment records in the data section (read or, over the size limit, skipped unread).
    pub attachments: u64,
    /// Metadata records in the data section (the `rosbag2` one included).
    pub metadata: u64,
    /// Messages the file's statistics record says it holds (finished files with an intact summary).
    pub expected_messages: Option<u64>,
    /// Every damaged place found, in file order.
    pub damage: Vec<Damage>,
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

    /// Whether anything in the file is damaged.
    pub fn damaged(&self) -> bool {
        !self.damage.is_empty()
    }

    /// Messages lost to damage: (known count, whether some damage has an unknown count).
    pub fn lost_messages(&self) -> (u64, bool) {
        let known = self.damage.iter().filter_map(|d| d.lost_messages).sum();
        (known, self.damage.iter().any(|d| d.lost_messages.is_none()))
    }
}

/// Every damaged place of the scanned files, in order.
pub fn damage_of(scans: &[FileScan]) -> Vec<&Damage> {
    scans.iter().flat_map(|s| s.damage.iter()).collect()
}

/// One line summing up the damage of scanned files, e.g. `3 damaged places in 2 files, 1,024 messages lost`.
pub fn damage_summary(scans: &[FileScan]) -> String {
    let places = scans.iter().map(|s| s.damage.len()).sum::<usize>();
    let files = scans.iter().filter(|s| s.damaged()).count();
    let known: u64 = scans.iter().map(|s| s.lost_messages().0).sum();
    let unknown = scans.iter().any(|s| s.lost_messages().1);
    let lost = if unknown { format!("at least {known} messages lost") } else { format!("{known} messages lost") };
    format!("{places} damaged place(s) in {files} file(s), {lost}")
}

/// Largest `metadata.yaml` read, bytes (sweetspot's are a few KiB; one with thousands of topics and files
/// stays well under a MiB).
pub const MAX_METADATA_YAML_SIZE: u64 = 16 * 1024 * 1024;

/// One file of a bag as its `metadata.yaml` lists it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ListedFile {
    /// Its path (the bag directory joined with the listed relative path).
    pub path: PathBuf,
    /// Whether it exists.
    pub present: bool,
    /// Messages `metadata.yaml` says it holds (its `files:` entry), if it says.
    pub message_count: Option<u64>,
}

/// The files of a bag: what `metadata.yaml`'s `relative_file_paths` lists, in its order (as `ros2 bag`
/// reads a bag), each file once, and the `.mcap` files in the directory it does not list (named, never read).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BagListing {
    /// The listed files, present or not, each once (where it is first listed).
    pub files: Vec<ListedFile>,
    /// `.mcap` files in the directory that `metadata.yaml` does not list, sorted.
    pub stray: Vec<PathBuf>,
    /// Files `metadata.yaml` lists more than once (by name, or by two names of one file): read once.
    pub duplicates: Vec<DuplicateListing>,
}

/// A file `metadata.yaml` lists more than once.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DuplicateListing {
    /// The file as first listed.
    pub path: PathBuf,
    /// How many times it is listed in all.
    pub times: usize,
}

impl std::fmt::Display for DuplicateListing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: listed {} times in metadata.yaml: read once (its messages counted once)",
            self.path.display(),
            self.times
        )
    }
}

impl BagListing {
    /// The listed files that exist, in order.
    pub fn present(&self) -> Vec<PathBuf> {
        self.files.iter().filter(|f| f.present).map(|f| f.path.clone()).collect()
    }
}

/// The files of a bag: a directory's as its `metadata.yaml` lists them (see [`BagListing`]), or a single
/// file. A directory without a readable `metadata.yaml` is refused (`bag recover` rebuilds one).
pub fn bag_listing(path: &Path) -> Result<BagListing, BagError> {
    let meta = std::fs::metadata(path).map_err(|source| BagError::Io { path: path.to_path_buf(), source })?;
    if !meta.is_dir() {
        let file = ListedFile { path: path.to_path_buf(), present: true, message_count: None };
        return Ok(BagListing { files: vec![file], ..BagListing::default() });
    }
    let unreadable = |why: String| {
        BagError::Format(format!(
            "{}: {why}; the files of a bag are what its metadata.yaml lists (as `ros2 bag` reads it): \
             `sweetspot bag recover {}` writes a copy with metadata.yaml rebuilt from the MCAP files",
            path.display(),
            path.display()
        ))
    };
    let yaml_path = path.join("metadata.yaml");
    let listed = read_small_regular_file(&yaml_path, MAX_METADATA_YAML_SIZE)
        .map_err(|why| format!("metadata.yaml {why}"))
        .and_then(|text| parse_file_list(&text).map_err(|why| format!("metadata.yaml is unreadable: {why}")));
    let listed = match listed {
        Ok(listed) => listed,
        Err(why) => {
            // A file in there that is no MCAP file at all (a FIFO, a device) is the first thing to say.
            for file in mcap_files_in_dir(path)? {
                open_mcap(&file)?;
            }
            return Err(unreadable(why));
        }
    };
    let (files, duplicates) = each_file_once(path, listed);
    let listed: std::collections::HashSet<&Path> = files.iter().map(|f| f.path.as_path()).collect();
    let stray = mcap_files_in_dir(path)?.into_iter().filter(|file| !listed.contains(file.as_path())).collect();
    Ok(BagListing { files, stray, duplicates })
}

/// The listed files of the bag directory `dir`, each once where it is first listed, and those listed more
/// than once: a file named twice (`a.mcap`, `./a.mcap`) or reached by two names (a link) would otherwise be
/// read, counted and replayed twice.
fn each_file_once(dir: &Path, listed: Vec<(String, Option<u64>)>) -> (Vec<ListedFile>, Vec<DuplicateListing>) {
    use std::collections::hash_map::Entry;
    use std::os::unix::fs::MetadataExt;
    let mut files: Vec<ListedFile> = Vec::new();
    let mut times: Vec<usize> = Vec::new();
    // Path equality compares components, so `a.mcap` and `./a.mcap` are one key; a link to a listed file is
    // the same device and inode.
    let mut by_path: std::collections::HashMap<PathBuf, usize> = std::collections::HashMap::new();
    let mut by_inode: std::collections::HashMap<(u64, u64), usize> = std::collections::HashMap::new();
    for (relative, message_count) in listed {
        let file = dir.join(&relative);
        let present = std::fs::symlink_metadata(&file).is_ok();
        let inode = std::fs::metadata(&file).ok().map(|m| (m.dev(), m.ino()));
        let index = match by_path.entry(file.clone()) {
            Entry::Occupied(seen) => Some(*seen.get()),
            Entry::Vacant(slot) => {
                let same_file = inode.and_then(|key| by_inode.get(&key).copied());
                slot.insert(same_file.unwrap_or(files.len()));
                same_file
            }
        };
        match index {
            Some(first) => times[first] += 1,
            None => {
                if let Some(key) = inode {
                    by_inode.insert(key, files.len());
                }
                files.push(ListedFile { path: file, present, message_count });
                times.push(1);
            }
        }
    }
    let duplicates = files
        .iter()
        .zip(times)
        .filter(|(_, times)| *times > 1)
        .map(|(file, times)| DuplicateListing { path: file.path.clone(), times })
        .collect();
    (files, duplicates)
}

/// The MCAP files of a bag that exist, in order: a directory's as its `metadata.yaml` lists them, or the
/// file itself (see [`bag_listing`]).
pub fn bag_files(path: &Path) -> Result<Vec<PathBuf>, BagError> {
    let listing = bag_listing(path)?;
    let files = listing.present();
    if files.is_empty() {
        return Err(BagError::Format(format!("{}: none of the files metadata.yaml lists is there", path.display())));
    }
    Ok(files)
}

/// Every `*.mcap` of a directory in split order (`_0`, `_1`, …, then names without a split number),
/// whatever `metadata.yaml` says: what `bag recover` rebuilds a bag from.
pub fn mcap_files_in_dir(path: &Path) -> Result<Vec<PathBuf>, BagError> {
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
    Ok(files.into_iter().map(|(_, f)| f).collect())
}

/// A regular file of at most `limit` bytes as UTF-8 text (the input rule of [`sweetspot_model::files`]), or why not
/// ("is missing", "is a FIFO, …").
fn read_small_regular_file(path: &Path, limit: u64) -> Result<String, String> {
    use sweetspot_model::files::InputError;
    match sweetspot_model::files::read_limited(path, "metadata.yaml", limit) {
        Ok(bytes) => String::from_utf8(bytes).map_err(|_| "is not UTF-8 text".to_string()),
        Err(InputError::Io { error, .. }) if error.kind() == std::io::ErrorKind::NotFound => {
            Err("is missing".to_string())
        }
        Err(InputError::Io { error, .. }) => Err(format!("cannot be read ({error})")),
        Err(InputError::NotRegular { kind, .. }) => Err(format!("is {kind}, not a regular file")),
        Err(InputError::TooLarge { size, limit, .. }) => {
            Err(format!("is {size} bytes, more than the {limit} read at most"))
        }
        Err(InputError::NotText { .. }) => Err("is not UTF-8 text".to_string()),
    }
}

/// `relative_file_paths` of a rosbag2 `metadata.yaml`, with each file's `message_count` from `files:` when
/// given there.
fn parse_file_list(text: &str) -> Result<Vec<(String, Option<u64>)>, String> {
    use yaml_rust2::Yaml;
    let docs = sweetspot_model::yaml::load(text).map_err(|e| e.to_string())?;
    let info = docs
        .first()
        .map(|d| &d["rosbag2_bagfile_information"])
        .filter(|i| i.as_hash().is_some())
        .ok_or("no rosbag2_bagfile_information mapping")?;
    let paths = info["relative_file_paths"].as_vec().ok_or("no relative_file_paths list")?;
    // Each file's count looked up once, not by a search of `files:` per listed path (quadratic: 80,000 entries
    // took minutes). The first entry of a path counts, as a search would have found it.
    let mut counts: std::collections::HashMap<&str, &Yaml> = std::collections::HashMap::new();
    for entry in info["files"].as_vec().map(Vec::as_slice).unwrap_or_default() {
        if let Some(listed) = entry["path"].as_str() {
            counts.entry(listed).or_insert(&entry["message_count"]);
        }
    }
    let mut out = Vec::new();
    for entry in paths {
        let relative = entry.as_str().ok_or("relative_file_paths holds something other than a path")?;
        if relative.is_empty() || Path::new(relative).is_absolute() || relative.split('/').any(|p| p == "..") {
            return Err(format!("relative_file_paths lists {relative:?}, not a file inside the bag directory"));
        }
        let count = match counts.get(relative) {
            Some(Yaml::Integer(n)) => u64::try_from(*n).ok(),
            _ => None,
        };
        out.push((relative.to_string(), count));
    }
    Ok(out)
}

/// Opens `path` for reading if it is (or a symlink resolves to) a regular file that starts with the MCAP magic;
/// returns it with its size. Never blocks (a FIFO is refused before it is opened) and never reads more than
/// the magic.
pub fn open_mcap(path: &Path) -> Result<(File, u64), BagError> {
    use std::os::unix::fs::OpenOptionsExt;
    let io = |source| BagError::Io { path: path.to_path_buf(), source };
    let refuse = |what: &str| BagError::NotRegularFile { path: path.to_path_buf(), what: what.to_string() };
    let meta = std::fs::metadata(path).map_err(io)?;
    if let Some(what) = not_regular(meta.file_type()) {
        return Err(refuse(what));
    }
    // O_NONBLOCK: should the path become a FIFO between the check and the open, the open does not hang.
    let mut file = std::fs::OpenOptions::new().read(true).custom_flags(libc::O_NONBLOCK).open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if let Some(what) = not_regular(meta.file_type()) {
        return Err(refuse(what));
    }
    sweetspot_model::files::note_input(path, &meta);
    let size = meta.len();
    let not_mcap = |reason: String| BagError::NotMcap { path: path.to_path_buf(), reason };
    if size == 0 {
        return Err(not_mcap("the file is empty".to_string()));
    }
    let mut magic = [0u8; 8];
    let n = read_up_to(&mut file, &mut magic).map_err(io)?;
    if n < magic.len() || &magic != MCAP_MAGIC {
        let shown: String = magic[..n].iter().map(|&b| if b.is_ascii_graphic() { b as char } else { '.' }).collect();
        return Err(not_mcap(format!(
            "it does not start with the MCAP magic \\x89MCAP0\\r\\n (it starts with {shown:?}, {size} bytes in all)"
        )));
    }
    Ok((file, size))
}

/// Reads until `buf` is full or the end of the input; returns how many bytes were read.
fn read_up_to(reader: &mut impl Read, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buf.len() {
        match reader.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(filled)
}

/// A chunk listed in the summary's chunk index.
#[derive(Debug, Clone, Copy)]
struct IndexedChunk {
    offset: u64,
    /// Messages in it (from the length of its message indexes); None when the chunk index lists no message
    /// index (the writer kept none: unknown, not 0) or the length is inconsistent.
    messages: Option<u64>,
}

/// The chunk just read, until the message indexes after it have been counted.
#[derive(Debug)]
struct PendingChunk {
    index: u64,
    offset: u64,
    fault: Option<DamageKind>,
    /// Message records inside it (0 if it failed).
    messages: u64,
    /// Entries of the message index records that follow it.
    indexed: Option<u64>,
}

/// Where the message to hand out lives.
#[derive(Debug, Clone, Copy)]
struct Current {
    channel_id: u16,
    sequence: u32,
    log_time: u64,
    publish_time: u64,
    in_chunk: bool,
    start: usize,
    end: usize,
}

/// A streaming reader of one MCAP file: [`FileReader::advance`] moves to the next message,
/// [`FileReader::message`] borrows it, [`FileReader::finish`] returns what the scan found.
pub struct FileReader {
    file: BufReader<File>,
    /// The crate's framing of the data section's top-level records (whole chunk records included), fed the
    /// file from `fed` up to `data_end`; `at` is where the next record it yields starts (it reports no
    /// offsets: every record is 9 bytes of frame and its body, in file order).
    top: LinearReader,
    fed: u64,
    at: u64,
    /// The chunk decoder, kept from chunk to chunk (and its zstd context with it) while their sizes round up
    /// to the same power of two, which is its record length limit; dropped after a chunk it fails on.
    decoder: Option<(usize, LinearReader)>,
    scan: FileScan,
    schemas: BTreeMap<u16, (String, String, String)>,
    /// End of the data section: the summary's start, the footer, or the end of an unfinished file.
    data_end: u64,
    /// Chunk index of an intact summary, by offset.
    indexed_chunks: Vec<IndexedChunk>,
    statistics: Option<u64>,
    /// Channels of an intact summary not (yet) declared in the data section, and where the summary starts:
    /// the definitions of last resort when the data section's are damaged.
    summary_channels: BTreeMap<u16, ChannelInfo>,
    summary_offset: u64,
    /// Channels defined from the summary, in the order they were needed.
    from_summary: Vec<u16>,
    next_chunk: u64,
    pending: Option<PendingChunk>,
    /// The current chunk's decompressed records, and (opcode, body start, body end) of each.
    chunk: Vec<u8>,
    spans: Vec<(u8, usize, usize)>,
    next_span: usize,
    /// The body of the current top-level record.
    record: Vec<u8>,
    current: Option<Current>,
    unknown_channels: BTreeMap<u16, (u64, u64)>,
    /// End of the last complete record read.
    consumed: u64,
    done: bool,
}

impl FileReader {
    /// Opens one MCAP file (refusing anything that is not a regular MCAP file) and reads its summary, if it
    /// has an intact one.
    pub fn open(path: &Path) -> Result<FileReader, BagError> {
        let (mut file, size) = open_mcap(path)?;
        let io = |source| BagError::Io { path: path.to_path_buf(), source };
        let mut scan = FileScan { path: path.to_path_buf(), size, ..FileScan::default() };
        let mut indexed_chunks = Vec::new();
        let mut statistics = None;
        let mut summary_channels = BTreeMap::new();
        let mut summary_offset = 0;
        let mut data_end = size;
        let summary_damage = |offset, reason| {
            let kind = DamageKind::Summary { reason };
            Damage { file: path.to_path_buf(), offset, chunk: None, kind, lost_messages: None }
        };
        if size >= 8 + FOOTER_AND_MAGIC {
            let footer_at = size - FOOTER_AND_MAGIC;
            let mut tail = [0u8; FOOTER_AND_MAGIC as usize];
            file.seek(SeekFrom::Start(footer_at)).map_err(io)?;
            file.read_exact(&mut tail).map_err(io)?;
            if &tail[29..] == MCAP_MAGIC {
                let le64 = |at: usize| u64::from_le_bytes(tail[at..at + 8].try_into().unwrap_or([0; 8]));
                let summary_start = le64(9);
                let footer_ok = tail[0] == op::FOOTER
                    && le64(1) == 20
                    && (summary_start == 0 || (8..=footer_at).contains(&summary_start));
                if footer_ok {
                    scan.complete = true;
                    data_end = if summary_start == 0 { footer_at } else { summary_start };
                    if summary_start != 0 {
                        match read_summary(&mut file, summary_start, footer_at, &tail) {
                            Ok(Ok(summary)) => {
                                indexed_chunks = summary.chunks;
                                statistics = summary.statistics;
                                summary_channels = summary.channels;
                                summary_offset = summary_start;
                            }
                            Ok(Err(reason)) => scan.damage.push(summary_damage(summary_start, reason)),
                            Err(e) => return Err(io(e)),
                        }
                    }
                } else {
                    scan.damage.push(summary_damage(footer_at, "the footer record does not parse".to_string()));
                }
            }
        }
        file.seek(SeekFrom::Start(0)).map_err(io)?;
        scan.expected_messages = statistics;
        Ok(FileReader {
            file: BufReader::with_capacity(64 * 1024, file),
            top: top_level_reader(true),
            fed: 0,
            at: 8,
            decoder: None,
            scan,
            schemas: BTreeMap::new(),
            data_end,
            indexed_chunks,
            statistics,
            summary_channels,
            summary_offset,
            from_summary: Vec::new(),
            next_chunk: 0,
            pending: None,
            chunk: Vec::new(),
            spans: Vec::new(),
            next_span: 0,
            record: Vec::new(),
            current: None,
            unknown_channels: BTreeMap::new(),
            consumed: 8,
            done: false,
        })
    }

    /// Moves to the next message; false at the end of the file. Damage is recorded and read around, never
    /// returned as an error: errors are I/O failures only.
    pub fn advance(&mut self) -> Result<bool, BagError> {
        self.current = None;
        loop {
            while self.next_span < self.spans.len() {
                let (opcode, start, end) = self.spans[self.next_span];
                self.next_span += 1;
                if opcode == op::MESSAGE {
                    if self.take_message(true, start, end) {
                        return Ok(true);
                    }
                } else if let Ok(record) = mcap::parse_record(opcode, &self.chunk[start..end]) {
                    take_definition(record, &mut self.scan, &mut self.schemas);
                }
            }
            if self.done {
                return Ok(false);
            }
            if self.read_top_level().map_err(|source| BagError::Io { path: self.scan.path.clone(), source })? {
                return Ok(true);
            }
        }
    }

    /// The message [`FileReader::advance`] moved to.
    pub fn message(&self) -> Option<MessageRef<'_>> {
        let c = self.current?;
        let channel = self.scan.channels.get(&c.channel_id)?;
        let data = if c.in_chunk { self.chunk.get(c.start..c.end)? } else { self.record.get(c.start..c.end)? };
        Some(MessageRef {
            channel,
            channel_id: c.channel_id,
            sequence: c.sequence,
            log_time_ns: c.log_time,
            publish_time_ns: c.publish_time,
            data,
        })
    }

    /// What the file held so far (everything, after [`FileReader::advance`] returned false).
    pub fn scan(&self) -> &FileScan {
        &self.scan
    }

    /// Reads whatever is left and returns the scan of the whole file.
    pub fn finish(mut self) -> Result<FileScan, BagError> {
        while self.advance()? {}
        Ok(self.scan)
    }

    fn damage(&mut self, offset: u64, chunk: Option<u64>, kind: DamageKind, lost_messages: Option<u64>) {
        self.scan.damage.push(Damage { file: self.scan.path.clone(), offset, chunk, kind, lost_messages });
    }

    /// Makes the message record at `start..end` of the chunk (or record) buffer current; false if its
    /// channel is unknown (counted as damage) or it does not parse.
    fn take_message(&mut self, in_chunk: bool, start: usize, end: usize) -> bool {
        let body = if in_chunk { &self.chunk[start..end] } else { &self.record[start..end] };
        if body.len() < MESSAGE_HEADER {
            return false;
        }
        let channel_id = u16::from_le_bytes([body[0], body[1]]);
        let sequence = u32::from_le_bytes(body[2..6].try_into().unwrap_or([0; 4]));
        let log_time = u64::from_le_bytes(body[6..14].try_into().unwrap_or([0; 8]));
        let publish_time = u64::from_le_bytes(body[14..22].try_into().unwrap_or([0; 8]));
        if !self.scan.channels.contains_key(&channel_id) {
            match self.summary_channels.remove(&channel_id) {
                Some(channel) => {
                    self.scan.channels.insert(channel_id, channel);
                    self.from_summary.push(channel_id);
                }
                None => {
                    let offset = self.pending.as_ref().map_or(self.at, |p| p.offset);
                    self.unknown_channels.entry(channel_id).or_insert((offset, 0)).1 += 1;
                    return false;
                }
            }
        }
        *self.scan.counts.entry(channel_id).or_insert(0) += 1;
        self.scan.time_range = Some(match self.scan.time_range {
            None => (log_time, log_time),
            Some((a, b)) => (a.min(log_time), b.max(log_time)),
        });
        self.current = Some(Current {
            channel_id,
            sequence,
            log_time,
            publish_time,
            in_chunk,
            start: start + MESSAGE_HEADER,
            end,
        });
        true
    }

    /// The index of the chunk at `offset`: its place in the summary's chunk index, else its place in the file.
    fn chunk_index_at(&self, offset: u64) -> u64 {
        match self.indexed_chunks.binary_search_by_key(&offset, |c| c.offset) {
            Ok(i) => i as u64,
            Err(_) => self.next_chunk,
        }
    }

    /// Records the damage of the chunk just read, now that the message indexes after it are counted.
    fn settle_pending_chunk(&mut self) {
        let Some(chunk) = self.pending.take() else { return };
        let summary_count = || {
            self.indexed_chunks
                .binary_search_by_key(&chunk.offset, |c| c.offset)
                .ok()
                .and_then(|i| self.indexed_chunks[i].messages)
        };
        match chunk.fault {
            Some(kind) => {
                let lost = chunk.indexed.or_else(summary_count);
                self.scan.corrupt_chunks += 1;
                self.damage(chunk.offset, Some(chunk.index), kind, lost);
            }
            None => {
                if let Some(expected) = chunk.indexed.or_else(summary_count) {
                    if expected != chunk.messages {
                        let kind = DamageKind::CountMismatch {
                            expected,
                            read: chunk.messages,
                            source: "chunk's message index".to_string(),
                        };
                        self.damage(chunk.offset, Some(chunk.index), kind, expected.checked_sub(chunk.messages));
                    }
                }
            }
        }
    }

    /// The framing broke at `at`: resume at the next chunk the summary knows, or stop.
    fn lose_framing(&mut self, at: u64, reason: String) -> std::io::Result<()> {
        self.settle_pending_chunk();
        let next = self.indexed_chunks.iter().position(|c| c.offset > at);
        match next {
            Some(next) if self.indexed_chunks[next].offset < self.data_end => {
                let first = self.indexed_chunks.iter().position(|c| c.offset >= at).unwrap_or(next);
                let skipped = &self.indexed_chunks[first..next];
                let lost = skipped.iter().map(|c| c.messages).sum::<Option<u64>>();
                let resume = self.indexed_chunks[next].offset;
                let kind =
                    DamageKind::Unparsable { reason, resumed_at: Some(resume), chunks_skipped: skipped.len() as u64 };
                let chunk = if skipped.is_empty() { None } else { Some(first as u64) };
                self.scan.corrupt_chunks += skipped.len() as u64;
                self.damage(at, chunk, kind, lost);
                self.next_chunk = next as u64;
                self.restart(resume)
            }
            _ => {
                let skipped = self.indexed_chunks.iter().filter(|c| c.offset >= at).count() as u64;
                let lost = if self.indexed_chunks.is_empty() {
                    None
                } else {
                    self.indexed_chunks.iter().filter(|c| c.offset >= at).map(|c| c.messages).sum::<Option<u64>>()
                };
                self.scan.corrupt_chunks += skipped;
                let chunk = if skipped > 0 { Some(self.chunk_index_at(at)) } else { None };
                self.damage(
                    at,
                    chunk,
                    DamageKind::Unparsable { reason, resumed_at: None, chunks_skipped: skipped },
                    lost,
                );
                self.end_of_data();
                Ok(())
            }
        }
    }

    /// Reads the next top-level record; true if it is a message (of an unchunked file) to hand out.
    fn read_top_level(&mut self) -> std::io::Result<bool> {
        self.spans.clear();
        self.next_span = 0;
        let start = self.at;
        let TopLevelRecord { opcode, length, chunk } = match self.next_top_level_record(start)? {
            ControlFlow::Continue(record) => record,
            ControlFlow::Break(message) => return Ok(message),
        };
        let end = start + FRAME + length;
        self.at = end;
        if opcode == 0 || (op::DATA_END < opcode && opcode < 0x80) {
            self.lose_framing(start, format!("a record with the invalid opcode {opcode:#04x}"))?;
            return Ok(false);
        }
        self.consumed = end;
        if opcode != op::MESSAGE_INDEX {
            self.settle_pending_chunk();
        }
        match opcode {
            op::CHUNK => {
                if let Some(decoded) = chunk {
                    self.take_chunk(start, decoded);
                }
            }
            op::MESSAGE_INDEX => self.count_indexed_messages(length),
            op::ATTACHMENT => self.scan.attachments += 1,
            op::DATA_END | op::FOOTER => self.end_of_data(),
            op::MESSAGE => return Ok(self.take_unchunked_message(start, end)),
            _ => self.take_other_record(start, end, opcode),
        }
        Ok(false)
    }

    /// Feeds the sans-io reader from the file (never past the data section) until it yields the record at
    /// `start` (a chunk decoded into `self.chunk`, any other record copied into `self.record`); `Break` with
    /// what [`Self::read_top_level`] returns when the data section ends or breaks there instead.
    fn next_top_level_record(&mut self, start: u64) -> std::io::Result<ControlFlow<bool, TopLevelRecord>> {
        loop {
            match self.top.next_event() {
                None => {
                    self.consumed = start;
                    self.end_of_data();
                    return Ok(ControlFlow::Break(false));
                }
                Some(Ok(LinearReadEvent::ReadRequest(n))) => {
                    // Never past the data section: a record that claims more is cut off there (0 = end).
                    let left = usize::try_from(self.data_end.saturating_sub(self.fed)).unwrap_or(usize::MAX);
                    let got = read_up_to(&mut self.file, self.top.insert(n.min(left)))?;
                    self.top.notify_read(got);
                    self.fed += got as u64;
                }
                Some(Ok(LinearReadEvent::Record { opcode, data })) => {
                    let chunk = if opcode == op::CHUNK {
                        Some(decode_chunk(&mut self.decoder, data, &mut self.chunk, &mut self.spans))
                    } else {
                        self.record.clear();
                        self.record.extend_from_slice(data);
                        None
                    };
                    return Ok(ControlFlow::Continue(TopLevelRecord { opcode, length: data.len() as u64, chunk }));
                }
                Some(Err(mcap::McapError::BadDataCrc { saved, calculated })) => {
                    let kind = DamageKind::DataSectionCrc { stored: saved, computed: calculated };
                    self.damage(start, None, kind, None);
                    self.consumed = start + FRAME + self.frame_at(start)?.map_or(0, |(_, length)| length);
                    self.end_of_data();
                    return Ok(ControlFlow::Break(false));
                }
                Some(Err(e)) => return self.broken(start, e).map(ControlFlow::Break),
            }
        }
    }

    /// A message index record (`length` bytes) after a chunk: the messages it indexes count toward the
    /// chunk's, when its array is whole.
    fn count_indexed_messages(&mut self, length: u64) {
        let head = self.record.get(2..6).and_then(|b| b.try_into().ok()).map(u32::from_le_bytes);
        if let (Some(chunk), Some(bytes)) = (&mut self.pending, head) {
            let bytes = u64::from(bytes);
            if bytes + 6 == length && bytes % 16 == 0 {
                *chunk.indexed.get_or_insert(0) += bytes / 16;
            }
        }
    }

    /// A message record of an unchunked file at `start`..`end`: true if it is one to hand out; one that does
    /// not parse is damage.
    fn take_unchunked_message(&mut self, start: u64, end: u64) -> bool {
        if mcap::parse_record(op::MESSAGE, &self.record).is_ok() {
            if self.take_message(false, 0, self.record.len()) {
                self.scan.unchunked_messages += 1;
                return true;
            }
        } else {
            let reason = "a message record does not parse".to_string();
            let kind = DamageKind::Unparsable { reason, resumed_at: Some(end), chunks_skipped: 0 };
            self.damage(start, None, kind, Some(1));
        }
        false
    }

    /// Any other record at `start`..`end`: the header's profile and library, a definition (schema, channel) or
    /// metadata taken into the scan; one that does not parse is damage.
    fn take_other_record(&mut self, start: u64, end: u64, opcode: u8) {
        let problem = match mcap::parse_record(opcode, &self.record) {
            Ok(Record::Header(h)) => {
                self.scan.profile = h.profile;
                self.scan.library = h.library;
                None
            }
            Ok(record) => {
                if let Record::Metadata(_) = record {
                    self.scan.metadata += 1;
                }
                take_definition(record, &mut self.scan, &mut self.schemas);
                None
            }
            Err(e) => Some(format!("a record (opcode {opcode:#04x}) does not parse: {e}")),
        };
        if let Some(reason) = problem {
            let kind = DamageKind::Unparsable { reason, resumed_at: Some(end), chunks_skipped: 0 };
            self.damage(start, None, kind, None);
        }
    }

    /// The crate stopped at the record at `start` (`error`): says why from its frame, as the file has it, and
    /// goes on after it where the file allows.
    fn broken(&mut self, start: u64, error: mcap::McapError) -> std::io::Result<bool> {
        let remaining = self.data_end.saturating_sub(start);
        let frame = if remaining >= FRAME { self.frame_at(start)? } else { None };
        let Some((opcode, length)) = frame else { return self.cut_off(start, remaining, None) };
        if opcode == 0 || (op::DATA_END < opcode && opcode < 0x80) {
            self.lose_framing(start, format!("a record with the invalid opcode {opcode:#04x}"))?;
            return Ok(false);
        }
        if length > remaining - FRAME {
            if !self.scan.complete {
                return self.cut_off(start, remaining, Some(opcode));
            }
            let reason = format!("a record (opcode {opcode:#04x}) claims {length} bytes, past the data section");
            self.lose_framing(start, reason)?;
            return Ok(false);
        }
        if opcode != op::MESSAGE_INDEX {
            self.settle_pending_chunk();
        }
        let end = start + FRAME + length;
        self.consumed = end;
        match opcode {
            // A Data End or Footer record too short for its fields: the data section ends all the same.
            op::DATA_END | op::FOOTER => {
                self.end_of_data();
                return Ok(false);
            }
            // Over the limit: skipped unread (they are not needed to read the messages).
            op::ATTACHMENT => self.scan.attachments += 1,
            op::MESSAGE_INDEX => {}
            op::CHUNK => {
                let reason = format!("a chunk record of {length} bytes, over the {MAX_RECORD_SIZE}-byte limit");
                self.take_chunk(start, Err(DamageKind::ChunkUndecodable { reason }));
            }
            _ => {
                let reason = if length > MAX_RECORD_SIZE {
                    format!("a record (opcode {opcode:#04x}) of {length} bytes, over the {MAX_RECORD_SIZE}-byte limit")
                } else {
                    format!("a record (opcode {opcode:#04x}) does not read: {error}")
                };
                let kind = DamageKind::Unparsable { reason, resumed_at: Some(end), chunks_skipped: 0 };
                self.damage(start, None, kind, None);
            }
        }
        self.restart(end)?;
        Ok(false)
    }

    /// The opcode and length of the record at `offset`, read from the file; None if the file ends first.
    fn frame_at(&self, offset: u64) -> std::io::Result<Option<(u8, u64)>> {
        let mut frame = [0u8; FRAME as usize];
        match self.file.get_ref().read_exact_at(&mut frame, offset) {
            Ok(()) => Ok(Some((frame[0], u64::from_le_bytes(frame[1..9].try_into().unwrap_or([0; 8]))))),
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// Goes on reading top-level records at `offset`, with a new reader: the data-section CRC can no longer be
    /// computed.
    fn restart(&mut self, offset: u64) -> std::io::Result<()> {
        self.file.seek(SeekFrom::Start(offset))?;
        self.top = top_level_reader(false);
        self.fed = offset;
        self.at = offset;
        Ok(())
    }

    /// The file ends inside the record at `start` (of type `opcode`, if its frame is there).
    fn cut_off(&mut self, start: u64, present: u64, opcode: Option<u8>) -> std::io::Result<bool> {
        self.settle_pending_chunk();
        let chunk = (opcode == Some(op::CHUNK)).then_some(self.next_chunk);
        self.damage(start, chunk, DamageKind::Truncated { cut_bytes: present }, None);
        self.end_of_data();
        Ok(false)
    }

    /// Takes in the chunk record at `start`, decoded into `chunk` and `spans` (Ok: its compression) or not.
    fn take_chunk(&mut self, start: u64, decoded: Result<String, DamageKind>) {
        let index = self.chunk_index_at(start);
        self.next_chunk = index + 1;
        let mut pending = PendingChunk { index, offset: start, fault: None, messages: 0, indexed: None };
        match decoded {
            Ok(compression) => {
                pending.messages = self.spans.iter().filter(|s| s.0 == op::MESSAGE).count() as u64;
                self.scan.chunks += 1;
                if !compression.is_empty() && !self.scan.compressions.contains(&compression) {
                    self.scan.compressions.push(compression);
                }
            }
            Err(kind) => {
                self.chunk.clear();
                self.spans.clear();
                pending.fault = Some(kind);
            }
        }
        self.pending = Some(pending);
    }

    /// The data section is over: settle what is pending and check the counts against the statistics.
    fn end_of_data(&mut self) {
        if self.done {
            return;
        }
        self.done = true;
        self.settle_pending_chunk();
        for (channel_id, (offset, count)) in std::mem::take(&mut self.unknown_channels) {
            self.damage(offset, None, DamageKind::UnknownChannel { channel_id }, Some(count));
        }
        // Damaged bytes may have held the definitions of channels whose messages were all lost too: the summary
        // still lists them, so the file keeps every topic it was written with.
        if self.scan.damaged() {
            for (channel_id, channel) in std::mem::take(&mut self.summary_channels) {
                if let std::collections::btree_map::Entry::Vacant(entry) = self.scan.channels.entry(channel_id) {
                    entry.insert(channel);
                    self.from_summary.push(channel_id);
                }
            }
        }
        if !self.from_summary.is_empty() {
            let channel_ids = std::mem::take(&mut self.from_summary);
            let topics = channel_ids
                .iter()
                .map(|id| self.scan.channels.get(id).map(|c| c.topic.name.clone()).unwrap_or_default())
                .collect();
            self.damage(self.summary_offset, None, DamageKind::DefinitionsFromSummary { channel_ids, topics }, Some(0));
        }
        if !self.scan.complete {
            self.scan.truncated_bytes = self.scan.size.saturating_sub(self.consumed);
        }
        let Some(expected) = self.statistics else { return };
        let read = self.scan.message_count();
        let (known, _) = self.scan.lost_messages();
        if read + known == expected {
            // Every message the statistics count was read or is counted lost: damage of unknown cost lost none.
            for damage in &mut self.scan.damage {
                damage.lost_messages.get_or_insert(0);
            }
            return;
        }
        let missing = expected.checked_sub(read + known);
        let unknown: Vec<usize> =
            (0..self.scan.damage.len()).filter(|&i| self.scan.damage[i].lost_messages.is_none()).collect();
        match (missing, unknown.as_slice()) {
            (Some(missing), [only]) => self.scan.damage[*only].lost_messages = Some(missing),
            _ => {
                let kind = DamageKind::CountMismatch { expected, read, source: "statistics".to_string() };
                self.damage(8, None, kind, missing);
            }
        }
    }
}

/// The most uncompressed bytes a chunk of `compressed_size` bytes may claim (see the limits above).
pub fn chunk_size_limit(compressed_size: u64) -> u64 {
    MAX_CHUNK_UNCOMPRESSED_SIZE.min(CHUNK_EXPANSION_FREE_SIZE.max(compressed_size.saturating_mul(MAX_CHUNK_EXPANSION)))
}

/// The crate's reader of the data section's top-level records, from the file's start (magic and data-section
/// CRC checked) or from a record after a jump.
fn top_level_reader(from_start: bool) -> LinearReader {
    LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_skip_start_magic(!from_start)
            .with_validate_data_section_crc(from_start)
            .with_emit_chunks(true)
            .with_skip_end_magic(true)
            .with_record_length_limit(usize::try_from(MAX_RECORD_SIZE).unwrap_or(usize::MAX)),
    )
}

/// Checks the header of the chunk record `record` (its body) against the limits, before anything is
/// decompressed: Ok(compression, uncompressed size) if it may be decoded.
fn check_chunk_header(record: &[u8]) -> Result<(String, u64), DamageKind> {
    let fail = |reason: String| DamageKind::ChunkUndecodable { reason };
    let header = match mcap::parse_record(op::CHUNK, record) {
        Ok(Record::Chunk { header, .. }) => header,
        Ok(_) => return Err(fail("not a chunk".to_string())),
        Err(e) => return Err(fail(format!("its header does not parse: {e}"))),
    };
    let (compression, uncompressed_size, records_len) =
        (header.compression, header.uncompressed_size, header.compressed_size);
    // 40 bytes of fixed fields, then the compression name, then the records.
    let body_left = (record.len() - 40 - compression.len()) as u64;
    if records_len != body_left {
        return Err(fail(format!("its records claim {records_len} bytes where the record holds {body_left}")));
    }
    let limit = chunk_size_limit(records_len);
    if uncompressed_size > limit {
        return Err(DamageKind::ChunkTooLarge { uncompressed_size, compressed_size: records_len, limit });
    }
    if compression.is_empty() && uncompressed_size != records_len {
        return Err(fail(format!("an uncompressed chunk of {records_len} bytes that claims {uncompressed_size}")));
    }
    if !matches!(compression.as_str(), "" | "zstd" | "lz4") {
        return Err(fail(format!("unsupported compression {compression:?}")));
    }
    Ok((compression, uncompressed_size))
}

/// Decodes the chunk record `record` (its body) into `chunk`, with (opcode, body start, body end) of each of its
/// records in `spans`, once its header has passed [`check_chunk_header`]: decompression, CRC and record
/// framing by the crate (the whole chunk is decompressed and its CRC checked before any record is taken), every
/// record checked to parse. Ok: its compression.
fn decode_chunk(
    decoder: &mut Option<(usize, LinearReader)>,
    record: &[u8],
    chunk: &mut Vec<u8>,
    spans: &mut Vec<(u8, usize, usize)>,
) -> Result<String, DamageKind> {
    let length = record.len() as u64;
    let (compression, uncompressed_size) = check_chunk_header(record)?;
    let fail = |reason: String| DamageKind::ChunkUndecodable { reason };
    chunk.clear();
    spans.clear();
    // The record length limit bounds what a lying record inside the chunk can make the crate allocate.
    let class = usize::try_from(uncompressed_size.max(length)).unwrap_or(usize::MAX).checked_next_power_of_two();
    let class = class.unwrap_or(usize::MAX);
    if decoder.as_ref().is_none_or(|(c, _)| *c != class) {
        let options = LinearReaderOptions::default()
            .with_skip_start_magic(true)
            .with_skip_end_magic(true)
            .with_prevalidate_chunk_crcs(true)
            .with_record_length_limit(class);
        *decoder = Some((class, LinearReader::new_with_options(options)));
    }
    let Some((_, reader)) = decoder.as_mut() else { return Err(fail("no decoder".to_string())) };
    let framed = record.len() + FRAME as usize;
    let buf = &mut reader.insert(framed)[..framed];
    buf[0] = op::CHUNK;
    buf[1..FRAME as usize].copy_from_slice(&length.to_le_bytes());
    buf[FRAME as usize..].copy_from_slice(record);
    reader.notify_read(framed);
    let verdict = loop {
        match reader.next_event() {
            // The whole record was given: asking for more means the chunk is read.
            None | Some(Ok(LinearReadEvent::ReadRequest(_))) => break Ok(()),
            Some(Err(mcap::McapError::BadChunkCrc { saved, calculated })) => {
                break Err(DamageKind::ChunkCrc { stored: saved, computed: calculated })
            }
            Some(Err(e)) => break Err(fail(e.to_string())),
            Some(Ok(LinearReadEvent::Record { data, opcode })) => {
                if !matches!(opcode, op::SCHEMA | op::CHANNEL | op::MESSAGE) {
                    break Err(fail(format!(
                        "byte {} of its records starts a record with opcode {opcode:#04x} (a chunk holds only \
                         schemas, channels and messages)",
                        chunk.len() + FRAME as usize * spans.len()
                    )));
                }
                let start = chunk.len();
                chunk.extend_from_slice(data);
                spans.push((opcode, start, chunk.len()));
            }
        }
    };
    let read = (chunk.len() + FRAME as usize * spans.len()) as u64;
    let verdict = verdict.and_then(|()| {
        if read != uncompressed_size {
            return Err(fail(format!("its records end after {read} of its {uncompressed_size} bytes")));
        }
        for (i, &(opcode, s, e)) in spans.iter().enumerate() {
            if let Err(err) = mcap::parse_record(opcode, &chunk[s..e]) {
                return Err(fail(format!("record {i} (opcode {opcode:#04x}) does not parse: {err}")));
            }
        }
        Ok(compression)
    });
    if verdict.is_err() {
        // Left in the middle of a chunk: the next one gets a new decoder.
        *decoder = None;
    }
    verdict
}

/// What an intact summary section tells the reader.
struct SummaryContents {
    /// The chunk index, by offset.
    chunks: Vec<IndexedChunk>,
    /// The statistics' message count.
    statistics: Option<u64>,
    /// Every channel of the file, from the summary's Schema and Channel records.
    channels: BTreeMap<u16, ChannelInfo>,
}

/// Reads and checks the summary section `[start, footer_at)` and the footer record and magic after it
/// (`footer`), through the `mcap` crate's `LinearReader` (record framing, the record size limit, the summary
/// CRC). Ok(Err(reason)) when the summary is damaged.
fn read_summary(
    file: &mut File,
    start: u64,
    footer_at: u64,
    footer: &[u8],
) -> std::io::Result<Result<SummaryContents, String>> {
    file.seek(SeekFrom::Start(start))?;
    // A Data End record (CRC 0: not checked) in front makes the crate start the summary's CRC where it starts.
    let mut data_end = vec![op::DATA_END];
    data_end.extend_from_slice(&4u64.to_le_bytes());
    data_end.extend_from_slice(&0u32.to_le_bytes());
    let mut input =
        data_end.chain(BufReader::with_capacity(64 * 1024, Read::by_ref(file).take(footer_at - start))).chain(footer);
    let options = LinearReaderOptions::default()
        .with_skip_start_magic(true)
        .with_validate_summary_section_crc(true)
        .with_record_length_limit(usize::try_from(MAX_RECORD_SIZE).unwrap_or(usize::MAX));
    let mut reader = LinearReader::new_with_options(options);
    let mut chunks = Vec::new();
    let mut statistics = None;
    // The summary's Schema and Channel records, taken in as the data section's are.
    let mut definitions = FileScan::default();
    let mut schemas = BTreeMap::new();
    let mut problem = None;
    // Where the next record starts (the crate reports no offsets; every record is 9 bytes of frame + body).
    let mut pos = start;
    while let Some(event) = reader.next_event() {
        match event {
            Ok(LinearReadEvent::ReadRequest(n)) => {
                let got = read_up_to(&mut input, reader.insert(n))?;
                reader.notify_read(got);
            }
            Ok(LinearReadEvent::Record { opcode: op::DATA_END, .. }) => {}
            Ok(LinearReadEvent::Record { data, opcode }) => {
                let at = pos;
                pos += FRAME + data.len() as u64;
                match mcap::parse_record(opcode, data) {
                    Ok(Record::ChunkIndex(index)) => {
                        // An empty offset map means the writer kept no message index (the specification's "no
                        // message indexing available"): the chunk's count is unknown, not 0.
                        let channels = index.message_index_offsets.len() as u64;
                        let framing = (FRAME + 6) * channels;
                        let messages = index
                            .message_index_length
                            .checked_sub(framing)
                            .filter(|bytes| channels > 0 && bytes % 16 == 0)
                            .map(|bytes| bytes / 16);
                        chunks.push(IndexedChunk { offset: index.chunk_start_offset, messages });
                    }
                    Ok(Record::Statistics(stats)) => statistics = Some(stats.message_count),
                    Ok(record @ (Record::Schema { .. } | Record::Channel(_))) => {
                        take_definition(record, &mut definitions, &mut schemas);
                    }
                    Ok(_) => {}
                    Err(e) => {
                        problem.get_or_insert(format!(
                            "a record (opcode {opcode:#04x}) at offset {at} does not parse: {e}"
                        ));
                    }
                }
            }
            Err(e) => {
                problem = Some(e.to_string());
                break;
            }
        }
    }
    if let Some(reason) = problem {
        return Ok(Err(reason));
    }
    chunks.sort_by_key(|c| c.offset);
    Ok(Ok(SummaryContents { chunks, statistics, channels: definitions.channels }))
}

/// Takes in a schema, channel or metadata record.
fn take_definition(record: Record<'_>, scan: &mut FileScan, schemas: &mut BTreeMap<u16, (String, String, String)>) {
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
            let type_hash = channel.metadata.get("topic_type_hash").cloned().unwrap_or_default();
            scan.channels.entry(channel.id).or_insert(ChannelInfo {
                topic: TopicInfo { name: channel.topic, type_name, schema_text, type_hash, qos },
                schema_encoding,
                message_encoding: channel.message_encoding,
                metadata: channel.metadata,
            });
        }
        Record::Metadata(m) if m.name == "rosbag2" => {
            if let Some(text) = m.metadata.get("serialized_metadata") {
                scan.rosbag2_metadata = Some(text.clone());
            }
        }
        _ => {}
    }
}

/// A streaming reader of a whole bag (a directory of split files, or one file): every file is checked to be
/// a regular MCAP file when the bag is opened, then read one after the other, one chunk in memory at a time.
///
/// A directory's files are those its `metadata.yaml` lists ([`bag_listing`]): a listed file that is missing
/// is damage ([`DamageKind::MissingFile`], in a scan of its own, with the messages `metadata.yaml` counted in
/// it as lost); an unlisted `.mcap` is left out ([`BagReader::stray`]).
pub struct BagReader {
    files: std::vec::IntoIter<ListedFile>,
    current: Option<FileReader>,
    scans: Vec<FileScan>,
    stray: Vec<PathBuf>,
    duplicates: Vec<DuplicateListing>,
}

impl BagReader {
    /// Opens a bag; refuses it if any of its files is not a regular file starting with the MCAP magic, or a
    /// directory without a readable `metadata.yaml`.
    pub fn open(path: &Path) -> Result<BagReader, BagError> {
        let listing = bag_listing(path)?;
        for file in listing.files.iter().filter(|f| f.present) {
            open_mcap(&file.path)?;
        }
        Ok(BagReader {
            files: listing.files.into_iter(),
            current: None,
            scans: Vec::new(),
            stray: listing.stray,
            duplicates: listing.duplicates,
        })
    }

    /// The `.mcap` files of the directory that `metadata.yaml` does not list: left out.
    pub fn stray(&self) -> &[PathBuf] {
        &self.stray
    }

    /// The files `metadata.yaml` lists more than once: read once.
    pub fn duplicates(&self) -> &[DuplicateListing] {
        &self.duplicates
    }

    /// The next message in file order (files in split order), or None at the end of the bag.
    pub fn next_message(&mut self) -> Result<Option<MessageRef<'_>>, BagError> {
        loop {
            match self.current.as_mut() {
                Some(reader) => {
                    if reader.advance()? {
                        break;
                    }
                    if let Some(reader) = self.current.take() {
                        self.scans.push(reader.finish()?);
                    }
                }
                None => match self.files.next() {
                    Some(file) if file.present => self.current = Some(FileReader::open(&file.path)?),
                    Some(file) => self.scans.push(missing_file_scan(&file)),
                    None => return Ok(None),
                },
            }
        }
        Ok(self.current.as_ref().and_then(FileReader::message))
    }

    /// Scans of the files read to their end so far.
    pub fn scans(&self) -> &[FileScan] {
        &self.scans
    }

    /// Damage found so far, in order (files read to their end, then the file being read).
    pub fn damage(&self) -> impl Iterator<Item = &Damage> {
        self.scans.iter().chain(self.current.as_ref().map(FileReader::scan)).flat_map(|s| s.damage.iter())
    }

    /// Reads whatever is left and returns the scans of every file.
    pub fn finish(mut self) -> Result<Vec<FileScan>, BagError> {
        while self.next_message()?.is_some() {}
        Ok(self.scans)
    }
}

/// The scan of a listed file that is missing: no messages, one damage naming it.
fn missing_file_scan(file: &ListedFile) -> FileScan {
    let damage = Damage {
        file: file.path.clone(),
        offset: 0,
        chunk: None,
        kind: DamageKind::MissingFile,
        lost_messages: file.message_count,
    };
    FileScan { path: file.path.clone(), damage: vec![damage], ..FileScan::default() }
}

/// Scans one MCAP file from start to end, calling `on_message` for every message of every intact chunk (or
/// unchunked message). Damage is in the returned scan, not an error: errors are for files that cannot be
/// read at all (I/O, not a regular file, not MCAP).
pub fn scan_file(path: &Path, mut on_message: impl FnMut(MessageRef<'_>)) -> Result<FileScan, BagError> {
    let mut reader = FileReader::open(path)?;
    while reader.advance()? {
        if let Some(message) = reader.message() {
            on_message(message);
        }
    }
    reader.finish()
}

/// Reads every message of a bag (directory or file), in file order then record order, streaming. Damage is in
/// the returned scans ([`FileScan::damage`]); callers that must not go on past damage check them.
pub fn read_bag(path: &Path, mut on_message: impl FnMut(MessageRef<'_>)) -> Result<Vec<FileScan>, BagError> {
    let mut reader = BagReader::open(path)?;
    while let Some(message) = reader.next_message()? {
        on_message(message);
    }
    reader.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    /// A record as the MCAP specification frames it: opcode, u64 length, body.
    fn record(opcode: u8, body: &[u8]) -> Vec<u8> {
        let mut out = vec![opcode];
        out.extend_from_slice(&(body.len() as u64).to_le_bytes());
        out.extend_from_slice(body);
        out
    }

    fn string(s: &str) -> Vec<u8> {
        let mut out = (s.len() as u32).to_le_bytes().to_vec();
        out.extend_from_slice(s.as_bytes());
        out
    }

    fn message(sequence: u32, data: &[u8]) -> Vec<u8> {
        let mut body = 1u16.to_le_bytes().to_vec();
        body.extend_from_slice(&sequence.to_le_bytes());
        body.extend_from_slice(&u64::from(sequence).to_le_bytes());
        body.extend_from_slice(&u64::from(sequence).to_le_bytes());
        body.extend_from_slice(data);
        record(op::MESSAGE, &body)
    }

    #[test]
    fn attachments_are_skipped_and_every_message_around_them_is_read() {
        let dir = tempfile::tempdir().unwrap();
        for chunked in [true, false] {
            let path = dir.path().join(format!("{chunked}.mcap"));
            let file = std::io::BufWriter::new(File::create(&path).unwrap());
            let mut w = mcap::WriteOptions::new().use_chunks(chunked).chunk_size(Some(2048)).create(file).unwrap();
            let schema = w.add_schema("std_msgs/msg/String", "ros2msg", b"string data\n").unwrap();
            let channel = w.add_channel(schema, "/t", "cdr", &BTreeMap::new()).unwrap();
            for i in 0..400u32 {
                if i % 100 == 50 {
                    let data = std::borrow::Cow::Owned(vec![7; 100_000]);
                    let name = format!("a{i}");
                    let media_type = "application/octet-stream".to_string();
                    w.attach(&mcap::Attachment { log_time: 0, create_time: 0, name, media_type, data }).unwrap();
                }
                let header = mcap::records::MessageHeader {
                    channel_id: channel,
                    sequence: i,
                    log_time: u64::from(i),
                    publish_time: u64::from(i),
                };
                w.write_to_known_channel(&header, &i.to_le_bytes().repeat(50)).unwrap();
            }
            w.finish().unwrap();
            drop(w);
            let mut seen = Vec::new();
            let scan = scan_file(&path, |m| seen.push((m.sequence, m.log_time_ns, m.data.to_vec()))).unwrap();
            assert!(scan.damage.is_empty() && scan.complete, "{:?}", scan.damage);
            let written: Vec<_> = (0..400u32).map(|i| (i, u64::from(i), i.to_le_bytes().repeat(50))).collect();
            assert_eq!(seen, written);
            assert_eq!(scan.expected_messages, Some(400));
            if chunked {
                assert!(scan.chunks > 10, "{}", scan.chunks);
            } else {
                assert_eq!((scan.chunks, scan.unchunked_messages), (0, 400));
            }
        }
    }

    #[test]
    fn records_over_the_size_limit_are_skipped_unread_and_named_unless_attachments() {
        // An unfinished file (no summary) written by hand: an attachment and a metadata record that claim 300 MiB
        // each (a hole in a sparse file) between three messages.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.mcap");
        let mut file = File::create(&path).unwrap();
        let huge = 300u64 << 20;
        let mut head = MCAP_MAGIC.to_vec();
        head.extend(record(op::HEADER, &[string("ros2"), string("hand")].concat()));
        let schema = [&1u16.to_le_bytes()[..], &string("std_msgs/msg/String"), &string("ros2msg"), &string("")];
        head.extend(record(op::SCHEMA, &schema.concat()));
        let channel =
            [&1u16.to_le_bytes()[..], &1u16.to_le_bytes(), &string("/t"), &string("cdr"), &0u32.to_le_bytes()];
        head.extend(record(op::CHANNEL, &channel.concat()));
        head.extend(message(0, b"zero"));
        let metadata_at = head.len() as u64;
        for (i, opcode) in [op::ATTACHMENT, op::METADATA].into_iter().enumerate() {
            file.write_all(&head).unwrap();
            file.write_all(&[opcode]).unwrap();
            file.write_all(&huge.to_le_bytes()).unwrap();
            file.seek(SeekFrom::Current(huge as i64)).unwrap();
            head = message(i as u32 + 1, b"after");
        }
        file.write_all(&head).unwrap();
        drop(file);
        let mut seen = Vec::new();
        let scan = scan_file(&path, |m| seen.push((m.sequence, m.data.to_vec()))).unwrap();
        assert_eq!(seen, vec![(0, b"zero".to_vec()), (1, b"after".to_vec()), (2, b"after".to_vec())]);
        assert_eq!((scan.complete, scan.truncated_bytes, scan.profile.as_str()), (false, 0, "ros2"));
        // Only the metadata record is damage: where it was, what it claimed, where reading went on.
        let metadata_at = metadata_at + FRAME + huge + message(1, b"after").len() as u64;
        assert_eq!(scan.damage.len(), 1, "{:?}", scan.damage);
        let damage = &scan.damage[0];
        assert_eq!(damage.offset, metadata_at);
        match &damage.kind {
            DamageKind::Unparsable { reason, resumed_at, chunks_skipped: 0 } => {
                assert!(reason.contains(&format!("of {huge} bytes, over the")), "{reason}");
                assert_eq!(*resumed_at, Some(metadata_at + FRAME + huge));
            }
            other => panic!("{other:?}"),
        }
    }
}
