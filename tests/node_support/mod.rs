//! Shared helpers of the node tests: the `sweetspot node` process, a unique DDS domain per test, and an
//! in-test ros2-client participant. Every DDS use goes through the msgs helper's network guard first.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A running `sweetspot node`; killed if the test ends without stopping it.
pub struct NodeProcess {
    child: Option<Child>,
    stderr: Arc<Mutex<Vec<String>>>,
}

impl NodeProcess {
    /// Starts the node binary on `domain` in `cwd` with `args` after `node`.
    pub fn spawn(domain: u16, cwd: &Path, args: &[&str]) -> NodeProcess {
        let mut child = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
            .arg("node")
            .args(args)
            .current_dir(cwd)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("RUST_LOG", "info,rustdds=error,ros2_client=error")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("starting the sweetspot binary");
        let stderr = Arc::new(Mutex::new(Vec::new()));
        let pipe = child.stderr.take().expect("piped stderr");
        let lines = Arc::clone(&stderr);
        std::thread::spawn(move || {
            for line in BufReader::new(pipe).lines().map_while(Result::ok) {
                lines.lock().unwrap().push(line);
            }
        });
        NodeProcess { child: Some(child), stderr }
    }

    /// Waits until a stderr line contains `needle` (panics with the log after `limit`).
    pub fn wait_for_log(&self, needle: &str, limit: Duration) {
        let start = Instant::now();
        loop {
            if self.stderr.lock().unwrap().iter().any(|l| l.contains(needle)) {
                return;
            }
            if start.elapsed() > limit {
                panic!("node never logged '{needle}'; stderr:\n{}", self.log());
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    /// Everything the node wrote to stderr so far.
    pub fn log(&self) -> String {
        self.stderr.lock().unwrap().join("\n")
    }

    /// Sends `signal` (e.g. libc SIGTERM = 15) and waits for the exit; returns status, time to exit, log.
    pub fn stop_with(mut self, signal: i32) -> (ExitStatus, Duration, String) {
        let mut child = self.child.take().expect("running");
        let pid = child.id().to_string();
        let sent = Instant::now();
        let status = Command::new("kill").arg(format!("-{signal}")).arg(&pid).status().expect("kill");
        assert!(status.success(), "kill -{signal} {pid} failed");
        // Generous limit only to turn a hang into a failure instead of a stuck suite.
        loop {
            if let Some(status) = child.try_wait().expect("try_wait") {
                let elapsed = sent.elapsed();
                std::thread::sleep(Duration::from_millis(50)); // let the stderr reader drain
                return (status, elapsed, self.log());
            }
            if sent.elapsed() > Duration::from_secs(30) {
                let _ = child.kill();
                panic!("node did not exit within 30 s of signal {signal}; stderr:\n{}", self.log());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for NodeProcess {
    fn drop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// A DDS domain id unique to one test (parallel tests never share one). Node tests use 100..=199.
pub fn domain(offset: u16) -> u16 {
    100 + offset
}

/// The Python interpreter with the test peers installed: $SWEETSPOT_PYTHON, else <repo>/.venv/bin/python.
pub fn python() -> PathBuf {
    if let Ok(p) = std::env::var("SWEETSPOT_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join(".venv/bin/python");
    assert!(
        venv.exists(),
        "no Python for the interop test: set SWEETSPOT_PYTHON or create {} (scripts/test does)",
        venv.display()
    );
    venv
}
