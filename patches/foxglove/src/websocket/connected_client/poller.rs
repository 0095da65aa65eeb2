use std::time::Duration;

use futures_util::{SinkExt, StreamExt};
use tokio::net::TcpStream;
use tokio::sync::oneshot;
use tokio_tungstenite::WebSocketStream;
use tokio_tungstenite::tungstenite::Message;

use crate::websocket::Status;
use crate::websocket::streams::ServerStream;

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
    websocket: WebSocketStream<ServerStream<TcpStream>>,
    data_plane_rx: flume::Receiver<Message>,
    control_plane_rx: flume::Receiver<Message>,
    shutdown_rx: oneshot::Receiver<ShutdownReason>,
}

impl Poller {
    /// Creates a new poller.
    pub fn new(
        websocket: WebSocketStream<ServerStream<TcpStream>>,
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
        let (mut ws_tx, mut ws_rx) = self.websocket.split();

        // Handle messages received from the WebSocket.
        let ws_rx_loop = async {
            loop {
                match ws_rx.next().await {
                    Some(Ok(Message::Close(_))) => {
                        tracing::info!("Connection closed by client {addr}");
                        return ShutdownReason::ClientClosed;
                    }
                    Some(Ok(msg)) => client.handle_message(msg),
                    Some(Err(err)) => {
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
