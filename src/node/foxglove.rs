//! The node's live view: a Foxglove WebSocket server (`sweetspot node --foxglove [ADDR:]PORT`, parameter
//! `foxglove_port`) built on Foxglove's own SDK (crate `foxglove`, feature `websocket` only).
//!
//! Every topic the node records is a channel here too (and `/diagnostics`, served but not recorded), with the bag's `ros2msg` schema text and `cdr`
//! message encoding ([`crate::bag::TopicInfo`], generated from `msgs/`), and carries the very CDR bytes the
//! recorder gets: [`super::recording::Tape::record`] encodes once and hands the bytes to both.
//!
//! Serving never blocks the node: [`LiveServer::send`] only enqueues. The SDK keeps one bounded queue per
//! client ([`BACKLOG`] messages); when a client falls behind, the oldest queued messages are dropped for that
//! client alone (the SDK's `send_lossy`; it logs "outbox for client … full" at most every 30 s but does not
//! expose a drop count, so none is reported on `/diagnostics`). A client whose control queue fills is
//! disconnected by the SDK.
//!
//! Latched topics (transient-local in DDS: the parameters and SweetSpot) are latched here too: the last
//! messages (as many as the topic's QoS depth) are replayed to a client when it subscribes, so a client that
//! connects mid-session sees the bats and balls in use.

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex};

use foxglove::websocket::{ChannelView, Client, ServerListener};
use foxglove::{ChannelBuilder, ChannelId, Context, PartialMetadata, RawChannel, Schema, WebSocketServer};

use crate::bag::TopicInfo;

/// Messages queued per client before the oldest are dropped for that client (the SDK's default is 1024).
pub const BACKLOG: usize = 4096;

/// Where the server listens: `[ADDR:]PORT`, the address 127.0.0.1 unless given.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Bind {
    /// Host or IP address to bind (IPv6 without brackets).
    pub host: String,
    /// TCP port; 0 = any free port.
    pub port: u16,
}

impl Bind {
    /// Parses `PORT`, `ADDR:PORT` or `[IPV6]:PORT`.
    pub fn parse(text: &str) -> Result<Bind, String> {
        let text = text.trim();
        let (host, port) = match text.rsplit_once(':') {
            Some((host, port)) => (host.trim_start_matches('[').trim_end_matches(']'), port),
            None => ("127.0.0.1", text),
        };
        let port = port.parse::<u16>().map_err(|_| format!("'{text}' is not [ADDR:]PORT (PORT 0–65535)"))?;
        if host.is_empty() {
            return Err(format!("'{text}' has an empty address"));
        }
        Ok(Bind { host: host.to_string(), port })
    }
}

/// The last messages of each latched channel, replayed to each new subscriber.
#[derive(Default)]
struct Latches {
    /// Channel id → (channel, depth, last messages with their log times).
    slots: Mutex<HashMap<ChannelId, Latch>>,
}

struct Latch {
    channel: Arc<RawChannel>,
    depth: usize,
    last: VecDeque<(Vec<u8>, u64)>,
}

impl ServerListener for Latches {
    fn on_subscribe(&self, client: Client, channel: ChannelView) {
        let Ok(slots) = self.slots.lock() else { return };
        if let Some(latch) = slots.get(&channel.id()) {
            for (cdr, log_time) in &latch.last {
                let meta = PartialMetadata { log_time: Some(*log_time) };
                latch.channel.log_with_meta_to_sink(cdr, meta, client.sink_id());
            }
        }
    }
}

/// A running server and its channels, in the order of the topics it was started with.
pub struct LiveServer {
    /// Kept alive: a channel whose context is dropped is closed.
    _context: Arc<Context>,
    channels: Vec<Arc<RawChannel>>,
    latched: Vec<bool>,
    latches: Arc<Latches>,
    port: u16,
    handle: Mutex<Option<foxglove::WebSocketServerHandle>>,
}

impl LiveServer {
    /// Starts serving `topics` (as the recorder registers them) on `bind`, named `name` to clients.
    pub async fn start(name: &str, bind: &Bind, topics: &[TopicInfo]) -> Result<LiveServer, String> {
        // A context of its own: channels of another server in the same process are not advertised here.
        let context = Context::new();
        let latches = Arc::new(Latches::default());
        let mut channels = Vec::with_capacity(topics.len());
        let mut latched = Vec::with_capacity(topics.len());
        for topic in topics {
            let schema = Schema::new(topic.type_name.clone(), "ros2msg", topic.schema_text.clone().into_bytes());
            let channel = ChannelBuilder::new(topic.name.clone())
                .message_encoding("cdr")
                .schema(schema)
                .context(&context)
                .build_raw()
                .map_err(|e| format!("channel {}: {e}", topic.name))?;
            if topic.qos.transient_local {
                let depth = (topic.qos.depth as usize).max(1);
                let latch = Latch { channel: Arc::clone(&channel), depth, last: VecDeque::new() };
                latches.slots.lock().map_err(|_| "latch table poisoned".to_string())?.insert(channel.id(), latch);
            }
            latched.push(topic.qos.transient_local);
            channels.push(channel);
        }
        let listener: Arc<dyn ServerListener> = latches.clone();
        let handle = WebSocketServer::new()
            .name(name)
            .bind(bind.host.clone(), bind.port)
            .context(&context)
            .listener(listener)
            .message_backlog_size(BACKLOG)
            .start()
            .await
            .map_err(|e| format!("Foxglove server on {}:{}: {e}", bind.host, bind.port))?;
        let port = handle.port();
        Ok(LiveServer { _context: context, channels, latched, latches, port, handle: Mutex::new(Some(handle)) })
    }

    /// The TCP port it listens on.
    pub fn port(&self) -> u16 {
        self.port
    }

    /// Hands one CDR message of topic `index` to every subscribed client's queue; never blocks on a client.
    pub fn send(&self, index: usize, cdr: &[u8], log_time_ns: u64) {
        let Some(channel) = self.channels.get(index) else { return };
        if self.latched.get(index).copied().unwrap_or(false) {
            if let Ok(mut slots) = self.latches.slots.lock() {
                if let Some(latch) = slots.get_mut(&channel.id()) {
                    if latch.last.len() == latch.depth {
                        latch.last.pop_front();
                    }
                    latch.last.push_back((cdr.to_vec(), log_time_ns));
                }
            }
        }
        channel.log_with_meta(cdr, PartialMetadata { log_time: Some(log_time_ns) });
    }

    /// Stops the server (clients are disconnected); later `send` calls go nowhere.
    pub fn stop(&self) {
        if let Some(handle) = self.handle.lock().ok().and_then(|mut h| h.take()) {
            drop(handle.stop());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bind_defaults_to_loopback_and_takes_an_address() {
        assert_eq!(Bind::parse("8765").unwrap(), Bind { host: "127.0.0.1".into(), port: 8765 });
        assert_eq!(Bind::parse("0.0.0.0:9000").unwrap(), Bind { host: "0.0.0.0".into(), port: 9000 });
        assert_eq!(Bind::parse("[::1]:8765").unwrap(), Bind { host: "::1".into(), port: 8765 });
        assert!(Bind::parse("70000").is_err());
        assert!(Bind::parse(":8765").is_err());
        assert!(Bind::parse("localhost:port").is_err());
    }
}
