//! The node outlives being stopped and continued (`kill -STOP`, `kill -CONT`: what Ctrl-Z then `fg` does in a
//! shell). A stopped process's `epoll_wait` returns EINTR when it continues, even without signal handlers;
//! DDS must take that as a spurious wake-up, not as the end of its event loops. Over real DDS on loopback,
//! inside the private network namespace of scripts/test (`bash scripts/test --test node_sigstop`).

mod support;

use std::collections::BTreeMap;
use std::pin::pin;
use std::process::Command;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use futures::StreamExt;
use support::node::{dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::diagnostic_msgs::msg::{DiagnosticArray, DiagnosticStatus};
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{BatParams, ExitVelocity, Swing};

const WAIT: Duration = Duration::from_secs(60);
/// One swing every 4 ms: fewer than the swing writer's 1000-sample window are ever unacknowledged, even by a
/// node that never answers again, so publishing never blocks and the test measures the node, not the writer.
const PERIOD: Duration = Duration::from_millis(4);

fn swing(id: u64) -> Swing {
    Swing {
        header: Header { stamp: Time { sec: 1000 + (id % 1000) as i32, nanosec: 0 }, frame_id: "rig".into() },
        swing_id: id,
        bat_id: "r161".into(),
        ball_id: String::new(),
        ball_speed: 40.0,
        bat_cm_speed: 18.0,
        bat_angular_speed: 45.0,
        impact_z: 0.45 + 0.3 * (id % 97) as f64 / 96.0,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    }
}

fn signal(node: &NodeProcess, name: &str) {
    let status = Command::new("kill").arg(format!("-{name}")).arg(node.pid().to_string()).status().expect("kill");
    assert!(status.success(), "kill -{name} {} failed", node.pid());
}

fn diagnostic(d: &DiagnosticArray, key: &str) -> Option<u64> {
    d.status.first()?.values.iter().find(|kv| kv.key == key)?.value.parse().ok()
}

#[test]
fn every_swing_sent_after_sigstop_and_sigcont_is_answered() {
    let domain = domain(13);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "sigstop_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", dds::swing());
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let diagnostics = peer.subscription::<DiagnosticArray>("/diagnostics", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    peer.wait_for_reader(&swing_pub);

    // Swings go out continuously from their own thread; `next_id` tells which were published when.
    let next_id = Arc::new(AtomicU64::new(0));
    let stop = Arc::new(AtomicBool::new(false));
    let sent = Arc::new(Mutex::new(Vec::<u64>::new()));
    let failed = Arc::new(Mutex::new(Vec::<(u64, String)>::new()));
    let publisher = {
        let (next_id, stop, sent, failed) = (next_id.clone(), stop.clone(), sent.clone(), failed.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::SeqCst) {
                let id = next_id.load(Ordering::SeqCst);
                match swing_pub.publish(swing(id)) {
                    Ok(()) => sent.lock().unwrap().push(id),
                    Err(e) => failed.lock().unwrap().push((id, format!("{e:?}"))),
                }
                next_id.store(id + 1, Ordering::SeqCst);
                std::thread::sleep(PERIOD);
            }
            swing_pub
        })
    };

    std::thread::sleep(Duration::from_secs(1));
    let before_stop = next_id.load(Ordering::SeqCst);
    signal(&node, "STOP");
    std::thread::sleep(Duration::from_secs(1));
    signal(&node, "CONT");
    // Every id from here on was published after the node continued.
    let after_cont = next_id.load(Ordering::SeqCst);
    std::thread::sleep(Duration::from_secs(2));
    stop.store(true, Ordering::SeqCst);
    let _swing_pub = publisher.join().unwrap();
    let sent = sent.lock().unwrap().clone();
    let failed = failed.lock().unwrap().clone();
    let expected: Vec<u64> = sent.iter().copied().filter(|id| *id >= after_cont).collect();
    assert!(
        before_stop > 0 && expected.len() > 100,
        "too few swings published ({before_stop} before, {} after)",
        expected.len()
    );

    // Every answer, until each swing sent after SIGCONT has one (or nothing new arrives for 20 s).
    let mut answered: BTreeMap<u64, Vec<u8>> = BTreeMap::new();
    peer.rt.block_on(async {
        let mut stream = pin!(answers.async_stream());
        let deadline = Instant::now() + WAIT;
        while !expected.iter().all(|id| answered.contains_key(id)) && Instant::now() < deadline {
            match tokio::time::timeout(Duration::from_secs(20), stream.next()).await {
                Ok(Some(Ok((ev, _)))) => answered.entry(ev.swing_id).or_default().push(ev.status),
                Ok(Some(Err(e))) => panic!("receive error: {e:?}"),
                Ok(None) | Err(_) => break,
            }
        }
    });
    let missing: Vec<u64> = expected.iter().copied().filter(|id| !answered.contains_key(id)).collect();
    let answered_before_stop = answered.range(..before_stop).count();
    assert!(
        missing.is_empty(),
        "{} of the {} swings sent after SIGCONT were never answered (first missing: {:?}); {} of {} answered \
         before SIGSTOP; {} publish errors {:?}",
        missing.len(),
        expected.len(),
        &missing[..missing.len().min(5)],
        answered_before_stop,
        before_stop,
        failed.len(),
        failed.first()
    );
    for id in &expected {
        assert_eq!(answered[id], vec![ExitVelocity::STATUS_OK], "swing {id} answered once, OK");
    }

    // Discovery still works: a writer that appears only now is matched, and its bat reaches the node.
    let bat_pub = peer.publisher::<BatParams>("/bat/params", dds::params());
    let header = Header { stamp: Time { sec: 3, nanosec: 0 }, frame_id: "rig".into() };
    bat_pub
        .publish(BatParams { header, bat_id: "after_cont".into(), preset: "r161".into(), ..BatParams::default() })
        .unwrap();
    node.wait_for_log("bat 'after_cont' set", WAIT);

    // /diagnostics still flows: a report that counts every swing published, stopped period included.
    let total = sent.len() as u64;
    let reports = peer.collect_until(&diagnostics, WAIT, |got| {
        got.last().is_some_and(|d| {
            diagnostic(d, "swings_received").unwrap_or(0) + diagnostic(d, "swings_lost_in_transport").unwrap_or(0)
                >= total
        })
    });
    let last = reports.last().unwrap();
    assert_ne!(last.status[0].level, DiagnosticStatus::ERROR, "diagnostics after SIGCONT: {}", last.status[0].message);

    let (status, _, log) = node.stop_with(2);
    assert!(status.success(), "SIGINT exits cleanly:\n{log}");
    println!(
        "{} swings published ({before_stop} before SIGSTOP, {} while stopped, {} after SIGCONT), all {} after \
         SIGCONT answered; {} publish errors",
        total,
        sent.iter().filter(|id| (before_stop..after_cont).contains(*id)).count(),
        expected.len(),
        expected.len(),
        failed.len()
    );
}

/// A clean shutdown logs no ERROR: writers and readers dropped after the participant has stopped its event
/// loop (ros2-client's node drops its context before its rosout and parameter-event writers) are not errors.
#[test]
fn a_clean_shutdown_logs_no_error() {
    let domain = domain(14);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "shutdown_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", dds::swing());
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    peer.wait_for_reader(&swing_pub);
    swing_pub.publish(swing(1)).unwrap();
    assert_eq!(peer.collect(&answers, 1, WAIT)[0].swing_id, 1);
    let (status, _, log) = node.stop_with(2);
    assert!(status.success(), "SIGINT exits cleanly:\n{log}");
    let errors: Vec<&str> = log.lines().filter(|l| l.contains("ERROR")).collect();
    assert!(errors.is_empty(), "ERROR lines on a clean shutdown:\n{}", errors.join("\n"));
}

/// A node whose disk fills up (here: its file-size limit drops to 0 while it runs, so every further write fails
/// with EFBIG, as ENOSPC would) keeps answering, reports the recorder ERROR, and leaves a bag that still has the
/// metadata.yaml written before the disk filled.
#[test]
fn a_full_disk_stops_the_recording_not_the_node() {
    let domain = domain(15);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "full_disk_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", dds::swing());
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &[]);
    peer.wait_for_reader(&swing_pub);
    swing_pub.publish(swing(1)).unwrap();
    assert_eq!(peer.collect(&answers, 1, WAIT)[0].swing_id, 1);
    // The recorder lists the node's topics in metadata.yaml at its first flush (within a second of start).
    let listed = || -> Option<std::path::PathBuf> {
        let bag = std::fs::read_dir(dir.path().join("bags")).ok()?.next()?.ok()?.path();
        let text = std::fs::read_to_string(bag.join("metadata.yaml")).ok()?;
        text.contains("/exit_velocity").then_some(bag)
    };
    let start = Instant::now();
    while listed().is_none() {
        assert!(start.elapsed() < WAIT, "metadata.yaml never listed the topics");
        std::thread::sleep(Duration::from_millis(20));
    }

    let status =
        Command::new("prlimit").args(["--pid", &node.pid().to_string(), "--fsize=0"]).status().expect("prlimit");
    assert!(status.success(), "prlimit failed");
    for id in 2..=400 {
        swing_pub.publish(swing(id)).unwrap();
    }
    let got = peer.collect(&answers, 399, WAIT);
    assert!(got.iter().all(|ev| ev.status == ExitVelocity::STATUS_OK));
    let (status, _, log) = node.stop_with(2);
    assert!(status.success(), "the node exits cleanly after its recording failed:\n{log}");
    assert!(log.contains("File too large"), "the recorder's failure is reported:\n{log}");
    let bags: Vec<_> = std::fs::read_dir(dir.path().join("bags")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(bags.len(), 1, "{bags:?}");
    let metadata = std::fs::read_to_string(bags[0].join("metadata.yaml")).expect("metadata.yaml after a full disk");
    assert!(metadata.contains("/swing") && metadata.contains("/exit_velocity"), "{metadata}");
}

/// Params do not overtake swings their publisher sent before them. The node is stopped while one publisher
/// sends 100 swings for bat 'lab', then new params for 'lab' (another preset), then 100 more swings: on
/// SIGCONT all of it is waiting at once, and the receive loop, which takes params ahead of swings, must still
/// answer the first 100 with the old bat and the last 100 with the new one (order by source timestamp).
#[test]
fn params_sent_after_swings_do_not_overtake_them() {
    let domain = domain(16);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "params_order_peer");
    let bat_pub = peer.publisher::<BatParams>("/bat/params", dds::params());
    let swing_pub = peer.publisher::<Swing>("/swing", dds::swing());
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    peer.wait_for_reader(&swing_pub);
    peer.wait_for_reader(&bat_pub);
    let params = |preset: &str, sec: i32| BatParams {
        header: Header { stamp: Time { sec, nanosec: 0 }, frame_id: "rig".into() },
        bat_id: "lab".into(),
        preset: preset.into(),
        ..BatParams::default()
    };
    let lab_swing = |id: u64| Swing { bat_id: "lab".into(), impact_z: 0.6, ..swing(id) };
    bat_pub.publish(params("r161", 1)).unwrap();
    node.wait_for_log("bat 'lab' set", WAIT);
    swing_pub.publish(lab_swing(1)).unwrap();
    let before = peer.collect(&answers, 1, WAIT)[0].clone();
    assert_eq!((before.swing_id, before.status), (1, ExitVelocity::STATUS_OK), "{}", before.message);

    signal(&node, "STOP");
    for id in 100..200 {
        swing_pub.publish(lab_swing(id)).unwrap();
    }
    std::thread::sleep(Duration::from_millis(20));
    bat_pub.publish(params("aluminum", 2)).unwrap();
    std::thread::sleep(Duration::from_millis(20));
    for id in 200..300 {
        swing_pub.publish(lab_swing(id)).unwrap();
    }
    std::thread::sleep(Duration::from_millis(300));
    signal(&node, "CONT");
    let got = peer.collect(&answers, 200, WAIT);
    swing_pub.publish(lab_swing(300)).unwrap();
    let after = peer.collect(&answers, 1, WAIT)[0].clone();
    assert_eq!(after.swing_id, 300);
    assert_ne!(
        after.exit_speed, before.exit_speed,
        "the two presets must answer differently for this test to mean anything"
    );

    let old_bat: Vec<u64> =
        got.iter().filter(|ev| ev.swing_id < 200 && ev.exit_speed != before.exit_speed).map(|ev| ev.swing_id).collect();
    let new_bat: Vec<u64> =
        got.iter().filter(|ev| ev.swing_id >= 200 && ev.exit_speed != after.exit_speed).map(|ev| ev.swing_id).collect();
    assert!(
        old_bat.is_empty() && new_bat.is_empty(),
        "swings sent before the new params but answered otherwise than with the old bat: {old_bat:?}; sent after \
         but answered otherwise than with the new bat: {new_bat:?}"
    );
    let (status, _, log) = node.stop_with(2);
    assert!(status.success(), "SIGINT exits cleanly:\n{log}");
}
