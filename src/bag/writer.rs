//! The file side of recording: one rosbag2 directory, its split MCAP files and their metadata. The
//! [`super::Recorder`] drives it from its writer thread; the only threads here are the optional chunk
//! compression workers, whose results are written strictly in order.
//!
//! Why this writes MCAP itself and what `mcap::Writer` measured against it (`examples/writer_vs_mcap`, the
//! node's per-swing mix of Swing + ExitVelocity + ModalEnergies, 756 B of CDR per swing, fed from one
//! thread): with zstd level 1 in 1 MiB chunks, `mcap::Writer` costs 1,160 ns of CPU per message on the
//! calling thread against 1,015 ns of process CPU here (180 ns of it on the caller; the rest on the writer
//! thread and compression pool), and 20,500 against 16,100 instructions per message (cachegrind, written and
//! read back); unchunked, 315 against 207 ns (3,630 against 3,180 instructions). At the node's highest
//! sustained rate with recording (40,000 swings/s = 120,000 messages/s) that is 0.14 of a core for
//! `mcap::Writer` against 0.12 here: the crate would hold the rate. What it does not do, and this file does:
//! compress chunks on a pool while the next one fills (its `compression_threads` are zstd's own workers
//! inside one chunk, and the chunk's compression still runs on the caller), take pre-framed batches from
//! many threads under one lock, start writeback with `sync_file_range` as it goes, split files by size or
//! duration, and map rosbag2's storage presets. The records written are the ones `mcap::Writer` writes (same
//! layout, summary, indexes and CRCs); the `mcap` crate (all CRCs checked), the Python `mcap` reader and
//! `rosbags` read the files back in the tests.
//!
//! Unchunked files ([`McapLayout::Unchunked`], rosbag2's `fastwrite`) get each batch's records as they
//! are, in one write: no chunk, no message index, nothing compressed; the summary still lists schemas,
//! channels, statistics and the metadata index, as the mcap C++ writer's `noChunking` does.

use mcap::records::op;
use mcap::MAGIC;
use std::collections::{BTreeMap, VecDeque};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Duration;

use super::rosbag2::{self, BagMetadata, FileEntry};
use super::{BagError, ChunkCompression, McapLayout, StorageOptions, TopicId, TopicInfo};

/// The MCAP `library` string, so a reader can tell who wrote a file.
pub const LIBRARY: &str = concat!("sweetspot ", env!("CARGO_PKG_VERSION"));
/// Default target uncompressed chunk size; chunks also close on every flush.
pub const CHUNK_SIZE: u64 = 1024 * 1024;
/// Compression threads used by default: the cores, up to this many.
pub const MAX_COMPRESSION_THREADS: usize = 4;

/// Opcode, record length, channel id, sequence, log time, publish time.
const MESSAGE_RECORD_OVERHEAD: usize = 1 + 8 + 2 + 4 + 8 + 8;

/// The MCAP channel id of a topic: ids start at 1 like `mcap::Writer`'s, so the id is the same in every file.
fn channel_id(topic: u16) -> u16 {
    topic + 1
}

/// Messages already framed as MCAP Message records, in arrival order, with what a chunk's message index
/// needs. Framing happens once, where the message arrives; the writer only copies bytes.
#[derive(Debug, Default)]
pub struct Batch {
    records: Vec<u8>,
    entries: Vec<BatchEntry>,
    payload_bytes: u64,
}

#[derive(Debug, Clone, Copy)]
struct BatchEntry {
    topic: u16,
    log_time: u64,
    start: usize,
}

impl Batch {
    /// Appends one message (CDR bytes with their encapsulation header) of topic `topic`.
    pub fn push(&mut self, topic: TopicId, sequence: u32, log_time_ns: u64, publish_time_ns: u64, data: &[u8]) {
        let start = self.records.len();
        let record_len = (MESSAGE_RECORD_OVERHEAD - 9 + data.len()) as u64;
        let mut head = [0u8; MESSAGE_RECORD_OVERHEAD];
        head[0] = op::MESSAGE;
        head[1..9].copy_from_slice(&record_len.to_le_bytes());
        head[9..11].copy_from_slice(&channel_id(topic.0).to_le_bytes());
        head[11..15].copy_from_slice(&sequence.to_le_bytes());
        head[15..23].copy_from_slice(&log_time_ns.to_le_bytes());
        head[23..31].copy_from_slice(&publish_time_ns.to_le_bytes());
        self.records.reserve(MESSAGE_RECORD_OVERHEAD + data.len());
        self.records.extend_from_slice(&head);
        self.records.extend_from_slice(data);
        self.entries.push(BatchEntry { topic: topic.0, log_time: log_time_ns, start });
        self.payload_bytes += data.len() as u64;
    }

    /// Messages in the batch.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the batch holds no message.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Framed bytes held (what the batch adds to a chunk).
    pub fn framed_bytes(&self) -> usize {
        self.records.len()
    }

    /// Message payload bytes held (CDR, as [`super::RecorderStats::bytes`] counts them).
    pub fn payload_bytes(&self) -> u64 {
        self.payload_bytes
    }

    /// Payload bytes of the first `count` messages.
    pub fn payload_bytes_of(&self, count: usize) -> u64 {
        let framed = self.entries.get(count).map_or(self.records.len(), |e| e.start);
        (framed - count.min(self.entries.len()) * MESSAGE_RECORD_OVERHEAD) as u64
    }

    /// Empties the batch, keeping its buffers for reuse.
    pub fn clear(&mut self) {
        self.records.clear();
        self.entries.clear();
        self.payload_bytes = 0;
    }

    fn record(&self, index: usize) -> &[u8] {
        let start = self.entries[index].start;
        let end = self.entries.get(index + 1).map_or(self.records.len(), |e| e.start);
        &self.records[start..end]
    }
}

/// A chunk index as the summary lists it.
struct ChunkIndexEntry {
    start_ns: u64,
    end_ns: u64,
    chunk_start: u64,
    chunk_length: u64,
    message_index_offsets: Vec<(u16, u64)>,
    message_index_length: u64,
    compression: &'static str,
    compressed_size: u64,
    uncompressed_size: u64,
}

/// The file currently being written.
struct OpenFile {
    out: BufWriter<File>,
    path: PathBuf,
    entry: FileEntry,
    /// Bytes written so far (the offset of the next record).
    position: u64,
    data_crc: crc32fast::Hasher,
    /// Bytes up to here have been handed to the disk's writeback (see [`start_writeback`]).
    writeback_from: u64,
    /// Schema id (from 1) of each declared topic; topics `0..schema_of.len()` are declared in this file.
    schema_of: Vec<u16>,
    /// Schemas declared in this file, by id - 1: the index of the first topic that declared it.
    schemas: Vec<usize>,
    /// The open chunk: framed Message records, and per topic (log time, offset in the chunk).
    chunk: Vec<u8>,
    chunk_index: Vec<Vec<(u64, u64)>>,
    chunk_bounds: Option<(u64, u64)>,
    chunk_indexes: Vec<ChunkIndexEntry>,
    metadata_indexes: Vec<(u64, u64, String)>,
    channel_counts: Vec<u64>,
    bounds: Option<(u64, u64)>,
    /// Messages written since the last flush.
    dirty: bool,
}

impl OpenFile {
    fn put(&mut self, bytes: &[u8]) -> std::io::Result<()> {
        self.out.write_all(bytes)?;
        self.data_crc.update(bytes);
        self.position += bytes.len() as u64;
        Ok(())
    }

    fn put_record(&mut self, op: u8, body: &[u8]) -> std::io::Result<()> {
        let mut head = [0u8; 9];
        head[0] = op;
        head[1..].copy_from_slice(&(body.len() as u64).to_le_bytes());
        self.put(&head)?;
        self.put(body)
    }
}

/// Writes one rosbag2 directory: `<dir>/<dirname>_N.mcap` files plus `metadata.yaml`.
pub struct BagWriter {
    dir: PathBuf,
    max_file_size: Option<u64>,
    max_file_duration: Option<Duration>,
    chunk_size: u64,
    layout: McapLayout,
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
    /// Compresses on this thread when there is no pool (or no compression).
    compressor: ChunkCompressor,
    compressed: Vec<u8>,
    /// Compresses sealed chunks on other threads while this one fills the next; None = inline.
    pool: Option<CompressPool>,
    /// Chunks being compressed, oldest first; written in this order.
    in_flight: VecDeque<InFlight>,
    /// Chunk buffers back from the pool, for reuse.
    spare: Vec<Vec<u8>>,
}

/// Compresses chunks: one zstd context (reused chunk after chunk) or lz4, or nothing.
struct ChunkCompressor {
    compression: ChunkCompression,
    zstd: Option<zstd::bulk::Compressor<'static>>,
}

impl ChunkCompressor {
    fn new(compression: ChunkCompression) -> Result<Self, String> {
        let zstd = match compression {
            ChunkCompression::Zstd { level } => {
                Some(zstd::bulk::Compressor::new(level).map_err(|e| format!("zstd level {level}: {e}"))?)
            }
            _ => None,
        };
        Ok(ChunkCompressor { compression, zstd })
    }

    /// Compresses `records` into `out` (left empty for `none`); returns the MCAP compression name.
    fn compress(&mut self, records: &[u8], out: &mut Vec<u8>) -> Result<&'static str, String> {
        out.clear();
        match self.compression {
            ChunkCompression::None => Ok(""),
            ChunkCompression::Zstd { .. } => {
                let zstd = self.zstd.as_mut().ok_or("internal: no zstd context")?;
                out.reserve(zstd::zstd_safe::compress_bound(records.len()));
                zstd.compress_to_buffer(records, out).map_err(|e| format!("zstd: {e}"))?;
                Ok("zstd")
            }
            ChunkCompression::Lz4 => {
                let mut encoder = lz4::EncoderBuilder::new()
                    // No block checksums, like mcap::Writer: the chunk has its own CRC.
                    .block_checksum(lz4::liblz4::BlockChecksum::NoBlockChecksum)
                    .build(std::mem::take(out))
                    .map_err(|e| format!("lz4: {e}"))?;
                encoder.write_all(records).map_err(|e| format!("lz4: {e}"))?;
                let (buffer, result) = encoder.finish();
                *out = buffer;
                result.map_err(|e| format!("lz4: {e}"))?;
                Ok("lz4")
            }
        }
    }
}

/// A sealed chunk on its way through a compression worker.
struct Job {
    records: Vec<u8>,
    out: Vec<u8>,
    reply: mpsc::SyncSender<JobDone>,
}

struct JobDone {
    records: Vec<u8>,
    out: Vec<u8>,
    crc: u32,
    result: Result<&'static str, String>,
}

/// What the writer keeps of a chunk while it is compressed.
struct InFlight {
    index: Vec<Vec<(u64, u64)>>,
    bounds: (u64, u64),
    reply: mpsc::Receiver<JobDone>,
}

/// Compression worker threads, each with its own context, fed from one queue.
struct CompressPool {
    jobs: Option<crossbeam_channel::Sender<Job>>,
    threads: Vec<std::thread::JoinHandle<()>>,
}

impl CompressPool {
    fn start(compression: ChunkCompression, threads: usize) -> Result<Self, BagError> {
        let (jobs, queue) = crossbeam_channel::unbounded::<Job>();
        let mut handles = Vec::with_capacity(threads);
        for n in 0..threads {
            let mut compressor = ChunkCompressor::new(compression).map_err(BagError::Format)?;
            let queue = queue.clone();
            let handle = std::thread::Builder::new()
                .name(format!("bag-compress-{n}"))
                .spawn(move || {
                    while let Ok(job) = queue.recv() {
                        let Job { records, mut out, reply } = job;
                        let crc = crc32fast::hash(&records);
                        let result = compressor.compress(&records, &mut out);
                        // The writer may have given up on this chunk (its own error); nothing to do then.
                        let _ = reply.send(JobDone { records, out, crc, result });
                    }
                })
                .map_err(|e| BagError::Format(format!("starting a compression thread: {e}")))?;
            handles.push(handle);
        }
        Ok(CompressPool { jobs: Some(jobs), threads: handles })
    }
}

impl Drop for CompressPool {
    fn drop(&mut self) {
        // Closing the queue ends the workers once they finish what they hold.
        self.jobs = None;
        for thread in self.threads.drain(..) {
            let _ = thread.join();
        }
    }
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> BagError + '_ {
    move |source| BagError::Io { path: path.to_path_buf(), source }
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
        let compressor = ChunkCompressor::new(storage.compression).map_err(BagError::Format)?;
        if storage.chunk_size == Some(0) {
            return Err(BagError::Format("chunk_size must be > 0".to_string()));
        }
        // Chunks must be well under the split size, or a file could not be seen growing before it closes.
        // (Unchunked files use it only as the stride of the early writeback.)
        let chunk_size = match max_file_size {
            Some(max) => storage.chunk_size.unwrap_or(CHUNK_SIZE).min((max / 4).max(1024)),
            None => storage.chunk_size.unwrap_or(CHUNK_SIZE),
        };
        // Splitting by size decides after each chunk whether the file is full, which needs every earlier
        // chunk written; so only unsplit-by-size bags compress ahead on other threads.
        let threads = match (storage.compression, max_file_size) {
            (ChunkCompression::None, _) | (_, Some(_)) => 0,
            _ => storage.compression_threads.unwrap_or_else(|| {
                std::thread::available_parallelism().map_or(1, |n| n.get()).min(MAX_COMPRESSION_THREADS)
            }),
        };
        let pool = if threads > 0 { Some(CompressPool::start(storage.compression, threads)?) } else { None };
        if let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        std::fs::create_dir(dir).map_err(io_err(dir))?;
        let mut writer = BagWriter {
            dir: dir.to_path_buf(),
            max_file_size,
            max_file_duration,
            chunk_size,
            layout: storage.layout,
            topics: Vec::new(),
            topic_counts: Vec::new(),
            sequences: Vec::new(),
            closed_files: Vec::new(),
            current: None,
            next_index: 0,
            ros_distro: rosbag2::ros_distro(),
            custom_data: BTreeMap::new(),
            single: Batch::default(),
            compressor,
            compressed: Vec::new(),
            pool,
            in_flight: VecDeque::new(),
            spare: Vec::new(),
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
        if let Some(mut file) = self.current.take() {
            let declared = declare_topics(&mut file, &self.topics);
            self.current = Some(file);
            declared?;
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

    /// Writes a batch of framed messages in order, splitting files by duration (before the message that
    /// would exceed it) and by size (after the chunk that reached it). Returns how many messages were
    /// written, and the error that stopped it, if any.
    pub fn write_batch(&mut self, batch: &Batch) -> (usize, Result<(), BagError>) {
        if self.layout == McapLayout::Unchunked {
            return self.write_unchunked(batch);
        }
        for index in 0..batch.len() {
            if let Err(err) = self.write_one(batch, index) {
                return (index, Err(err));
            }
        }
        (batch.len(), Ok(()))
    }

    fn write_one(&mut self, batch: &Batch, index: usize) -> Result<(), BagError> {
        let entry = batch.entries[index];
        let topic = usize::from(entry.topic);
        if topic >= self.topics.len() {
            return Err(BagError::Format(format!("unknown topic id {}", entry.topic)));
        }
        let log_time = entry.log_time;
        self.ready_file_for(log_time)?;
        let Some(file) = self.current.as_mut() else {
            return Err(BagError::Format("no open file".to_string()));
        };
        let offset = file.chunk.len() as u64;
        file.chunk.extend_from_slice(batch.record(index));
        file.chunk_index[topic].push((log_time, offset));
        file.chunk_bounds = Some(match file.chunk_bounds {
            None => (log_time, log_time),
            Some((start, end)) => (start.min(log_time), end.max(log_time)),
        });
        count_message(file, topic, log_time);
        self.topic_counts[topic] += 1;
        if file.chunk.len() as u64 >= self.chunk_size {
            self.seal_chunk()?;
            if let (Some(limit), Some(file)) = (self.max_file_size, self.current.as_ref()) {
                if file.position >= limit {
                    self.split()?;
                }
            }
        }
        Ok(())
    }

    /// `max_file_duration` in ns, if set.
    fn duration_limit_ns(&self) -> Option<u64> {
        self.max_file_duration.map(|limit| u64::try_from(limit.as_nanos()).unwrap_or(u64::MAX))
    }

    /// Makes `self.current` the file a message logged at `log_time` goes to: splits when the open file's
    /// duration would reach the limit, opens the next file if none is open, and re-declares the topics if
    /// an earlier declaration failed (before any message needs the channel).
    fn ready_file_for(&mut self, log_time: u64) -> Result<(), BagError> {
        if let (Some(limit_ns), Some(file)) = (self.duration_limit_ns(), self.current.as_ref()) {
            if file.entry.message_count > 0 && log_time.saturating_sub(file.entry.start_ns) >= limit_ns {
                self.split()?;
            }
        }
        if self.current.is_none() {
            self.open_next_file()?;
        }
        if let Some(file) = self.current.as_mut() {
            if file.schema_of.len() < self.topics.len() {
                declare_topics(file, &self.topics)?;
            }
        }
        Ok(())
    }

    /// Writes a batch into an unchunked file: runs of messages, each one slice of the batch's records.
    fn write_unchunked(&mut self, batch: &Batch) -> (usize, Result<(), BagError>) {
        let mut done = 0;
        while done < batch.len() {
            match self.write_run(batch, done) {
                Ok(end) => done = end,
                Err(err) => return (done, Err(err)),
            }
        }
        (batch.len(), Ok(()))
    }

    /// Writes messages `from..end` of `batch` to the file as top-level Message records in one write and
    /// returns `end`: the end of the batch, or the first message that belongs in the next file (by
    /// duration) or an unknown topic, or just after the message that reached the split size.
    fn write_run(&mut self, batch: &Batch, from: usize) -> Result<usize, BagError> {
        let first = batch.entries[from];
        if usize::from(first.topic) >= self.topics.len() {
            return Err(BagError::Format(format!("unknown topic id {}", first.topic)));
        }
        let limit_ns = self.duration_limit_ns();
        self.ready_file_for(first.log_time)?;
        let Some(file) = self.current.as_mut() else {
            return Err(BagError::Format("no open file".to_string()));
        };
        let topics = self.topics.len();
        let record_end = |index: usize| batch.entries.get(index).map_or(batch.records.len(), |e| e.start);
        let mut start_ns = (file.entry.message_count > 0).then_some(file.entry.start_ns);
        let mut end = from;
        while end < batch.len() {
            let entry = batch.entries[end];
            if usize::from(entry.topic) >= topics {
                break;
            }
            if let (Some(limit_ns), Some(start)) = (limit_ns, start_ns) {
                if end > from && entry.log_time.saturating_sub(start) >= limit_ns {
                    break;
                }
            }
            start_ns = Some(start_ns.map_or(entry.log_time, |start| start.min(entry.log_time)));
            end += 1;
            if self.max_file_size.is_some_and(|max| file.position + (record_end(end) - first.start) as u64 >= max) {
                break;
            }
        }
        file.put(&batch.records[first.start..record_end(end)]).map_err(io_err(&file.path))?;
        for entry in &batch.entries[from..end] {
            let topic = usize::from(entry.topic);
            count_message(file, topic, entry.log_time);
            file.bounds = Some(match file.bounds {
                None => (entry.log_time, entry.log_time),
                Some((start, end)) => (start.min(entry.log_time), end.max(entry.log_time)),
            });
            self.topic_counts[topic] += 1;
        }
        if file.position - file.writeback_from >= self.chunk_size {
            // As after each chunk of a chunked file: start the disk now, so the fsync at close finds little.
            file.out.flush().map_err(io_err(&file.path))?;
            start_writeback(file.out.get_ref(), file.writeback_from, file.position - file.writeback_from);
            file.writeback_from = file.position;
        }
        if self.max_file_size.is_some_and(|max| file.position >= max) {
            self.split()?;
        }
        Ok(end)
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
        self.close_chunk()?;
        if let Some(file) = self.current.as_mut() {
            file.out.flush().map_err(io_err(&file.path))?;
            file.dirty = false;
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
        let mut file = OpenFile {
            // Unchunked files get each batch as it comes (~64 KiB): buffering a chunk's worth turns those into
            // writes as large as a chunked file's, which measured ~10 % faster for 84-byte messages.
            out: BufWriter::with_capacity(
                match self.layout {
                    McapLayout::Chunked => 64 * 1024,
                    McapLayout::Unchunked => self.chunk_size.clamp(64 * 1024, CHUNK_SIZE) as usize,
                },
                out,
            ),
            path,
            entry: FileEntry { path: name, ..FileEntry::default() },
            position: 0,
            data_crc: crc32fast::Hasher::new(),
            writeback_from: 0,
            schema_of: Vec::new(),
            schemas: Vec::new(),
            chunk: match self.layout {
                McapLayout::Chunked => Vec::with_capacity(self.chunk_size.min(CHUNK_SIZE) as usize + 4096),
                McapLayout::Unchunked => Vec::new(),
            },
            chunk_index: Vec::new(),
            chunk_bounds: None,
            chunk_indexes: Vec::new(),
            metadata_indexes: Vec::new(),
            channel_counts: Vec::new(),
            bounds: None,
            dirty: false,
        };
        let started = start_file(&mut file).map_err(io_err(&file.path.clone()));
        // Kept open even on error, so that close_current lists the file and later writes report failure.
        let declared = started.and_then(|()| declare_topics(&mut file, &self.topics));
        self.current = Some(file);
        declared
    }

    /// Seals the open chunk and writes every chunk still being compressed.
    fn close_chunk(&mut self) -> Result<(), BagError> {
        self.seal_chunk()?;
        while !self.in_flight.is_empty() {
            self.write_oldest()?;
        }
        Ok(())
    }

    /// Ends the open chunk: hands it to the compression pool (writing the oldest chunk in flight once
    /// as many are queued as there are workers), or compresses and writes it here.
    fn seal_chunk(&mut self) -> Result<(), BagError> {
        let Some(file) = self.current.as_mut() else { return Ok(()) };
        if file.chunk.is_empty() {
            return Ok(());
        }
        let fresh = self.spare.pop().unwrap_or_else(|| Vec::with_capacity(file.chunk.capacity()));
        let records = std::mem::replace(&mut file.chunk, fresh);
        let topics = file.chunk_index.len();
        let index = std::mem::replace(&mut file.chunk_index, vec![Vec::new(); topics]);
        let bounds = file.chunk_bounds.take().unwrap_or((0, 0));
        if let Some(pool) = &self.pool {
            let (reply, receive) = mpsc::sync_channel(1);
            let out = self.spare.pop().unwrap_or_default();
            let job = Job { records, out, reply };
            let sent = pool.jobs.as_ref().map(|jobs| jobs.send(job).is_ok()).unwrap_or(false);
            if !sent {
                return Err(BagError::Format(format!("{}: the compression threads stopped", file.path.display())));
            }
            self.in_flight.push_back(InFlight { index, bounds, reply: receive });
            let workers = pool.threads.len().max(1);
            while self.in_flight.len() > workers {
                self.write_oldest()?;
            }
            return Ok(());
        }
        let crc = crc32fast::hash(&records);
        let mut out = std::mem::take(&mut self.compressed);
        let name = self
            .compressor
            .compress(&records, &mut out)
            .map_err(|e| BagError::Mcap(format!("{}: {e}", file.path.display())))?;
        let data = if name.is_empty() { &records } else { &out };
        let written = write_chunk(file, &records, data, name, crc, &index, bounds);
        self.compressed = out;
        self.recycle(records);
        written
    }

    /// Waits for the oldest chunk in flight and writes it.
    fn write_oldest(&mut self) -> Result<(), BagError> {
        let Some(chunk) = self.in_flight.pop_front() else { return Ok(()) };
        let Some(file) = self.current.as_mut() else {
            return Err(BagError::Format("internal: a chunk in flight without an open file".to_string()));
        };
        let done = chunk
            .reply
            .recv()
            .map_err(|_| BagError::Format(format!("{}: a compression thread stopped", file.path.display())))?;
        let name = done.result.map_err(|e| BagError::Mcap(format!("{}: {e}", file.path.display())))?;
        let data = if name.is_empty() { &done.records } else { &done.out };
        let written = write_chunk(file, &done.records, data, name, done.crc, &chunk.index, chunk.bounds);
        self.recycle(done.records);
        self.recycle(done.out);
        written
    }

    fn recycle(&mut self, mut buffer: Vec<u8>) {
        // Enough for the chunks in flight plus their outputs; more would only hold memory.
        if self.spare.len() < 2 * MAX_COMPRESSION_THREADS + 2 {
            buffer.clear();
            self.spare.push(buffer);
        }
    }

    fn close_current(&mut self) -> Result<(), BagError> {
        if self.current.is_none() {
            return Ok(());
        }
        let chunk = self.close_chunk();
        let Some(mut file) = self.current.take() else { return Ok(()) };
        // The entry is listed even if closing fails: the bytes that made it to disk are recoverable.
        self.closed_files.push(file.entry.clone());
        chunk?;
        let metadata = self.metadata();
        let rosbag2 = BTreeMap::from([("serialized_metadata".to_string(), metadata.to_yaml_body(0))]);
        finish_file(&mut file, &self.topics, &rosbag2).map_err(io_err(&file.path))?;
        let out =
            file.out.into_inner().map_err(|e| BagError::Io { path: file.path.clone(), source: e.into_error() })?;
        out.sync_all().map_err(io_err(&file.path))?;
        Ok(())
    }
}

/// Counts one message written to `file` of topic `topic` (statistics and the file's metadata.yaml entry).
fn count_message(file: &mut OpenFile, topic: usize, log_time: u64) {
    file.channel_counts[topic] += 1;
    file.dirty = true;
    let entry = &mut file.entry;
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

/// Writes one chunk record (`data` = its records compressed as `compression`, or the records themselves),
/// then its message indexes, and notes its chunk index for the summary.
fn write_chunk(
    file: &mut OpenFile,
    records: &[u8],
    data: &[u8],
    compression: &'static str,
    uncompressed_crc: u32,
    index: &[Vec<(u64, u64)>],
    (start_ns, end_ns): (u64, u64),
) -> Result<(), BagError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| BagError::Io { path, source }
    };
    let mut head = Vec::with_capacity(64);
    head.push(op::CHUNK);
    put_u64(&mut head, 0); // record length, set below
    put_u64(&mut head, start_ns);
    put_u64(&mut head, end_ns);
    put_u64(&mut head, records.len() as u64);
    put_u32(&mut head, uncompressed_crc);
    put_str(&mut head, compression);
    put_u64(&mut head, data.len() as u64);
    let record_len = (head.len() - 9 + data.len()) as u64;
    head[1..9].copy_from_slice(&record_len.to_le_bytes());
    let chunk_start = file.position;
    file.put(&head).map_err(io(&file.path))?;
    file.put(data).map_err(io(&file.path))?;
    let chunk_length = file.position - chunk_start;
    let indexes_start = file.position;
    let mut message_index_offsets = Vec::new();
    let mut body = Vec::new();
    for (topic, entries) in index.iter().enumerate().filter(|(_, e)| !e.is_empty()) {
        let channel = channel_id(topic as u16);
        body.clear();
        put_u16(&mut body, channel);
        put_u32(&mut body, (entries.len() * 16) as u32);
        for &(log_time, offset) in entries {
            put_u64(&mut body, log_time);
            put_u64(&mut body, offset);
        }
        message_index_offsets.push((channel, file.position));
        file.put_record(op::MESSAGE_INDEX, &body).map_err(io(&file.path))?;
    }
    file.chunk_indexes.push(ChunkIndexEntry {
        start_ns,
        end_ns,
        chunk_start,
        chunk_length,
        message_index_offsets,
        message_index_length: file.position - indexes_start,
        compression,
        compressed_size: data.len() as u64,
        uncompressed_size: records.len() as u64,
    });
    file.bounds = Some(match file.bounds {
        None => (start_ns, end_ns),
        Some((start, end)) => (start.min(start_ns), end.max(end_ns)),
    });
    // Start the disk on this chunk now rather than at the fsync of close: the writeback overlaps the
    // next chunks, the final fsync finds little left, and a power cut loses less.
    file.out.flush().map_err(io(&file.path))?;
    start_writeback(file.out.get_ref(), file.writeback_from, file.position - file.writeback_from);
    file.writeback_from = file.position;
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

fn put_u16(buf: &mut Vec<u8>, v: u16) {
    buf.extend_from_slice(&v.to_le_bytes());
}
fn put_u32(buf: &mut Vec<u8>, v: u32) {
    buf.extend_from_slice(&v.to_le_bytes());
}
fn put_u64(buf: &mut Vec<u8>, v: u64) {
    buf.extend_from_slice(&v.to_le_bytes());
}
fn put_str(buf: &mut Vec<u8>, s: &str) {
    put_u32(buf, s.len() as u32);
    buf.extend_from_slice(s.as_bytes());
}
fn put_map(buf: &mut Vec<u8>, map: &BTreeMap<String, String>) {
    let mut body = Vec::new();
    for (key, value) in map {
        put_str(&mut body, key);
        put_str(&mut body, value);
    }
    put_u32(buf, body.len() as u32);
    buf.extend_from_slice(&body);
}

/// Magic and Header record.
fn start_file(file: &mut OpenFile) -> std::io::Result<()> {
    file.put(MAGIC)?;
    let mut body = Vec::new();
    put_str(&mut body, "ros2");
    put_str(&mut body, LIBRARY);
    file.put_record(op::HEADER, &body)
}

fn schema_body(id: u16, topic: &TopicInfo) -> Vec<u8> {
    let mut body = Vec::new();
    put_u16(&mut body, id);
    put_str(&mut body, &topic.type_name);
    put_str(&mut body, "ros2msg");
    put_str(&mut body, &topic.schema_text);
    body
}

fn channel_body(id: u16, schema_id: u16, topic: &TopicInfo) -> Vec<u8> {
    let metadata = BTreeMap::from([
        ("offered_qos_profiles".to_string(), rosbag2::offered_qos_profiles_yaml(&topic.qos)),
        // Jazzy writes the key even when the publisher announced no type hash (empty); so do we.
        ("topic_type_hash".to_string(), topic.type_hash.clone()),
    ]);
    let mut body = Vec::new();
    put_u16(&mut body, id);
    put_u16(&mut body, schema_id);
    put_str(&mut body, &topic.name);
    put_str(&mut body, "cdr");
    put_map(&mut body, &metadata);
    body
}

/// Writes the Schema (encoding `ros2msg`, full dependency text; one per distinct type) and Channel
/// (encoding `cdr`, rosbag2's channel metadata) records of the topics not yet declared in `file`.
/// They go between chunks, so a linear reader meets them before any message that uses them.
fn declare_topics(file: &mut OpenFile, topics: &[TopicInfo]) -> Result<(), BagError> {
    while file.schema_of.len() < topics.len() {
        let index = file.schema_of.len();
        let topic = &topics[index];
        let known = file.schemas.iter().position(|&first| {
            topics[first].type_name == topic.type_name && topics[first].schema_text == topic.schema_text
        });
        let schema_id = match known {
            Some(position) => position as u16 + 1,
            None => {
                file.schemas.push(index);
                let id = file.schemas.len() as u16;
                file.put_record(op::SCHEMA, &schema_body(id, topic)).map_err(io_err(&file.path.clone()))?;
                id
            }
        };
        file.put_record(op::CHANNEL, &channel_body(channel_id(index as u16), schema_id, topic))
            .map_err(io_err(&file.path.clone()))?;
        file.schema_of.push(schema_id);
        file.chunk_index.push(Vec::new());
        file.channel_counts.push(0);
    }
    Ok(())
}

/// Metadata record, DataEnd, the summary (schemas, channels, statistics, chunk and metadata indexes),
/// summary offsets, footer and closing magic — the records and order of `mcap::Writer::finish`.
fn finish_file(file: &mut OpenFile, topics: &[TopicInfo], rosbag2: &BTreeMap<String, String>) -> std::io::Result<()> {
    let mut body = Vec::new();
    put_str(&mut body, "rosbag2");
    put_map(&mut body, rosbag2);
    let metadata_start = file.position;
    file.put_record(op::METADATA, &body)?;
    file.metadata_indexes.push((metadata_start, file.position - metadata_start, "rosbag2".to_string()));

    let data_section_crc = file.data_crc.clone().finalize();
    body.clear();
    put_u32(&mut body, data_section_crc);
    file.put_record(op::DATA_END, &body)?;

    // From here on the CRC is the summary CRC.
    let summary_start = file.position;
    file.data_crc = crc32fast::Hasher::new();
    let mut groups: Vec<(u8, u64, u64)> = Vec::new();
    let mut group = |file: &mut OpenFile, op: u8, bodies: Vec<Vec<u8>>| -> std::io::Result<()> {
        if bodies.is_empty() {
            return Ok(());
        }
        let start = file.position;
        for body in bodies {
            file.put_record(op, &body)?;
        }
        groups.push((op, start, file.position - start));
        Ok(())
    };
    let declared = file.schema_of.len().min(topics.len());
    let schemas =
        file.schemas.iter().enumerate().map(|(i, &first)| schema_body(i as u16 + 1, &topics[first])).collect();
    group(file, op::SCHEMA, schemas)?;
    let channels = (0..declared).map(|t| channel_body(channel_id(t as u16), file.schema_of[t], &topics[t])).collect();
    group(file, op::CHANNEL, channels)?;

    let mut stats = Vec::new();
    put_u64(&mut stats, file.channel_counts.iter().sum());
    put_u16(&mut stats, file.schemas.len() as u16);
    put_u32(&mut stats, declared as u32);
    put_u32(&mut stats, 0); // attachments
    put_u32(&mut stats, file.metadata_indexes.len() as u32);
    put_u32(&mut stats, file.chunk_indexes.len() as u32);
    let (start, end) = file.bounds.unwrap_or((0, 0));
    put_u64(&mut stats, start);
    put_u64(&mut stats, end);
    let mut counts = Vec::new();
    for (topic, &count) in file.channel_counts.iter().enumerate().filter(|(_, &c)| c > 0) {
        put_u16(&mut counts, channel_id(topic as u16));
        put_u64(&mut counts, count);
    }
    put_u32(&mut stats, counts.len() as u32);
    stats.extend_from_slice(&counts);
    group(file, op::STATISTICS, vec![stats])?;

    let chunk_indexes = file
        .chunk_indexes
        .iter()
        .map(|c| {
            let mut body = Vec::new();
            put_u64(&mut body, c.start_ns);
            put_u64(&mut body, c.end_ns);
            put_u64(&mut body, c.chunk_start);
            put_u64(&mut body, c.chunk_length);
            put_u32(&mut body, (c.message_index_offsets.len() * 10) as u32);
            for &(channel, offset) in &c.message_index_offsets {
                put_u16(&mut body, channel);
                put_u64(&mut body, offset);
            }
            put_u64(&mut body, c.message_index_length);
            put_str(&mut body, c.compression);
            put_u64(&mut body, c.compressed_size);
            put_u64(&mut body, c.uncompressed_size);
            body
        })
        .collect();
    group(file, op::CHUNK_INDEX, chunk_indexes)?;
    let metadata_indexes = file
        .metadata_indexes
        .iter()
        .map(|(offset, length, name)| {
            let mut body = Vec::new();
            put_u64(&mut body, *offset);
            put_u64(&mut body, *length);
            put_str(&mut body, name);
            body
        })
        .collect();
    group(file, op::METADATA_INDEX, metadata_indexes)?;

    let summary_offset_start = file.position;
    for (op, start, length) in groups {
        body.clear();
        body.push(op);
        put_u64(&mut body, start);
        put_u64(&mut body, length);
        file.put_record(op::SUMMARY_OFFSET, &body)?;
    }
    // The summary CRC covers the footer up to (not including) the CRC field itself.
    let mut footer = vec![op::FOOTER];
    put_u64(&mut footer, 20);
    put_u64(&mut footer, summary_start);
    put_u64(&mut footer, summary_offset_start);
    file.put(&footer)?;
    let summary_crc = file.data_crc.clone().finalize();
    let mut tail = Vec::new();
    put_u32(&mut tail, summary_crc);
    tail.extend_from_slice(MAGIC);
    file.put(&tail)?;
    file.out.flush()
}
