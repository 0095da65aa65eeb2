//! Bounds on what clients send.
//!
//! tungstenite holds an unfinished message (its frames so far, and the frame being read) until its
//! last frame arrives, up to `max_message_size` (64 MiB by default) per connection: clients that
//! send large non-final fragments and stay connected would hold that much each. The client's side
//! of the protocol (subscriptions, advertisements, parameters, service calls, playback controls)
//! needs far less, so each connection is given a small `max_message_size` (and `max_frame_size`),
//! and [`Metered`] counts the bytes read from each client that have not yet made a whole message,
//! against a bound for all clients together ([`IncomingBudget`]).

use std::io;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::task::{Context, Poll};

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::TcpStream;
use tokio_tungstenite::tungstenite::{self, Message};

use super::streams::ServerStream;

/// A client's connection as the WebSocket reads and writes it.
pub(crate) type ClientStream = Metered<ServerStream<TcpStream>>;

/// Largest message (and frame) a client may send unless ServerOptions says otherwise.
pub(crate) const DEFAULT_MAX_MESSAGE_BYTES: usize = 1024 * 1024;
/// Bytes of unfinished messages all clients together may hold unless ServerOptions says otherwise.
pub(crate) const DEFAULT_TOTAL_INCOMING_BYTES: usize = 16 * 1024 * 1024;
/// A masked client frame's header without extended length: what a control frame (payload of at
/// most 125 bytes) adds to its payload on the wire.
const CONTROL_FRAME_HEADER: usize = 6;

/// The bytes read from all clients and not yet delivered as a whole message, and their bound.
#[derive(Debug)]
pub(crate) struct IncomingBudget {
    held: AtomicUsize,
    limit: usize,
    /// Connections open now, among which the bound is shared.
    connections: Arc<AtomicUsize>,
}

impl IncomingBudget {
    pub fn new(limit: usize, connections: Arc<AtomicUsize>) -> Self {
        Self {
            held: AtomicUsize::new(0),
            limit,
            connections,
        }
    }
}

/// One connection's share of the [`IncomingBudget`].
#[derive(Debug)]
pub(crate) struct ClientMeter {
    held: AtomicUsize,
    budget: Arc<IncomingBudget>,
}

/// The error a read from a client fails with once it holds its share of a full budget.
#[derive(Debug, thiserror::Error)]
#[error(
    "{held} bytes of unfinished messages held, the server's bound of {limit} bytes for {clients} clients is reached"
)]
pub(crate) struct BudgetFull {
    held: usize,
    limit: usize,
    clients: usize,
}

impl ClientMeter {
    pub fn new(budget: Arc<IncomingBudget>) -> Arc<Self> {
        Arc::new(Self {
            held: AtomicUsize::new(0),
            budget,
        })
    }

    /// Counts `n` bytes read from the client. When the total would pass the bound, a client that
    /// holds at least its share (the bound divided by the open connections) is refused; below its
    /// share it reads on, so the total stays within the bound plus a read per connection.
    fn take(&self, n: usize) -> Result<(), BudgetFull> {
        let held = self.held.load(Ordering::Acquire).saturating_add(n);
        let total = self.budget.held.load(Ordering::Acquire).saturating_add(n);
        if total > self.budget.limit {
            let clients = self.budget.connections.load(Ordering::Acquire).max(1);
            if held.saturating_mul(clients) >= self.budget.limit {
                return Err(BudgetFull {
                    held,
                    limit: self.budget.limit,
                    clients,
                });
            }
        }
        self.held.fetch_add(n, Ordering::AcqRel);
        self.budget.held.fetch_add(n, Ordering::AcqRel);
        Ok(())
    }

    fn release(&self, n: usize) {
        let mut released = 0;
        let _ = self
            .held
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |held| {
                released = held.min(n);
                Some(held - released)
            });
        self.budget.held.fetch_sub(released, Ordering::AcqRel);
    }

    /// Releases what `message` took. A data message is whole: everything read before it has been
    /// delivered (what the same read brought of the next frame, at most one read, is released with
    /// it). A control frame may arrive between the fragments of a data message, so it releases only
    /// its own bytes.
    pub fn delivered(&self, message: &Message) {
        match message {
            Message::Ping(payload) | Message::Pong(payload) => {
                self.release(payload.len() + CONTROL_FRAME_HEADER)
            }
            _ => self.release(usize::MAX),
        }
    }

    /// Releases everything held (the handshake's bytes, once it is done).
    pub fn clear(&self) {
        self.release(usize::MAX);
    }
}

impl Drop for ClientMeter {
    fn drop(&mut self) {
        self.budget
            .held
            .fetch_sub(*self.held.get_mut(), Ordering::AcqRel);
    }
}

/// Why a client's input ended its connection, if it was too much: a message over the bound
/// (tungstenite's `MessageTooLong`), or the client's share of the full budget.
pub(crate) enum Excess {
    Message { size: usize, max: usize },
    Budget(String),
}

impl Excess {
    pub fn of(err: &tungstenite::Error) -> Option<Self> {
        match err {
            tungstenite::Error::Capacity(tungstenite::error::CapacityError::MessageTooLong {
                size,
                max_size,
            }) => Some(Excess::Message {
                size: *size,
                max: *max_size,
            }),
            tungstenite::Error::Io(io) => io
                .get_ref()
                .and_then(|inner| inner.downcast_ref::<BudgetFull>())
                .map(|full| Excess::Budget(full.to_string())),
            _ => None,
        }
    }
}

/// A client's stream, counting what is read from it against its [`ClientMeter`].
#[derive(Debug)]
pub(crate) struct Metered<S> {
    inner: S,
    meter: Arc<ClientMeter>,
}

impl<S> Metered<S> {
    pub fn new(inner: S, meter: Arc<ClientMeter>) -> Self {
        Self { inner, meter }
    }

    pub fn meter(&self) -> &Arc<ClientMeter> {
        &self.meter
    }
}

impl<S: AsyncRead + Unpin> AsyncRead for Metered<S> {
    fn poll_read(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let before = buf.filled().len();
        match Pin::new(&mut this.inner).poll_read(cx, buf) {
            Poll::Ready(Ok(())) => {
                let n = buf.filled().len() - before;
                match this.meter.take(n) {
                    Ok(()) => Poll::Ready(Ok(())),
                    Err(full) => {
                        buf.set_filled(before);
                        Poll::Ready(Err(io::Error::other(full)))
                    }
                }
            }
            other => other,
        }
    }
}

impl<S: AsyncWrite + Unpin> AsyncWrite for Metered<S> {
    fn poll_write(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().inner).poll_write(cx, buf)
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().inner).poll_flush(cx)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().inner).poll_shutdown(cx)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        Pin::new(&mut self.get_mut().inner).poll_write_vectored(cx, bufs)
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn meter(limit: usize, connections: usize) -> (Arc<IncomingBudget>, Arc<ClientMeter>) {
        let budget = Arc::new(IncomingBudget::new(
            limit,
            Arc::new(AtomicUsize::new(connections)),
        ));
        (budget.clone(), ClientMeter::new(budget))
    }

    #[test]
    fn a_client_at_its_share_of_a_full_budget_is_refused_below_it_reads_on() {
        let (budget, a) = meter(100, 2);
        let b = ClientMeter::new(budget.clone());
        a.take(60).unwrap();
        b.take(40).unwrap();
        // The total is full: `a` holds more than its share (50), `b` less.
        assert!(a.take(1).is_err());
        b.take(9).unwrap();
        assert!(b.take(1).is_err(), "b now holds its share");
        assert_eq!(budget.held.load(Ordering::Acquire), 109);
        drop(b);
        assert_eq!(budget.held.load(Ordering::Acquire), 60);
        a.take(40).unwrap();
    }

    #[test]
    fn a_whole_message_releases_all_a_control_frame_its_own_bytes() {
        let (budget, a) = meter(1000, 1);
        a.take(500).unwrap();
        a.delivered(&Message::Ping(vec![0; 10].into()));
        assert_eq!(budget.held.load(Ordering::Acquire), 484);
        a.delivered(&Message::Text("x".into()));
        assert_eq!(budget.held.load(Ordering::Acquire), 0);
        a.delivered(&Message::Pong(vec![0; 10].into()));
        assert_eq!(budget.held.load(Ordering::Acquire), 0);
    }
}
