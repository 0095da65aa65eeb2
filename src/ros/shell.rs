//! Small pieces every DDS command-line tool needs: ending cleanly on a signal and writing through a full
//! reliable send window.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use crate::msgs::RosMessage;

/// A reliable write that could not complete.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The readers did not take samples for `timeout` while the send window was full.
    #[error("the subscribers did not keep up for {:.1} s (send window full)", timeout.as_secs_f64())]
    Stalled { timeout: Duration },
    /// SIGINT/SIGTERM arrived while waiting for room in the send window.
    #[error("interrupted while the send window was full")]
    Interrupted,
    /// RustDDS refused the sample.
    #[error("DDS write failed: {0}")]
    Dds(String),
}

/// The process-wide flag set by SIGINT or SIGTERM, so loops end cleanly and DDS says goodbye to its peers.
/// The first call installs the handler (on a small thread of its own); later calls share the same flag.
pub fn interrupt_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let set = Arc::clone(&flag);
        std::thread::spawn(move || {
            let Ok(rt) = tokio::runtime::Builder::new_current_thread().enable_all().build() else {
                return;
            };
            rt.block_on(async move {
                use tokio::signal::unix::{signal, SignalKind};
                let (Ok(mut int), Ok(mut term)) = (signal(SignalKind::interrupt()), signal(SignalKind::terminate()))
                else {
                    return;
                };
                tokio::select! {
                    _ = int.recv() => {}
                    _ = term.recv() => {}
                }
                set.store(true, Ordering::Relaxed);
            });
        });
        flag
    })
    .clone()
}

/// Writes one sample, retrying while the reliable send window is full (the readers are slower than us),
/// for at most `timeout`, and giving up early once `interrupted` is set.
pub fn write_reliably<T: RosMessage>(
    writer: &rustdds::no_key::DataWriterCdr<T>,
    message: T,
    timeout: Duration,
    interrupted: &AtomicBool,
) -> Result<(), WriteError> {
    let start = Instant::now();
    let mut message = message;
    loop {
        match writer.write(message, Some(rustdds::Timestamp::now())) {
            Ok(()) => return Ok(()),
            Err(rustdds::dds::WriteError::WouldBlock { data }) => {
                if interrupted.load(Ordering::Relaxed) {
                    return Err(WriteError::Interrupted);
                }
                if start.elapsed() >= timeout {
                    return Err(WriteError::Stalled { timeout });
                }
                message = data;
                std::thread::sleep(Duration::from_millis(1));
            }
            Err(e) => return Err(WriteError::Dds(e.to_string())),
        }
    }
}
