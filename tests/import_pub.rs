//! `import --pub`: a real TrackMan export sent straight to a running node (over real DDS, inside the private
//! network namespace of scripts/test) is answered swing by swing with the tracker's exit speed carried
//! through; `--rate` spaces the swings at the given rate instead of the rows' minutes apart.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use support::node::{dds, keep_all, NodeProcess, Peer};
use sweetspot::calibrate::read_inputs;
use sweetspot::msgs::sweetspot_msgs::msg::ExitVelocity;
use sweetspot::play::PlayOptions;

/// ROS_DOMAIN_ID of these tests (other suites use 100.., 151..163, 183, 201..228).
const DOMAIN: u16 = 231;
const WAIT: Duration = Duration::from_secs(30);

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/trackman_game.csv")
}

fn import_bag(dir: &Path) -> PathBuf {
    let bag = dir.join("game");
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "trackman"])
        .arg(fixture())
        .arg("-o")
        .arg(&bag)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    bag
}

#[test]
fn a_fixed_rate_spaces_the_swings_evenly_and_keeps_the_params_first() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = import_bag(tmp.path());
    // Recorded pace: the fixture's first and last swings are at 18:42:14.69 and 19:17:03.33 (34 min 48.64 s).
    let recorded = PlayOptions::new(1.0).schedule(&bag).unwrap().items;
    assert_eq!(recorded.len(), 7, "bat, ball, five swings");
    let span = recorded[6].at - recorded[2].at;
    assert!((span.as_secs_f64() - 2088.64).abs() < 0.01, "{span:?}");
    let fixed = PlayOptions { interval: Some(Duration::from_millis(250)), ..PlayOptions::new(1.0) };
    let items = fixed.schedule(&bag).unwrap().items;
    let at: Vec<u128> = items.iter().map(|i| i.at.as_millis()).collect();
    assert_eq!(at, [0, 0, 0, 250, 500, 750, 1000]);
    assert!(items[..2].iter().all(|i| i.type_name != "sweetspot_msgs/msg/Swing"));
}

#[test]
fn every_imported_swing_reaches_a_running_node_and_is_answered_with_its_measurement() {
    let tmp = tempfile::tempdir().unwrap();
    let kept = tmp.path().join("kept");
    // A node in a namespace, as a lab runs one per cage: --ns sends the swings there.
    let node = NodeProcess::spawn(DOMAIN, tmp.path(), &["--no-record", "--ros-args", "-r", "__ns:=/cage2"]);
    node.wait_for_log(" up on ROS_DOMAIN_ID ", WAIT);
    let mut peer = Peer::new(DOMAIN, "import_pub_peer");
    let answers = peer.subscription::<ExitVelocity>("/cage2/exit_velocity", keep_all(dds::results()));

    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "trackman"])
        .arg(fixture())
        .args(["--pub", "--rate", "4", "--ns", "/cage2", "--timeout", "30", "-o"])
        .arg(&kept)
        .env("ROS_DOMAIN_ID", DOMAIN.to_string())
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        .env_remove("ROS_LOCALHOST_ONLY")
        .output()
        .unwrap();
    let elapsed = start.elapsed();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "import --pub failed: {stderr}\nnode:\n{}", node.log());
    assert!(stderr.contains("published 7 messages in 1 pass"), "{stderr}");
    // Four gaps of 1/4 s between the five swings.
    assert!(elapsed >= Duration::from_secs(1), "{elapsed:?}");

    let got = peer.collect(&answers, 5, WAIT);
    // The kept bag holds what was sent: the tracker's rows as Swings, ids 1..5.
    let inputs = read_inputs(&kept).unwrap();
    assert_eq!(inputs.swings.len(), 5);
    for (_, swing) in &inputs.swings {
        let answer = got
            .iter()
            .find(|a| a.swing_id == swing.swing_id)
            .unwrap_or_else(|| panic!("swing {} unanswered: {got:?}", swing.swing_id));
        assert_eq!(answer.status, ExitVelocity::STATUS_OK, "{}", answer.message);
        assert_eq!(answer.measured_exit_speed.to_bits(), swing.measured_exit_speed.to_bits());
        assert_eq!(answer.header.stamp, swing.header.stamp, "the row's time is the answer's stamp");
    }
    let mut ids: Vec<u64> = got.iter().map(|a| a.swing_id).collect();
    ids.sort_unstable();
    assert_eq!(ids, [1, 2, 3, 4, 5]);
    // Line 3 of the export: ExitSpeed 90.41575 mph = 40.41946 m/s (× 0.44704), reaching the node unchanged.
    let first = got.iter().find(|a| a.swing_id == 1).unwrap();
    assert!((first.measured_exit_speed - 40.41946).abs() < 1e-5, "{}", first.measured_exit_speed);
    assert!((first.residual - (first.measured_exit_speed - first.exit_speed)).abs() < 1e-12);
}

#[test]
fn pub_without_output_keeps_no_bag_and_rate_needs_pub() {
    let tmp = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "trackman"])
        .arg(fixture())
        .args(["--rate", "4"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--pub"), "{}", String::from_utf8_lossy(&out.stderr));
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "trackman"])
        .arg(fixture())
        .args(["--pub", "--rate", "0"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("out of range"), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read_dir(tmp.path()).unwrap().next().is_none(), "nothing written where it ran");
}

#[test]
fn pub_alone_leaves_no_bag_behind() {
    support::require_isolated_network();
    let tmp = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(["import", "trackman"])
        .arg(fixture())
        .args(["--pub", "--rate", "100", "--no-wait", "--json"])
        .current_dir(tmp.path())
        .env("ROS_DOMAIN_ID", (DOMAIN + 1).to_string())
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        .env("TMPDIR", tmp.path())
        .env_remove("ROS_LOCALHOST_ONLY")
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["swings"], 5);
    assert!(report["bag"].is_null(), "no bag kept: {}", report["bag"]);
    assert!(stderr.contains("published 7 messages in 1 pass"), "{stderr}");
    let left: Vec<_> = std::fs::read_dir(tmp.path()).unwrap().map(|e| e.unwrap().path()).collect();
    assert!(left.is_empty(), "the temporary bag is removed, nothing else written: {left:?}");
}
