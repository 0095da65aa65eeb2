//! The synchronous part of recording: one rosbag2 directory, its split MCAP files and their metadata.
//! No threads here; the [`super::Recorder`] drives it from its writer thread and `bag recover` reuses it.

use std::cell::Cell;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::Duration;

use mcap::records::MessageHeader;

use super::rosbag2::{self, BagMetadata, FileEntry};
use super::{BagError, TopicId, TopicInfo};

/// The MCAP `library` string, so a reader can tell who wrote a file.
pub const LIBRARY: &str = concat!("sweetspot ", env!("CARGO_PKG_VERSION"), " (mcap-rust 0.26)");
/// Target uncompressed chunk size; chunks also close on every flush.
const CHUNK_SIZE: u64 = 1024 * 1024;

/// A file that counts how far it has been written, so splits by size need no syscalls.
struct CountingFile {
    file: File,
    position: u64,
    high_water: Rc<Cell<u64>>,
}

impl Write for CountingFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.position += n as u64;
        if self.position > self.high_water.get() {
            self.high_water.set(self.position);
        }
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl Seek for CountingFile {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.position = self.file.seek(pos)?;
        Ok(self.position)
    }
}

type McapWriter = mcap::Writer<BufWriter<CountingFile>>;

/// The file currently being written.
struct OpenFile {
    writer: McapWriter,
    path: PathBuf,
    entry: FileEntry,
    size: Rc<Cell<u64>>,
    /// MCAP channel id of each registered topic in this file (channels are re-declared in every split).
    channels: Vec<u16>,
    /// Messages written since the last flush.
    dirty: bool,
}

/// Writes one rosbag2 directory: `<dir>/<dirname>_N.mcap` files plus `metadata.yaml`.
pub struct BagWriter {
    dir: PathBuf,
    max_file_size: Option<u64>,
    max_file_duration: Option<Duration>,
    topics: Vec<TopicInfo>,
    topic_counts: Vec<u64>,
    sequences: Vec<u32>,
    closed_files: Vec<FileEntry>,
    current: Option<OpenFile>,
    next_index: usize,
    ros_distro: String,
    custom_data: BTreeMap<String, String>,
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

impl BagWriter {
    /// Creates `dir` (which must not exist yet; parents are created) and opens its first file.
    pub fn create(
        dir: &Path,
        max_file_size: Option<u64>,
        max_file_duration: Option<Duration>,
    ) -> Result<Self, BagError> {
        if let Some(parent) = dir.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        std::fs::create_dir(dir).map_err(io_err(dir))?;
        let mut writer = BagWriter {
            dir: dir.to_path_buf(),
            max_file_size,
            max_file_duration,
            topics: Vec::new(),
            topic_counts: Vec::new(),
            sequences: Vec::new(),
            closed_files: Vec::new(),
            current: None,
            next_index: 0,
            ros_distro: std::env::var("ROS_DISTRO").unwrap_or_default(),
            custom_data: BTreeMap::new(),
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
        let id = u16::try_from(self.topics.len())
            .map_err(|_| BagError::Format("more than 65535 topics".to_string()))?;
        self.topics.push(topic);
        self.topic_counts.push(0);
        self.sequences.push(0);
        if let Some(file) = self.current.as_mut() {
            let topic = &self.topics[usize::from(id)];
            let channel = declare_channel(&mut file.writer, topic).map_err(mcap_err(&file.path))?;
            file.channels.push(channel);
        }
        Ok(TopicId(id))
    }

    /// Writes one message (CDR with its encapsulation header), splitting first if the file is full
    /// by duration. Returns the size of the open file afterwards.
    pub fn write(&mut self, id: TopicId, cdr: &[u8], log_time_ns: u64, publish_time_ns: u64) -> Result<(), BagError> {
        let index = usize::from(id.0);
        if index >= self.topics.len() {
            return Err(BagError::Format(format!("unknown topic id {}", id.0)));
        }
        if let (Some(limit), Some(file)) = (self.max_file_duration, self.current.as_ref()) {
            let limit_ns = u64::try_from(limit.as_nanos()).unwrap_or(u64::MAX);
            if file.entry.message_count > 0 && log_time_ns.saturating_sub(file.entry.start_ns) >= limit_ns {
                self.split()?;
            }
        }
        if self.current.is_none() {
            self.open_next_file()?;
        }
        self.sequences[index] = self.sequences[index].wrapping_add(1);
        let sequence = self.sequences[index];
        let Some(file) = self.current.as_mut() else {
            return Err(BagError::Format("no open file".to_string()));
        };
        let header = MessageHeader {
            channel_id: file.channels[index],
            sequence,
            log_time: log_time_ns,
            publish_time: publish_time_ns,
        };
        file.writer.write_to_known_channel(&header, cdr).map_err(mcap_err(&file.path))?;
        file.dirty = true;
        let entry = &mut file.entry;
        if entry.message_count == 0 {
            entry.start_ns = log_time_ns;
            entry.duration_ns = 0;
        } else if log_time_ns < entry.start_ns {
            entry.duration_ns += entry.start_ns - log_time_ns;
            entry.start_ns = log_time_ns;
        } else {
            entry.duration_ns = entry.duration_ns.max(log_time_ns - entry.start_ns);
        }
        entry.message_count += 1;
        self.topic_counts[index] += 1;
        if let (Some(limit), Some(file)) = (self.max_file_size, self.current.as_ref()) {
            if file.size.get() >= limit {
                self.split()?;
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
            file.writer.flush().map_err(mcap_err(&file.path))?;
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
        let file = File::create(&path).map_err(io_err(&path))?;
        self.next_index += 1;
        let size = Rc::new(Cell::new(0));
        let counting = CountingFile { file, position: 0, high_water: size.clone() };
        let options = mcap::WriteOptions::new()
            .profile("ros2")
            .library(LIBRARY)
            .compression(Some(mcap::Compression::Zstd))
            // Chunks must be well under the split size, or a file could not be seen growing before it closes.
            .chunk_size(Some(self.max_file_size.map_or(CHUNK_SIZE, |max| (max / 4).clamp(1024, CHUNK_SIZE))))
            // One compression thread: the writer thread must not compete with the node for cores.
            .compression_threads(1)
            // Buffer each chunk and write it whole when it closes: with seeking, a chunk is streamed to
            // the file behind a placeholder length, and a crash would leave that placeholder on disk.
            .disable_seeking(true);
        let mut writer = options.create(BufWriter::new(counting)).map_err(mcap_err(&path))?;
        let mut channels = Vec::with_capacity(self.topics.len());
        for topic in &self.topics {
            channels.push(declare_channel(&mut writer, topic).map_err(mcap_err(&path))?);
        }
        self.current = Some(OpenFile {
            writer,
            path,
            entry: FileEntry { path: name, ..FileEntry::default() },
            size,
            channels,
            dirty: false,
        });
        Ok(())
    }

    fn close_current(&mut self) -> Result<(), BagError> {
        let Some(mut file) = self.current.take() else { return Ok(()) };
        // The entry is listed even if closing fails: the bytes that made it to disk are recoverable.
        self.closed_files.push(file.entry.clone());
        let metadata = self.metadata();
        let record = mcap::records::Metadata {
            name: "rosbag2".to_string(),
            metadata: BTreeMap::from([("serialized_metadata".to_string(), metadata.to_yaml_body(0))]),
        };
        file.writer.write_metadata(&record).map_err(mcap_err(&file.path))?;
        file.writer.finish().map_err(mcap_err(&file.path))?;
        let mut inner = file.writer.into_inner();
        inner.flush().map_err(io_err(&file.path))?;
        let counting = inner.into_inner().map_err(|e| BagError::Io { path: file.path.clone(), source: e.into_error() })?;
        counting.file.sync_all().map_err(io_err(&file.path))?;
        Ok(())
    }
}

/// Adds the schema (encoding `ros2msg`, full dependency text) and the channel (encoding `cdr`, rosbag2's
/// channel metadata) of one topic.
fn declare_channel(writer: &mut McapWriter, topic: &TopicInfo) -> mcap::McapResult<u16> {
    let schema = writer.add_schema(&topic.type_name, "ros2msg", topic.schema_text.as_bytes())?;
    let metadata = BTreeMap::from([
        ("offered_qos_profiles".to_string(), rosbag2::offered_qos_profiles_yaml(&topic.qos)),
        // Jazzy writes the key even when the publisher announced no type hash (empty); so do we.
        ("topic_type_hash".to_string(), String::new()),
    ]);
    writer.add_channel(schema, &topic.name, "cdr", &metadata)
}
