//! `locate` runs a swing with a tilted bat or a path off centre through the 3-D collision: swings computed by
//! the node's engine at known impact points and undercuts (a right- and a left-handed batter, bat tilted 30°,
//! path 15° toward the pull side), written to a bag with what a radar measures (exit speed, launch angle,
//! total spin and its axis, spray angle), are located back at the truth, and the model's spray angle and
//! spin axis there match the measured ones.

use std::path::Path;

use sweetspot::bag::writer::BagWriter;
use sweetspot::bag::{RecordedQos, TopicInfo};
use sweetspot::locate::{locate_bag, LocateOptions, Outcome, Solution};
use sweetspot::model::convert::swing_input;
use sweetspot::model::engine::{compute, plan_swing, Registry};
use sweetspot::model::settings::ModelSettings;
use sweetspot::model::time::RosTime;
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::Swing;

/// Truth: (impact_z, undercut), m, clear of the sweet spot (≈ 0.70 m on the r161) where dv/dz vanishes.
const TRUTH: [(f64, f64); 4] = [(0.62, 0.010), (0.65, -0.004), (0.76, 0.015), (0.79, 0.006)];

/// A swing of a batter on `side`, its path 15° toward his pull side, the bat 30° below the horizontal.
fn swing(id: u64, side: u8, z: f64, d: f64) -> Swing {
    let pull = if side == Swing::BATTER_LEFT { 15f64 } else { -15f64 };
    Swing {
        header: Header { stamp: Time::from_unix_ns(1_000_000_000 * id), frame_id: String::new() },
        swing_id: id,
        bat_id: "r161".into(),
        ball_id: "baseball".into(),
        ball_speed: 38.0,
        bat_cm_speed: 22.0,
        bat_angular_speed: 48.0,
        impact_z: z,
        undercut: d,
        attack_angle: 10f64.to_radians(),
        pitch_angle: 6f64.to_radians(),
        pitch_spin: 230.0,
        bat_tilt: 30f64.to_radians(),
        swing_direction: pull.to_radians(),
        batter_side: side,
        ..Swing::default()
    }
}

/// `swing` with what a radar would measure of the node's answer to it.
fn measured(mut swing: Swing) -> Swing {
    let settings = ModelSettings::default();
    let mut registry = Registry::with_limits(settings.max_bats, settings.max_balls);
    let (plan, _) = plan_swing(&mut registry, &settings, "r161", "baseball", swing_input(&swing));
    let launch = compute(&plan, &()).expect("the swing computes").launch;
    assert!(launch.spray_angle.abs() > 0.05, "a 3-D swing: {launch:?}");
    swing.measured_exit_speed = launch.exit_speed;
    swing.measured_launch_angle = launch.launch_angle;
    swing.measured_spin = launch.total_spin;
    swing.measured_spin_axis = launch.spin_axis;
    swing.measured_spray_angle = launch.spray_angle;
    // Where the search starts: the model's usual point, level.
    swing.impact_z = 0.70;
    swing.undercut = 0.0;
    swing
}

fn write_bag(dir: &Path, swings: &[Swing]) {
    let qos = RecordedQos { reliable: true, transient_local: false, depth: 1000 };
    let mut writer = BagWriter::create(dir, None, None).unwrap();
    let topic = writer.add_topic(TopicInfo::of::<Swing>("/swing", qos)).unwrap();
    for (i, s) in swings.iter().enumerate() {
        let t = 1_000_000 * (i as u64 + 1);
        writer.write(topic, &encode_cdr(s).unwrap(), t, t).unwrap();
    }
    writer.finish().unwrap();
}

fn nearest(solutions: &[Solution], z: f64) -> &Solution {
    solutions.iter().min_by(|a, b| (a.impact_z - z).abs().total_cmp(&(b.impact_z - z).abs())).unwrap()
}

#[test]
fn tilted_swings_are_located_at_the_truth_with_spray_and_spin_axis_residuals_near_zero() {
    let tmp = tempfile::tempdir().unwrap();
    let mut truths = Vec::new();
    let mut swings = Vec::new();
    for side in [Swing::BATTER_RIGHT, Swing::BATTER_LEFT] {
        for &(z, d) in &TRUTH {
            swings.push(measured(swing(swings.len() as u64 + 1, side, z, d)));
            truths.push((z, d));
        }
    }
    let bag = tmp.path().join("bag");
    write_bag(&bag, &swings);
    let report = locate_bag(&bag, &LocateOptions::default()).unwrap();
    assert_eq!(report.located, swings.len(), "{:#?}", report.swings);
    for ((located, &(z, d)), swing) in report.swings.iter().zip(&truths).zip(&swings) {
        let id = located.swing_id;
        let Outcome::Located { solutions, .. } = &located.outcome else { panic!("swing {id}: {located:?}") };
        let s = nearest(solutions, z);
        // Noise-free: the truth reproduces all three measurements, within a fraction of its uncertainty.
        assert!(s.chi2 < 1e-6, "swing {id}: χ² {}", s.chi2);
        assert!(
            (s.impact_z - z).abs() <= (0.1 * s.impact_z_sigma).max(1e-4),
            "swing {id}: z {} ± {} against {z}",
            s.impact_z,
            s.impact_z_sigma
        );
        assert!(
            (s.undercut - d).abs() <= (0.1 * s.undercut_sigma).max(1e-4),
            "swing {id}: D {} ± {} against {d}",
            s.undercut,
            s.undercut_sigma
        );
        let direction = s.direction.expect("a 3-D swing reports its direction");
        assert!(direction.spray_angle_residual.abs() < 1e-4, "swing {id}: {direction:?}");
        assert!(direction.spin_axis_residual.abs() < 1e-3, "swing {id}: {direction:?}");
        // Pulled: right-handed to left field, left-handed to right field.
        let toward_right = swing.batter_side == Swing::BATTER_LEFT;
        assert_eq!(direction.spray_angle > 0.0, toward_right, "swing {id}: {direction:?}");
        assert_eq!(located.measured_direction, Some([swing.measured_spray_angle, swing.measured_spin_axis]));
        // The spin compared is the radar's backspin part, total × −cos axis, as the node's spin_residual.
        let backspin = -swing.measured_spin * swing.measured_spin_axis.cos();
        assert_eq!(located.measured[2], backspin);
    }
    // The table and JSON carry the direction.
    let json = serde_json::to_value(&report).unwrap();
    let first = &json["swings"][0]["solutions"][0]["direction"];
    assert!(first["spray_angle"].is_number() && first["spin_axis_residual"].is_number(), "{first}");
}

/// A planar swing with nothing measured about its direction reports none: its JSON is what it was.
#[test]
fn a_planar_swing_without_a_measured_direction_reports_none() {
    let tmp = tempfile::tempdir().unwrap();
    let mut planar = swing(1, Swing::BATTER_RIGHT, 0.65, 0.005);
    planar.bat_tilt = 0.0;
    planar.swing_direction = 0.0;
    let mut planar = measured_planar(planar);
    planar.measured_spray_angle = f64::NAN;
    planar.measured_spin_axis = f64::NAN;
    let bag = tmp.path().join("bag");
    write_bag(&bag, &[planar]);
    let report = locate_bag(&bag, &LocateOptions::default()).unwrap();
    let located = &report.swings[0];
    assert_eq!(located.measured_direction, None);
    let Outcome::Located { solutions, .. } = &located.outcome else { panic!("{located:?}") };
    assert!(solutions.iter().all(|s| s.direction.is_none()));
    let json = serde_json::to_string(&report).unwrap();
    assert!(!json.contains("direction"), "{json}");
}

/// The planar swing's node answer as a tracker measures it: exit speed, launch angle, backspin.
fn measured_planar(mut swing: Swing) -> Swing {
    let settings = ModelSettings::default();
    let mut registry = Registry::with_limits(settings.max_bats, settings.max_balls);
    let (plan, _) = plan_swing(&mut registry, &settings, "r161", "baseball", swing_input(&swing));
    let launch = compute(&plan, &()).expect("the swing computes").launch;
    swing.measured_exit_speed = launch.exit_speed;
    swing.measured_launch_angle = launch.launch_angle;
    swing.measured_spin = launch.spin;
    swing.impact_z = 0.70;
    swing.undercut = 0.0;
    swing
}
