//! `sweetspot rig` as its own process feeding `sweetspot node` over real DDS on loopback (inside the private
//! network namespace of `scripts/test`): the rig is started first and waits for the node; every swing it
//! publishes gets an OK answer whose measured exit speed is the rig's and whose model exit speed is close to it.

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use sweetspot::msgs::sweetspot_msgs::msg::ExitVelocity;
use sweetspot::rig::dds::{context, Answer, AnswerListener, TopicNames};
use sweetspot::ros::{DdsConfig, DiscoveryRange};

struct Killed(Child);
impl Drop for Killed {
    fn drop(&mut self) {
        let _ = Command::new("kill").args(["-TERM", &self.0.id().to_string()]).status();
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(5) {
            if let Ok(Some(_)) = self.0.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn sweetspot(args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .args(args)
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn sweetspot")
}

#[test]
fn rig_process_feeds_a_node_and_every_swing_is_answered() {
    sweetspot::ros::network_guard().expect("DDS tests must run in a private network namespace (scripts/test)");
    const COUNT: u64 = 6;
    let ns = "/rigtest";
    let ctx = context(&DdsConfig { domain_id: 0, range: DiscoveryRange::Localhost }).unwrap();
    let listener = AnswerListener::new(&ctx, &TopicNames::in_namespace(ns).unwrap()).unwrap();

    let rig = sweetspot(&[
        "rig",
        "--namespace",
        ns,
        "--count",
        &COUNT.to_string(),
        "--rate",
        "20",
        "--bats",
        "r161,torpedo",
        "--swings-per-bat",
        "3",
        "--wait",
        "120",
    ]);
    std::thread::sleep(Duration::from_millis(500));
    let _node = Killed(sweetspot(&["node", "--no-record", "--ros-args", "-r", &format!("__ns:={ns}")]));

    let mut exits: Vec<ExitVelocity> = Vec::new();
    let start = Instant::now();
    while (exits.len() as u64) < COUNT && start.elapsed() < Duration::from_secs(240) {
        for a in listener.poll().0 {
            if let Answer::Exit(e) = a {
                exits.push(e);
            }
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let output = rig.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "rig failed: {}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(exits.len() as u64, COUNT, "answers: {exits:?}\nrig said:\n{stdout}");
    exits.sort_by_key(|e| e.swing_id);
    for (i, e) in exits.iter().enumerate() {
        assert_eq!(e.swing_id, i as u64 + 1);
        assert_eq!(e.status, ExitVelocity::STATUS_OK, "{}", e.message);
        assert_eq!(e.bat_id, if i < 3 { "r161" } else { "torpedo" });
        assert_eq!(e.ball_id, sweetspot::rig::RIG_BALL_ID);
        // The rig's radar reading is the physics plus noise (σ 0.45 m/s) on noisy inputs.
        assert!(e.measured_exit_speed.is_finite() && (e.measured_exit_speed - e.exit_speed).abs() < 4.0, "{e:?}");
        assert!(stdout.contains(&format!("swing {:>5}", e.swing_id)), "{stdout}");
    }
}
