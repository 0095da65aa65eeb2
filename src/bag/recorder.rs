//! The recorder: a bounded channel into a writer thread that owns the [`BagWriter`].
//!
//! The caller's side (`record`) is a `try_send` and a few atomics, so it never blocks and never allocates
//! beyond the message it hands over. Topics are registered through a shared list rather than the
//! channel, so registration can never be dropped or block behind a full queue.

use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, SyncSender, TrySendError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use super::writer::BagWriter;
use super::{BagError, RecorderConfig, RecorderStats, TopicId, TopicInfo};

struct Recorded {
    id: TopicId,
    cdr: Vec<u8>,
    log_time_ns: u64,
    publish_time_ns: u64,
}

#[derive(Default)]
struct Shared {
    topics: Mutex<Vec<TopicInfo>>,
    topic_count: AtomicUsize,
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
    sender: Option<SyncSender<Recorded>>,
    shared: Arc<Shared>,
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
        if config.flush_interval.is_zero() {
            return Err(BagError::Format("flush_interval must be > 0".to_string()));
        }
        if config.max_file_size == Some(0) || config.max_file_duration.is_some_and(|d| d.is_zero()) {
            return Err(BagError::Format("max_file_size / max_file_duration must be > 0 when set".to_string()));
        }
        // The writer holds an Rc internally, so it is built on the writer thread; creation errors come
        // back through this rendezvous so that start() reports them synchronously.
        let (ready_tx, ready_rx) = mpsc::sync_channel::<Result<(), BagError>>(1);
        let (sender, receiver) = mpsc::sync_channel::<Recorded>(config.queue_capacity.max(1));
        let shared = Arc::new(Shared::default());
        let thread_shared = shared.clone();
        let thread_config = config.clone();
        let thread = std::thread::Builder::new()
            .name("bag-writer".to_string())
            .spawn(move || {
                let writer = match BagWriter::create(
                    &thread_config.dir,
                    thread_config.max_file_size,
                    thread_config.max_file_duration,
                ) {
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
            Ok(Ok(())) => Ok(Recorder { sender: Some(sender), shared, thread: Some(thread), dir: config.dir }),
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
        let id = u16::try_from(topics.len()).map_err(|_| BagError::Format("more than 65535 topics".to_string()))?;
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

    /// Queues one message (CDR bytes with their 4-byte encapsulation header). Never blocks: returns
    /// false, and counts it in `dropped`, if the queue is full, the id is unknown or recording failed.
    pub fn record(&self, id: TopicId, cdr: Vec<u8>, log_time_ns: u64, publish_time_ns: u64) -> bool {
        let known = usize::from(id.0) < self.shared.topic_count.load(Ordering::Acquire);
        let sent = known
            && !self.shared.failed.load(Ordering::Acquire)
            && match &self.sender {
                Some(sender) => match sender.try_send(Recorded { id, cdr, log_time_ns, publish_time_ns }) {
                    Ok(()) => true,
                    Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => false,
                },
                None => false,
            };
        if !sent {
            self.shared.dropped.fetch_add(1, Ordering::Relaxed);
        }
        sent
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
        // Dropping the sender lets the writer drain the queue and then see the disconnect.
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

/// The writer thread: drain the queue, flush at least every `flush_interval`, finish on disconnect.
/// After an error it keeps draining (counting drops) so senders never see a full queue because of it.
fn run_writer(
    mut writer: BagWriter,
    receiver: mpsc::Receiver<Recorded>,
    shared: &Shared,
    flush_interval: Duration,
) -> Result<(), BagError> {
    let mut healthy = true;
    let mut last_flush = Instant::now();
    let fail = |err: BagError, healthy: &mut bool| {
        tracing::error!("recording to {} failed: {err}", writer_dir_display(&err));
        shared.fail(&err);
        *healthy = false;
    };
    loop {
        let deadline = last_flush + flush_interval;
        let timeout = deadline.saturating_duration_since(Instant::now());
        let received = receiver.recv_timeout(timeout);
        if healthy {
            if let Err(err) = sync_topics(&mut writer, shared) {
                fail(err, &mut healthy);
            }
        }
        match received {
            Ok(msg) => {
                if healthy {
                    let len = msg.cdr.len() as u64;
                    match writer.write(msg.id, &msg.cdr, msg.log_time_ns, msg.publish_time_ns) {
                        Ok(()) => {
                            shared.written.fetch_add(1, Ordering::Relaxed);
                            shared.bytes.fetch_add(len, Ordering::Relaxed);
                        }
                        Err(err) => {
                            shared.dropped.fetch_add(1, Ordering::Relaxed);
                            fail(err, &mut healthy);
                        }
                    }
                } else {
                    shared.dropped.fetch_add(1, Ordering::Relaxed);
                }
            }
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => break,
        }
        if Instant::now() >= deadline {
            if healthy && writer.is_dirty() {
                if let Err(err) = writer.flush() {
                    fail(err, &mut healthy);
                }
            }
            last_flush = Instant::now();
        }
    }
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

fn writer_dir_display(err: &BagError) -> String {
    match err {
        BagError::Io { path, .. } => path.display().to_string(),
        _ => "bag".to_string(),
    }
}

/// Declares in the file every topic registered since the last call, and picks up new custom data.
fn sync_topics(writer: &mut BagWriter, shared: &Shared) -> Result<(), BagError> {
    if shared.custom_data_changed.swap(false, Ordering::AcqRel) {
        writer.set_custom_data(shared.custom_data.lock().unwrap_or_else(|p| p.into_inner()).clone());
    }
    let known = writer.topics().len();
    if shared.topic_count.load(Ordering::Acquire) == known {
        return Ok(());
    }
    let new: Vec<TopicInfo> = shared.topics()[known..].to_vec();
    for topic in new {
        writer.add_topic(topic)?;
    }
    Ok(())
}
