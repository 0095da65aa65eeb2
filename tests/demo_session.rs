//! `sweetspot demo` end to end, over real DDS on loopback (run inside the private network namespace of
//! `scripts/test`): a short session through a real node child process; checks the printed table, the bag
//! (read back by `sweetspot bag info`, `sweetspot bag replay` and by the project's reader, every recorded answer recomputed from the
//! recorded inputs with the physics), and the figures.

use std::path::{Path, PathBuf};
use std::process::Command;

use sweetspot::bag::reader::read_bag;
use sweetspot::calibrate::problem_bat;
use sweetspot::model::convert::ball_from_params;
use sweetspot::model::settings::ModelSettings;
use sweetspot::msgs::decode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, ExitVelocity, Swing};
use sweetspot::msgs::RosMessage;
use sweetspot::physics::oblique::{collide_oblique, rpm_to_rad_per_s, ObliqueImpact, TangentialContact};
use sweetspot::physics::{CollisionOptions, Impact, ModeSet};

const SWINGS: usize = 8;

fn sweetspot() -> Command {
    Command::new(env!("CARGO_BIN_EXE_sweetspot"))
}

fn run_demo(out: &Path) -> String {
    sweetspot::ros::network_guard().expect("DDS tests must run in a private network namespace (scripts/test)");
    let output = sweetspot()
        .args([
            "demo",
            "--swings",
            &SWINGS.to_string(),
            "--bats",
            "r161,aluminum",
            "--swings-per-bat",
            "2",
            "--seed",
            "3",
        ])
        .args(["--timeout", "300", "--format", "png", "--out"])
        .arg(out)
        .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
        .output()
        .expect("run sweetspot demo");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "demo failed: {}\nstdout:\n{stdout}\nstderr:\n{stderr}", output.status);
    stdout
}

fn bag_path(stdout: &str) -> PathBuf {
    let line = stdout.lines().find(|l| l.starts_with("bag:")).unwrap_or_else(|| panic!("no bag line in:\n{stdout}"));
    PathBuf::from(line.trim_start_matches("bag:").split_whitespace().next().unwrap())
}

#[test]
fn demo_runs_a_session_through_dds_and_leaves_a_bag_and_figures() {
    let tmp = tempfile::tempdir().unwrap();
    let stdout = run_demo(tmp.path());

    // The table: one row per bat with its swings, sensible numbers.
    for bat in ["r161", "aluminum"] {
        let row = stdout
            .lines()
            .find(|l| l.split_whitespace().next() == Some(bat))
            .unwrap_or_else(|| panic!("no row for {bat} in:\n{stdout}"));
        let cells: Vec<&str> = row.split_whitespace().collect();
        assert_eq!(cells[1], (SWINGS / 2).to_string(), "{row}");
        // bat, swings, swing weight, bat speed (mph), time gained, mean exit (mph), best exit (mph), sweet
        // spot (in), BBCOR, …
        let swing_weight: f64 = cells[2].parse().unwrap();
        assert!((0.05..0.4).contains(&swing_weight), "swing weight {swing_weight} kg·m² in {row}");
        let bat_speed: f64 = cells[3].parse().unwrap();
        assert!((20.0..45.0).contains(&bat_speed), "bat speed {bat_speed} m/s in {row}");
        let mean: f64 = cells[6].parse().unwrap();
        // A real session's exit speeds, roughly 60–120 mph, the aluminum bat swung at its equal-effort speed.
        assert!((25.0..55.0).contains(&mean), "mean exit speed {mean} m/s in {row}");
        let bbcor: f64 = cells[12].parse().unwrap();
        assert!((0.3..0.7).contains(&bbcor), "BBCOR {bbcor} in {row}");
        assert!(row.contains('%'), "{row}");
        // …, vibration (%), measured − model (mean ± RMS), launch angle (deg, model / measured), spin (rpm,
        // model / measured). The demo's rig swings upward (attack angle +10° on average) at pitches descending
        // 6°, with undercuts centred on 0: the session's mean launch angle is positive, and at these launch
        // angles trackers report backspin of some hundreds to a few thousand rpm.
        let (launch, launch_measured): (f64, f64) = (cells[18].parse().unwrap(), cells[20].parse().unwrap());
        assert_eq!(cells[19], "/", "{row}");
        assert!((0.0..45.0).contains(&launch), "mean launch angle {launch}° in {row}");
        // Model and tracker differ by the tracker's noise (1°, 100 rpm) and by what the noise in the reported
        // inputs does to the model (a 2 mm undercut error moves the launch ≈ 3° and the spin ≈ 500 rpm): about
        // 1.7° and 250 rpm on a mean of 4 swings; the bounds are 5σ of that.
        assert!((launch - launch_measured).abs() < 8.0, "model {launch}° vs tracker {launch_measured}° in {row}");
        let (spin, spin_measured): (f64, f64) = (cells[21].parse().unwrap(), cells[23].parse().unwrap());
        assert!((0.0..6000.0).contains(&spin), "mean spin {spin} rpm in {row}");
        assert!((spin - spin_measured).abs() < 1200.0, "model {spin} rpm vs tracker {spin_measured} rpm in {row}");
    }

    // The bag: complete, with every input and answer, readable by `sweetspot bag info`.
    let bag = bag_path(&stdout);
    assert!(bag.join("metadata.yaml").is_file(), "{}", bag.display());
    let info = sweetspot().args(["bag", "info"]).arg(&bag).output().unwrap();
    let info_text = String::from_utf8_lossy(&info.stdout);
    assert!(info.status.success(), "bag info failed: {}", String::from_utf8_lossy(&info.stderr));
    assert!(info_text.contains("/demo/swing") && info_text.contains("sweetspot_msgs/msg/ExitVelocity"), "{info_text}");

    // `sweetspot bag replay` re-runs the model on every recorded swing and must match bit for bit.
    let replay = sweetspot().args(["bag", "replay"]).arg(&bag).output().unwrap();
    let replay_text = String::from_utf8_lossy(&replay.stdout);
    assert!(replay.status.success(), "bag replay failed: {replay_text}{}", String::from_utf8_lossy(&replay.stderr));
    assert!(replay_text.contains(&format!("{SWINGS} swings: {SWINGS} match, 0 differ")), "{replay_text}");

    // And independently: every recorded ExitVelocity equals the physics recomputed from the recorded params and swing.
    let (mut bats, mut balls, mut swings, mut exits) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    read_bag(&bag, |m| match m.channel.topic.type_name.as_str() {
        t if t == BatParams::TYPE_NAME => bats.push(decode_cdr::<BatParams>(m.data).unwrap()),
        t if t == BallParams::TYPE_NAME => balls.push(decode_cdr::<BallParams>(m.data).unwrap()),
        t if t == Swing::TYPE_NAME => swings.push(decode_cdr::<Swing>(m.data).unwrap()),
        t if t == ExitVelocity::TYPE_NAME => exits.push(decode_cdr::<ExitVelocity>(m.data).unwrap()),
        _ => {}
    })
    .unwrap();
    assert_eq!((bats.len(), balls.len(), swings.len(), exits.len()), (2, 1, SWINGS, SWINGS));
    let ball = ball_from_params(&balls[0]).unwrap().ball;
    for swing in &swings {
        let exit = exits.iter().find(|e| e.swing_id == swing.swing_id).expect("an answer per swing");
        assert_eq!(exit.status, ExitVelocity::STATUS_OK, "{}", exit.message);
        let params = bats.iter().find(|b| b.bat_id == swing.bat_id).unwrap();
        let bat = problem_bat(params, &ModelSettings::default()).unwrap();
        let (bat, modes) = (bat.bat, bat.modes);
        let set = ModeSet::compute(&bat, modes).unwrap();
        let impact = Impact {
            ball_speed: swing.ball_speed,
            bat_cm_speed: swing.bat_cm_speed,
            bat_angular_speed: swing.bat_angular_speed,
            impact_z: swing.impact_z,
        };
        let options = CollisionOptions { modes, time_step: 5e-6 };
        // The demo's rig swings obliquely: every swing carries its geometry and the tracker's launch readings.
        assert!(swing.undercut != 0.0 && swing.attack_angle != 0.0 && swing.pitch_angle != 0.0, "{swing:?}");
        assert!(swing.pitch_spin > 0.0, "a fastball's backspin: {}", swing.pitch_spin);
        let oblique = ObliqueImpact {
            impact,
            barrel_radius: bat.radii_at(swing.impact_z).0,
            undercut: swing.undercut,
            attack_angle: swing.attack_angle,
            pitch_angle: swing.pitch_angle,
            pitch_spin: swing.pitch_spin,
        };
        let r = collide_oblique(&set, &ball, &oblique, &TangentialContact::default(), &options).unwrap();
        assert!(
            (r.exit_speed - exit.exit_speed).abs() < 1e-9,
            "swing {}: {} vs {}",
            swing.swing_id,
            r.exit_speed,
            exit.exit_speed
        );
        assert!((r.launch_angle - exit.launch_angle).abs() < 1e-9 && (r.spin - exit.spin).abs() < 1e-6);
        assert!(swing.measured_exit_speed.is_finite() && (swing.measured_exit_speed - r.exit_speed).abs() < 5.0);
        assert_eq!(exit.measured_exit_speed, swing.measured_exit_speed);
        // The tracker's readings: within 5σ of the model the node computed from the reported inputs of the same
        // swing (σ ≈ 3.4° and 500 rpm per swing, as above); a missing reading or a flipped sign falls outside.
        assert!((swing.measured_launch_angle - r.launch_angle).abs() < 17f64.to_radians(), "{swing:?}");
        assert!((swing.measured_spin - r.spin).abs() < rpm_to_rad_per_s(2500.0), "{swing:?}");
        assert_eq!(exit.launch_angle_residual, swing.measured_launch_angle - exit.launch_angle);
        // A line drive or fly ball is hit with backspin, of the order trackers report (0–6000 rpm; the model's
        // defaults run high at large launch angles, see physics::oblique).
        if (10f64.to_radians()..40f64.to_radians()).contains(&r.launch_angle) {
            assert!((0.0..6000.0).contains(&r.spin_rpm()), "swing {}: {} rpm", swing.swing_id, r.spin_rpm());
        }
    }

    // The figures, next to the bag.
    let figures = sweetspot::demo::figures_dir(&bag);
    assert_eq!(figures, bag.parent().unwrap().join("figures").join(bag.file_name().unwrap()));
    for file in [
        "demo-exit-speed-vs-impact.png",
        "fig2-rigid-exit-speed.png",
        "fig5-normal-vs-corked.png",
        "fig6-wood-vs-aluminum.png",
        "mode-shapes.png",
    ] {
        let bytes = std::fs::read(figures.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() > 10_000, "{file}: {} bytes", bytes.len());
        assert!(stdout.contains(file), "{file} not listed in:\n{stdout}");
    }
    assert!(figures.join("README.md").is_file());
}
