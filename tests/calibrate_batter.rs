//! `calibrate --fit-batter` recovers a known batter from recorded sessions, refuses a session that cannot
//! determine one, and writes a batter file `compare --batter` reads.
//!
//! The sessions are the rig's (the demo's batter swinging several bats at equal effort, with its sensor
//! noise) written through the project's Recorder into a rosbag2/MCAP directory, or hand-made swings of a known
//! batter. The truth is a batter with n = 0.3 — not the default 0.25 — and a known reference speed and pivot.

mod support;

use support::cli::{fails, json, num, s};
use support::rig::record_rig_session;
use sweetspot::bag::{RecordedQos, Recorder, RecorderConfig, TopicInfo};
use sweetspot::calibrate::batter::{batter_fit_from_bag, BatterFitOptions, Estimate};
use sweetspot::model::convert::{params_from_bat, params_of_preset};
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::std_msgs::msg::Header;
use sweetspot::msgs::sweetspot_msgs::msg::{BatParams, Swing};
use sweetspot::physics::batter::{Batter, ReferenceSwing, SwingShape, DEFAULT_SWING_LENGTH};
use sweetspot::physics::units::MPH;
use sweetspot::physics::Bat;
use sweetspot::rig::{RigConfig, SensorNoise, SessionGenerator};

/// The true exponent of the rig's batter (the model's default is 0.25).
const TRUE_EXPONENT: f64 = 0.3;
/// The true bat speed with the r161 at 6 in from the barrel end, m/s.
const TRUE_SPEED: f64 = 30.0;
/// The true pivot of the swing, m from the knob.
const TRUE_PIVOT: f64 = 0.05;
/// 6 in, m.
const SIX_INCHES: f64 = 6.0 * 0.0254;

/// The batter the rig simulates: `speed` m/s 6 in from the barrel end of `reference`, turning about `pivot`.
fn batter(reference: &str, speed: f64, pivot: f64, exponent: f64) -> Batter {
    let props = Bat::preset(reference).expect("preset").mass_properties();
    let swing = ReferenceSwing::from_speed_at(props, speed, props.length - SIX_INCHES, pivot).expect("swing");
    Batter::new(swing, exponent, SIX_INCHES, DEFAULT_SWING_LENGTH, SwingShape::SamePivot).expect("batter")
}

fn rig_config(seed: u64, barrel_mph: (f64, f64), noise: SensorNoise) -> RigConfig {
    RigConfig {
        seed,
        noise,
        barrel_speed: (barrel_mph.0 * MPH, barrel_mph.1 * MPH),
        batter: Some(batter("r161", TRUE_SPEED, TRUE_PIVOT, TRUE_EXPONENT)),
        ..RigConfig::default()
    }
}

fn assert_within(what: &str, got: Estimate, truth: f64, sigmas: f64) {
    assert!(got.std_error > 0.0 && got.std_error.is_finite(), "{what}: {got:?}");
    assert!(
        (got.value - truth).abs() < sigmas * got.std_error,
        "{what}: {} ± {} vs true {truth} ({:.1}σ)",
        got.value,
        got.std_error,
        (got.value - truth) / got.std_error
    );
}

/// Σ n_b (x_b − x̄)² of the default bats, x = ln(swing weight), with the swing weight computed here from the
/// presets' mass properties (I_cm + M (z_cm − 6 in)²), `per_bat` swings each.
fn spread_of_log_swing_weight(per_bat: f64) -> f64 {
    let x: Vec<f64> = Bat::preset_names()
        .iter()
        .map(|name| {
            let p = Bat::preset(name).unwrap().mass_properties();
            (p.moment_of_inertia + p.mass * (p.center_of_mass - SIX_INCHES).powi(2)).ln()
        })
        .collect();
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    per_bat * x.iter().map(|v| (v - mean).powi(2)).sum::<f64>()
}

/// The demo's effort spread (60–80 mph: ±1/7 about the batter's effort) and sensor noise: the fit finds the
/// true n and v_ref within 3σ, and its σ is what the spread predicts in closed form.
#[test]
fn the_batter_is_recovered_from_a_noisy_rig_session_with_the_uncertainty_the_spread_predicts() {
    let tmp = tempfile::tempdir().unwrap();
    let swings = 240;
    let bag = record_rig_session(
        tmp.path(),
        swings,
        SessionGenerator::new(rig_config(31, (60.0, 80.0), SensorNoise::default())).expect("rig"),
    );
    let fit = batter_fit_from_bag(&bag, &BatterFitOptions::default()).expect("fit");
    assert_eq!((fit.swings, fit.bats.len(), fit.dof), (swings, 4, swings - 2));
    assert_eq!(fit.reference_bat, "r161", "the first bat swung");
    assert!(fit.skipped.is_empty(), "{:?}", fit.skipped);
    assert_within("n", fit.exponent, TRUE_EXPONENT, 3.0);
    assert_within("v_ref", fit.bat_speed, TRUE_SPEED, 3.0);
    assert_within("pivot_z", fit.pivot_z, TRUE_PIVOT, 3.0);

    // Closed form of the scatter of ln v: the effort e uniform on [1 − h, 1 + h] (h = 10/70) has
    // var(ln e) ≈ h²/3; the sensors add (1.08 σ_ω/ω)² (the speed at 6 in is ω·(z − z_p) with z − z_p ≈
    // 0.64 m, while the gyro's error multiplies ω·z, z ≈ 0.69 m) and (σ_knob/v)².
    let h: f64 = 10.0 / 70.0;
    let noise = SensorNoise::default();
    let sigma =
        (h * h / 3.0 + (noise.angular_rate_relative * 1.08).powi(2) + (noise.knob_speed / TRUE_SPEED).powi(2)).sqrt();
    let ratio = fit.log_speed_sigma / sigma;
    assert!((0.8..1.25).contains(&ratio), "s = {} vs closed form {sigma}", fit.log_speed_sigma);
    let expected = sigma / spread_of_log_swing_weight(swings as f64 / 4.0).sqrt();
    let ratio = fit.exponent.std_error / expected;
    assert!((0.8..1.25).contains(&ratio), "σ(n) = {} vs closed form {expected}", fit.exponent.std_error);
}

/// A batter who swings every swing at nearly the same effort (69.5–70.5 mph): only the sensors' noise is
/// left, and the fit tells n = 0.3 from the default 0.25 by many σ.
#[test]
fn a_steady_batter_is_told_apart_from_the_default_exponent() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = record_rig_session(
        tmp.path(),
        120,
        SessionGenerator::new(rig_config(8, (69.5, 70.5), SensorNoise::default())).expect("rig"),
    );
    let fit = batter_fit_from_bag(&bag, &BatterFitOptions::default()).expect("fit");
    assert_within("n", fit.exponent, TRUE_EXPONENT, 3.0);
    assert!(fit.exponent.std_error < 0.01, "{:?}", fit.exponent);
    let from_default = (fit.exponent.value - 0.25) / fit.exponent.std_error;
    assert!(from_default > 5.0, "n = 0.25 only {from_default:.1}σ away: {:?}", fit.exponent);
    assert_within("v_ref", fit.bat_speed, TRUE_SPEED, 3.0);
}

/// Perfect sensors and one effort: every swing lies on the power law, which is recovered to rounding; with
/// another reference bat, v_ref is the true batter's speed with that bat.
#[test]
fn a_noiseless_session_gives_the_batter_exactly() {
    let tmp = tempfile::tempdir().unwrap();
    let bag = record_rig_session(
        tmp.path(),
        24,
        SessionGenerator::new(rig_config(3, (70.0, 70.0), SensorNoise::none())).expect("rig"),
    );
    let fit = batter_fit_from_bag(&bag, &BatterFitOptions::default()).expect("fit");
    assert!((fit.exponent.value - TRUE_EXPONENT).abs() < 1e-9, "{:?}", fit.exponent);
    assert!((fit.bat_speed.value / TRUE_SPEED - 1.0).abs() < 1e-9, "{:?}", fit.bat_speed);
    assert!((fit.pivot_z.value - TRUE_PIVOT).abs() < 1e-9, "{:?}", fit.pivot_z);
    for b in &fit.bats {
        assert!(b.residual.abs() < 1e-8, "{b:?}");
    }

    let options = BatterFitOptions { reference_bat: Some("aluminum".into()), ..BatterFitOptions::default() };
    let fit = batter_fit_from_bag(&bag, &options).expect("fit");
    let truth = batter("r161", TRUE_SPEED, TRUE_PIVOT, TRUE_EXPONENT);
    let aluminum = truth.predict(&Bat::preset("aluminum").unwrap().mass_properties()).unwrap().bat_speed;
    assert!((fit.bat_speed.value / aluminum - 1.0).abs() < 1e-9, "{} vs {aluminum}", fit.bat_speed.value);
    assert!((fit.exponent.value - TRUE_EXPONENT).abs() < 1e-9);
    let refitted = fit.batter().expect("batter");
    let r161 = refitted.predict(&Bat::preset("r161").unwrap().mass_properties()).unwrap().bat_speed;
    assert!((r161 / TRUE_SPEED - 1.0).abs() < 1e-9, "{r161}");
}

#[test]
fn a_one_bat_session_is_refused_naming_why() {
    let tmp = tempfile::tempdir().unwrap();
    let config = RigConfig { bats: vec!["r161".into()], ..rig_config(4, (60.0, 80.0), SensorNoise::default()) };
    let bag = record_rig_session(tmp.path(), 12, SessionGenerator::new(config).expect("rig"));
    let err = batter_fit_from_bag(&bag, &BatterFitOptions::default()).unwrap_err().to_string();
    assert!(err.contains("at least two different swing weights") && err.contains("'r161'"), "{err}");
    let out = tmp.path().join("batter.toml");
    let stderr = fails(&["calibrate", s(&bag), "--batter-out", s(&out)]);
    assert_eq!(stderr.matches("at least two different swing weights").count(), 1, "{stderr}");
    assert!(stderr.contains(s(&bag)), "{stderr}");
    assert!(!out.exists(), "no batter file for a refused fit");
}

/// Hand-made session of a bat described by BatParams (no preset) and two presets, swung by a known batter
/// at three efforts each: `calibrate --batter-out` writes the batter and the bat file, `compare --batter`
/// reads them and predicts the true batter's speeds.
#[test]
fn the_written_batter_file_is_what_compare_reads() {
    let tmp = tempfile::tempdir().unwrap();
    let truth = batter("r161", 31.0, 0.0, 0.27);
    let club = Bat { name: "club".into(), ..Bat::preset("r161-corked").unwrap() };
    let bag = tmp.path().join("hand");
    let recorder = Recorder::start(RecorderConfig::new(&bag)).unwrap();
    let qos = RecordedQos { reliable: true, transient_local: false, depth: 100 };
    let bat_topic = recorder.register_topic(TopicInfo::of::<BatParams>("/bat/params", qos)).unwrap();
    let swing_topic = recorder.register_topic(TopicInfo::of::<Swing>("/swing", qos)).unwrap();
    let params = [
        params_from_bat("club", &club, 18, Header::default()),
        params_of_preset("game", "aluminum", Header::default()),
    ];
    for (t, p) in params.iter().enumerate() {
        assert!(recorder.record(bat_topic, encode_cdr(p).unwrap(), t as u64 + 1, t as u64 + 1));
    }
    let mut id = 0;
    for (bat_id, bat) in
        [("club", &club), ("game", &Bat::preset("aluminum").unwrap()), ("torpedo", &Bat::preset("torpedo").unwrap())]
    {
        let swing = truth.predict(&bat.mass_properties()).unwrap();
        for effort in [0.95, 1.0, 1.05] {
            id += 1;
            let msg = Swing {
                swing_id: id,
                bat_id: bat_id.into(),
                bat_cm_speed: effort * swing.bat_cm_speed,
                bat_angular_speed: effort * swing.bat_angular_speed,
                ball_speed: 40.0,
                impact_z: swing.impact_z,
                measured_exit_speed: f64::NAN,
                ..Swing::default()
            };
            assert!(recorder.record(swing_topic, encode_cdr(&msg).unwrap(), 10 + id, 10 + id));
        }
    }
    recorder.finish().unwrap();

    let out = tmp.path().join("fitted.toml");
    let doc = json(&["calibrate", s(&bag), "--batter-out", s(&out), "--reference-bat", "club"]);
    assert_eq!(doc["reference_bat"], "club");
    assert!(doc["reference_preset"].is_null(), "{doc}");
    assert!((num(&doc, "/exponent/value") - 0.27).abs() < 1e-9, "{doc}");
    let written: Vec<&str> = doc["written"].as_array().unwrap().iter().map(|v| v.as_str().unwrap()).collect();
    let bat_file = tmp.path().join("fitted.club.toml");
    assert_eq!(written, [s(&bat_file), s(&out)]);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("reference_bat = \"fitted.club.toml\""), "{text}");

    let compared = json(&["compare", "--batter", s(&out), "--bats", "r161,r161-corked,aluminum", "--modes", "6"]);
    assert!((num(&compared, "/batter/exponent") - 0.27).abs() < 1e-9, "{compared}");
    assert_eq!(compared["batter"]["reference_bat"], "club");
    let speeds: Vec<f64> = (0..3).map(|i| num(&compared, &format!("/bats/{i}/bat_speed"))).collect();
    for (name, got) in ["r161", "r161-corked", "aluminum"].iter().zip(speeds) {
        let expected = truth.predict(&Bat::preset(name).unwrap().mass_properties()).unwrap().bat_speed;
        assert!((got / expected - 1.0).abs() < 1e-9, "{name}: compare {got} vs the true batter {expected}");
    }
}

#[test]
fn a_missing_bag_is_one_error_naming_the_file() {
    for extra in [&[][..], &["--fit-batter"][..]] {
        let mut args = vec!["calibrate", "no-such-bag"];
        args.extend_from_slice(extra);
        let stderr = fails(&args);
        assert_eq!(stderr.matches("No such file or directory").count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains("no-such-bag"), "{stderr}");
        assert_eq!(stderr.lines().filter(|l| !l.trim().is_empty()).count(), 1, "{stderr}");
    }
    let stderr = fails(&["calibrate", "Cargo.toml"]);
    assert_eq!(stderr.matches("not an MCAP file").count(), 1, "{stderr}");
}
