//! Calibration recovers known parameters from a synthetic noisy session written to a real bag.
//!
//! The rig announces a regulation ball (COR 0.53) but really hits deader balls (COR 0.50): the exit speeds it
//! measures are the physics with COR 0.50 plus Gaussian radar noise (σ 0.45 m/s) and noisy inputs. The
//! session goes through the project's Recorder into a rosbag2/MCAP directory, `calibrate` reads it back and
//! must find 0.50 within 3σ, with a σ consistent with the noise (not tiny, not huge).

mod support;

use support::rig::{finish, record_rig};
use sweetspot::bag::{RecordedQos, Recorder, RecorderConfig, TopicInfo};
use sweetspot::calibrate::{fit, problem_from_bag, FitOptions};
use sweetspot::msgs::encode_cdr;
use sweetspot::msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use sweetspot::physics::Ball;
use sweetspot::rig::{RigConfig, SensorNoise, SessionGenerator};

const TRUE_COR: f64 = 0.50;

fn write_session(dir: &std::path::Path, swings: usize, config: RigConfig) -> std::path::PathBuf {
    write_session_with(dir, swings, config, |_, _, _, _| {})
}

/// Writes a session; `extra(recorder, bat topic, swing topic, time)` adds messages at the end.
fn write_session_with(
    dir: &std::path::Path,
    swings: usize,
    config: RigConfig,
    extra: impl FnOnce(&Recorder, sweetspot::bag::TopicId, sweetspot::bag::TopicId, u64),
) -> std::path::PathBuf {
    let bag = dir.join("session");
    let recorder = Recorder::start(RecorderConfig::new(&bag)).expect("start recorder");
    let mut rig = SessionGenerator::new(config).expect("rig").with_block(3);
    let session = record_rig(&recorder, &mut rig, swings, |_| {});
    extra(&recorder, session.bat_topic, session.swing_topic, session.last + 1_000_000);
    finish(recorder);
    bag
}

#[test]
fn calibrate_recovers_the_true_cor_from_a_noisy_bag() {
    let tmp = tempfile::tempdir().unwrap();
    let noise = SensorNoise::default();
    // The constant-COR `baseball` announced (0.53), its true COR another: the fit must find the true one.
    let config = RigConfig { ball: Ball::default(), true_cor: Some(TRUE_COR), seed: 11, noise, ..RigConfig::default() };
    let bag = write_session(tmp.path(), 48, config);

    let problem = problem_from_bag(&bag, None).expect("problem from bag");
    assert_eq!(problem.observations.len(), 48);
    assert_eq!(problem.ball_id, sweetspot::rig::RIG_BALL_ID);
    assert!((problem.ball.cor - 0.53).abs() < 1e-12, "start value is the announced COR");
    assert_eq!(problem.bats.len(), 4);

    let result = fit(&problem, &FitOptions::default()).expect("fit");
    let cor = result.parameter("cor").unwrap();
    assert!(result.converged, "fit did not converge: {result:?}");
    // σ: exit speed moves ≈ 40–60 m/s per unit COR, so 48 swings with ≈ 0.5–0.8 m/s scatter give σ ≈ 1e-3.
    assert!(cor.std_error > 2e-4 && cor.std_error < 5e-3, "σ(COR) = {}", cor.std_error);
    assert!(
        (cor.value - TRUE_COR).abs() < 3.0 * cor.std_error,
        "COR {} ± {} vs true {TRUE_COR}",
        cor.value,
        cor.std_error
    );
    // The wrong start value shows as a bias the fit removes; what is left is the sensor noise.
    assert!(result.rms_before > 1.0, "rms before {}", result.rms_before);
    assert!(result.rms < 1.0 && result.rms > 0.3, "rms after {}", result.rms);
    let mean: f64 = result.residuals.iter().map(|r| r.residual).sum::<f64>() / result.residuals.len() as f64;
    assert!(mean.abs() < 0.2, "mean residual {mean}");
}

#[test]
fn calibrate_fits_youngs_modulus_with_exact_inputs() {
    // Exit-speed noise only, so the moduli are identifiable from a short session; the true bats are the presets.
    let tmp = tempfile::tempdir().unwrap();
    let noise = SensorNoise { exit_speed: 0.3, ..SensorNoise::none() };
    let config = RigConfig {
        bats: vec!["r161".into(), "aluminum".into()],
        true_cor: Some(TRUE_COR),
        seed: 5,
        noise,
        ..RigConfig::default()
    };
    let bag = write_session(tmp.path(), 24, config);
    let problem = problem_from_bag(&bag, None).expect("problem");
    let result = fit(&problem, &FitOptions { fit_youngs: true, ..FitOptions::default() }).expect("fit");
    assert_eq!(result.parameters.len(), 3);
    let cor = result.parameter("cor").unwrap();
    assert!((cor.value - TRUE_COR).abs() < 3.0 * cor.std_error + 1e-4, "{cor:?}");
    for (name, truth) in [("youngs_modulus[r161]", 1.814e10), ("youngs_modulus[aluminum]", 7.0e10)] {
        let e = result.parameter(name).unwrap();
        assert!(e.std_error > 0.0 && e.std_error.is_finite(), "{e:?}");
        assert!((e.value - truth).abs() < 3.0 * e.std_error, "{name}: {} ± {} vs {truth}", e.value, e.std_error);
        assert_eq!(result.bats[&name[15..name.len() - 1]].shell.youngs_modulus, e.value);
    }
}

#[test]
fn a_bag_without_measurements_is_a_clear_error() {
    let tmp = tempfile::tempdir().unwrap();
    let noise = SensorNoise { exit_speed: 0.0, ..SensorNoise::none() };
    let bag = tmp.path().join("empty");
    let recorder = Recorder::start(RecorderConfig::new(&bag)).unwrap();
    let _ = noise;
    let stream = RecordedQos { reliable: true, transient_local: false, depth: 1000 };
    let topic = recorder.register_topic(TopicInfo::of::<Swing>("/swing", stream)).unwrap();
    let swing = Swing {
        bat_id: "r161".into(),
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.7,
        measured_exit_speed: f64::NAN,
        ..Default::default()
    };
    recorder.record(topic, encode_cdr(&swing).unwrap(), 1, 1);
    recorder.finish().unwrap();
    let err = problem_from_bag(&bag, None).unwrap_err().to_string();
    assert!(err.contains("measured_exit_speed"), "{err}");
}

#[test]
fn calibrate_command_reports_and_writes_params_pub_can_send() {
    let tmp = tempfile::tempdir().unwrap();
    let config = RigConfig {
        bats: vec!["r161".into(), "aluminum".into()],
        true_cor: Some(TRUE_COR),
        seed: 21,
        ..RigConfig::default()
    };
    let bag = write_session(tmp.path(), 16, config);
    let out = tmp.path().join("fitted.jsonl");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .arg("calibrate")
        .arg(&bag)
        .args(["--fit-youngs", "--write"])
        .arg(&out)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{stdout}{}", String::from_utf8_lossy(&output.stderr));
    for needle in [
        "cor",
        "youngs_modulus[r161]",
        "youngs_modulus[aluminum]",
        "RMS",
        "largest residuals",
        "sweetspot pub ball --file",
    ] {
        assert!(stdout.contains(needle), "{needle} missing in:\n{stdout}");
    }
    // The files are JSON lines that `sweetspot pub` parses as BallParams / BatParams (same tolerant reader).
    let ball_line = std::fs::read_to_string(&out).unwrap();
    let ball: BallParams = sweetspot::msgs::json::from_json(&serde_json::from_str(ball_line.trim()).unwrap()).unwrap();
    assert_eq!(ball.ball_id, sweetspot::rig::RIG_BALL_ID);
    assert!((ball.cor - TRUE_COR).abs() < 0.02, "{}", ball.cor);
    let bats_text = std::fs::read_to_string(tmp.path().join("fitted.bats.jsonl")).unwrap();
    let bats: Vec<BatParams> = bats_text
        .lines()
        .map(|l| sweetspot::msgs::json::from_json(&serde_json::from_str(l).unwrap()).unwrap())
        .collect();
    assert_eq!(bats.len(), 2);
    for b in &bats {
        assert!(b.preset.is_empty() && b.station_z.len() > 10 && b.youngs_modulus > 1e9, "{b:?}");
        // A fitted bat is the preset's geometry with the fitted modulus: it must build.
        sweetspot::model::convert::bat_from_params(b).unwrap();
    }
}

#[test]
fn inputs_the_node_would_reject_are_left_out_and_reported() {
    let tmp = tempfile::tempdir().unwrap();
    let config = RigConfig { bats: vec!["r161".into()], seed: 8, ..RigConfig::default() };
    let bag = write_session_with(tmp.path(), 12, config, |rec, bat_topic, swing_topic, t| {
        let bad_bat = BatParams {
            bat_id: "broken".into(),
            station_z: vec![0.0],
            outer_radius: vec![0.03],
            inner_radius: vec![0.0],
            ..Default::default()
        };
        rec.record(bat_topic, encode_cdr(&bad_bat).unwrap(), t, t);
        let off_the_bat = Swing {
            swing_id: 999,
            bat_id: "r161".into(),
            ball_speed: 40.0,
            bat_cm_speed: 20.0,
            bat_angular_speed: 50.0,
            impact_z: 5.0,
            measured_exit_speed: 40.0,
            ..Default::default()
        };
        rec.record(swing_topic, encode_cdr(&off_the_bat).unwrap(), t + 1, t + 1);
    });
    let problem = problem_from_bag(&bag, None).expect("problem");
    assert_eq!(problem.observations.len(), 12);
    assert_eq!(problem.skipped.len(), 2, "{:?}", problem.skipped);
    assert!(problem.skipped[0].contains("broken") && problem.skipped[1].contains("swing 999"), "{:?}", problem.skipped);
    let result = fit(&problem, &FitOptions::default()).expect("fit");
    assert!(result.converged);
}
