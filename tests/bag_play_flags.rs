//! `bag play` with rosbag2's flags, end to end over real DDS (inside the private network namespace of
//! scripts/test): the golden bag played into an in-test subscriber. The expectations come from the bag as an
//! independent reader (Python `mcap`) lists it, not from the player's schedule.

mod support;

use std::path::PathBuf;
use std::process::{Child, Command};
use std::time::Duration;

use support::node::{keep_all, Peer};
use support::{python, spawn_piped, sweetspot};
use sweetspot::msgs::rosgraph_msgs::msg::Clock;
use sweetspot::msgs::sweetspot_msgs::msg::Swing;

/// ROS_DOMAIN_ID of these tests (bag_play uses 201).
const REMAP_DOMAIN: u16 = 202;
const OFFSET_DOMAIN: u16 = 203;
const LOOP_DOMAIN: u16 = 204;
const CLOCK_DOMAIN: u16 = 205;

fn golden() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("bags/golden/sweetspot_golden")
}

/// Every message of the golden bag as (topic, log time ns), in log-time order, as Python's `mcap` reads it.
fn golden_log() -> Vec<(String, u64)> {
    let script = "import sys, glob\nfrom mcap.reader import make_reader\n\
                  f = sorted(glob.glob(sys.argv[1] + '/*.mcap'))[0]\n\
                  for s, c, m in make_reader(open(f, 'rb')).iter_messages(log_time_order=True):\n\
                  \x20   print(c.topic, m.log_time)\n";
    let out = Command::new(python()).arg("-c").arg(script).arg(golden()).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let (topic, t) = l.split_once(' ').unwrap();
            (topic.to_string(), t.parse().unwrap())
        })
        .collect()
}

fn swing_ids(swings: &[Swing]) -> Vec<u64> {
    swings.iter().map(|s| s.swing_id).collect()
}

/// Starts `bag play -q --wait-subscribers 1 GOLDEN ARGS [--ros-args ROS_ARGS]`. The test takes what it
/// expects while the player is up (a RustDDS reader may drop what it has not taken once the writer left).
fn start_play(domain: u16, args: &[&str], ros_args: &[&str]) -> Child {
    let mut c = sweetspot(domain, &["bag", "play", "-q", "--wait-subscribers", "1", "--timeout", "30"]);
    // The bag first: --topics takes every value that follows it.
    c.arg(golden()).args(args);
    if !ros_args.is_empty() {
        c.arg("--ros-args").args(ros_args);
    }
    spawn_piped(c)
}

/// Waits for the player; it must succeed. Returns its stderr.
fn finish(child: Child) -> String {
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "bag play failed: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn remap_publishes_on_the_new_topic() {
    let mut peer = Peer::new(REMAP_DOMAIN, "remap_listener");
    let moved = peer.subscription::<Swing>("/moved/swing", keep_all(sweetspot::ros::swing_qos()));
    let child = start_play(
        REMAP_DOMAIN,
        &["-r", "4", "--topics", "/golden/swing", "--remap", "/golden/swing:=/moved/swing"],
        &[],
    );
    let got = peer.collect(&moved, 10, Duration::from_secs(20));
    assert!(finish(child).contains("published 10 messages"));
    assert_eq!(swing_ids(&got), (1..=10).collect::<Vec<u64>>());

    // The same rule as a ROS argument, relative names taken from the root.
    let again = peer.subscription::<Swing>("/again/swing", keep_all(sweetspot::ros::swing_qos()));
    let child =
        start_play(REMAP_DOMAIN, &["-r", "4", "--topics", "/golden/swing"], &["-r", "golden/swing:=again/swing"]);
    let got = peer.collect(&again, 10, Duration::from_secs(20));
    finish(child);
    assert_eq!(swing_ids(&got), (1..=10).collect::<Vec<u64>>());
}

#[test]
fn start_offset_skips_the_swings_recorded_before_it() {
    let log = golden_log();
    let start = log[0].1;
    let swing_times: Vec<u64> = log.iter().filter(|(t, _)| t == "/golden/swing").map(|(_, t)| *t).collect();
    assert_eq!(swing_times.len(), 10);
    // Halfway between the 3rd and 4th swing, measured from the bag's first message.
    let offset_ns = (swing_times[2] + swing_times[3]) / 2 - start;
    let offset = format!("{:.6}", offset_ns as f64 / 1e9);
    let mut peer = Peer::new(OFFSET_DOMAIN, "offset_listener");
    let swings = peer.subscription::<Swing>("/golden/swing", keep_all(sweetspot::ros::swing_qos()));
    let child = start_play(OFFSET_DOMAIN, &["--topics", "/golden/swing", "--start-offset", &offset], &[]);
    let got = peer.collect(&swings, 7, Duration::from_secs(20));
    let stderr = finish(child);
    assert!(stderr.contains("published 7 messages"), "{stderr}");
    assert_eq!(swing_ids(&got), (4..=10).collect::<Vec<u64>>());
}

#[test]
fn loop_replays_until_interrupted() {
    let mut peer = Peer::new(LOOP_DOMAIN, "loop_listener");
    let swings = peer.subscription::<Swing>("/golden/swing", keep_all(sweetspot::ros::swing_qos()));
    let child = start_play(LOOP_DOMAIN, &["-l", "-r", "4", "--topics", "/golden/swing"], &[]);
    let got = peer.collect(&swings, 25, Duration::from_secs(20));
    let status = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(status.success());
    let stderr = finish(child);
    // Three passes and more, each the whole bag in order.
    assert_eq!(swing_ids(&got[..25]), (0..25).map(|k| k % 10 + 1).collect::<Vec<u64>>());
    assert!(stderr.contains("pass(es)"), "{stderr}");
}

#[test]
fn clock_publishes_the_bag_time() {
    let log = golden_log();
    let swing_times: Vec<u64> = log.iter().filter(|(t, _)| t == "/golden/swing").map(|(_, t)| *t).collect();
    let (first, last) = (swing_times[0], swing_times[9]);
    let mut peer = Peer::new(CLOCK_DOMAIN, "clock_listener");
    let clock = peer.subscription::<Clock>(
        "/clock",
        sweetspot::play::clock_qos().history(ros2_client::qos::History::KeepLast { depth: 1000 }),
    );
    let _swings = peer.subscription::<Swing>("/golden/swing", keep_all(sweetspot::ros::swing_qos()));
    // At half speed the 0.45 s of swings take 0.9 s: some 45 ticks at 50 Hz.
    let child = start_play(CLOCK_DOMAIN, &["--topics", "/golden/swing", "-r", "0.5", "--clock", "50"], &[]);
    let ticks = peer.collect_until(&clock, Duration::from_secs(20), |got| got.len() >= 20);
    finish(child);
    let ns: Vec<u64> = ticks.iter().map(|c| c.clock.sec as u64 * 1_000_000_000 + u64::from(c.clock.nanosec)).collect();
    // Bag time, not wall time: from the first swing's log time to the last one's (plus one tick at 0.5×).
    let slack = 20_000_000;
    assert!(ns.iter().all(|&t| t >= first && t <= last + slack), "{ns:?} outside [{first}, {last}]");
    assert!(ns.windows(2).all(|w| w[0] <= w[1]), "{ns:?}");
    assert!(ns[ns.len() - 1] - ns[0] > (last - first) / 4, "the clock advanced: {ns:?}");
}

#[test]
fn start_offset_keeps_the_params_in_force_and_skips_earlier_swings() {
    let log = golden_log();
    let start = log[0].1;
    let swing_times: Vec<u64> = log.iter().filter(|(t, _)| t == "/golden/swing").map(|(_, t)| *t).collect();
    let offset = Duration::from_nanos((swing_times[2] + swing_times[3]) / 2 - start);
    let schedule = sweetspot::play::schedule_from(&golden(), &[], 1.0, offset).unwrap();
    let params = log.iter().filter(|(t, _)| t.ends_with("/params")).count();
    let types: Vec<&str> = schedule.items.iter().map(|i| i.type_name.as_str()).collect();
    // Every param (all recorded before the swings) first, at once; then the 7 swings from the 4th on.
    assert!(types[..params].iter().all(|t| t.ends_with("Params")), "{types:?}");
    assert!(schedule.items[..params].iter().all(|i| i.at == Duration::ZERO));
    let swings: Vec<u64> = schedule.items[params..].iter().map(|i| i.log_time_ns).collect();
    assert_eq!(swings, swing_times[3..]);
    assert_eq!(schedule.origin_ns, swing_times[3]);
    assert_eq!(schedule.items[params].at, Duration::ZERO);
}
