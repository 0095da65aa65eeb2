//! Bad input over real DDS (inside the private network namespace of scripts/test): malformed CDR and
//! wrong-type payloads on every input topic from a raw writer with the right topic and type name, and params
//! with NaN, negative or huge values. The node must report each, stay alive, and answer every valid swing.

mod support;

use std::collections::BTreeSet;
use std::time::Duration;

use ros2_client::Publisher;
use support::node::{blocking, dds, domain, keep_all, NodeInputs, NodeProcess, Peer};
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, Swing};

const WAIT: Duration = Duration::from_secs(60);

fn valid_swing(id: u64) -> Swing {
    Swing {
        header: Header::default(),
        swing_id: id,
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.6,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    }
}

/// A publisher of arbitrary serde data `D` on the topic `name` declared with the ROS type of `M`: the bytes on
/// the wire are whatever `D` serializes to, the type name is `M`'s, so the node's reader matches it.
fn raw_writer<M: sweetspot::msgs::RosMessage, D: serde::Serialize>(
    peer: &mut Peer,
    name: &str,
    qos: ros2_client::QosProfile,
) -> Publisher<D> {
    let topic = dds::topic::<M>(&peer.node, name, &qos);
    peer.node.create_publisher::<D>(&topic, None).expect("raw publisher")
}

/// Waits until `publisher` (of any payload type) has matched the node's reader, or panics after 60 s.
fn wait_matched<D: serde::Serialize>(peer: &Peer, publisher: &Publisher<D>) {
    peer.rt
        .block_on(async { tokio::time::timeout(WAIT, publisher.wait_for_subscription(&peer.node)).await })
        .expect("the node's reader never matched the raw writer");
}

/// Every kind of bad payload we send; each one fails to decode as any of the three input types.
#[derive(serde::Serialize, Clone, Copy, Debug)]
struct Truncated([u8; 5]);
/// A string length field of 0xFFFF_FFFF where the header's frame_id starts: a decoder that trusts it would
/// try to allocate 4 GiB.
#[derive(serde::Serialize, Clone, Copy, Debug)]
struct HugeLength([u8; 16]);

#[test]
fn malformed_and_wrong_type_payloads_on_every_input_are_reported_and_every_valid_swing_is_answered() {
    let domain = domain(70);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "fault_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let bad_swing_truncated = raw_writer::<Swing, Truncated>(&mut peer, "/swing", dds::swing());
    let bad_swing_huge = raw_writer::<Swing, HugeLength>(&mut peer, "/swing", dds::swing());
    // Wrong type: a std_msgs/String-like payload on the Swing topic.
    let bad_swing_wrong_type = raw_writer::<Swing, String>(&mut peer, "/swing", dds::swing());
    let bad_bat_truncated = raw_writer::<BatParams, Truncated>(&mut peer, "/bat/params", dds::params());
    let bad_bat_huge = raw_writer::<BatParams, HugeLength>(&mut peer, "/bat/params", dds::params());
    let bad_ball_truncated = raw_writer::<BallParams, Truncated>(&mut peer, "/ball/params", dds::params());
    let bad_ball_huge = raw_writer::<BallParams, HugeLength>(&mut peer, "/ball/params", dds::params());
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    peer.wait_for_reader(&swing_pub);
    wait_matched(&peer, &bad_swing_truncated);
    wait_matched(&peer, &bad_bat_truncated);
    wait_matched(&peer, &bad_ball_truncated);
    wait_matched(&peer, &bad_swing_huge);
    wait_matched(&peer, &bad_swing_wrong_type);
    wait_matched(&peer, &bad_bat_huge);
    wait_matched(&peer, &bad_ball_huge);
    std::thread::sleep(Duration::from_millis(300)); // the reader side matches a moment after the writer side

    let truncated = Truncated([0xFF; 5]);
    let huge = HugeLength([0xFF; 16]);
    let mut sent = BTreeSet::new();
    for round in 0..20u64 {
        for k in 0..5 {
            let id = round * 5 + k + 1;
            swing_pub.publish(valid_swing(id)).unwrap();
            sent.insert(id);
        }
        bad_swing_truncated.publish(truncated).unwrap();
        bad_swing_huge.publish(huge).unwrap();
        bad_swing_wrong_type.publish(format!("not a swing #{round}")).unwrap();
        bad_bat_truncated.publish(truncated).unwrap();
        bad_bat_huge.publish(huge).unwrap();
        bad_ball_truncated.publish(truncated).unwrap();
        bad_ball_huge.publish(huge).unwrap();
    }
    let got = peer.collect_until(&answers, WAIT, |got: &[ExitVelocity]| {
        sent.iter().all(|id| got.iter().any(|ev| ev.swing_id == *id))
    });
    for id in &sent {
        let ev = got.iter().find(|ev| ev.swing_id == *id).unwrap();
        assert_eq!(ev.status, ExitVelocity::STATUS_OK, "swing {id}: {}", ev.message);
        assert!(ev.exit_speed.is_finite() && ev.exit_speed > 0.0);
    }
    // Nothing but the valid swings was answered as a swing (a garbage payload decoded into a "swing" would be).
    assert!(
        got.iter().all(|ev| sent.contains(&ev.swing_id)),
        "answers to swings never sent: {:?}",
        got.iter().map(|ev| ev.swing_id).filter(|id| !sent.contains(id)).collect::<Vec<_>>()
    );

    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "the node exits cleanly after the bad input:\n{log}");
    for topic in ["swing", "bat/params", "ball/params"] {
        assert!(
            log.contains(&format!("{topic}: unreadable sample")),
            "no report of the unreadable {topic} samples:\n{log}"
        );
    }
    assert!(
        log.contains(&format!("{} swings received", sent.len())),
        "only the valid swings count as received:\n{log}"
    );
}

/// Reads the node's /diagnostics until `key` is present; returns its value.
fn diagnostic_value(
    peer: &Peer,
    sub: &ros2_client::Subscription<sweetspot::msgs::diagnostic_msgs::msg::DiagnosticArray>,
    key: &str,
) -> Option<String> {
    let arrays = peer.collect(sub, 3, WAIT);
    arrays
        .iter()
        .rev()
        .flat_map(|a| a.status.iter())
        .flat_map(|s| s.values.iter())
        .find(|kv| kv.key == key)
        .map(|kv| kv.value.clone())
}

#[test]
fn unreadable_samples_are_counted_on_diagnostics() {
    let domain = domain(71);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "fault_diag_peer");
    let diagnostics = peer.subscription::<sweetspot::msgs::diagnostic_msgs::msg::DiagnosticArray>(
        "/diagnostics",
        keep_all(sweetspot::ros::diagnostics_qos()),
    );
    let bad = raw_writer::<Swing, Truncated>(&mut peer, "/swing", dds::swing());
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record", "--ros-args", "-p", "diagnostics_period:=0.2"]);
    wait_matched(&peer, &bad);
    std::thread::sleep(Duration::from_millis(300));
    for _ in 0..3 {
        bad.publish(Truncated([0xFF; 5])).unwrap();
    }
    node.wait_for_log("swing: unreadable sample", WAIT);
    std::thread::sleep(Duration::from_millis(500));
    let value = diagnostic_value(&peer, &diagnostics, "samples_unreadable");
    assert_eq!(value.as_deref(), Some("3"), "diagnostics should count the 3 unreadable swings");
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
}

#[test]
fn params_with_nan_negative_or_huge_values_are_rejected_with_the_reason() {
    let domain = domain(72);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "fault_params_peer");
    let inputs = NodeInputs::on(&mut peer);
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    inputs.wait_for_node(&peer);
    let NodeInputs { bat: bat_pub, ball: ball_pub, swing: swing_pub, answers } = inputs;

    let good_ball = BallParams {
        ball_id: String::new(),
        mass: 0.145,
        radius: 0.0365,
        cor: 0.5,
        stiffness: 7.0e7,
        exponent: 1.5,
        ..BallParams::default()
    };
    let balls = [
        ("nan_mass", BallParams { mass: f64::NAN, ..good_ball.clone() }, "mass"),
        ("negative_radius", BallParams { radius: -0.0365, ..good_ball.clone() }, "radius"),
        ("huge_stiffness", BallParams { stiffness: 1e300, ..good_ball.clone() }, "stiffness"),
        ("infinite_cor", BallParams { cor: f64::INFINITY, ..good_ball.clone() }, "cor"),
        ("negative_exponent", BallParams { exponent: -1.5, ..good_ball.clone() }, "exponent"),
    ];
    for (id, params, _) in &balls {
        ball_pub.publish(BallParams { ball_id: (*id).into(), ..params.clone() }).unwrap();
    }
    let bats = [
        (
            "nan_density",
            BatParams {
                preset: String::new(),
                station_z: vec![0.0, 0.84],
                outer_radius: vec![0.03, 0.03],
                inner_radius: vec![0.0, 0.0],
                density: f64::NAN,
                youngs_modulus: 1.8e10,
                shear_modulus: 1.0e9,
                slice_length: 0.01,
                max_modes: 10,
                ..BatParams::default()
            },
            "density",
        ),
        (
            "negative_modulus",
            BatParams {
                preset: String::new(),
                station_z: vec![0.0, 0.84],
                outer_radius: vec![0.03, 0.03],
                inner_radius: vec![0.0, 0.0],
                density: 650.0,
                youngs_modulus: -1.8e10,
                shear_modulus: 1.0e9,
                slice_length: 0.01,
                max_modes: 10,
                ..BatParams::default()
            },
            "youngs_modulus",
        ),
        (
            "huge_radius",
            BatParams {
                preset: String::new(),
                station_z: vec![0.0, 0.84],
                outer_radius: vec![1e300, 1e300],
                inner_radius: vec![0.0, 0.0],
                density: 650.0,
                youngs_modulus: 1.8e10,
                shear_modulus: 1.0e9,
                slice_length: 0.01,
                max_modes: 10,
                ..BatParams::default()
            },
            "radius",
        ),
    ];
    for (id, params, _) in &bats {
        bat_pub.publish(BatParams { bat_id: (*id).into(), ..params.clone() }).unwrap();
    }
    let expected = balls.len() + bats.len();
    let rejections = peer.collect(&answers, expected, WAIT);
    for (id, _, field) in &balls {
        let ev = rejections
            .iter()
            .find(|ev| ev.ball_id == *id)
            .unwrap_or_else(|| panic!("no answer to BallParams '{id}': {rejections:?}"));
        assert_eq!(ev.status, ExitVelocity::STATUS_REJECTED, "BallParams '{id}'");
        assert!(ev.message.contains(field), "BallParams '{id}': '{}' should name {field}", ev.message);
    }
    for (id, _, field) in &bats {
        let ev = rejections
            .iter()
            .find(|ev| ev.bat_id == *id)
            .unwrap_or_else(|| panic!("no answer to BatParams '{id}': {rejections:?}"));
        assert_eq!(ev.status, ExitVelocity::STATUS_REJECTED, "BatParams '{id}'");
        assert!(ev.message.contains(field), "BatParams '{id}': '{}' should name {field}", ev.message);
    }
    // A rejected id is unknown: a swing naming it is refused, and the defaults still answer.
    swing_pub.publish(Swing { bat_id: "nan_density".into(), ..valid_swing(1) }).unwrap();
    swing_pub.publish(Swing { ball_id: "nan_mass".into(), ..valid_swing(2) }).unwrap();
    swing_pub.publish(valid_swing(3)).unwrap();
    let got = peer.collect(&answers, 3, WAIT);
    assert_eq!(got[0].status, ExitVelocity::STATUS_REJECTED, "{}", got[0].message);
    assert_eq!(got[1].status, ExitVelocity::STATUS_REJECTED, "{}", got[1].message);
    assert_eq!(got[2].status, ExitVelocity::STATUS_OK, "{}", got[2].message);
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
}

/// Answers that would be absurd are refusals: a ball compressed far beyond its radius, a bat whose kept modes
/// the node's time step cannot resolve (refused when its params arrive, not on every swing), and a measured
/// exit speed of ±inf or 1e300.
#[test]
fn absurd_balls_unresolvable_bats_and_infinite_measurements_are_refused() {
    let domain = domain(78);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "fault_absurd_peer");
    let inputs = NodeInputs::on(&mut peer);
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    inputs.wait_for_node(&peer);
    let NodeInputs { bat: bat_pub, ball: ball_pub, swing: swing_pub, answers } = inputs;

    let r161 = sweetspot::physics::Bat::preset("r161").unwrap();
    let fine = BatParams {
        slice_length: 7e-4,
        ..sweetspot::model::convert::params_from_bat("fine", &r161, 200, Header::default())
    };
    bat_pub.publish(fine).unwrap();
    let refused = peer.collect(&answers, 1, WAIT);
    assert_eq!(refused[0].status, ExitVelocity::STATUS_REJECTED, "{}", refused[0].message);
    assert_eq!(refused[0].bat_id, "fine");
    assert!(
        refused[0].message.starts_with("BatParams 'fine': max_modes = 200 is out of range")
            && refused[0].message.contains("resolves at most"),
        "{}",
        refused[0].message
    );

    let soft = BallParams {
        header: Header::default(),
        ball_id: "soft".into(),
        mass: 0.145,
        radius: 0.0366,
        cor: 0.5,
        stiffness: 1e4,
        exponent: 1.0,
        ..BallParams::default()
    };
    ball_pub.publish(soft).unwrap();
    node.wait_for_log("ball 'soft' set", WAIT);
    swing_pub.publish(Swing { ball_id: "soft".into(), ..valid_swing(1) }).unwrap();
    for (id, measured) in [(2, f64::INFINITY), (3, f64::NEG_INFINITY), (4, 1e300)] {
        swing_pub
            .publish(Swing { ball_id: "baseball".into(), measured_exit_speed: measured, ..valid_swing(id) })
            .unwrap();
    }
    swing_pub.publish(Swing { ball_id: "baseball".into(), measured_exit_speed: 44.0, ..valid_swing(5) }).unwrap();
    let got = peer.collect(&answers, 5, WAIT);
    assert_eq!(got[0].status, ExitVelocity::STATUS_REJECTED);
    assert!(
        got[0].message.starts_with("ball 'soft' (stiffness = 10000 N/m^α, exponent α = 1")
            && got[0].message.contains("compressed by"),
        "{}",
        got[0].message
    );
    for ev in &got[1..4] {
        assert_eq!(ev.status, ExitVelocity::STATUS_REJECTED, "swing {}", ev.swing_id);
        assert!(ev.message.starts_with("measured_exit_speed = "), "{}", ev.message);
        assert!(ev.measured_exit_speed.is_nan() && ev.residual.is_nan(), "never echoed: {ev:?}");
    }
    assert!(got[3].message.starts_with("measured_exit_speed = 1e300 m/s"), "{}", got[3].message);
    assert_eq!(got[4].status, ExitVelocity::STATUS_OK, "{}", got[4].message);
    assert!(got[4].residual.is_finite());
    let (status, _, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
}
