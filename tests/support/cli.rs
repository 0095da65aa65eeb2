//! Runs the real `sweetspot` binary for the CLI tests.

use std::path::Path;
use std::process::{Command, Output};

pub use super::repo;

/// The outcome of one run.
pub struct Run {
    pub status_ok: bool,
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

/// Runs `sweetspot ARGS` from the repository root.
pub fn sweetspot(args: &[&str]) -> Run {
    let output: Output = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(args)
        .current_dir(repo())
        .output()
        .unwrap_or_else(|e| panic!("cannot run sweetspot: {e}"));
    Run {
        status_ok: output.status.success(),
        code: output.status.code(),
        stdout: String::from_utf8_lossy(&output.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
    }
}

/// Runs and expects success; returns stdout.
pub fn ok(args: &[&str]) -> String {
    let run = sweetspot(args);
    assert!(run.status_ok, "sweetspot {args:?} failed ({:?}):\n{}", run.code, run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
    run.stdout
}

/// Runs with `--json` appended and parses stdout as one JSON document.
pub fn json(args: &[&str]) -> serde_json::Value {
    let mut all = args.to_vec();
    all.push("--json");
    let text = ok(&all);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("stdout of {all:?} is not JSON ({e}):\n{text}"))
}

/// Runs and expects a clean failure (non-zero exit, a message, no panic); returns stderr.
pub fn fails(args: &[&str]) -> String {
    let run = sweetspot(args);
    assert!(!run.status_ok, "sweetspot {args:?} should fail but printed:\n{}", run.stdout);
    assert!(run.code.is_some_and(|c| c != 0), "killed by a signal? {:?}", run.code);
    assert!(!run.stderr.contains("panicked"), "sweetspot {args:?} panicked:\n{}", run.stderr);
    assert!(!run.stderr.trim().is_empty(), "no error message for {args:?}");
    run.stderr
}

/// A number from a JSON document.
pub fn num(v: &serde_json::Value, pointer: &str) -> f64 {
    v.pointer(pointer).and_then(serde_json::Value::as_f64).unwrap_or_else(|| panic!("no number at {pointer} in {v}"))
}

/// Path as &str.
pub fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}
