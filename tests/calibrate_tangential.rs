//! The e_T fit recovers a known tangential COR from a synthetic noisy session written to a real bag.
//!
//! The rig's balls grip the bat less than the model's default (true e_T 0.30 against the default start value
//! 0.405, KNS 2017): its tracker measures the launch angles and spins of [`collide_oblique`] with e_T 0.30,
//! plus Gaussian noise (1°, 100 rpm), and the swing inputs it reports carry their own sensor noise. The
//! session goes through the project's Recorder into a rosbag2/MCAP directory; `calibrate`'s e_T fit reads it
//! back and must find 0.30 within 3σ of its stated uncertainty, with a σ that means something (not tiny, not
//! huge). A second session leaves every undercut unreported: the fit must find each swing's undercut as well.

mod support;

use support::rig::{finish, record_rig};
use sweetspot::bag::{Recorder, RecorderConfig};
use sweetspot::calibrate::tangential::{fit_tangential, problem_from_bag, TangentialOptions};
use sweetspot::calibrate::{fit, problem_from_bag as exit_speed_problem_from_bag, CalibrateError, FitOptions};
use sweetspot::msgs::builtin_interfaces::msg::Time;
use sweetspot::msgs::sweetspot_msgs::msg::BallParams;
use sweetspot::physics::oblique::{collide_oblique, TangentialContact};
use sweetspot::physics::CollisionOptions;
use sweetspot::rig::{LaunchConditions, RigConfig, RigSwing, SessionGenerator};

const TRUE_E_T: f64 = 0.30;

/// Writes a session of `swings` swings to a bag under `dir`; returns the bag and the rig's swings (truth).
fn write_session(dir: &std::path::Path, swings: usize, config: RigConfig) -> (std::path::PathBuf, Vec<RigSwing>) {
    write_session_with(dir, swings, config, |_| {})
}

/// As [`write_session`], with the rig's BallParams changed by `edit_ball` before it is recorded.
fn write_session_with(
    dir: &std::path::Path,
    swings: usize,
    config: RigConfig,
    edit_ball: impl FnOnce(&mut BallParams),
) -> (std::path::PathBuf, Vec<RigSwing>) {
    let bag = dir.join("session");
    let recorder = Recorder::start(RecorderConfig::new(&bag)).expect("start recorder");
    let mut rig = SessionGenerator::new(config).expect("rig").with_block(4);
    let truth = record_rig(&recorder, &mut rig, swings, edit_ball).truth;
    finish(recorder);
    (bag, truth)
}

fn config(seed: u64, report_undercut: bool) -> RigConfig {
    let launch = LaunchConditions {
        contact: TangentialContact { tangential_cor: TRUE_E_T, ..TangentialContact::default() },
        report_undercut,
        ..LaunchConditions::default()
    };
    RigConfig {
        bats: vec!["r161".into(), "r161-corked".into()],
        seed,
        // The bag's BatParams name presets, which the fit integrates with the node's default_modes (18).
        options: CollisionOptions { modes: 18, ..CollisionOptions::default() },
        launch: Some(launch),
        ..RigConfig::default()
    }
}

#[test]
fn the_rig_tracks_the_launch_of_the_true_contact() {
    let mut rig = SessionGenerator::new(config(5, true)).unwrap();
    let swing = rig.next_swing().unwrap();
    let launch = swing.launch.as_ref().expect("oblique swings");
    // The rig's truth is the oblique collision with its true contact (an independent call of the physics).
    let bat = rig.bats().iter().find(|b| b.bat_id == swing.bat_id).unwrap();
    let again = collide_oblique(
        &bat.modes,
        &rig.config().true_ball(),
        &launch.truth,
        &TangentialContact { tangential_cor: TRUE_E_T, ..TangentialContact::default() },
        &rig.config().options,
    )
    .unwrap();
    assert_eq!(again.spin.to_bits(), launch.result.spin.to_bits());
    assert_eq!(launch.truth.impact, swing.truth);
    let msg = rig.swing_message(&swing, Time::default());
    assert_eq!((msg.measured_launch_angle, msg.measured_spin), (launch.launch_angle, launch.spin));
    assert_eq!(msg.undercut, launch.undercut);
}

#[test]
fn the_tangential_fit_recovers_the_true_e_t_from_a_noisy_bag() {
    let tmp = tempfile::tempdir().unwrap();
    let (bag, _) = write_session(tmp.path(), 48, config(21, true));

    let problem = problem_from_bag(&bag, None).expect("problem");
    assert_eq!(problem.observations.len(), 48);
    // The exit-speed fit runs on the same oblique session (its model answers oblique swings as the node does).
    let exit_fit = fit(&exit_speed_problem_from_bag(&bag, None).unwrap(), &FitOptions::default()).expect("COR fit");
    let cor = exit_fit.parameter("cor").unwrap();
    assert!((cor.value - 0.53).abs() < 4.0 * cor.std_error + 2e-3, "COR {} ± {}", cor.value, cor.std_error);

    let result = fit_tangential(&problem, &problem.ball, &TangentialOptions::default()).expect("e_T fit");
    let e = result.parameter("tangential_cor").unwrap();
    assert!(result.converged, "{result:?}");
    assert_eq!(e.initial, 0.405);
    assert!(e.std_error > 1e-3 && e.std_error < 0.05, "σ(e_T) = {}", e.std_error);
    assert!((e.value - TRUE_E_T).abs() < 3.0 * e.std_error, "e_T {} ± {} vs true {TRUE_E_T}", e.value, e.std_error);
    // And the data tell the true value from the start value (KNS's 0.405) by more than 3σ.
    assert!((e.value - e.initial).abs() > 3.0 * e.std_error, "e_T {} ± {}", e.value, e.std_error);
    // Starting from the default, the fit removes a bias in the spins: the RMS spin residual falls.
    assert!(result.rms_spin.1 < result.rms_spin.0, "{:?}", result.rms_spin);
    // Every reported undercut is refined within its σ (2 mm), which keeps its noise from biasing e_T.
    assert_eq!(result.parameters.len(), 49, "e_T and one undercut per swing");
}

#[test]
fn the_tangential_fit_finds_unreported_undercuts_too() {
    let tmp = tempfile::tempdir().unwrap();
    let (bag, truth) = write_session(tmp.path(), 40, config(22, false));

    // The exit-speed fit cannot use swings without an undercut and says so.
    let exit_problem = exit_speed_problem_from_bag(&bag, None).unwrap_err();
    assert!(matches!(exit_problem, CalibrateError::NoData(_)), "{exit_problem}");

    let problem = problem_from_bag(&bag, None).expect("problem");
    assert!(problem.observations.iter().all(|o| o.input.undercut.is_nan()));
    let result = fit_tangential(&problem, &problem.ball, &TangentialOptions::default()).expect("e_T fit");
    let e = result.parameter("tangential_cor").unwrap();
    assert_eq!(result.parameters.len(), 41, "e_T and one undercut per swing");
    assert!(e.std_error > 1e-3 && e.std_error < 0.1, "σ(e_T) = {}", e.std_error);
    assert!((e.value - TRUE_E_T).abs() < 3.0 * e.std_error, "e_T {} ± {} vs true {TRUE_E_T}", e.value, e.std_error);
    // And the data tell the true value from the start value (KNS's 0.405) by more than 3σ.
    assert!((e.value - e.initial).abs() > 3.0 * e.std_error, "e_T {} ± {}", e.value, e.std_error);
    // Each fitted undercut against the rig's true one, within its own stated uncertainty (3σ) for most
    // swings (noise in the other reported inputs is not in the stated σ, so a few may fall outside).
    let mut within = 0;
    for swing in &truth {
        let launch = swing.launch.as_ref().unwrap();
        let fitted = result.parameter(&format!("undercut[{}]", swing.swing_id)).expect("fitted undercut");
        assert!(fitted.std_error > 0.0 && fitted.std_error < 0.005, "{fitted:?}");
        if (fitted.value - launch.truth.undercut).abs() < 3.0 * fitted.std_error {
            within += 1;
        }
    }
    assert!(within >= truth.len() * 8 / 10, "{within} of {} undercuts within 3σ", truth.len());
}

/// The loop calibrate closes for a rig: `--fit-tangential --write` puts the fitted e_T into the BallParams it
/// writes (which `sweetspot pub` sends to a node), and a session recorded with that BallParams starts the next
/// fit from it, with μ and the moment of inertia the ball carried.
#[test]
fn the_fitted_e_t_is_written_into_ball_params_and_read_back_as_the_start() {
    let tmp = tempfile::tempdir().unwrap();
    let (bag, _) = write_session(tmp.path(), 40, config(23, true));
    let out = tmp.path().join("fitted.jsonl");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_sweetspot"))
        .arg("calibrate")
        .arg(&bag)
        .args(["--fit-tangential", "--json", "--write"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let fitted = doc["tangential"]["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "tangential_cor")
        .and_then(|p| p["value"].as_f64())
        .expect("fitted e_T");
    assert!((fitted - TRUE_E_T).abs() < 0.1, "e_T {fitted}");
    let line = std::fs::read_to_string(&out).unwrap();
    let written: BallParams = sweetspot::msgs::json::from_json(&serde_json::from_str(line.trim()).unwrap()).unwrap();
    assert_eq!(written.tangential_cor, fitted);
    let model = sweetspot::model::convert::ball_from_params(&written).expect("the node accepts it");
    assert_eq!(model.contact.tangential_cor, fitted);
    assert_eq!(model.contact.friction, TangentialContact::default().friction);

    // A session whose BallParams carry a contact: the fit starts from its e_T and keeps its μ and I.
    let next = tmp.path().join("next");
    std::fs::create_dir(&next).unwrap();
    let (bag2, _) = write_session_with(&next, 12, config(24, true), |b| {
        b.tangential_cor = 0.25;
        b.friction = 0.6;
        b.moment_of_inertia = 0.38 * b.mass * b.radius * b.radius;
    });
    let problem = problem_from_bag(&bag2, None).expect("problem");
    assert_eq!((problem.contact.tangential_cor, problem.contact.friction), (0.25, 0.6));
    assert!((problem.contact.ball_inertia_ratio - 0.38).abs() < 1e-12);
    let options = TangentialOptions { contact: problem.contact, ..TangentialOptions::default() };
    let result = fit_tangential(&problem, &problem.ball, &options).expect("e_T fit");
    assert_eq!(result.parameter("tangential_cor").unwrap().initial, 0.25);
    assert_eq!((result.contact.friction, result.contact.ball_inertia_ratio), (0.6, problem.contact.ball_inertia_ratio));
}
