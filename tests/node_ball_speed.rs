//! Over real DDS on loopback (inside scripts/test's private network namespace): a BallParams carrying a COR
//! speed law (`cor_speed_exponent`, `cor_reference_speed`) reaches the node, whose answers then equal the
//! library's collision with that ball — e0 taken at each swing's own approach speed — while the same params
//! without the law (0, what older publishers send) answer as the constant-COR ball.

mod support;

use std::time::Duration;

use support::node::{blocking, dds, domain, keep_all, NodeProcess, Peer};
use sweetspot::model::convert;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, ExitVelocity, Swing};
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

const WAIT: Duration = Duration::from_secs(60);

#[test]
fn the_node_takes_e0_at_each_swings_speed_from_the_ball_params() {
    let domain = domain(97);
    let dir = tempfile::tempdir().unwrap();
    let mut peer = Peer::new(domain, "ball_speed_peer");
    let ball_pub = peer.publisher::<BallParams>("/ball/params", dds::params());
    let swing_pub = peer.publisher::<Swing>("/swing", blocking(dds::swing()));
    let answers = peer.subscription::<ExitVelocity>("/exit_velocity", keep_all(dds::results()));
    let node = NodeProcess::spawn(domain, dir.path(), &["--no-record", "--ros-args", "-p", "default_modes:=6"]);
    let game = Ball::mlb();
    let with_law = convert::params_from_ball("game", &game, None, Header::default());
    assert!(with_law.cor_speed_exponent > 0.0);
    let without =
        BallParams { ball_id: "old".into(), cor_speed_exponent: 0.0, cor_reference_speed: 0.0, ..with_law.clone() };
    ball_pub.publish(with_law).unwrap();
    node.wait_for_log("ball 'game' set", WAIT);
    ball_pub.publish(without).unwrap();
    node.wait_for_log("ball 'old' set", WAIT);
    peer.wait_for_reader(&swing_pub);
    let swing = |id: u64, ball_id: &str, ball_speed: f64| Swing {
        swing_id: id,
        bat_id: "r161".into(),
        ball_id: ball_id.into(),
        ball_speed,
        bat_cm_speed: 20.0,
        bat_angular_speed: 45.0,
        impact_z: 0.70,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    };
    let sent = [swing(1, "game", 30.0), swing(2, "game", 45.0), swing(3, "old", 30.0), swing(4, "old", 45.0)];
    for s in &sent {
        swing_pub.publish(s.clone()).unwrap();
    }
    let got = peer.collect(&answers, sent.len(), WAIT);
    let set = ModeSet::compute(&Bat::preset("r161").unwrap(), 6).unwrap();
    let options = CollisionOptions { modes: 6, time_step: 5e-6 };
    // Without the law the ball is a constant 0.66 (its `cor`), as any BallParams from before the fields.
    let constant = Ball { cor_speed_exponent: 0.0, cor_reference_speed: 0.0, ..game };
    for s in &sent {
        let ev = got.iter().find(|e| e.swing_id == s.swing_id).expect("an answer per swing");
        assert_eq!(ev.status, ExitVelocity::STATUS_OK, "{}", ev.message);
        let ball = if s.ball_id == "game" { game } else { constant };
        let impact = Impact { ball_speed: s.ball_speed, bat_cm_speed: 20.0, bat_angular_speed: 45.0, impact_z: 0.70 };
        let r = collide(&set, &ball, &impact, &options).unwrap();
        assert_eq!(ev.exit_speed, r.exit_speed, "swing {}", s.swing_id);
    }
    let exit = |id: u64| got.iter().find(|e| e.swing_id == id).unwrap().exit_speed;
    // The law makes the game ball deader than its 1-m/s COR at both speeds, and more so at the faster pitch.
    assert!(exit(1) < exit(3) && exit(2) < exit(4));
    assert!(exit(4) - exit(2) > exit(3) - exit(1));
    drop(node);
}
