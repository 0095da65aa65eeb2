//! The node's side of recording: which topics are recorded (with their QoS as rosbag2 stores it), CDR-encoding
//! each message once, the model settings written to the bag, and the recorder's state for `/diagnostics`. Recording never blocks and never stops the node: when the recorder
//! fails, the node reports it and keeps computing and publishing.

use std::path::PathBuf;
use std::sync::Mutex;

use ros2_client::qos::{Durability, History, Reliability};
use ros2_client::QosProfile;

use crate::bag::{BagError, RecordedQos, RecorderStats, TopicId, TopicInfo};
use crate::msgs::{encode_cdr, RosMessage};

use super::stats::{RecorderState, TapeState};

/// What the node needs of a recorder (implemented by the bag's `Recorder`; by fakes in tests).
pub trait RecordBackend: Send {
    /// Adds a topic (before its first message).
    fn register_topic(&mut self, topic: TopicInfo) -> Result<TopicId, BagError>;
    /// Hands over one CDR message without blocking; false = dropped (and counted by the recorder).
    fn record(&self, id: TopicId, cdr: Vec<u8>, log_time_ns: u64, publish_time_ns: u64) -> bool;
    /// Counters so far.
    fn stats(&self) -> RecorderStats;
    /// Closes the bag (summary, metadata.yaml).
    fn finish(self: Box<Self>) -> Result<RecorderStats, BagError>;
    /// Stores a rosbag2 `custom_data` entry (kept in the bag's metadata); backends without metadata ignore it.
    fn set_custom_data(&self, _key: &str, _value: &str) {}
}

/// The topics the node records, in registration order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Recorded {
    /// Input `bat/params`.
    BatParams = 0,
    /// Input `ball/params`.
    BallParams = 1,
    /// Input `swing`.
    Swing = 2,
    /// Output `exit_velocity`.
    ExitVelocity = 3,
    /// Output `modal_energies`.
    ModalEnergies = 4,
    /// Output `sweet_spot`.
    SweetSpot = 5,
    /// Output `swing_scene`: recorded with the `swing_scene` parameter (registered last then), served live
    /// always.
    SwingScene = 6,
    /// Output `/diagnostics`: served live only, not recorded.
    Diagnostics = 7,
    /// Output `/rosout` (the node's log lines): served live only, not recorded.
    Rosout = 8,
    /// `~/simulate_swing/_service_event`: the service's calls, recorded only with `record_services`
    /// ([`Tape::add_topic`]); not served live.
    ServiceEvent = 9,
}

/// The node's recorder: a backend plus the ids of its topics, or nothing when recording is off or failed.
pub struct Tape {
    dir: Option<PathBuf>,
    backend: Mutex<Option<Box<dyn RecordBackend>>>,
    ids: Vec<Option<TopicId>>,
    error: Mutex<Option<String>>,
    final_stats: Mutex<Option<RecorderStats>>,
    live: Option<crate::foxglove::LiveServer>,
}

impl Tape {
    /// Recording off.
    pub fn off() -> Tape {
        Tape {
            dir: None,
            backend: Mutex::new(None),
            ids: Vec::new(),
            error: Mutex::new(None),
            final_stats: Mutex::new(None),
            live: None,
        }
    }

    /// Also serves every recorded message live (the same CDR bytes, topic for topic) on `live`, whose
    /// channels were started from the same topic list, in [`Recorded`] order.
    pub fn with_live(mut self, live: crate::foxglove::LiveServer) -> Tape {
        self.live = Some(live);
        self
    }

    /// The live server's port, when one runs.
    pub fn live_port(&self) -> Option<u16> {
        self.live.as_ref().map(|l| l.port())
    }

    /// A recorder that could not start: the node runs and reports why.
    pub fn failed(dir: PathBuf, error: String) -> Tape {
        Tape { dir: Some(dir), error: Mutex::new(Some(error)), ..Tape::off() }
    }

    /// Registers one more topic, recorded as `at`: for topics recorded only on request (the service's events).
    pub fn add_topic(&mut self, at: Recorded, topic: TopicInfo) {
        let Ok(mut backend) = self.backend.lock() else { return };
        let Some(backend) = backend.as_mut() else { return };
        let name = topic.name.clone();
        match backend.register_topic(topic) {
            Ok(id) => {
                if self.ids.len() <= at as usize {
                    self.ids.resize(at as usize + 1, None);
                }
                self.ids[at as usize] = Some(id);
            }
            Err(e) => {
                if let Ok(mut err) = self.error.lock() {
                    err.get_or_insert_with(|| format!("registering {name}: {e}"));
                }
            }
        }
    }

    /// Registers `topics` (in [`Recorded`] order: name, type, schema, QoS) with `backend`.
    pub fn start(dir: PathBuf, mut backend: Box<dyn RecordBackend>, topics: Vec<TopicInfo>) -> Tape {
        let mut ids = Vec::new();
        for topic in topics {
            let name = topic.name.clone();
            match backend.register_topic(topic) {
                Ok(id) => ids.push(Some(id)),
                Err(e) => return Tape::failed(dir, format!("registering {name}: {e}")),
            }
        }
        Tape {
            dir: Some(dir),
            backend: Mutex::new(Some(backend)),
            ids,
            error: Mutex::new(None),
            final_stats: Mutex::new(None),
            live: None,
        }
    }

    /// Whether the bag records `topic`.
    pub fn records(&self, topic: Recorded) -> bool {
        self.ids.get(topic as usize).copied().flatten().is_some()
    }

    /// Whether a live client subscribes to `topic` now.
    pub fn serves(&self, topic: Recorded) -> bool {
        self.live.as_ref().is_some_and(|live| live.has_subscribers(topic as usize))
    }

    /// Records one message: CDR-encoded now, logged at `log_time_ns`, published at `publish_time_ns`.
    pub fn record<M: RosMessage>(&self, topic: Recorded, message: &M, log_time_ns: u64, publish_time_ns: u64) {
        self.record_to(topic, message, log_time_ns, publish_time_ns, true);
    }

    /// [`Tape::record`], served to live clients only if `serve_live` (a rate-limited live view).
    pub fn record_to<M: RosMessage>(
        &self,
        topic: Recorded,
        message: &M,
        log_time_ns: u64,
        publish_time_ns: u64,
        serve_live: bool,
    ) {
        let id = self.ids.get(topic as usize).copied().flatten();
        let live = self.live.as_ref().filter(|_| serve_live);
        if id.is_none() && live.is_none() {
            return;
        }
        let cdr = match encode_cdr(message) {
            Ok(cdr) => cdr,
            Err(e) => {
                if let Ok(mut err) = self.error.lock() {
                    err.get_or_insert_with(|| format!("encoding {}: {e}", M::TYPE_NAME));
                }
                return;
            }
        };
        // Live clients get the bytes the bag gets; enqueueing never waits for a client.
        if let Some(live) = live {
            live.send(topic as usize, &cdr, log_time_ns);
        }
        let Some(id) = id else { return };
        let Ok(backend) = self.backend.lock() else { return };
        let Some(backend) = backend.as_ref() else { return };
        // A false return is a drop the recorder counts and diagnostics report.
        let _ = backend.record(id, cdr, log_time_ns, publish_time_ns);
    }

    /// Writes the model settings a replay needs to recompute the recorded swings into the bag's `custom_data`
    /// ([`crate::model::settings::ModelSettings::custom_data`]).
    /// Called at start and after every parameter change, so the bag holds the settings last in force.
    pub fn note_settings(&self, settings: &super::settings::NodeSettings) {
        let Ok(backend) = self.backend.lock() else { return };
        let Some(backend) = backend.as_ref() else { return };
        for (key, value) in settings.model.custom_data() {
            backend.set_custom_data(key, &value);
        }
    }

    /// The state for `/diagnostics`: the recorder's, and the Foxglove server's counters.
    pub fn state(&self) -> TapeState {
        TapeState { recorder: self.recorder_state(), live: self.live.as_ref().map(|l| l.counters()) }
    }

    fn recorder_state(&self) -> RecorderState {
        let Some(dir) = &self.dir else { return RecorderState::Off };
        let dir = dir.display().to_string();
        let stats = match self.backend.lock().ok().and_then(|b| b.as_ref().map(|b| b.stats())) {
            Some(stats) => stats,
            None => self.final_stats.lock().ok().and_then(|s| s.clone()).unwrap_or_default(),
        };
        let error = self.error.lock().ok().and_then(|e| e.clone()).or(stats.error.clone());
        match error {
            Some(error) => RecorderState::Failed { dir, error, written: stats.written, dropped: stats.dropped },
            None => {
                RecorderState::Recording { dir, written: stats.written, dropped: stats.dropped, bytes: stats.bytes }
            }
        }
    }

    /// The bag directory, if recording was requested.
    pub fn dir(&self) -> Option<&PathBuf> {
        self.dir.as_ref()
    }

    /// Closes the bag; later `record` calls do nothing. Returns the final counters (None when off).
    pub fn finish(&self) -> Option<Result<RecorderStats, String>> {
        if let Some(live) = &self.live {
            live.stop();
        }
        let backend = self.backend.lock().ok()?.take()?;
        let result = backend.finish().map_err(|e| e.to_string());
        if let (Ok(stats), Ok(mut slot)) = (&result, self.final_stats.lock()) {
            *slot = Some(stats.clone());
        }
        Some(result)
    }
}

/// A ROS QoS as the recorder writes it into `offered_qos_profiles`.
pub fn recorded_qos(qos: &QosProfile) -> RecordedQos {
    RecordedQos {
        reliable: matches!(qos.reliability, Reliability::Reliable { .. }),
        transient_local: matches!(qos.durability, Durability::TransientLocal),
        depth: match qos.history {
            History::KeepLast { depth } => u32::try_from(depth).unwrap_or(u32::MAX),
            History::KeepAll => 0,
        },
    }
}

/// Starts the bag's recorder (its writer thread) for `config`.
pub fn start_backend(
    config: crate::bag::RecorderConfig,
    storage: crate::bag::StorageOptions,
) -> Result<Box<dyn RecordBackend>, BagError> {
    Ok(Box::new(crate::bag::Recorder::start_with(config, storage)?))
}

/// Bag directories tried by [`start_backend_unique`] before giving up.
pub const MAX_BAG_DIR_ATTEMPTS: u32 = 1000;

/// Starts the recorder in `config.dir`, or, if that directory already exists (another recorder started in
/// the same second, e.g. a second node of the same name), in the first free `<dir>_2`, `<dir>_3`, …
/// ([`crate::bag::rosbag2::numbered_bag_dir`]). Creating the directory is the claim, so two recorders racing
/// for one name never both get it. Returns the recorder and the directory it writes.
pub fn start_backend_unique(
    config: crate::bag::RecorderConfig,
    storage: crate::bag::StorageOptions,
) -> Result<(Box<dyn RecordBackend>, PathBuf), BagError> {
    let base = config.dir.clone();
    let mut attempt = 1;
    loop {
        let dir = crate::bag::rosbag2::numbered_bag_dir(&base, attempt);
        let config = crate::bag::RecorderConfig { dir: dir.clone(), ..config.clone() };
        match start_backend(config, storage) {
            Ok(backend) => return Ok((backend, dir)),
            Err(BagError::Io { path, source })
                if path == dir
                    && source.kind() == std::io::ErrorKind::AlreadyExists
                    && attempt < MAX_BAG_DIR_ATTEMPTS =>
            {
                attempt += 1;
            }
            Err(e) => return Err(e),
        }
    }
}

impl RecordBackend for crate::bag::Recorder {
    fn register_topic(&mut self, topic: TopicInfo) -> Result<TopicId, BagError> {
        crate::bag::Recorder::register_topic(self, topic)
    }
    fn record(&self, id: TopicId, cdr: Vec<u8>, log_time_ns: u64, publish_time_ns: u64) -> bool {
        crate::bag::Recorder::record(self, id, cdr, log_time_ns, publish_time_ns)
    }
    fn stats(&self) -> RecorderStats {
        crate::bag::Recorder::stats(self)
    }
    fn finish(self: Box<Self>) -> Result<RecorderStats, BagError> {
        crate::bag::Recorder::finish(*self)
    }
    fn set_custom_data(&self, key: &str, value: &str) {
        crate::bag::Recorder::set_custom_data(self, key, value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ros::qos::{params_qos, results_qos, sweet_spot_qos, swing_qos};

    #[test]
    fn recorded_qos_keeps_reliability_durability_and_depth() {
        assert_eq!(recorded_qos(&params_qos()), RecordedQos { reliable: true, transient_local: true, depth: 16 });
        assert_eq!(recorded_qos(&swing_qos()), RecordedQos { reliable: true, transient_local: false, depth: 1000 });
        assert_eq!(recorded_qos(&results_qos()), RecordedQos { reliable: true, transient_local: false, depth: 1000 });
        assert!(recorded_qos(&sweet_spot_qos()).transient_local);
        let keep_all = swing_qos().history(History::KeepAll);
        assert_eq!(recorded_qos(&keep_all).depth, 0);
    }

    #[test]
    fn a_taken_bag_directory_gets_the_next_free_suffix() {
        let root = tempfile::tempdir().unwrap();
        let base = root.path().join("sweetspot_2026_11_24-08_00_00");
        std::fs::create_dir(&base).unwrap();
        std::fs::create_dir(root.path().join("sweetspot_2026_11_24-08_00_00_2")).unwrap();
        let config = crate::bag::RecorderConfig::new(&base);
        let (first, dir) = start_backend_unique(config.clone(), crate::bag::StorageOptions::default()).unwrap();
        assert_eq!(dir, root.path().join("sweetspot_2026_11_24-08_00_00_3"));
        let (second, next) = start_backend_unique(config, crate::bag::StorageOptions::default()).unwrap();
        assert_eq!(next, root.path().join("sweetspot_2026_11_24-08_00_00_4"));
        first.finish().unwrap();
        second.finish().unwrap();
        assert!(dir.join("metadata.yaml").is_file() && next.join("metadata.yaml").is_file());
        assert!(dir.join("sweetspot_2026_11_24-08_00_00_3_0.mcap").is_file());
        // Anything other than "the directory exists" is not retried under another name.
        let blocked = root.path().join("file");
        std::fs::write(&blocked, b"").unwrap();
        let config = crate::bag::RecorderConfig::new(blocked.join("bag"));
        assert!(start_backend_unique(config, crate::bag::StorageOptions::default()).is_err());
    }
}
