//! Pause and resume `bag play` with the space bar, as `ros2 bag play` does, when stdin is a terminal.
//!
//! The terminal goes into non-canonical mode without echo (keys arrive one at a time and are not printed)
//! while signals stay on, so Ctrl-C still stops the player; the previous settings come back when the
//! [`SpaceBarPause`] is dropped. With stdin not a terminal (a pipe, a file, a test) nothing is touched.

use std::io::{IsTerminal, Read};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The terminal in single-key mode and a thread toggling [`SpaceBarPause::paused`] on every space.
pub struct SpaceBarPause {
    saved: libc::termios,
    /// Set while playback is paused.
    pub paused: Arc<AtomicBool>,
}

impl SpaceBarPause {
    /// Starts listening if stdin is a terminal whose settings can be changed; `None` otherwise.
    pub fn on_terminal() -> Option<SpaceBarPause> {
        if !std::io::stdin().is_terminal() {
            return None;
        }
        // SAFETY: tcgetattr fills the termios it is given; it is only used if the call succeeded.
        let mut saved: libc::termios = unsafe { std::mem::zeroed() };
        if unsafe { libc::tcgetattr(libc::STDIN_FILENO, &mut saved) } != 0 {
            return None;
        }
        let mut keys = saved;
        keys.c_lflag &= !(libc::ICANON | libc::ECHO);
        keys.c_cc[libc::VMIN] = 1;
        keys.c_cc[libc::VTIME] = 0;
        // SAFETY: a valid termios for the descriptor it was read from.
        if unsafe { libc::tcsetattr(libc::STDIN_FILENO, libc::TCSANOW, &keys) } != 0 {
            return None;
        }
        let paused = Arc::new(AtomicBool::new(false));
        let toggle = Arc::clone(&paused);
        let spawned = std::thread::Builder::new().name("play-keys".to_string()).spawn(move || {
            let mut stdin = std::io::stdin();
            let mut key = [0u8; 1];
            // Ends with stdin (EOF or error); the process does not wait for it.
            while let Ok(1) = stdin.read(&mut key) {
                if key[0] == b' ' {
                    let now_paused = !toggle.fetch_xor(true, Ordering::Relaxed);
                    eprintln!("{}", if now_paused { "paused (space to resume)" } else { "resumed" });
                }
            }
        });
        let pause = SpaceBarPause { saved, paused };
        // Dropping `pause` here restores the terminal if the thread could not start.
        spawned.ok().map(|_| pause)
    }
}

impl Drop for SpaceBarPause {
    fn drop(&mut self) {
        // SAFETY: the settings read from this descriptor in `on_terminal`.
        unsafe { libc::tcsetattr(libc::STDIN_FILENO, libc::TCSANOW, &self.saved) };
    }
}
