//! Oblique impacts and hollow bats from the command line: `simulate` with undercut, angles and spin,
//! `sweep --over undercut`, and `modes`' hoop frequency.

mod support;

use serde_json::Value;
use support::cli::{json, num, ok};
use sweetspot::physics::TangentialContact;
use sweetspot::physics::{collide_oblique, Ball, Bat, CollisionOptions, Impact, ModeSet, ObliqueImpact};

const BASE: &[&str] = &["simulate", "--bat", "r161", "--modes", "6", "--impact-z", "0.7"];

fn with(extra: &[&str]) -> Vec<&'static str> {
    let mut args: Vec<&'static str> = BASE.to_vec();
    for a in extra {
        args.push(Box::leak(a.to_string().into_boxed_str()));
    }
    args
}

#[test]
fn zero_oblique_inputs_give_the_head_on_output_byte_for_byte() {
    let zeros = ["--undercut", "0", "--attack-angle", "0", "--pitch-angle", "0", "--pitch-spin", "0"];
    assert_eq!(ok(&with(&zeros)), ok(BASE), "text");
    assert_eq!(ok(&with(&[&zeros[..], &["--json"]].concat())), ok(&with(&["--json"])), "JSON");
}

#[test]
fn undercut_sign_flips_launch_angle_and_spin() {
    let up = json(&with(&["--undercut", "0.02"]));
    let down = json(&with(&["--undercut", "-0.02"]));
    let at = |doc: &Value, f: &str| num(doc, &format!("/results/0/oblique/{f}"));
    assert!(at(&up, "launch_angle_deg") > 5.0, "{}", at(&up, "launch_angle_deg"));
    assert!(at(&up, "spin_rpm") > 500.0, "{}", at(&up, "spin_rpm"));
    for f in ["launch_angle_deg", "spin_rpm", "tangential_exit_speed"] {
        let (a, b) = (at(&up, f), at(&down, f));
        assert!((a + b).abs() <= 1e-9 * a.abs(), "{f}: {a} vs {b}");
    }
    assert!((at(&up, "exit_speed") - at(&down, "exit_speed")).abs() < 1e-9);
    assert_eq!(up["oblique"]["undercut"].as_f64(), Some(0.02));
}

#[test]
fn simulate_matches_collide_oblique_called_directly() {
    let doc = json(&with(&[
        "--undercut",
        "0.015",
        "--attack-angle",
        "8",
        "--pitch-angle",
        "6",
        "--pitch-spin",
        "2000",
        "--tangential-cor",
        "0.3",
        "--friction",
        "0.4",
    ]));
    let bat = Bat::preset("r161").unwrap();
    let modes = ModeSet::compute(&bat, 6).unwrap();
    let options = CollisionOptions { modes: 6, ..CollisionOptions::default() };
    let impact = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: 0.7 };
    let degrees = std::f64::consts::PI / 180.0;
    let oblique = ObliqueImpact {
        impact,
        barrel_radius: bat.radii_at(0.7).0,
        undercut: 0.015,
        attack_angle: 8.0 * degrees,
        pitch_angle: 6.0 * degrees,
        pitch_spin: 2000.0 * 2.0 * std::f64::consts::PI / 60.0,
    };
    let contact = TangentialContact { tangential_cor: 0.3, friction: 0.4, ..TangentialContact::default() };
    let r = collide_oblique(&modes, &Ball::game(), &oblique, &contact, &options).unwrap();
    let at = |f: &str| num(&doc, &format!("/results/0/oblique/{f}"));
    let close = |a: f64, b: f64, what: &str| assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{what}: {a} vs {b}");
    close(at("launch_angle_deg"), r.launch_angle / degrees, "launch angle");
    close(at("spin_rpm"), r.spin * 60.0 / (2.0 * std::f64::consts::PI), "spin");
    close(at("exit_speed"), r.exit_speed, "exit speed");
    close(at("normal_exit_speed"), r.normal_exit_speed, "normal exit speed");
    close(at("tangential_exit_speed"), r.tangential_exit_speed, "tangential exit speed");
    assert_eq!(doc["results"][0]["oblique"]["sliding"].as_bool(), Some(r.sliding));
    // The text report carries the same batted ball.
    let text = ok(&with(&["--undercut", "0.015", "--attack-angle", "8", "--pitch-angle", "6", "--pitch-spin", "2000"]));
    for row in ["launch angle (deg)", "spin (rpm, backspin +)", "normal exit speed", "tangential exit speed", "sliding"]
    {
        assert!(text.contains(row), "'{row}' missing:\n{text}");
    }
}

#[test]
fn oblique_case_file_equals_the_same_flags() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case.json");
    std::fs::write(
        &case,
        r#"{"bat": "r161", "impact_z": 0.7, "modes": 6, "undercut": -0.01, "attack_angle_deg": 10,
            "pitch_angle_deg": 5, "pitch_spin_rpm": 1500, "tangential_cor": 0.35}"#,
    )
    .unwrap();
    let from_case = json(&["simulate", "--case", case.to_str().unwrap()]);
    let from_flags = json(&with(&[
        "--undercut",
        "-0.01",
        "--attack-angle",
        "10",
        "--pitch-angle",
        "5",
        "--pitch-spin",
        "1500",
        "--tangential-cor",
        "0.35",
    ]));
    assert_eq!(from_case, from_flags);
}

#[test]
fn undercut_sweep_shows_the_speed_spin_trade_off() {
    let doc = json(&["sweep", "--over", "undercut", "--modes", "6", "--points", "41"]);
    assert_eq!(doc["over"].as_str(), Some("undercut"));
    let points = doc["points"].as_array().unwrap();
    assert_eq!(points.len(), 41);
    let get = |p: &Value, f: &str| p[f].as_f64().unwrap();
    // Non-negative undercuts, ascending: exit speed falls with |D|, spin rises then falls.
    let upper: Vec<&Value> = points.iter().filter(|p| get(p, "undercut") >= -1e-12).collect();
    let lower: Vec<&Value> = points.iter().filter(|p| get(p, "undercut") <= 1e-12).rev().collect();
    for side in [&upper, &lower] {
        for w in side.windows(2) {
            assert!(get(w[1], "exit_speed") < get(w[0], "exit_speed"), "exit speed must fall with |D|");
        }
    }
    let spins: Vec<f64> = upper.iter().map(|p| get(p, "spin_rpm")).collect();
    let peak = spins.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)).map(|(i, _)| i).unwrap();
    assert!(peak > 0 && peak < spins.len() - 1, "spin peaks inside the range: {spins:?}");
    assert!(spins[..=peak].windows(2).all(|w| w[1] > w[0]), "spin rises up to its peak: {spins:?}");
    assert!(spins[peak..].windows(2).all(|w| w[1] < w[0]), "then falls: {spins:?}");
    assert!(spins[0].abs() < 1e-9, "no spin head-on");
    let launch: Vec<f64> = upper.iter().map(|p| get(p, "launch_angle_deg")).collect();
    assert!(launch.windows(2).all(|w| w[1] > w[0]), "launch angle rises with undercut: {launch:?}");
}

#[test]
fn undercut_sweep_plot_has_three_panels() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("undercut.svg");
    let out = ok(&["sweep", "--over", "undercut", "--modes", "4", "--points", "9", "--plot", svg.to_str().unwrap()]);
    assert!(out.contains("plot written to"), "{out}");
    let text = std::fs::read_to_string(&svg).unwrap();
    for label in ["exit speed vs undercut", "launch angle vs undercut", "spin vs undercut", "undercut D (mm"] {
        assert!(text.contains(label), "'{label}' missing from the SVG");
    }
}

#[test]
fn modes_lists_the_hoop_frequency_for_hollow_bats_only() {
    let doc = json(&["modes", "--bat", "aluminum"]);
    let f = num(&doc, "/hoop/sweet_spot/frequency_hz");
    assert!((1000.0..3000.0).contains(&f), "aluminum hoop frequency at the sweet spot {f} Hz");
    let along = doc["hoop"]["along"].as_array().unwrap();
    assert!(along.len() >= 3, "{along:?}");
    let text = ok(&["modes", "--bat", "aluminum"]);
    assert!(text.contains("hoop (n = 2) mode") && text.contains("(sweet spot)"), "{text}");
    let solid = json(&["modes", "--bat", "r161"]);
    assert!(solid.get("hoop").is_none(), "a wood bat has no hoop mode");
    assert!(!ok(&["modes", "--bat", "r161"]).contains("hoop"));
}

#[test]
fn simulate_json_carries_the_wall_for_hollow_bats() {
    let doc = json(&["simulate", "--bat", "aluminum", "--modes", "6", "--impact-z", "0.65"]);
    let r = &doc["results"][0];
    let f = r["hoop"]["frequency_hz"].as_f64().unwrap();
    assert!((1000.0..3000.0).contains(&f), "{f}");
    let stored = r["energy"]["hoop_stored"].as_f64().unwrap();
    let returned = r["energy"]["hoop_returned"].as_f64().unwrap();
    let left = r["energy"]["hoop"].as_f64().unwrap();
    assert!(stored > 0.0 && returned > 0.0, "the wall stores and returns energy: {stored} {returned}");
    assert!((stored - returned - left).abs() <= 1e-9 * stored, "stored − returned = left");
}

#[test]
fn the_compliant_tangential_law_runs_from_flags_and_case_files_as_in_the_library() {
    let flags =
        ["--undercut", "0.015", "--attack-angle", "8", "--pitch-spin", "2000", "--tangential-stiffness-ratio", "4.75"];
    let doc = json(&with(&flags));
    assert_eq!(doc["oblique"]["tangential_stiffness_ratio"].as_f64(), Some(4.75));
    let bat = Bat::preset("r161").unwrap();
    let modes = ModeSet::compute(&bat, 6).unwrap();
    let options = CollisionOptions { modes: 6, ..CollisionOptions::default() };
    let impact = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: 0.7 };
    let oblique = ObliqueImpact {
        undercut: 0.015,
        attack_angle: 8f64.to_radians(),
        pitch_spin: 2000.0 * std::f64::consts::TAU / 60.0,
        ..ObliqueImpact::head_on(impact, bat.radii_at(0.7).0)
    };
    let compliant = TangentialContact { stiffness_ratio: Some(4.75), ..TangentialContact::default() };
    let r = collide_oblique(&modes, &Ball::game(), &oblique, &compliant, &options).unwrap();
    let constant = collide_oblique(&modes, &Ball::game(), &oblique, &TangentialContact::default(), &options).unwrap();
    let spin = num(&doc, "/results/0/oblique/spin_rpm");
    assert!((spin - r.spin_rpm()).abs() <= 1e-9 * r.spin_rpm().abs(), "{spin} vs {}", r.spin_rpm());
    assert!((spin - constant.spin_rpm()).abs() > 10.0, "the law changed nothing: {spin} rpm");
    // Along the line of centres the collision is the same either way.
    assert_eq!(r.normal_exit_speed.to_bits(), constant.normal_exit_speed.to_bits());

    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case.json");
    std::fs::write(
        &case,
        r#"{"bat": "r161", "impact_z": 0.7, "modes": 6, "undercut": 0.015, "attack_angle_deg": 8,
            "pitch_spin_rpm": 2000, "tangential_stiffness_ratio": 4.75}"#,
    )
    .unwrap();
    assert_eq!(json(&["simulate", "--case", case.to_str().unwrap()]), json(&with(&flags)));

    let refused = support::cli::sweetspot(&with(&["--undercut", "0.01", "--tangential-stiffness-ratio", "0.01"]));
    assert!(!refused.status_ok);
    assert!(refused.stderr.contains("stiffness_ratio"), "{}", refused.stderr);
}
