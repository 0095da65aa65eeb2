//! `calibrate --fit-cor-exponent` recovers a known COR-against-speed law from swings at several pitch speeds,
//! starting from a constant-COR ball, and refuses sessions that do not span speeds.

use std::collections::BTreeMap;

use sweetspot::calibrate::cor_speed::fit_cor_law;
use sweetspot::calibrate::{CalibrateError, FitOptions, Observation, Problem, ProblemBat};
use sweetspot::msgs::sweetspot_msgs::msg::BatParams;
use sweetspot::physics::oblique::TangentialContact;
use sweetspot::physics::{collide, Ball, Bat, CollisionOptions, Impact, ModeSet};

const MODES: usize = 12;
const DT: f64 = 5e-6;

/// A session with the R161: pitch speeds 28–44 m/s, two impact points, exit speeds from the true ball plus a
/// fixed ±0.1 m/s pattern of "radar noise" (deterministic, zero mean).
fn session(truth: &Ball, pitches: &[f64]) -> Problem {
    let bat = Bat::preset("r161").unwrap();
    let modes = ModeSet::compute(&bat, MODES).unwrap();
    let options = CollisionOptions { modes: MODES, time_step: DT };
    let mut observations = Vec::new();
    for (i, &pitch) in pitches.iter().enumerate() {
        for (j, z) in [0.68, 0.72].into_iter().enumerate() {
            let impact = Impact { ball_speed: pitch, bat_cm_speed: 24.0, bat_angular_speed: 45.0, impact_z: z };
            let exit = collide(&modes, truth, &impact, &options).unwrap().exit_speed;
            let noise = if (i + j) % 2 == 0 { 0.1 } else { -0.1 };
            observations.push(Observation {
                swing_id: (2 * i + j) as u64,
                bat_id: "r161".into(),
                impact,
                input: impact.into(),
                measured_exit_speed: exit + noise,
            });
        }
    }
    let mut bats = BTreeMap::new();
    bats.insert("r161".to_string(), ProblemBat { bat, modes: MODES, params: BatParams::default() });
    Problem {
        bats,
        ball_id: "b".into(),
        ball: Ball::default(),
        contact: TangentialContact::default(),
        observations,
        time_step: DT,
        skipped: Vec::new(),
    }
}

#[test]
fn the_speed_law_is_recovered_from_sessions_at_several_pitch_speeds() {
    let truth = Ball::mlb();
    let problem = session(&truth, &[28.0, 32.0, 36.0, 40.0, 44.0]);
    let fit = fit_cor_law(&problem, &FitOptions::default()).unwrap();
    assert!(fit.converged);
    let v_ref = fit.reference_speed;
    // The truth at the fit's reference speed, from the published law written out (the power law through
    // e0 = 0.66 at 1 m/s and 0.50 at 60 m/s).
    let p = (0.66f64 / 0.50).ln() / 60f64.ln();
    let e_ref = 0.66 * v_ref.powf(-p);
    let (cor, exponent) = (&fit.parameters[0], &fit.parameters[1]);
    assert!((cor.value - e_ref).abs() < 3.0 * cor.std_error + 1e-4, "cor {} ± {} vs {e_ref}", cor.value, cor.std_error);
    assert!(
        (exponent.value - p).abs() < 3.0 * exponent.std_error + 1e-4,
        "exponent {} ± {} vs {p}",
        exponent.value,
        exponent.std_error
    );
    // The noise is ±0.1 m/s: the fit leaves about that, and started well above it (a constant 0.53).
    assert!(fit.rms < 0.12 && fit.rms_before > 0.3, "rms {} (before {})", fit.rms, fit.rms_before);
    assert!(exponent.std_error > 0.0 && exponent.std_error < 0.02, "σ {}", exponent.std_error);
    assert_eq!((fit.ball.cor_speed_exponent, fit.ball.cor_reference_speed), (exponent.value, v_ref));
}

#[test]
fn a_session_at_one_pitch_speed_is_refused() {
    let problem = session(&Ball::mlb(), &[40.0, 40.5, 41.0]);
    match fit_cor_law(&problem, &FitOptions::default()) {
        Err(CalibrateError::NoData(m)) => assert!(m.contains("several approach speeds"), "{m}"),
        other => panic!("expected a refusal, got {other:?}"),
    }
}
