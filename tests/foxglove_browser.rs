//! A real browser as Foxglove client: Debian's headless Chromium (driven by puppeteer-core) opens a page
//! served on loopback whose script runs Foxglove's own client, `@foxglove/ws-protocol`'s FoxgloveClient, on the
//! browser's WebSocket, offering only the classic subprotocol `foxglove.websocket.v1` and never asking for
//! playback control, and decodes every message with Foxglove's ROS 2 decoder (`tests/js/foxglove_browser.mjs`,
//! `tests/js/browser/page.mjs`; scripts/test installs Chromium and the npm packages). Inside scripts/test's
//! private network namespace:
//! - against `sweetspot node --foxglove`: the handshake succeeds under the classic name; the node's channels are
//!   advertised; the latched `/bat_frame` FrameTransform (world → bat, identity) arrives on subscription, before
//!   any answer; swings published over DDS are answered on `/exit_velocity` and the browser decodes each answer
//!   equal, field for field and in order, to the one a DDS subscriber receives;
//! - against `sweetspot bag play BAG --foxglove 0 --no-dds`: the bag is played to this client, which cannot
//!   control playback: it receives every message of the golden bag exactly once, its answers equal to the
//!   bag's;
//! - in both, the client reports no error (a binary opcode 5, PlaybackState, sent to it would be one:
//!   "Unrecognized server opcode: 5"), and closing is clean: the browser's CloseEvent has `wasClean` and code
//!   1005 (its Close carries no code, the server's answer echoes none), not 1006.

mod support;

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, ChildStdout};
use std::time::Duration;
use support::same_json as same;

use serde_json::Value;
use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use support::require_isolated_network;
use sweetspot::msgs::decode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};

const WAIT: Duration = Duration::from_secs(60);
/// Swings answered while the browser reads.
const SWINGS: u64 = 20;

/// The browser client (tests/js/foxglove_browser.mjs) with `args`; stdout piped.
fn browser(args: &[&str]) -> (Child, BufReader<ChildStdout>) {
    // The browser has its own background networking; it is started only where nothing leaves the machine.
    require_isolated_network();
    // A bound, not a measurement: a page still waiting then closes and the test reports what it missed.
    support::node_client("foxglove_browser.mjs", "puppeteer-core", args, &[("DEADLINE", "60")])
}

/// One event line of the browser client.
fn event(line: &str) -> Value {
    serde_json::from_str(line).unwrap_or_else(|e| panic!("{e}: {line}"))
}

fn text(events: &[Value]) -> String {
    events.iter().map(Value::to_string).collect::<Vec<_>>().join("\n")
}

/// Checks how every run starts: in Chromium, connected under the classic subprotocol.
fn check_open(events: &[Value]) {
    assert!(
        events.first().is_some_and(|e| e["browser"].as_str().is_some_and(|v| v.contains("Chrom"))),
        "not Chromium: {}",
        text(events)
    );
    let open: Vec<&Value> = events.iter().filter_map(|e| e.get("open")).collect();
    assert_eq!(open, [&Value::from("foxglove.websocket.v1")], "{}", text(events));
}

/// Checks how every run ends: no client error, the page closed the connection itself (not at the deadline),
/// and the close the browser reports, the last event, is clean.
fn check_end(events: &[Value]) {
    let errors: Vec<&Value> = events.iter().filter(|e| e.get("error").is_some()).collect();
    assert!(errors.is_empty(), "client errors: {errors:?}");
    assert!(events.iter().all(|e| e.get("deadline").is_none()), "the page never got what it waited for");
    let close = events.last().filter(|e| e.get("close").is_some());
    let close = close.unwrap_or_else(|| panic!("no close: {}", text(events)));
    assert_eq!((&close["close"], &close["clean"]), (&Value::from(1005), &Value::from(true)), "{}", text(events));
}

#[test]
fn chromium_with_foxglove_client_watches_the_live_node() {
    let domain = domain(99);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "browser_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--foxglove", "0", "--no-record"]);
    node.wait_for_log("Foxglove WebSocket server on ws://127.0.0.1:", WAIT);
    let log = node.log();
    let url = log
        .lines()
        .find_map(|l| l.split("Foxglove WebSocket server on ").nth(1))
        .map(|rest| rest.split_whitespace().next().unwrap_or_default().to_string())
        .unwrap();
    peer.wait_for_reader(&swing_pub);

    let count = SWINGS.to_string();
    let (mut client, out) = browser(&[&url, &count, "/exit_velocity", "/bat_frame"]);
    let mut events = Vec::new();
    for line in out.lines() {
        let e = event(&line.unwrap());
        // The page subscribes to /exit_velocity, then to /bat_frame; the server handles a client's
        // subscriptions in order, so the latched frame's arrival means answers now reach the browser.
        if e["topic"] == "/bat_frame" && events.iter().all(|e: &Value| e["topic"] != "/bat_frame") {
            for id in 1..=SWINGS {
                let swing = Swing {
                    swing_id: id,
                    ball_speed: 40.0,
                    bat_cm_speed: 20.0,
                    bat_angular_speed: 50.0,
                    impact_z: 0.45 + 0.01 * id as f64,
                    measured_exit_speed: if id % 2 == 0 { 30.0 + id as f64 } else { f64::NAN },
                    ..Swing::default()
                };
                swing_pub.publish(swing).unwrap();
            }
        }
        events.push(e);
    }
    assert!(client.wait().unwrap().success(), "the browser client failed: {events:?}");
    check_open(&events);

    let advertised: Vec<&str> =
        events.iter().filter_map(|e| e["advertised"].as_array()).flatten().filter_map(Value::as_str).collect();
    for topic in [
        "/swing",
        "/bat/params",
        "/ball/params",
        "/exit_velocity",
        "/modal_energies",
        "/sweet_spot",
        "/swing_scene",
        "/bat_frame",
        "/diagnostics",
        "/rosout",
    ] {
        assert!(advertised.contains(&topic), "{topic} not advertised: {advertised:?}");
    }

    let over_dds = peer.collect(&answers, SWINGS as usize, WAIT);
    let decoded: Vec<(usize, &Value)> = events
        .iter()
        .enumerate()
        .filter(|(_, e)| e["topic"] == "/exit_velocity")
        .map(|(n, e)| (n, &e["message"]))
        .collect();
    assert_eq!(decoded.len(), over_dds.len(), "answers decoded by the browser vs received over DDS");
    for ((_, browser), dds) in decoded.iter().zip(&over_dds) {
        let dds = serde_json::to_value(dds).unwrap();
        assert!(same(browser, &dds), "the browser decoded\n{browser}\nDDS delivered\n{dds}");
    }
    assert!(decoded.iter().all(|(_, m)| m["status"] == ExitVelocity::STATUS_OK), "{decoded:?}");

    let frames: Vec<(usize, &Value)> = events.iter().enumerate().filter(|(_, e)| e["topic"] == "/bat_frame").collect();
    assert_eq!(frames.len(), 1, "one latched frame transform: {frames:?}");
    let (at, frame) = frames[0];
    assert_eq!(frame["type"], "foxglove.FrameTransform");
    assert!(at < decoded[0].0, "the frame came after the first answer");
    let frame = &frame["message"];
    assert_eq!((frame["parent_frame_id"].as_str(), frame["child_frame_id"].as_str()), (Some("world"), Some("bat")));
    let is = |object: &Value, fields: &[(&str, f64)]| fields.iter().all(|(k, v)| object[*k].as_f64() == Some(*v));
    assert!(is(&frame["rotation"], &[("x", 0.0), ("y", 0.0), ("z", 0.0), ("w", 1.0)]), "{frame}");
    assert!(is(&frame["translation"], &[("x", 0.0), ("y", 0.0), ("z", 0.0)]), "{frame}");
    check_end(&events);
}

#[test]
fn chromium_with_foxglove_client_gets_a_bag_played_without_playback_control() {
    let bag = Path::new(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden");
    let mut recorded: BTreeMap<String, usize> = BTreeMap::new();
    let mut answers: Vec<ExitVelocity> = Vec::new();
    let (mut first, mut last) = (u64::MAX, 0);
    sweetspot::bag::reader::read_bag(&bag, |m| {
        *recorded.entry(m.channel.topic.name.clone()).or_default() += 1;
        if m.channel.topic.type_name == "sweetspot_msgs/msg/ExitVelocity" {
            answers.push(decode_cdr(m.data).expect("the bag's ExitVelocity decodes"));
        }
        first = first.min(m.log_time_ns);
        last = last.max(m.log_time_ns);
    })
    .unwrap();
    let total: usize = recorded.values().sum();
    // Played in about 2 s (it starts 2 s after the first subscription, by itself).
    let rate = ((last - first) as f64 * 1e-9 / 2.0).max(1.0);

    let (mut player, url) = support::bag::play_to_foxglove(&bag, rate);

    // Every channel, closing 1 s after the bag's last message (so a message sent twice would be seen).
    let (mut client, out) = browser(&[&url, &total.to_string()]);
    let events: Vec<Value> = out.lines().map(|l| event(&l.unwrap())).collect();
    let _ = player.kill();
    let _ = player.wait();
    assert!(client.wait().unwrap().success(), "the browser client failed: {events:?}");
    check_open(&events);

    let mut received: BTreeMap<String, usize> = BTreeMap::new();
    for e in events.iter().filter_map(|e| e["topic"].as_str()) {
        *received.entry(e.to_string()).or_default() += 1;
    }
    assert_eq!(received, recorded, "messages per topic, received by the browser vs in the bag");
    let decoded: Vec<&Value> =
        events.iter().filter(|e| e["type"] == "sweetspot_msgs/msg/ExitVelocity").map(|e| &e["message"]).collect();
    for (browser, bag) in decoded.iter().zip(&answers) {
        assert_eq!(browser["swing_id"].as_u64(), Some(bag.swing_id), "{browser}");
        assert_eq!(browser["exit_speed"].as_f64(), Some(bag.exit_speed).filter(|v| !v.is_nan()), "{browser}");
    }
    check_end(&events);
}
