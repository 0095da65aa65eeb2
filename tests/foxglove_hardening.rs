//! The Foxglove WebSocket server under hostile or careless clients, against a real server: `sweetspot bag
//! play BAG --foxglove 0 --no-dds` (no DDS participant) on 127.0.0.1, reached with plain TCP sockets and a
//! WebSocket client (tungstenite, not the server's code). Every wait is bounded.
//! - 150 connections against a server limited to 48 file descriptors (below the client cap) (EMFILE) leave it accepting: a
//!   WebSocket handshake afterwards gets the serverInfo, and the accept error is logged a bounded number of
//!   times, not per connection;
//! - beyond the client cap (64) further connections are closed at once, the refusal logged once;
//! - a connection that never sends its handshake is closed after the handshake timeout (5 s);
//! - a client offering only the classic subprotocol `foxglove.websocket.v1` is accepted under that name;
//! - a client's Close frame is answered with a Close frame (not a reset: 1006 in a browser);
//! - 60 clients each holding an unfinished message of 1,000,000 bytes (under the 1 MiB bound of one message)
//!   hold no more than the server's total for incoming bytes (16 MiB): those holding their share of the full
//!   total are disconnected, the others stay, and the server's resident memory grows by less than what they sent.

mod support;

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use support::foxglove::{closed_within, frame_header, rss_mib, BINARY};
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::{self, Message};

struct Player {
    child: Child,
    port: u16,
    log: Arc<Mutex<Vec<String>>>,
}

impl Player {
    /// `bag play` of the golden bag serving Foxglove only, with at most `fds` file descriptors if given.
    fn start(fds: Option<u32>) -> Player {
        let bag = Path::new(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden");
        let mut command = Command::new("bash");
        let limit = fds.map_or(String::new(), |n| format!("ulimit -n {n} && "));
        command
            .arg("-c")
            .arg(format!("{limit}exec \"$0\" \"$@\""))
            .arg(env!("CARGO_BIN_EXE_sweetspot"))
            .args(["bag", "play"])
            .arg(&bag)
            .args(["--foxglove", "0", "--no-dds"])
            .env("RUST_LOG", "info")
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        let mut child = command.spawn().expect("bag play");
        let mut stderr = BufReader::new(child.stderr.take().unwrap());
        let mut line = String::new();
        let port = loop {
            line.clear();
            assert!(stderr.read_line(&mut line).unwrap() > 0, "bag play exited before serving");
            if let Some(rest) = line.split("Foxglove WebSocket server on ws://127.0.0.1:").nth(1) {
                break rest.split(':').next().unwrap().parse::<u16>().unwrap();
            }
        };
        let log = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&log);
        std::thread::spawn(move || {
            for line in stderr.lines().map_while(Result::ok) {
                sink.lock().unwrap().push(line);
            }
        });
        Player { child, port, log }
    }

    fn lines_with(&self, needle: &str) -> usize {
        self.log.lock().unwrap().iter().filter(|l| l.contains(needle)).count()
    }

    fn log(&self) -> String {
        self.log.lock().unwrap().join("\n")
    }
}

impl Drop for Player {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

type Ws = tungstenite::WebSocket<TcpStream>;

/// A WebSocket handshake offering `protocols`; the negotiated subprotocol, or the refusal.
fn connect(port: u16, protocols: &str) -> Result<(Ws, Option<String>), String> {
    let stream = TcpStream::connect(("127.0.0.1", port)).map_err(|e| e.to_string())?;
    stream.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let mut request = format!("ws://127.0.0.1:{port}").into_client_request().unwrap();
    request.headers_mut().insert("sec-websocket-protocol", protocols.parse().unwrap());
    let (ws, response) = tungstenite::client(request, stream).map_err(|e| e.to_string())?;
    let chosen = response.headers().get("sec-websocket-protocol").map(|v| v.to_str().unwrap().to_string());
    Ok((ws, chosen))
}

/// Reads until the serverInfo (the first text message) arrives.
fn server_info(ws: &mut Ws) -> serde_json::Value {
    loop {
        match ws.read().expect("a message within 5 s") {
            Message::Text(text) => return serde_json::from_str(&text).unwrap(),
            _ => continue,
        }
    }
}

#[test]
fn the_listener_survives_running_out_of_file_descriptors() {
    let player = Player::start(Some(48));
    let mut held = Vec::new();
    for _ in 0..150 {
        if let Ok(stream) = TcpStream::connect(("127.0.0.1", player.port)) {
            held.push(stream);
        }
    }
    std::thread::sleep(Duration::from_secs(1));
    drop(held);
    // The back-off is at most 1 s; the server has closed the accepted ones when they went.
    std::thread::sleep(Duration::from_millis(1500));
    let (mut ws, _) = connect(player.port, "foxglove.sdk.v1")
        .unwrap_or_else(|e| panic!("no handshake after EMFILE: {e}\n{}", player.log()));
    let info = server_info(&mut ws);
    assert_eq!(info["op"], "serverInfo", "{info}");
    let said = player.lines_with("Cannot accept connections");
    assert!((1..=5).contains(&said), "accept errors logged {said} times:\n{}", player.log());
}

#[test]
fn connections_beyond_the_cap_are_closed_and_the_refusal_logged_once() {
    let player = Player::start(None);
    let cap = sweetspot::foxglove::DEFAULT_MAX_CLIENTS;
    let mut streams: Vec<TcpStream> =
        (0..cap + 30).map(|_| TcpStream::connect(("127.0.0.1", player.port)).unwrap()).collect();
    // The refused ones are closed as they are accepted: after a moment, each is looked at briefly, so all 94
    // are judged well inside the handshake timeout (5 s) that would close the others too.
    std::thread::sleep(Duration::from_millis(500));
    let closed = streams.iter_mut().map(|s| closed_within(s, Duration::from_millis(10))).filter(|&c| c).count();
    assert_eq!(closed, 30, "{} connections with a cap of {cap}", cap + 30);
    assert_eq!(player.lines_with("Refusing new connections"), 1, "{}", player.log());
    drop(streams);
    std::thread::sleep(Duration::from_millis(500));
    let (mut ws, _) = connect(player.port, "foxglove.sdk.v1").expect("accepted again below the cap");
    assert_eq!(server_info(&mut ws)["op"], "serverInfo");
}

#[test]
fn a_connection_without_a_handshake_is_closed_after_the_timeout() {
    let player = Player::start(None);
    let start = Instant::now();
    let mut streams: Vec<TcpStream> =
        (0..20).map(|_| TcpStream::connect(("127.0.0.1", player.port)).unwrap()).collect();
    for stream in &mut streams {
        assert!(closed_within(stream, Duration::from_secs(10).saturating_sub(start.elapsed())), "still open");
    }
    let took = start.elapsed();
    assert!(took >= Duration::from_secs(4) && took < Duration::from_secs(9), "closed after {took:?}");
}

#[test]
fn the_classic_subprotocol_is_accepted_and_a_close_frame_answered() {
    let player = Player::start(None);
    let (mut ws, chosen) = connect(player.port, "foxglove.websocket.v1").expect("classic subprotocol accepted");
    assert_eq!(chosen.as_deref(), Some("foxglove.websocket.v1"));
    assert_eq!(server_info(&mut ws)["op"], "serverInfo");
    ws.close(None).unwrap();
    let answered = loop {
        match ws.read() {
            Ok(Message::Close(_)) => break true,
            Ok(_) => continue,
            Err(tungstenite::Error::ConnectionClosed) => break true,
            Err(e) => panic!("no Close frame in answer: {e}"),
        }
    };
    assert!(answered);
    // Both offered: the newest name wins.
    let (_, chosen) = connect(player.port, "foxglove.websocket.v1, foxglove.sdk.v1").unwrap();
    assert_eq!(chosen.as_deref(), Some("foxglove.sdk.v1"));
}

#[test]
fn unfinished_messages_of_many_clients_are_bounded_in_total() {
    const CLIENTS: usize = 60;
    const FRAGMENT: usize = 1_000_000;
    let total = sweetspot::foxglove::Limits::default().total_incoming_bytes;
    let player = Player::start(None);
    let mut clients: Vec<Ws> = (0..CLIENTS)
        .map(|_| {
            let (mut ws, _) = connect(player.port, "foxglove.sdk.v1").expect("handshake");
            server_info(&mut ws);
            ws
        })
        .collect();
    let before = rss_mib(player.child.id());
    let payload = vec![0u8; FRAGMENT];
    for ws in &mut clients {
        let stream = ws.get_mut();
        stream.set_write_timeout(Some(Duration::from_secs(5))).unwrap();
        // A refused client may find its connection closed while writing.
        let _ = stream.write_all(&frame_header(BINARY, false, FRAGMENT)).and_then(|()| stream.write_all(&payload));
    }
    std::thread::sleep(Duration::from_secs(1));
    let after = rss_mib(player.child.id());
    let refused =
        clients.iter_mut().map(|ws| closed_within(ws.get_mut(), Duration::from_millis(200))).filter(|&c| c).count();
    let kept = CLIENTS - refused;
    eprintln!(
        "{CLIENTS} clients x {FRAGMENT} B unfinished: {kept} kept, {refused} refused; RSS {before:.0} MiB before, \
         {after:.0} MiB after ({:+.0} MiB)",
        after - before
    );
    // Those kept hold their whole fragment; all together no more than the total and a read (128 KiB) each.
    assert!(kept * FRAGMENT <= total + CLIENTS * (128 << 10), "{kept} clients kept holding {FRAGMENT} B each");
    assert!(kept >= 4, "the total is shared, not refused to everyone: {kept} kept");
    assert_eq!(player.lines_with(&format!("bound of {total} bytes")), refused, "{}", player.log());
    assert!(after - before < 64.0, "RSS grew by {:.0} MiB", after - before);
}
