//! Bags written by another tool: the Python `rosbags` writes rosbag2 MCAP bags the way rosbag2 does, in its
//! own layout (keys sorted, values single-quoted or bare, `custom_data` as a plain mapping), with integer QoS
//! enums for metadata version 8 (Humble) and string enums for version 9 (Jazzy). sweetspot reads back what it
//! wrote: every topic's QoS, the `custom_data` and the `ros_distro` (from the `rosbag2` MCAP record) and the
//! `custom_data` of `metadata.yaml` itself.

mod support;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use support::bag::python;
use sweetspot::bag::info::{custom_data_of, ros_distro_of};
use sweetspot::bag::reader::read_bag;
use sweetspot::bag::rosbag2::parse_custom_data;
use sweetspot::bag::RecordedQos;

/// Writes a two-topic rosbag2 MCAP bag at `dir` with `rosbags.rosbag2.Writer` (metadata `version`).
fn write_with_rosbags(dir: &Path, version: u32) {
    let script = r#"
import sys
from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

ts = get_typestore(Stores.ROS2_JAZZY)
String = ts.types['std_msgs/msg/String']
inf = QosTime(sec=9223372036, nsec=854775807)
latched = Qos(QosHistory.KEEP_LAST, 7, QosReliability.RELIABLE, QosDurability.TRANSIENT_LOCAL, inf, inf,
              QosLiveliness.AUTOMATIC, inf, False)
lossy = Qos(QosHistory.KEEP_LAST, 3, QosReliability.BEST_EFFORT, QosDurability.VOLATILE, inf, inf,
            QosLiveliness.AUTOMATIC, inf, False)
with Writer(sys.argv[1], version=int(sys.argv[2]), storage_plugin=StoragePlugin.MCAP) as w:
    a = w.add_connection('/latched', 'std_msgs/msg/String', typestore=ts, offered_qos_profiles=[latched])
    b = w.add_connection('/lossy', 'std_msgs/msg/String', typestore=ts, offered_qos_profiles=[lossy])
    w.write(a, 1_000_000_000, ts.serialize_cdr(String(data='hi'), 'std_msgs/msg/String'))
    w.write(b, 2_000_000_000, ts.serialize_cdr(String(data='ho'), 'std_msgs/msg/String'))
    w.write(b, 3_000_000_000, ts.serialize_cdr(String(data='hu'), 'std_msgs/msg/String'))
    w.set_custom_data('sweetspot/note', 'a value: with colon')
    w.set_custom_data('plain', 'x')
    w.set_custom_data('number', '42')
"#;
    let out = Command::new(python()).arg("-c").arg(script).arg(dir).arg(version.to_string()).output().unwrap();
    assert!(out.status.success(), "rosbags writer: {}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn qos_custom_data_and_distro_of_bags_rosbags_writes_for_humble_and_jazzy_read_back() {
    let tmp = tempfile::tempdir().unwrap();
    let expected_custom: BTreeMap<String, String> =
        [("number", "42"), ("plain", "x"), ("sweetspot/note", "a value: with colon")]
            .into_iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
    for version in [8, 9] {
        let dir = tmp.path().join(format!("v{version}"));
        write_with_rosbags(&dir, version);
        let metadata_yaml = std::fs::read_to_string(dir.join("metadata.yaml")).unwrap();
        // The layout is rosbags' (rosbag2's) own, not sweetspot's: no double-quoted custom_data entries.
        assert!(metadata_yaml.contains("    plain: x\n"), "v{version}: {metadata_yaml}");
        assert!(metadata_yaml.contains(&format!("  version: {version}\n")), "{metadata_yaml}");

        let mut payloads = Vec::new();
        let scans = read_bag(&dir, |m| payloads.push((m.channel.topic.name.clone(), m.data.to_vec()))).unwrap();
        assert_eq!(scans.len(), 1);
        let scan = &scans[0];
        assert!(scan.damage.is_empty(), "v{version}: {:?}", scan.damage);
        assert_eq!(payloads.len(), 3, "v{version}");
        assert_eq!(payloads[0].0, "/latched");
        // CDR of std_msgs/String "hu" as rosbags serializes it: encapsulation, length 3, "hu\0", no padding.
        assert_eq!(payloads[2].1, b"\x00\x01\x00\x00\x03\x00\x00\x00hu\x00", "v{version}: the CDR rosbags wrote");

        let qos: BTreeMap<&str, RecordedQos> =
            scan.channels.values().map(|c| (c.topic.name.as_str(), c.topic.qos)).collect();
        let want_latched = RecordedQos { reliable: true, transient_local: true, depth: 7 };
        let want_lossy = RecordedQos { reliable: false, transient_local: false, depth: 3 };
        assert_eq!(qos.get("/latched"), Some(&want_latched), "v{version}: {qos:?}");
        assert_eq!(qos.get("/lossy"), Some(&want_lossy), "v{version}: {qos:?}");

        assert_eq!(custom_data_of(&scans), expected_custom, "v{version}: from the rosbag2 MCAP record");
        assert_eq!(ros_distro_of(&scans), "rosbags", "v{version}: rosbags names itself as the distro");
        assert_eq!(parse_custom_data(&metadata_yaml), expected_custom, "v{version}: from metadata.yaml");
    }
}
