//! What `ROS_AUTOMATIC_DISCOVERY_RANGE` really does on the wire with RustDDS.
//!
//! Each case runs a participant in a nested private network namespace that has, besides `lo`, a veth pair
//! (`v0` 10.199.0.1 ↔ `v1` 10.199.0.2, both multicast-capable, IPv6 off so nothing else talks), and counts the
//! packets the participant makes each interface transmit. LOCALHOST must transmit on `lo` only; SUBNET must
//! also transmit on `v0` (so the counter can see leaks); OFF must transmit nothing at all.

use std::process::Command;

const CHILD_ENV: &str = "SWEETSPOT_RANGE_CHILD";

fn tx_packets() -> Vec<(String, u64)> {
    let dev = std::fs::read_to_string("/proc/self/net/dev").expect("read /proc/self/net/dev");
    dev.lines()
        .skip(2)
        .filter_map(|l| {
            let (name, rest) = l.split_once(':')?;
            let fields: Vec<u64> = rest.split_whitespace().filter_map(|f| f.parse().ok()).collect();
            Some((name.trim().to_string(), *fields.get(9)?))
        })
        .collect()
}

fn tx_of(counters: &[(String, u64)], name: &str) -> u64 {
    counters.iter().find(|(n, _)| n == name).map(|(_, c)| *c).unwrap_or(0)
}

/// Runs the child in a nested namespace and returns (lo, v0) packets transmitted while the participant ran.
fn run_child(range: &str) -> (u64, u64) {
    sweetspot::ros::network_guard().expect("DDS tests must run in a private network namespace (scripts/test)");
    let exe = std::env::current_exe().expect("test binary path");
    let setup = "set -e
        echo 1 > /proc/sys/net/ipv6/conf/all/disable_ipv6
        echo 1 > /proc/sys/net/ipv6/conf/default/disable_ipv6
        ip link set lo up multicast on
        ip route add 224.0.0.0/4 dev lo
        ip link add v0 type veth peer name v1
        ip addr add 10.199.0.1/24 dev v0
        ip addr add 10.199.0.2/24 dev v1
        ip link set v1 up multicast on
        ip link set v0 up multicast on
        exec \"$0\" --ignored --exact range_child --nocapture --test-threads 1";
    let out = Command::new("unshare")
        .args(["--net", "--", "bash", "-c", setup])
        .arg(&exe)
        .env(CHILD_ENV, range)
        .env_remove("SWEETSPOT_TEST_NETNS") // the nested namespace has v0/v1 of its own; the child checks them
        .env_remove("ROS_LOCALHOST_ONLY")
        .output()
        .expect("run unshare");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "child for {range} failed (nested `unshare --net` needed):\n{stdout}\n{stderr}");
    let line = stdout
        .lines()
        .find_map(|l| l.split_once("RESULT ").map(|(_, r)| r))
        .unwrap_or_else(|| panic!("no RESULT from child:\n{stdout}\n{stderr}"));
    let nums: Vec<u64> = line.split_whitespace().filter_map(|kv| kv.split_once('=')?.1.parse().ok()).collect();
    (nums[0], nums[1])
}

#[test]
fn ros_range_localhost_transmits_on_loopback_only() {
    let (lo, v0) = run_child("LOCALHOST");
    assert!(lo > 0, "a LOCALHOST participant should still announce itself on lo");
    assert_eq!(v0, 0, "a LOCALHOST participant transmitted {v0} packets on a non-loopback interface");
}

#[test]
fn ros_range_subnet_reaches_other_interfaces() {
    // The control case: proves the counters see traffic on v0 when discovery is meant to reach it.
    let (_lo, v0) = run_child("SUBNET");
    assert!(v0 > 0, "a SUBNET participant should announce itself on v0");
}

#[test]
fn ros_range_off_transmits_nothing_at_all() {
    let (lo, v0) = run_child("OFF");
    assert_eq!((lo, v0), (0, 0), "an OFF participant transmitted packets (lo, v0)");
}

/// The participant side, run by `run_child` inside the nested namespace.
#[test]
#[ignore = "run by the ros_range_* tests inside a nested network namespace"]
fn range_child() {
    let range = std::env::var(CHILD_ENV).expect("only run by the ros_range_* tests");
    // Refuse to run anywhere but the namespace run_child builds.
    let names: Vec<String> = tx_packets().into_iter().map(|(n, _)| n).collect();
    let mut sorted = names.clone();
    sorted.sort();
    assert_eq!(sorted, ["lo", "v0", "v1"], "unexpected interfaces {names:?}");

    let range = sweetspot::ros::DiscoveryRange::from_vars(Some(&range), None).unwrap();
    let config = sweetspot::ros::DdsConfig { domain_id: 7, range };
    let before = tx_packets();
    {
        let ctx = sweetspot::ros::context(&config).expect("participant");
        let qos = sweetspot::ros::swing_qos();
        let topic = ctx
            .create_topic(
                "rt/swing".into(),
                sweetspot::ros::message_type_name::<sweetspot::msgs::sweetspot_msgs::msg::Swing>(),
                &qos,
            )
            .unwrap();
        let dds_qos = rustdds::QosPolicies::from(&qos);
        let writer = ctx
            .domain_participant()
            .create_publisher(&dds_qos)
            .unwrap()
            .create_datawriter_no_key_cdr::<sweetspot::msgs::sweetspot_msgs::msg::Swing>(&topic, None)
            .unwrap();
        writer.write(Default::default(), None).unwrap();
        // SPDP announces at start-up and then periodically; this covers the start-up burst and a resend.
        std::thread::sleep(std::time::Duration::from_millis(2500));
    }
    let after = tx_packets();
    println!(
        "RESULT lo={} v0={}",
        tx_of(&after, "lo") - tx_of(&before, "lo"),
        tx_of(&after, "v0") - tx_of(&before, "v0")
    );
}
