//! The batted ball in three dimensions from the command line: `--bat-tilt`, `--swing-direction` and
//! `--batter-side` on `simulate` and `sweep --over undercut`, the same keys in case files, and the flight
//! (spray angle, backspin, sidespin, gyro spin, total spin, spin axis) in their JSON.

mod support;

use serde_json::Value;
use support::cli::{fails, json, num, ok, sweetspot};
use sweetspot::physics::{
    collide_spatial, Ball, Bat, BatterSide, CollisionOptions, Impact, ModeSet, ObliqueImpact, SpatialImpact,
    TangentialContact,
};

const BASE: &[&str] = &["simulate", "--bat", "r161", "--modes", "6", "--impact-z", "0.7"];
/// A tilted swing toward the right-field side with undercut, a descending pitch and backspin.
const SWING: &[&str] = &[
    "--undercut",
    "0.01",
    "--attack-angle",
    "8",
    "--pitch-angle",
    "6",
    "--pitch-spin",
    "2000",
    "--bat-tilt",
    "30",
    "--swing-direction",
    "10",
];
/// The flight's keys in each oblique result.
const FLIGHT: [&str; 6] =
    ["spray_angle_deg", "backspin_rpm", "sidespin_rpm", "gyro_spin_rpm", "total_spin_rpm", "spin_axis_deg"];

fn with(extra: &[&str]) -> Vec<&'static str> {
    let mut args: Vec<&'static str> = BASE.to_vec();
    for a in extra {
        args.push(Box::leak(a.to_string().into_boxed_str()));
    }
    args
}

fn batted(doc: &Value, key: &str) -> f64 {
    num(doc, &format!("/results/0/oblique/{key}"))
}

fn close(a: f64, b: f64, tolerance: f64, what: &str) {
    assert!((a - b).abs() <= tolerance, "{what}: {a} vs {b} (tolerance {tolerance})");
}

#[test]
fn flags_case_file_and_library_give_the_same_batted_ball() {
    let flags = json(&with(&[SWING, &["--batter-side", "left"]].concat()));
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case.yaml");
    std::fs::write(
        &case,
        "bat: r161\nimpact_z: 0.7\nmodes: 6\nundercut: 0.01\nattack_angle_deg: 8\npitch_angle_deg: 6\n\
         pitch_spin_rpm: 2000\nbat_tilt_deg: 30\nswing_direction_deg: 10\nbatter_side: left\n",
    )
    .unwrap();
    let from_case = json(&["simulate", "--case", case.to_str().unwrap()]);
    assert_eq!(from_case, flags, "a case file is its flags");
    close(num(&flags, "/oblique/bat_tilt_deg"), 30.0, 1e-12, "echoed tilt");
    close(num(&flags, "/oblique/swing_direction_deg"), 10.0, 1e-12, "echoed direction");
    assert_eq!(flags["oblique"]["batter_side"].as_str(), Some("left"));

    let bat = Bat::preset("r161").unwrap();
    let modes = ModeSet::compute(&bat, 6).unwrap();
    let options = CollisionOptions { modes: 6, ..CollisionOptions::default() };
    let impact = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: 0.7 };
    let swing = SpatialImpact {
        oblique: ObliqueImpact {
            undercut: 0.01,
            attack_angle: 8.0 * std::f64::consts::PI / 180.0,
            pitch_angle: 6.0 * std::f64::consts::PI / 180.0,
            pitch_spin: 2000.0 / 60.0 * std::f64::consts::TAU,
            ..ObliqueImpact::head_on(impact, bat.radii_at(0.7).0)
        },
        bat_tilt: 30.0 * std::f64::consts::PI / 180.0,
        swing_direction: 10.0 * std::f64::consts::PI / 180.0,
        batter_side: BatterSide::Left,
    };
    let r = collide_spatial(&modes, &Ball::game(), &swing, &TangentialContact::default(), &options).unwrap();
    let rpm = 60.0 / std::f64::consts::TAU;
    let degrees = 180.0 / std::f64::consts::PI;
    close(batted(&flags, "exit_speed"), r.exit_speed, 1e-9, "exit speed");
    close(batted(&flags, "launch_angle_deg"), r.launch_angle * degrees, 1e-9, "launch angle");
    close(batted(&flags, "spray_angle_deg"), r.spray_angle * degrees, 1e-9, "spray angle");
    close(batted(&flags, "backspin_rpm"), r.backspin * rpm, 1e-6, "backspin");
    close(batted(&flags, "spin_rpm"), r.backspin * rpm, 1e-6, "spin_rpm keeps the signed backspin");
    close(batted(&flags, "sidespin_rpm"), r.sidespin * rpm, 1e-6, "sidespin");
    close(batted(&flags, "gyro_spin_rpm"), r.gyro_spin * rpm, 1e-6, "gyro spin");
    close(batted(&flags, "total_spin_rpm"), r.total_spin * rpm, 1e-6, "total spin");
    close(batted(&flags, "spin_axis_deg"), r.spin_axis * degrees, 1e-9, "spin axis");
    close(batted(&flags, "normal_exit_speed"), r.normal.exit_speed, 1e-9, "normal exit speed");
    assert_eq!(flags["results"][0]["oblique"]["sliding"].as_bool(), Some(r.sliding));
    assert!(batted(&flags, "spray_angle_deg").abs() > 1.0 && batted(&flags, "sidespin_rpm").abs() > 100.0);
    // The parts defined in a vertical plane are left out of a three-dimensional swing.
    for key in ["tangential_exit_speed", "line_of_centres_angle_deg", "slip_before", "bat_roll_rate_after"] {
        assert!(flags["results"][0]["oblique"].get(key).is_none(), "{key} in a 3-D result");
    }

    // The text report shows the flight where it shows launch and spin.
    let text = ok(&with(SWING));
    for row in ["spray angle (deg, right field +)", "sidespin (rpm, hook +)", "total spin (rpm)", "spin axis"] {
        assert!(text.contains(row), "'{row}' missing:\n{text}");
    }
    assert!(text.contains("bat tilt 30.00°, swing direction 10.00° (right field +), right-handed batter"), "{text}");
}

#[test]
fn a_left_handed_swing_mirrors_the_right_handed_one() {
    let right = json(&with(&[SWING, &["--batter-side", "right"]].concat()));
    let mut mirrored: Vec<&str> = SWING.to_vec();
    let direction = mirrored.iter().position(|a| *a == "--swing-direction").unwrap() + 1;
    mirrored[direction] = "-10";
    let left = json(&with(&[&mirrored[..], &["--batter-side", "left"]].concat()));
    for key in ["exit_speed", "launch_angle_deg", "backspin_rpm", "spin_rpm", "total_spin_rpm", "normal_exit_speed"] {
        assert_eq!(batted(&left, key).to_bits(), batted(&right, key).to_bits(), "{key}");
    }
    for key in ["spray_angle_deg", "sidespin_rpm", "gyro_spin_rpm"] {
        assert_eq!(batted(&left, key), -batted(&right, key), "{key} changes sign");
        assert!(batted(&right, key) != 0.0, "{key} is zero: the test shows nothing");
    }
    close(batted(&left, "spin_axis_deg"), 360.0 - batted(&right, "spin_axis_deg"), 1e-9, "spin axis mirrored");

    // A level square swing is its own mirror image: the left-handed batter's numbers are the right-handed ones.
    let planar = ["--undercut", "0.01", "--attack-angle", "8", "--pitch-spin", "2000"];
    let planar_right = json(&with(&planar));
    let planar_left = json(&with(&[&planar[..], &["--batter-side", "left"]].concat()));
    assert_eq!(planar_left["results"], planar_right["results"]);
    assert_eq!(planar_left["oblique"]["batter_side"].as_str(), Some("left"));
}

#[test]
fn a_tilted_bat_meeting_a_level_pitch_rolls_the_planar_answer_about_the_forward_axis() {
    // Level pitch without spin and a level swing toward centre field: the tilted swing is the planar swing
    // rotated by the tilt ψ about the forward axis, so its exit velocity (v cos L, 0, v sin L) becomes
    // (v cos L, −v sin L sin ψ, v sin L cos ψ): launch asin(sin L cos ψ), spray atan2(sin L sin ψ, cos L), and
    // the spin keeps its magnitude.
    let level = ["--attack-angle", "0", "--pitch-angle", "0", "--pitch-spin", "0"];
    for (undercut, tilt) in [(0.012, 25.0_f64), (-0.02, 40.0), (0.03, -15.0)] {
        let u = undercut.to_string();
        let planar = json(&with(&[&level[..], &["--undercut", &u]].concat()));
        let t = tilt.to_string();
        let tilted = json(&with(&[&level[..], &["--undercut", &u, "--bat-tilt", &t]].concat()));
        let launch = batted(&planar, "launch_angle_deg").to_radians();
        let psi = tilt.to_radians();
        let what = format!("undercut {undercut} m, tilt {tilt}°");
        close(batted(&tilted, "exit_speed"), batted(&planar, "exit_speed"), 1e-9, &format!("{what}: exit speed"));
        let expected_launch = (launch.sin() * psi.cos()).asin().to_degrees();
        close(batted(&tilted, "launch_angle_deg"), expected_launch, 1e-8, &format!("{what}: launch"));
        let expected_spray = (launch.sin() * psi.sin()).atan2(launch.cos()).to_degrees();
        close(batted(&tilted, "spray_angle_deg"), expected_spray, 1e-8, &format!("{what}: spray"));
        assert!(expected_spray.abs() > 0.5, "{what}: the roll must show in the spray ({expected_spray}°)");
        let spin = batted(&planar, "spin_rpm").abs();
        close(batted(&tilted, "total_spin_rpm"), spin, 1e-6 * spin, &format!("{what}: total spin"));
        close(batted(&planar, "total_spin_rpm"), spin, 0.0, &format!("{what}: planar total spin"));
    }
}

/// The lines of `text` that do not hold one of `keys`.
fn without_keys(text: &str, keys: &[&str]) -> String {
    text.lines()
        .filter(|line| !keys.iter().any(|k| line.trim_start().starts_with(&format!("\"{k}\":"))))
        .map(|line| format!("{line}\n"))
        .collect()
}

#[test]
fn a_planar_run_keeps_every_former_field_byte_for_byte_and_adds_the_planar_flight() {
    // tests/data/planar/*.json: the output of these commands before the flight was added.
    let new_keys: Vec<&str> =
        FLIGHT.iter().copied().chain(["bat_tilt_deg", "swing_direction_deg", "batter_side"]).collect();
    let simulate = [
        "simulate",
        "--bat",
        "r161",
        "--modes",
        "6",
        "--impact-z",
        "0.66,0.7",
        "--undercut=-0.012",
        "--attack-angle",
        "8",
        "--pitch-angle",
        "6",
        "--pitch-spin",
        "2000",
        "--json",
    ];
    let sweep = [
        "sweep",
        "--over",
        "undercut",
        "--modes",
        "4",
        "--points",
        "5",
        "--attack-angle",
        "8",
        "--pitch-spin",
        "1500",
        "--json",
    ];
    for (args, expected) in [(&simulate[..], "simulate-oblique.json"), (&sweep[..], "sweep-undercut.json")] {
        let before = std::fs::read_to_string(support::repo().join("tests/data/planar").join(expected)).unwrap();
        let now = ok(args);
        assert_eq!(without_keys(&now, &new_keys), before, "{args:?}");
        // Zero angles and the default side written out change nothing.
        let mut explicit = args.to_vec();
        explicit.extend(["--bat-tilt", "0", "--swing-direction", "0"]);
        assert_eq!(ok(&explicit), now, "{explicit:?}");
    }
    // The planar flight: straight away, all backspin or topspin.
    let doc = json(&simulate[..simulate.len() - 1]);
    for result in doc["results"].as_array().unwrap() {
        let o = &result["oblique"];
        let spin = o["spin_rpm"].as_f64().unwrap();
        assert!(spin < -100.0, "the undercut below the path gives topspin: {spin}");
        assert_eq!(o["backspin_rpm"].as_f64(), Some(spin));
        assert_eq!(o["total_spin_rpm"].as_f64(), Some(-spin));
        assert_eq!(o["spin_axis_deg"].as_f64(), Some(0.0), "pure topspin's axis");
        for key in ["spray_angle_deg", "sidespin_rpm", "gyro_spin_rpm"] {
            assert_eq!(o[key].to_string(), "0.0", "{key}");
        }
    }
    let backspin = json(&with(&["--undercut", "0.01"]));
    close(batted(&backspin, "spin_axis_deg"), 180.0, 1e-12, "pure backspin's axis");
    // A head-on run is untouched: zero angles do not make it oblique.
    assert_eq!(ok(&with(&["--bat-tilt", "0", "--swing-direction", "0"])), ok(BASE));
    assert_eq!(ok(&with(&["--bat-tilt", "0", "--json"])), ok(&with(&["--json"])));
}

#[test]
fn the_undercut_sweep_runs_the_tilted_swing_point_by_point() {
    let angles = ["--attack-angle", "8", "--pitch-angle", "6", "--pitch-spin", "2000", "--bat-tilt", "30"];
    let mut sweep_args = vec!["sweep", "--over", "undercut", "--modes", "6", "--impact-z", "0.7"];
    sweep_args.extend(["--from=-0.01", "--to", "0.01", "--points", "3", "--swing-direction", "10"]);
    sweep_args.extend(angles);
    let doc = json(&sweep_args);
    close(num(&doc, "/oblique/bat_tilt_deg"), 30.0, 1e-12, "echoed tilt");
    let last = &doc["points"][2];
    assert_eq!(last["undercut"].as_f64(), Some(0.01));
    let single = json(&with(SWING));
    for key in FLIGHT.iter().chain(&["exit_speed", "launch_angle_deg", "spin_rpm", "normal_exit_speed"]) {
        let (a, b) = (last[*key].as_f64().unwrap(), batted(&single, key));
        assert_eq!(a.to_bits(), b.to_bits(), "{key}: sweep {a} vs simulate {b}");
    }
    assert!(last.get("tangential_exit_speed").is_none());
    let text = ok(&sweep_args);
    assert!(text.contains("spray (deg)") && text.contains("total spin (rpm)"), "{text}");
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("tilted.svg");
    let mut plot_args = sweep_args.clone();
    plot_args.extend(["--plot", svg.to_str().unwrap()]);
    ok(&plot_args);
    let drawn = std::fs::read_to_string(&svg).unwrap();
    assert!(drawn.contains("total spin") && drawn.contains("backspin"), "the spin panel draws both");
    // A sweep over z is head-on: the angles belong to --over undercut.
    let err = fails(&["sweep", "--bat-tilt", "20"]);
    assert!(err.contains("--bat-tilt"), "{err}");
}

#[test]
fn out_of_range_angles_and_unknown_sides_are_refused_naming_the_field() {
    // The boundary: |tilt| ≤ 80° passes, beyond is refused; likewise the swing direction.
    for flag in ["--bat-tilt", "--swing-direction"] {
        ok(&with(&["--undercut", "0.01", flag, "80"]));
        for bad in ["80.001", "85", "-85"] {
            let err = fails(&with(&["--undercut", "0.01", flag, bad]));
            assert!(err.contains(flag) && err.contains("80°"), "{flag} {bad}: {err}");
        }
        let err = fails(&with(&[flag, "NaN"]));
        assert!(err.contains(flag), "{flag} NaN: {err}");
    }
    // A bat across its path: |tilt| + |attack| must stay below 90°.
    ok(&with(&["--undercut", "0.01", "--bat-tilt", "45", "--attack-angle", "44.9"]));
    for (tilt, attack) in [("45", "45"), ("50", "45"), ("-60", "30")] {
        let err = fails(&with(&["--bat-tilt", tilt, "--attack-angle", attack]));
        assert!(err.contains("--bat-tilt") && err.contains("90°"), "tilt {tilt}, attack {attack}: {err}");
    }
    let err = fails(&with(&["--batter-side", "middle"]));
    assert!(err.contains("--batter-side") && err.contains("middle"), "{err}");

    let dir = tempfile::tempdir().unwrap();
    for (text, field) in [
        ("bat_tilt_deg: 85\n", "bat_tilt_deg"),
        ("bat_tilt_deg: .nan\n", "bat_tilt_deg"),
        ("swing_direction_deg: -81\n", "swing_direction_deg"),
        ("bat_tilt_deg: 50\nattack_angle_deg: 45\n", "bat_tilt_deg"),
        ("batter_side: middle\n", "batter_side"),
        ("batter_side: 1\n", "batter_side"),
    ] {
        let case = dir.path().join("case.yaml");
        std::fs::write(&case, format!("modes: 4\nundercut: 0.01\n{text}")).unwrap();
        let run = sweetspot(&["simulate", "--case", case.to_str().unwrap()]);
        assert!(!run.status_ok && run.code.is_some_and(|c| c != 0), "{text:?} was accepted");
        assert!(run.stderr.contains(field) && !run.stderr.contains("panicked"), "{text:?}: {}", run.stderr);
    }
}
