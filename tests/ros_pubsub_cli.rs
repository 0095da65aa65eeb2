//! `sweetspot pub` and `sweetspot echo` as separate processes over real DDS on loopback (inside the private
//! network namespace of scripts/test). Each test uses its own ROS_DOMAIN_ID so parallel tests never meet.

mod support;

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Output, Stdio};

use serde_json::{json, Value};
use support::{require_isolated_network as guard, sweetspot as cmd, BIN};

fn json_lines(out: &Output) -> Vec<Value> {
    support::json_lines(out, "echo")
}

fn run_ok(c: Command) -> Output {
    support::run_ok(c, "command")
}

/// Starts `sweetspot echo TOPIC --json --count N` and returns it (stdout piped).
fn start_echo(domain: u16, topic: &str, count: usize, extra: &[&str]) -> Child {
    let n = count.to_string();
    let mut args = vec!["echo", topic, "--json", "--count", &n, "--timeout", "60"];
    args.extend_from_slice(extra);
    support::spawn_piped(cmd(domain, &args))
}

fn finish(child: Child) -> Output {
    child.wait_with_output().expect("wait")
}

#[test]
fn ros_cli_swings_from_json_lines_reach_echo_in_a_namespace() {
    guard();
    let domain = 151;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("swings.jsonl");
    std::fs::write(
        &file,
        "# three swings\n\
         {\"swing_id\": 11, \"bat_id\": \"r161\", \"ball_speed\": 40.2, \"bat_cm_speed\": 23.5, \"bat_angular_speed\": 51, \"impact_z\": 0.71, \"measured_exit_speed\": 44.5}\n\
         {\"swing_id\": 12, \"bat_id\": \"r161\", \"ball_speed\": 38, \"impact_z\": 0.65, \"header\": {\"frame_id\": \"cage\", \"stamp\": {\"sec\": 7, \"nanosec\": 9}}}\n\
         \n\
         {\"bat_id\": \"torpedo\", \"ball_id\": \"mlb\", \"impact_z\": 0.5, \"measured_exit_speed\": \"nan\"}\n",
    )
    .unwrap();
    let echo = start_echo(domain, "/rig3/swing", 3, &[]);
    let file_arg = file.to_str().unwrap();
    run_ok(cmd(
        domain,
        &[
            "pub",
            "swing",
            "--file",
            file_arg,
            "--wait-subscribers",
            "1",
            "--timeout",
            "60",
            "-q",
            "--ros-args",
            "-r",
            "__ns:=/rig3",
        ],
    ));
    let got = json_lines(&finish(echo));
    assert_eq!(got.len(), 3);
    assert_eq!(got[0]["swing_id"], 11);
    assert_eq!(got[0]["ball_speed"], 40.2);
    assert_eq!(got[0]["bat_angular_speed"], 51.0);
    assert_eq!(got[0]["measured_exit_speed"], 44.5);
    assert_eq!(got[1]["swing_id"], 12);
    assert_eq!(got[1]["header"], json!({"stamp": {"sec": 7, "nanosec": 9}, "frame_id": "cage"}));
    assert_eq!(got[1]["measured_exit_speed"], Value::Null, "absent = not measured = NaN");
    assert_eq!(got[2]["swing_id"], 3, "a swing without an id gets its sequence number");
    assert_eq!(got[2]["ball_id"], "mlb");
    assert_eq!(got[2]["measured_exit_speed"], Value::Null);
    // Unset stamps are filled with the publish time.
    assert!(got[0]["header"]["stamp"]["sec"].as_i64().unwrap() > 1_600_000_000);
    // Field order is the .msg order.
    let keys: Vec<&String> = got[0].as_object().unwrap().keys().collect();
    assert_eq!(keys[..3], ["header", "swing_id", "bat_id"]);
}

#[test]
fn ros_cli_csv_rate_and_count() {
    guard();
    let domain = 152;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("swings.csv");
    std::fs::write(&file, "swing_id,bat_id,ball_speed,impact_z,header.frame_id\n1,r161,40,0.7,a\n2,r161,41.5,0.66,b\n")
        .unwrap();
    // --count 5 cycles through the 2 rows: ids 1,2,1,2,1 as written in the file.
    let echo = start_echo(domain, "swing", 5, &[]);
    run_ok(cmd(
        domain,
        &[
            "pub",
            "swing",
            "--file",
            file.to_str().unwrap(),
            "--count",
            "5",
            "--rate",
            "200",
            "--wait-subscribers",
            "1",
            "--timeout",
            "60",
            "-q",
        ],
    ));
    let got = json_lines(&finish(echo));
    let ids: Vec<i64> = got.iter().map(|m| m["swing_id"].as_i64().unwrap()).collect();
    assert_eq!(ids, [1, 2, 1, 2, 1]);
    assert_eq!(got[1]["ball_speed"], 41.5);
    assert_eq!(got[1]["header"]["frame_id"], "b");
}

#[test]
fn ros_cli_params_are_latched_for_late_joiners() {
    guard();
    let domain = 153;
    let bats = r#"[{"bat_id": "a", "preset": "r161"},
                   {"bat_id": "b", "station_z": [0, 0.5, 0.84], "outer_radius": "0.013;0.02;0.033", "inner_radius": [0, 0, 0],
                    "density": 649, "youngs_modulus": 1.814e10, "shear_modulus": 1.05e9, "max_modes": 12}]"#;
    let mut publisher = cmd(domain, &["pub", "bat", bats, "--keep-alive", "120"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start pub");
    // Wait until the publisher reports both messages written (no subscriber exists yet).
    let mut lines = BufReader::new(publisher.stdout.take().unwrap()).lines();
    let mut written = 0;
    while written < 2 {
        let line = lines.next().expect("pub ended early").unwrap();
        if line.starts_with("publishing #") {
            written += 1;
        }
    }
    // A late joiner still receives both bats.
    let got = json_lines(&finish(start_echo(domain, "bat/params", 2, &[])));
    assert_eq!(got[0]["bat_id"], "a");
    assert_eq!(got[0]["preset"], "r161");
    assert_eq!(got[1]["bat_id"], "b");
    assert_eq!(got[1]["outer_radius"], json!([0.013, 0.02, 0.033]));
    assert_eq!(got[1]["max_modes"], 12);
    // SIGTERM ends the publisher cleanly.
    let status = Command::new("kill").args(["-TERM", &publisher.id().to_string()]).status().unwrap();
    assert!(status.success());
    let status = publisher.wait().unwrap();
    assert!(status.success(), "pub should exit 0 on SIGTERM, got {status}");
}

/// Every message type survives DDS unchanged: what echo prints equals what pub was given.
#[test]
fn ros_cli_every_message_type_round_trips_over_dds() {
    guard();
    let domain = 154;
    let cases: Vec<(&str, Value)> = vec![
        (
            "ball",
            json!({"header": {"stamp": {"sec": 1, "nanosec": 2}, "frame_id": "f"}, "ball_id": "mlb", "mass": 0.145, "radius": 0.0366, "cor": 0.5, "stiffness": 7.1e6, "exponent": 1.25}),
        ),
        (
            "exit_velocity",
            json!({"header": {"stamp": {"sec": 3, "nanosec": 4}, "frame_id": ""}, "swing_id": 18446744073709551615u64, "bat_id": "r161", "ball_id": "mlb", "status": 1, "message": "impact_z: 2 m is beyond the bat", "impact_z": 2.0, "exit_speed": 41.5, "rigid_exit_speed": 43.0, "effective_cor": 0.21, "collision_efficiency": 0.2, "contact_time": 0.00063, "peak_force": 21000.0, "impulse": 12.0, "max_compression": 0.012, "measured_exit_speed": null, "residual": null}),
        ),
        (
            "modal_energies",
            json!({"header": {"stamp": {"sec": 5, "nanosec": 6}, "frame_id": ""}, "swing_id": 2, "bat_id": "r161", "frequency": [177.0, 583.0], "energy": [1.5, 0.25], "fraction": [0.01, 0.002], "vibration_energy": 1.75, "hysteresis_loss": 30.0, "energy_residual": -1e-9}),
        ),
        (
            "sweet_spot",
            json!({"header": {"stamp": {"sec": 7, "nanosec": 8}, "frame_id": ""}, "bat_id": "r161", "ball_id": "mlb", "max_exit_speed_z": 0.71, "max_exit_speed": 44.1, "rigid_optimum_z": 0.69, "node1_z": 0.68, "node2_z": 0.72, "center_of_percussion_z": 0.66, "ball_speed": 40.0, "bat_cm_speed": 20.0, "bat_angular_speed": 50.0, "bbcor": 0.48, "frequency": [177.0], "mass": 0.885, "center_of_mass": 0.564, "moment_of_inertia": 0.0455}),
        ),
        (
            "diagnostics",
            json!({"header": {"stamp": {"sec": 9, "nanosec": 10}, "frame_id": ""}, "status": [{"level": 1, "name": "sweetspot: node", "message": "queue full", "hardware_id": "", "values": [{"key": "swings_processed", "value": "10"}]}]}),
        ),
    ];
    for (kind, message) in cases {
        let echo = start_echo(domain, kind, 1, &[]);
        run_ok(cmd(domain, &["pub", kind, &message.to_string(), "--wait-subscribers", "1", "--timeout", "60", "-q"]));
        let got = json_lines(&finish(echo));
        support::assert_json_fields(&serde_json::Value::Array(got), &serde_json::Value::Array(vec![message]), kind);
    }
}

#[test]
fn ros_cli_rejects_bad_input_with_the_field_named() {
    // None of these reach DDS: input and environment are checked first.
    let fail = |domain: &str, range: &str, args: &[&str]| -> String {
        let out = Command::new(BIN)
            .args(args)
            .env("ROS_DOMAIN_ID", domain)
            .env("ROS_AUTOMATIC_DISCOVERY_RANGE", range)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?} should fail");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let e = fail("155", "LOCALHOST", &["pub", "swing", r#"{"ball_sped": 40}"#]);
    assert!(e.contains("ball_sped") && e.contains("no such field"), "{e}");
    let e = fail("155", "LOCALHOST", &["pub", "swing", r#"{"swing_id": -3}"#]);
    assert!(e.contains("swing_id"), "{e}");
    let e = fail("155", "LOCALHOST", &["pub", "swing", "{not json"]);
    assert!(e.contains("not valid JSON"), "{e}");
    let e = fail("155", "LOCALHOST", &["pub", "/lab/thing", "{}"]);
    assert!(e.contains("--type"), "{e}");
    let e = fail("999", "LOCALHOST", &["pub", "swing", "{}"]);
    assert!(e.contains("ROS_DOMAIN_ID"), "{e}");
    let e = fail("155", "LAN", &["echo", "swing"]);
    assert!(e.contains("ROS_AUTOMATIC_DISCOVERY_RANGE"), "{e}");
    let e = fail("155", "LOCALHOST", &["echo", "swing", "--ros-args", "-r", "__ns:=/bad name"]);
    assert!(e.contains("invalid ROS name"), "{e}");
}

#[test]
fn ros_cli_echo_fails_when_too_few_messages_arrive() {
    guard();
    let out = cmd(156, &["echo", "exit_velocity", "--json", "--count", "1", "--timeout", "0.5"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("timed out"));
}

/// A burst far deeper than any QoS history: pub is flow-controlled by acknowledgments and echo's reader queues
/// what it has not printed yet, so every swing arrives, in order.
#[test]
fn ros_cli_ten_thousand_swings_back_to_back_arrive_in_order() {
    guard();
    let domain = 157;
    let n = 10_000;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("burst.jsonl");
    let lines: Vec<String> =
        (1..=n).map(|i| format!("{{\"swing_id\": {i}, \"bat_id\": \"r161\", \"impact_z\": 0.7}}")).collect();
    std::fs::write(&file, lines.join("\n")).unwrap();
    let echo = start_echo(domain, "swing", n, &[]);
    run_ok(cmd(
        domain,
        &["pub", "swing", "--file", file.to_str().unwrap(), "--wait-subscribers", "1", "--timeout", "120", "-q"],
    ));
    let got = json_lines(&finish(echo));
    let ids: Vec<u64> = got.iter().map(|m| m["swing_id"].as_u64().unwrap()).collect();
    assert_eq!(ids, (1..=n as u64).collect::<Vec<_>>());
}

/// `sweetspot node` on `domain` with `ros_args` after `--ros-args`, stderr piped; returns once it is up.
fn start_node(domain: u16, ros_args: &[&str]) -> Child {
    let mut args = vec!["node", "--no-record", "--ros-args"];
    args.extend_from_slice(ros_args);
    let mut node = cmd(domain, &args).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("start node");
    let stderr = node.stderr.take().unwrap();
    let mut lines = BufReader::new(stderr).lines();
    loop {
        let line = lines.next().expect("the node ended before it was up").unwrap();
        if line.contains(" up on ROS_DOMAIN_ID") {
            break;
        }
    }
    // Keep draining its log so it never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines {});
    node
}

/// Ends the node with SIGTERM (it finishes cleanly).
fn stop(mut node: Child) {
    let _ = Command::new("kill").args(["-TERM", &node.id().to_string()]).status();
    let _ = node.wait();
}

/// A process that should end on its own; killed (and the test failed) if it is still running after `secs`.
fn exits_by_itself(mut c: Command, secs: u64) -> Output {
    let mut child = c.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn");
    for _ in 0..secs * 10 {
        if child.try_wait().unwrap().is_some() {
            return child.wait_with_output().unwrap();
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let _ = child.kill();
    let out = child.wait_with_output().unwrap();
    panic!("still running after {secs} s; stderr:\n{}", String::from_utf8_lossy(&out.stderr));
}

/// The README's `sweetspot pub swing '{…}'` run before the node is up: pub waits for the node's subscription
/// (as `ros2 topic pub --once` does), so the swing is answered instead of lost.
#[test]
fn ros_cli_pub_waits_for_a_node_started_afterwards() {
    guard();
    let domain = 190;
    let publisher = support::spawn_piped(cmd(
        domain,
        &[
            "pub",
            "swing",
            r#"{"bat_id": "r161", "ball_speed": 40, "bat_cm_speed": 25, "bat_angular_speed": 45, "impact_z": 0.62}"#,
            "--timeout",
            "60",
        ],
    ));
    let echo = start_echo(domain, "exit_velocity", 1, &[]);
    std::thread::sleep(std::time::Duration::from_secs(1)); // the node comes up after pub started waiting
    let node = start_node(domain, &[]);
    let published = finish(publisher);
    support::assert_success(&published, "pub");
    assert!(String::from_utf8_lossy(&published.stderr).contains("published 1 message(s) to /swing"));
    let got = json_lines(&finish(echo));
    stop(node);
    assert_eq!(got.len(), 1);
    assert_eq!(got[0]["swing_id"], 1);
    assert_eq!(got[0]["bat_id"], "r161");
    assert_eq!(got[0]["status"], 0, "answered: {}", got[0]);
}

/// `ros2 topic pub TOPIC TYPE VALUES --once` with YAML flow values, and `-t 3` at `-r`.
#[test]
fn ros_cli_pub_takes_the_positional_yaml_once_and_times_forms() {
    guard();
    let domain = 191;
    let echo = start_echo(domain, "/swing", 1, &[]);
    let out = run_ok(cmd(
        domain,
        &[
            "pub",
            "/swing",
            "sweetspot_msgs/msg/Swing",
            "{swing_id: 7, bat_id: r161, impact_z: 0.7}",
            "-1",
            "--timeout",
            "60",
        ],
    ));
    assert_eq!(String::from_utf8_lossy(&out.stdout).matches("publishing #").count(), 1);
    let got = json_lines(&finish(echo));
    assert_eq!(got.len(), 1);
    assert_eq!((got[0]["swing_id"].as_u64(), got[0]["bat_id"].as_str()), (Some(7), Some("r161")));
    assert_eq!(got[0]["impact_z"], 0.7);

    // The issue's own line: YAML flow, the kind word, no type.
    let echo = start_echo(domain, "swing", 1, &[]);
    run_ok(cmd(domain, &["pub", "swing", "{swing_id: 1, bat_id: r161}", "--timeout", "60", "-q"]));
    let got = json_lines(&finish(echo));
    assert_eq!((got[0]["swing_id"].as_u64(), got[0]["bat_id"].as_str()), (Some(1), Some("r161")));

    let echo = start_echo(domain, "swing", 3, &[]);
    let out = run_ok(cmd(domain, &["pub", "swing", "bat_id: torpedo", "-t", "3", "-r", "20", "--timeout", "60"]));
    assert_eq!(String::from_utf8_lossy(&out.stdout).matches("publishing #").count(), 3);
    let got = json_lines(&finish(echo));
    let ids: Vec<u64> = got.iter().map(|m| m["swing_id"].as_u64().unwrap()).collect();
    assert_eq!(ids, [1, 2, 3]);
    assert!(got.iter().all(|m| m["bat_id"] == "torpedo"));
}

/// With nobody subscribed, `-w 1` gives up after --timeout with a warning and a failure status.
#[test]
fn ros_cli_pub_without_a_matching_subscription_fails_with_a_warning() {
    guard();
    let out = exits_by_itself(cmd(192, &["pub", "swing", "{impact_z: 0.7}", "-w", "1", "--timeout", "1.5"]), 30);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("warning:") && stderr.contains("nothing was published"), "{stderr}");
    assert!(stderr.contains("/swing"), "{stderr}");
    assert!(!String::from_utf8_lossy(&out.stdout).contains("publishing #"), "nothing may be published");
    // The default is the same wait.
    let out = exits_by_itself(cmd(192, &["pub", "swing", "--timeout", "1"]), 30);
    assert!(!out.status.success());
}

/// `echo /exit_velocity` with the node in /lab says where that type is published; `--namespace /lab --once`
/// then prints one answer and exits.
#[test]
fn ros_cli_echo_in_the_wrong_namespace_names_the_right_one() {
    guard();
    let domain = 193;
    let node = start_node(domain, &["-r", "__ns:=/lab"]);
    let out = exits_by_itself(cmd(domain, &["echo", "/exit_velocity", "--timeout", "8"]), 60);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("nothing publishes /exit_velocity"), "{stderr}");
    assert!(stderr.contains("/lab/exit_velocity") && stderr.contains("--ns /lab"), "{stderr}");

    let echo = support::spawn_piped(cmd(domain, &["echo", "exit_velocity", "--namespace", "/lab", "--once", "--json"]));
    run_ok(cmd(domain, &["pub", "swing", "{bat_id: r161, impact_z: 0.7}", "--ns", "/lab", "--timeout", "60", "-q"]));
    let answered = finish(echo);
    stop(node);
    let got = json_lines(&answered);
    assert_eq!(got.len(), 1, "--once prints one message and exits");
    assert_eq!(got[0]["bat_id"], "r161");
}

/// Parameters are checked alike at start-up: a bad default_bat or a record_path that cannot be written stops
/// the node with one line naming the parameter.
#[test]
fn ros_cli_node_refuses_a_bad_default_bat_or_record_path_at_start_up() {
    guard();
    let out = exits_by_itself(cmd(194, &["node", "--ros-args", "-p", "default_bat:=alumnium"]), 30);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("default_bat") && stderr.contains("alumnium") && stderr.contains("aluminum"), "{stderr}");
    assert_eq!(stderr.lines().filter(|l| l.starts_with("error:")).count(), 1, "{stderr}");

    let out = exits_by_itself(cmd(194, &["node", "--ros-args", "-p", "record_path:=/proc/nope"]), 30);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let error: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(error.len(), 1, "{stderr}");
    assert!(error[0].contains("record_path") && error[0].contains("/proc/nope"), "{stderr}");
    assert!(!stderr.contains("recording /proc/nope"), "{stderr}");
}

/// `bag play --clock` publishes rosgraph_msgs/msg/Clock on /clock; `echo /clock` decodes it. The golden bag's
/// time span is its metadata.yaml's (starting_time 1795256853.359 s, duration 3.645 s).
#[test]
fn ros_cli_echo_decodes_the_clock_bag_play_publishes() {
    guard();
    let domain = 158;
    let golden = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden");
    let echo = support::spawn_piped(cmd(domain, &["echo", "/clock", "--count", "3", "--timeout", "60"]));
    // A quarter speed and 20 Hz: some 20 s of ticks, time enough for discovery, and --no-wait as ros2 bag play.
    let play = support::spawn_piped(cmd(
        domain,
        &[
            "bag",
            "play",
            "-q",
            "--no-wait",
            golden.to_str().unwrap(),
            "-r",
            "0.25",
            "--clock",
            "20",
            "--topics",
            "/golden/swing",
        ],
    ));
    let out = finish(echo);
    let _ = Command::new("kill").args(["-INT", &play.id().to_string()]).status();
    let _ = finish(play);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}\n{}", String::from_utf8_lossy(&out.stderr));
    let secs: Vec<i64> = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("sec: "))
        .map(|s| s.parse().unwrap_or_else(|_| panic!("{text}")))
        .collect();
    assert_eq!(secs.len(), 3, "{text}");
    assert!(secs.iter().all(|s| (1_795_256_853..=1_795_256_857).contains(s)), "bag time, not wall time: {text}");
    assert!(text.starts_with("clock:\n  sec: "), "{text}");
}

/// The readable form names a constant's value (`status: 1 (REJECTED)`); --json keeps the bare number.
#[test]
fn ros_cli_echo_names_status_constants_and_json_keeps_numbers() {
    guard();
    let domain = 159;
    let message = r#"{swing_id: 4, bat_id: r161, status: 1, message: "impact_z: 2 m is beyond the bat"}"#;
    let readable = support::spawn_piped(cmd(domain, &["echo", "exit_velocity", "--count", "1", "--timeout", "60"]));
    let json = start_echo(domain, "exit_velocity", 1, &[]);
    run_ok(cmd(domain, &["pub", "exit_velocity", message, "--wait-subscribers", "2", "--timeout", "60", "-q"]));
    let text = String::from_utf8_lossy(&finish(readable).stdout).into_owned();
    assert!(text.contains("\nstatus: 1 (REJECTED)\n"), "{text}");
    let got = json_lines(&finish(json));
    assert_eq!(got[0]["status"], json!(1));
}
