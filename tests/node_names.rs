//! Two `sweetspot` nodes with one name on one domain: each warns (rosout + /diagnostics WARN) that another node
//! of its name is on the graph, and each records to its own bag directory even when both start within the same
//! second. Over real DDS on loopback, inside the private network namespace of scripts/test
//! (`bash scripts/test --test node_names`).

mod support;

use std::time::Duration;

use support::node::{dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus};

const WAIT: Duration = Duration::from_secs(60);

/// The bag directory a node announced in its start-up line (`… recording DIR`).
fn bag_dir(log: &str) -> String {
    let line = log.lines().find(|l| l.contains(" up on ROS_DOMAIN_ID ")).expect("start-up line");
    line.rsplit("recording ").next().expect("recording …").trim().to_string()
}

#[test]
fn two_nodes_of_one_name_warn_and_record_to_distinct_directories() {
    let domain = domain(17);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "names_peer");
    let diagnostics = peer.subscription::<DiagnosticArray>("/diagnostics", keep_all(dds::results()));
    // Same name, same working directory, started back to back: the same default bag name for both.
    let first = NodeProcess::spawn(domain, dir.path(), &[]);
    let second = NodeProcess::spawn(domain, dir.path(), &[]);
    first.wait_for_log(" up on ROS_DOMAIN_ID ", WAIT);
    second.wait_for_log(" up on ROS_DOMAIN_ID ", WAIT);

    let warned = |s: &DiagnosticStatus| {
        s.name.contains("/sweetspot")
            && s.level == DiagnosticStatus::WARN
            && s.message.contains("another node named /sweetspot is on the graph")
    };
    let reports = peer.collect_until(&diagnostics, WAIT, |got| got.iter().flat_map(|d| &d.status).any(warned));
    let status = reports.iter().flat_map(|d| &d.status).find(|s| warned(s)).unwrap();
    assert!(status.values.iter().any(|kv| kv.key == "duplicate_node_name" && kv.value == "true"));
    // The same warning went to the log (and /rosout) of at least one of the two.
    let logs = [first.log(), second.log()];
    assert!(logs.iter().any(|l| l.contains("another node named /sweetspot")), "{}\n---\n{}", logs[0], logs[1]);

    let (first_status, _, first_log) = first.stop_with(2);
    let (second_status, _, second_log) = second.stop_with(2);
    assert!(first_status.success(), "first node:\n{first_log}");
    assert!(second_status.success(), "second node:\n{second_log}");
    let (first_bag, second_bag) = (bag_dir(&first_log), bag_dir(&second_log));
    assert_ne!(first_bag, second_bag, "both nodes recorded into one directory");
    for (bag, log) in [(&first_bag, &first_log), (&second_bag, &second_log)] {
        assert!(!log.contains("recording to"), "a recorder failed:\n{log}");
        assert!(dir.path().join(bag).join("metadata.yaml").is_file(), "{bag} has no metadata.yaml:\n{log}");
        assert!(log.contains(&format!("bag {bag} closed")), "{bag} not closed:\n{log}");
    }
    println!("bags: {first_bag}, {second_bag}");
    // The names differ only by the suffix when both started within one second.
    let (short, long) =
        if first_bag.len() <= second_bag.len() { (&first_bag, &second_bag) } else { (&second_bag, &first_bag) };
    if long.starts_with(short.as_str()) {
        assert_eq!(&long[short.len()..], "_2", "{short} vs {long}");
    }
}
