//! The ROS 2 command-line client: what `ros2 topic pub/echo`, `ros2 param`, `ros2 service call`, `ros2
//! topic/service/node list` and `ros2 interface` do, for sweetspot's topics and for any ROS 2 node, without a
//! ROS installation. Each of `pub`, `echo`, `param`, `call`, `topic`, `service`, `nodes` and `interface`
//! parses its flags in `cli/` and calls one function here.
//!
//! Inside, imports run one way: [`pubsub`] → [`kind`], [`values`]; [`call`] → [`values`], [`graph`];
//! [`param`] → [`graph`].

use std::borrow::Cow;

pub mod call;
pub mod graph;
pub mod kind;
pub mod param;
pub mod pubsub;
pub mod values;

/// Longest a graph listing listens to discovery (`--spin-time`), s: an hour. A listing prints only when the
/// wait is over, so a wait without end (inf) would never print.
pub const MAX_SPIN_TIME_SECS: f64 = 3600.0;

/// Longest a service call (`call`, `param`) waits for its answer (`--timeout`), s: a day. The answer is the
/// whole output, so a wait without end (inf) would never print.
pub const MAX_CALL_TIMEOUT_SECS: f64 = 86_400.0;

/// A user's name, type or request as an error message quotes it: at most
/// [`crate::model::limits::MAX_STRING_BYTES`] bytes, then `…(N bytes)`, so a 100-KB name is named, not repeated.
pub fn quoted(text: &str) -> Cow<'_, str> {
    crate::model::limits::echo(text)
}

/// Most bytes kept of an error from a lower layer that quotes a whole name (a ROS name's own check).
pub const MAX_QUOTING_ERROR_BYTES: usize = 1024;

/// `err` in at most [`MAX_QUOTING_ERROR_BYTES`] (and the marker): its start and its end, where the reason
/// stands, with the middle cut as `…(N bytes cut)…`.
pub fn bounded_error(err: impl std::fmt::Display) -> anyhow::Error {
    let text = err.to_string();
    if text.len() <= MAX_QUOTING_ERROR_BYTES {
        return anyhow::anyhow!(text);
    }
    let mut head = MAX_QUOTING_ERROR_BYTES / 2;
    while !text.is_char_boundary(head) {
        head -= 1;
    }
    let mut tail = text.len() - MAX_QUOTING_ERROR_BYTES / 2;
    while !text.is_char_boundary(tail) {
        tail += 1;
    }
    anyhow::anyhow!("{}…({} bytes cut)…{}", &text[..head], tail - head, &text[tail..])
}
