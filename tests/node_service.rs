//! The node's `~/simulate_swing` service called by another DDS vendor: a Cyclone DDS client
//! (tests/python/cyclone_service.py, request/response types built from the .srv alone, ROS 2's `rq/…Request` /
//! `rr/…Reply` topics and `sweetspot_msgs::srv::dds_::SimulateSwing_Request_` names) calls the `sweetspot node`
//! binary. Every answer must equal `sweetspot simulate --json` for the same inputs bit for bit (an independent
//! run of the library from the command line, no DDS, no node); a NaN is REJECTED naming its field; 10,000
//! calls sent at once are all answered; a node with a small queue refuses the overflow with a reason, none
//! lost; and the session's `exit_velocity` topic carries none of the calls. Also `sweetspot call` against the
//! node. Runs inside the private network namespace of scripts/test; Cyclone is kept on loopback.

mod support;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use support::node::{domain, NodeProcess};
use support::{cyclone_peer, dds_env, python, repo, run_ok, sweetspot};
use sweetspot::physics::oblique::rad_per_s_to_rpm;

/// The Cyclone service client with `args` after `call`, on `domain`.
fn cyclone_call(domain: u16, args: &[&str]) -> Output {
    let mut c = Command::new(python());
    c.arg(repo().join("tests/python/cyclone_service.py")).args(["--loopback", "call"]).args(args);
    dds_env(&mut c, domain);
    c.output().expect("cyclone_service.py")
}

fn lines(out: &Output, what: &str) -> Vec<Value> {
    support::json_lines(out, what)
}

/// The service events recorded in `bag`, decoded by rosbags with the definition stored in the bag
/// (tests/python/service_events.py): {"type", "count", "metadata_count", "events"}.
fn service_events(bag: &Path) -> Value {
    let out = Command::new(python())
        .arg(repo().join("tests/python/service_events.py"))
        .arg(bag)
        .arg("/sweetspot/simulate_swing/_service_event")
        .output()
        .expect("service_events.py");
    lines(&out, "service_events.py").swap_remove(0)
}

/// One swing of the 19: a preset, an impact point, speeds, and (oblique) undercut m, attack angle deg,
/// pitch spin rpm.
#[derive(Clone, Copy)]
struct Case {
    bat: &'static str,
    z: f64,
    ball_speed: f64,
    bat_cm_speed: f64,
    bat_angular_speed: f64,
    oblique: Option<(f64, f64, f64)>,
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for (i, bat) in ["r161", "r161-corked", "aluminum", "torpedo"].into_iter().enumerate() {
        for (j, z) in [0.55, 0.62, 0.70, 0.76].into_iter().enumerate() {
            let k = (4 * i + j) as f64;
            let (ball_speed, bat_cm_speed, bat_angular_speed) = (33.0 + k * 0.75, 19.5 + k * 0.4, 41.0 + k);
            out.push(Case { bat, z, ball_speed, bat_cm_speed, bat_angular_speed, oblique: None });
        }
    }
    for (k, geometry) in [(0.01, 10.0, 1500.0), (-0.008, 6.0, -900.0), (0.015, 0.0, 2400.0)].into_iter().enumerate() {
        let z = 0.66 + 0.02 * k as f64;
        out.push(Case {
            bat: "r161",
            z,
            ball_speed: 38.0,
            bat_cm_speed: 22.0,
            bat_angular_speed: 47.0,
            oblique: Some(geometry),
        });
    }
    assert_eq!(out.len(), 19);
    out
}

fn request(id: u64, c: &Case) -> Value {
    let (undercut, attack_deg, spin_rpm) = c.oblique.unwrap_or((0.0, 0.0, 0.0));
    json!({"swing": {
        "header": {"stamp": {"sec": 1700000200 + id as i64, "nanosec": 9}, "frame_id": "cage"},
        "swing_id": id, "bat_id": c.bat, "ball_id": "", "ball_speed": c.ball_speed, "bat_cm_speed": c.bat_cm_speed,
        "bat_angular_speed": c.bat_angular_speed, "impact_z": c.z, "measured_exit_speed": Value::Null,
        "undercut": undercut, "attack_angle": f64::to_radians(attack_deg),
        "pitch_spin": sweetspot::physics::oblique::rpm_to_rad_per_s(spin_rpm),
    }})
}

/// `sweetspot simulate --json` for the case (the node's defaults: the built-in baseball, 18 modes, 5 µs).
fn simulate(c: &Case) -> Value {
    let s = |v: f64| format!("{v:?}");
    let mut args = vec![
        "simulate".to_string(),
        "--bat".into(),
        c.bat.into(),
        "--ball-speed".into(),
        s(c.ball_speed),
        "--bat-cm-speed".into(),
        s(c.bat_cm_speed),
        "--bat-angular-speed".into(),
        s(c.bat_angular_speed),
        "--impact-z".into(),
        s(c.z),
        "--json".into(),
    ];
    if let Some((undercut, attack, spin)) = c.oblique {
        args.extend(["--undercut".into(), s(undercut), "--attack-angle".into(), s(attack)]);
        args.extend(["--pitch-spin".into(), s(spin)]);
    }
    let out = Command::new(support::BIN).args(&args).output().expect("sweetspot simulate");
    support::assert_success(&out, "sweetspot simulate");
    serde_json::from_slice(&out.stdout).expect("simulate JSON")
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// Every number the topics would carry equals simulate's, bit for bit.
fn assert_same_as_simulate(answer: &Value, c: &Case, sim: &Value) {
    let ev = &answer["exit_velocity"];
    let r = &sim["results"][0];
    let what = format!("{} at {} m ({:?})", c.bat, c.z, c.oblique);
    assert_eq!(ev["status"], json!(0), "{what}: {ev}");
    for key in ["rigid_exit_speed", "effective_cor", "collision_efficiency", "contact_time", "peak_force", "impulse"] {
        assert_eq!(f(&ev[key]).to_bits(), f(&r[key]).to_bits(), "{what}: {key}");
    }
    assert_eq!(f(&ev["max_compression"]).to_bits(), f(&r["max_compression"]).to_bits(), "{what}");
    match c.oblique {
        None => {
            assert_eq!(f(&ev["exit_speed"]).to_bits(), f(&r["exit_speed"]).to_bits(), "{what}: exit_speed");
            assert_eq!(f(&ev["launch_angle"]), 0.0);
        }
        Some(_) => {
            let o = &r["oblique"];
            assert_eq!(f(&ev["exit_speed"]).to_bits(), f(&o["exit_speed"]).to_bits(), "{what}: exit_speed");
            assert_eq!(f(&ev["normal_exit_speed"]).to_bits(), f(&o["normal_exit_speed"]).to_bits(), "{what}");
            assert_eq!(f(&ev["tangential_exit_speed"]).to_bits(), f(&o["tangential_exit_speed"]).to_bits(), "{what}");
            let launch_deg = f(&ev["launch_angle"]).to_degrees();
            assert_eq!(launch_deg.to_bits(), f(&o["launch_angle_deg"]).to_bits(), "{what}: launch angle");
            let spin_rpm = rad_per_s_to_rpm(f(&ev["spin"]));
            assert_eq!(spin_rpm.to_bits(), f(&o["spin_rpm"]).to_bits(), "{what}: spin");
        }
    }
    let me = &answer["modal_energies"];
    assert_eq!(me.as_array().map(Vec::len), Some(1), "{what}: one ModalEnergies with an OK answer");
    let me = &me[0];
    let modes = r["mode_energies"].as_array().expect("mode_energies");
    assert_eq!(me["frequency"].as_array().unwrap().len(), modes.len(), "{what}: mode count");
    for (i, mode) in modes.iter().enumerate() {
        assert_eq!(f(&me["frequency"][i]).to_bits(), f(&mode["frequency_hz"]).to_bits(), "{what}: mode {i}");
        assert_eq!(f(&me["energy"][i]).to_bits(), f(&mode["energy"]).to_bits(), "{what}: mode {i} energy");
    }
    assert_eq!(f(&me["vibration_energy"]).to_bits(), f(&r["energy"]["vibration"]).to_bits(), "{what}");
    assert_eq!(f(&me["hysteresis_loss"]).to_bits(), f(&r["energy"]["hysteresis_loss"]).to_bits(), "{what}");
    assert_eq!(f(&me["energy_residual"]).to_bits(), f(&r["energy"]["residual"]).to_bits(), "{what}");
}

fn wait_for_file(path: &Path) {
    let start = Instant::now();
    while !path.exists() {
        assert!(start.elapsed() < Duration::from_secs(60), "{} never appeared", path.display());
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn cyclone_calls_get_simulate_s_numbers_nan_is_rejected_a_flood_is_answered_and_the_topics_see_none() {
    support::node::require_isolated_network();
    let domain = domain(26);
    let dir = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));

    // The session's answers topic, listened to by Cyclone from before the first call to after the last.
    let ready = dir.path().join("sub.ready");
    let session = support::spawn_piped({
        let mut c = cyclone_peer(domain, &["sub", "--type", "sweetspot_msgs/msg/ExitVelocity"]);
        c.args(["--topic", "/exit_velocity", "--count", "1", "--timeout", "600", "--qos", "results"]);
        c.args(["--wait-publishers", "1", "--ready-file", ready.to_str().unwrap()]);
        c
    });
    wait_for_file(&ready);

    // The 19 swings in one batch.
    let cases = cases();
    let requests: Vec<Value> = cases.iter().enumerate().map(|(i, c)| request(i as u64 + 1, c)).collect();
    let batch = Value::Array(requests.clone()).to_string();
    let answers = lines(&cyclone_call(domain, &["--json", &batch, "--timeout", "300"]), "19 calls");
    assert_eq!(answers.len(), 19);
    for (i, (c, answer)) in cases.iter().zip(&answers).enumerate() {
        assert_eq!(answer["exit_velocity"]["swing_id"], json!(i + 1));
        assert_eq!(answer["exit_velocity"]["header"], requests[i]["swing"]["header"], "the stamp is echoed");
        assert_eq!(answer["exit_velocity"]["bat_id"], json!(c.bat));
        assert_eq!(answer["exit_velocity"]["ball_id"], json!("mlb2024"), "no ball named: the default_ball");
        assert_same_as_simulate(answer, c, &simulate(c));
    }

    // A NaN is REJECTED, naming the field; nothing computed.
    let mut nan = request(100, &cases[0]);
    nan["swing"]["bat_cm_speed"] = Value::Null;
    let rejected = lines(&cyclone_call(domain, &["--json", &nan.to_string(), "--timeout", "60"]), "NaN call");
    let ev = &rejected[0]["exit_velocity"];
    assert_eq!(ev["status"], json!(1), "{ev}");
    assert!(ev["message"].as_str().unwrap().contains("bat_cm_speed"), "{ev}");
    assert_eq!(ev["exit_speed"], Value::Null);
    assert_eq!(rejected[0]["modal_energies"], json!([]));

    // 10,000 calls at once: every one answered, none twice.
    let flood = request(0, &cases[2]).to_string();
    let out = cyclone_call(domain, &["--json", &flood, "--repeat", "10000", "--summary", "--timeout", "600"]);
    let summary = &lines(&out, "10,000 calls")[0];
    assert_eq!(summary["answered"], json!(10000), "{summary}");
    assert_eq!(
        (&summary["duplicates"], &summary["unknown"], &summary["without_reason"]),
        (&json!(0), &json!(0), &json!(0))
    );
    let ok = summary["status_counts"]["0"].as_u64().unwrap_or(0);
    let dropped = summary["status_counts"]["2"].as_u64().unwrap_or(0);
    assert_eq!(ok + dropped, 10000, "OK or DROPPED with a reason: {summary}");

    // None of it reached the session's topic: the first ExitVelocity there is the one real swing sent now.
    let swing = json!({"header": {"stamp": {"sec": 1700009999, "nanosec": 1}, "frame_id": "cage"}, "swing_id": 424242,
                       "bat_id": "r161", "ball_speed": 40.0, "bat_cm_speed": 25.0, "bat_angular_speed": 45.0,
                       "impact_z": 0.7});
    let publish = ["pub", "--type", "sweetspot_msgs/msg/Swing", "--topic", "/swing", "--qos", "swing"];
    let mut c = cyclone_peer(domain, &publish);
    c.args(["--json", &swing.to_string(), "--wait-subscribers", "1", "--timeout", "60", "--keep-alive", "0.5"]);
    run_ok(c, "cyclone pub /swing");
    let seen = lines(&session.wait_with_output().unwrap(), "the session's exit_velocity");
    assert_eq!(seen.len(), 1);
    assert_eq!(seen[0]["swing_id"], json!(424242), "a call's answer reached exit_velocity: {}", seen[0]);
    let (status, _, log) = node.stop_with(libc::SIGINT);
    assert!(status.success(), "{log}");
    assert!(log.contains("1 swings received = 1 answered OK"), "calls are not swings of the session:\n{log}");
}

#[test]
fn a_node_with_a_small_queue_refuses_the_overflow_of_a_burst_with_a_reason_and_loses_none() {
    support::node::require_isolated_network();
    let domain = domain(27);
    let dir = tempfile::tempdir().unwrap();
    let args = ["--no-record", "--ros-args", "-p", "queue_capacity:=2", "-p", "workers:=1"];
    let node = NodeProcess::spawn(domain, dir.path(), &args);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));
    let call = request(0, &cases()[0]).to_string();
    let out = cyclone_call(domain, &["--json", &call, "--repeat", "2000", "--summary", "--timeout", "600"]);
    let summary = &lines(&out, "2,000 calls")[0];
    assert_eq!(summary["answered"], json!(2000), "{summary}");
    assert_eq!(summary["without_reason"], json!(0), "{summary}");
    let dropped = summary["status_counts"]["2"].as_u64().unwrap_or(0);
    let ok = summary["status_counts"]["0"].as_u64().unwrap_or(0);
    assert!(dropped > 0, "a queue of 2 on one worker refuses some of 2,000 calls sent at once: {summary}");
    assert_eq!(ok + dropped, 2000, "{summary}");
    drop(node);
}

#[test]
fn sweetspot_call_prints_the_answer_and_says_by_its_exit_status_what_happened() {
    support::node::require_isolated_network();
    let domain = domain(28);
    let dir = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record", "--ros-args", "-r", "__ns:=/rig3"]);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));
    let c = cases()[0];
    let call = |args: &[&str]| {
        let mut cmd = sweetspot(domain, &["call"]);
        cmd.args(args).stdin(Stdio::null());
        cmd.output().expect("sweetspot call")
    };

    let out = call(&["simulate_swing", &request(7, &c).to_string(), "--ns", "/rig3", "--timeout", "60"]);
    let answer = &lines(&out, "sweetspot call")[0];
    assert_same_as_simulate(answer, &c, &simulate(&c));
    // The fully-qualified form, as `ros2 service call` takes it.
    let out = call(&["/rig3/sweetspot/simulate_swing", &request(8, &c).to_string(), "--timeout", "60"]);
    assert_eq!(lines(&out, "sweetspot call /rig3/…")[0]["exit_velocity"]["swing_id"], json!(8));
    // YAML, as `ros2 service call` takes it.
    let yaml = "{swing: {swing_id: 9, bat_id: r161, ball_speed: 40, bat_cm_speed: 25, impact_z: 0.7}}";
    let out = call(&["simulate_swing", yaml, "--ns", "/rig3", "--timeout", "60"]);
    let answer = &lines(&out, "sweetspot call YAML")[0];
    assert_eq!((&answer["exit_velocity"]["swing_id"], &answer["exit_velocity"]["status"]), (&json!(9), &json!(0)));

    // REJECTED: the answer on stdout, the reason on stderr, exit status 1.
    let out = call(&["simulate_swing", r#"{"swing": {"bat_id": "no-such-bat"}}"#, "--ns", "/rig3", "--timeout", "60"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("REJECTED") && stderr.contains("unknown bat_id 'no-such-bat'"), "{stderr}");
    let answer: Value = serde_json::from_slice(&out.stdout).expect("the answer is printed");
    assert_eq!(answer["exit_velocity"]["status"], json!(1));

    // Bad JSON for the type: refused before any DDS, naming the field.
    let out = call(&["simulate_swing", r#"{"swing": {"ball_sped": 3}}"#, "--timeout", "5"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("request.swing.ball_sped"), "{out:?}");
    // Nobody serves it: a clear error after --timeout.
    let out = call(&["simulate_swing", "{}", "--timeout", "2"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("no answer from /sweetspot/simulate_swing within"), "{stderr}");
    // Unknown service.
    let out = call(&["reset", "{}"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown service \"reset\""), "{out:?}");
    drop(node);
}

#[test]
fn record_services_records_each_call_as_rosbag2_records_a_service_and_only_then() {
    support::node::require_isolated_network();
    let domain = domain(29);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("calls");
    let record_path = format!("record_path:={}", bag.display());
    let args = ["--ros-args", "-p", "record_services:=true", "-p", &record_path];
    let node = NodeProcess::spawn(domain, dir.path(), &args);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));
    let c = cases()[1];
    for id in [31, 32] {
        let mut cmd = sweetspot(domain, &["call", "simulate_swing", &request(id, &c).to_string(), "--timeout", "60"]);
        lines(&cmd.output().expect("sweetspot call"), "sweetspot call");
    }
    let (status, _, log) = node.stop_with(libc::SIGINT);
    assert!(status.success(), "{log}");

    let read = &service_events(&bag);
    assert_eq!(read["type"], json!("sweetspot_msgs/srv/SimulateSwing_Event"), "{read}");
    assert_eq!(read["count"], json!(4), "request and response of 2 calls: {read}");
    assert_eq!(read["metadata_count"], json!(4), "metadata.yaml agrees");
    let events = read["events"].as_array().unwrap();
    for (k, id) in [31, 32].into_iter().enumerate() {
        let (asked, answered) = (&events[2 * k], &events[2 * k + 1]);
        assert_eq!(asked["info"]["event_type"], json!(1), "REQUEST_RECEIVED first: {asked}");
        assert_eq!(asked["request"][0]["swing"]["swing_id"], json!(id));
        assert_eq!(asked["response"], json!([]));
        assert_eq!(answered["info"]["event_type"], json!(2), "then RESPONSE_SENT: {answered}");
        assert_eq!(answered["response"][0]["exit_velocity"]["swing_id"], json!(id));
        assert_eq!(answered["response"][0]["exit_velocity"]["status"], json!(0));
        assert_eq!(asked["info"]["client_gid"], answered["info"]["client_gid"], "one client");
        assert_eq!(asked["info"]["sequence_number"], answered["info"]["sequence_number"], "one request");
    }
    // Calls are not swings of the session: nothing recorded on exit_velocity.
    let info = sweetspot::bag::info::bag_info(&bag).expect("bag info");
    assert!(info.topics.iter().all(|t| t.name != "/exit_velocity" || t.count == 0), "{info:?}");
}

#[test]
fn the_documented_call_runs_as_written() {
    support::node::require_isolated_network();
    let page = std::fs::read_to_string(repo().join("docs/node.md")).unwrap();
    let line =
        page.lines().find(|l| l.starts_with("sweetspot call ")).expect("a `sweetspot call` line in docs/node.md");
    let (command, rest) = line.split_once(" '").expect("the request in single quotes");
    let request = rest.strip_suffix('\'').expect("the line ends with the request's closing quote");
    let words: Vec<&str> = command.split_whitespace().skip(1).collect();
    assert_eq!(words, ["call", "simulate_swing"], "{line}");
    let domain = domain(31);
    let dir = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(domain, dir.path(), &["--ros-args", "-p", "record:=false"]);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));
    let mut cmd = sweetspot(domain, &words);
    let out = cmd.arg(request).stdin(Stdio::null()).output().expect("sweetspot call");
    assert!(out.status.success(), "{line}: {out:?}");
    let answer = &lines(&out, "the documented sweetspot call")[0];
    assert_eq!(answer["exit_velocity"]["swing_id"], json!(1), "{answer}");
    assert_eq!(answer["exit_velocity"]["status"], json!(0), "OK: {answer}");
    drop(node);
}

/// A node started with `service_mapping:=cyclone` serves clients on rmw_cyclonedds_cpp: the Cyclone peer puts
/// that RMW's request header `{uint64 guid; int64 seq}` in front of each request and keeps a reply only if the
/// node echoed both (exit status 3 otherwise). The answers equal `simulate --json`; the recorded service events
/// (read by rosbags) carry the client's own sequence numbers — one past 2^32, so the two 32-bit halves of the
/// int64 must not be swapped — and its id in the last 8 bytes of client_gid; `sweetspot call --mapping cyclone`
/// gets its answer too.
#[test]
fn a_node_on_the_cyclone_mapping_answers_rmw_cyclonedds_style_clients() {
    support::node::require_isolated_network();
    let domain = domain(32);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("cyclone");
    let record_path = format!("record_path:={}", bag.display());
    let args = ["--ros-args", "-p", "service_mapping:=cyclone", "-p", "record_services:=true", "-p", &record_path];
    let node = NodeProcess::spawn(domain, dir.path(), &args);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));

    let all = cases();
    let picked = [all[0], all[all.len() / 2], all[all.len() - 1]];
    let requests: Vec<Value> = picked.iter().enumerate().map(|(k, c)| request(41 + k as u64, c)).collect();
    let guid: u64 = 0x5EE7_5907_0000_0001;
    let first_seq: i64 = (1 << 32) + 5;
    let out = cyclone_call(
        domain,
        &[
            "--json",
            &Value::Array(requests).to_string(),
            "--mapping",
            "cyclone",
            "--guid",
            &guid.to_string(),
            "--first-seq",
            &first_seq.to_string(),
            "--timeout",
            "60",
        ],
    );
    assert!(out.status.success(), "{out:?}");
    let answers = lines(&out, "cyclone_service.py --mapping cyclone");
    assert_eq!(answers.len(), picked.len());
    for (answer, c) in answers.iter().zip(&picked) {
        assert_same_as_simulate(answer, c, &simulate(c));
    }
    let mut cmd = sweetspot(domain, &["call", "simulate_swing", &request(44, &picked[0]).to_string()]);
    let out = cmd.args(["--mapping", "cyclone", "--timeout", "60"]).stdin(Stdio::null()).output().unwrap();
    assert_eq!(lines(&out, "sweetspot call --mapping cyclone")[0]["exit_velocity"]["swing_id"], json!(44));
    // The default (enhanced) client matches the same topics but gets no answer: the error says which flag.
    let mut cmd = sweetspot(domain, &["call", "simulate_swing", &request(45, &picked[0]).to_string()]);
    let out = cmd.args(["--timeout", "3"]).stdin(Stdio::null()).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("service_mapping:=cyclone is called with --mapping cyclone"), "{stderr}");
    let (status, _, log) = node.stop_with(libc::SIGINT);
    assert!(status.success(), "{log}");

    let events = service_events(&bag)["events"].as_array().unwrap().clone();
    assert_eq!(events.len(), 8, "request and response of 4 calls");
    let guid_bytes: Vec<Value> = guid.to_le_bytes().iter().map(|&b| json!(b)).collect();
    // The three calls were in flight together: their events interleave, so each is matched by its swing_id.
    let mut checked = 0;
    for event in &events {
        let swing_id = event["request"][0]["swing"]["swing_id"]
            .as_i64()
            .or_else(|| event["response"][0]["exit_velocity"]["swing_id"].as_i64())
            .unwrap_or_else(|| panic!("an event without its call: {event}"));
        if swing_id >= 44 {
            continue; // sweetspot call's, numbered by ros2-client
        }
        assert_eq!(event["info"]["sequence_number"], json!(first_seq + (swing_id - 41)), "{event}");
        let gid = event["info"]["client_gid"].as_array().unwrap();
        assert_eq!(gid[8..], guid_bytes[..], "the client's id in the last 8 bytes: {event}");
        checked += 1;
    }
    assert_eq!(checked, 6, "request and response of the Cyclone client's 3 calls");
}

/// One call whose `header.frame_id` is 70 KB, then one of 10 MB, then a bystander (another participant)
/// calling normally, on a node serving `mapping`: the attacker's 70 KB call is answered REJECTED naming the
/// field, echoing at most 256 bytes of it and no ModalEnergies; the bystander is answered OK after both.
fn a_huge_frame_id_neither_breaks_the_reply_nor_stops_other_clients(mapping: &str, offset: u16) {
    support::node::require_isolated_network();
    let domain = domain(offset);
    let dir = tempfile::tempdir().unwrap();
    let mapping_arg = format!("service_mapping:={mapping}");
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record", "--ros-args", "-p", &mapping_arg]);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));
    let c = cases()[0];
    let call = |id: u64, extra: &[&str], timeout: &str| {
        let request = request(id, &c).to_string();
        let mut args = vec!["--json", &request, "--mapping", mapping, "--timeout", timeout];
        args.extend_from_slice(extra);
        cyclone_call(domain, &args)
    };
    let out = call(1, &["--frame-id-bytes", "70000"], "60");
    assert!(out.status.success(), "the 70 KB call got no reply: {out:?}\n{}", node.log());
    let answer = &lines(&out, "the 70 KB call")[0];
    let ev = &answer["exit_velocity"];
    assert_eq!(ev["status"], json!(1), "REJECTED: {ev}");
    assert!(ev["message"].as_str().unwrap().contains("header.frame_id is 70000 bytes long"), "{ev}");
    let echoed = ev["header"]["frame_id"].as_str().unwrap();
    assert!(echoed.len() <= 256 && echoed.starts_with("ffff"), "{} bytes echoed", echoed.len());
    assert_eq!(answer["modal_energies"], json!([]), "one verdict: no ModalEnergies with a REJECTED answer");
    // 10 MB: whatever becomes of it, it must not stop the service for anyone else.
    let _ = call(2, &["--frame-id-bytes", "10485760"], "20");
    let out = call(3, &[], "60");
    assert!(out.status.success(), "the bystander got no reply after the huge calls: {out:?}\n{}", node.log());
    let answer = &lines(&out, "the bystander's call")[0];
    assert_eq!(answer["exit_velocity"]["status"], json!(0), "{answer}");
    assert_same_as_simulate(answer, &c, &simulate(&c));
    drop(node);
}

#[test]
fn a_huge_frame_id_leaves_the_enhanced_mapping_answering_everyone() {
    a_huge_frame_id_neither_breaks_the_reply_nor_stops_other_clients("enhanced", 33);
}

#[test]
fn a_huge_frame_id_leaves_the_cyclone_mapping_answering_everyone() {
    a_huge_frame_id_neither_breaks_the_reply_nor_stops_other_clients("cyclone", 34);
}

/// A call carrying its own 1,200-slice bat (density `density`, so each call's bat is another bat to solve).
fn inline_bat_request(id: u64, density: f64) -> Value {
    let mut r = request(id, &cases()[0]);
    r["swing"]["bat_id"] = json!("");
    r["bat"] = json!([{
        "bat_id": "probe", "station_z": [0.0, 0.84], "outer_radius": [0.03, 0.03], "inner_radius": [0.0, 0.0],
        "density": density, "youngs_modulus": 1.814e10, "shear_modulus": 1.05e9, "slice_length": 0.84 / 1200.0,
    }]);
    r
}

/// Inline bats are solved on the service's workers, not on the receive loop: while 40 calls, each with a
/// 1,200-slice bat of its own, are being solved, a peer publishing swings one at a time (each after the
/// previous one's answer) keeps being answered, in order, none lost — no swing waits for the burst: the longest
/// wait is a small part of the burst's duration (when the loop solved them, one swing waited for nearly all of
/// it). Then 300 calls with one identical bat solve it once (the summary's mode-cache misses).
#[test]
fn topic_swings_keep_flowing_during_a_burst_of_inline_bat_calls_and_identical_bats_are_solved_once() {
    use support::node::{blocking, dds, keep_all, Peer};
    use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
    support::node::require_isolated_network();
    let domain = domain(36);
    let dir = tempfile::tempdir().unwrap();
    let args = ["--no-record", "--ros-args", "-p", "workers:=1"];
    let node = NodeProcess::spawn(domain, dir.path(), &args);
    node.wait_for_log("up on ROS_DOMAIN_ID", Duration::from_secs(60));
    let mut peer = Peer::new(domain, "stall_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    peer.wait_for_reader(&swing_pub);
    let swing = |id: u64| Swing {
        swing_id: id,
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.7,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    };
    swing_pub.publish(swing(1)).unwrap();
    assert_eq!(peer.collect(&answers, 1, Duration::from_secs(60))[0].status, ExitVelocity::STATUS_OK);

    let burst: Vec<Value> = (1..=40).map(|k| inline_bat_request(k, 600.0 + k as f64)).collect();
    let batch = Value::Array(burst).to_string();
    let started = Instant::now();
    let calls = std::thread::spawn(move || {
        let out = cyclone_call(domain, &["--json", &batch, "--timeout", "600"]);
        (out, Instant::now())
    });
    let (mut id, mut longest_wait, mut answered) = (2u64, Duration::ZERO, Vec::new());
    while !calls.is_finished() {
        let sent = Instant::now();
        swing_pub.publish(swing(id)).unwrap();
        let got = peer.collect(&answers, 1, Duration::from_secs(600));
        longest_wait = longest_wait.max(sent.elapsed());
        answered.push(got[0].swing_id);
        id += 1;
    }
    let (out, ended) = calls.join().unwrap();
    let replies = lines(&out, "40 inline-bat calls");
    assert_eq!(replies.len(), 40);
    assert!(replies.iter().all(|r| r["exit_velocity"]["status"] == json!(0)), "{:?}", replies[0]);
    assert_eq!(answered, (2..id).collect::<Vec<_>>(), "every swing answered, in order");
    let burst_took = ended - started;
    println!("{} swings answered during the burst of {burst_took:?}; longest wait {longest_wait:?}", answered.len());
    assert!(
        longest_wait * 4 < burst_took,
        "a swing waited {longest_wait:?} during a burst of {burst_took:?}: the receive loop solved the bats"
    );

    // 300 calls with one bat: built once, solved once.
    let same = inline_bat_request(0, 649.0).to_string();
    let out = cyclone_call(domain, &["--json", &same, "--repeat", "300", "--summary", "--timeout", "600"]);
    let summary = &lines(&out, "300 identical inline bats")[0];
    assert_eq!(summary["status_counts"]["0"], json!(300), "{summary}");
    let (status, _, log) = node.stop_with(libc::SIGINT);
    assert!(status.success(), "{log}");
    // The default bat, the 40 bats of the burst, and the one bat of the 300 calls.
    assert!(log.contains(" hits / 42 misses"), "one solve per distinct bat:\n{log}");
}
