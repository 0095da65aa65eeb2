//! What Foxglove clients send cannot take the node's memory or fill its log. `sweetspot node --foxglove 0`
//! (a DDS participant: inside the private network namespace of scripts/test), reached on 127.0.0.1 by
//! WebSocket clients (tungstenite, not the server's code) that write raw frames:
//! - 8 clients each sending 4 non-final fragments of 15 MiB (a message never finished): each is disconnected
//!   at its first frame header, and the node's resident memory (/proc/PID/status) grows by far less than the
//!   480 MiB they sent (before the bound, 64 MiB a message, the node held them all: +600 MB);
//! - the bound itself: a message of exactly `MAX_INCOMING_MESSAGE_BYTES` is read and answered, one byte more
//!   closes the connection with code 1009 (message too big);
//! - a subscribe naming 10,000 unknown channels is answered with one status and logged in one line (before:
//!   10,000 ERROR lines), and a client repeating it is logged at most once a second, the lines left out
//!   counted in the next.

mod support;

use std::io::Write;
use std::net::TcpStream;
use std::sync::Arc;
use std::time::{Duration, Instant};

use support::foxglove::{closed_within, frame_header, rss_mib, BINARY, CONTINUATION, TEXT};
use support::node::{domain, require_isolated_network, NodeProcess};
use sweetspot::foxglove::MAX_INCOMING_MESSAGE_BYTES;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::protocol::frame::coding::CloseCode;
use tokio_tungstenite::tungstenite::{self, Message};

const WAIT: Duration = Duration::from_secs(60);

/// The node serving Foxglove on a free port, and that port.
fn node(domain: u16, dir: &std::path::Path) -> (NodeProcess, u16) {
    require_isolated_network();
    let node = NodeProcess::spawn(domain, dir, &["--no-record", "--foxglove", "0"]);
    let needle = "Foxglove WebSocket server on ws://127.0.0.1:";
    node.wait_for_log(needle, WAIT);
    let log = node.log();
    let port = log
        .split(needle)
        .nth(1)
        .and_then(|rest| rest.chars().take_while(char::is_ascii_digit).collect::<String>().parse::<u16>().ok());
    (node, port.expect("the server's port in the log"))
}

fn lines_with(node: &NodeProcess, needle: &str) -> Vec<String> {
    node.log().lines().filter(|l| l.contains(needle)).map(String::from).collect()
}

type Ws = tungstenite::WebSocket<TcpStream>;

/// A handshake offering `foxglove.sdk.v1`, the serverInfo read.
fn connect(port: u16) -> Ws {
    let stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    stream.set_write_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut request = format!("ws://127.0.0.1:{port}").into_client_request().unwrap();
    request.headers_mut().insert("sec-websocket-protocol", "foxglove.sdk.v1".parse().unwrap());
    let (mut ws, _) = tungstenite::client(request, stream).unwrap();
    loop {
        if let Message::Text(text) = ws.read().expect("serverInfo") {
            let info: serde_json::Value = serde_json::from_str(&text).unwrap();
            assert_eq!(info["op"], "serverInfo");
            return ws;
        }
    }
}

/// The messages the server sends until `done` says so or `limit` passes; JSON texts only.
fn read_json(
    ws: &mut Ws,
    limit: Duration,
    mut done: impl FnMut(&[serde_json::Value]) -> bool,
) -> Vec<serde_json::Value> {
    let end = Instant::now() + limit;
    let mut got = Vec::new();
    while !done(&got) {
        let left = end.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break;
        }
        ws.get_mut().set_read_timeout(Some(left)).unwrap();
        match ws.read() {
            Ok(Message::Text(text)) => got.push(serde_json::from_str(&text).unwrap()),
            Ok(_) => {}
            Err(tungstenite::Error::Io(e))
                if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) =>
            {
                break
            }
            Err(e) => panic!("connection lost: {e}"),
        }
    }
    got
}

fn statuses(messages: &[serde_json::Value]) -> usize {
    messages.iter().filter(|m| m["op"] == "status").count()
}

#[test]
fn a_fragment_flood_is_refused_at_the_first_frame_and_the_nodes_memory_stays_bounded() {
    const CLIENTS: usize = 8;
    const FRAGMENTS: usize = 4;
    const FRAGMENT: usize = 15 << 20;
    let dir = tempfile::tempdir().unwrap();
    let (node, port) = node(domain(86), dir.path());
    let before = rss_mib(node.pid());
    let payload = Arc::new(vec![0u8; FRAGMENT]);
    let clients: Vec<_> = (0..CLIENTS)
        .map(|_| {
            let payload = Arc::clone(&payload);
            std::thread::spawn(move || {
                let mut ws = connect(port);
                let stream = ws.get_mut();
                for i in 0..FRAGMENTS {
                    let opcode = if i == 0 { BINARY } else { CONTINUATION };
                    // A refused client finds its connection closed while writing: that is the point.
                    if stream.write_all(&frame_header(opcode, false, FRAGMENT)).is_err()
                        || stream.write_all(&payload).is_err()
                    {
                        break;
                    }
                }
                ws
            })
        })
        .collect();
    let mut clients: Vec<Ws> = clients.into_iter().map(|c| c.join().unwrap()).collect();
    std::thread::sleep(Duration::from_secs(1));
    let after = rss_mib(node.pid());
    let closed =
        clients.iter_mut().map(|ws| closed_within(ws.get_mut(), Duration::from_secs(5))).filter(|&c| c).count();
    eprintln!(
        "{CLIENTS} clients x {FRAGMENTS} x {} MiB non-final fragments: node RSS {before:.0} MiB before, {after:.0} MiB \
         after ({:+.0} MiB), {closed} connections closed",
        FRAGMENT >> 20,
        after - before
    );
    assert!(after - before < 200.0, "node RSS grew by {:.0} MiB", after - before);
    assert_eq!(closed, CLIENTS, "connections left open holding unfinished messages");
    let said = lines_with(&node, &format!("over the bound of {MAX_INCOMING_MESSAGE_BYTES}"));
    assert_eq!(said.len(), CLIENTS, "one line per refused client:\n{}", said.join("\n"));
}

#[test]
fn a_message_of_the_bound_is_read_and_one_byte_more_closes_with_1009() {
    let dir = tempfile::tempdir().unwrap();
    let (_node, port) = node(domain(87), dir.path());

    // Exactly the bound: a subscribe to an unknown channel, padded with JSON whitespace, is answered.
    let mut ws = connect(port);
    let mut text = br#"{"op":"subscribe","subscriptions":[{"id":1,"channelId":999999}]}"#.to_vec();
    text.resize(MAX_INCOMING_MESSAGE_BYTES, b' ');
    let stream = ws.get_mut();
    stream.write_all(&frame_header(TEXT, true, text.len())).unwrap();
    stream.write_all(&text).unwrap();
    let got = read_json(&mut ws, Duration::from_secs(10), |m| statuses(m) > 0);
    let status = got.iter().find(|m| m["op"] == "status").expect("the message of the bound answered");
    assert!(status["message"].as_str().unwrap().contains("999999"), "{status}");

    // One byte more: refused on its header, with a status and a Close frame saying why.
    let mut ws = connect(port);
    ws.get_mut().write_all(&frame_header(TEXT, true, MAX_INCOMING_MESSAGE_BYTES + 1)).unwrap();
    let (mut status, mut code) = (None, None);
    loop {
        match ws.read() {
            Ok(Message::Text(text)) => status = Some(text.to_string()),
            Ok(Message::Close(frame)) => code = frame.map(|f| f.code),
            Ok(_) => {}
            // After the Close frame the connection may end either way.
            Err(_) if code.is_some() => break,
            Err(e) => panic!("no Close frame: {e} (status {status:?}, code {code:?})"),
        }
    }
    assert_eq!(code, Some(CloseCode::Size), "status {status:?}");
    assert!(status.is_some_and(|s| s.contains(&format!("over {MAX_INCOMING_MESSAGE_BYTES} bytes"))));
}

/// A subscribe naming `n` channels the server does not have (ids from 1,000,000 on).
fn unknown_subscribe(n: u32) -> Message {
    let subscriptions: Vec<_> = (0..n).map(|i| serde_json::json!({"id": i, "channelId": 1_000_000 + i})).collect();
    Message::Text(serde_json::json!({"op": "subscribe", "subscriptions": subscriptions}).to_string().into())
}

#[test]
fn a_subscribe_to_ten_thousand_unknown_channels_is_one_status_and_one_rate_limited_line() {
    const IDS: u32 = 10_000;
    const BURST: usize = 20;
    let dir = tempfile::tempdir().unwrap();
    let (node, port) = node(domain(88), dir.path());
    let needle = "attempted to subscribe to unknown channels";
    let mut ws = connect(port);

    ws.send(unknown_subscribe(IDS)).unwrap();
    // Everything the server sends for the message has arrived well within the wait after the first status.
    let got = read_json(&mut ws, Duration::from_secs(10), |m| statuses(m) > 0);
    let got = [got, read_json(&mut ws, Duration::from_millis(500), |_| false)].concat();
    assert_eq!(statuses(&got), 1, "statuses for one message: {got:?}");
    std::thread::sleep(Duration::from_millis(200));
    let lines = lines_with(&node, needle);
    assert_eq!(lines.len(), 1, "log lines for one message:\n{}", lines.join("\n"));
    assert!(lines[0].contains("and 9995 more (10000 in all)"), "{}", lines[0]);

    // A burst, then one more after the interval: every message counted, in a line or among those left out.
    for _ in 0..BURST {
        ws.send(unknown_subscribe(IDS)).unwrap();
    }
    let got = read_json(&mut ws, Duration::from_secs(30), |m| statuses(m) >= BURST);
    assert_eq!(statuses(&got), BURST, "one status per message");
    std::thread::sleep(Duration::from_millis(1100));
    ws.send(unknown_subscribe(IDS)).unwrap();
    read_json(&mut ws, Duration::from_secs(10), |m| statuses(m) > 0);
    std::thread::sleep(Duration::from_millis(200));
    let lines = lines_with(&node, needle);
    let left_out: usize = lines
        .iter()
        .filter_map(|l| l.rsplit(" (").next()?.split(" more such lines").next()?.parse::<usize>().ok())
        .sum();
    assert_eq!(lines.len() + left_out, BURST + 2, "every message counted:\n{}", lines.join("\n"));
    // The burst took well under a second or two, so at most a few of its messages got their own line.
    assert!(lines.len() <= 5, "{} lines for {} messages:\n{}", lines.len(), BURST + 2, lines.join("\n"));
    assert!(lines.last().unwrap().contains("more such lines left out"), "{}", lines.join("\n"));
}
