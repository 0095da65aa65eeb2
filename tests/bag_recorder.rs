//! The Recorder writes rosbag2 directories that the project and independent readers read back exactly.

mod support;

use std::time::Duration;

use support::bag::*;
use sweetspot::bag::reader::{bag_files, read_bag, scan_file};
use sweetspot::bag::{BagError, McapLayout, Recorder, RecorderConfig, StorageOptions, TopicId};

const T0: u64 = 1_763_700_000_000_000_000;

#[test]
fn recorded_bag_reads_back_identically_with_project_and_python_readers() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("rig_2026_11_21-05_00_00");
    let recorder = Recorder::start(RecorderConfig::new(&dir)).unwrap();
    let params = recorder.register_topic(string_topic("/rig/bat_params", LATCHED)).unwrap();
    let swings = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    let fast = recorder.register_topic(string_topic("/rig/fast", BEST_EFFORT)).unwrap();
    // Same name and type again gives the same id; a different type is refused.
    assert_eq!(recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap(), swings);
    let mut other = string_topic("/rig/swing", RELIABLE);
    other.type_name = "std_msgs/msg/Int32".into();
    assert!(matches!(recorder.register_topic(other), Err(BagError::Format(_))));

    assert!(recorder.record(params, cdr_string("bat r161"), T0, T0));
    let settings = r#"{"time_step": 1e-6, "note": "quotes \" and\nnewlines: kept"}"#;
    recorder.set_custom_data("sweetspot/settings", settings);
    for i in 0..1000u64 {
        let t = T0 + 1_000_000 * (i + 1);
        assert!(recorder.record(swings, cdr_string(&format!("swing {i}")), t, t - 500));
        if i % 10 == 0 {
            assert!(recorder.record(fast, cdr_string(&format!("fast {i}")), t, t));
        }
    }
    // An id that was never registered is refused and counted as dropped.
    assert!(!recorder.record(TopicId(99), cdr_string("nobody"), T0, T0));
    let stats = recorder.finish().unwrap();
    assert_eq!(stats.written, 1101);
    assert_eq!(stats.dropped, 1);
    assert_eq!(stats.error, None);

    // Layout: metadata.yaml + <dirname>_0.mcap.
    let files = bag_files(&dir).unwrap();
    assert_eq!(files, vec![dir.join("rig_2026_11_21-05_00_00_0.mcap")]);
    let yaml = std::fs::read_to_string(dir.join("metadata.yaml")).unwrap();
    assert!(yaml.starts_with("rosbag2_bagfile_information:\n  version: 8\n  storage_identifier: mcap\n"), "{yaml}");
    assert!(yaml.contains("message_count: 1101"), "{yaml}");

    // The project's reader: every message, in order, with per-channel sequence numbers from 1.
    let mut seen: Vec<(String, u32, u64, u64, Vec<u8>)> = Vec::new();
    let scans = read_bag(&dir, |m| {
        seen.push((m.channel.topic.name.clone(), m.sequence, m.log_time_ns, m.publish_time_ns, m.data.to_vec()))
    })
    .unwrap();
    let scan = &scans[0];
    assert!(scan.complete, "file has summary and footer");
    assert_eq!(scan.profile, "ros2");
    assert_eq!(scan.compressions, vec!["zstd".to_string()]);
    assert_eq!(scan.truncated_bytes, 0);
    assert!(scan.rosbag2_metadata.as_deref().is_some_and(|m| m.contains("version: 8")));
    assert_eq!(seen.len(), 1101);
    assert_eq!(seen[0], ("/rig/bat_params".into(), 1, T0, T0, cdr_string("bat r161")));
    let swing_msgs: Vec<_> = seen.iter().filter(|s| s.0 == "/rig/swing").collect();
    assert_eq!(swing_msgs.len(), 1000);
    for (i, s) in swing_msgs.iter().enumerate() {
        let t = T0 + 1_000_000 * (i as u64 + 1);
        assert_eq!((s.1, s.2, s.3), (i as u32 + 1, t, t - 500));
        assert_eq!(s.4, cdr_string(&format!("swing {i}")));
    }
    let channel = scan.channels.values().find(|c| c.topic.name == "/rig/bat_params").unwrap();
    assert_eq!(channel.topic.qos, LATCHED);
    assert_eq!(channel.schema_encoding, "ros2msg");
    assert_eq!(channel.message_encoding, "cdr");
    assert_eq!(channel.topic.schema_text, STRING_SCHEMA);
    assert!(channel.metadata.contains_key("topic_type_hash"));

    // Independent readers: mcap + mcap-ros2-support (schemas in the file only) and rosbags (metadata.yaml).
    let verdict = python_check_bag(&dir);
    for reader in ["mcap", "rosbags"] {
        let t = &verdict[reader]["topics"];
        assert_eq!(t["/rig/swing"]["count"], 1000, "{reader}");
        assert_eq!(t["/rig/fast"]["count"], 100, "{reader}");
        assert_eq!(t["/rig/bat_params"]["count"], 1, "{reader}");
        assert_eq!(t["/rig/swing"]["first"]["data"], "swing 0", "{reader}");
        assert_eq!(t["/rig/swing"]["last"]["data"], "swing 999", "{reader}");
        assert_eq!(t["/rig/bat_params"]["type"], "std_msgs/msg/String", "{reader}");
    }
    let rb = &verdict["rosbags"]["topics"];
    assert_eq!(rb["/rig/bat_params"]["durability"], "transient_local");
    assert_eq!(rb["/rig/bat_params"]["depth"], 1);
    assert_eq!(rb["/rig/fast"]["reliability"], "best_effort");
    assert_eq!(verdict["rosbags"]["metadata"]["message_count"], 1101);
    assert_eq!(verdict["rosbags"]["metadata"]["start_time"], T0);
    // custom_data survives in metadata.yaml (read by rosbags) and in the file's rosbag2 record (read by us).
    assert_eq!(verdict["rosbags"]["metadata"]["custom_data"]["sweetspot/settings"], settings);
    assert_eq!(sweetspot::bag::info::custom_data_of(&scans)["sweetspot/settings"], settings);
}

#[test]
fn splits_by_size_into_complete_files_that_all_readers_join() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sized");
    let mut config = RecorderConfig::new(&dir);
    config.max_file_size = Some(32 * 1024);
    let recorder = Recorder::start(config).unwrap();
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for i in 0..400u64 {
        // Poorly compressible payload so the files really grow.
        let text: String = (0..200)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                char::from(b'a' + (state % 26) as u8)
            })
            .collect();
        // 400 messages cannot overflow a queue of 16384: a drop would break the count below.
        assert!(recorder.record(topic, cdr_string(&format!("{i} {text}")), T0 + i, T0 + i));
    }
    let stats = recorder.finish().unwrap();
    assert_eq!(stats.written, 400);
    let files = bag_files(&dir).unwrap();
    assert!(files.len() >= 2, "expected a split, got {files:?}");
    let mut total = 0;
    for (n, file) in files.iter().enumerate() {
        assert_eq!(file.file_name().unwrap().to_string_lossy(), format!("sized_{n}.mcap"));
        let scan = scan_file(file, |_| {}).unwrap();
        assert!(scan.complete, "{} has a summary", file.display());
        // Every split re-declares the channel.
        assert_eq!(scan.channels.len(), 1);
        total += scan.message_count();
        // A file closes once it passes the limit, so it overshoots by at most one chunk plus summary.
        assert!(scan.size < 32 * 1024 + 64 * 1024, "{} is {} bytes", file.display(), scan.size);
    }
    assert_eq!(total, 400);
    let verdict = python_check_bag(&dir);
    assert_eq!(verdict["mcap"]["files"].as_array().unwrap().len(), files.len());
    assert_eq!(verdict["mcap"]["topics"]["/rig/swing"]["count"], 400);
    assert_eq!(verdict["rosbags"]["topics"]["/rig/swing"]["count"], 400);
}

#[test]
fn splits_by_duration_of_recorded_time() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("timed");
    let mut config = RecorderConfig::new(&dir);
    config.max_file_duration = Some(Duration::from_secs(2));
    let recorder = Recorder::start(config).unwrap();
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    // 10 s of recorded time, one message every 100 ms.
    for i in 0..100u64 {
        let t = T0 + i * 100_000_000;
        assert!(recorder.record(topic, cdr_string(&format!("{i}")), t, t));
    }
    recorder.finish().unwrap();
    let files = bag_files(&dir).unwrap();
    assert_eq!(files.len(), 5, "10 s in 2 s files: {files:?}");
    for file in &files {
        let scan = scan_file(file, |_| {}).unwrap();
        let (first, last) = scan.time_range.unwrap();
        assert!(last - first < 2_000_000_000, "{}: {first}..{last}", file.display());
        assert_eq!(scan.message_count(), 20);
    }
    let verdict = python_check_bag(&dir);
    assert_eq!(verdict["rosbags"]["topics"]["/rig/swing"]["count"], 100);
    assert_eq!(verdict["mcap"]["topics"]["/rig/swing"]["files"].as_array().unwrap().len(), 5);
}

#[test]
fn unwritable_path_is_a_clean_error_naming_the_path() {
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("not_a_dir");
    std::fs::write(&file, b"x").unwrap();
    let dir = file.join("bag");
    match Recorder::start(RecorderConfig::new(&dir)) {
        Err(BagError::Io { path, .. }) => assert!(path.starts_with(&file), "{}", path.display()),
        Err(other) => panic!("expected an I/O error, got {other}"),
        Ok(_) => panic!("recording under a regular file must fail"),
    }
    // An existing directory is refused too (never overwrite a bag).
    let existing = tmp.path().join("existing");
    std::fs::create_dir(&existing).unwrap();
    assert!(matches!(Recorder::start(RecorderConfig::new(&existing)), Err(BagError::Io { .. })));
}

#[test]
fn full_disk_is_reported_and_record_keeps_returning() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("full");
    let mut config = RecorderConfig::new(&dir);
    config.max_file_size = Some(4 * 1024);
    config.queue_capacity = 64;
    let recorder = Recorder::start(config).unwrap();
    // The second split file lands on /dev/full: every write to it fails with ENOSPC, like a full disk.
    std::os::unix::fs::symlink("/dev/full", dir.join("full_1.mcap")).unwrap();
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    let mut attempts = 0u64;
    let mut accepted = 0u64;
    let mut i = 0u64;
    // Keep recording until the failure is reported; record() must return every time (no deadlock).
    while recorder.stats().error.is_none() {
        let text: String = (0..64).map(|k| char::from(b'a' + ((i * 7 + k) % 26) as u8)).collect();
        attempts += 1;
        if recorder.record(topic, cdr_string(&text), T0 + i, T0 + i) {
            accepted += 1;
        }
        i += 1;
        if i.is_multiple_of(64) {
            std::thread::sleep(Duration::from_millis(5));
        }
        assert!(i < 10_000_000, "the full disk was never reported");
    }
    let error = recorder.stats().error.unwrap();
    assert!(error.contains("full_1.mcap"), "error names the file: {error}");
    // After the failure record() refuses immediately and counts the drop.
    for _ in 0..1000 {
        attempts += 1;
        assert!(!recorder.record(topic, cdr_string("late"), T0, T0));
    }
    let stats = recorder.stats();
    assert_eq!(stats.written + stats.dropped, attempts, "every attempt is either written or counted as dropped");
    assert!(stats.written < accepted + 1);
    assert!(recorder.finish().is_err(), "finish reports the failure");
    // What was written before the disk filled up is intact.
    let first = scan_file(&dir.join("full_0.mcap"), |_| {}).unwrap();
    assert!(first.complete);
    assert!(first.message_count() > 0);
}

#[test]
fn dropping_the_recorder_finishes_the_bag() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("dropped");
    {
        let recorder = std::sync::Arc::new(Recorder::start(RecorderConfig::new(&dir)).unwrap());
        let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
        let threads: Vec<_> = (0..4)
            .map(|k| {
                let recorder = recorder.clone();
                std::thread::spawn(move || {
                    for i in 0..250u64 {
                        assert!(recorder.record(topic, cdr_string(&format!("{k}:{i}")), T0 + i, T0 + i));
                    }
                })
            })
            .collect();
        for t in threads {
            t.join().unwrap();
        }
    }
    let scan = scan_file(&dir.join("dropped_0.mcap"), |_| {}).unwrap();
    assert!(scan.complete);
    assert_eq!(scan.message_count(), 1000);
    assert!(dir.join("metadata.yaml").exists());
}

#[test]
fn records_that_race_the_writer_are_all_accounted_for() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("tiny_queue");
    let mut config = RecorderConfig::new(&dir);
    config.queue_capacity = 1;
    let recorder = Recorder::start(config).unwrap();
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    let mut accepted = 0u64;
    for i in 0..20_000u64 {
        if recorder.record(topic, cdr_string("x"), T0 + i, T0 + i) {
            accepted += 1;
        }
    }
    let stats = recorder.finish().unwrap();
    assert_eq!(stats.written, accepted);
    assert_eq!(stats.written + stats.dropped, 20_000);
    let scan = scan_file(&dir.join("tiny_queue_0.mcap"), |_| {}).unwrap();
    assert_eq!(scan.message_count(), accepted);
}

/// Offsets where each top-level Message record of an MCAP file ends.
fn message_record_ends(bytes: &[u8]) -> Vec<u64> {
    top_level_records(bytes).into_iter().filter(|r| r.message.is_some()).map(|r| r.end).collect()
}

#[test]
fn fastwrite_splits_by_size_right_after_the_message_that_fills_a_file() {
    const LIMIT: u64 = 32 * 1024;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("sized");
    let mut config = RecorderConfig::new(&dir);
    config.max_file_size = Some(LIMIT);
    let recorder = Recorder::start_with(config, StorageOptions::preset("fastwrite").unwrap()).unwrap();
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    for i in 0..400u64 {
        // 400 messages of ~230 bytes: whole batches of them reach the writer at once, so the split
        // happens inside a batch.
        assert!(recorder.record(topic, cdr_string(&format!("{i} {}", "y".repeat(200))), T0 + i, T0 + i));
    }
    assert_eq!(recorder.finish().unwrap().written, 400);
    let files = bag_files(&dir).unwrap();
    assert!(files.len() >= 2, "expected a split, got {files:?}");
    let mut next = 0u64;
    for (n, file) in files.iter().enumerate() {
        let mut indices = Vec::new();
        let scan = scan_file(file, |m| {
            let text = std::str::from_utf8(&m.data[8..]).unwrap();
            indices.push(text.split(' ').next().unwrap().parse::<u64>().unwrap());
        })
        .unwrap();
        assert!(scan.complete, "{} has a summary", file.display());
        assert_eq!(scan.layout(), Some(McapLayout::Unchunked));
        assert_eq!(scan.channels.len(), 1, "every split re-declares the channel");
        assert!(indices.iter().copied().eq(next..next + indices.len() as u64), "gap-free across files");
        next += indices.len() as u64;
        let ends = message_record_ends(&std::fs::read(file).unwrap());
        if n + 1 < files.len() {
            // The file closed with the first message that took it to the limit: not one earlier or later.
            let last = ends[ends.len() - 1];
            let before = ends[ends.len() - 2];
            assert!(before < LIMIT && last >= LIMIT, "{}: messages end at {before} then {last}", file.display());
        }
    }
    assert_eq!(next, 400);
    let verdict = python_check_bag(&dir);
    assert_eq!(verdict["mcap"]["files"].as_array().unwrap().len(), files.len());
    assert_eq!(verdict["mcap"]["topics"]["/rig/swing"]["count"], 400);
    assert_eq!(verdict["rosbags"]["topics"]["/rig/swing"]["count"], 400);
}

#[test]
fn fastwrite_splits_by_duration_of_recorded_time() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("timed");
    let mut config = RecorderConfig::new(&dir);
    config.max_file_duration = Some(Duration::from_secs(2));
    let recorder = Recorder::start_with(config, StorageOptions::preset("fastwrite").unwrap()).unwrap();
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    for i in 0..100u64 {
        let t = T0 + i * 100_000_000;
        assert!(recorder.record(topic, cdr_string(&format!("{i}")), t, t));
    }
    recorder.finish().unwrap();
    let files = bag_files(&dir).unwrap();
    assert_eq!(files.len(), 5, "10 s in 2 s files: {files:?}");
    for file in &files {
        let scan = scan_file(file, |_| {}).unwrap();
        let (first, last) = scan.time_range.unwrap();
        assert!(last - first < 2_000_000_000, "{}: {first}..{last}", file.display());
        assert_eq!((scan.message_count(), scan.unchunked_messages, scan.chunks), (20, 20, 0));
    }
    let verdict = python_check_bag(&dir);
    assert_eq!(verdict["rosbags"]["topics"]["/rig/swing"]["count"], 100);
    assert_eq!(verdict["mcap"]["topics"]["/rig/swing"]["files"].as_array().unwrap().len(), 5);
}
