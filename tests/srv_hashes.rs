//! RIHS01 hashes of services (REP-2011): build.rs splits a `.srv` at `---` into `pkg/srv/Name_Request` and
//! `pkg/srv/Name_Response` and hashes the service with the `Name_Event` type rosidl adds, as
//! rosidl_generator_type_description does. Checked two independent ways:
//! - against hashes rosidl published: example_interfaces/srv/AddTwoInts (service, Request, Response, Event) and
//!   service_msgs/msg/ServiceEventInfo, from rosidl_generator_c's `add_two_ints__description.c` of a ROS 2
//!   build (`*__get_type_hash` and `*__EXPECTED_HASH`);
//! - against Python `rosbags` (tests/python/srv_hashes.py) for sweetspot_msgs/srv/SimulateSwing and its halves.

mod support;

#[allow(dead_code)]
#[path = "../crates/msgs/build.rs"]
mod build_script;

use serde_json::Value;
use sweetspot::msgs::sweetspot_msgs::srv::{SimulateSwing, SimulateSwing_Request, SimulateSwing_Response};
use sweetspot::msgs::{RosMessage, RosService};

const ADD_TWO_INTS: &str = "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a";
const ADD_TWO_INTS_REQUEST: &str = "RIHS01_000c5fd92d6b2e1a05949348f584d6d652adea1e92d691792011ac2273508302";
const ADD_TWO_INTS_RESPONSE: &str = "RIHS01_de5c030d4af33cba2749310b249737b631594703f9300495f48bffb2b44dcc2f";
const ADD_TWO_INTS_EVENT: &str = "RIHS01_32c1d140259c71e5c355115942bcb31df98b4330e4d906b1b75ccb1c9b3ce6c8";
const SERVICE_EVENT_INFO: &str = "RIHS01_41bcbbe07a75c9b52bc96bfd5c24d7f0fc0a08c0cb7921b3373c5732345a6f45";

/// example_interfaces/srv/AddTwoInts.srv (ros2/example_interfaces), comments left out (RIHS01 ignores them).
const ADD_TWO_INTS_SRV: &str = "int64 a\nint64 b\n---\nint64 sum\n";

fn vendored(path: &str) -> String {
    std::fs::read_to_string(support::repo().join("msgs/ros_interfaces").join(path)).expect("vendored .msg")
}

#[test]
fn a_published_service_hashes_as_rosidl_publishes_with_its_request_response_and_event() {
    let (time, info) = (vendored("builtin_interfaces/msg/Time.msg"), vendored("service_msgs/msg/ServiceEventInfo.msg"));
    let hashes = build_script::interface_hashes_of(
        &[("builtin_interfaces", "Time", &time), ("service_msgs", "ServiceEventInfo", &info)],
        &[("example_interfaces", "AddTwoInts", ADD_TWO_INTS_SRV)],
    )
    .expect("parses");
    assert_eq!(hashes["service_msgs/msg/ServiceEventInfo"], SERVICE_EVENT_INFO, "char[16] is an IDL uint8[16]");
    assert_eq!(hashes["example_interfaces/srv/AddTwoInts_Request"], ADD_TWO_INTS_REQUEST);
    assert_eq!(hashes["example_interfaces/srv/AddTwoInts_Response"], ADD_TWO_INTS_RESPONSE);
    assert_eq!(hashes["example_interfaces/srv/AddTwoInts_Event"], ADD_TWO_INTS_EVENT);
    assert_eq!(hashes["example_interfaces/srv/AddTwoInts"], ADD_TWO_INTS);
}

#[test]
fn simulate_swing_hashes_as_rosbags_computes_them() {
    let out = std::process::Command::new(support::python())
        .arg(support::repo().join("tests/python/srv_hashes.py"))
        .arg(support::repo().join("msgs"))
        .arg("sweetspot_msgs/SimulateSwing")
        .output()
        .expect("python");
    support::assert_success(&out, "srv_hashes.py");
    let rosbags: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(rosbags["sweetspot_msgs/srv/SimulateSwing"], SimulateSwing::TYPE_HASH);
    assert_eq!(rosbags["sweetspot_msgs/srv/SimulateSwing_Request"], SimulateSwing_Request::TYPE_HASH);
    assert_eq!(rosbags["sweetspot_msgs/srv/SimulateSwing_Response"], SimulateSwing_Response::TYPE_HASH);
    // The halves are types of their own: none shares a hash.
    let all = [SimulateSwing::TYPE_HASH, SimulateSwing_Request::TYPE_HASH, SimulateSwing_Response::TYPE_HASH];
    assert!(all[0] != all[1] && all[1] != all[2] && all[0] != all[2]);
}

#[test]
fn the_halves_carry_ros_2_names() {
    assert_eq!(SimulateSwing::TYPE_NAME, "sweetspot_msgs/srv/SimulateSwing");
    assert_eq!(SimulateSwing_Request::TYPE_NAME, "sweetspot_msgs/srv/SimulateSwing_Request");
    assert_eq!(SimulateSwing_Response::TYPE_NAME, "sweetspot_msgs/srv/SimulateSwing_Response");
    assert_eq!(SimulateSwing_Request::DDS_TYPE_NAME, "sweetspot_msgs::srv::dds_::SimulateSwing_Request_");
    assert_eq!(SimulateSwing_Response::DDS_TYPE_NAME, "sweetspot_msgs::srv::dds_::SimulateSwing_Response_");
    assert!(SimulateSwing_Request::MSG_TEXT.starts_with("# What would this swing give?"));
    assert!(SimulateSwing_Response::MSG_TEXT.starts_with("# The ExitVelocity"));
    assert!(SimulateSwing::SRV_TEXT.contains("\n---\n"));
}

#[test]
fn a_malformed_srv_is_refused_with_file_and_line() {
    let hash = |srv: &str| build_script::interface_hashes_of(&[], &[("p", "S", srv)]);
    let err = hash("int32 a\n").unwrap_err().join("\n");
    assert!(err.contains("exactly one `---`"), "{err}");
    let err = hash("int32 a\n---\nint32 b\n---\n").unwrap_err().join("\n");
    assert!(err.contains("found 2"), "{err}");
    // A bad line in the response half is reported at its line of the .srv.
    let err = hash("int32 a\n---\nint32 b\nNotAType! c\n").unwrap_err().join("\n");
    assert!(err.contains("p/srv/S.srv:4:"), "{err}");
}
