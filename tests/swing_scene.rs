//! `swing_scene` over DDS and in the bag (`-p swing_scene:=true`), inside the private network namespace of
//! scripts/test: every OK swing gets one visualization_msgs/MarkerArray (a rejected one none), drawn in frame
//! `bat`, with the exit-velocity arrow at the answer's launch angle, the ball at impact_z and the bat's outline
//! at the R161 data file's radii; the recorded scenes decode with both independent Python readers
//! (mcap-ros2-support from the schema in the file, rosbags from metadata.yaml's stored definitions) to the
//! markers received over DDS.

mod support;

use std::process::Command;
use std::time::Duration;

use serde_json::Value;
use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
use sweetspot::msgs::visualization_msgs::msg::{Marker, MarkerArray};

const WAIT: Duration = Duration::from_secs(60);

fn swing(id: u64, undercut: f64, attack_angle: f64, impact_z: f64) -> Swing {
    Swing {
        swing_id: id,
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z,
        measured_exit_speed: f64::NAN,
        undercut,
        attack_angle,
        measured_launch_angle: f64::NAN,
        measured_spin: f64::NAN,
        ..Swing::default()
    }
}

/// The R161's radii from its data file (diameter in mm per 1-cm slice), m.
fn r161_radii() -> Vec<f64> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/physics/src/data/r161.dat");
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1).and_then(|d| d.parse::<f64>().ok()))
        .map(|d| d / 2000.0)
        .collect()
}

fn marker<'a>(scene: &'a MarkerArray, ns: &str) -> &'a Marker {
    scene.markers.iter().find(|m| m.ns == ns).unwrap_or_else(|| panic!("no marker {ns}"))
}

/// Per recorded swing_scene message, by each reader: stamp, namespaces, the arrow's points, outline point count.
const PY_READ: &str = r#"
import json, sys
from pathlib import Path
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore, get_types_from_msg

bag = Path(sys.argv[1])
def summary(m):
    arrow = [k for k in m.markers if k.ns == "exit_velocity"][0]
    outline = [k for k in m.markers if k.ns == "bat_outline"][0]
    return {"stamp": [m.markers[0].header.stamp.sec, m.markers[0].header.stamp.nanosec],
            "frame": m.markers[0].header.frame_id, "ns": [k.ns for k in m.markers],
            "arrow": [[p.x, p.y, p.z] for p in arrow.points], "outline_points": len(outline.points)}
out = {"mcap": [], "rosbags": []}
for path in sorted(bag.glob("*.mcap")):
    with open(path, "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        for schema, ch, msg, decoded in reader.iter_decoded_messages(topics=["/swing_scene"]):
            out["mcap"].append(summary(decoded))
store = get_typestore(Stores.EMPTY)
with Reader(bag) as reader:
    types = {}
    for conn in reader.connections:
        if conn.msgdef.data:
            types.update(get_types_from_msg(conn.msgdef.data, conn.msgtype))
    store.register(types)
    conns = [c for c in reader.connections if c.topic == "/swing_scene"]
    out["rosbags_type"] = [c.msgtype for c in conns]
    for conn, _t, raw in reader.messages(connections=conns):
        out["rosbags"].append(summary(store.deserialize_cdr(raw, conn.msgtype)))
print(json.dumps(out))
"#;

#[test]
fn each_answered_swing_is_drawn_over_dds_and_in_the_bag() {
    let domain = domain(98);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag");
    let mut peer = Peer::new(domain, "scene_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let scenes = peer.subscription::<MarkerArray>("/swing_scene", keep_all(dds::results()));
    let record = format!("record_path:={}", bag.display());
    let node = NodeProcess::spawn(domain, dir.path(), &["--ros-args", "-p", &record, "-p", "swing_scene:=true"]);
    peer.wait_for_reader(&swing_pub);

    // Head-on, undercut, topped, and one off the bat's end (REJECTED: no scene).
    let swings = [
        swing(1, 0.0, 0.0, 0.70),
        swing(2, 0.015, 0.14, 0.68),
        swing(3, -0.01, 0.05, 0.60),
        swing(4, 0.0, 0.0, 2.0),
        swing(5, 0.02, 0.2, 0.72),
    ];
    for s in &swings {
        swing_pub.publish(s.clone()).unwrap();
    }
    let evs = peer.collect(&answers, swings.len(), WAIT);
    assert_eq!(evs[3].status, ExitVelocity::STATUS_REJECTED);
    let ok: Vec<&ExitVelocity> = evs.iter().filter(|ev| ev.status == ExitVelocity::STATUS_OK).collect();
    assert_eq!(ok.len(), 4);
    let got = peer.collect(&scenes, ok.len(), WAIT);
    let radii = r161_radii();
    for (scene, ev) in got.iter().zip(&ok) {
        let s = &swings[(ev.swing_id - 1) as usize];
        assert!(scene.markers.iter().all(|m| m.header.frame_id == "bat" && m.header.stamp == ev.header.stamp));
        let arrow = marker(scene, "exit_velocity");
        let (a, b) = (&arrow.points[0], &arrow.points[1]);
        let angle = (b.y - a.y).atan2(b.x - a.x);
        assert!((angle - ev.launch_angle).abs() < 1e-12, "swing {}: {angle} vs {}", ev.swing_id, ev.launch_angle);
        let ball = marker(scene, "ball");
        assert_eq!(ball.pose.position.z, s.impact_z);
        let outline = marker(scene, "bat_outline");
        let out: Vec<f64> = outline.points[1..=radii.len()].iter().map(|p| p.x).collect();
        assert_eq!(out, radii, "the outline is the data file's profile");
        assert!(marker(scene, "deflection x20").points.len() > radii.len());
        assert!(marker(scene, "label").text.contains(&format!("swing {}", ev.swing_id)));
    }
    assert!(ok[1].launch_angle > 0.1, "the undercut swing leaves upward: {}", ok[1].launch_angle);
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");

    let out = Command::new(support::python()).arg("-c").arg(PY_READ).arg(&bag).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let read: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(read["rosbags_type"], serde_json::json!(["visualization_msgs/msg/MarkerArray"]));
    for reader in ["mcap", "rosbags"] {
        let recorded = read[reader].as_array().unwrap();
        assert_eq!(recorded.len(), got.len(), "{reader}");
        for (r, scene) in recorded.iter().zip(&got) {
            let stamp = &scene.markers[0].header.stamp;
            assert_eq!(r["stamp"], serde_json::json!([stamp.sec, stamp.nanosec]), "{reader}");
            assert_eq!(r["frame"], "bat");
            let ns: Vec<&str> = scene.markers.iter().map(|m| m.ns.as_str()).collect();
            assert_eq!(r["ns"], serde_json::json!(ns), "{reader}");
            let arrow = &marker(scene, "exit_velocity").points;
            let want: Vec<[f64; 3]> = arrow.iter().map(|p| [p.x, p.y, p.z]).collect();
            assert_eq!(r["arrow"], serde_json::json!(want), "{reader}");
            assert_eq!(r["outline_points"], marker(scene, "bat_outline").points.len(), "{reader}");
        }
    }
}
