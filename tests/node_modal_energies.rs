//! ModalEnergies are always recorded but published only while a subscription is matched (a DDS write to
//! nobody still wakes RustDDS's event loop for every answer). Over real DDS on loopback, inside the private
//! network namespace of scripts/test: a listener that subscribes while the node runs gets the energies of
//! every swing answered after its subscription reached the node, none is skipped, and the bag has them all.

mod support;

use std::time::{Duration, Instant};

use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::msgs::diagnostic_msgs::msg::DiagnosticArray;
use sweetspot::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, Swing};

const WAIT: Duration = Duration::from_secs(60);

fn swing(id: u64) -> Swing {
    Swing {
        swing_id: id,
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.5 + 0.01 * (id % 20) as f64,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    }
}

/// The node's latest diagnostics value of `key` once it reports `swings_processed` = `processed`.
fn diagnostic_after(
    peer: &Peer,
    diagnostics: &ros2_client::Subscription<DiagnosticArray>,
    processed: u64,
    key: &str,
) -> u64 {
    let value = |a: &DiagnosticArray, k: &str| -> Option<u64> {
        a.status.iter().flat_map(|s| s.values.iter()).find(|kv| kv.key == k).and_then(|kv| kv.value.parse().ok())
    };
    let arrays = peer.collect_until(diagnostics, WAIT, |got| {
        got.last().and_then(|a| value(a, "swings_processed")) == Some(processed)
    });
    value(arrays.last().unwrap(), key).unwrap_or_else(|| panic!("{key} missing from /diagnostics"))
}

#[test]
fn modal_energies_reach_a_listener_from_its_subscription_on_and_are_always_recorded() {
    let domain = domain(60);
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag");
    let mut peer = Peer::new(domain, "energies_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let diagnostics = peer.subscription::<DiagnosticArray>("/diagnostics", keep_all(sweetspot::ros::diagnostics_qos()));
    let node = NodeProcess::spawn(
        domain,
        dir.path(),
        &["--ros-args", "-p", &format!("record_path:={}", bag.display()), "-p", "diagnostics_period:=0.1"],
    );
    peer.wait_for_reader(&swing_pub);
    let mut next_id = 1u64;
    let answer = |peer: &Peer, id: u64| {
        swing_pub.publish(swing(id)).unwrap();
        let got = peer.collect(&answers, 1, WAIT);
        assert_eq!(got[0].swing_id, id);
        assert_eq!(got[0].status, ExitVelocity::STATUS_OK);
    };

    // Nobody listens: answered, not published.
    for _ in 0..10 {
        answer(&peer, next_id);
        next_id += 1;
    }
    assert_eq!(diagnostic_after(&peer, &diagnostics, 10, "modal_energies_published"), 0);

    // A listener arrives while the node runs. DDS matches it at some moment the test cannot see, so swings
    // go one by one until the first energies come back; from then on none may be missing.
    let energies = peer.subscription::<ModalEnergies>("/modal_energies", keep_all(dds::results()));
    let deadline = Instant::now() + WAIT;
    let first = loop {
        assert!(Instant::now() < deadline, "no ModalEnergies within {WAIT:?} of subscribing");
        let id = next_id;
        answer(&peer, id);
        next_id += 1;
        std::thread::sleep(Duration::from_millis(20));
        if let Ok(Some((me, _))) = energies.take() {
            assert!(me.swing_id > 10 && me.swing_id <= id, "energies of swing {} before anyone listened", me.swing_id);
            break me.swing_id;
        }
    };
    const AFTER: u64 = 50;
    let burst: Vec<u64> = (next_id..next_id + AFTER).collect();
    for &id in &burst {
        swing_pub.publish(swing(id)).unwrap();
    }
    next_id += AFTER;
    let got = peer.collect(&answers, AFTER as usize, WAIT);
    assert_eq!(got.iter().map(|ev| ev.swing_id).collect::<Vec<_>>(), burst);
    let total = next_id - 1;
    let expected: Vec<u64> = (first + 1..=total).collect();
    let got_energies = peer.collect(&energies, expected.len(), WAIT);
    assert_eq!(got_energies.iter().map(|me| me.swing_id).collect::<Vec<_>>(), expected, "every one, in order");
    assert_eq!(diagnostic_after(&peer, &diagnostics, total, "modal_energies_published"), total - first + 1);

    // The listener leaves: publishing stops again (noticed from the discovery event of its removal).
    drop(energies);
    let deadline = Instant::now() + WAIT;
    loop {
        assert!(Instant::now() < deadline, "ModalEnergies still published {WAIT:?} after the listener left");
        let before = diagnostic_after(&peer, &diagnostics, next_id - 1, "modal_energies_published");
        answer(&peer, next_id);
        next_id += 1;
        if diagnostic_after(&peer, &diagnostics, next_id - 1, "modal_energies_published") == before {
            break;
        }
    }
    let total = next_id - 1;

    println!("energies from swing {first} on; {total} swings; the listener's leave noticed by swing {total}");
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
    let mut recorded = Vec::new();
    sweetspot::bag::reader::read_bag(&bag, |m| {
        if m.channel.topic.name == "/modal_energies" {
            let me: ModalEnergies = sweetspot::msgs::decode_cdr(m.data).unwrap();
            recorded.push(me.swing_id);
        }
    })
    .expect("read the bag");
    assert_eq!(recorded, (1..=total).collect::<Vec<_>>(), "recorded for every swing, listened to or not");
}
