//! `bag play`: the schedule keeps latched params first and the recorded timing; over real DDS (inside the
//! private network namespace of scripts/test) playing the golden bag into a fresh node reproduces its answers.

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use support::bag::sweetspot_bin;
use sweetspot::play::schedule;

/// ROS_DOMAIN_ID of these tests (other suites use 100.., 151..163).
const DOMAIN: u16 = 201;

fn golden() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden")
}

#[test]
fn schedule_puts_leading_params_first_and_keeps_recorded_timing() {
    let items = schedule(&golden(), &[], 1.0).unwrap();
    // 2 BatParams + 1 BallParams + 10 swings; outputs are never replayed.
    assert_eq!(items.len(), 13);
    assert!(items[..3].iter().all(|i| i.type_name != "sweetspot_msgs/msg/Swing" && i.at == Duration::ZERO));
    assert_eq!(items[3].type_name, "sweetspot_msgs/msg/Swing");
    assert_eq!(items[3].at, Duration::ZERO);
    assert!(items.windows(2).all(|w| w[0].at <= w[1].at));
    // The swings were published at 20 Hz: 9 gaps of ~50 ms.
    let span = items[12].at - items[3].at;
    assert!(span > Duration::from_millis(300) && span < Duration::from_secs(3), "{span:?}");
    let fast = schedule(&golden(), &[], 4.0).unwrap();
    assert_eq!(fast[12].at, items[12].at.div_f64(4.0));
    let only_swings = schedule(&golden(), &["/golden/swing".to_string()], 1.0).unwrap();
    assert_eq!(only_swings.len(), 10);
    let err = schedule(&golden(), &["/golden/exit_velocity".to_string()], 1.0).unwrap_err().to_string();
    assert!(err.contains("only inputs"), "{err}");
    let err = schedule(&golden(), &["/nope".to_string()], 1.0).unwrap_err().to_string();
    assert!(err.contains("/nope is not in the bag"), "{err}");
    assert!(schedule(&golden(), &[], 0.0).is_err());
}

fn exit_speeds(bag: &Path) -> Vec<(u64, String)> {
    let (rows, _) = sweetspot::bag::export::swing_rows(bag).unwrap();
    let mut out: Vec<(u64, String)> = rows
        .iter()
        .map(|r| {
            let ev = r
                .exit_velocity
                .as_ref()
                .unwrap_or_else(|| panic!("swing {} unanswered in {}", r.swing.swing_id, bag.display()));
            (r.swing.swing_id, format!("{} {:?} {:?}", ev.status, ev.exit_speed.to_bits(), ev.bat_id))
        })
        .collect();
    out.sort();
    out
}

#[test]
fn playing_the_golden_bag_into_a_node_reproduces_its_answers() {
    sweetspot::ros::network_guard().expect("DDS tests must run in a private network namespace (scripts/test)");
    let tmp = tempfile::tempdir().unwrap();
    let bag = tmp.path().join("played");
    let env = |c: &mut Command| {
        c.env("ROS_DOMAIN_ID", DOMAIN.to_string())
            .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
            .env_remove("ROS_LOCALHOST_ONLY");
    };
    let mut node = Command::new(sweetspot_bin());
    node.args(["node", "--ros-args", "-r", "__ns:=/golden", "-p"])
        .arg(format!("record_path:={}", bag.display()))
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    env(&mut node);
    let node = node.spawn().unwrap();
    let mut play = Command::new(sweetspot_bin());
    play.args(["bag", "play", "--rate", "4", "--wait-subscribers", "1", "--timeout", "30", "-q"]).arg(golden());
    env(&mut play);
    let out = play.output().unwrap();
    assert!(out.status.success(), "play failed: {}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("published 13 messages in 1 pass"));
    // Let the node answer the last swings, then stop it with SIGINT (it finishes the bag).
    let deadline = Instant::now() + Duration::from_secs(30);
    loop {
        std::thread::sleep(Duration::from_millis(200));
        let info = sweetspot::bag::info::bag_info(&bag).ok();
        let answered = info.and_then(|i| i.topics.iter().find(|t| t.name == "/golden/exit_velocity").map(|t| t.count));
        if answered.unwrap_or(0) >= 11 || Instant::now() > deadline {
            break;
        }
    }
    let status = Command::new("kill").args(["-INT", &node.id().to_string()]).status().unwrap();
    assert!(status.success());
    let out = node.wait_with_output().unwrap();
    assert!(out.status.success(), "node: {}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(exit_speeds(&bag), exit_speeds(&golden()), "the node answers the played inputs exactly as recorded");
    let replay = Command::new(sweetspot_bin()).args(["bag", "replay"]).arg(&bag).output().unwrap();
    assert!(replay.status.success(), "{}", String::from_utf8_lossy(&replay.stdout));
}
