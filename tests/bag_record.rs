//! `bag record` end to end over real DDS (inside the private network namespace of scripts/test): the node
//! runs, `bag record` records beside it, `sweetspot pub` publishes swings; the bag is then read by the
//! independent Python readers (`mcap` + `mcap-ros2-support`, and `rosbags`).

mod support;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;
use support::node::NodeProcess;
use support::{python, run_ok, sweetspot};

/// ROS_DOMAIN_ID of these tests.
const ALL_DOMAIN: u16 = 211;
const LIST_DOMAIN: u16 = 212;

/// Reads a bag directory with both Python readers. Prints JSON: per channel (mcap) its type, schema
/// encoding, schema length and count; the swings decoded by mcap-ros2-support; the swings decoded by rosbags
/// from the stored definitions (types without a definition are not registered).
const PY_READ: &str = r#"
import json, sys
from pathlib import Path
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore, get_types_from_msg

bag = Path(sys.argv[1]); swing_topic = sys.argv[2]
channels, mcap_swings = {}, []
for path in sorted(bag.glob("*.mcap")):
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        for ch in summary.channels.values():
            schema = summary.schemas[ch.schema_id]
            channels.setdefault(ch.topic, {"type": schema.name, "encoding": schema.encoding,
                                           "schema_len": len(schema.data), "count": 0})
        for schema, ch, msg in reader.iter_messages():
            channels[ch.topic]["count"] += 1
        f.seek(0)
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for schema, ch, msg, decoded in reader.iter_decoded_messages(topics=[swing_topic]):
            mcap_swings.append({"swing_id": decoded.swing_id, "bat_id": decoded.bat_id,
                                "impact_z": decoded.impact_z})
store = get_typestore(Stores.EMPTY)
rosbags_swings, rosbags_topics = [], {}
with Reader(bag) as reader:
    types = {}
    for conn in reader.connections:
        rosbags_topics[conn.topic] = conn.msgtype
        if conn.msgdef.data:
            types.update(get_types_from_msg(conn.msgdef.data, conn.msgtype))
    store.register(types)
    conns = [c for c in reader.connections if c.topic == swing_topic]
    for conn, _t, raw in reader.messages(connections=conns):
        m = store.deserialize_cdr(raw, conn.msgtype)
        rosbags_swings.append({"swing_id": m.swing_id, "bat_id": m.bat_id, "impact_z": m.impact_z})
print(json.dumps({"channels": channels, "mcap_swings": mcap_swings, "rosbags_swings": rosbags_swings,
                  "rosbags_topics": rosbags_topics}))
"#;

fn read_bag(dir: &Path, swing_topic: &str) -> Value {
    let out = Command::new(python()).arg("-c").arg(PY_READ).arg(dir).arg(swing_topic).output().unwrap();
    assert!(
        out.status.success(),
        "python readers failed on {}: {}",
        dir.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Starts `bag record ARGS` with stderr piped.
fn start_record(domain: u16, args: &[&str]) -> Child {
    let mut c = sweetspot(domain, &["bag", "record"]);
    c.args(args).stdin(Stdio::null()).stdout(Stdio::null()).stderr(Stdio::piped());
    c.spawn().expect("starting bag record")
}

/// Publishes five swings into /lab/swing, waiting for two subscriptions (the node's and the recorder's).
fn publish_swings(domain: u16) {
    let swing = "{bat_id: r161, ball_speed: 40, bat_cm_speed: 20, impact_z: 0.7}";
    run_ok(
        sweetspot(
            domain,
            &["pub", "swing", swing, "--ns", "/lab", "-t", "5", "-r", "20", "-w", "2", "--timeout", "30"],
        ),
        "sweetspot pub",
    );
}

/// Waits until the bag being written holds `n` messages on `topic` (the recorder flushes every second).
fn wait_for_count(dir: &Path, topic: &str, n: u64) {
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        let count = sweetspot::bag::info::bag_info(dir)
            .ok()
            .and_then(|i| i.topics.iter().find(|t| t.name == topic).map(|t| t.count))
            .unwrap_or(0);
        if count >= n {
            return;
        }
        assert!(Instant::now() < deadline, "{topic}: {count} of {n} messages recorded in {}", dir.display());
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// SIGINT, then the recorder must finish the bag and exit 0; returns its stderr.
fn stop_record(child: Child) -> String {
    let status = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "bag record: {stderr}");
    stderr
}

fn expected_swings() -> Vec<Value> {
    (1..=5).map(|id| serde_json::json!({"swing_id": id, "bat_id": "r161", "impact_z": 0.7})).collect()
}

#[test]
fn record_all_beside_the_node_keeps_its_topics_and_the_swings() {
    let tmp = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(ALL_DOMAIN, tmp.path(), &["--no-record", "--ros-args", "-r", "__ns:=/lab"]);
    let dir = tmp.path().join("all");
    let record = start_record(ALL_DOMAIN, &["-a", "-o", dir.to_str().unwrap()]);
    publish_swings(ALL_DOMAIN);
    wait_for_count(&dir, "/lab/exit_velocity", 5);
    let stderr = stop_record(record);
    assert!(dir.join("metadata.yaml").is_file());
    let got = read_bag(&dir, "/lab/swing");
    let channels = got["channels"].as_object().unwrap();
    for (topic, type_name) in [
        ("/lab/swing", "sweetspot_msgs/msg/Swing"),
        ("/lab/exit_velocity", "sweetspot_msgs/msg/ExitVelocity"),
        ("/lab/modal_energies", "sweetspot_msgs/msg/ModalEnergies"),
        ("/diagnostics", "diagnostic_msgs/msg/DiagnosticArray"),
    ] {
        let ch = &channels.get(topic).unwrap_or_else(|| panic!("{topic} not recorded: {channels:?}\n{stderr}"));
        assert_eq!(ch["type"], type_name, "{topic}");
        assert_eq!(ch["encoding"], "ros2msg", "{topic}");
        assert!(ch["schema_len"].as_u64().unwrap() > 0, "{topic} has its schema");
    }
    assert_eq!(channels["/lab/swing"]["count"], 5);
    assert!(channels["/lab/exit_velocity"]["count"].as_u64().unwrap() >= 5);
    assert_eq!(got["mcap_swings"], Value::from(expected_swings()));
    assert_eq!(got["rosbags_swings"], Value::from(expected_swings()));
    // The node's /parameter_events (rcl_interfaces/msg/ParameterEvent, not generated here): recorded raw,
    // without a schema, and said so.
    let events = &channels["/parameter_events"];
    assert_eq!(events["type"], "rcl_interfaces/msg/ParameterEvent");
    assert_eq!(events["schema_len"], 0);
    assert!(stderr.contains("/parameter_events (rcl_interfaces/msg/ParameterEvent): type not generated"), "{stderr}");
    assert!(
        stderr.contains("skipped rr/lab/sweetspot/get_parametersReply: a service"),
        "services are named as skipped: {stderr}"
    );
    node.stop_with(libc::SIGINT);
}

#[test]
fn record_a_topic_list_resolved_in_the_namespace() {
    let tmp = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(LIST_DOMAIN, tmp.path(), &["--no-record", "--ros-args", "-r", "__ns:=/lab"]);
    let dir = tmp.path().join("list");
    let record =
        start_record(LIST_DOMAIN, &["swing", "/lab/exit_velocity", "--ns", "/lab", "-o", dir.to_str().unwrap()]);
    publish_swings(LIST_DOMAIN);
    wait_for_count(&dir, "/lab/exit_velocity", 5);
    stop_record(record);
    let got = read_bag(&dir, "/lab/swing");
    let mut topics: Vec<&String> = got["channels"].as_object().unwrap().keys().collect();
    topics.sort();
    assert_eq!(topics, ["/lab/exit_velocity", "/lab/swing"]);
    assert_eq!(got["rosbags_swings"], Value::from(expected_swings()));
    node.stop_with(libc::SIGINT);
}

#[test]
fn storage_other_than_mcap_is_refused_and_nothing_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("never");
    let out = sweetspot(LIST_DOMAIN, &["bag", "record", "-a", "-s", "sqlite3", "-o", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("sqlite3") && stderr.contains("-s mcap"), "{stderr}");
    assert_eq!(stderr.matches("error").count(), 1, "one error line: {stderr}");
    assert!(!dir.exists());
    let out = sweetspot(LIST_DOMAIN, &["bag", "record", "-o", dir.to_str().unwrap()]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("nothing to record"));
}
