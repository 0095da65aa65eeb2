//! The file side of recording: one rosbag2 directory, its split MCAP files and their metadata. The
//! [`super::Recorder`] drives it from its writer thread.
//!
//! Each MCAP file is written by `mcap::Writer` (records, chunks, compression, message and chunk indexes,
//! summary, CRCs). What this file adds is what the crate does not do: the rosbag2 directory with its
//! `metadata.yaml` and the `rosbag2` Metadata record in every file, splitting files by size or duration,
//! mapping rosbag2's storage presets onto the crate's options, and starting the disk's writeback with
//! `sync_file_range` as the file grows. Chunks are compressed on the writer thread by `mcap::Writer`;
//! [`StorageOptions::compression_threads`] gives zstd its own workers inside each chunk.
//!
//! Cost, measured (`mcap::Writer` alone on the node's per-swing mix of Swing + ExitVelocity + ModalEnergies,
//! 756 B of CDR per swing, fed from one thread): zstd level 1 in 1 MiB chunks 1,160 ns of CPU per message,
//! unchunked 315 ns. At the node's highest sustained rate with recording (40,000 swings/s = 120,000
//! messages/s) that is 0.14 of a core on the writer thread, so recording does not limit the node.
//! `examples/recorder_cpu` measures the whole recorder per message.
//!
//! Chunks are built in memory and reach the file whole (`disable_seeking`), so a crash leaves complete chunks
//! and at most a cut-off tail. Schema and Channel records get a small chunk of their own, written before any
//! message of their topics (`declare_topics` says why); unchunked files ([`McapLayout::Unchunked`], rosbag2's
//! `fastwrite`) get them and every message as top-level records, with no chunk, message index or compression.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use mcap::records::MessageHeader;

use super::rosbag2::{self, BagMetadata, FileEntry};
use super::{BagError, ChunkCompression, McapLayout, StorageOptions, TopicId, TopicInfo};

/// The MCAP `library` string, so a reader can tell who wrote a file.
pub const LIBRARY: &str = concat!("sweetspot ", env!("CARGO_PKG_VERSION"));
/// Default target uncompressed chunk size; chunks also close on every flush.
pub const CHUNK_SIZE: u64 = 1024 * 1024;

/// The MCAP channel id of a topic: ids start at 1 like `mcap::Writer`'s, so the id is the same in every file.
fn channel_id(topic: u16) -> u16 {
    topic + 1
}

/// The channel metadata rosbag2 writes for a topic.
fn channel_metadata(topic: &TopicInfo) -> BTreeMap<String, String> {
    BTreeMap::from([
        ("offered_qos_profiles".to_string(), rosbag2::offered_qos_profiles_yaml(&topic.qos)),
        // Jazzy writes the key even when the publisher announced no type hash (empty); so do we.
        ("topic_type_hash".to_string(), topic.type_hash.clone()),
    ])
}

/// Messages waiting to be written, in arrival order: each one's topic, sequence number and times, with the
/// bytes of all of them in one buffer. Filling it is one copy of the bytes; the writer frames them.
#[derive(Debug, Default)]
pub struct Batch {
    data: Vec<u8>,
    entries: Vec<BatchEntry>,
}

#[derive(Debug, Clone, Copy)]
struct BatchEntry {
    topic: u16,
    sequence: u32,
    log_time: u64,
    publish_time: u64,
    /// End of the message's bytes in `data`; they start where the previous message's end.
    end: usize,
}

impl Batch {
    /// Appends one message (CDR bytes with their encapsulation header) of topic `topic`.
    pub fn push(&mut self, topic: TopicId, sequence: u32, log_time_ns: u64, publish_time_ns: u64, data: &[u8]) {
        self.data.extend_from_slice(data);
        self.entries.push(BatchEntry {
            topic: topic.0,
            sequence,
            log_time: log_time_ns,
            publish_time: publish_time_ns,
            end: self.data.len(),
        });
    }

    /// Messages in the batch.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the batch holds no message.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Message payload bytes held (CDR, as [`super::RecorderStats::bytes`] counts them).
    pub fn payload_bytes(&self) -> u64 {
        self.data.len() as u64
    }

    /// Payload bytes of the first `count` messages.
    pub fn payload_bytes_of(&self, count: usize) -> u64 {
        match count.checked_sub(1) {
            None => 0,
            Some(last) => self.entries.get(last).map_or(self.data.len(), |e| e.end) as u64,
        }
    }

    /// Empties the batch, keeping its buffers for reuse.
    pub fn clear(&mut self) {
        self.data.clear();
        self.entries.clear();
    }

    /// Message `index`: its entry and its bytes.
    fn message(&self, index: usize) -> (BatchEntry, &[u8]) {
        let entry = self.entries[index];
        let start = index.checked_sub(1).map_or(0, |previous| self.entries[previous].end);
        (entry, &self.data[start..entry.end])
    }
}

/// The file under `mcap::Writer`: buffered, counting its bytes (the crate asks for its position instead of
/// seeking, and the size split reads the count), and starting writeback as bytes reach the OS.
struct FileSink {
    out: BufWriter<File>,
    /// Bytes written so far, buffered ones included.
    position: u64,
    /// `position`, for the [`BagWriter`] that owns the `mcap::Writer` owning this sink.
    size: Arc<AtomicU64>,
    /// Bytes up to here have been handed to the disk's writeback (see [`start_writeback`]).
    writeback_from: u64,
    /// Writeback starts once this many more bytes have reached the OS.
    writeback_stride: u64,
}

impl FileSink {
    /// Starts writeback of what reached the OS since the last call: the disk works on it while the next
    /// chunks fill, the fsync at close finds little left, and a power cut loses less.
    fn start_writeback(&mut self) {
        let handed_over = self.position - self.out.buffer().len() as u64;
        if handed_over > self.writeback_from {
            start_writeback(self.out.get_ref(), self.writeback_from, handed_over - self.writeback_from);
            self.writeback_from = handed_over;
        }
    }
}

impl Write for FileSink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let written = self.out.write(buf)?;
        self.position += written as u64;
        self.size.store(self.position, Ordering::Relaxed);
        let handed_over = self.position - self.out.buffer().len() as u64;
        if handed_over - self.writeback_from >= self.writeback_stride {
            self.start_writeback();
        }
        Ok(written)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()?;
        self.start_writeback();
        Ok(())
    }
}

impl Seek for FileSink {
    /// Only tells the position: with `disable_seeking`, that is all `mcap::Writer` asks of the file.
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        match pos {
            SeekFrom::Current(0) => Ok(self.position),
            _ => Err(std::io::Error::new(std::io::ErrorKind::Unsupported, "bag files are only appended to")),
        }
    }

    fn stream_position(&mut self) -> std::io::Result<u64> {
        Ok(self.position)
    }
}

/// The file currently being written.
struct OpenFile {
    mcap: mcap::Writer<FileSink>,
    path: PathBuf,
    entry: FileEntry,
    /// Bytes written so far (shared with the file's [`FileSink`]).
    size: Arc<AtomicU64>,
    /// Topics `0..declared` have their Schema and Channel records in this file.
    declared: usize,
    /// Whether the file is chunked (definitions then get a chunk of their own).
    chunked: bool,
    /// The open chunk holds Schema and Channel records and no message: it is closed before the next message.
    definitions_open: bool,
    /// Messages written since the last flush.
    dirty: bool,
}

/// Writes one rosbag2 directory: `<dir>/<dirname>_N.mcap` files plus `metadata.yaml`.
pub struct BagWriter {
    dir: PathBuf,
    max_file_size: Option<u64>,
    max_file_duration_ns: Option<u64>,
    chunk_size: u64,
    layout: McapLayout,
    options: mcap::WriteOptions,
    topics: Vec<TopicInfo>,
    topic_counts: Vec<u64>,
    sequences: Vec<u32>,
    closed_files: Vec<FileEntry>,
    current: Option<OpenFile>,
    next_index: usize,
    ros_distro: String,
    custom_data: BTreeMap<String, String>,
    /// Reused by [`Self::write`].
    single: Batch,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> BagError + '_ {
    move |source| BagError::Io { path: path.to_path_buf(), source }
}

fn mcap_err(path: &Path) -> impl FnOnce(mcap::McapError) -> BagError + '_ {
    move |err| match err {
        mcap::McapError::Io(source) => BagError::Io { path: path.to_path_buf(), source },
        other => BagError::Mcap(format!("{}: {other}", path.display())),
    }
}

/// `mcap::Writer`'s options for `storage`, chunks of `chunk_size` bytes.
fn write_options(storage: &StorageOptions, chunk_size: u64) -> mcap::WriteOptions {
    let options = mcap::WriteOptions::new()
        .profile("ros2")
        .library(LIBRARY)
        // Chunks are built in memory and written whole, never patched in place.
        .disable_seeking(true);
    if storage.layout == McapLayout::Unchunked {
        return options.use_chunks(false).compression(None);
    }
    let threads = storage.compression_threads.map_or(0, |n| u32::try_from(n).unwrap_or(u32::MAX));
    let options = options.chunk_size(Some(chunk_size)).compression_threads(threads);
    match storage.compression {
        // mcap::Writer hands the level to zstd as an i32 again, so negative ("fast") levels survive the cast.
        ChunkCompression::Zstd { level } => {
            options.compression(Some(mcap::Compression::Zstd)).compression_level(level as u32)
        }
        ChunkCompression::Lz4 => options.compression(Some(mcap::Compression::Lz4)),
        ChunkCompression::None => options.compression(None),
    }
}

impl BagWriter {
    /// Creates `dir` (which must not exist yet; parents are created) and opens its first file, with
    /// zstd chunks.
    pub fn create(
        dir: &Path,
        max_file_size: Option<u64>,
        max_file_duration: Option<Duration>,
    ) -> Result<Self, BagError> {
        Self::create_with(dir, max_file_size, max_file_duration, StorageOptions::default())
    }

    /// Like [`Self::create`], with the layout, chunk compression and chunk size of `storage`.
    pub fn create_with(
        dir: &Path,
        max_file_size: Option<u64>,
        max_file_duration: Option<Duration>,
        storage: StorageOptions,
    ) -> Result<Self, BagError> {
        // Checked here too, for options not built through StorageOptions::with_compression.
        let storage = storage.with_compression(storage.compression)?;
        if storage.chunk_size == Some(0) {
            return Err(BagError::Format("chunk_size must be > 0".to_string()));
        }
        // Chunks must be well under the split size, or a file could not be seen growing before it closes.
        // (Unchunked files use it only as the stride of the early writeback.)
        let chunk_size = match max_file_size {
            Some(max) => storage.chunk_size.unwrap_or(CHUNK_SIZE).min((max / 4).max(1024)),
            None => storage.chunk_size.unwrap_or(CHUNK_SIZE),
        };
        if let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        std::fs::create_dir(dir).map_err(io_err(dir))?;
        let mut writer = BagWriter {
            dir: dir.to_path_buf(),
            max_file_size,
            max_file_duration_ns: max_file_duration.map(|limit| u64::try_from(limit.as_nanos()).unwrap_or(u64::MAX)),
            chunk_size,
            layout: storage.layout,
            options: write_options(&storage, chunk_size),
            topics: Vec::new(),
            topic_counts: Vec::new(),
            sequences: Vec::new(),
            closed_files: Vec::new(),
            current: None,
            next_index: 0,
            ros_distro: rosbag2::ros_distro(),
            custom_data: BTreeMap::new(),
            single: Batch::default(),
        };
        writer.open_next_file()?;
        Ok(writer)
    }

    /// The bag directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Registered topics, indexed by [`TopicId`].
    pub fn topics(&self) -> &[TopicInfo] {
        &self.topics
    }

    /// Declares a topic (schema + channel) in the open file and every later split.
    pub fn add_topic(&mut self, topic: TopicInfo) -> Result<TopicId, BagError> {
        // Channel ids are topic index + 1, so 65535 topics at most.
        let id = u16::try_from(self.topics.len())
            .ok()
            .filter(|&id| id < u16::MAX)
            .ok_or_else(|| BagError::Format("more than 65535 topics".to_string()))?;
        self.topics.push(topic);
        self.topic_counts.push(0);
        self.sequences.push(0);
        if let Some(file) = self.current.as_mut() {
            declare_topics(file, &self.topics)?;
        }
        Ok(TopicId(id))
    }

    /// Writes one message (CDR with its encapsulation header), numbering it in its topic's sequence.
    pub fn write(&mut self, id: TopicId, cdr: &[u8], log_time_ns: u64, publish_time_ns: u64) -> Result<(), BagError> {
        let index = usize::from(id.0);
        if index >= self.topics.len() {
            return Err(BagError::Format(format!("unknown topic id {}", id.0)));
        }
        self.sequences[index] = self.sequences[index].wrapping_add(1);
        let mut single = std::mem::take(&mut self.single);
        single.clear();
        single.push(id, self.sequences[index], log_time_ns, publish_time_ns, cdr);
        let (_, result) = self.write_batch(&single);
        self.single = single;
        result
    }

    /// Writes a batch of messages in order, splitting files by duration (before the message that would
    /// exceed it) and by size (after the chunk, or in an unchunked file the message, that reached it).
    /// Returns how many messages were written, and the error that stopped it, if any.
    pub fn write_batch(&mut self, batch: &Batch) -> (usize, Result<(), BagError>) {
        for index in 0..batch.len() {
            let (entry, data) = batch.message(index);
            if let Err(err) = self.write_message(entry, data) {
                return (index, Err(err));
            }
        }
        (batch.len(), Ok(()))
    }

    fn write_message(&mut self, message: BatchEntry, data: &[u8]) -> Result<(), BagError> {
        let topic = usize::from(message.topic);
        if topic >= self.topics.len() {
            return Err(BagError::Format(format!("unknown topic id {}", message.topic)));
        }
        self.ready_file_for(message.log_time)?;
        let Some(file) = self.current.as_mut() else {
            return Err(BagError::Format("no open file".to_string()));
        };
        if file.definitions_open {
            file.mcap.flush().map_err(mcap_err(&file.path))?;
            file.definitions_open = false;
        }
        let header = MessageHeader {
            channel_id: channel_id(message.topic),
            sequence: message.sequence,
            log_time: message.log_time,
            publish_time: message.publish_time,
        };
        file.mcap.write_to_known_channel(&header, data).map_err(mcap_err(&file.path))?;
        count_message(&mut file.entry, message.log_time);
        file.dirty = true;
        self.topic_counts[topic] += 1;
        // A chunked file grows a chunk at a time, so this splits after the chunk that reached the size.
        if self.max_file_size.is_some_and(|max| file.size.load(Ordering::Relaxed) >= max) {
            self.split()?;
        }
        Ok(())
    }

    /// Makes `self.current` the file a message logged at `log_time` goes to: splits when the open file's
    /// duration would reach the limit, opens the next file if none is open, and declares the topics it
    /// lacks (an earlier declaration may have failed).
    fn ready_file_for(&mut self, log_time: u64) -> Result<(), BagError> {
        if let (Some(limit_ns), Some(file)) = (self.max_file_duration_ns, self.current.as_ref()) {
            if file.entry.message_count > 0 && log_time.saturating_sub(file.entry.start_ns) >= limit_ns {
                self.split()?;
            }
        }
        if self.current.is_none() {
            self.open_next_file()?;
        }
        if let Some(file) = self.current.as_mut() {
            if file.declared < self.topics.len() {
                declare_topics(file, &self.topics)?;
            }
        }
        Ok(())
    }

    /// Sets rosbag2 `custom_data` entries (kept in every later `rosbag2` record and in metadata.yaml).
    pub fn set_custom_data(&mut self, custom_data: BTreeMap<String, String>) {
        self.custom_data = custom_data;
    }

    /// Whether messages were written since the last [`Self::flush`].
    pub fn is_dirty(&self) -> bool {
        self.current.as_ref().is_some_and(|f| f.dirty)
    }

    /// Closes the open chunk and hands everything to the OS, so a crash of this process loses nothing
    /// written so far.
    pub fn flush(&mut self) -> Result<(), BagError> {
        if let Some(file) = self.current.as_mut() {
            file.mcap.flush().map_err(mcap_err(&file.path))?;
            file.dirty = false;
            file.definitions_open = false;
        }
        Ok(())
    }

    /// The metadata as of now (open file included).
    pub fn metadata(&self) -> BagMetadata {
        let mut files = self.closed_files.clone();
        if let Some(file) = &self.current {
            files.push(file.entry.clone());
        }
        BagMetadata {
            topics: self.topics.iter().cloned().zip(self.topic_counts.iter().copied()).collect(),
            files,
            compression_format: String::new(),
            ros_distro: self.ros_distro.clone(),
            custom_data: self.custom_data.clone(),
        }
    }

    /// Closes the open file (with its `rosbag2` metadata record and summary) and starts the next one lazily.
    pub fn split(&mut self) -> Result<(), BagError> {
        self.close_current()?;
        self.metadata().write_to_dir(&self.dir)
    }

    /// Closes the last file and writes `metadata.yaml`. Returns the final metadata.
    pub fn finish(mut self) -> Result<BagMetadata, BagError> {
        let closed = self.close_current();
        let metadata = self.metadata();
        let written = metadata.write_to_dir(&self.dir);
        closed?;
        written?;
        Ok(metadata)
    }

    fn open_next_file(&mut self) -> Result<(), BagError> {
        let name = rosbag2::file_name(&self.dir, self.next_index);
        let path = self.dir.join(&name);
        let out = File::create(&path).map_err(io_err(&path))?;
        self.next_index += 1;
        // Unchunked files get every message as its own small writes: buffering a chunk's worth turns those
        // into writes as large as a chunked file's, which measured ~10 % faster for 84-byte messages.
        let buffer = match self.layout {
            McapLayout::Chunked => 64 * 1024,
            McapLayout::Unchunked => self.chunk_size.clamp(64 * 1024, CHUNK_SIZE) as usize,
        };
        let size = Arc::new(AtomicU64::new(0));
        let sink = FileSink {
            out: BufWriter::with_capacity(buffer, out),
            position: 0,
            size: size.clone(),
            writeback_from: 0,
            writeback_stride: self.chunk_size,
        };
        let mcap = self.options.clone().create(sink).map_err(mcap_err(&path))?;
        let mut file = OpenFile {
            mcap,
            path,
            entry: FileEntry { path: name, ..FileEntry::default() },
            size,
            declared: 0,
            chunked: self.layout == McapLayout::Chunked,
            definitions_open: false,
            dirty: false,
        };
        // Kept open even on error, so that close_current lists the file and later writes report failure.
        let declared = declare_topics(&mut file, &self.topics);
        self.current = Some(file);
        declared
    }

    fn close_current(&mut self) -> Result<(), BagError> {
        let Some(mut file) = self.current.take() else { return Ok(()) };
        // The entry is listed even if closing fails: the bytes that made it to disk are recoverable.
        self.closed_files.push(file.entry.clone());
        let rosbag2 = mcap::records::Metadata {
            name: "rosbag2".to_string(),
            metadata: BTreeMap::from([("serialized_metadata".to_string(), self.metadata().to_yaml_body(0))]),
        };
        file.mcap.write_metadata(&rosbag2).map_err(mcap_err(&file.path))?;
        file.mcap.finish().map_err(mcap_err(&file.path))?;
        let sink = file.mcap.into_inner();
        let out =
            sink.out.into_inner().map_err(|e| BagError::Io { path: file.path.clone(), source: e.into_error() })?;
        out.sync_all().map_err(io_err(&file.path))?;
        Ok(())
    }
}

/// Counts one message logged at `log_time` in its file's metadata.yaml entry.
fn count_message(entry: &mut FileEntry, log_time: u64) {
    if entry.message_count == 0 {
        entry.start_ns = log_time;
        entry.duration_ns = 0;
    } else if log_time < entry.start_ns {
        entry.duration_ns += entry.start_ns - log_time;
        entry.start_ns = log_time;
    } else {
        entry.duration_ns = entry.duration_ns.max(log_time - entry.start_ns);
    }
    entry.message_count += 1;
}

/// Declares in `file` the topics it lacks: a Schema record (encoding `ros2msg`, full dependency text) per
/// distinct type and a Channel record (encoding `cdr`, rosbag2's channel metadata) per topic.
///
/// In a chunked file the records go into a chunk of their own: the chunk holding messages is closed first, and
/// the definitions chunk before the next message ([`BagWriter::write_message`]). `mcap::Writer` would put them
/// into whatever chunk is open, among messages; a reader of a file cut off by a crash (no summary) finds a
/// channel's definition only there, so one damaged bit in that chunk would cost every message of the file
/// instead of the chunk's own. A definitions chunk is a few KiB and damage to a message chunk leaves it whole.
fn declare_topics(file: &mut OpenFile, topics: &[TopicInfo]) -> Result<(), BagError> {
    if file.declared == topics.len() {
        return Ok(());
    }
    if file.chunked && file.dirty && !file.definitions_open {
        // Messages may be in the open chunk (flush closes it; one the crate closed on size leaves nothing open).
        file.mcap.flush().map_err(mcap_err(&file.path))?;
        file.dirty = false;
    }
    file.definitions_open = file.chunked;
    while file.declared < topics.len() {
        let index = file.declared;
        let topic = &topics[index];
        let schema = file
            .mcap
            .add_schema(&topic.type_name, "ros2msg", topic.schema_text.as_bytes())
            .map_err(mcap_err(&file.path))?;
        // The channel id is fixed (topic index + 1) rather than assigned, so it is the same in every split.
        file.mcap
            .add_channel_with_id(channel_id(index as u16), schema, &topic.name, "cdr", &channel_metadata(topic))
            .map_err(mcap_err(&file.path))?;
        file.declared += 1;
    }
    Ok(())
}

/// Starts writeback of `len` bytes from `offset` without waiting for it to complete (Linux
/// `sync_file_range(SYNC_FILE_RANGE_WRITE)`; durability still comes from the fsync at close). Best effort:
/// an error here only means the fsync at close does the work.
#[cfg(target_os = "linux")]
fn start_writeback(file: &File, offset: u64, len: u64) {
    use std::os::fd::AsRawFd;
    let (Ok(offset), Ok(len)) = (i64::try_from(offset), i64::try_from(len)) else { return };
    // SAFETY: a plain syscall on a file descriptor `file` keeps open for the duration of the call; no
    // memory is passed.
    let _ = unsafe { libc::sync_file_range(file.as_raw_fd(), offset, len, libc::SYNC_FILE_RANGE_WRITE) };
}

#[cfg(not(target_os = "linux"))]
fn start_writeback(_file: &File, _offset: u64, _len: u64) {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RecordedQos;

    fn topic(name: &str) -> TopicInfo {
        TopicInfo {
            name: name.to_string(),
            type_name: "std_msgs/msg/String".to_string(),
            schema_text: "string data\n".to_string(),
            qos: RecordedQos { reliable: true, transient_local: false, depth: 10 },
            type_hash: String::new(),
        }
    }

    /// Messages of the file as it is on disk now, read by the `mcap` crate: (channel, sequence, payload). An
    /// open file has no footer, so the stream ends with an error there.
    fn on_disk(path: &Path) -> Vec<(u16, u32, Vec<u8>)> {
        let bytes = std::fs::read(path).unwrap();
        mcap::MessageStream::new(&bytes)
            .unwrap()
            .map_while(Result::ok)
            .map(|m| (m.channel.id, m.sequence, m.data.to_vec()))
            .collect()
    }

    /// What each chunk of the file holds, read by the `mcap` crate: `D` + the topics of a chunk of Schema and
    /// Channel records only, `M` + the channel ids of a chunk of messages only, `mixed` otherwise.
    fn chunk_contents(path: &Path) -> Vec<String> {
        let bytes = std::fs::read(path).unwrap();
        let mut chunks = Vec::new();
        for record in mcap::read::LinearReader::new(&bytes).unwrap() {
            let mcap::records::Record::Chunk { header, data } = record.unwrap() else { continue };
            let (mut topics, mut channels, mut schemas) = (Vec::new(), BTreeMap::<u16, u64>::new(), 0);
            for inner in mcap::read::ChunkReader::new(header, &data).unwrap() {
                match inner.unwrap() {
                    mcap::records::Record::Schema { .. } => schemas += 1,
                    mcap::records::Record::Channel(channel) => topics.push(channel.topic),
                    mcap::records::Record::Message { header, .. } => {
                        *channels.entry(header.channel_id).or_default() += 1
                    }
                    other => panic!("unexpected record in a chunk: {other:?}"),
                }
            }
            chunks.push(match (schemas + topics.len(), channels.is_empty()) {
                (0, false) => format!("M {:?}", channels.keys().collect::<Vec<_>>()),
                (1.., true) => format!("D {}", topics.join(" ")),
                _ => "mixed".to_string(),
            });
        }
        chunks
    }

    #[test]
    fn definitions_get_a_chunk_of_their_own_before_any_message_of_their_topics() {
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("defs");
        let mut writer = BagWriter::create(&dir, None, None).unwrap();
        let a = writer.add_topic(topic("/a")).unwrap();
        let b = writer.add_topic(topic("/b")).unwrap();
        for i in 0..10 {
            writer.write(if i % 2 == 0 { a } else { b }, &[0, 1, 0, 0, i], 1_000, 1_000).unwrap();
        }
        // A topic declared while a chunk of messages is open.
        let c = writer.add_topic(topic("/c")).unwrap();
        writer.write(c, &[0, 1, 0, 0, 7], 2_000, 2_000).unwrap();
        writer.write(a, &[0, 1, 0, 0, 8], 2_000, 2_000).unwrap();
        writer.split().unwrap();
        writer.write(b, &[0, 1, 0, 0, 9], 3_000, 3_000).unwrap();
        writer.finish().unwrap();
        let file = |n| dir.join(rosbag2::file_name(&dir, n));
        assert_eq!(chunk_contents(&file(0)), ["D /a /b", "M [1, 2]", "D /c", "M [1, 3]"]);
        // Every split declares every topic again, in its first chunk.
        assert_eq!(chunk_contents(&file(1)), ["D /a /b /c", "M [2]"]);
    }

    #[test]
    fn each_flush_leaves_every_message_so_far_readable_in_the_open_file() {
        for storage in [StorageOptions::default(), StorageOptions::preset("fastwrite").unwrap()] {
            let root = tempfile::tempdir().unwrap();
            let dir = root.path().join("flushed");
            let mut writer = BagWriter::create_with(&dir, None, None, storage).unwrap();
            let a = writer.add_topic(topic("/a")).unwrap();
            let b = writer.add_topic(topic("/b")).unwrap();
            let path = dir.join(rosbag2::file_name(&dir, 0));
            let mut expected = Vec::new();
            for round in 0..3u8 {
                for i in 0..50u8 {
                    let (id, channel) = if i % 2 == 0 { (a, 1) } else { (b, 2) };
                    let payload = vec![0, 1, 0, 0, round, i];
                    writer.write(id, &payload, 1_000 + u64::from(i), 1_000).unwrap();
                    let sequence = expected.iter().filter(|(c, _, _)| *c == channel).count() as u32 + 1;
                    expected.push((channel, sequence, payload));
                }
                assert!(writer.is_dirty());
                writer.flush().unwrap();
                assert!(!writer.is_dirty());
                assert_eq!(on_disk(&path), expected, "{storage:?}, after flush {round}");
            }
            let metadata = writer.finish().unwrap();
            assert_eq!(metadata.message_count(), 150);
            let summary = mcap::Summary::read(&std::fs::read(&path).unwrap()).unwrap().expect("a finished file");
            let keys: Vec<&str> = summary.channels[&1].metadata.keys().map(String::as_str).collect();
            // rosbag2's MCAP storage plugin writes exactly these channel metadata keys.
            assert_eq!(keys, ["offered_qos_profiles", "topic_type_hash"]);
            assert_eq!(summary.metadata_indexes.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(), ["rosbag2"]);
        }
    }
}
