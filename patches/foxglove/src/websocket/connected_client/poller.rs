use std::time::Duration;

use futures_util::{SinkExt, StreamExt};
use tokio::sync::oneshot;
use tokio_tungstenite::WebSocketStream;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::tungstenite::protocol::CloseFrame;
use tokio_tungstenite::tungstenite::protocol::frame::coding::CloseCode;

use crate::websocket::Status;
use crate::websocket::incoming::{ClientStream, Excess};

use super::{ConnectedClient, ShutdownReason};

/// Longest time given to the final messages of a connection (a Close reply, a status).
const CLOSE_TIMEOUT: Duration = Duration::from_secs(1);

/// A poller for a connected client.
///
/// The poller is responsible for:
/// - Sending messages (from `data_plane` and `control_plane`) to the WebSocket.
/// - Receiving messages from the WebSocket and invoking [`ConnectedClient::handle_message`].
/// - Waiting for a shutdown signal, and closing the WebSocket.
pub(super) struct Poller {
    websocket: WebSocketStream<ClientStream>,
    data_plane_rx: flume::Receiver<Message>,
    control_plane_rx: flume::Receiver<Message>,
    shutdown_rx: oneshot::Receiver<ShutdownReason>,
}

impl Poller {
    /// Creates a new poller.
    pub fn new(
        websocket: WebSocketStream<ClientStream>,
        data_plane_rx: flume::Receiver<Message>,
        control_plane_rx: flume::Receiver<Message>,
        shutdown_rx: oneshot::Receiver<ShutdownReason>,
    ) -> Self {
        Self {
            websocket,
            data_plane_rx,
            control_plane_rx,
            shutdown_rx,
        }
    }

    /// Runs the main poll loop for a WebSocket connection.
    ///
    /// Each connection ends with one log line saying why. A client's Close frame is answered; every
    /// final message is given at most [`CLOSE_TIMEOUT`], so a client that stopped reading cannot
    /// hold the connection open.
    pub async fn run(self, client: &ConnectedClient) {
        let addr = client.addr();
        let meter = self.websocket.get_ref().meter().clone();
        let (mut ws_tx, mut ws_rx) = self.websocket.split();

        // Handle messages received from the WebSocket.
        let ws_rx_loop = async {
            loop {
                match ws_rx.next().await {
                    Some(Ok(Message::Close(_))) => {
                        tracing::info!("Connection closed by client {addr}");
                        return ShutdownReason::ClientClosed;
                    }
                    Some(Ok(msg)) => {
                        meter.delivered(&msg);
                        client.handle_message(msg)
                    }
                    Some(Err(err)) => {
                        if let Some(excess) = Excess::of(&err) {
                            return refuse(addr, excess);
                        }
                        tracing::info!("Connection to client {addr} lost: {err}");
                        return ShutdownReason::ClientDisconnected;
                    }
                    None => {
                        tracing::info!("Connection closed by client {addr}");
                        return ShutdownReason::ClientDisconnected;
                    }
                }
            }
        };

        // Send messages from queues to the WebSocket.
        let ws_tx_loop = async {
            loop {
                let msg = tokio::select! {
                    msg = self.control_plane_rx.recv_async() => msg,
                    msg = self.data_plane_rx.recv_async() => msg.inspect(|msg| client.data_dequeued(msg)),
                };
                let Ok(msg) = msg else {
                    unreachable!("ConnectedClient holds queues");
                };
                if let Err(err) = ws_tx.send(msg).await {
                    // Said once: the connection is over.
                    tracing::info!("Disconnecting client {addr}: sending failed: {err}");
                    return ShutdownReason::SendFailed;
                }
            }
        };

        // Run send and receive loops concurrently.
        let reason = tokio::select! {
            r = ws_tx_loop => r,
            r = ws_rx_loop => r,
            r = self.shutdown_rx => r.expect("ConnectedClient sends before dropping sender"),
        };

        // Send final messages, as appropriate.
        let goodbye = async {
            match reason {
                ShutdownReason::ClientDisconnected | ShutdownReason::SendFailed => (),
                ShutdownReason::ClientClosed => {
                    // Flushes the Close frame the WebSocket queued in reply to the client's.
                    ws_tx.close().await.ok();
                }
                ShutdownReason::ServerStopped => {
                    ws_tx.send(Message::Close(None)).await.ok();
                }
                ShutdownReason::ControlPlaneQueueFull => {
                    let status = Status::error(
                        "Disconnected because the message backlog on the server is full. \
                        The backlog size is configurable in the server setup.",
                    );
                    ws_tx.send(Message::from(&status)).await.ok();
                    ws_tx.send(Message::Close(None)).await.ok();
                }
                ShutdownReason::MessageTooLong { max } => {
                    let why = format!("Disconnected because a message was over {max} bytes.");
                    goodbye_with(&mut ws_tx, CloseCode::Size, why).await;
                }
                ShutdownReason::IncomingFull => {
                    let why =
                        "Disconnected because the server holds as much of clients' unfinished \
                        messages as it takes."
                            .to_string();
                    goodbye_with(&mut ws_tx, CloseCode::Again, why).await;
                }
                ShutdownReason::SlowClient => {
                    let status = Status::error(
                        "Disconnected because this client did not read its messages as fast as \
                        they came.",
                    );
                    ws_tx.send(Message::from(&status)).await.ok();
                    ws_tx.send(Message::Close(None)).await.ok();
                }
            }
        };
        tokio::time::timeout(CLOSE_TIMEOUT, goodbye).await.ok();
    }
}

/// Sends an error status saying `why`, then a Close frame with `code` (and `why`, cut to what a Close
/// frame carries).
async fn goodbye_with<S>(ws_tx: &mut S, code: CloseCode, why: String)
where
    S: futures_util::Sink<Message> + Unpin,
{
    ws_tx
        .send(Message::from(&Status::error(why.clone())))
        .await
        .ok();
    let mut reason = why;
    // A Close frame's reason is at most 123 bytes.
    while reason.len() > 123 {
        reason.pop();
    }
    let frame = CloseFrame {
        code,
        reason: reason.into(),
    };
    ws_tx.send(Message::Close(Some(frame))).await.ok();
}

/// Says once why a client that sent too much is disconnected.
fn refuse(addr: std::net::SocketAddr, excess: Excess) -> ShutdownReason {
    match excess {
        Excess::Message { size, max } => {
            tracing::warn!(
                "Disconnecting client {addr}: it sent a message of {size} bytes, over the bound of {max}"
            );
            ShutdownReason::MessageTooLong { max }
        }
        Excess::Budget(why) => {
            tracing::warn!("Disconnecting client {addr}: {why}");
            ShutdownReason::IncomingFull
        }
    }
}
