//! Interop with another DDS vendor: a Cyclone DDS participant (PyPI `cyclonedds`, tests/python/cyclone_peer.py,
//! types built from the .msg files alone, ROS 2 `rt/` topic and `sweetspot_msgs::msg::dds_::X_` type names)
//! publishes params and swings to the `sweetspot node` binary and receives its ExitVelocity answers, whose
//! numbers must equal the library's. Runs inside the private network namespace of scripts/test; Cyclone is
//! additionally kept on loopback.

mod support;

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use support::node::{domain, NodeProcess};
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

fn cyclone(domain: u16, args: &[&str]) -> Command {
    support::cyclone_peer(domain, args)
}

fn publish(domain: u16, type_name: &str, topic: &str, qos: &str, messages: &Value) {
    let messages = messages.to_string();
    let args = [
        "pub",
        "--type",
        type_name,
        "--topic",
        topic,
        "--json",
        &messages,
        "--qos",
        qos,
        "--wait-subscribers",
        "1",
        "--timeout",
        "60",
        "--keep-alive",
        "0.5",
    ];
    support::run_ok(cyclone(domain, &args), &format!("cyclone pub {topic}"));
}

fn wait_for_file(path: &Path, what: &str) {
    let start = Instant::now();
    while !path.exists() {
        assert!(start.elapsed() < Duration::from_secs(60), "{what} never became ready");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The number after `"key": ` in a JSON line, parsed exactly (Rust's `str::parse` rounds correctly; a JSON
/// library's fast float path may not, and the comparison is bit-for-bit).
fn number(line: &str, key: &str) -> f64 {
    let pattern = format!("\"{key}\": ");
    let start = line.find(&pattern).unwrap_or_else(|| panic!("no {key} in {line}")) + pattern.len();
    let token: String = line[start..].chars().take_while(|c| !matches!(c, ',' | '}' | ' ')).collect();
    token.parse().unwrap_or_else(|e| panic!("{key} = {token}: {e}"))
}

fn bat_json(bat_id: &str, bat: &Bat) -> Value {
    json!({
        "header": {"stamp": {"sec": 1700000000, "nanosec": 1}, "frame_id": "cage"},
        "bat_id": bat_id,
        "preset": "",
        "station_z": bat.stations.iter().map(|s| s.z).collect::<Vec<_>>(),
        "outer_radius": bat.stations.iter().map(|s| s.outer_radius).collect::<Vec<_>>(),
        "inner_radius": bat.stations.iter().map(|s| s.inner_radius).collect::<Vec<_>>(),
        "density": bat.shell.density,
        "youngs_modulus": bat.shell.youngs_modulus,
        "shear_modulus": bat.shell.shear_modulus,
        "core_density": 0.0,
        "slice_length": bat.slice_length,
        "max_modes": 12,
    })
}

#[test]
fn cyclone_dds_peer_sends_params_and_swings_and_gets_the_library_numbers() {
    support::node::require_isolated_network();
    let domain = domain(10);
    let dir = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));

    // Cyclone listens for answers first (volatile topic).
    let ready = dir.path().join("sub.ready");
    let listener: Child = cyclone(
        domain,
        &[
            "sub",
            "--type",
            "sweetspot_msgs/msg/ExitVelocity",
            "--topic",
            "/exit_velocity",
            "--count",
            "3",
            "--timeout",
            "120",
            "--qos",
            "results",
            "--wait-publishers",
            "1",
            "--ready-file",
            ready.to_str().unwrap(),
        ],
    )
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .expect("Cyclone DDS listener");
    wait_for_file(&ready, "the Cyclone DDS listener");

    let bat = Bat::preset("aluminum").unwrap();
    let ball = Ball { mass: 0.142, radius: 0.0365, cor: 0.5, stiffness: 6.0e7, exponent: 1.9, ..Ball::default() };
    publish(domain, "sweetspot_msgs/msg/BatParams", "/bat/params", "params", &bat_json("cy_bat", &bat));
    node.wait_for_log("bat 'cy_bat' set", Duration::from_secs(60));
    let ball_msg = json!({
        "header": {"stamp": {"sec": 1700000000, "nanosec": 2}, "frame_id": "cage"}, "ball_id": "cy_ball",
        "mass": ball.mass, "radius": ball.radius, "cor": ball.cor, "stiffness": ball.stiffness, "exponent": ball.exponent,
    });
    publish(domain, "sweetspot_msgs/msg/BallParams", "/ball/params", "params", &ball_msg);
    node.wait_for_log("ball 'cy_ball' set", Duration::from_secs(60));

    let swing = |id: u64, bat_id: &str, ball_id: &str, z: f64, measured: Value| {
        json!({"header": {"stamp": {"sec": 1700000100 + id as i64, "nanosec": 7}, "frame_id": "cage"},
               "swing_id": id, "bat_id": bat_id, "ball_id": ball_id, "ball_speed": 38.5, "bat_cm_speed": 21.0,
               "bat_angular_speed": 48.0, "impact_z": z, "measured_exit_speed": measured})
    };
    let swings = json!([
        swing(1, "cy_bat", "cy_ball", 0.62, json!(43.0)),
        swing(2, "r161", "baseball", 0.70, Value::Null),
        swing(3, "cy_bat", "", 5.0, Value::Null),
    ]);
    publish(domain, "sweetspot_msgs/msg/Swing", "/swing", "swing", &swings);

    let out = listener.wait_with_output().unwrap();
    assert!(out.status.success(), "Cyclone listener: {}", String::from_utf8_lossy(&out.stderr));
    let lines: Vec<String> = String::from_utf8_lossy(&out.stdout).lines().map(str::to_string).collect();
    let answers: Vec<Value> = lines.iter().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(answers.len(), 3);

    let check = |line: &str, bat: &Bat, modes: usize, ball: &Ball, z: f64| {
        let answer: Value = serde_json::from_str(line).unwrap();
        let answer = &answer;
        let set = ModeSet::compute(bat, modes).unwrap();
        let impact = Impact { ball_speed: 38.5, bat_cm_speed: 21.0, bat_angular_speed: 48.0, impact_z: z };
        let r = collide(&set, ball, &impact, &CollisionOptions { modes, time_step: 5e-6 }).unwrap();
        assert_eq!(answer["status"], json!(0), "{answer}");
        assert_eq!(number(line, "exit_speed"), r.exit_speed, "{answer}");
        assert_eq!(number(line, "rigid_exit_speed"), r.rigid_exit_speed);
        assert_eq!(number(line, "effective_cor"), r.effective_cor);
        assert_eq!(number(line, "collision_efficiency"), r.collision_efficiency);
        assert_eq!(number(line, "contact_time"), r.contact_time);
        assert_eq!(number(line, "peak_force"), r.peak_force);
        assert_eq!(number(line, "impulse"), r.impulse);
        assert_eq!(number(line, "max_compression"), r.max_compression);
        r
    };
    assert_eq!(answers[0]["swing_id"], json!(1));
    assert_eq!(answers[0]["header"], swings[0]["header"]);
    assert_eq!((answers[0]["bat_id"].as_str(), answers[0]["ball_id"].as_str()), (Some("cy_bat"), Some("cy_ball")));
    let r = check(&lines[0], &bat, 12, &ball, 0.62);
    assert_eq!(number(&lines[0], "residual"), 43.0 - r.exit_speed);
    assert_eq!(answers[1]["swing_id"], json!(2));
    check(&lines[1], &Bat::preset("r161").unwrap(), 18, &Ball::default(), 0.70);
    assert_eq!(answers[1]["residual"], Value::Null, "NaN residual when nothing was measured");
    assert_eq!(answers[2]["swing_id"], json!(3));
    assert_eq!(answers[2]["status"], json!(1), "off the bat: REJECTED");
    assert!(answers[2]["message"].as_str().unwrap().contains("impact_z"), "{}", answers[2]);
    drop(node);
}
