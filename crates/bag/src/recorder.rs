//! The recorder: callers copy messages into a shared batch; full batches go over a channel to a writer
//! thread that owns the [`BagWriter`].
//!
//! Why batches: a channel hop per message (send, wake-up, receive, a `Vec` per message) cost more than the
//! disk. The caller's side (`record`) is now a short lock, one copy of the bytes into the batch, and a few
//! atomics; once per batch it hands the batch to the writer. The writer also takes the unfinished batch at
//! every flush, so the flush interval still bounds what a crash can lose. Topics are registered through a
//! shared list rather than the channel, so registration can never be dropped or block behind a full queue.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::writer::{BagWriter, Batch};
use super::{BagError, RecorderConfig, RecorderStats, StorageOptions, TopicId, TopicInfo};

/// A batch is handed to the writer once it holds this many message bytes (or `batch_messages` messages).
const BATCH_BYTES: u64 = 64 * 1024;
/// Emptied batches kept for reuse, so steady recording allocates nothing.
const SPARE_BATCHES: usize = 8;

/// The batch being filled, and each topic's sequence number so far.
#[derive(Default)]
struct Pending {
    batch: Batch,
    sequences: Vec<u32>,
}

#[derive(Default)]
struct Shared {
    topics: Mutex<Vec<TopicInfo>>,
    topic_count: AtomicUsize,
    pending: Mutex<Pending>,
    spare: Mutex<Vec<Batch>>,
    /// Messages accepted and not yet written or dropped.
    queued: AtomicUsize,
    written: AtomicU64,
    dropped: AtomicU64,
    bytes: AtomicU64,
    failed: AtomicBool,
    error: Mutex<Option<String>>,
    custom_data: Mutex<std::collections::BTreeMap<String, String>>,
    custom_data_changed: AtomicBool,
}

impl Shared {
    fn topics(&self) -> MutexGuard<'_, Vec<TopicInfo>> {
        // A panic while holding this lock cannot leave the Vec inconsistent (push only), so poison is ignored.
        self.topics.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn pending(&self) -> MutexGuard<'_, Pending> {
        // Batch::push leaves the batch consistent at every step that can panic (allocation), so poison is ignored.
        self.pending.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// An empty batch, reused if one is spare.
    fn empty_batch(&self) -> Batch {
        self.spare.lock().unwrap_or_else(|p| p.into_inner()).pop().unwrap_or_default()
    }

    fn recycle(&self, mut batch: Batch) {
        batch.clear();
        let mut spare = self.spare.lock().unwrap_or_else(|p| p.into_inner());
        if spare.len() < SPARE_BATCHES {
            spare.push(batch);
        }
    }

    /// Takes the unfinished batch (what `record` accepted but has not handed over yet).
    fn take_pending(&self) -> Batch {
        let fresh = self.empty_batch();
        std::mem::replace(&mut self.pending().batch, fresh)
    }

    /// Counts every message of `batch` as dropped.
    fn drop_batch(&self, batch: Batch) {
        self.dropped.fetch_add(batch.len() as u64, Ordering::Relaxed);
        self.queued.fetch_sub(batch.len(), Ordering::AcqRel);
        self.recycle(batch);
    }

    fn fail(&self, err: &BagError) {
        let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
        if slot.is_none() {
            *slot = Some(err.to_string());
        }
        self.failed.store(true, Ordering::Release);
    }

    fn stats(&self) -> RecorderStats {
        RecorderStats {
            written: self.written.load(Ordering::Relaxed),
            dropped: self.dropped.load(Ordering::Relaxed),
            bytes: self.bytes.load(Ordering::Relaxed),
            error: self.error.lock().unwrap_or_else(|p| p.into_inner()).clone(),
        }
    }
}

/// Records messages into a rosbag2 directory from any thread without blocking (`Send + Sync`; share it
/// through an `Arc`). Dropping it finishes the bag like [`Recorder::finish`].
pub struct Recorder {
    /// Unbounded: `queued` bounds what is in flight, in messages.
    sender: Option<Sender<Batch>>,
    shared: Arc<Shared>,
    capacity: usize,
    /// A batch is handed over at this many messages even if not full of bytes, so that a small
    /// `queue_capacity` still keeps the writer busy instead of waiting for the flush.
    batch_messages: usize,
    thread: Option<JoinHandle<Result<(), BagError>>>,
    dir: std::path::PathBuf,
}

impl RecorderConfig {
    /// Defaults: no split, flush every second, room for 16384 queued messages.
    pub fn new(dir: impl Into<std::path::PathBuf>) -> Self {
        RecorderConfig {
            dir: dir.into(),
            max_file_size: None,
            max_file_duration: None,
            flush_interval: Duration::from_secs(1),
            queue_capacity: 16_384,
        }
    }
}

impl Recorder {
    /// Creates the bag directory and its first file, then starts the writer thread.
    /// Fails (without starting anything) if the directory exists or cannot be created.
    pub fn start(config: RecorderConfig) -> Result<Recorder, BagError> {
        Self::start_with(config, StorageOptions::default())
    }

    /// Like [`Recorder::start`], with the chunk compression and size of `storage`.
    pub fn start_with(config: RecorderConfig, storage: StorageOptions) -> Result<Recorder, BagError> {
        if config.flush_interval.is_zero() {
            return Err(BagError::Format("flush_interval must be > 0".to_string()));
        }
        if config.max_file_size == Some(0) || config.max_file_duration.is_some_and(|d| d.is_zero()) {
            return Err(BagError::Format("max_file_size / max_file_duration must be > 0 when set".to_string()));
        }
        // The writer is built on its thread; creation errors come back through this rendezvous so that
        // start() reports them synchronously.
        let (ready_tx, ready_rx) = mpsc::sync_channel::<Result<(), BagError>>(1);
        let (sender, receiver) = mpsc::channel::<Batch>();
        let shared = Arc::new(Shared::default());
        let thread_shared = shared.clone();
        let thread_config = config.clone();
        let thread = std::thread::Builder::new()
            .name("bag-writer".to_string())
            .spawn(move || {
                // metadata.yaml is written first, while there is room, and kept up to date: a bag whose disk
                // fills up keeps the last one written (see `run_writer`).
                let created = BagWriter::create_with(
                    &thread_config.dir,
                    thread_config.max_file_size,
                    thread_config.max_file_duration,
                    storage,
                )
                .and_then(|writer| writer.metadata().write_to_dir(&thread_config.dir).map(|()| writer));
                let writer = match created {
                    Ok(writer) => {
                        let _ = ready_tx.send(Ok(()));
                        writer
                    }
                    Err(err) => {
                        let _ = ready_tx.send(Err(err));
                        return Ok(());
                    }
                };
                run_writer(writer, receiver, &thread_shared, thread_config.flush_interval)
            })
            .map_err(|source| BagError::Io { path: config.dir.clone(), source })?;
        match ready_rx.recv() {
            Ok(Ok(())) => {
                let capacity = config.queue_capacity.max(1);
                Ok(Recorder {
                    sender: Some(sender),
                    shared,
                    capacity,
                    batch_messages: (capacity / 4).max(1),
                    thread: Some(thread),
                    dir: config.dir,
                })
            }
            Ok(Err(err)) => {
                let _ = thread.join();
                Err(err)
            }
            Err(_) => {
                let _ = thread.join();
                Err(BagError::Format("the bag writer thread exited during start".to_string()))
            }
        }
    }

    /// The bag directory being written.
    pub fn dir(&self) -> &std::path::Path {
        &self.dir
    }

    /// Declares a topic. Registering the same name again with the same type returns the same id;
    /// with a different type it is an error.
    pub fn register_topic(&self, topic: TopicInfo) -> Result<TopicId, BagError> {
        validate_topic(&topic)?;
        let mut topics = self.shared.topics();
        if let Some(index) = topics.iter().position(|t| t.name == topic.name) {
            if topics[index].type_name != topic.type_name {
                return Err(BagError::Format(format!(
                    "topic {} already registered with type {}, not {}",
                    topic.name, topics[index].type_name, topic.type_name
                )));
            }
            return Ok(TopicId(index as u16));
        }
        // MCAP channel ids are topic index + 1, so 65535 topics at most.
        let id = u16::try_from(topics.len())
            .ok()
            .filter(|&id| id < u16::MAX)
            .ok_or_else(|| BagError::Format("more than 65535 topics".to_string()))?;
        topics.push(topic);
        self.shared.topic_count.store(topics.len(), Ordering::Release);
        Ok(TopicId(id))
    }

    /// Stores a rosbag2 `custom_data` entry (e.g. the node settings a later `bag replay` needs). It is
    /// written into the `rosbag2` record of every file closed from now on and into metadata.yaml.
    pub fn set_custom_data(&self, key: impl Into<String>, value: impl Into<String>) {
        let mut map = self.shared.custom_data.lock().unwrap_or_else(|p| p.into_inner());
        map.insert(key.into(), value.into());
        self.shared.custom_data_changed.store(true, Ordering::Release);
    }

    /// Records one message (CDR bytes with their 4-byte encapsulation header). Never waits for the disk:
    /// returns false, and counts it in `dropped`, if `queue_capacity` messages are already waiting, the
    /// id is unknown or recording failed.
    pub fn record(&self, id: TopicId, cdr: Vec<u8>, log_time_ns: u64, publish_time_ns: u64) -> bool {
        self.record_bytes(id, &cdr, log_time_ns, publish_time_ns)
    }

    /// [`Recorder::record`] from a borrowed buffer (the bytes are copied into the batch).
    pub fn record_bytes(&self, id: TopicId, cdr: &[u8], log_time_ns: u64, publish_time_ns: u64) -> bool {
        let accepted = self.try_record(id, cdr, log_time_ns, publish_time_ns);
        if !accepted {
            self.shared.dropped.fetch_add(1, Ordering::Relaxed);
        }
        accepted
    }

    fn try_record(&self, id: TopicId, cdr: &[u8], log_time_ns: u64, publish_time_ns: u64) -> bool {
        let topic = usize::from(id.0);
        let Some(sender) = &self.sender else { return false };
        if topic >= self.shared.topic_count.load(Ordering::Acquire) || self.shared.failed.load(Ordering::Acquire) {
            return false;
        }
        if self.shared.queued.fetch_add(1, Ordering::AcqRel) >= self.capacity {
            self.shared.queued.fetch_sub(1, Ordering::AcqRel);
            return false;
        }
        let mut pending = self.shared.pending();
        // Checked again under the lock: the writer sets `failed` before it empties the pending batch, so
        // a message pushed after that emptying sees the failure and is not stranded uncounted.
        if self.shared.failed.load(Ordering::Acquire) {
            drop(pending);
            self.shared.queued.fetch_sub(1, Ordering::AcqRel);
            return false;
        }
        if pending.sequences.len() <= topic {
            pending.sequences.resize(topic + 1, 0);
        }
        let sequence = pending.sequences[topic].wrapping_add(1);
        pending.sequences[topic] = sequence;
        pending.batch.push(id, sequence, log_time_ns, publish_time_ns, cdr);
        if pending.batch.payload_bytes() < BATCH_BYTES && pending.batch.len() < self.batch_messages {
            return true;
        }
        let fresh = self.shared.empty_batch();
        let full = std::mem::replace(&mut pending.batch, fresh);
        // Sent under the lock, so batches reach the writer in the order their messages were accepted.
        if let Err(mpsc::SendError(batch)) = sender.send(full) {
            // Only if the writer thread died: count what the batch held (this message included).
            drop(pending);
            self.shared.drop_batch(batch);
            self.shared.dropped.fetch_sub(1, Ordering::Relaxed);
            return false;
        }
        true
    }

    /// Counters so far (a few atomic loads).
    pub fn stats(&self) -> RecorderStats {
        self.shared.stats()
    }

    /// Writes everything queued, closes the last file with its summary and writes `metadata.yaml`.
    pub fn finish(mut self) -> Result<RecorderStats, BagError> {
        self.shutdown()
    }

    fn shutdown(&mut self) -> Result<RecorderStats, BagError> {
        // Dropping the sender lets the writer drain the channel, see the disconnect, then write the
        // unfinished batch.
        self.sender = None;
        let outcome = match self.thread.take() {
            Some(thread) => match thread.join() {
                Ok(result) => result,
                Err(_) => Err(BagError::Format("the bag writer thread panicked".to_string())),
            },
            None => Ok(()),
        };
        if let Err(err) = &outcome {
            self.shared.fail(err);
        }
        // Empty unless the writer thread died: count what it left behind.
        self.shared.drop_batch(self.shared.take_pending());
        outcome.map(|()| self.shared.stats())
    }
}

impl Drop for Recorder {
    fn drop(&mut self) {
        if self.thread.is_some() {
            if let Err(err) = self.shutdown() {
                tracing::error!("finishing bag {}: {err}", self.dir.display());
            }
        }
    }
}

fn validate_topic(topic: &TopicInfo) -> Result<(), BagError> {
    if !topic.name.starts_with('/') || topic.name.len() < 2 {
        return Err(BagError::Format(format!("topic name {:?} must be fully qualified (start with '/')", topic.name)));
    }
    let parts: Vec<&str> = topic.type_name.split('/').collect();
    if parts.len() != 3 || parts.iter().any(|p| p.is_empty()) {
        return Err(BagError::Format(format!(
            "type name {:?} of {} must look like package/msg/Type",
            topic.type_name, topic.name
        )));
    }
    Ok(())
}

/// The writer thread: write batches as they come, take the unfinished batch and flush at least every
/// `flush_interval`, finish on disconnect. After an error it keeps receiving (counting drops) so that
/// `queued` drains and callers are refused at once rather than by a full queue.
fn run_writer(
    mut writer: BagWriter,
    receiver: mpsc::Receiver<Batch>,
    shared: &Shared,
    flush_interval: Duration,
) -> Result<(), BagError> {
    let mut healthy = true;
    let mut last_flush = Instant::now();
    loop {
        let deadline = last_flush + flush_interval;
        let timeout = deadline.saturating_duration_since(Instant::now());
        let disconnected = match receiver.recv_timeout(timeout) {
            Ok(batch) => {
                write_batch(&mut writer, batch, shared, &mut healthy);
                false
            }
            Err(RecvTimeoutError::Timeout) => false,
            Err(RecvTimeoutError::Disconnected) => true,
        };
        if disconnected {
            break;
        }
        if Instant::now() >= deadline {
            for batch in take_in_order(shared, &receiver) {
                write_batch(&mut writer, batch, shared, &mut healthy);
            }
            // Topics registered or custom data set with no message since: into the file and metadata.yaml now.
            if healthy {
                if let Err(err) = sync_topics(&mut writer, shared) {
                    fail(shared, &err, &mut healthy);
                }
            }
            if healthy && writer.is_dirty() {
                if let Err(err) = writer.flush() {
                    fail(shared, &err, &mut healthy);
                }
            }
            last_flush = Instant::now();
        }
    }
    // Every sender is gone, so nothing can join the pending batch any more.
    write_batch(&mut writer, shared.take_pending(), shared, &mut healthy);
    if healthy {
        sync_topics(&mut writer, shared)?;
    }
    let finished = writer.finish();
    if healthy {
        finished.map(|_| ())
    } else {
        // The first error is already in the stats; report it again as the outcome of finish().
        Err(BagError::Format(shared.stats().error.unwrap_or_else(|| "recording failed".to_string())))
    }
}

/// The batches already handed over, then the unfinished one. Callers hand batches over while holding the
/// pending lock, so with the lock held every batch filled before the unfinished one is in the channel.
fn take_in_order(shared: &Shared, receiver: &mpsc::Receiver<Batch>) -> Vec<Batch> {
    let fresh = shared.empty_batch();
    let mut pending = shared.pending();
    let mut batches: Vec<Batch> = receiver.try_iter().collect();
    batches.push(std::mem::replace(&mut pending.batch, fresh));
    batches
}

fn write_batch(writer: &mut BagWriter, batch: Batch, shared: &Shared, healthy: &mut bool) {
    if batch.is_empty() {
        shared.recycle(batch);
        return;
    }
    if !*healthy {
        shared.drop_batch(batch);
        return;
    }
    if let Err(err) = sync_topics(writer, shared) {
        fail(shared, &err, healthy);
        shared.drop_batch(batch);
        return;
    }
    let (written, result) = writer.write_batch(&batch);
    let written_bytes = if written == batch.len() { batch.payload_bytes() } else { batch.payload_bytes_of(written) };
    shared.written.fetch_add(written as u64, Ordering::Relaxed);
    shared.bytes.fetch_add(written_bytes, Ordering::Relaxed);
    shared.dropped.fetch_add((batch.len() - written) as u64, Ordering::Relaxed);
    shared.queued.fetch_sub(batch.len(), Ordering::AcqRel);
    shared.recycle(batch);
    if let Err(err) = result {
        fail(shared, &err, healthy);
    }
}

/// Records the first error, refuses new messages and drops what is waiting in the unfinished batch.
fn fail(shared: &Shared, err: &BagError, healthy: &mut bool) {
    tracing::error!("recording to {} failed: {err}", writer_dir_display(err));
    shared.fail(err);
    *healthy = false;
    shared.drop_batch(shared.take_pending());
}

fn writer_dir_display(err: &BagError) -> String {
    match err {
        BagError::Io { path, .. } => path.display().to_string(),
        _ => "bag".to_string(),
    }
}

/// Declares in the file every topic registered since the last call, and picks up new custom data; when either
/// changed, rewrites metadata.yaml, so the bag always has one listing every topic, even if the disk fills
/// up before the first split or the end.
fn sync_topics(writer: &mut BagWriter, shared: &Shared) -> Result<(), BagError> {
    let custom_data_changed = shared.custom_data_changed.swap(false, Ordering::AcqRel);
    if custom_data_changed {
        writer.set_custom_data(shared.custom_data.lock().unwrap_or_else(|p| p.into_inner()).clone());
    }
    let known = writer.topics().len();
    if shared.topic_count.load(Ordering::Acquire) != known {
        let new: Vec<TopicInfo> = shared.topics()[known..].to_vec();
        for topic in new {
            writer.add_topic(topic)?;
        }
    } else if !custom_data_changed {
        return Ok(());
    }
    writer.metadata().write_to_dir(writer.dir())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::RecordedQos;
    use std::path::Path;
    use std::process::Command;

    /// Set in the child process of [`a_full_disk_leaves_a_bag_with_metadata_that_recover_rebuilds`]: its bag dir.
    const CHILD_DIR: &str = "SWEETSPOT_TEST_FULL_DISK_BAG";
    const TOPIC: &str = "/swing";
    const BEFORE_FULL: usize = 100;

    fn topic() -> TopicInfo {
        TopicInfo {
            name: TOPIC.to_string(),
            type_name: "sweetspot_msgs/msg/Swing".to_string(),
            schema_text: "uint64 swing_id\n".to_string(),
            type_hash: String::new(),
            qos: RecordedQos { reliable: true, transient_local: false, depth: 1000 },
        }
    }

    fn wait_for(what: &str, mut done: impl FnMut() -> bool) {
        // Generous: only turns a hang into a failure.
        let start = Instant::now();
        while !done() {
            assert!(start.elapsed() < Duration::from_secs(30), "{what} never happened");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// The child: records, waits until the first messages are on disk, then makes every further write fail
    /// as on a full disk (RLIMIT_FSIZE 0 with SIGXFSZ ignored: `write` fails with EFBIG) and finishes the bag.
    fn record_until_the_disk_is_full(dir: &Path) {
        // SAFETY: plain libc calls on this process's own signal disposition and limits.
        unsafe {
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
        }
        let mut config = RecorderConfig::new(dir);
        config.flush_interval = Duration::from_millis(20);
        let recorder = Recorder::start(config).unwrap();
        let id = recorder.register_topic(topic()).unwrap();
        let message = |i: usize| [&[0u8, 1, 0, 0][..], &(i as u64).to_le_bytes(), &[7u8; 1000]].concat();
        for i in 0..BEFORE_FULL {
            assert!(recorder.record(id, message(i), 1_000 + i as u64, 1_000 + i as u64));
        }
        // On disk means in the file as the OS has it: complete chunks an MCAP reader can read back.
        let file = dir.join(crate::rosbag2::file_name(dir, 0));
        wait_for("the first messages on disk", || {
            let bytes = std::fs::read(&file).unwrap_or_default();
            mcap::MessageStream::new(&bytes).is_ok_and(|s| s.take_while(|m| m.is_ok()).count() == BEFORE_FULL)
        });
        let limit = libc::rlimit { rlim_cur: 0, rlim_max: libc::RLIM_INFINITY };
        // SAFETY: as above.
        assert_eq!(unsafe { libc::setrlimit(libc::RLIMIT_FSIZE, &limit) }, 0);
        for i in BEFORE_FULL..BEFORE_FULL + 2_000 {
            recorder.record(id, message(i), 1_000 + i as u64, 1_000 + i as u64);
        }
        let finished = recorder.finish();
        let error = finished.expect_err("writing past a full disk fails").to_string();
        assert!(error.contains("File too large"), "{error}");
    }

    #[test]
    fn a_full_disk_leaves_a_bag_with_metadata_that_recover_rebuilds() {
        if let Some(dir) = std::env::var_os(CHILD_DIR) {
            return record_until_the_disk_is_full(Path::new(&dir));
        }
        let root = tempfile::tempdir().unwrap();
        let dir = root.path().join("full");
        let child = Command::new(std::env::current_exe().unwrap())
            .args(["recorder::tests::a_full_disk_leaves_a_bag_with_metadata_that_recover_rebuilds", "--exact"])
            .args(["--nocapture", "--test-threads=1"])
            .env(CHILD_DIR, &dir)
            .output()
            .unwrap();
        let child_log = format!("{}{}", String::from_utf8_lossy(&child.stdout), String::from_utf8_lossy(&child.stderr));
        assert!(child.status.success(), "child failed:\n{child_log}");
        assert!(child_log.contains("1 passed"), "the child ran no test:\n{child_log}");

        // The bag has the metadata.yaml written before the disk filled: every topic, no half-written temp file.
        let metadata = std::fs::read_to_string(dir.join("metadata.yaml")).expect("metadata.yaml after a full disk");
        assert!(metadata.contains(&format!("name: \"{TOPIC}\"")), "{metadata}");
        assert!(!dir.join(".metadata.yaml.tmp").exists());

        // `bag recover` rebuilds metadata.yaml from the MCAP alone, counting what reached the disk.
        std::fs::remove_file(dir.join("metadata.yaml")).unwrap();
        let recovery = crate::recover::recover(&dir, None, |_| {}).unwrap();
        let out = recovery.output.expect("a repaired copy");
        let rebuilt = std::fs::read_to_string(out.join("metadata.yaml")).unwrap();
        assert!(rebuilt.contains(&format!("message_count: {BEFORE_FULL}")), "{rebuilt}");
        assert!(rebuilt.contains(&format!("name: \"{TOPIC}\"")), "{rebuilt}");
        // The mcap crate, reading the repaired file on its own, finds the same messages.
        let bytes = std::fs::read(out.join(crate::rosbag2::file_name(&dir, 0))).unwrap();
        let read: Vec<u64> = mcap::MessageStream::new(&bytes).unwrap().map(|m| m.unwrap().sequence as u64).collect();
        assert_eq!(read, (1..=BEFORE_FULL as u64).collect::<Vec<_>>());
    }
}
