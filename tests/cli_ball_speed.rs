//! The speed-dependent ball from the command line: `--ball mlb`, `--ball-cor-exponent`/`--ball-cor-speed` and
//! the case file's `cor_speed_exponent`/`cor_reference_speed` give the library's collision with that ball; a
//! constant ball's documents keep exactly their former fields; bad laws and names are refused.

mod support;

use support::cli::{fails, json, num, ok};
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

fn library(ball: &Ball, z: f64) -> f64 {
    let modes = ModeSet::compute(&Bat::preset("r161").unwrap(), 18).unwrap();
    let impact = Impact { ball_speed: 40.0, bat_cm_speed: 25.0, bat_angular_speed: 45.0, impact_z: z };
    collide(&modes, ball, &impact, &CollisionOptions::default()).unwrap().exit_speed
}

#[test]
fn simulate_takes_the_mlb_ball_and_an_explicit_law_alike() {
    let args =
        ["simulate", "--impact-z", "0.705", "--ball-speed", "40", "--bat-cm-speed", "25", "--bat-angular-speed", "45"];
    let mlb = json(&[&args[..], &["--ball", "mlb"]].concat());
    assert_eq!(num(&mlb, "/results/0/exit_speed"), library(&Ball::mlb(), 0.705));
    let law = Ball::mlb();
    let (p, v) = (law.cor_speed_exponent.to_string(), law.cor_reference_speed.to_string());
    let explicit =
        json(&[&args[..], &["--ball-cor", "0.66", "--ball-cor-exponent", &p, "--ball-cor-speed", &v]].concat());
    assert_eq!(num(&explicit, "/results/0/exit_speed"), num(&mlb, "/results/0/exit_speed"));
    assert_eq!(num(&mlb, "/ball/cor_speed_exponent"), law.cor_speed_exponent);
    // The constant `baseball`: the same fields as before the law existed, and a harder hit.
    let plain = json(&[&args[..], &["--ball", "baseball"]].concat());
    assert!(plain["ball"].get("cor_speed_exponent").is_none() && plain["ball"].get("cor_reference_speed").is_none());
    assert!(num(&plain, "/results/0/exit_speed") > num(&mlb, "/results/0/exit_speed"));
    // The default is the game ball fitted to the 2024 season, with its law.
    let default = json(&args);
    assert_eq!(num(&default, "/results/0/exit_speed"), library(&Ball::mlb2024(), 0.705));
    assert_eq!(num(&default, "/ball/cor_speed_exponent"), Ball::mlb2024().cor_speed_exponent);
    // docs/physics.md's comparison at the R161's sweet spot (z = 0.705 m in the default swing): the game
    // balls' collision efficiency is inside the 0.20–0.23 of MLB wood bats (Statcast's squared-up maximum),
    // the constant `baseball`'s above it.
    let q = |doc: &serde_json::Value| num(doc, "/results/0/collision_efficiency");
    assert!((0.20..=0.23).contains(&q(&mlb)), "q = {}", q(&mlb));
    assert!((0.20..=0.23).contains(&q(&default)), "q = {}", q(&default));
    assert!(q(&plain) > 0.23, "q = {}", q(&plain));
    // The human report names the law.
    assert!(ok(&[&args[..], &["--ball", "mlb"]].concat()).contains("e0 0.6600·(v / 1.000 m/s)^−0.06781"));
}

#[test]
fn case_files_bbcor_and_refusals() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case.json");
    let law = Ball::mlb();
    let text = format!(
        r#"{{"bat": "r161", "ball": {{"cor": 0.66, "cor_speed_exponent": {}, "cor_reference_speed": 1.0}},
            "ball_speed": 40.0, "bat_cm_speed": 25.0, "bat_angular_speed": 45.0, "impact_z": [0.705]}}"#,
        law.cor_speed_exponent
    );
    std::fs::write(&case, text).unwrap();
    let doc = json(&["simulate", "--case", case.to_str().unwrap()]);
    assert_eq!(num(&doc, "/results/0/exit_speed"), library(&law, 0.705));
    // BBCOR with the game ball: its e0 at 136 mph is within 0.001 of the protocol ball's 0.50.
    let bbcor = json(&["bbcor", "--bat", "r161", "--ball", "mlb"]);
    let protocol = json(&["bbcor", "--bat", "r161"]);
    assert!((num(&bbcor, "/bbcor/bbcor") - num(&protocol, "/bbcor/bbcor")).abs() < 1e-3);
    assert!(fails(&["simulate", "--ball", "softball"]).contains("unknown ball preset"));
    assert!(fails(&["simulate", "--ball-cor-exponent", "2"]).contains("cor_speed_exponent"));
    // A law with no speed to refer to is refused (the game ball's own speed is kept otherwise).
    assert!(fails(&["simulate", "--ball", "baseball", "--ball-cor-exponent", "0.1"]).contains("cor_reference_speed"));
}
