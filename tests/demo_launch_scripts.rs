//! The launch scripts: every script parses, and `launch-scripts/demo.sh` runs a short demo with the binary
//! named by SWEETSPOT_BIN, defaulting discovery to LOCALHOST (inside the private network namespace of
//! `scripts/test`, since it starts DDS).

use std::path::Path;
use std::process::Command;

fn scripts() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/launch-scripts"))
}

#[test]
fn every_launch_script_parses() {
    for name in ["common.sh", "demo.sh", "rig.sh", "record.sh", "play.sh"] {
        let status = Command::new("bash").arg("-n").arg(scripts().join(name)).status().unwrap();
        assert!(status.success(), "{name} does not parse");
    }
    let launch = std::fs::read_to_string(scripts().join("sweetspot.launch.py")).unwrap();
    assert!(launch.contains("def generate_launch_description") && launch.contains("ExecuteProcess"));
}

#[test]
fn demo_script_runs_a_demo_with_localhost_discovery() {
    sweetspot::ros::network_guard().expect("DDS tests must run in a private network namespace (scripts/test)");
    let tmp = tempfile::tempdir().unwrap();
    let output = Command::new("bash")
        .arg(scripts().join("demo.sh"))
        .args(["--swings", "4", "--bats", "r161", "--no-figures", "--out"])
        .arg(tmp.path())
        .env("SWEETSPOT_BIN", env!("CARGO_BIN_EXE_sweetspot"))
        .env_remove("ROS_AUTOMATIC_DISCOVERY_RANGE")
        .env_remove("ROS_LOCALHOST_ONLY")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST"), "{stderr}");
    assert!(stderr.contains("discovery LOCALHOST"), "{stderr}");
    assert!(stdout.lines().any(|l| l.starts_with("r161 ") && l.split_whitespace().nth(1) == Some("4")), "{stdout}");
    assert!(stdout.contains("bag:") && stdout.contains("(4 swings, 4 exit velocities"), "{stdout}");
}
