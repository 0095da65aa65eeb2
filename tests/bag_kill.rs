//! kill -9 while recording under load, then `sweetspot bag recover`: everything older than the flush
//! interval (plus a margin for scheduling) survives, gap-free and uncorrupted, in a repaired copy beside the
//! bag (`DIR.recovered/`); the original is left byte for byte. Unchunked (`fastwrite`) files cut anywhere keep
//! every complete message.

mod support;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use support::bag::*;
use sweetspot::bag::reader::{bag_files, read_bag, scan_file};

const FLUSH_MS: u64 = 200;
/// Scheduling slack on a loaded 2-core machine on top of the flush interval.
const MARGIN_MS: u64 = 1500;

fn example_bin(name: &str) -> std::path::PathBuf {
    // tests run from target/<profile>/deps; cargo test builds examples into target/<profile>/examples.
    let exe = std::env::current_exe().unwrap();
    let path = exe.parent().unwrap().parent().unwrap().join("examples").join(name);
    if !path.exists() {
        // A plain `cargo test` builds examples; `cargo test --test bag_kill` does not, so build it here.
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let status = Command::new(cargo)
            .args(["build", "--offline", "--example", name])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .status()
            .unwrap();
        assert!(status.success(), "building example {name}");
    }
    assert!(path.exists(), "{} not built", path.display());
    path
}

#[test]
fn sigkill_mid_recording_loses_at_most_the_last_flush_interval() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("load");
    let mut child = Command::new(example_bin("bag_load_writer"))
        .arg(&dir)
        .arg(FLUSH_MS.to_string())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    assert_eq!(line.trim(), "started");
    std::thread::sleep(Duration::from_millis(2500));
    let kill_time = SystemTime::now().duration_since(UNIX_EPOCH).unwrap().as_nanos() as u64;
    child.kill().unwrap(); // SIGKILL
    let status = child.wait().unwrap();
    assert!(status.code().is_none(), "the writer must have been killed, not exited: {status}");

    let files = bag_files(&dir).unwrap();
    assert_eq!(files.len(), 1);
    let before = scan_file(&files[0], |_| {}).unwrap();
    assert!(!before.complete, "a killed recording has no summary");
    let original = std::fs::read(&files[0]).unwrap();

    let out = Command::new(sweetspot_bin()).args(["bag", "recover"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "recover failed: {}", String::from_utf8_lossy(&out.stderr));
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(report.contains("rebuilt"), "{report}");
    assert_eq!(std::fs::read(&files[0]).unwrap(), original, "the original is left byte for byte");
    let killed = dir;
    let dir = tmp.path().join("load.recovered");
    assert!(report.contains(&dir.display().to_string()), "the report names the copy: {report}");

    let mut indices = Vec::new();
    let mut last_log_time = 0;
    let scans = read_bag(&dir, |m| {
        // Payload: CDR header, length, "<index> <log_time> xxx…" NUL.
        let text = std::str::from_utf8(&m.data[8..m.data.len()]).unwrap().trim_end_matches('\0');
        let mut parts = text.split(' ');
        let index: u64 = parts.next().unwrap().parse().unwrap();
        let stamp: u64 = parts.next().unwrap().parse().unwrap();
        assert_eq!(stamp, m.log_time_ns, "payload and log time agree (no corrupt data)");
        assert_eq!(parts.next().unwrap(), "x".repeat(100));
        let expected_topic = ["/load/a", "/load/b", "/load/c"][(index % 3) as usize];
        assert_eq!(m.channel.topic.name, expected_topic);
        indices.push(index);
        last_log_time = last_log_time.max(m.log_time_ns);
    })
    .unwrap();
    assert!(scans.iter().all(|s| s.complete), "recovered files are complete");
    assert_eq!(scans[0].message_count(), before.message_count(), "recovery keeps every message it could read");
    indices.sort_unstable();
    let n = indices.len() as u64;
    assert!(n > 1000, "recorded under load: {n}");
    assert!(indices.iter().copied().eq(0..n), "the survivors are exactly messages 0..{n}, no gaps or duplicates");
    let lost_ns = kill_time.saturating_sub(last_log_time);
    eprintln!("survived {n} messages; lost the last {} ms before the kill", lost_ns / 1_000_000);
    assert!(
        lost_ns <= (FLUSH_MS + MARGIN_MS) * 1_000_000,
        "lost the last {} ms, more than flush {FLUSH_MS} ms + margin {MARGIN_MS} ms",
        lost_ns / 1_000_000
    );

    // metadata.yaml was rebuilt and the independent readers agree.
    let verdict = python_check_bag(&dir);
    let total: u64 = ["/load/a", "/load/b", "/load/c"]
        .iter()
        .map(|t| verdict["rosbags"]["topics"][t]["count"].as_u64().unwrap())
        .sum();
    assert_eq!(total, n);
    // The copy is finished and undamaged: recovering it writes nothing.
    let again = Command::new(sweetspot_bin()).args(["bag", "recover"]).arg(&dir).output().unwrap();
    assert!(again.status.success());
    assert!(String::from_utf8_lossy(&again.stdout).contains("nothing to recover"));
    assert!(!tmp.path().join("load.recovered.recovered").exists());
    // Recovering the original again is refused rather than overwriting the copy.
    let twice = Command::new(sweetspot_bin()).args(["bag", "recover"]).arg(&killed).output().unwrap();
    assert!(!twice.status.success());
    assert!(String::from_utf8_lossy(&twice.stderr).contains("already exists"));
}

#[test]
fn info_reports_topics_counts_and_an_unfinished_file() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("info");
    {
        let recorder = sweetspot::bag::Recorder::start(sweetspot::bag::RecorderConfig::new(&dir)).unwrap();
        let a = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
        let b = recorder.register_topic(string_topic("/rig/bat_params", LATCHED)).unwrap();
        assert!(recorder.record(b, cdr_string("bat"), 1_000_000_000, 1_000_000_000));
        for i in 0..10u64 {
            assert!(recorder.record(a, cdr_string("s"), 2_000_000_000 + i * 100_000_000, 0));
        }
        recorder.finish().unwrap();
    }
    let out = Command::new(sweetspot_bin()).args(["bag", "info"]).arg(&dir).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Messages:          11"), "{text}");
    assert!(text.contains("Duration:          1.900000000s"), "{text}");
    assert!(text.contains("Topic: /rig/swing      | Type: std_msgs/msg/String | Count: 10"), "{text}");
    assert!(text.contains("transient_local, depth 1"), "{text}");
    assert!(text.contains("zstd"), "{text}");
    // One chunk holds the two topics' Schema and Channel records, one the 11 messages: the definitions get a
    // chunk of their own, so damage to a message chunk cannot take them with it.
    assert!(text.contains("Chunks:            2\n"), "{text}");
    let out =
        Command::new(sweetspot_bin()).args(["bag", "info", "--json"]).arg(dir.join("info_0.mcap")).output().unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["messages"], 11);
    assert_eq!(json["start_ns"], 1_000_000_000u64);
    assert_eq!(json["files"][0]["complete"], true);
    assert_eq!(json["profile"], "ros2");

    // Cut the file in the middle of a record: info still reads what is complete, but the cut-off record is
    // a loss, named, and an error unless the user skips damage.
    let file = dir.join("info_0.mcap");
    let bytes = std::fs::read(&file).unwrap();
    std::fs::write(&file, &bytes[..bytes.len() / 2]).unwrap();
    let out = Command::new(sweetspot_bin()).args(["bag", "info", "--json"]).arg(&dir).output().unwrap();
    assert!(!out.status.success(), "a cut-off record is damage");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("info_0.mcap") && stderr.contains("ends inside a record"), "{stderr}");
    let out =
        Command::new(sweetspot_bin()).args(["bag", "info", "--json", "--skip-damaged"]).arg(&dir).output().unwrap();
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["files"][0]["complete"], false);
    assert!(json["files"][0]["truncated_bytes"].as_u64().unwrap() > 0);
    assert_eq!(json["files"][0]["damage"][0]["kind"], "truncated");
}

/// (end offset of the record, log time, channel id, payload) of each top-level Message record of a file.
fn top_level_messages(bytes: &[u8]) -> Vec<(u64, u64, u16, Vec<u8>)> {
    top_level_records(bytes)
        .into_iter()
        .filter_map(|r| r.message.map(|(log_time, channel, data)| (r.end, log_time, channel, data)))
        .collect()
}

fn record_fastwrite(dir: &std::path::Path, config: sweetspot::bag::RecorderConfig) -> sweetspot::bag::Recorder {
    let storage = sweetspot::bag::StorageOptions::preset("fastwrite").unwrap();
    let recorder = sweetspot::bag::Recorder::start_with(config, storage).unwrap();
    assert_eq!(recorder.dir(), dir);
    recorder
}

#[test]
fn a_cut_off_fastwrite_file_recovers_with_every_complete_message() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("fw");
    let recorder = record_fastwrite(&dir, sweetspot::bag::RecorderConfig::new(&dir));
    let topics: Vec<_> = ["/rig/a", "/rig/b", "/rig/c"]
        .iter()
        .map(|name| recorder.register_topic(string_topic(name, RELIABLE)).unwrap())
        .collect();
    for i in 0..900u64 {
        let t = 1_000_000_000 + i * 1_000_000;
        assert!(recorder.record(topics[(i % 3) as usize], cdr_string(&format!("{i} {}", "z".repeat(40))), t, t));
    }
    recorder.finish().unwrap();
    let bytes = std::fs::read(dir.join("fw_0.mcap")).unwrap();
    let messages = top_level_messages(&bytes);
    assert_eq!(messages.len(), 900);

    // Cut inside a message record, exactly at a record boundary, inside the summary (every message but no
    // footer), and before the first message ends.
    let cuts =
        [(messages[499].0 + 5, 500), (messages[699].0, 700), (bytes.len() as u64 - 30, 900), (messages[0].0 - 1, 0)];
    for (cut, survivors) in cuts {
        let case = tmp.path().join(format!("cut_{cut}"));
        std::fs::create_dir(&case).unwrap();
        let file = case.join("cut_0.mcap");
        std::fs::write(&file, &bytes[..cut as usize]).unwrap();
        let before = scan_file(&file, |_| {}).unwrap();
        assert!(!before.complete);
        assert_eq!(before.message_count(), survivors as u64, "cut at {cut}");

        let out = Command::new(sweetspot_bin()).args(["bag", "recover"]).arg(&case).output().unwrap();
        assert!(out.status.success(), "recover failed: {}", String::from_utf8_lossy(&out.stderr));
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(stdout.contains("rebuilt"));
        if survivors > 0 {
            assert!(stdout.contains(&format!("kept {survivors} messages unchunked;")), "{stdout}");
        }
        assert_eq!(std::fs::read(&file).unwrap(), &bytes[..cut as usize], "the original is left as it was");
        let case = tmp.path().join(format!("cut_{cut}.recovered"));
        let file = case.join("cut_0.mcap");

        let mut recovered = Vec::new();
        let scans = read_bag(&case, |m| recovered.push((m.log_time_ns, m.channel_id, m.data.to_vec()))).unwrap();
        assert!(scans[0].complete, "cut at {cut}: the rebuilt file is complete");
        let kept: Vec<_> = messages[..survivors].iter().map(|m| (m.1, m.2, m.3.clone())).collect();
        assert_eq!(recovered, kept, "cut at {cut}: exactly the complete messages, byte for byte");
        if survivors == 0 {
            continue;
        }
        assert_eq!(scans[0].layout(), Some(sweetspot::bag::McapLayout::Unchunked), "recovery keeps the layout");
        // The rebuilt file has a proper summary (the mcap crate, all CRCs) and the Python readers agree.
        let rebuilt = std::fs::read(&file).unwrap();
        let summary = mcap::Summary::read(&rebuilt).unwrap().expect("a summary");
        assert_eq!(summary.stats.as_ref().unwrap().message_count, survivors as u64);
        assert!(summary.chunk_indexes.is_empty());
        let verdict = python_check_bag(&case);
        let total: u64 = ["/rig/a", "/rig/b", "/rig/c"]
            .iter()
            .map(|t| verdict["rosbags"]["topics"][t]["count"].as_u64().unwrap_or(0))
            .sum();
        assert_eq!(total, survivors as u64, "cut at {cut}");
    }
}

#[test]
fn fastwrite_flushes_every_interval_so_a_kill_keeps_what_was_recorded_before_it() {
    // What a kill -9 leaves is what the process handed to the OS: a copy of the file taken while the
    // recorder runs is that state. Everything recorded must reach it within the flush interval.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("live");
    let mut config = sweetspot::bag::RecorderConfig::new(&dir);
    config.flush_interval = Duration::from_millis(100);
    let recorder = record_fastwrite(&dir, config);
    let topic = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    // Fewer than a batch: only the periodic flush can get them to the file.
    for i in 0..500u64 {
        assert!(recorder.record(topic, cdr_string(&format!("{i}")), 1_000 + i, 1_000 + i));
    }
    let snapshot = tmp.path().join("snapshot");
    std::fs::create_dir(&snapshot).unwrap();
    let copy = snapshot.join("snapshot_0.mcap");
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    let found = loop {
        std::fs::copy(dir.join("live_0.mcap"), &copy).unwrap();
        // Until the writer's first flush the file is empty, which is not an MCAP file (yet).
        let count = match scan_file(&copy, |_| {}) {
            Ok(scan) => scan.message_count(),
            Err(sweetspot::bag::BagError::NotMcap { reason, .. }) if reason.contains("empty") => 0,
            Err(e) => panic!("{e}"),
        };
        if count == 500 || std::time::Instant::now() > deadline {
            break count;
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(found, 500, "every message recorded reached the file while the recorder was still running");
    let out = Command::new(sweetspot_bin()).args(["bag", "recover"]).arg(&snapshot).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let mut indices = Vec::new();
    let scans = read_bag(&tmp.path().join("snapshot.recovered"), |m| {
        indices.push(std::str::from_utf8(&m.data[8..]).unwrap().trim_end_matches('\0').parse::<u64>().unwrap())
    })
    .unwrap();
    assert!(scans[0].complete);
    assert!(indices.iter().copied().eq(0..500), "recovered in order, gap-free");
    recorder.finish().unwrap();
}

#[test]
fn info_says_a_fastwrite_bag_is_unchunked_and_keeps_the_chunked_lines() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("fwinfo");
    let recorder = record_fastwrite(&dir, sweetspot::bag::RecorderConfig::new(&dir));
    let a = recorder.register_topic(string_topic("/rig/swing", RELIABLE)).unwrap();
    for i in 0..10u64 {
        assert!(recorder.record(a, cdr_string("s"), 2_000_000_000 + i * 100_000_000, 0));
    }
    recorder.finish().unwrap();
    let out = Command::new(sweetspot_bin()).args(["bag", "info"]).arg(&dir).output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Compression:       none\n"), "{text}");
    assert!(
        text.contains("Chunks:            none (unchunked: messages outside chunks, no message indexes)"),
        "{text}"
    );
    assert!(text.contains("Messages:          10"), "{text}");
    let out = Command::new(sweetspot_bin()).args(["bag", "info", "--json"]).arg(&dir).output().unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["layout"], serde_json::json!(["unchunked"]));
    assert_eq!(
        (json["files"][0]["layout"].as_str(), json["files"][0]["chunks"].as_u64()),
        (Some("unchunked"), Some(0))
    );
}
