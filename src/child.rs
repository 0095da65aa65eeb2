//! A `sweetspot` subcommand (usually `sweetspot node`) run as a child process: started with its arguments and
//! environment, watched while the parent waits for it over DDS, stopped with SIGTERM so that it closes its
//! bag, and its output collected for error messages. `demo` and `bench` both start their nodes with it.
//!
//! It knows nothing of DDS: whether the child is ready is something only the parent's DDS peers can see, so
//! the parent waits on those and asks [`ChildProcess::exited`] whether to stop waiting.

use std::ffi::OsString;
use std::fs::File;
use std::io::BufRead as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};

/// How long a child left running is given to exit after SIGTERM when its handle is dropped.
const DROP_GRACE: Duration = Duration::from_secs(3);

/// Lines of output quoted when a child fails.
const TAIL_LINES: usize = 15;

/// Where a child's output goes.
#[derive(Debug, Clone)]
enum OutputSink {
    /// stderr kept in memory, stdout discarded.
    Memory,
    /// stdout and stderr both written to this file.
    File(PathBuf),
}

/// How to start a child: the executable, its arguments, environment and working directory.
#[derive(Debug, Clone)]
pub struct ChildCommand {
    exe: PathBuf,
    args: Vec<OsString>,
    env: Vec<(OsString, OsString)>,
    current_dir: Option<PathBuf>,
    output: OutputSink,
    label: String,
}

impl ChildCommand {
    /// `exe node --ros-args`, to which [`ChildCommand::remap`] and [`ChildCommand::param`] append.
    pub fn node(exe: &Path) -> ChildCommand {
        ChildCommand::new(exe, "the node").arg("node").arg("--ros-args")
    }

    /// `exe` with no arguments yet; `label` names the child in messages (e.g. "the raw echo").
    pub fn new(exe: &Path, label: &str) -> ChildCommand {
        ChildCommand {
            exe: exe.to_path_buf(),
            args: Vec::new(),
            env: Vec::new(),
            current_dir: None,
            output: OutputSink::Memory,
            label: label.to_string(),
        }
    }

    /// One more argument.
    pub fn arg(mut self, arg: impl Into<OsString>) -> ChildCommand {
        self.args.push(arg.into());
        self
    }

    /// A ROS remapping `-r from:=to` (after `--ros-args`).
    pub fn remap(self, from: &str, to: &str) -> ChildCommand {
        self.arg("-r").arg(format!("{from}:={to}"))
    }

    /// A ROS parameter `-p name:=value` (after `--ros-args`).
    pub fn param(self, name: &str, value: impl std::fmt::Display) -> ChildCommand {
        self.arg("-p").arg(format!("{name}:={value}"))
    }

    /// An environment variable of the child (the rest is inherited).
    pub fn env(mut self, key: impl Into<OsString>, value: impl Into<OsString>) -> ChildCommand {
        self.env.push((key.into(), value.into()));
        self
    }

    /// The child's working directory (default: the parent's).
    pub fn current_dir(mut self, dir: &Path) -> ChildCommand {
        self.current_dir = Some(dir.to_path_buf());
        self
    }

    /// Writes the child's stdout and stderr to `log` (created or truncated) instead of keeping its stderr in
    /// memory; for children whose log the user should be able to read afterwards.
    pub fn log_to(mut self, log: &Path) -> ChildCommand {
        self.output = OutputSink::File(log.to_path_buf());
        self
    }

    /// Starts the child.
    pub fn spawn(self) -> Result<ChildProcess> {
        let mut command = Command::new(&self.exe);
        command.args(&self.args).envs(self.env.iter().map(|(k, v)| (k, v))).stdin(Stdio::null());
        if let Some(dir) = &self.current_dir {
            command.current_dir(dir);
        }
        match &self.output {
            OutputSink::Memory => {
                command.stdout(Stdio::null()).stderr(Stdio::piped());
            }
            OutputSink::File(log) => {
                let file = File::create(log).with_context(|| format!("cannot create '{}'", log.display()))?;
                command.stdout(file.try_clone().with_context(|| format!("log '{}'", log.display()))?).stderr(file);
            }
        }
        let mut child =
            command.spawn().with_context(|| format!("cannot start {} ('{}')", self.label, self.command_line()))?;
        let lines = Arc::new(Mutex::new(Vec::new()));
        let reader = child.stderr.take().map(|pipe| {
            let lines = Arc::clone(&lines);
            std::thread::spawn(move || {
                for line in std::io::BufReader::new(pipe).lines().map_while(Result::ok) {
                    if let Ok(mut l) = lines.lock() {
                        l.push(line);
                    }
                }
            })
        });
        Ok(ChildProcess { child, label: self.label, output: self.output, lines, reader })
    }

    fn command_line(&self) -> String {
        std::iter::once(self.exe.as_os_str())
            .chain(self.args.iter().map(OsString::as_os_str))
            .map(|a| a.to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// A running child; stopped (SIGTERM, then SIGKILL after a few seconds) when dropped.
pub struct ChildProcess {
    child: Child,
    label: String,
    output: OutputSink,
    lines: Arc<Mutex<Vec<String>>>,
    reader: Option<JoinHandle<()>>,
}

impl ChildProcess {
    /// The child's process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Why the child is gone, if it is (with the end of its output); `None` while it runs.
    pub fn exited(&mut self) -> Option<String> {
        match self.child.try_wait() {
            Ok(Some(status)) => {
                Some(format!("{} exited early ({status}); its log:\n{}", self.label, self.output_tail()))
            }
            Ok(None) => None,
            Err(e) => Some(format!("cannot watch {}: {e}", self.label)),
        }
    }

    /// Everything the child wrote so far (its stderr, or its log file).
    pub fn output(&self) -> String {
        match &self.output {
            OutputSink::Memory => self.lines.lock().map(|l| l.join("\n")).unwrap_or_default(),
            OutputSink::File(log) => std::fs::read_to_string(log).unwrap_or_default(),
        }
    }

    /// The last lines of [`ChildProcess::output`].
    pub fn output_tail(&self) -> String {
        let text = self.output();
        let lines: Vec<&str> = text.lines().collect();
        lines[lines.len().saturating_sub(TAIL_LINES)..].join("\n")
    }

    /// SIGTERM, then up to `grace` for the child to exit on its own (a node finishes its bag on the way out);
    /// killed after that. Ok only for a clean exit; either way the child is gone and its output complete.
    pub fn stop(&mut self, grace: Duration) -> Result<()> {
        let outcome = self.terminate(grace);
        if let Some(reader) = self.reader.take() {
            let _ = reader.join();
        }
        match outcome {
            Ok(Some(status)) if status.success() => Ok(()),
            Ok(Some(status)) => bail!("{} ended with {status}; its log:\n{}", self.label, self.output_tail()),
            Ok(None) => {
                bail!("{} did not stop within {:.0} s of SIGTERM and was killed", self.label, grace.as_secs_f64())
            }
            Err(e) => bail!("waiting for {}: {e}", self.label),
        }
    }

    /// The exit status after SIGTERM, or `None` if it had to be killed.
    fn terminate(&mut self, grace: Duration) -> std::io::Result<Option<ExitStatus>> {
        if self.child.try_wait()?.is_none() {
            let _ = Command::new("kill").args(["-TERM", &self.child.id().to_string()]).status();
        }
        let start = Instant::now();
        loop {
            if let Some(status) = self.child.try_wait()? {
                return Ok(Some(status));
            }
            if start.elapsed() >= grace {
                let _ = self.child.kill();
                let _ = self.child.wait();
                return Ok(None);
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for ChildProcess {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            let _ = self.stop(DROP_GRACE);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sh(script: &str) -> ChildCommand {
        ChildCommand::new(Path::new("/bin/sh"), "the script").arg("-c").arg(script)
    }

    #[test]
    fn stop_reports_a_clean_exit_after_sigterm_and_keeps_stderr() {
        let mut child =
            sh("trap 'echo bye >&2; exit 0' TERM; echo up >&2; while :; do sleep 0.01; done").spawn().unwrap();
        let start = Instant::now();
        while !child.output().contains("up") && start.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(child.exited(), None);
        child.stop(Duration::from_secs(10)).unwrap();
        assert_eq!(child.output(), "up\nbye");
    }

    #[test]
    fn an_early_exit_and_a_failed_stop_quote_the_log_file() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("child.log");
        let mut child = sh("echo out; echo err >&2; exit 3").log_to(&log).spawn().unwrap();
        let start = Instant::now();
        let reason = loop {
            if let Some(reason) = child.exited() {
                break reason;
            }
            assert!(start.elapsed() < Duration::from_secs(10), "the child did not exit");
            std::thread::sleep(Duration::from_millis(10));
        };
        assert!(reason.starts_with("the script exited early (exit status: 3)"), "{reason}");
        assert!(reason.ends_with("out\nerr"), "{reason}");
        let err = child.stop(Duration::from_secs(1)).unwrap_err().to_string();
        assert!(err.starts_with("the script ended with exit status: 3"), "{err}");
    }

    #[test]
    fn a_child_ignoring_sigterm_is_killed_after_the_grace() {
        let mut child = sh("trap '' TERM; echo up >&2; while :; do sleep 0.01; done").spawn().unwrap();
        let start = Instant::now();
        while !child.output().contains("up") && start.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(10));
        }
        let err = child.stop(Duration::from_millis(200)).unwrap_err().to_string();
        assert!(err.contains("did not stop within 0 s of SIGTERM and was killed"), "{err}");
        assert!(child.exited().is_some());
    }

    #[test]
    fn remaps_and_params_follow_ros_args() {
        let command = ChildCommand::node(Path::new("sweetspot")).remap("__ns", "/demo").param("record_path", "b");
        assert_eq!(command.command_line(), "sweetspot node --ros-args -r __ns:=/demo -p record_path:=b");
    }
}
