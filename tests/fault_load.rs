//! Faults under load over real DDS (inside the private network namespace of scripts/test): a flood far beyond
//! what the node can compute, recording to a full or unwritable disk, and SIGTERM while swings keep coming.
//! No timing assertions: every check is about what was counted, reported, answered and recorded.

mod support;

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use support::node::{blocking, dds, domain, keep_all, python, Peer};
use sweetspot::msgs::diagnostic_msgs::msg::DiagnosticArray;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};

const WAIT: Duration = Duration::from_secs(60);

/// A `sweetspot node` child, optionally started through `unshare --mount` + a shell `wrapper` (which must end
/// in `exec "$@"`); killed if the test ends without stopping it.
struct NodeProcess {
    child: Option<std::process::Child>,
    stderr: Arc<std::sync::Mutex<Vec<String>>>,
}

impl NodeProcess {
    fn spawn(wrapper: Option<&str>, domain: u16, cwd: &Path, args: &[&str]) -> NodeProcess {
        let exe = env!("CARGO_BIN_EXE_sweetspot");
        let mut command = match wrapper {
            None => Command::new(exe),
            Some(script) => {
                let mut c = Command::new("unshare");
                c.args(["--mount", "--", "sh", "-c", script, "sh", exe]);
                c
            }
        };
        let mut child = command
            .arg("node")
            .args(args)
            .current_dir(cwd)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("RUST_LOG", "info,rustdds=error,ros2_client=error")
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("starting the sweetspot binary");
        let stderr = Arc::new(std::sync::Mutex::new(Vec::new()));
        let pipe = child.stderr.take().expect("piped stderr");
        let lines = Arc::clone(&stderr);
        std::thread::spawn(move || {
            use std::io::BufRead;
            for line in std::io::BufReader::new(pipe).lines().map_while(Result::ok) {
                lines.lock().unwrap().push(line);
            }
        });
        NodeProcess { child: Some(child), stderr }
    }

    fn pid(&self) -> u32 {
        self.child.as_ref().expect("running").id()
    }

    fn log(&self) -> String {
        self.stderr.lock().unwrap().join("\n")
    }

    /// Sends `signal`, waits for the exit (30 s at most, to turn a hang into a failure); status and log.
    fn stop_with(mut self, signal: i32) -> (std::process::ExitStatus, (), String) {
        let mut child = self.child.take().expect("running");
        let status = Command::new("kill").arg(format!("-{signal}")).arg(child.id().to_string()).status().expect("kill");
        assert!(status.success());
        let start = std::time::Instant::now();
        loop {
            if let Some(status) = child.try_wait().expect("try_wait") {
                std::thread::sleep(Duration::from_millis(100));
                return (status, (), self.log());
            }
            if start.elapsed() > Duration::from_secs(30) {
                let _ = child.kill();
                panic!("node did not exit within 30 s of signal {signal}:\n{}", self.log());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for NodeProcess {
    fn drop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
            if std::thread::panicking() {
                eprintln!("---- sweetspot node stderr ----\n{}\n----", self.log());
            }
        }
    }
}

fn valid_swing(id: u64) -> Swing {
    Swing {
        header: Header::default(),
        swing_id: id,
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.55 + (id % 8) as f64 * 0.01,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    }
}

/// The numbers of the node's final summary line ("N swings received, N answered OK, N rejected, N dropped,
/// N lost in transport").
fn summary_counts(log: &str) -> (u64, u64, u64, u64, u64) {
    let line =
        log.lines().rev().find(|l| l.contains("swings received")).unwrap_or_else(|| panic!("no summary line:\n{log}"));
    let number_before = |word: &str| -> u64 {
        let at = line.find(word).unwrap_or_else(|| panic!("no '{word}' in '{line}'"));
        line[..at]
            .trim_end()
            .rsplit(|c: char| !c.is_ascii_digit())
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no count before '{word}' in '{line}'"))
    };
    (
        number_before(" swings received"),
        number_before(" answered OK"),
        number_before(" rejected"),
        number_before(" dropped"),
        number_before(" lost in transport"),
    )
}

/// The last value of `key` in the diagnostics received so far, and the matching status's level and message.
fn latest(arrays: &[DiagnosticArray], key: &str) -> Option<(String, u8, String)> {
    arrays
        .iter()
        .rev()
        .flat_map(|a| a.status.iter())
        .find_map(|s| s.values.iter().find(|kv| kv.key == key).map(|kv| (kv.value.clone(), s.level, s.message.clone())))
}

fn peak_rss_kb(pid: u32) -> u64 {
    sweetspot::bench::proc_status_kb(pid, "VmHWM").expect("VmHWM of the node")
}

#[test]
fn a_flood_far_beyond_capacity_is_dropped_counted_reported_and_memory_stays_bounded() {
    flood(domain(73));
}

/// Under a flood the node's KeepLast swing reader may evict samples before the node takes them (RustDDS
/// acknowledges on reception); those must then show up as `lost in transport`, never vanish uncounted.
#[test]
fn a_flood_loses_no_swing_without_counting_it() {
    let (sent, received, lost) = flood(domain(77));
    assert_eq!(received + lost, sent, "{} swings vanished without being counted", sent - received - lost);
}

/// Floods a slowed-down node; checks what it counted and reported; returns (swings sent, swings the node
/// says it received, swings it says were lost in transport).
fn flood(domain: u16) -> (u64, u64, u64) {
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "flood_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let diagnostics = peer.subscription::<DiagnosticArray>("/diagnostics", keep_all(sweetspot::ros::diagnostics_qos()));
    // One worker, 8 swings in flight and a 100× finer time step: the node computes a few hundred swings a
    // second, and the flood below arrives tens of times faster than that.
    let node = NodeProcess::spawn(
        None,
        domain,
        dir.path(),
        &[
            "--no-record",
            "--ros-args",
            "-p",
            "workers:=1",
            "-p",
            "queue_capacity:=8",
            "-p",
            "time_step:=1e-8",
            "-p",
            "diagnostics_period:=0.2",
        ],
    );
    peer.wait_for_reader(&swing_pub);
    std::thread::sleep(Duration::from_millis(300));
    // Warm: the default bat's modes are computed before the flood.
    swing_pub.publish(valid_swing(1)).unwrap();
    peer.collect(&answers, 1, WAIT);

    let flood = 5_000u64;
    for id in 2..2 + flood {
        swing_pub.publish(valid_swing(id)).unwrap();
    }
    // Answers stop once the backlog is gone; then diagnostics must show the drops.
    let got = drain(&peer, &answers, Duration::from_secs(3));
    // OK answers; the swings dropped at the full queue are answered DROPPED instead.
    let answered: BTreeSet<u64> =
        got.iter().filter(|ev| ev.status == ExitVelocity::STATUS_OK).map(|ev| ev.swing_id).collect();
    let dropped_answers = got.iter().filter(|ev| ev.status == ExitVelocity::STATUS_DROPPED).count() as u64;
    std::thread::sleep(Duration::from_millis(600));
    let arrays = peer.collect_until(&diagnostics, WAIT, |a: &[DiagnosticArray]| {
        latest(a, "swings_received").is_some_and(|(v, _, _)| v.parse::<u64>().unwrap_or(0) > answered.len() as u64)
            && a.len() >= 3
    });
    let peak = peak_rss_kb(node.pid());
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
    let (received, ok, rejected, dropped, lost) = summary_counts(&log);
    eprintln!("flood: {flood} sent, {received} received, {ok} OK, {rejected} rejected, {dropped} dropped, {lost} lost in transport; peak RSS {peak} kB");
    assert!(dropped > 0, "a flood of {flood} at 8 in flight must drop swings:\n{log}");
    assert_eq!(ok + rejected + dropped, received, "every swing taken is answered or counted as dropped:\n{log}");
    assert_eq!(ok, 1 + answered.len() as u64, "the listener got every OK answer the node counted");
    assert_eq!(dropped_answers, dropped, "every dropped swing is answered DROPPED:\n{log}");
    let (diag_dropped, _, _) = latest(&arrays, "swings_dropped").expect("swings_dropped on /diagnostics");
    assert!(diag_dropped.parse::<u64>().unwrap() > 0, "diagnostics report the drops");
    assert!(
        arrays.iter().flat_map(|a| a.status.iter()).any(|s| s.level == 1 && s.message.contains("dropped")),
        "a WARN status naming the drops was published"
    );
    assert!(log.contains("dropped: 8 swings already in flight"), "the drop warning names the limit:\n{log}");
    // Memory bounded: the flood never piles up in the node (generous ceiling; the node idles near 40 MB).
    assert!(peak < 400 * 1024, "peak RSS {peak} kB under the flood");
    (1 + flood, received, lost)
}

#[test]
fn sigterm_under_load_leaves_a_complete_bag_holding_every_answer_the_listener_got() {
    let domain = domain(74);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag");
    let mut peer = Peer::new(domain, "sigterm_peer");
    let swing_pub = Arc::new(peer.publisher::<Swing>("/swing", dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node =
        NodeProcess::spawn(None, domain, dir.path(), &["--ros-args", "-p", &format!("record_path:={}", bag.display())]);
    peer.wait_for_reader(&swing_pub);
    std::thread::sleep(Duration::from_millis(300));
    swing_pub.publish(valid_swing(1)).unwrap();
    peer.collect(&answers, 1, WAIT);

    // A steady stream (~2000/s) that keeps going through the SIGTERM.
    let stop = Arc::new(AtomicBool::new(false));
    let sender = {
        let (stop, swing_pub) = (Arc::clone(&stop), Arc::clone(&swing_pub));
        std::thread::spawn(move || {
            let mut id = 2;
            while !stop.load(Ordering::Relaxed) {
                let _ = swing_pub.publish(valid_swing(id));
                id += 1;
                std::thread::sleep(Duration::from_micros(500));
            }
            id
        })
    };
    // Let a few thousand answers through, then terminate mid-stream.
    let mut got = peer.collect(&answers, 2_000, WAIT);
    let (status, _, log) = node.stop_with(15);
    stop.store(true, Ordering::Relaxed);
    let last_sent = sender.join().unwrap();
    got.extend(drain(&peer, &answers, Duration::from_secs(1)));
    assert!(status.success(), "SIGTERM exits cleanly:\n{log}");
    assert!(last_sent > 2_000);

    let script = r#"
import json, sys, glob, os
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
files = sorted(glob.glob(os.path.join(sys.argv[1], "*.mcap")))
ids, summaries = [], 0
for f in files:
    with open(f, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        if reader.get_summary() is not None:
            summaries += 1
        for schema, channel, message, ros in reader.iter_decoded_messages(topics=["/exit_velocity"]):
            ids.append(ros.swing_id)
print(json.dumps({"files": len(files), "summaries": summaries, "ids": ids}))
"#;
    let out = Command::new(python()).arg("-c").arg(script).arg(&bag).output().expect("running python");
    assert!(out.status.success(), "python mcap reader failed: {}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json from the reader");
    let files = report["files"].as_u64().unwrap();
    assert!(files >= 1, "no MCAP file in {}", bag.display());
    assert_eq!(report["summaries"].as_u64(), Some(files), "every MCAP file is closed with a summary");
    assert!(Path::new(&bag).join("metadata.yaml").exists(), "rosbag2 metadata.yaml written on SIGTERM");
    let recorded: BTreeSet<u64> = report["ids"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap()).collect();
    eprintln!(
        "SIGTERM: {} answers received by the listener, {} in the bag, {} swings sent",
        got.len(),
        recorded.len(),
        last_sent - 1
    );
    let missing: Vec<u64> = got.iter().map(|ev| ev.swing_id).filter(|id| !recorded.contains(id)).collect();
    assert!(
        missing.is_empty(),
        "{} answers the listener received are not in the bag (first: {:?})",
        missing.len(),
        &missing[..missing.len().min(10)]
    );
}

/// Takes whatever is still arriving until nothing comes for `quiet`.
fn drain(peer: &Peer, sub: &ros2_client::Subscription<ExitVelocity>, quiet: Duration) -> Vec<ExitVelocity> {
    use futures::StreamExt;
    peer.rt.block_on(async {
        let mut out = Vec::new();
        let mut stream = std::pin::pin!(sub.async_stream());
        while let Ok(Some(Ok((m, _)))) = tokio::time::timeout(quiet, stream.next()).await {
            out.push(m);
        }
        out
    })
}

/// Runs the recording-failure scenario: the node records to `record_path` (made unusable by `setup`, run
/// in the node's own mount namespace), and must report the failure and keep answering.
fn recording_failure_is_reported_and_answers_keep_coming(domain: u16, record_path: &Path, wrapper: Option<String>) {
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "disk_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let diagnostics = peer.subscription::<DiagnosticArray>("/diagnostics", keep_all(sweetspot::ros::diagnostics_qos()));
    let args = [
        "--ros-args".to_string(),
        "-p".into(),
        format!("record_path:={}", record_path.display()),
        "-p".into(),
        "diagnostics_period:=0.2".into(),
    ];
    let node = match wrapper {
        None => NodeProcess::spawn(None, domain, dir.path(), &args.iter().map(String::as_str).collect::<Vec<_>>()),
        Some(script) => {
            NodeProcess::spawn(Some(&script), domain, dir.path(), &args.iter().map(String::as_str).collect::<Vec<_>>())
        }
    };
    peer.wait_for_reader(&swing_pub);
    std::thread::sleep(Duration::from_millis(300));
    // Enough swings to fill a 64 KiB disk several times over (each swing records ~3 messages).
    let total = 3_000u64;
    for id in 1..=total {
        swing_pub.publish(valid_swing(id)).unwrap();
    }
    let got = peer.collect(&answers, total as usize, WAIT);
    let arrays = peer.collect_until(&diagnostics, WAIT, |a: &[DiagnosticArray]| {
        latest(a, "recorder_state").is_some_and(|(v, _, _)| v == "failed")
    });
    // After the failure, answers keep coming.
    for id in total + 1..=total + 100 {
        swing_pub.publish(valid_swing(id)).unwrap();
    }
    let after = peer.collect(&answers, 100, WAIT);
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
    assert!(got.iter().chain(&after).all(|ev| ev.status == ExitVelocity::STATUS_OK));
    let (state, level, message) = latest(&arrays, "recorder_state").unwrap();
    assert_eq!(state, "failed");
    assert_eq!(level, 2, "recording failure is an ERROR on /diagnostics");
    assert!(message.contains("recording failed"), "{message}");
    let (error, _, _) = latest(&arrays, "recorder_error").expect("recorder_error on /diagnostics");
    assert!(!error.is_empty());
    assert!(log.to_lowercase().contains("record"), "the failure is logged (rosout + stderr):\n{log}");
}

#[test]
fn recording_to_a_full_disk_is_reported_and_answers_keep_coming() {
    let dir = tempfile::tempdir().unwrap();
    let mount = dir.path().join("tiny");
    std::fs::create_dir(&mount).unwrap();
    // A 64 KiB tmpfs visible only to the node: its own mount namespace (needs root or a user namespace, as
    // scripts/test has).
    let wrapper = format!("mount -t tmpfs -o size=64k tmpfs {} && exec \"$@\"", mount.display());
    recording_failure_is_reported_and_answers_keep_coming(domain(76), &mount.join("bag"), Some(wrapper));
}
