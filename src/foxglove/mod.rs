//! The Foxglove WebSocket server that `sweetspot node --foxglove [ADDR:]PORT` (parameter `foxglove_port`) and
//! `bag play --foxglove [ADDR:]PORT` serve on, built on Foxglove's own SDK (crate `foxglove`, feature
//! `websocket` only).
//!
//! Every topic is a channel with the bag's `ros2msg` schema text and `cdr` message encoding
//! ([`crate::bag::TopicInfo`]: generated from `msgs/` in the node, as recorded in `bag play`), and carries the
//! very CDR bytes the bag holds: the node's [`crate::node::recording::Tape::record`] encodes once and hands the
//! bytes to both the recorder and this server.
//!
//! Serving never blocks the caller: [`LiveServer::send`] only enqueues. The SDK (patched, see
//! `patches/README.md`) keeps one bounded queue per client ([`BACKLOG`] messages) and bounds the bytes queued
//! for all clients together ([`Limits::total_backlog_bytes`]); a client that does not keep up — its queue
//! full, or holding its share of a full total — is disconnected, with one log line, rather than served at the
//! node's expense. [`LiveCounters`] holds what the server can see — clients, subscriptions, messages handed
//! over for subscribers — and the node reports those on `/diagnostics`.
//!
//! Who can connect: anyone who reaches the port. The server has no authentication, and it accepts every
//! `Origin` (Foxglove's and Lichtblick's web apps are served from many origins, and desktop apps send
//! none), so the default bind is loopback (127.0.0.1): only this machine's users. Binding `0.0.0.0` serves
//! every host that can reach the port; put it behind something that authenticates (an SSH tunnel, or a
//! reverse proxy with TLS and authentication in front of a loopback bind). At most [`Limits::max_clients`]
//! connections are served at once (more are closed as they arrive, the refusal logged once until one is
//! accepted again); a connection has [`Limits::handshake_timeout`] to complete its WebSocket handshake; an
//! accept error (file descriptors exhausted) pauses accepting with a back-off instead of ending it. What
//! clients send is bounded as well: a message over [`Limits::max_incoming_message_bytes`] ends its client's
//! connection as soon as its length is known, and the unfinished messages of all clients together are
//! bounded by [`Limits::total_incoming_bytes`] (a client holding its share of a full total is disconnected).
//! A client's bad requests (unknown channel ids, invalid messages) are logged at most once a second per
//! client, one line per request.
//!
//! Latched topics (transient-local in DDS: the parameters and SweetSpot) are latched here too: the last
//! messages (as many as the topic's QoS depth) are replayed to a client when it subscribes, so a client that
//! connects mid-session sees the bats and balls in use.
//!
//! Where swing scenes are served (a `visualization_msgs/msg/MarkerArray` topic), the server also serves the
//! scenes' frame on [`FRAME_TOPIC`]: a `foxglove.FrameTransform` (JSON) placing `bat` at the origin of
//! `world`, latched, so Foxglove's and Lichtblick's 3D panels know the frame as soon as they subscribe instead
//! of warning "Frame bat not found" until the first scene arrives. The latched copy goes out at the latest
//! log time the server has sent (not at 0: a client's clock jumping back to 1970 makes a 3D panel clear its
//! transforms), and the frame is sent again just before every scene, at the scene's log time: a 3D panel
//! clears its transforms whenever time jumps back (a seek or `--loop` of `bag play`, a rig whose clock
//! restarts), and the next scene brings the frame back instead of leaving the panel without it.
//!
//! With [`Playback`] (`bag play`) the server also declares the bag's time range and answers Foxglove's
//! playback controls (play, pause, seek, speed) through a [`PlaybackHandler`].

use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use foxglove::websocket::{Capability, ChannelView, Client, PlaybackControlRequest, PlaybackState, ServerListener};
use foxglove::{ChannelBuilder, ChannelId, Context, PartialMetadata, RawChannel, Schema, WebSocketServer};

use crate::bag::TopicInfo;

/// The channel that announces the scenes' frame ([`crate::model::scene::FRAME_ID`]) to live clients.
pub const FRAME_TOPIC: &str = "/bat_frame";
/// The frame [`FRAME_TOPIC`] places the scenes' frame in, at its origin.
pub const WORLD_FRAME: &str = "world";
/// The type of the swing scenes, whose presence among the served topics brings [`FRAME_TOPIC`] with it.
const SCENE_TYPE: &str = "visualization_msgs/msg/MarkerArray";

/// Foxglove's `foxglove.FrameTransform` as a JSON schema: the fields Foxglove's schema defines, types only.
const FRAME_TRANSFORM_SCHEMA: &str = r#"{"title":"foxglove.FrameTransform","type":"object","properties":{
"timestamp":{"type":"object","title":"time","properties":{"sec":{"type":"integer","minimum":0},
"nsec":{"type":"integer","minimum":0,"maximum":999999999}}},
"parent_frame_id":{"type":"string"},"child_frame_id":{"type":"string"},
"translation":{"title":"foxglove.Vector3","type":"object","properties":{"x":{"type":"number"},
"y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]},
"rotation":{"title":"foxglove.Quaternion","type":"object","properties":{"x":{"type":"number"},
"y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}},"required":["x","y","z","w"]}},
"required":["timestamp","parent_frame_id","child_frame_id","translation","rotation"]}"#;

/// The message of [`FRAME_TOPIC`]: the scenes' frame at the origin of [`WORLD_FRAME`], unrotated, valid
/// from time 0 on.
fn frame_transform_json() -> Vec<u8> {
    serde_json::json!({
        "timestamp": {"sec": 0, "nsec": 0},
        "parent_frame_id": WORLD_FRAME,
        "child_frame_id": crate::model::scene::FRAME_ID,
        "translation": {"x": 0.0, "y": 0.0, "z": 0.0},
        "rotation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
    })
    .to_string()
    .into_bytes()
}

/// Messages queued per client; a client whose queue is full is disconnected (the SDK's default is 1024).
pub const BACKLOG: usize = 4096;

/// How many clients the server takes and how long it waits for them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Most connections (handshaking or connected) served at once.
    pub max_clients: usize,
    /// Time a connection has to complete its WebSocket handshake, s.
    pub handshake_timeout: std::time::Duration,
    /// Bytes queued for all clients together before the slowest are disconnected.
    pub total_backlog_bytes: usize,
    /// Largest message a client may send; a client that sends a larger one is disconnected.
    pub max_incoming_message_bytes: usize,
    /// Bytes of unfinished client messages held for all clients together before those holding their
    /// share are disconnected.
    pub total_incoming_bytes: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_clients: DEFAULT_MAX_CLIENTS,
            handshake_timeout: std::time::Duration::from_secs(5),
            total_backlog_bytes: 64 << 20,
            max_incoming_message_bytes: MAX_INCOMING_MESSAGE_BYTES,
            total_incoming_bytes: 16 << 20,
        }
    }
}

/// Largest message a client may send. A client sends subscriptions and playback controls: a subscription
/// takes about 40 bytes a channel, so 1 MiB is thousands of times what sweetspot's channels need (tungstenite
/// allows 64 MiB unless told otherwise). What many clients hold at once is bounded by
/// [`Limits::total_incoming_bytes`], whatever [`Limits::max_clients`].
pub const MAX_INCOMING_MESSAGE_BYTES: usize = 1 << 20;

/// Connections served at once unless told otherwise (the node's `foxglove_max_clients`).
pub const DEFAULT_MAX_CLIENTS: usize = 64;

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

    /// The URL a client connects to on `port`: `ws://HOST:PORT`, an IPv6 address in brackets.
    pub fn url(&self, port: u16) -> String {
        if self.host.contains(':') {
            format!("ws://[{}]:{port}", self.host)
        } else {
            format!("ws://{}:{port}", self.host)
        }
    }
}

/// Answers Foxglove's playback control requests (play/pause, speed, seek) with the resulting state.
pub trait PlaybackHandler: Send + Sync {
    /// Applies `request`; returns the playback state after it (the SDK sends it to every client).
    fn on_request(&self, request: PlaybackControlRequest) -> PlaybackState;
}

/// A fixed time range served with playback controls (`bag play`).
pub struct Playback {
    /// First and last log time of the data, ns since the Unix epoch.
    pub range: (u64, u64),
    /// Who applies the controls.
    pub handler: Arc<dyn PlaybackHandler>,
}

/// What the server can see of its clients, for `/diagnostics`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LiveCounters {
    /// Clients connected now.
    pub clients: u64,
    /// Channel subscriptions held by those clients now.
    pub subscriptions: u64,
    /// Messages handed to the server while their channel had at least one subscriber.
    pub served: u64,
    /// Per-client queue bound, messages ([`BACKLOG`]).
    pub backlog: u64,
}

/// The last messages of each latched channel, replayed to each new subscriber; the client and subscription
/// counts; the playback handler, if any.
#[derive(Default)]
struct Listener {
    /// Channel id → (channel, depth, last messages with their log times).
    slots: Mutex<HashMap<ChannelId, Latch>>,
    clients: AtomicU64,
    subscriptions: AtomicU64,
    playback: Option<Arc<dyn PlaybackHandler>>,
    /// The latest log time sent on any channel, ns.
    last_log_time: AtomicU64,
}

struct Latch {
    channel: Arc<RawChannel>,
    depth: usize,
    last: VecDeque<(Vec<u8>, u64)>,
    /// Replayed at the latest log time sent rather than its own ([`FRAME_TOPIC`]: valid at any time).
    at_latest_time: bool,
}

impl ServerListener for Listener {
    fn on_subscribe(&self, client: Client, channel: ChannelView) {
        self.subscriptions.fetch_add(1, Ordering::Relaxed);
        let Ok(slots) = self.slots.lock() else { return };
        if let Some(latch) = slots.get(&channel.id()) {
            let latest = self.last_log_time.load(Ordering::Relaxed);
            for (cdr, log_time) in &latch.last {
                let log_time = if latch.at_latest_time { latest.max(*log_time) } else { *log_time };
                let meta = PartialMetadata { log_time: Some(log_time) };
                latch.channel.log_with_meta_to_sink(cdr, meta, client.sink_id());
            }
        }
    }

    fn on_unsubscribe(&self, _client: Client, _channel: ChannelView) {
        // The SDK calls this for every subscription a disconnecting client held, too.
        let _ = self.subscriptions.fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| n.checked_sub(1));
    }

    fn on_client_connect(&self) {
        self.clients.fetch_add(1, Ordering::Relaxed);
    }

    fn on_client_disconnect(&self) {
        let _ = self.clients.fetch_update(Ordering::Relaxed, Ordering::Relaxed, |n| n.checked_sub(1));
    }

    fn on_playback_control_request(&self, request: PlaybackControlRequest) -> Option<PlaybackState> {
        self.playback.as_ref().map(|handler| handler.on_request(request))
    }
}

/// A running server and its channels, in the order of the topics it was started with.
pub struct LiveServer {
    /// Kept alive: a channel whose context is dropped is closed.
    _context: Arc<Context>,
    /// [`FRAME_TOPIC`], when scenes are served (its message latched, and sent again before each scene).
    frame: Option<Arc<RawChannel>>,
    channels: Vec<Arc<RawChannel>>,
    latched: Vec<bool>,
    /// Whether each topic is a scene topic (brings the frame with each message).
    scenes: Vec<bool>,

    listener: Arc<Listener>,
    served: AtomicU64,
    port: u16,
    handle: Mutex<Option<foxglove::WebSocketServerHandle>>,
}

impl LiveServer {
    /// Starts serving `topics` (as the recorder registers them) on `bind`, named `name` to clients.
    pub async fn start(name: &str, bind: &Bind, topics: &[TopicInfo]) -> Result<LiveServer, String> {
        LiveServer::start_with(name, bind, topics, None, Limits::default()).await
    }

    /// [`LiveServer::start`], within `limits`, with playback controls over a fixed time range when
    /// `playback` is given.
    pub async fn start_with(
        name: &str,
        bind: &Bind,
        topics: &[TopicInfo],
        playback: Option<Playback>,
        limits: Limits,
    ) -> Result<LiveServer, String> {
        // A context of its own: channels of another server in the same process are not advertised here.
        let context = Context::new();
        let mut listener =
            Listener { playback: playback.as_ref().map(|p| Arc::clone(&p.handler)), ..Default::default() };
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
                let latch =
                    Latch { channel: Arc::clone(&channel), depth, last: VecDeque::new(), at_latest_time: false };
                listener.slots.get_mut().map_err(|_| "latch table poisoned".to_string())?.insert(channel.id(), latch);
            }
            latched.push(topic.qos.transient_local);
            channels.push(channel);
        }
        let frame = if topics.iter().any(|t| t.type_name == SCENE_TYPE) {
            let schema = Schema::new("foxglove.FrameTransform", "jsonschema", FRAME_TRANSFORM_SCHEMA.as_bytes());
            let channel = ChannelBuilder::new(FRAME_TOPIC)
                .message_encoding("json")
                .schema(schema)
                .context(&context)
                .build_raw()
                .map_err(|e| format!("channel {FRAME_TOPIC}: {e}"))?;
            let last = VecDeque::from([(frame_transform_json(), 0)]);
            let latch = Latch { channel: Arc::clone(&channel), depth: 1, last, at_latest_time: true };
            listener.slots.get_mut().map_err(|_| "latch table poisoned".to_string())?.insert(channel.id(), latch);
            Some(channel)
        } else {
            None
        };
        let listener = Arc::new(listener);
        let as_listener: Arc<dyn ServerListener> = listener.clone();
        let mut server = WebSocketServer::new()
            .name(name)
            .bind(bind.host.clone(), bind.port)
            .context(&context)
            .listener(as_listener)
            .message_backlog_size(BACKLOG)
            .max_clients(limits.max_clients)
            .handshake_timeout(limits.handshake_timeout)
            .total_backlog_bytes(limits.total_backlog_bytes)
            .max_incoming_message_bytes(limits.max_incoming_message_bytes)
            .total_incoming_bytes(limits.total_incoming_bytes);
        if let Some(playback) = &playback {
            // The time range implies the PlaybackControl capability; Time lets clients follow the position.
            server = server.playback_time_range(playback.range.0, playback.range.1).capabilities([Capability::Time]);
        }
        let handle =
            server.start().await.map_err(|e| format!("Foxglove server on {}:{}: {e}", bind.host, bind.port))?;
        let port = handle.port();
        Ok(LiveServer {
            _context: context,
            frame,
            channels,
            latched,
            scenes: topics.iter().map(|t| t.type_name == SCENE_TYPE).collect(),

            listener,
            served: AtomicU64::new(0),
            port,
            handle: Mutex::new(Some(handle)),
        })
    }

    /// The TCP port it listens on.
    pub fn port(&self) -> u16 {
        self.port
    }

    /// Hands one CDR message of topic `index` to every subscribed client's queue; never blocks on a client.
    pub fn send(&self, index: usize, cdr: &[u8], log_time_ns: u64) {
        let Some(channel) = self.channels.get(index) else { return };
        self.listener.last_log_time.fetch_max(log_time_ns, Ordering::Relaxed);
        if self.latched.get(index).copied().unwrap_or(false) {
            self.latch(channel, cdr.to_vec(), log_time_ns);
        }
        if let (Some(frame), true) = (&self.frame, self.scenes.get(index).copied().unwrap_or(false)) {
            let json = frame_transform_json();
            frame.log_with_meta(&json, PartialMetadata { log_time: Some(log_time_ns) });
            self.latch(frame, json, log_time_ns);
        }
        if channel.has_sinks() {
            self.served.fetch_add(1, Ordering::Relaxed);
        }
        channel.log_with_meta(cdr, PartialMetadata { log_time: Some(log_time_ns) });
    }

    /// Keeps `message` as the latest of `channel`'s latched ones (its oldest dropped past the topic's depth).
    fn latch(&self, channel: &RawChannel, message: Vec<u8>, log_time_ns: u64) {
        if let Ok(mut slots) = self.listener.slots.lock() {
            if let Some(latch) = slots.get_mut(&channel.id()) {
                if latch.last.len() == latch.depth {
                    latch.last.pop_front();
                }
                latch.last.push_back((message, log_time_ns));
            }
        }
    }

    /// Whether any client subscribes to topic `index` now.
    pub fn has_subscribers(&self, index: usize) -> bool {
        self.channels.get(index).is_some_and(|channel| channel.has_sinks())
    }

    /// Tells every client the current time (ns since the Unix epoch; the bag's time in `bag play`).
    pub fn broadcast_time(&self, time_ns: u64) {
        if let Some(handle) = self.handle.lock().ok().as_ref().and_then(|h| h.as_ref()) {
            handle.broadcast_time(time_ns);
        }
    }

    /// Tells every client the playback state (a server started with [`Playback`] only).
    pub fn broadcast_playback_state(&self, state: PlaybackState) {
        if let Some(handle) = self.handle.lock().ok().as_ref().and_then(|h| h.as_ref()) {
            handle.broadcast_playback_state(state);
        }
    }

    /// What the server sees of its clients now.
    pub fn counters(&self) -> LiveCounters {
        LiveCounters {
            clients: self.listener.clients.load(Ordering::Relaxed),
            subscriptions: self.listener.subscriptions.load(Ordering::Relaxed),
            served: self.served.load(Ordering::Relaxed),
            backlog: BACKLOG as u64,
        }
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

    #[test]
    fn an_ipv6_url_puts_the_address_in_brackets() {
        assert_eq!(Bind::parse("[::1]:8768").unwrap().url(8768), "ws://[::1]:8768");
        assert_eq!(Bind::parse("8765").unwrap().url(8765), "ws://127.0.0.1:8765");
        assert_eq!(Bind::parse("localhost:0").unwrap().url(40000), "ws://localhost:40000");
    }
}
