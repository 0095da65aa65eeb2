//! One dead subscriber must not stall answers to everyone (issue 23, item 10). Two Cyclone DDS subscribers of
//! `exit_velocity` (tests/python/cyclone_peer.py, an independent DDS implementation) are matched with the
//! node; then one is killed with -9 and the other stopped with SIGSTOP (Ctrl-Z) while this test publishes
//! 2,500 swings/s, far more than the 8,192 samples a reliable RustDDS writer once let one reader leave
//! unacknowledged. Neither stops acknowledging "politely": both stay in discovery until their lease expires
//! (10 s for Cyclone), longer than the stream lasts. A healthy subscriber (this test's own participant) must
//! still get an answer to every swing, each exactly once. Over real DDS on loopback, inside the private
//! network namespace of scripts/test (`bash scripts/test --test node_dead_subscriber`).

mod support;

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::pin::pin;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use futures::StreamExt;
use support::node::{dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};

const WAIT: Duration = Duration::from_secs(60);
/// Swings per second while the subscribers are dead.
const RATE: f64 = 2_500.0;
/// Swings published after the subscribers die: well past the 8,192 a dead reader used to hold up, and
/// within the healthy reader's 20,000-deep history.
const AFTER_DEATH: u64 = 14_000;

fn swing(id: u64) -> Swing {
    Swing {
        header: Header {
            stamp: Time { sec: 1000 + (id / 1000) as i32, nanosec: (id % 1000) as u32 },
            frame_id: "rig".into(),
        },
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

/// A Cyclone DDS subscriber of `/exit_velocity` whose received lines are counted; killed when dropped.
struct CycloneSubscriber {
    child: Child,
    received: Arc<AtomicU64>,
}

impl CycloneSubscriber {
    fn start(domain: u16, ready: &std::path::Path) -> CycloneSubscriber {
        let errors = std::fs::File::create(ready.with_extension("stderr")).expect("stderr file");
        let ready = ready.to_str().expect("utf-8 path");
        let mut command = support::cyclone_peer(
            domain,
            &[
                "sub",
                "--type",
                "sweetspot_msgs/msg/ExitVelocity",
                "--topic",
                "/exit_velocity",
                "--count",
                "30000",
                "--timeout",
                "300",
                "--qos",
                "results",
                "--wait-publishers",
                "1",
                "--ready-file",
                ready,
            ],
        );
        command.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(errors);
        let mut child = command.spawn().expect("starting the Cyclone subscriber");
        let received = Arc::new(AtomicU64::new(0));
        let (pipe, counter) = (child.stdout.take().expect("piped stdout"), Arc::clone(&received));
        std::thread::spawn(move || {
            for _ in BufReader::new(pipe).lines().map_while(Result::ok) {
                counter.fetch_add(1, Ordering::SeqCst);
            }
        });
        CycloneSubscriber { child, received }
    }

    fn signal(&self, name: &str) {
        let status = Command::new("kill").arg(format!("-{name}")).arg(self.child.id().to_string()).status();
        assert!(status.expect("kill").success(), "kill -{name} {} failed", self.child.id());
    }
}

impl Drop for CycloneSubscriber {
    fn drop(&mut self) {
        // A stopped process must be continued to die of anything but SIGKILL; SIGKILL works either way.
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn wait_for_file(path: &std::path::Path) {
    let start = Instant::now();
    while !path.exists() {
        assert!(start.elapsed() < WAIT, "{} never appeared", path.display());
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_killed_and_a_stopped_subscriber_cost_a_healthy_subscriber_no_answer() {
    support::require_isolated_network();
    let domain = domain(18);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "dead_subscriber_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", dds::swing());
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let (killed_ready, stopped_ready) = (dir.path().join("killed.ready"), dir.path().join("stopped.ready"));
    let killed = CycloneSubscriber::start(domain, &killed_ready);
    let stopped = CycloneSubscriber::start(domain, &stopped_ready);
    // The subscribers say ready once they have matched the node's writer (`--wait-publishers 1`).
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    wait_for_file(&killed_ready);
    wait_for_file(&stopped_ready);
    peer.wait_for_reader(&swing_pub);

    // Warm-up, slowly, until both Cyclone subscribers have answers: they are matched with the node's writer
    // and acknowledging.
    let mut next_id = 0u64;
    let warm_up = Instant::now();
    while killed.received.load(Ordering::SeqCst) == 0 || stopped.received.load(Ordering::SeqCst) == 0 {
        assert!(
            warm_up.elapsed() < WAIT,
            "the Cyclone subscribers never received an answer ({} and {}); their stderr: {:?} {:?}; node log:\n{}",
            killed.received.load(Ordering::SeqCst),
            stopped.received.load(Ordering::SeqCst),
            std::fs::read_to_string(killed_ready.with_extension("stderr")),
            std::fs::read_to_string(stopped_ready.with_extension("stderr")),
            node.log()
        );
        swing_pub.publish(swing(next_id)).expect("publishing a warm-up swing");
        next_id += 1;
        std::thread::sleep(Duration::from_millis(20));
    }

    // Now they die: one is gone without a goodbye, the other hangs. Both stay matched until their leases
    // expire.
    killed.signal("KILL");
    stopped.signal("STOP");
    let first_after_death = next_id;

    // The healthy subscriber takes answers while the swings stream in (on its own thread).
    let answered = Arc::new(Mutex::new(BTreeMap::<u64, Vec<u8>>::new()));
    let total = first_after_death + AFTER_DEATH;
    let collector = {
        let answered = Arc::clone(&answered);
        let rt = std::mem::replace(&mut peer.rt, tokio::runtime::Runtime::new().unwrap());
        std::thread::spawn(move || {
            rt.block_on(async {
                let mut stream = pin!(answers.async_stream());
                loop {
                    if answered.lock().unwrap().len() as u64 >= total {
                        break;
                    }
                    match tokio::time::timeout(Duration::from_secs(20), stream.next()).await {
                        Ok(Some(Ok((ev, _)))) => {
                            answered.lock().unwrap().entry(ev.swing_id).or_default().push(ev.status)
                        }
                        Ok(Some(Err(e))) => panic!("receive error: {e:?}"),
                        Ok(None) | Err(_) => break,
                    }
                }
            });
            (rt, answers)
        })
    };

    let start = Instant::now();
    let mut failed = Vec::new();
    for i in 0..AFTER_DEATH {
        let due = start + Duration::from_secs_f64(i as f64 / RATE);
        if let Some(wait) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        if let Err(e) = swing_pub.publish(swing(next_id)) {
            failed.push((next_id, format!("{e:?}")));
        }
        next_id += 1;
    }
    let streamed = start.elapsed();
    assert!(failed.is_empty(), "{} swings could not be published, first {:?}", failed.len(), failed.first());
    let (_rt, _answers) = collector.join().expect("the collector panicked");
    let (status, _, log) = node.stop_with(2);
    assert!(status.success(), "node exit {status:?}");
    let summary = log.lines().find(|l| l.contains("swings received")).unwrap_or("(no summary)").to_string();

    let answered = answered.lock().unwrap();
    let missing: Vec<u64> = (0..total).filter(|id| !answered.contains_key(id)).collect();
    let missing_after_death = missing.iter().filter(|id| **id >= first_after_death).count();
    eprintln!(
        "{AFTER_DEATH} swings in {:.1} s after the subscribers died; the healthy subscriber missed {} answers \
         ({missing_after_death} of them after the deaths); node: {summary}",
        streamed.as_secs_f64(),
        missing.len()
    );
    assert!(
        missing.is_empty(),
        "the healthy subscriber missed {} of {total} answers ({missing_after_death} after the deaths; first \
         missing {:?}); node: {summary}",
        missing.len(),
        &missing[..missing.len().min(5)]
    );
    for (id, statuses) in answered.iter() {
        assert_eq!(statuses.len(), 1, "swing {id} answered {} times: {statuses:?}", statuses.len());
        assert!(
            statuses[0] == ExitVelocity::STATUS_OK || statuses[0] == ExitVelocity::STATUS_DROPPED,
            "swing {id} answered with status {}",
            statuses[0]
        );
    }
    // The stopped subscriber really was stopped: it received nothing after SIGSTOP beyond what was in flight.
    assert!(stopped.received.load(Ordering::SeqCst) < first_after_death + 1_000);
    drop(stopped);
    drop(killed);
}
