//! The DDS client commands (`call`, `param`, `nodes`, `pub`) tell the user what went wrong instead of
//! reporting success: a closed stdout ends `call` quietly, a refused `param describe` fails, two nodes of one
//! name are warned of, and `pub` refuses a message the node would refuse or DDS could not carry before sending
//! it. Over real DDS on loopback, inside the private network namespace of scripts/test.

mod support;

use std::process::{Output, Stdio};
use std::time::Duration;

use support::node::{domain, NodeProcess};
use support::sweetspot;

const WAIT: Duration = Duration::from_secs(60);
const PIPE_DOMAIN: u16 = 216;
const NAMESAKE_DOMAIN: u16 = 217;
const PUB_DOMAIN: u16 = 218;

const SWING: &str = "{swing: {bat_id: r161, ball_speed: 40, bat_cm_speed: 25, impact_z: 0.7}}";

fn run(domain: u16, args: &[&str]) -> Output {
    sweetspot(domain, args).output().expect("run sweetspot")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn call_into_a_closed_pipe_and_a_refused_describe() {
    support::require_isolated_network();
    assert!(PIPE_DOMAIN > domain(99), "outside the node tests' domains");
    let dir = tempfile::tempdir().unwrap();
    let node = NodeProcess::spawn(PIPE_DOMAIN, dir.path(), &["--no-record"]);
    node.wait_for_log(" up on ROS_DOMAIN_ID ", WAIT);

    // `call … | true`: the reader is gone before the answer is printed.
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    let out = sweetspot(PIPE_DOMAIN, &["call", "simulate_swing", SWING, "--timeout", "30"])
        .stdout(Stdio::from(writer))
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    assert!(!stderr.contains("panicked") && !stderr.contains("Broken pipe"), "{stderr}");

    // A describe of 1,024 names is answered (unknown names are described as not set); 1,025 are refused by
    // the node, and the command says so instead of printing nothing with status 0.
    let names: Vec<String> = (0..1025).map(|i| format!("p{i}")).collect();
    let mut args = vec!["param", "describe", "/sweetspot", "--timeout", "30"];
    args.extend(names[..1024].iter().map(String::as_str));
    let at_limit = run(PIPE_DOMAIN, &args);
    assert!(at_limit.status.success(), "{}", text(&at_limit.stderr));
    assert_eq!(text(&at_limit.stdout).matches("Parameter name: ").count(), 1024, "{}", text(&at_limit.stdout));
    args.push(&names[1024]);
    let over = run(PIPE_DOMAIN, &args);
    let stderr = text(&over.stderr);
    assert_eq!(over.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("/sweetspot described 0 of the 1025 parameter(s) asked"), "{stderr}");
    assert!(text(&over.stdout).is_empty(), "{}", text(&over.stdout));

    // A 100-KB parameter name the node refuses is named in the error, not repeated.
    let long = "p".repeat(100_000);
    let out = run(PIPE_DOMAIN, &["param", "get", "/sweetspot", &long, "--timeout", "30"]);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{}", &stderr[..stderr.len().min(300)]);
    assert!(stderr.len() < 2_000, "{} bytes of error: {}…", stderr.len(), &stderr[..300]);
    assert!(stderr.contains("Parameter not set: ppp") && stderr.contains("…(100000 bytes)"), "{stderr}");
}

#[test]
fn two_nodes_of_one_name_are_warned_of_by_nodes_call_and_param() {
    support::require_isolated_network();
    let dir = tempfile::tempdir().unwrap();
    let first = NodeProcess::spawn(NAMESAKE_DOMAIN, dir.path(), &["--no-record"]);
    let second = NodeProcess::spawn(NAMESAKE_DOMAIN, dir.path(), &["--no-record"]);
    first.wait_for_log(" up on ROS_DOMAIN_ID ", WAIT);
    second.wait_for_log(" up on ROS_DOMAIN_ID ", WAIT);
    let warning = "2 nodes named /sweetspot";

    let nodes = run(NAMESAKE_DOMAIN, &["nodes", "--spin-time", "3"]);
    assert!(nodes.status.success(), "{}", text(&nodes.stderr));
    assert_eq!(text(&nodes.stdout).lines().filter(|l| *l == "/sweetspot").count(), 2, "{}", text(&nodes.stdout));
    assert!(text(&nodes.stderr).contains(warning), "{}", text(&nodes.stderr));

    for args in [
        vec!["call", "simulate_swing", SWING, "--timeout", "30"],
        vec!["param", "get", "/sweetspot", "default_modes", "--timeout", "30"],
    ] {
        let out = run(NAMESAKE_DOMAIN, &args);
        let stderr = text(&out.stderr);
        assert!(out.status.success(), "{args:?}: {stderr}");
        assert!(stderr.contains(warning) && stderr.contains("rename one"), "{args:?}: {stderr}");
    }
    // One node of the name: no warning.
    drop(second);
    let alone = run(NAMESAKE_DOMAIN, &["nodes", "--spin-time", "3"]);
    assert!(!text(&alone.stderr).contains("nodes named"), "{}", text(&alone.stderr));
}

#[test]
fn pub_refuses_before_sending_what_the_node_would_refuse_or_dds_cannot_carry() {
    support::require_isolated_network();
    let swing = |bat_id: &str| format!("{{\"bat_id\": \"{bat_id}\", \"ball_speed\": 40, \"impact_z\": 0.7}}");
    // -w 0: no subscriber needed, so only the refusal decides the status.
    let at_bound = run(PUB_DOMAIN, &["pub", "swing", &swing(&"b".repeat(256)), "-w", "0", "--keep-alive", "0"]);
    assert!(at_bound.status.success(), "{}", text(&at_bound.stderr));
    let over = run(PUB_DOMAIN, &["pub", "swing", &swing(&"b".repeat(257)), "-w", "0"]);
    let stderr = text(&over.stderr);
    assert_eq!(over.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("bat_id is 257 bytes long, over the limit of 256 bytes"), "{stderr}");
    assert!(stderr.contains("the node refuses it; nothing was published"), "{stderr}");
    assert!(text(&over.stdout).is_empty(), "nothing published: {}", text(&over.stdout));

    // The 15 MB bat_id of a swing file.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("huge.jsonl");
    std::fs::write(&file, swing(&"x".repeat(15_000_000)) + "\n").unwrap();
    let huge = run(PUB_DOMAIN, &["pub", "swing", "--file", file.to_str().unwrap(), "-w", "0", "-q"]);
    let stderr = text(&huge.stderr);
    assert_eq!(huge.status.code(), Some(1), "{}", &stderr[..stderr.len().min(2000)]);
    assert!(stderr.contains("over the 1048576 bytes DDS carries here"), "{}", &stderr[..stderr.len().min(2000)]);
    assert!(stderr.len() < 4096, "the refusal does not echo the input: {} bytes", stderr.len());

    // A type the node does not bound (a log line) is still held to what DDS carries.
    let log_file = dir.path().join("log.jsonl");
    std::fs::write(&log_file, format!("{{\"msg\": \"{}\"}}\n", "m".repeat(1_100_000))).unwrap();
    let too_big = run(PUB_DOMAIN, &["pub", "rosout", "--file", log_file.to_str().unwrap(), "-w", "0", "-q"]);
    assert_eq!(too_big.status.code(), Some(1), "{}", text(&too_big.stderr));
    assert!(text(&too_big.stderr).contains("DDS carries"), "{}", text(&too_big.stderr));
}
