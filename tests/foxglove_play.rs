//! `sweetspot bag play BAG --foxglove PORT --no-dds` serves a bag over the Foxglove WebSocket protocol with
//! playback controls. Checked with Foxglove's own client and decoder from npm (`tests/js/`, installed by
//! scripts/test), which sends the protocol's playbackControlRequest and reads its playbackState:
//! - nothing is sent before the client presses play (`--no-dds` starts paused);
//! - after a seek to the middle of the golden bag, the client receives every message logged from there on,
//!   in log-time order, each decoded by Foxglove's decoder from the advertised ros2msg schema equal to the
//!   bag's message; before them only the latched topics' last messages before the seek point;
//! - at speed 2 the rest of the bag takes at least half its recorded span, and playback then reports "ended".
//!
//! - without `--no-dds` the inputs still go out over DDS (to a subscriber in scripts/test's private network
//!   namespace) while the same bag is served to Foxglove.

mod support;

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{ChildStderr, Command, Stdio};
use std::time::{Duration, Instant};
use support::same_json as same;

use serde_json::Value;
use support::js_dir;
use sweetspot::msgs::decode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};

const SPEED: f64 = 2.0;

/// A bag message as JSON, decoded by sweetspot's own types.
fn as_json(type_name: &str, cdr: &[u8]) -> Value {
    fn j<T: serde::de::DeserializeOwned + serde::Serialize>(cdr: &[u8]) -> Value {
        serde_json::to_value(decode_cdr::<T>(cdr).expect("decodes")).unwrap()
    }
    match type_name {
        "sweetspot_msgs/msg/BatParams" => j::<BatParams>(cdr),
        "sweetspot_msgs/msg/BallParams" => j::<BallParams>(cdr),
        "sweetspot_msgs/msg/Swing" => j::<Swing>(cdr),
        "sweetspot_msgs/msg/ExitVelocity" => j::<ExitVelocity>(cdr),
        "sweetspot_msgs/msg/ModalEnergies" => j::<ModalEnergies>(cdr),
        "sweetspot_msgs/msg/SweetSpot" => j::<SweetSpot>(cdr),
        other => panic!("unexpected type {other}"),
    }
}

/// `json` without the fields its recorded schema does not name: fields appended to a message after the bag
/// was recorded are not in the bag's schema, so Foxglove's decoder has none, while sweetspot's gives them
/// their absent value.
fn recorded_fields(mut json: Value, schema: &str) -> Value {
    let own = schema.split("\n====").next().unwrap_or_default();
    let named =
        |key: &str| own.lines().any(|l| !l.trim_start().starts_with('#') && l.split_whitespace().nth(1) == Some(key));
    if let Value::Object(fields) = &mut json {
        fields.retain(|k, _| named(k));
    }
    json
}

/// Reads `bag play`'s stderr until it names the server's URL (`ws://ADDR:PORT`).
fn served_url(stderr: &mut BufReader<ChildStderr>) -> String {
    let mut line = String::new();
    loop {
        line.clear();
        assert!(stderr.read_line(&mut line).unwrap() > 0, "bag play exited before serving");
        if let Some(rest) = line.strip_prefix("Foxglove WebSocket server on ") {
            return rest.split(':').take(3).collect::<Vec<_>>().join(":");
        }
    }
}

struct Recorded {
    topic: String,
    log_time: u64,
    latched: bool,
    json: Value,
}

#[test]
fn a_foxglove_client_seeks_into_a_played_bag_and_gets_the_rest_in_log_time_order() {
    let bag = Path::new(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden");
    let mut recorded: Vec<Recorded> = Vec::new();
    sweetspot::bag::reader::read_bag(&bag, |m| {
        recorded.push(Recorded {
            topic: m.channel.topic.name.clone(),
            log_time: m.log_time_ns,
            latched: m.channel.topic.qos.transient_local,
            json: recorded_fields(as_json(&m.channel.topic.type_name, m.data), &m.channel.topic.schema_text),
        })
    })
    .unwrap();
    let mut times: Vec<u64> = recorded.iter().map(|r| r.log_time).collect();
    times.sort_unstable();
    let seek = times[times.len() / 2];
    let end = *times.last().unwrap();
    let mut topics: Vec<&str> = recorded.iter().map(|r| r.topic.as_str()).collect();
    topics.sort_unstable();
    topics.dedup();

    let mut player = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["bag", "play"])
        .arg(&bag)
        .args(["--foxglove", "0", "--no-dds"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = BufReader::new(player.stderr.take().unwrap());
    let url = served_url(&mut stderr);
    assert!(url.starts_with("ws://127.0.0.1:"), "bound beyond loopback: {url}");

    assert!(js_dir().join("node_modules/@foxglove/ws-protocol").is_dir(), "run `bash scripts/test` (npm ci)");
    let mode = format!("play:{seek}:{SPEED}");
    let mut args = vec![js_dir().join("foxglove_client.mjs").display().to_string(), url.clone(), mode];
    args.extend(topics.iter().map(|t| t.to_string()));
    let mut client = Command::new("node").args(&args).stdout(Stdio::piped()).spawn().expect("node (Node.js)");
    let out = BufReader::new(client.stdout.take().unwrap());
    // Play is pressed when the client sends its request: the server may send the latched messages of the seek
    // before its answer (the playing state) reaches the client, so messages are checked against the request.
    let (mut subscribed, mut requested_at, mut playing_at, mut ended_at) = (false, None, None, None);
    let mut received: Vec<(String, u64, Value)> = Vec::new();
    for line in out.lines() {
        let line = line.unwrap();
        let v: Value = serde_json::from_str(&line).unwrap_or_else(|e| panic!("{e}: {line}"));
        if v.get("subscribed").is_some() {
            subscribed = true;
        } else if v.get("requested").is_some() {
            requested_at = Some(Instant::now());
        } else if let Some(state) = v.get("playback") {
            match state["status"].as_str() {
                Some("playing") => {
                    assert_eq!(state["current_time"], seek.to_string(), "{line}");
                    assert_eq!((state["did_seek"].as_bool(), state["speed"].as_f64()), (Some(true), Some(SPEED)));
                    assert_eq!(state["request_id"], "seek-1");
                    playing_at.get_or_insert(Instant::now());
                }
                Some("ended") => {
                    assert_eq!(state["current_time"], end.to_string(), "{line}");
                    ended_at = Some(Instant::now());
                }
                _ => panic!("unexpected playback state {line}"),
            }
        } else {
            assert!(subscribed && requested_at.is_some(), "a message before play was pressed: {line}");
            let log_time: u64 = v["log_time"].as_str().unwrap().parse().unwrap();
            received.push((v["topic"].as_str().unwrap().to_string(), log_time, v["message"].clone()));
        }
    }
    assert!(client.wait().unwrap().success(), "the client did not see playback end");
    assert!(playing_at.is_some(), "the server never said it was playing");
    let (requested_at, ended_at) = (requested_at.unwrap(), ended_at.unwrap());

    // Before the seek point: only each latched topic's last message before it.
    let head = received.iter().take_while(|(_, t, _)| *t < seek).count();
    for (topic, log_time, message) in &received[..head] {
        let last = recorded
            .iter()
            .filter(|r| r.topic == *topic && r.log_time < seek)
            .max_by_key(|r| r.log_time)
            .unwrap_or_else(|| panic!("{topic} at {log_time}: nothing recorded there before the seek"));
        assert!(last.latched, "{topic} is not latched but was re-sent on the seek");
        assert!(
            last.log_time == *log_time && same(message, &last.json),
            "{topic}: not the last before the seek: {log_time} {message}\n vs {} {}",
            last.log_time,
            last.json
        );
    }
    let latched_topics = recorded
        .iter()
        .filter(|r| r.latched && r.log_time < seek)
        .map(|r| &r.topic)
        .collect::<std::collections::BTreeSet<_>>();
    assert_eq!(head, latched_topics.len(), "one message per latched topic recorded before the seek");

    // From the seek point: every message, in log-time order, each equal to the bag's.
    let rest = &received[head..];
    assert!(rest.windows(2).all(|w| w[0].1 <= w[1].1), "not in log-time order");
    let expected: Vec<&Recorded> = recorded.iter().filter(|r| r.log_time >= seek).collect();
    assert_eq!(rest.len(), expected.len(), "messages from the seek point on");
    for (topic, log_time, message) in rest {
        let twin = expected
            .iter()
            .find(|r| r.topic == *topic && r.log_time == *log_time && same(message, &r.json))
            .unwrap_or_else(|| panic!("{topic} at {log_time}: {message} is not in the bag"));
        assert_eq!(twin.log_time, *log_time);
    }

    // At the recorded pace scaled by SPEED (never faster; the bound is loose only upwards).
    let span = Duration::from_nanos(end - seek).div_f64(SPEED);
    let took = ended_at - requested_at;
    assert!(
        took >= span.mul_f64(0.9),
        "played {:?} of bag time in {took:?} at speed {SPEED}",
        Duration::from_nanos(end - seek)
    );

    let pid = player.id().to_string();
    assert!(Command::new("kill").args(["-INT", &pid]).status().unwrap().success());
    let status = player.wait().unwrap();
    let mut tail = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut tail).unwrap();
    assert!(status.success(), "bag play: {status}\n{tail}");
    assert!(tail.contains("served "), "{tail}");
    println!("{} messages from the seek point, {head} latched re-sent, {took:?} for {span:?}", rest.len());
}

#[test]
fn with_dds_the_inputs_go_out_while_the_bag_is_served() {
    use support::node::{keep_all, Peer};
    let domain = support::node::domain(92);
    let bag = Path::new(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden");
    let mut peer = Peer::new(domain, "foxglove_play_listener");
    let swings = peer.subscription::<Swing>("/golden/swing", keep_all(sweetspot::ros::swing_qos()));
    let mut c = support::sweetspot(domain, &["bag", "play", "-q", "--wait-subscribers", "1", "--timeout", "30"]);
    c.arg(&bag).args(["--topics", "/golden/swing", "--foxglove", "0"]);
    let mut player = c.stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    let mut stderr = BufReader::new(player.stderr.take().unwrap());
    let url = served_url(&mut stderr);
    let over_dds = peer.collect(&swings, 10, Duration::from_secs(30));
    assert_eq!(over_dds.iter().map(|s| s.swing_id).collect::<Vec<_>>(), (1..=10).collect::<Vec<u64>>());

    // Foxglove's timeline is its own: from the start, at speed 8, the client gets the same ten swings.
    let mut first = u64::MAX;
    sweetspot::bag::reader::read_bag(&bag, |m| first = first.min(m.log_time_ns)).unwrap();
    let client = Command::new("node")
        .arg(js_dir().join("foxglove_client.mjs"))
        .args([url.as_str(), &format!("play:{first}:8"), "/golden/swing"])
        .output()
        .expect("node (Node.js)");
    assert!(client.status.success(), "the client did not see playback end");
    let ids: Vec<u64> = String::from_utf8_lossy(&client.stdout)
        .lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(|v| v["topic"] == "/golden/swing")
        .map(|v| v["message"]["swing_id"].as_u64().unwrap())
        .collect();
    assert_eq!(ids, (1..=10).collect::<Vec<u64>>());

    let pid = player.id().to_string();
    assert!(Command::new("kill").args(["-INT", &pid]).status().unwrap().success());
    let status = player.wait().unwrap();
    let mut tail = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut tail).unwrap();
    assert!(status.success() && tail.contains("published 10 messages"), "bag play: {status}\n{tail}");
}
