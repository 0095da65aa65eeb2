//! End to end over real DDS on loopback (inside the private network namespace of scripts/test): the
//! `sweetspot node` binary in its own process, and this test process publishing params and swings and
//! listening to the answers. Every number the node publishes is compared with the library's for the same
//! inputs, exactly (the same code computes both).

mod support;

use std::collections::HashMap;
use std::time::{Duration, Instant};

use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::model::convert;
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, ModalEnergies, SweetSpot, Swing};
use sweetspot::physics::{collide, metrics, Ball, Bat, CollisionOptions, CollisionResult, Impact, ModeSet};

const WAIT: Duration = Duration::from_secs(60);

fn header(sec: i32) -> Header {
    Header { stamp: Time { sec, nanosec: 500 }, frame_id: "rig".into() }
}

/// BatParams spelling out every field of `bat` (no preset), under `bat_id`: the node's own conversion.
fn explicit_params(bat_id: &str, bat: &Bat, max_modes: u32) -> BatParams {
    convert::params_from_bat(bat_id, bat, max_modes as usize, header(1))
}

fn ball_params(ball_id: &str, ball: &Ball) -> BallParams {
    BallParams {
        header: header(2),
        ball_id: ball_id.into(),
        mass: ball.mass,
        radius: ball.radius,
        cor: ball.cor,
        stiffness: ball.stiffness,
        exponent: ball.exponent,
        ..BallParams::default()
    }
}

fn swing(id: u64, bat_id: &str, ball_id: &str, impact_z: f64) -> Swing {
    Swing {
        header: header(1000 + id as i32),
        swing_id: id,
        bat_id: bat_id.into(),
        ball_id: ball_id.into(),
        ball_speed: 38.0 + (id % 5) as f64,
        bat_cm_speed: 18.0,
        bat_angular_speed: 45.0,
        impact_z,
        measured_exit_speed: if id.is_multiple_of(2) { f64::NAN } else { 44.0 },
        ..Swing::default()
    }
}

fn impact(s: &Swing) -> Impact {
    Impact {
        ball_speed: s.ball_speed,
        bat_cm_speed: s.bat_cm_speed,
        bat_angular_speed: s.bat_angular_speed,
        impact_z: s.impact_z,
    }
}

fn library(bat: &Bat, modes: usize, ball: &Ball, s: &Swing) -> (ModeSet, CollisionResult) {
    let set = ModeSet::compute(bat, modes).unwrap();
    let result = collide(&set, ball, &impact(s), &CollisionOptions { modes, time_step: 5e-6 }).unwrap();
    (set, result)
}

fn assert_answer_equals(ev: &ExitVelocity, s: &Swing, r: &CollisionResult) {
    assert_eq!(ev.status, ExitVelocity::STATUS_OK, "swing {}: {}", s.swing_id, ev.message);
    assert_eq!(ev.header, s.header);
    assert_eq!(ev.impact_z, s.impact_z);
    assert_eq!(ev.exit_speed, r.exit_speed, "swing {}", s.swing_id);
    assert_eq!(ev.rigid_exit_speed, r.rigid_exit_speed);
    assert_eq!(ev.effective_cor, r.effective_cor);
    assert_eq!(ev.collision_efficiency, r.collision_efficiency);
    assert_eq!(ev.contact_time, r.contact_time);
    assert_eq!(ev.peak_force, r.peak_force);
    assert_eq!(ev.impulse, r.impulse);
    assert_eq!(ev.max_compression, r.max_compression);
    if s.measured_exit_speed.is_nan() {
        assert!(ev.measured_exit_speed.is_nan() && ev.residual.is_nan());
    } else {
        assert_eq!(ev.measured_exit_speed, s.measured_exit_speed);
        assert_eq!(ev.residual, s.measured_exit_speed - r.exit_speed);
    }
}

fn assert_energies_equal(me: &ModalEnergies, s: &Swing, r: &CollisionResult, bat_mass: f64, ball: &Ball) {
    assert_eq!((me.swing_id, &me.header), (s.swing_id, &s.header));
    assert_eq!(me.frequency, r.mode_energies.iter().map(|m| m.frequency).collect::<Vec<_>>());
    assert_eq!(me.energy, r.mode_energies.iter().map(|m| m.energy).collect::<Vec<_>>());
    assert_eq!(me.vibration_energy, r.energy.vibration);
    assert_eq!(me.hysteresis_loss, r.energy.hysteresis_loss);
    assert_eq!(me.energy_residual, r.energy.residual);
    // Independent spelling of the centre-of-mass-frame collision energy.
    let v_cm = (bat_mass * s.bat_cm_speed - ball.mass * s.ball_speed) / (bat_mass + ball.mass);
    let collision_energy = r.energy.initial - 0.5 * (bat_mass + ball.mass) * v_cm * v_cm;
    for (f, m) in me.fraction.iter().zip(&r.mode_energies) {
        assert!(
            (f - m.energy / collision_energy).abs() <= 1e-12 * f.abs().max(1e-300),
            "{f} vs {}",
            m.energy / collision_energy
        );
    }
}

#[test]
fn answers_equal_the_library_for_params_presets_and_defaults() {
    let domain = domain(1);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "e2e_peer");
    let bat_pub = peer.publisher::<BatParams>("/bat/params", dds::params());
    let ball_pub = peer.publisher::<BallParams>("/ball/params", dds::params());
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let energies = peer.subscription::<ModalEnergies>("/modal_energies", keep_all(dds::results()));
    let sweet_spots = peer.subscription::<SweetSpot>("/sweet_spot", keep_all(dds::latched_results()));

    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    let lab_bat = Bat::preset("torpedo").unwrap();
    let lab_ball = Ball { mass: 0.15, cor: 0.5, stiffness: 7.0e7, ..Ball::default() };
    ball_pub.publish(ball_params("lab_ball", &lab_ball)).unwrap();
    node.wait_for_log("ball 'lab_ball' set", WAIT);
    bat_pub.publish(explicit_params("lab_bat", &lab_bat, 0)).unwrap();
    // The bat's SweetSpot shows the node has taken the params; its reference ball is the latest, lab_ball.
    let spots = peer.collect_until(&sweet_spots, WAIT, |got| got.iter().any(|s| s.bat_id == "lab_bat"));
    let spot = spots.iter().rev().find(|s| s.bat_id == "lab_bat").unwrap();
    assert_eq!(spot.ball_id, "lab_ball");
    let spot_ball = lab_ball;
    let modes = ModeSet::compute(&lab_bat, 18).unwrap();
    let options = CollisionOptions { modes: 18, time_step: 5e-6 };
    let reference = Impact { ball_speed: 40.0, bat_cm_speed: 20.0, bat_angular_speed: 50.0, impact_z: 0.0 };
    let expected = metrics::sweet_spots(&modes, &spot_ball, &reference, &options).unwrap();
    assert_eq!(spot.max_exit_speed_z, expected.max_exit_speed_z);
    assert_eq!(spot.max_exit_speed, expected.max_exit_speed);
    assert_eq!(spot.rigid_optimum_z, expected.rigid_optimum_z);
    assert_eq!((spot.node1_z, spot.node2_z), (expected.node1_z, expected.node2_z));
    assert_eq!(spot.center_of_percussion_z, expected.center_of_percussion_z);
    assert_eq!(spot.bbcor, metrics::bbcor(&modes, &options).unwrap());
    assert_eq!(spot.frequency, modes.frequencies_hz());
    assert_eq!(spot.mass, modes.mass_properties().mass);
    assert_eq!((spot.ball_speed, spot.bat_cm_speed, spot.bat_angular_speed), (40.0, 20.0, 50.0));
    peer.wait_for_reader(&swing_pub);

    let swings = vec![
        swing(1, "lab_bat", "lab_ball", 0.55),
        swing(2, "", "", 0.62),
        swing(3, "r161", "baseball", 0.70),
        swing(4, "torpedo", "", 0.65),
        swing(5, "lab_bat", "baseball", 0.45),
    ];
    for s in &swings {
        swing_pub.publish(s.clone()).unwrap();
    }
    let got = peer.collect(&answers, swings.len(), WAIT);
    let got_energies = peer.collect(&energies, swings.len(), WAIT);
    let r161 = Bat::preset("r161").unwrap();
    let expectations: Vec<(&Bat, &str, Ball, &str)> = vec![
        (&lab_bat, "lab_bat", lab_ball, "lab_ball"),
        (&lab_bat, "lab_bat", lab_ball, "lab_ball"), // empty ids = the latest received
        (&r161, "r161", Ball::default(), "baseball"),
        (&lab_bat, "torpedo", lab_ball, "lab_ball"),
        (&lab_bat, "lab_bat", Ball::default(), "baseball"),
    ];
    for (((s, ev), me), (bat, bat_id, ball, ball_id)) in swings.iter().zip(&got).zip(&got_energies).zip(expectations) {
        assert_eq!(ev.swing_id, s.swing_id, "answers in swing order");
        assert_eq!((ev.bat_id.as_str(), ev.ball_id.as_str()), (bat_id, ball_id));
        let (set, r) = library(bat, 18, &ball, s);
        assert_answer_equals(ev, s, &r);
        assert_energies_equal(me, s, &r, set.mass_properties().mass, &ball);
    }
    let (_, elapsed, log) = node.stop_with(15);
    println!("node stopped {elapsed:?} after SIGTERM\n{log}");
}

#[test]
fn a_node_started_after_the_params_still_gets_them() {
    let domain = domain(2);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "late_peer");
    let bat_pub = peer.publisher::<BatParams>("/bat/params", dds::params());
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let energies = peer.subscription::<ModalEnergies>("/modal_energies", keep_all(dds::results()));
    let late_bat = Bat::preset("aluminum").unwrap();
    // Published (latched) before the node exists.
    bat_pub.publish(explicit_params("late_bat", &late_bat, 6)).unwrap();

    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    node.wait_for_log("bat 'late_bat' set", WAIT);
    peer.wait_for_reader(&swing_pub);
    let s = swing(7, "late_bat", "", 0.6);
    swing_pub.publish(s.clone()).unwrap();
    let ev = &peer.collect(&answers, 1, WAIT)[0];
    let me = &peer.collect(&energies, 1, WAIT)[0];
    // No ball named or sent: the node's default_ball, the game ball.
    let (set, r) = library(&late_bat, 6, &Ball::game(), &s);
    assert_answer_equals(ev, &s, &r);
    assert_eq!(ev.ball_id, "mlb2024");
    assert_eq!(me.frequency.len(), 6, "max_modes = 6 from the latched params");
    assert_energies_equal(me, &s, &r, set.mass_properties().mass, &Ball::game());
    drop(node);
}

#[test]
fn ten_thousand_swings_sent_back_to_back_are_all_answered_in_order() {
    const N: u64 = 10_000;
    let domain = domain(3);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "burst_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);
    peer.wait_for_reader(&swing_pub);

    let swings: Vec<Swing> = (0..N).map(|i| swing(i, "r161", "", 0.45 + 0.3 * (i % 97) as f64 / 96.0)).collect();
    let start = Instant::now();
    let sender = {
        let swings = swings.clone();
        std::thread::spawn(move || {
            for s in swings {
                swing_pub.publish(s).expect("blocking reliable publish");
            }
            swing_pub
        })
    };
    let got = peer.collect(&answers, N as usize, WAIT);
    let elapsed = start.elapsed();
    let _swing_pub = sender.join().unwrap();
    let ids: Vec<u64> = got.iter().map(|ev| ev.swing_id).collect();
    assert_eq!(ids, (0..N).collect::<Vec<_>>(), "every swing answered once, in order");
    assert!(got.iter().all(|ev| ev.status == ExitVelocity::STATUS_OK));
    // Spot-check numbers across the run.
    let r161 = Bat::preset("r161").unwrap();
    let set = ModeSet::compute(&r161, 18).unwrap();
    for k in [0usize, 1, 4_999, 9_998, 9_999] {
        let r = collide(&set, &Ball::game(), &impact(&swings[k]), &CollisionOptions::default()).unwrap();
        assert_answer_equals(&got[k], &swings[k], &r);
    }
    let (status, stop, log) = node.stop_with(15);
    assert!(status.success(), "{log}");
    let summary = log.lines().find(|l| l.contains("latency p50")).unwrap_or("(no summary)").to_string();
    assert!(summary.contains(&format!("{N} swings received")), "{summary}");
    assert!(summary.contains(" 0 dropped"), "{summary}");
    println!(
        "{N} swings answered in {elapsed:.2?} ({:.0} swings/s end to end); node exit {stop:?} after SIGTERM; {summary}",
        N as f64 / elapsed.as_secs_f64()
    );
}

#[test]
fn bad_params_and_swings_are_rejected_with_reasons_and_the_node_keeps_answering() {
    let domain = domain(4);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "bad_peer");
    let bat_pub = peer.publisher::<BatParams>("/bat/params", dds::params());
    let ball_pub = peer.publisher::<BallParams>("/ball/params", dds::params());
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record"]);

    bat_pub
        .publish(BatParams { header: header(3), bat_id: "good".into(), preset: "r161".into(), ..BatParams::default() })
        .unwrap();
    node.wait_for_log("bat 'good' set", WAIT);
    // The same bat_id again with a bore wider than the bat: refused, the r161 stays in force.
    let mut broken = explicit_params("good", &Bat::preset("r161").unwrap(), 0);
    broken.inner_radius = broken.outer_radius.iter().map(|r| r * 1.5).collect();
    bat_pub.publish(broken).unwrap();
    ball_pub.publish(BallParams { cor: 1.5, ..ball_params("bouncy", &Ball::default()) }).unwrap();
    let rejections = peer.collect(&answers, 2, WAIT);
    let bat_rejection =
        rejections.iter().find(|ev| ev.message.starts_with("BatParams 'good'")).expect("bat params rejected");
    assert_eq!(bat_rejection.status, ExitVelocity::STATUS_REJECTED);
    assert_eq!(bat_rejection.bat_id, "good");
    assert!(bat_rejection.message.contains("inner"), "{}", bat_rejection.message);
    assert!(bat_rejection.message.contains("stay in force"), "{}", bat_rejection.message);
    let ball_rejection =
        rejections.iter().find(|ev| ev.message.starts_with("BallParams 'bouncy'")).expect("ball params rejected");
    assert!(ball_rejection.message.contains("cor"), "{}", ball_rejection.message);
    assert!(ball_rejection.exit_speed.is_nan());

    peer.wait_for_reader(&swing_pub);
    let bad = vec![
        (Swing { ball_speed: f64::NAN, ..swing(10, "good", "", 0.6) }, "ball_speed"),
        (swing(11, "good", "", 2.5), "impact_z"),
        (swing(12, "nope", "", 0.6), "unknown bat_id 'nope'"),
        (swing(13, "good", "bouncy", 0.6), "unknown ball_id 'bouncy'"),
        (Swing { bat_angular_speed: f64::INFINITY, ..swing(14, "good", "", 0.6) }, "bat_angular_speed"),
    ];
    let good = swing(15, "good", "", 0.6);
    for (s, _) in &bad {
        swing_pub.publish(s.clone()).unwrap();
    }
    swing_pub.publish(good.clone()).unwrap();
    let got = peer.collect(&answers, bad.len() + 1, WAIT);
    for ((s, why), ev) in bad.iter().zip(&got) {
        assert_eq!(ev.swing_id, s.swing_id);
        assert_eq!(ev.status, ExitVelocity::STATUS_REJECTED, "swing {}", s.swing_id);
        assert!(ev.message.contains(why), "swing {}: '{}' should mention {why}", s.swing_id, ev.message);
        assert!(ev.exit_speed.is_nan());
    }
    let (_, r) = library(&Bat::preset("r161").unwrap(), 18, &Ball::game(), &good);
    assert_answer_equals(&got[bad.len()], &good, &r);
    let mut seen = HashMap::new();
    for ev in &got {
        *seen.entry(ev.status).or_insert(0) += 1;
    }
    assert_eq!(seen.get(&ExitVelocity::STATUS_OK), Some(&1));
    let (status, _, log) = node.stop_with(2);
    assert!(status.success(), "SIGINT exits cleanly:\n{log}");
}

#[test]
fn a_full_queue_drops_counts_and_reports_instead_of_growing() {
    use sweetspot::msgs::diagnostic_msgs::msg::DiagnosticArray;
    use sweetspot::msgs::rcl_interfaces::msg::Log;
    const N: u64 = 3_000;
    const CAPACITY: u64 = 4;
    let domain = domain(8);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "flood_peer");
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let diagnostics = peer.subscription::<DiagnosticArray>("/diagnostics", keep_all(dds::results()));
    let rosout = peer.subscription::<Log>("/rosout", sweetspot::ros::rosout_qos());
    // One worker, four swings in flight, and a 0.1 µs time step (50× the work per swing): a flood must overflow.
    let node = NodeProcess::spawn(
        domain,
        dir.path(),
        &["--no-record", "--ros-args", "-p", "queue_capacity:=4", "-p", "workers:=1", "-p", "time_step:=1e-7"],
    );
    peer.wait_for_reader(&swing_pub);
    for i in 0..N {
        swing_pub.publish(swing(i, "r161", "", 0.6)).unwrap();
    }
    let value = |d: &DiagnosticArray, key: &str| -> u64 {
        d.status[0].values.iter().find(|kv| kv.key == key).map(|kv| kv.value.parse().unwrap()).unwrap()
    };
    let reports = peer.collect_until(&diagnostics, WAIT, |got| {
        got.last().is_some_and(|d| {
            value(d, "swings_received") + value(d, "swings_lost_in_transport") == N && value(d, "swings_in_flight") == 0
        })
    });
    let last = reports.last().unwrap();
    let (ok, rejected, dropped, unsent, lost) = (
        value(last, "swings_processed"),
        value(last, "swings_rejected"),
        value(last, "swings_dropped"),
        value(last, "publish_failures"),
        value(last, "swings_lost_in_transport"),
    );
    assert!(dropped > 0, "the flood must overflow a 4-swing queue");
    assert_eq!(unsent, 0, "a keep-all reader that keeps up leaves the send window room for every answer");
    assert_eq!(ok + rejected + dropped + lost, N, "every swing is answered or counted as dropped or lost");
    assert!(reports.iter().all(|d| value(d, "swings_in_flight") <= CAPACITY), "in flight never exceeds capacity");
    assert!(reports.iter().any(|d| d.status[0].level == 1 && d.status[0].message.contains("dropped")), "a WARN report");
    // One answer per swing taken: the dropped ones DROPPED (sent at once), the rest in swing order.
    let got = peer.collect(&answers, (ok + rejected + dropped) as usize, WAIT);
    let (dropped_answers, computed): (Vec<&ExitVelocity>, Vec<&ExitVelocity>) =
        got.iter().partition(|ev| ev.status == ExitVelocity::STATUS_DROPPED);
    assert_eq!(dropped_answers.len() as u64, dropped, "every dropped swing is answered DROPPED");
    assert!(dropped_answers.iter().all(|ev| ev.message.contains("queue_capacity") && ev.exit_speed.is_nan()));
    assert!(computed.windows(2).all(|w| w[0].swing_id < w[1].swing_id), "computed answers are in swing order");
    let mut ids: Vec<u64> = got.iter().map(|ev| ev.swing_id).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), got.len(), "no swing is answered twice");
    let warnings =
        peer.collect_until(&rosout, WAIT, |got| got.iter().any(|l| l.level == Log::WARN && l.msg.contains("dropped")));
    let warning = warnings.iter().find(|l| l.msg.contains("dropped")).unwrap();
    assert!(warning.msg.contains("queue_capacity"), "{}", warning.msg);
    println!(
        "{N} swings flooded into a 4-swing queue: {ok} answered, {dropped} dropped, {lost} lost in transport; rosout: {}",
        warning.msg
    );
    drop(node);
}

/// A ball's tangential contact (BallParams' appended fields) reaches the node's oblique collisions: a ball
/// that nearly rolls (e_T = 0.05), with a measured-style moment of inertia, and a ball left at the defaults (0) get
/// exactly the library's launch for their own contact, and different launches from each other.
#[test]
fn oblique_swings_use_the_contact_their_ball_params_give() {
    use sweetspot::physics::oblique::{collide_oblique, ObliqueImpact, TangentialContact};
    let domain = domain(11);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "contact_peer");
    let ball_pub = peer.publisher::<BallParams>("/ball/params", dds::params());
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record", "--ros-args", "-p", "default_modes:=6"]);
    let ball = Ball::default();
    let inertia = 0.37 * ball.mass * ball.radius * ball.radius;
    let grippy =
        BallParams { tangential_cor: 0.05, friction: 2.0, moment_of_inertia: inertia, ..ball_params("rolling", &ball) };
    // The node's own conversion (I in kg·m² → I/(m R²)) gives the contact the library is called with.
    let rolling = convert::ball_from_params(&grippy).unwrap().contact;
    assert_eq!((rolling.tangential_cor, rolling.friction), (0.05, 2.0));
    assert!((rolling.ball_inertia_ratio - 0.37).abs() < 1e-12);
    ball_pub.publish(grippy).unwrap();
    node.wait_for_log("ball 'rolling' set", WAIT);
    ball_pub.publish(ball_params("plain", &ball)).unwrap();
    node.wait_for_log("ball 'plain' set", WAIT);
    peer.wait_for_reader(&swing_pub);
    let oblique = |id: u64, ball_id: &str| Swing {
        undercut: 0.012,
        attack_angle: 8f64.to_radians(),
        pitch_angle: 6f64.to_radians(),
        pitch_spin: 200.0,
        ..swing(id, "r161", ball_id, 0.7)
    };
    let sent = [oblique(1, "rolling"), oblique(2, "plain")];
    for s in &sent {
        swing_pub.publish(s.clone()).unwrap();
    }
    let got = peer.collect(&answers, 2, WAIT);
    let bat = Bat::preset("r161").unwrap();
    let set = ModeSet::compute(&bat, 6).unwrap();
    for (s, contact) in sent.iter().zip([rolling, TangentialContact::default()]) {
        let ev = got.iter().find(|e| e.swing_id == s.swing_id).expect("an answer per swing");
        assert_eq!(ev.status, ExitVelocity::STATUS_OK, "{}", ev.message);
        let o = ObliqueImpact {
            impact: impact(s),
            barrel_radius: bat.radii_at(s.impact_z).0,
            undercut: s.undercut,
            attack_angle: s.attack_angle,
            pitch_angle: s.pitch_angle,
            pitch_spin: s.pitch_spin,
        };
        let r = collide_oblique(&set, &ball, &o, &contact, &CollisionOptions { modes: 6, time_step: 5e-6 }).unwrap();
        assert_eq!((ev.exit_speed, ev.launch_angle, ev.spin), (r.exit_speed, r.launch_angle, r.spin), "{}", s.ball_id);
    }
    let (a, b) = (&got[0], &got[1]);
    assert!((a.spin - b.spin).abs() > 10.0, "the two contacts gave the same spin: {} vs {}", a.spin, b.spin);
    drop(node);
}
