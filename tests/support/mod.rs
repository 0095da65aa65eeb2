//! The one support module of the integration tests (`mod support;`): the repository and Python lookup, the
//! private-network guard, and running the `sweetspot` binary and the Cyclone DDS peer on one domain of
//! loopback discovery; [`bag`] (hand-made topics and the Python bag readers), [`cli`] (running the binary for
//! CLI tests), [`foxglove`] (raw WebSocket frames, a process's resident memory), [`import`] (the import fixtures and default options), [`node`] (the node as a child process and an
//! in-test ROS 2 peer), [`rig`] (rig sessions recorded straight into a bag) and [`ros2`] (the checks against real ROS 2 from PyPI, per distribution).
#![allow(dead_code)]

pub mod bag;
pub mod cli;
pub mod foxglove;
pub mod import;
pub mod node;
pub mod rig;
pub mod ros2;

use std::path::PathBuf;
use std::process::{Child, Command, Output, Stdio};

use serde_json::Value;

/// The `sweetspot` binary under test.
pub const BIN: &str = env!("CARGO_BIN_EXE_sweetspot");

/// The Node.js test clients (tests/js; `scripts/test` runs `npm ci` there).
pub fn js_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/js")
}

/// `node tests/js/SCRIPT ARGS` with `env` set, stdout piped and read line by line, stderr inherited; panics
/// with the fix if the npm package `needs` is not installed.
pub fn node_client(
    script: &str,
    needs: &str,
    args: &[&str],
    env: &[(&str, &str)],
) -> (Child, std::io::BufReader<std::process::ChildStdout>) {
    let modules = js_dir().join("node_modules").join(needs);
    assert!(modules.is_dir(), "{} missing: run `bash scripts/test` (it runs npm ci in tests/js)", modules.display());
    let mut child = Command::new("node")
        .arg(js_dir().join(script))
        .args(args)
        .envs(env.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .expect("starting node (Node.js); scripts/test installs it");
    let out = std::io::BufReader::new(child.stdout.take().expect("piped stdout"));
    (child, out)
}

/// The repository root.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The Python with the independent peers (mcap, mcap-ros2-support, rosbags, cyclonedds): $SWEETSPOT_PYTHON,
/// else <repo>/.venv/bin/python; a test that needs it fails without it, never skips.
pub fn python() -> PathBuf {
    if let Some(p) = std::env::var_os("SWEETSPOT_PYTHON") {
        let p = PathBuf::from(p);
        assert!(p.exists(), "SWEETSPOT_PYTHON={} does not exist", p.display());
        return p;
    }
    let venv = repo().join(".venv/bin/python");
    assert!(
        venv.exists(),
        "no Python for the independent checks and peers: set SWEETSPOT_PYTHON or create {} (scripts/test does)",
        venv.display()
    );
    venv
}

/// Refuses to go on unless this process is in a private network namespace (scripts/test provides one).
pub fn require_isolated_network() {
    sweetspot::ros::network_guard().expect("DDS tests must run in a private network namespace (scripts/test)");
}

/// Puts `c` on DDS `domain` with loopback-only discovery, whatever the caller's environment says.
pub fn dds_env(c: &mut Command, domain: u16) -> &mut Command {
    c.env("ROS_DOMAIN_ID", domain.to_string())
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        .env_remove("ROS_LOCALHOST_ONLY")
        .env_remove("CYCLONEDDS_URI")
}

/// `sweetspot ARGS` on `domain`.
pub fn sweetspot(domain: u16, args: &[&str]) -> Command {
    let mut c = Command::new(BIN);
    c.args(args);
    dds_env(&mut c, domain);
    c
}

/// The Cyclone DDS peer (tests/python/cyclone_peer.py, kept on loopback) with `args`, on `domain`.
pub fn cyclone_peer(domain: u16, args: &[&str]) -> Command {
    let mut c = Command::new(python());
    c.arg(repo().join("tests/python/cyclone_peer.py")).arg("--loopback").args(args);
    dds_env(&mut c, domain);
    c
}

/// Starts `c` with stdout and stderr piped.
pub fn spawn_piped(mut c: Command) -> Child {
    c.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().expect("spawn")
}

/// Panics with `what`, stderr and stdout unless `out` is a success.
pub fn assert_success(out: &Output, what: &str) {
    assert!(
        out.status.success(),
        "{what} failed: {}\n{}",
        String::from_utf8_lossy(&out.stderr),
        String::from_utf8_lossy(&out.stdout)
    );
}

/// Runs `c` to completion; it must succeed.
pub fn run_ok(mut c: Command, what: &str) -> Output {
    let out = c.output().expect("run");
    assert_success(&out, what);
    out
}

/// The JSON lines `what` printed; it must have succeeded.
pub fn json_lines(out: &Output, what: &str) -> Vec<Value> {
    assert_success(out, what);
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{what}: bad JSON line {l:?}: {e}")))
        .collect()
}

/// Panics unless every field of `expected` (a JSON object, or an array of them) is in `got` with the same value:
/// messages grow fields at their end, and a peer that sent the older form gets the newer one back.
pub fn assert_json_fields(got: &Value, expected: &Value, what: &str) {
    match (got, expected) {
        (Value::Array(g), Value::Array(e)) => {
            assert_eq!(g.len(), e.len(), "{what}: {got} vs {expected}");
            for (g, e) in g.iter().zip(e) {
                assert_json_fields(g, e, what);
            }
        }
        (Value::Object(g), Value::Object(e)) => {
            for (key, value) in e {
                assert_eq!(g.get(key), Some(value), "{what}: field {key} in {got}");
            }
        }
        _ => assert_eq!(got, expected, "{what}"),
    }
}

/// Two JSON documents equal as Foxglove's decoders give them: numbers compared as f64 (JavaScript writes 5.0 as 5),
/// `nsec` taken for `nanosec`, everything else exactly.
pub fn same_json(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => x.as_f64() == y.as_f64(),
        (Value::Object(x), Value::Object(y)) => {
            // Foxglove's decoders name builtin_interfaces/Time's `nanosec` `nsec`.
            let key = |k: &str| if k == "nsec" { "nanosec".to_string() } else { k.to_string() };
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(&key(k)).is_some_and(|w| same_json(v, w)))
        }
        (Value::Array(x), Value::Array(y)) => x.len() == y.len() && x.iter().zip(y).all(|(v, w)| same_json(v, w)),
        // NaN (a measurement not given) is null in JSON on both sides.
        _ => a == b,
    }
}
