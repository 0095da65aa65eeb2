//! `@foxglove/ws-protocol`'s FoxgloveClient used exactly as its README shows (`tests/js/
//! foxglove_readme_client.cjs`: the classic subprotocol `foxglove.websocket.v1` only, no playback controls)
//! against `sweetspot bag play BAG --foxglove 0 --no-dds` (no DDS participant):
//! - the handshake succeeds under the classic name (HTTP 400 before);
//! - with nobody pressing play, the bag is played by itself after the first subscription: the client
//!   receives every message of the golden bag exactly once (0 before);
//! - the end of playback sends it no playbackState (binary opcode 5, which this client rejects as
//!   "Unrecognized server opcode: 5"): it reports no error at all;
//! - its Close is answered: it sees close code 1000, not 1006.

mod support;

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};

use serde_json::Value;
use support::js_dir;

#[test]
fn the_readme_client_gets_the_bag_played_without_errors_and_a_clean_close() {
    let bag = Path::new(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden");
    let mut recorded: BTreeMap<String, usize> = BTreeMap::new();
    let (mut first, mut last) = (u64::MAX, 0);
    sweetspot::bag::reader::read_bag(&bag, |m| {
        *recorded.entry(m.channel.topic.name.clone()).or_default() += 1;
        first = first.min(m.log_time_ns);
        last = last.max(m.log_time_ns);
    })
    .unwrap();
    let span = (last - first) as f64 * 1e-9;
    let rate = (span / 2.0).max(1.0);

    let (mut player, url) = support::bag::play_to_foxglove(&bag, rate);

    assert!(js_dir().join("node_modules/@foxglove/ws-protocol").is_dir(), "run `bash scripts/test` (npm ci)");
    // 2 s until it plays by itself, the bag's span at `rate` (≤ 2 s), and slack.
    let seconds = 2.0 + span / rate + 2.0;
    let out = Command::new("node")
        .arg(js_dir().join("foxglove_readme_client.cjs"))
        .arg(&url)
        .arg(format!("{seconds:.1}"))
        .stderr(Stdio::inherit())
        .output()
        .expect("node (Node.js)");
    let _ = player.kill();
    let _ = player.wait();
    let events: Vec<Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect();
    let text = String::from_utf8_lossy(&out.stdout);

    assert_eq!(events.first().map(|e| e["open"].clone()), Some(Value::from("foxglove.websocket.v1")), "{text}");
    let errors: Vec<&Value> = events.iter().filter(|e| e.get("error").is_some()).collect();
    assert!(errors.is_empty(), "client errors: {errors:?}");
    let mut received: BTreeMap<String, usize> = BTreeMap::new();
    for e in events.iter().filter_map(|e| e.get("message")) {
        *received.entry(e.as_str().unwrap().to_string()).or_default() += 1;
    }
    assert_eq!(received, recorded, "messages per topic");
    // FoxgloveClient's close() sends a Close frame without a status code; the server's answer echoes none, so
    // the client reports 1005 ("no status received": the closing handshake completed). 1006 would mean the
    // connection just ended with no Close frame from the server.
    assert_eq!(events.last().map(|e| e["close"].clone()), Some(Value::from(1005)), "{text}");
}
