//! Foxglove clients that never read do not cost the server memory without bound (issue: 300 such clients held
//! 1.2 GB). A live server in this process (127.0.0.1, any free port) serves one topic to 20 WebSocket clients
//! (tungstenite) that subscribe and then stop reading; at least 8,000 messages of 4 KiB each are sent (32 MiB
//! per client, 640 MiB in all), more while any client is still connected. Measured: this process's resident
//! memory before and after, and the clients still connected. Before the fix each client kept up to 4,096
//! queued messages (16 MiB: ~320 MiB for 20) and stayed connected; now each is disconnected as too slow, the
//! total queued is bounded by the server's backlog (16 MiB here), and what they had queued is freed.

mod support;

use std::io::Write;
use std::net::TcpStream;
use std::time::{Duration, Instant};

use sweetspot::foxglove::{Bind, Limits, LiveServer};
use tokio_tungstenite::tungstenite::{self, Message};

const CLIENTS: usize = 20;
const MESSAGES: usize = 8_000;
/// Most messages sent waiting for the last client to go: ten times a client's queue of 4,096.
const MAX_MESSAGES: usize = 40_960;
const SIZE: usize = 4096;

fn rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let kb: f64 = status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())
        .unwrap();
    kb / 1024.0
}

/// Connects, subscribes to the one advertised channel, and returns the socket without reading further.
fn stalled_client(port: u16) -> tungstenite::WebSocket<TcpStream> {
    let stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut request =
        tungstenite::client::IntoClientRequest::into_client_request(format!("ws://127.0.0.1:{port}")).unwrap();
    request.headers_mut().insert("sec-websocket-protocol", "foxglove.sdk.v1".parse().unwrap());
    let (mut ws, _) = tungstenite::client(request, stream).unwrap();
    loop {
        if let Message::Text(text) = ws.read().unwrap() {
            let v: serde_json::Value = serde_json::from_str(&text).unwrap();
            if v["op"] == "advertise" {
                let id = v["channels"][0]["id"].clone();
                let subscribe = serde_json::json!({"op": "subscribe", "subscriptions": [{"id": 1, "channelId": id}]});
                ws.send(Message::Text(subscribe.to_string().into())).unwrap();
                ws.get_mut().flush().unwrap();
                return ws;
            }
        }
    }
}

#[test]
fn clients_that_never_read_are_disconnected_and_their_memory_freed() {
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
    let topic = support::bag::string_topic("/big", support::bag::RELIABLE);
    let bind = Bind { host: "127.0.0.1".into(), port: 0 };
    let limits = Limits { total_backlog_bytes: 16 << 20, ..Limits::default() };
    let server = runtime.block_on(LiveServer::start_with("slow", &bind, &[topic], None, limits)).unwrap();
    let port = server.port();
    let clients: Vec<_> = (0..CLIENTS).map(|_| stalled_client(port)).collect();
    let deadline = Instant::now() + Duration::from_secs(10);
    while server.counters().subscriptions < CLIENTS as u64 {
        assert!(Instant::now() < deadline, "subscriptions: {:?}", server.counters());
        std::thread::sleep(Duration::from_millis(20));
    }
    let before = rss_mib();
    let payload = support::bag::cdr_string(&"x".repeat(SIZE));
    // A client that never reads is dropped once it holds its share of the total or its queue is full, so
    // the last ones may outlast a short burst while holding less: the messages keep coming, as a node's do,
    // until nobody is left or far more than any queue holds (4,096 messages) has gone out.
    let mut sent = 0;
    while sent < MESSAGES || (server.counters().clients > 0 && sent < MAX_MESSAGES) {
        for _ in 0..1000 {
            server.send(0, &payload, sent as u64);
            sent += 1;
        }
        // The send loops drain into the sockets' kernel buffers, and departures are counted, between batches.
        std::thread::sleep(Duration::from_millis(50));
    }
    std::thread::sleep(Duration::from_secs(2));
    let after = rss_mib();
    let still = server.counters().clients;
    eprintln!(
        "{CLIENTS} stalled clients, {sent} x {SIZE} B: RSS {before:.0} MiB before, {after:.0} MiB after \
         ({:+.0} MiB), {still} clients still connected",
        after - before
    );
    assert_eq!(still, 0, "clients that never read are still connected");
    assert!(after - before < 64.0, "RSS grew by {:.0} MiB (before {before:.0}, after {after:.0})", after - before);
    drop(clients);
    server.stop();
}
