//! kill -9 while recording under load, then `sweetspot bag recover`: everything older than the flush
//! interval (plus a margin for scheduling) survives, gap-free and uncorrupted.

mod bag_support;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use bag_support::*;
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

    let out = Command::new(sweetspot_bin()).args(["bag", "recover"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "recover failed: {}", String::from_utf8_lossy(&out.stderr));
    let report = String::from_utf8_lossy(&out.stdout);
    assert!(report.contains("rebuilt"), "{report}");

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
    // Recovering again leaves the complete file alone.
    let again = Command::new(sweetspot_bin()).args(["bag", "recover"]).arg(&dir).output().unwrap();
    assert!(String::from_utf8_lossy(&again.stdout).contains("left as is"));
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
    let out = Command::new(sweetspot_bin()).args(["bag", "info", "--json"]).arg(dir.join("info_0.mcap")).output().unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["messages"], 11);
    assert_eq!(json["start_ns"], 1_000_000_000u64);
    assert_eq!(json["files"][0]["complete"], true);
    assert_eq!(json["profile"], "ros2");

    // Cut the file in the middle: info still reads what is complete and flags it.
    let file = dir.join("info_0.mcap");
    let bytes = std::fs::read(&file).unwrap();
    std::fs::write(&file, &bytes[..bytes.len() / 2]).unwrap();
    let out = Command::new(sweetspot_bin()).args(["bag", "info", "--json"]).arg(&dir).output().unwrap();
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["files"][0]["complete"], false);
    assert!(json["files"][0]["truncated_bytes"].as_u64().unwrap() > 0);
}
