//! Bags recorded and played over real DDS (inside the private network namespace of scripts/test; issue 23,
//! items 1 and 4): a `bag record` → `bag replay` round trip at several rates, with and without `fastwrite`,
//! read back in log-time order by the Python `mcap` reader and by `rosbags`; `bag play` into a node that is
//! already running losing no swing.

mod support;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;
use support::node::NodeProcess;
use support::{python, run_ok, sweetspot};

/// ROS_DOMAIN_IDs of these tests.
const TRIP_DOMAIN: u16 = 226;
const PLAY_DOMAIN: u16 = 227;
const REFUSE_DOMAIN: u16 = 228;

/// In file order (files as metadata.yaml lists them, each read front to back by `NonSeekingReader`): every
/// log time, and the swings and answers decoded by `rosbags` through metadata.yaml and the stored message
/// definitions, as (swing_id, sec, nanosec).
const PY_READ: &str = r#"
import json, sys
from pathlib import Path
from mcap.reader import NonSeekingReader
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore, get_types_from_msg
from ruamel.yaml import YAML

bag = Path(sys.argv[1])
meta = YAML(typ="safe").load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
log_times = []
for name in meta["relative_file_paths"]:
    with open(bag / name, "rb") as f:
        for schema, channel, message in NonSeekingReader(f).iter_messages():
            log_times.append(message.log_time)
store = get_typestore(Stores.EMPTY)
out = {"log_times": log_times, "swings": [], "answers": [], "modal": []}
with Reader(bag) as reader:
    types = {}
    for conn in reader.connections:
        if conn.msgdef.data:
            types.update(get_types_from_msg(conn.msgdef.data, conn.msgtype))
    store.register(types)
    kinds = {"sweetspot_msgs/msg/Swing": "swings", "sweetspot_msgs/msg/ExitVelocity": "answers",
             "sweetspot_msgs/msg/ModalEnergies": "modal"}
    conns = [c for c in reader.connections if c.msgtype in kinds]
    for conn, _t, raw in reader.messages(connections=conns):
        m = store.deserialize_cdr(raw, conn.msgtype)
        out[kinds[conn.msgtype]].append([int(m.swing_id), int(m.header.stamp.sec), int(m.header.stamp.nanosec)])
print(json.dumps(out))
"#;

fn python_read(dir: &Path) -> Value {
    let out = Command::new(python()).arg("-c").arg(PY_READ).arg(dir).output().unwrap();
    assert!(out.status.success(), "python readers on {}: {}", dir.display(), String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Waits until `topic` has `n` messages in the bag being written (the recorder flushes every second).
fn wait_for_count(dir: &Path, topic: &str, n: u64) {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let count = sweetspot::bag::info::bag_info(dir)
            .ok()
            .and_then(|i| i.topics.iter().find(|t| t.name == topic).map(|t| t.count))
            .unwrap_or(0);
        if count >= n {
            return;
        }
        assert!(Instant::now() < deadline, "{topic}: {count} of {n} messages in {}", dir.display());
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// SIGINT, then the child must exit 0; returns its stderr.
fn interrupt(child: Child, what: &str) -> String {
    let status = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{what}: {stderr}");
    stderr
}

/// `count` swings as JSON lines, on two bats (one sent as BatParams, one a preset).
fn swings_file(dir: &Path, count: usize) -> PathBuf {
    let path = dir.join("swings.jsonl");
    let lines: Vec<String> = (0..count)
        .map(|k| {
            let bat = if k % 3 == 0 { "r161" } else { "mine" };
            format!(
                "{{\"bat_id\": \"{bat}\", \"ball_speed\": {}, \"bat_cm_speed\": 24, \"bat_angular_speed\": 45, \
                 \"impact_z\": {}}}",
                36 + k % 9,
                0.60 + 0.01 * (k % 12) as f64
            )
        })
        .collect();
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    path
}

/// node → `bag record -a` beside it → swings at `rate` → the bag replays whole and reads in log-time order.
fn round_trip(rate: u32, preset: &str, count: usize) {
    let tmp = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(TRIP_DOMAIN, tmp.path(), &["--no-record", "--ros-args", "-r", "__ns:=/lab"]);
    let dir = tmp.path().join("trip");
    let mut record = sweetspot(TRIP_DOMAIN, &["bag", "record", "-a", "--storage-preset-profile", preset, "-o"]);
    record.arg(&dir).stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::piped());
    let record = record.spawn().unwrap();
    // A bat of our own, latched (the recorder picks it up whenever it subscribes).
    run_ok(
        sweetspot(
            TRIP_DOMAIN,
            &["pub", "bat", "{bat_id: mine, preset: aluminum}", "--ns", "/lab", "--keep-alive", "1", "--timeout", "30"],
        ),
        "pub bat",
    );
    // -w 2: the node's subscription and the recorder's, so that the recorder has every swing.
    let file = swings_file(tmp.path(), count);
    let mut pubs = sweetspot(TRIP_DOMAIN, &["pub", "swing", "--ns", "/lab", "-w", "2", "--timeout", "60", "--rate"]);
    pubs.arg(rate.to_string()).arg("--file").arg(&file).stdout(Stdio::null());
    run_ok(pubs, "pub swing");
    wait_for_count(&dir, "/lab/exit_velocity", count as u64);
    wait_for_count(&dir, "/lab/modal_energies", count as u64);
    let stderr = interrupt(record, "bag record");
    node.stop_with(libc::SIGINT);
    let what = format!("{count} swings at {rate}/s, preset {preset}");

    // The readers that share no code with sweetspot: log times never go backwards in file order (rosbags
    // would refuse an unindexed fastwrite file otherwise), and every answer has its swing.
    let got = python_read(&dir);
    let log_times: Vec<u64> = got["log_times"].as_array().unwrap().iter().map(|t| t.as_u64().unwrap()).collect();
    assert!(log_times.windows(2).all(|w| w[0] <= w[1]), "{what}: log times go backwards in file order\n{stderr}");
    let key = |v: &Value| (v[0].as_u64().unwrap(), v[1].as_i64().unwrap(), v[2].as_u64().unwrap());
    let swings: Vec<_> = got["swings"].as_array().unwrap().iter().map(key).collect();
    assert_eq!(swings.len(), count, "{what}");
    for kind in ["answers", "modal"] {
        let outputs: Vec<_> = got[kind].as_array().unwrap().iter().map(key).collect();
        assert_eq!(outputs.len(), count, "{what}: {kind}");
        assert!(outputs.iter().all(|o| swings.contains(o)), "{what}: every {kind} entry has its swing");
    }

    // sweetspot's own tools pair every answer with its swing and replay it bit for bit.
    let out = support::run_ok(
        {
            let mut c = Command::new(support::BIN);
            c.args(["bag", "replay"]).arg(&dir);
            c
        },
        "bag replay",
    );
    let replay = String::from_utf8_lossy(&out.stdout);
    let tally = format!("{count} swings: {count} match, 0 differ (bit-exact), 0 without recorded output");
    assert!(replay.contains(&tally), "{what}:\n{replay}");
    let mut export = Command::new(support::BIN);
    export.args(["bag", "export", "--csv"]).arg(&dir);
    let out = support::run_ok(export, "bag export");
    let note = String::from_utf8_lossy(&out.stderr);
    let paired = format!(
        "exported {count} swings ({count} with ExitVelocity, {count} with ModalEnergies; 0 outputs without their swing"
    );
    assert!(note.contains(&paired), "{what}: {note}");
    let csv = String::from_utf8_lossy(&out.stdout);
    assert!(csv.lines().skip(1).all(|l| l.starts_with("/lab,")), "{what}: the node's namespace on every row");
}

#[test]
fn record_then_replay_round_trips_at_several_rates_with_and_without_fastwrite() {
    support::require_isolated_network();
    for (rate, preset) in [(20, "none"), (400, "fastwrite"), (2000, "fastwrite"), (2000, "none")] {
        round_trip(rate, preset, 60);
    }
}

fn golden() -> PathBuf {
    support::repo().join("bags/golden/sweetspot_golden")
}

/// (swing_id, exit speed bits) of every answered swing of a bag.
fn answers(bag: &Path) -> Vec<(u64, u64)> {
    let (rows, _) = sweetspot::bag::export::swing_rows(bag).unwrap();
    let mut out: Vec<(u64, u64)> = rows
        .iter()
        .filter_map(|r| r.exit_velocity.as_ref().map(|e| (r.swing.swing_id, e.exit_speed.to_bits())))
        .collect();
    out.sort();
    out
}

#[test]
fn play_into_a_running_node_loses_no_swing() {
    support::require_isolated_network();
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("answers");
    let record_path = format!("record_path:={}", bag.display());
    let node = NodeProcess::spawn(PLAY_DOMAIN, tmp.path(), &["--ros-args", "-r", "__ns:=/golden", "-p", &record_path]);
    // The node is up (its bag lists its topics) before play starts: play must find it, not the other way.
    let deadline = Instant::now() + Duration::from_secs(30);
    while !std::fs::read_to_string(bag.join("metadata.yaml")).is_ok_and(|m| m.contains("/golden/exit_velocity")) {
        assert!(Instant::now() < deadline, "the node never started recording");
        std::thread::sleep(Duration::from_millis(100));
    }
    // No --wait-subscribers, no --delay: the default wait.
    let mut play = sweetspot(PLAY_DOMAIN, &["bag", "play", "-q", "--rate", "4"]);
    play.arg(golden());
    let out = run_ok(play, "bag play");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("warning"), "{stderr}");
    assert!(stderr.contains("published 13 messages in 1 pass"), "{stderr}");
    let expected = answers(&golden());
    assert_eq!(expected.len(), 10);
    wait_for_count(&bag, "/golden/exit_velocity", 10);

    // A played topic nobody subscribes to is warned of, and playing goes on.
    let mut play =
        sweetspot(PLAY_DOMAIN, &["bag", "play", "-q", "--rate", "8", "--remap", "/golden/swing:=/nobody/swing"]);
    play.arg(golden());
    let out = run_ok(play, "bag play --remap");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("warning: no subscriber on /nobody/swing"), "{stderr}");
    assert!(!stderr.contains("no subscriber on /golden/bat/params"), "{stderr}");

    node.stop_with(libc::SIGINT);
    assert_eq!(answers(&bag), expected, "every played swing answered, exactly as recorded");
}

#[test]
fn play_and_record_refuse_before_doing_anything() {
    support::require_isolated_network();
    let tmp = tempfile::tempdir().unwrap();
    let run = |args: &[&str], extra: Option<&Path>| {
        let mut c = sweetspot(REFUSE_DOMAIN, args);
        if let Some(p) = extra {
            c.arg(p);
        }
        let out = c.stdin(Stdio::null()).output().unwrap();
        assert!(!out.status.success(), "{args:?} must fail");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    // Two types on one topic through a remap: refused before publishing, and not blamed on the bag.
    let err = run(&["bag", "play", "--remap", "/golden/swing:=/golden/bat/params"], Some(&golden()));
    assert!(err.contains("one topic carries one type") && !err.contains("bad bag"), "{err}");
    let err = run(&["bag", "play", "-r", "0"], Some(&golden()));
    assert!(err.contains("0 is out of range") && err.contains("--rate") && !err.contains("bad bag"), "{err}");
    let err = run(&["bag", "play", golden().to_str().unwrap(), "--topics", "/nope"], None);
    assert!(err.contains("--topics: /nope is not in the bag") && !err.contains("bad bag"), "{err}");
    // A topic whose subscribers take another type: refused before the first message.
    let mut echo = sweetspot(REFUSE_DOMAIN, &["echo", "exit_velocity", "--ns", "/golden"]);
    let echo = echo.stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
    let err = run(&["bag", "play", "--remap", "/golden/swing:=/golden/exit_velocity"], Some(&golden()));
    assert!(err.contains("its subscribers take sweetspot_msgs::msg::dds_::ExitVelocity_"), "{err}");
    assert!(!err.contains("published"), "{err}");
    let _ = interrupt(echo, "echo");
    // bag record -o onto something that exists: refused, and never said to be recording.
    let existing = tmp.path().join("existing");
    std::fs::create_dir(&existing).unwrap();
    let err = run(&["bag", "record", "-a", "-o"], Some(&existing));
    assert!(!err.contains("recording to"), "{err}");
    assert!(err.contains("exists"), "{err}");
}
