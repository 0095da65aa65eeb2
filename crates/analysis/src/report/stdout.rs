//! Standard output for every command that prints: once the reader closes the pipe (`| head`), everything
//! later is dropped and reported as written, and [`closed`] says so, so a command ends quietly with status 0,
//! as Unix filters do, instead of panicking or blaming its input; a command that would print for ever (a rig,
//! `pub --rate`, `echo`) stops when it sees [`closed`].

use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context as _, Result};

/// Set once a write to stdout met a closed pipe.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Whether stdout's reader has gone (a write met EPIPE): nothing printed from now on is read.
pub fn closed() -> bool {
    CLOSED.load(Ordering::Relaxed)
}

/// Writes `text` to stdout; a closed pipe (e.g. `| head`) ends the output quietly instead of panicking.
pub fn emit(text: &str) -> Result<()> {
    use std::io::Write;
    Stdout::default().write_all(text.as_bytes()).context("cannot write to stdout")
}

/// Standard output that treats a closed pipe as the end of the output (see the module docs).
#[derive(Debug, Default)]
pub struct Stdout {
    /// Nothing: the state ([`closed`]) is the process's, shared by every handle.
    _shared: (),
}

/// `result` of a write to stdout, with a broken pipe turned into "written" (and [`closed`] set).
fn absorb_broken_pipe<T>(result: std::io::Result<T>, written: T) -> std::io::Result<T> {
    match result {
        Err(err) if err.kind() == std::io::ErrorKind::BrokenPipe => {
            CLOSED.store(true, Ordering::Relaxed);
            Ok(written)
        }
        other => other,
    }
}

impl std::io::Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if closed() {
            return Ok(buf.len());
        }
        absorb_broken_pipe(std::io::stdout().lock().write(buf), buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if closed() {
            return Ok(());
        }
        absorb_broken_pipe(std::io::stdout().lock().flush(), ())
    }
}
