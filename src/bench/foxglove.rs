//! A Foxglove WebSocket client for the bench (`--foxglove-client`): connected to a node's live server, it
//! subscribes to every channel the server advertises and either reads everything (as a Foxglove app keeps
//! up) or stops reading after subscribing (a client that has frozen), so the latency and sustained-rate rows
//! can be measured with a viewer attached.
//!
//! It speaks the protocol's v1 JSON control messages itself (`advertise` in, `subscribe` out, ws-protocol's
//! docs/spec.md) over `tokio-tungstenite`, and counts binary frames without decoding them: the bench measures
//! what serving a client costs the node, not what decoding costs the client.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context as _};
use futures::{SinkExt as _, StreamExt as _};
use tokio_tungstenite::tungstenite::client::IntoClientRequest as _;
use tokio_tungstenite::tungstenite::http::HeaderValue;
use tokio_tungstenite::tungstenite::Message;

/// The subprotocol the foxglove SDK's server negotiates for protocol v1 (inline schemas).
const SUBPROTOCOL: &str = "foxglove.sdk.v1";

/// How a bench client behaves once subscribed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
pub enum ClientMode {
    /// Reads every message as it arrives.
    Reading,
    /// Subscribes, then never reads again (its socket buffers and the server's queue for it fill up).
    Stalled,
}

/// What a client saw, for the bench's log.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct ClientCounts {
    /// Channels subscribed to.
    pub channels: u64,
    /// Binary (message data) frames read.
    pub messages: u64,
    /// Bytes of those frames.
    pub bytes: u64,
}

/// A connected bench client running on its own thread until [`LiveClient::finish`].
pub struct LiveClient {
    stop: Arc<AtomicBool>,
    channels: Arc<AtomicU64>,
    messages: Arc<AtomicU64>,
    bytes: Arc<AtomicU64>,
    thread: Option<JoinHandle<anyhow::Result<()>>>,
}

impl LiveClient {
    /// Connects to `ws://127.0.0.1:PORT`, subscribes to every channel advertised within `settle`, and returns
    /// once subscribed (or with the reason it could not).
    pub fn connect(port: u16, mode: ClientMode, settle: Duration) -> anyhow::Result<LiveClient> {
        let stop = Arc::new(AtomicBool::new(false));
        let channels = Arc::new(AtomicU64::new(0));
        let messages = Arc::new(AtomicU64::new(0));
        let bytes = Arc::new(AtomicU64::new(0));
        let (ready_tx, ready_rx) = std::sync::mpsc::channel::<Result<(), String>>();
        let shared = (Arc::clone(&stop), Arc::clone(&channels), Arc::clone(&messages), Arc::clone(&bytes));
        let thread = std::thread::Builder::new().name("bench-foxglove".into()).spawn(move || {
            let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build()?;
            runtime.block_on(run_client(port, mode, settle, shared, ready_tx))
        })?;
        let client = LiveClient { stop, channels, messages, bytes, thread: Some(thread) };
        match ready_rx.recv_timeout(settle + Duration::from_secs(10)) {
            Ok(Ok(())) => Ok(client),
            Ok(Err(e)) => Err(anyhow!("Foxglove client on port {port}: {e}")),
            Err(_) => Err(anyhow!("Foxglove client on port {port}: not subscribed within {settle:?}")),
        }
    }

    /// What it has seen so far.
    pub fn counts(&self) -> ClientCounts {
        ClientCounts {
            channels: self.channels.load(Ordering::Relaxed),
            messages: self.messages.load(Ordering::Relaxed),
            bytes: self.bytes.load(Ordering::Relaxed),
        }
    }

    /// Disconnects and returns what it saw (an error if its connection failed while in use).
    pub fn finish(mut self) -> anyhow::Result<ClientCounts> {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            thread.join().map_err(|_| anyhow!("the Foxglove client thread panicked"))??;
        }
        Ok(self.counts())
    }
}

impl Drop for LiveClient {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

type Shared = (Arc<AtomicBool>, Arc<AtomicU64>, Arc<AtomicU64>, Arc<AtomicU64>);

async fn run_client(
    port: u16,
    mode: ClientMode,
    settle: Duration,
    (stop, channels, messages, bytes): Shared,
    ready: std::sync::mpsc::Sender<Result<(), String>>,
) -> anyhow::Result<()> {
    let fail = |e: String| {
        let _ = ready.send(Err(e.clone()));
        anyhow!(e)
    };
    let mut request = format!("ws://127.0.0.1:{port}").into_client_request().map_err(|e| fail(e.to_string()))?;
    request.headers_mut().insert("Sec-WebSocket-Protocol", HeaderValue::from_static(SUBPROTOCOL));
    let (mut socket, _) = tokio_tungstenite::connect_async(request).await.map_err(|e| fail(e.to_string()))?;

    // Channels arrive in one or more `advertise` messages after `serverInfo`; subscribe to each as it comes
    // until none has come for `settle`.
    let mut next_id = 1u64;
    let mut deadline = Instant::now() + settle;
    while let Some(left) = deadline.checked_duration_since(Instant::now()) {
        let frame = match tokio::time::timeout(left, socket.next()).await {
            Err(_) => break,
            Ok(None) => return Err(fail("the server closed the connection".into())),
            Ok(Some(frame)) => frame.map_err(|e| fail(e.to_string()))?,
        };
        let Message::Text(text) = frame else { continue };
        let Ok(value) = serde_json::from_str::<serde_json::Value>(text.as_str()) else { continue };
        if value["op"] != "advertise" {
            continue;
        }
        let mut subscriptions = Vec::new();
        for channel in value["channels"].as_array().into_iter().flatten() {
            if let Some(channel_id) = channel["id"].as_u64() {
                subscriptions.push(serde_json::json!({ "id": next_id, "channelId": channel_id }));
                next_id += 1;
            }
        }
        if !subscriptions.is_empty() {
            channels.fetch_add(subscriptions.len() as u64, Ordering::Relaxed);
            let subscribe = serde_json::json!({ "op": "subscribe", "subscriptions": subscriptions });
            socket.send(Message::Text(subscribe.to_string().into())).await.map_err(|e| fail(e.to_string()))?;
            deadline = Instant::now() + settle;
        }
    }
    if channels.load(Ordering::Relaxed) == 0 {
        return Err(fail(format!("no channel advertised within {settle:?}")));
    }
    let _ = ready.send(Ok(()));

    match mode {
        ClientMode::Stalled => {
            while !stop.load(Ordering::Relaxed) {
                tokio::time::sleep(Duration::from_millis(50)).await;
            }
        }
        ClientMode::Reading => {
            while !stop.load(Ordering::Relaxed) {
                match tokio::time::timeout(Duration::from_millis(50), socket.next()).await {
                    Err(_) => {}
                    Ok(None) => bail!("the server closed the connection"),
                    Ok(Some(frame)) => {
                        if let Message::Binary(data) = frame.context("reading from the Foxglove server")? {
                            messages.fetch_add(1, Ordering::Relaxed);
                            bytes.fetch_add(data.len() as u64, Ordering::Relaxed);
                        }
                    }
                }
            }
        }
    }
    let _ = socket.close(None).await;
    Ok(())
}

/// A TCP port on 127.0.0.1 free at the time of asking (for a node's `foxglove_port`).
pub fn free_port() -> anyhow::Result<u16> {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").context("finding a free port on 127.0.0.1")?;
    Ok(listener.local_addr()?.port())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bag::{RecordedQos, TopicInfo};
    use crate::foxglove::{Bind, LiveServer};

    fn topic(name: &str) -> TopicInfo {
        // The server forwards bytes without decoding them, so any type's schema will do.
        TopicInfo::of::<crate::msgs::sweetspot_msgs::msg::Swing>(
            name,
            RecordedQos { reliable: true, transient_local: false, depth: 10 },
        )
    }

    /// The reading client subscribes to every channel and counts each message the server sends while it is
    /// subscribed; the server's own counters (the SDK's view, not this client's) agree on the subscriptions.
    #[test]
    fn a_reading_client_subscribes_to_every_channel_and_counts_what_the_server_sends() {
        let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(1).enable_all().build().unwrap();
        let bind = Bind::parse("127.0.0.1:0").unwrap();
        let server = runtime.block_on(LiveServer::start("bench-test", &bind, &[topic("/a"), topic("/b")])).unwrap();
        let client = LiveClient::connect(server.port(), ClientMode::Reading, Duration::from_millis(300)).unwrap();
        assert_eq!(client.counts().channels, 2);
        let deadline = Instant::now() + Duration::from_secs(5);
        while server.counters().subscriptions < 2 && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(server.counters().subscriptions, 2);
        let cdr = [0u8, 1, 0, 0, 3, 0, 0, 0, b'h', b'i', 0];
        for k in 0..50u64 {
            server.send((k % 2) as usize, &cdr, 1_000 + k);
        }
        while client.counts().messages < 50 && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(10));
        }
        let counts = client.finish().unwrap();
        assert_eq!(counts.messages, 50);
        // A message data frame: opcode 1, subscription id u32, log time u64, then the payload.
        assert_eq!(counts.bytes, 50 * (1 + 4 + 8 + cdr.len() as u64));
        server.stop();
    }

    #[test]
    fn a_client_without_a_server_says_so() {
        let port = free_port().unwrap();
        let err = LiveClient::connect(port, ClientMode::Reading, Duration::from_millis(100)).err().unwrap();
        assert!(err.to_string().contains(&port.to_string()), "{err}");
    }
}
