//! Interoperability with another DDS vendor: a Cyclone DDS participant (PyPI `cyclonedds`) whose types are built
//! at run time from the .msg files alone (tests/python/cyclone_peer.py) exchanges messages with `sweetspot pub`
//! and `sweetspot echo` over `rt/` topics with ROS 2 type names, in both directions. Cyclone is restricted to
//! loopback (`--loopback`), and everything runs inside the private network namespace of scripts/test.

mod support;

use std::io::{BufRead, BufReader};

use serde_json::{json, Value};
use support::{cyclone_peer, json_lines, require_isolated_network, run_ok, spawn_piped, sweetspot};

#[test]
fn interop_cyclone_publishes_swings_to_sweetspot_echo() {
    require_isolated_network();
    let domain = 161;
    let swings = json!([
        {"header": {"stamp": {"sec": 1700000000, "nanosec": 5}, "frame_id": "cage"}, "swing_id": 18446744073709551615u64,
         "bat_id": "r161", "ball_id": "", "ball_speed": 40.2, "bat_cm_speed": 23.5, "bat_angular_speed": 51.0,
         "impact_z": 0.71, "measured_exit_speed": 44.5},
        {"header": {"stamp": {"sec": -2, "nanosec": 300000000}, "frame_id": ""}, "swing_id": 2, "bat_id": "torpedo",
         "ball_id": "mlb", "ball_speed": -1e-300, "bat_cm_speed": 0.0, "bat_angular_speed": 1e300, "impact_z": 0.5,
         "measured_exit_speed": null}
    ]);
    let echo = spawn_piped({
        let mut c = sweetspot(domain, &["echo", "/rig3/swing", "--json", "--count", "2", "--timeout", "60"]);
        c.args(["--ros-args", "-r", "__ns:=/rig3"]);
        c
    });
    run_ok(
        cyclone_peer(
            domain,
            &[
                "pub",
                "--type",
                "sweetspot_msgs/msg/Swing",
                "--topic",
                "/rig3/swing",
                "--json",
                &swings.to_string(),
                "--qos",
                "swing",
                "--wait-subscribers",
                "1",
                "--timeout",
                "60",
                "--keep-alive",
                "0.5",
            ],
        ),
        "cyclone pub",
    );
    let got = json_lines(&echo.wait_with_output().unwrap(), "sweetspot echo");
    support::assert_json_fields(&Value::Array(got), &swings, "cyclone swings");
}

#[test]
fn interop_sweetspot_pub_reaches_cyclone_for_every_output_type() {
    require_isolated_network();
    let domain = 162;
    let cases = [
        (
            "exit_velocity",
            "sweetspot_msgs/msg/ExitVelocity",
            "/exit_velocity",
            "results",
            json!({"header": {"stamp": {"sec": 3, "nanosec": 4}, "frame_id": ""}, "swing_id": 77, "bat_id": "r161", "ball_id": "mlb",
                "status": 1, "message": "impact_z: 2 m is beyond the bat (0..0.864 m)", "impact_z": 2.0, "exit_speed": 41.5,
                "rigid_exit_speed": 43.0, "effective_cor": 0.21, "collision_efficiency": 0.2, "contact_time": 0.00063,
                "peak_force": 21000.0, "impulse": 12.0, "max_compression": 0.012, "measured_exit_speed": null, "residual": null}),
        ),
        (
            "modal_energies",
            "sweetspot_msgs/msg/ModalEnergies",
            "/modal_energies",
            "results",
            json!({"header": {"stamp": {"sec": 5, "nanosec": 6}, "frame_id": "x"}, "swing_id": 2, "bat_id": "r161",
                "frequency": [177.0, 583.0, 1179.5], "energy": [1.5, 0.25, null], "fraction": [0.01, 0.002, 0.0],
                "vibration_energy": 1.75, "hysteresis_loss": 30.0, "energy_residual": -1e-9}),
        ),
        (
            "sweet_spot",
            "sweetspot_msgs/msg/SweetSpot",
            "/sweet_spot",
            "sweet_spot",
            json!({"header": {"stamp": {"sec": 7, "nanosec": 8}, "frame_id": ""}, "bat_id": "r161", "ball_id": "mlb",
                "max_exit_speed_z": 0.71, "max_exit_speed": 44.1, "rigid_optimum_z": 0.69, "node1_z": 0.68, "node2_z": 0.72,
                "center_of_percussion_z": 0.66, "ball_speed": 40.0, "bat_cm_speed": 20.0, "bat_angular_speed": 50.0,
                "bbcor": 0.48, "frequency": [177.0, 583.0], "mass": 0.885, "center_of_mass": 0.564, "moment_of_inertia": 0.0455}),
        ),
        (
            "diagnostics",
            "diagnostic_msgs/msg/DiagnosticArray",
            "/diagnostics",
            "diagnostics",
            json!({"header": {"stamp": {"sec": 9, "nanosec": 10}, "frame_id": ""},
                "status": [{"level": 1, "name": "sweetspot: node", "message": "queue full", "hardware_id": "",
                            "values": [{"key": "swings_processed", "value": "10"}, {"key": "dropped", "value": "0"}]},
                           {"level": 0, "name": "sweetspot: recorder", "message": "", "hardware_id": "h", "values": []}]}),
        ),
    ];
    for (kind, type_name, topic, qos, message) in cases {
        let sub = spawn_piped(cyclone_peer(
            domain,
            &["sub", "--type", type_name, "--topic", topic, "--qos", qos, "--count", "1", "--timeout", "60"],
        ));
        run_ok(
            sweetspot(domain, &["pub", kind, &message.to_string(), "--wait-subscribers", "1", "--timeout", "60", "-q"]),
            "sweetspot pub",
        );
        let got = json_lines(&sub.wait_with_output().unwrap(), "cyclone sub");
        support::assert_json_fields(&Value::Array(got), &Value::Array(vec![message]), kind);
    }
}

/// Params published by Cyclone with transient-local QoS reach a sweetspot subscriber that starts later, and
/// Cyclone sees sweetspot's publications under their ROS 2 DDS names.
#[test]
fn interop_latched_params_and_ros_naming() {
    require_isolated_network();
    let domain = 163;
    let ball = json!({"header": {"stamp": {"sec": 1, "nanosec": 2}, "frame_id": ""}, "ball_id": "mlb", "mass": 0.145,
                      "radius": 0.0366, "cor": 0.5, "stiffness": 7.1e6, "exponent": 1.25, "tangential_cor": 0.3,
                      "friction": 0.5, "moment_of_inertia": 7.4e-5, "cor_speed_exponent": 0.0678,
                      "cor_reference_speed": 25.9});
    let mut cyclone = spawn_piped(cyclone_peer(
        domain,
        &[
            "pub",
            "--type",
            "sweetspot_msgs/msg/BallParams",
            "--topic",
            "/rig3/ball/params",
            "--json",
            &ball.to_string(),
            "--qos",
            "params",
            "--keep-alive",
            "120",
        ],
    ));
    let line = BufReader::new(cyclone.stdout.take().unwrap()).lines().next().expect("peer output").unwrap();
    assert_eq!(line, "published 1");
    let got = json_lines(
        &sweetspot(domain, &["echo", "ball/params", "--json", "--count", "1", "--timeout", "60", "--ns", "/rig3"])
            .output()
            .unwrap(),
        "late sweetspot echo",
    );
    assert_eq!(got, [ball]);
    let _ = cyclone.kill();
    let _ = cyclone.wait();

    // Cyclone pairs readers and writers by exact DDS type name, so the exchanges above prove sweetspot uses the
    // ROS 2 names. Control: the same layout under a non-ROS type name receives nothing from sweetspot's latched
    // publisher, while the ROS 2 name does.
    let mut publisher = spawn_piped(sweetspot(
        domain,
        &[
            "pub",
            "bat",
            r#"{"bat_id": "a", "preset": "r161"}"#,
            "--keep-alive",
            "120",
            "-q",
            "--ros-args",
            "-r",
            "__ns:=/rig3",
        ],
    ));
    let sub = |type_override: Option<&str>, timeout: &str| {
        let mut args = vec![
            "sub",
            "--type",
            "sweetspot_msgs/msg/BatParams",
            "--topic",
            "/rig3/bat/params",
            "--qos",
            "params",
            "--count",
            "1",
            "--timeout",
            timeout,
        ];
        if let Some(t) = type_override {
            args.extend(["--dds-type-name", t]);
        }
        cyclone_peer(domain, &args).output().unwrap()
    };
    let right = sub(None, "60");
    let wrong = sub(Some("sweetspot_msgs::msg::BatParams"), "3");
    let _ = std::process::Command::new("kill").args(["-TERM", &publisher.id().to_string()]).status();
    let status = publisher.wait().unwrap();
    let got = json_lines(&right, "cyclone sub with the ROS 2 type name");
    assert_eq!(got[0]["bat_id"], "a");
    assert_eq!(got[0]["preset"], "r161");
    assert!(!wrong.status.success(), "a reader with a non-ROS type name must not match sweetspot's writer");
    assert!(String::from_utf8_lossy(&wrong.stderr).contains("timed out"));
    assert!(status.success(), "sweetspot pub should exit cleanly on SIGTERM");
}
