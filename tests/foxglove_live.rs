//! `sweetspot node --foxglove PORT` serves the session live over the Foxglove WebSocket protocol. Checked with
//! Foxglove's own client and decoder from npm (`tests/js/`, installed by scripts/test: `@foxglove/ws-protocol`'s
//! FoxgloveClient, `@foxglove/rosmsg` and `@foxglove/rosmsg2-serialization`), inside the private network
//! namespace of scripts/test (the node binds 127.0.0.1, the swings arrive over DDS on loopback):
//! - every ExitVelocity the client decodes equals, field for field, the one the node recorded in its bag, in
//!   order, with none missing; modal energies decode too, and the latched SweetSpot reaches a client that
//!   connects after it was published; the swings' scenes (`swing_scene`, served without the DDS-side
//!   parameter, rate-limited by `swing_scene_live_hz`) decode with the arrow at the decoded answer's launch
//!   angle and the R161's outline;
//! - a client that subscribes and then stops reading changes no answer and loses no swing;
//! - `/diagnostics` is served (live only; it is not recorded), with the server's own counters (clients,
//!   subscriptions, messages served);
//! - `/rosout` is served: the node's log lines as rcl_interfaces/Log, each one a line of the node's log, the
//!   startup lines still there for a client that connects later.

mod support;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, ChildStdout};
use std::time::Duration;
use support::same_json as same;

use serde_json::Value;
use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};

const WAIT: Duration = Duration::from_secs(60);
const PORT: u16 = 8765;
/// Swings answered while the decoding client reads.
const LIVE: u64 = 200;
/// Swings answered while the stalled client is connected (several times its queue in bytes of answers).
const STALLED: u64 = 600;

fn swing(id: u64) -> Swing {
    Swing {
        swing_id: id,
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.45 + 0.01 * (id % 20) as f64,
        measured_exit_speed: 30.0 + (id % 7) as f64,
        ..Swing::default()
    }
}

/// The npm client (see tests/js/foxglove_client.mjs) with `args`; stdout piped.
fn client(args: &[&str]) -> (Child, BufReader<ChildStdout>) {
    support::node_client("foxglove_client.mjs", "@foxglove/ws-protocol", args, &[])
}

/// Reads lines until the first message on `latched`, the client's last topic, and returns the message lines
/// read (that one included): the client subscribes in the order given and the server handles a client's
/// subscriptions in order, so from then on every subscription is in effect.
fn wait_latched(out: &mut BufReader<ChildStdout>, latched: &str) -> Vec<String> {
    let (mut lines, mut line) = (Vec::new(), String::new());
    let topic = format!("\"topic\":\"{latched}\"");
    loop {
        line.clear();
        assert!(out.read_line(&mut line).unwrap() > 0, "the client exited before {latched} arrived");
        if !line.contains("\"subscribed\"") {
            lines.push(line.trim_end().to_string());
        }
        if line.contains(&topic) {
            return lines;
        }
    }
}

/// Reads lines until the client says it subscribed to everything; panics if it exits first.
fn wait_subscribed(out: &mut BufReader<ChildStdout>) {
    let mut line = String::new();
    loop {
        line.clear();
        assert!(out.read_line(&mut line).unwrap() > 0, "the client exited before subscribing");
        if line.contains("\"subscribed\"") {
            return;
        }
    }
}

/// The R161's radii from its data file (diameter in mm per 1-cm slice), m.
fn r161_radii() -> Vec<f64> {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/physics/src/data/r161.dat"))
        .unwrap()
        .lines()
        .filter_map(|l| l.split_whitespace().nth(1).and_then(|d| d.parse::<f64>().ok()))
        .map(|d| d / 2000.0)
        .collect()
}

/// The live view's scenes are rate-limited (`swing_scene_live_hz`, 30 Hz by default) and the burst of answers
/// takes well under a second, so only a few scenes come, the first for the first swing. Each is drawn for the
/// answer of the swing it names: its stamp, its arrow at the answer's launch angle and the ball at its impact_z,
/// and the default bat (R161) outlined at its data file's radii.
fn check_scenes(scenes: &[Value], answers: &[Value]) {
    assert!(!scenes.is_empty(), "no scene");
    assert!(
        scenes.len() < answers.len() / 2,
        "{} scenes for {} answers: not rate-limited",
        scenes.len(),
        answers.len()
    );
    let radii = r161_radii();
    let num = |v: &Value| v.as_f64().unwrap_or_else(|| panic!("{v}"));
    for (k, scene) in scenes.iter().enumerate() {
        let markers = scene["markers"].as_array().unwrap();
        let find = |ns: &str| markers.iter().find(|m| m["ns"] == ns).unwrap_or_else(|| panic!("no {ns}: {scene}"));
        let label = find("label")["text"].as_str().unwrap().to_string();
        let answer = answers
            .iter()
            .find(|a| label.starts_with(&format!("swing {} ", a["swing_id"])))
            .unwrap_or_else(|| panic!("no answer for the scene labelled {label}"));
        if k == 0 {
            assert_eq!(answer["swing_id"], answers[0]["swing_id"], "the first answered swing is drawn at once");
        }
        assert_eq!(markers[0]["header"]["stamp"], answer["header"]["stamp"]);
        assert_eq!(markers[0]["header"]["frame_id"], "bat");
        let arrow = find("exit_velocity")["points"].as_array().unwrap();
        let angle = (num(&arrow[1]["y"]) - num(&arrow[0]["y"])).atan2(num(&arrow[1]["x"]) - num(&arrow[0]["x"]));
        assert!((angle - num(&answer["launch_angle"])).abs() < 1e-12, "{angle} vs {}", answer["launch_angle"]);
        assert_eq!(num(&find("ball")["pose"]["position"]["z"]), num(&answer["impact_z"]));
        let outline: Vec<f64> =
            find("bat_outline")["points"].as_array().unwrap()[1..=radii.len()].iter().map(|p| num(&p["x"])).collect();
        assert_eq!(outline, radii);
    }
}

#[test]
fn a_foxglove_client_decodes_what_the_bag_records_and_a_stalled_one_changes_nothing() {
    let domain = domain(91);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag");
    let mut peer = Peer::new(domain, "foxglove_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    // The command line of docs/foxglove.md, with the bag put in the test's directory.
    let page = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/foxglove.md")).unwrap();
    let line = page.lines().find(|l| l.starts_with("sweetspot node")).expect("a node command line");
    let line = line.split('#').next().unwrap().trim();
    assert_eq!(line, format!("sweetspot node --foxglove {PORT}"));
    let mut args: Vec<String> = line.split_whitespace().skip(2).map(String::from).collect();
    args.extend(["--ros-args".into(), "-p".into(), format!("record_path:={}", bag.display())]);
    let node = NodeProcess::spawn(domain, dir.path(), &args.iter().map(String::as_str).collect::<Vec<_>>());
    node.wait_for_log("Foxglove WebSocket server on ws://127.0.0.1:8765", WAIT);
    peer.wait_for_reader(&swing_pub);
    let url = format!("ws://127.0.0.1:{PORT}");

    // 1. A client that connects after the default bat's SweetSpot was published and reads everything.
    let count = LIVE.to_string();
    let (mut reader, mut out) =
        client(&[&url, &count, "/exit_velocity", "/modal_energies", "/sweet_spot", "/swing_scene", "/bat_frame"]);
    let latched = wait_latched(&mut out, "/bat_frame");
    for id in 1..=LIVE {
        swing_pub.publish(swing(id)).unwrap();
    }
    let over_dds = peer.collect(&answers, LIVE as usize, WAIT);
    assert_eq!(over_dds.iter().map(|ev| ev.swing_id).collect::<Vec<_>>(), (1..=LIVE).collect::<Vec<_>>());
    let mut live: Vec<Value> = Vec::new();
    let (mut energies, mut sweet_spots) = (0, 0);
    let mut scenes: Vec<Value> = Vec::new();
    // The scenes' frame, announced on subscription: before any answer, so the 3D panel knows `bat` at once.
    let mut frames: Vec<(usize, Value)> = Vec::new();
    let mut first_answer = None;
    for (n, line) in latched.into_iter().chain(out.lines().map(Result::unwrap)).enumerate() {
        let v: Value = serde_json::from_str(&line).unwrap_or_else(|e| panic!("{e}: {line}"));
        if v["topic"] == "/exit_velocity" && first_answer.is_none() {
            first_answer = Some(n);
        }
        match v["topic"].as_str() {
            Some("/bat_frame") => {
                assert_eq!(v["type"], "foxglove.FrameTransform", "{line}");
                frames.push((n, v.clone()));
            }
            Some("/exit_velocity") => live.push(v["message"].clone()),
            Some("/modal_energies") => {
                assert!(v["message"]["energy"].as_array().is_some_and(|e| !e.is_empty()), "{line}");
                energies += 1;
            }
            Some("/sweet_spot") => sweet_spots += 1,
            Some("/swing_scene") => {
                // The frame again, at the scene's own log time, sent just before it: a 3D panel that cleared
                // its transforms when time jumped back gets `bat` back with the next scene.
                let log_time = &v["log_time"];
                assert!(
                    frames.iter().any(|(_, f)| f["log_time"] == *log_time),
                    "scene at {log_time} without its frame"
                );
                scenes.push(v["message"].clone());
            }
            _ => panic!("unexpected line {line}"),
        }
    }
    check_scenes(&scenes, &live);
    assert_eq!(frames.len(), 1 + scenes.len(), "the latched frame transform, then one before each scene");
    let (at, frame) = &frames[0];
    assert!(first_answer.is_some_and(|first| *at < first), "the frame came after the answers: {frames:?}");
    // Latched at the latest log time sent (the default bat's SweetSpot's), not at 0: a client's clock that
    // jumps back to 1970 makes a 3D panel clear its transforms.
    let since_epoch = frame["log_time"].as_str().and_then(|t| t.parse::<u64>().ok()).unwrap_or(0);
    assert!(since_epoch > 1_600_000_000_000_000_000, "the latched frame's log time: {}", frame["log_time"]);
    let frame = &frame["message"];
    assert_eq!((frame["parent_frame_id"].as_str(), frame["child_frame_id"].as_str()), (Some("world"), Some("bat")));
    let at_origin =
        |object: &Value, fields: &[(&str, f64)]| fields.iter().all(|(k, v)| object[*k].as_f64() == Some(*v));
    assert!(at_origin(&frame["rotation"], &[("x", 0.0), ("y", 0.0), ("z", 0.0), ("w", 1.0)]), "{frame}");
    assert!(at_origin(&frame["translation"], &[("x", 0.0), ("y", 0.0), ("z", 0.0)]), "{frame}");
    assert!(reader.wait().unwrap().success(), "the client did not get {LIVE} ExitVelocity");
    assert!(sweet_spots >= 1, "the latched SweetSpot did not reach a client that connected after it");
    assert!(energies >= 1, "no ModalEnergies decoded");

    // 2. A client that subscribes and stops reading; the node answers every swing, and the same swings
    //    (same kinematics as 1..=STALLED mod 20 / 7) get the same answers as before.
    let (mut stalled, mut stalled_out) = client(&[&url, "stall", "/exit_velocity", "/modal_energies", "/swing"]);
    wait_subscribed(&mut stalled_out);
    for id in LIVE + 1..=LIVE + STALLED {
        swing_pub.publish(swing(id)).unwrap();
    }
    let while_stalled = peer.collect(&answers, STALLED as usize, WAIT);
    assert_eq!(
        while_stalled.iter().map(|ev| ev.swing_id).collect::<Vec<_>>(),
        (LIVE + 1..=LIVE + STALLED).collect::<Vec<_>>(),
        "a swing was lost while a client stalled"
    );
    for ev in &while_stalled {
        // Swing ids 140 apart have the same kinematics (140 = lcm(20, 7)).
        let twin = over_dds.iter().find(|a| (ev.swing_id - a.swing_id) % 140 == 0).expect("a twin swing");
        assert_eq!(ev.exit_speed.to_bits(), twin.exit_speed.to_bits(), "swing {} vs {}", ev.swing_id, twin.swing_id);
        assert_eq!(ev.status, ExitVelocity::STATUS_OK);
    }
    let _ = stalled.kill();
    let _ = stalled.wait();

    // 3. /diagnostics is served too (the node's counters, every diagnostics_period = 1 s).
    let (mut watcher, watched) = client(&[&url, "1", "/diagnostics"]);
    let line = watched
        .lines()
        .map(Result::unwrap)
        .find(|l| l.contains("\"topic\":\"/diagnostics\""))
        .expect("a diagnostics line");
    assert!(watcher.wait().unwrap().success());
    let v: Value = serde_json::from_str(&line).unwrap();
    let statuses = v["message"]["status"].as_array().unwrap_or_else(|| panic!("no statuses: {line}"));
    let values: Vec<&Value> = statuses.iter().filter_map(|s| s["values"].as_array()).flatten().collect();
    let value = |key: &str| values.iter().find(|kv| kv["key"] == key).and_then(|kv| kv["value"].as_str());
    assert!(value("swings_processed").is_some(), "{line}");
    // The client reading this line is connected and subscribed, so the server counts at least it.
    let at_least_one = |key: &str| value(key).and_then(|v| v.parse::<u64>().ok()).is_some_and(|n| n >= 1);
    assert!(at_least_one("foxglove_clients") && at_least_one("foxglove_subscriptions"), "{line}");
    assert!(at_least_one("foxglove_messages_served"), "{line}");

    // 4. /rosout: the node's log lines as rcl_interfaces/Log; a client connecting now still gets the
    //    startup lines (the latch), and each is a line the node also logged on stderr.
    let (mut logs, logged) = client(&[&url, "1", "/rosout"]);
    let lines: Vec<Value> = logged
        .lines()
        .map(|l| serde_json::from_str::<Value>(&l.unwrap()).unwrap())
        .filter(|v| v["topic"] == "/rosout")
        .collect();
    assert!(logs.wait().unwrap().success(), "no /rosout line");

    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
    for line in &lines {
        let m = &line["message"];
        assert_eq!(line["type"], "rcl_interfaces/msg/Log", "{line}");
        assert_eq!(m["level"], 20, "an INFO line: {line}");
        assert_eq!(m["name"], "sweetspot", "{line}");
        let text = m["msg"].as_str().unwrap_or_default();
        assert!(!text.is_empty() && log.contains(text), "/rosout line not in the node's log: {line}");
    }
    let mut recorded: Vec<ExitVelocity> = Vec::new();
    sweetspot::bag::reader::read_bag(&bag, |m| {
        if m.channel.topic.name == "/exit_velocity" {
            recorded.push(sweetspot::msgs::decode_cdr(m.data).unwrap());
        }
    })
    .expect("read the bag");
    assert_eq!(recorded.len() as u64, LIVE + STALLED, "every swing recorded");
    assert_eq!(live.len(), LIVE as usize);
    for (decoded, bagged) in live.iter().zip(&recorded) {
        let bagged = serde_json::to_value(bagged).unwrap();
        assert!(same(decoded, &bagged), "live {decoded}\n bag {bagged}");
    }
    println!(
        "{LIVE} ExitVelocity decoded live = bag; {energies} ModalEnergies; {STALLED} answered with a client stalled"
    );
}
