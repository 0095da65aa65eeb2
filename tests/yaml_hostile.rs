//! Hostile YAML against every command that reads YAML: a "billion laughs" (anchors of aliases of aliases, a
//! few hundred bytes that expand into hundreds of millions of nodes) and a nest deeper than the stack. Each is
//! refused with a message that names the limit and the input, with a non-zero exit status, never a signal:
//! `simulate --case`, `call`, `pub` (argument and `--file`), `node --params-file`, `--ros-args -p`,
//! `param set`, `bag info` (the bomb in a bag's `metadata.yaml`) and `bag record --qos-profile-overrides-path`.
//!
//! The commands that would go on to DDS refuse the text first; they run with DDS discovery off
//! (`ROS_AUTOMATIC_DISCOVERY_RANGE=OFF`, no network at all), so no packet could leave even if one did not.
//! Every run is held to 1 GiB of address space: a bomb that got past the budget ends in an allocation failure
//! within a second instead of taking the machine's memory.

mod support;

use std::path::Path;
use std::process::Command;

use support::BIN;

const BOMB: &str = "YAML aliases expand past";
const DEEP: &str = "YAML nested deeper than 128 levels";

/// Nine anchors of nine aliases each: 9^9 ≈ 387 million strings once expanded, 498 bytes as a block mapping.
fn bomb() -> String {
    let mut text = "a0: &a0 lol\n".to_string();
    for level in 1..=9 {
        text += &format!("a{level}: &a{level} [{}]\n", vec![format!("*a{}", level - 1); 9].join(", "));
    }
    text
}

/// The same bomb as one flow sequence (for a value on the command line).
fn flow_bomb() -> String {
    let mut items = vec!["&a0 lol".to_string()];
    for level in 1..=9 {
        items.push(format!("&a{level} [{}]", vec![format!("*a{}", level - 1); 9].join(", ")));
    }
    format!("[{}]", items.join(", "))
}

/// `levels` block sequences, one inside the other: `- - - … 1`.
fn deep(levels: usize) -> String {
    "- ".repeat(levels) + "1"
}

/// The nest as a value on the command line, where a leading `-` would read as a flag: `swing:` then the nest.
/// 60,000 levels (120 kB, under Linux's 128 KiB limit on one argument) overflowed yaml-rust2's own loader.
fn deep_argument(levels: usize) -> String {
    format!("swing:\n{}", deep(levels))
}

/// Runs `sweetspot ARGS` under a 1 GiB address-space limit with DDS discovery off; expects a clean refusal:
/// a non-zero exit code (not a signal), no panic, and `expected` in the message. Returns stderr.
fn refused(args: &[&str], expected: &str) -> String {
    let output = Command::new("bash")
        .arg("-c")
        .arg("ulimit -v 1048576 && exec \"$0\" \"$@\"")
        .arg(BIN)
        .args(args)
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "OFF")
        .env("ROS_DOMAIN_ID", "143")
        .env_remove("ROS_LOCALHOST_ONLY")
        .current_dir(support::repo())
        .output()
        .expect("running sweetspot");
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    let shown = |s: &str| s.chars().take(2000).collect::<String>();
    let what = args.iter().map(|a| shown(a).chars().take(60).collect::<String>()).collect::<Vec<_>>();
    assert!(
        output.status.code().is_some(),
        "sweetspot {what:?} was killed by {:?}:\n{}",
        output.status,
        shown(&stderr)
    );
    assert_ne!(output.status.code(), Some(0), "sweetspot {what:?} accepted it");
    assert!(!stderr.contains("panicked"), "sweetspot {what:?} panicked:\n{}", shown(&stderr));
    assert!(stderr.contains(expected), "sweetspot {what:?}: no {expected:?} in:\n{}", shown(&stderr));
    stderr
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn the_bomb_is_under_500_bytes_and_the_nest_20_kb() {
    assert_eq!(bomb().len(), 498);
    assert_eq!(deep(10_000).len(), 20_001);
}

#[test]
fn simulate_refuses_a_hostile_case_file() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, expected) in [("bomb.yaml", bomb(), BOMB), ("deep.yaml", deep(10_000), DEEP)] {
        let path = write(dir.path(), name, &text);
        let stderr = refused(&["simulate", "--case", &path], expected);
        assert!(stderr.contains(name), "the case file is named: {stderr}");
    }
}

#[test]
fn call_refuses_a_hostile_request_before_any_dds() {
    for (text, expected) in [(flow_bomb(), BOMB), (deep_argument(10_000), DEEP)] {
        let stderr = refused(&["call", "simulate_swing", &text, "--timeout", "30"], expected);
        assert!(stderr.contains("the message"), "{}", &stderr[stderr.len().saturating_sub(300)..]);
    }
}

#[test]
fn pub_refuses_a_hostile_message_and_file() {
    let dir = tempfile::tempdir().unwrap();
    for (text, expected) in [(flow_bomb(), BOMB), (deep_argument(10_000), DEEP)] {
        refused(&["pub", "swing", &text, "--timeout", "30"], expected);
    }
    for (name, text, expected) in [("bomb.yaml", bomb(), BOMB), ("deep.yaml", deep(10_000), DEEP)] {
        let path = write(dir.path(), name, &text);
        let stderr = refused(&["pub", "swing", "--file", &path, "--timeout", "30"], expected);
        assert!(stderr.contains(name), "the file is named: {stderr}");
    }
}

#[test]
fn node_refuses_a_hostile_params_file_and_parameter_value() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, expected) in [("bomb.yaml", bomb(), BOMB), ("deep.yaml", deep(200_000), DEEP)] {
        let path = write(dir.path(), name, &text);
        let stderr = refused(&["node", "--no-record", "--ros-args", "--params-file", &path], expected);
        assert!(stderr.contains(name), "the parameter file is named: {stderr}");
    }
    let deep_flow = "[".repeat(129) + &"]".repeat(129);
    for (text, expected) in [(flow_bomb(), BOMB), (deep_flow, DEEP), (deep_argument(60_000), DEEP)] {
        let value = format!("default_bat:={text}");
        let stderr = refused(&["node", "--no-record", "--ros-args", "-p", &value], expected);
        assert!(stderr.contains("default_bat"), "the parameter is named: {stderr}");
    }
}

#[test]
fn param_set_refuses_a_hostile_value_before_any_dds() {
    for (text, expected) in [(flow_bomb(), BOMB), (deep_argument(60_000), DEEP)] {
        // With no node to answer, a value read after the DDS lookup would fail on the timeout instead.
        let stderr = refused(&["param", "set", "/sweetspot", "default_bat", &text, "--timeout", "30"], expected);
        assert!(stderr.contains("default_bat"), "the parameter is named: {stderr}");
    }
}

#[test]
fn bag_info_refuses_a_bag_whose_metadata_is_hostile() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, expected) in [("bomb", bomb(), BOMB), ("deep", deep(200_000), DEEP)] {
        let bag = dir.path().join(name);
        std::fs::create_dir(&bag).unwrap();
        write(&bag, "metadata.yaml", &text);
        let stderr = refused(&["bag", "info", bag.to_str().unwrap()], expected);
        assert!(stderr.contains("metadata.yaml"), "the file is named: {stderr}");
    }
}

#[test]
fn bag_record_refuses_a_hostile_qos_override_file_before_any_dds() {
    let dir = tempfile::tempdir().unwrap();
    for (name, text, expected) in [("bomb.yaml", bomb(), BOMB), ("deep.yaml", deep(200_000), DEEP)] {
        let path = write(dir.path(), name, &text);
        let out = dir.path().join(format!("{name}.bag"));
        let args = ["bag", "record", "-a", "-o", out.to_str().unwrap(), "--qos-profile-overrides-path", &path];
        let stderr = refused(&args, expected);
        assert!(stderr.contains(name), "the file is named: {stderr}");
        assert!(!out.exists(), "nothing recorded");
    }
}
