//! One verdict per swing, decided before anything is published: a topic swing the answer refuses (a
//! `header.frame_id` over 256 bytes) is answered REJECTED and nothing else of it goes out — no ModalEnergies on
//! the topic or in the bag — and `/diagnostics` and the shutdown summary count it rejected, not processed.
//! Also: the summary is printed once. Over real DDS on loopback, inside the private network namespace of
//! scripts/test; the bag is read back with the library's reader.

mod support;

use std::time::{Duration, Instant};

use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::diagnostic_msgs::msg::DiagnosticArray;
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, Swing};

const WAIT: Duration = Duration::from_secs(60);

fn swing(id: u64, frame_id: &str) -> Swing {
    let mut s = Swing {
        swing_id: id,
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.7,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    };
    s.header.frame_id = frame_id.to_string();
    s
}

fn value(a: &DiagnosticArray, key: &str) -> Option<u64> {
    a.status.iter().flat_map(|s| s.values.iter()).find(|kv| kv.key == key).and_then(|kv| kv.value.parse().ok())
}

#[test]
fn a_swing_rejected_for_its_frame_id_publishes_and_records_no_energies_and_counts_as_rejected() {
    support::node::require_isolated_network();
    let domain = domain(35);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag");
    let mut peer = Peer::new(domain, "verdicts_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let energies = peer.subscription::<ModalEnergies>("/modal_energies", keep_all(dds::results()));
    let diagnostics = peer.subscription::<DiagnosticArray>("/diagnostics", keep_all(sweetspot::ros::diagnostics_qos()));
    let record_path = format!("record_path:={}", bag.display());
    let node =
        NodeProcess::spawn(domain, dir.path(), &["--ros-args", "-p", &record_path, "-p", "diagnostics_period:=0.1"]);
    peer.wait_for_reader(&swing_pub);

    // Good swings until the node publishes energies to this listener (it matches at a moment the test cannot
    // see); from then on every OK swing's energies arrive, in order.
    let mut next_id = 1u64;
    let deadline = Instant::now() + WAIT;
    loop {
        assert!(Instant::now() < deadline, "no ModalEnergies within {WAIT:?}");
        swing_pub.publish(swing(next_id, "cage")).unwrap();
        assert_eq!(peer.collect(&answers, 1, WAIT)[0].status, ExitVelocity::STATUS_OK);
        next_id += 1;
        std::thread::sleep(Duration::from_millis(20));
        if let Ok(Some(_)) = energies.take() {
            break;
        }
    }
    while let Ok(Some(_)) = energies.take() {}
    let good_before = next_id - 1;

    // The 300-byte frame_id, then one more good swing.
    let (bad, last) = (next_id, next_id + 1);
    swing_pub.publish(swing(bad, &"f".repeat(300))).unwrap();
    swing_pub.publish(swing(last, "cage")).unwrap();
    let got = peer.collect(&answers, 2, WAIT);
    assert_eq!((got[0].swing_id, got[0].status), (bad, ExitVelocity::STATUS_REJECTED), "{}", got[0].message);
    assert!(got[0].message.contains("header.frame_id is 300 bytes long"), "{}", got[0].message);
    assert!(got[0].header.frame_id.len() <= 256, "{} bytes echoed", got[0].header.frame_id.len());
    assert_eq!((got[1].swing_id, got[1].status), (last, ExitVelocity::STATUS_OK));
    // Energies go out in swing order: the good swing's come, and nothing of the rejected one before them.
    let after = peer.collect_until(&energies, WAIT, |got: &[ModalEnergies]| got.iter().any(|me| me.swing_id == last));
    let ids: Vec<u64> = after.iter().map(|me| me.swing_id).collect();
    assert_eq!(ids, [last], "energies of the rejected swing {bad} were published");

    let arrays = peer.collect_until(&diagnostics, WAIT, |got: &[DiagnosticArray]| {
        got.last().and_then(|a| value(a, "swings_received")) == Some(last)
    });
    let report = arrays.last().unwrap();
    assert_eq!(value(report, "swings_rejected"), Some(1), "/diagnostics");
    assert_eq!(value(report, "swings_processed"), Some(good_before + 1), "/diagnostics");

    let (status, _, log) = node.stop_with(libc::SIGINT);
    assert!(status.success(), "{log}");
    let counted = format!("{last} swings received = {} answered OK + 1 rejected", good_before + 1);
    assert_eq!(log.matches(&counted).count(), 1, "the summary, once, counting the swing rejected:\n{log}");
    let mut recorded = Vec::new();
    sweetspot::bag::reader::read_bag(&bag, |m| {
        if m.channel.topic.name == "/modal_energies" {
            let me: ModalEnergies = sweetspot::msgs::decode_cdr(m.data).unwrap();
            recorded.push(me.swing_id);
        }
    })
    .expect("read the bag");
    let expected: Vec<u64> = (1..=good_before).chain([last]).collect();
    assert_eq!(recorded, expected, "recorded for every OK swing and for no other");
}
