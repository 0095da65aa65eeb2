//! Calibration: fit the ball's COR (and optionally each bat's Young's modulus) to measured exit speeds.
//!
//! The model is the physics itself: for parameters θ the predicted exit speed of swing i is
//! `collide(modes(bat_i; E), ball(e0), impact_i).exit_speed`. We minimise Σ r_i², r_i = measured_i −
//! predicted_i(θ), by Levenberg–Marquardt with forward-difference Jacobians (the collision is a fixed-step
//! integration, so analytic derivatives are not available). Parameters are scaled by their start values so
//! the damped normal equations are well conditioned whatever their units.
//!
//! **Uncertainty.** At the optimum, with s² = Σ r_i²/(n − p) the residual variance, the covariance of θ is
//! s²·(JᵀJ)⁻¹ (the usual linearised least-squares estimate); the standard uncertainty of parameter k is
//! √Cov_kk. It assumes independent, equal-variance errors in the measured exit speeds, and treats the
//! measured swing inputs (ball speed, bat speed, impact point) as exact.
//!
//! **The node's rules.** Bats, balls and swings are read from the bag by [`sweetspot_model`] — the conversions
//! and settings the node ran with (mode counts, time step, `max_bat_slices`, default bat, all from the bag's
//! `custom_data`) — so the fit simulates exactly the bats the node simulated.
//!
//! The sans-IO part ([`Problem`], [`fit`]) is pure; [`problem_from_bag`] reads a recorded session. Oblique
//! swings are predicted as the node answers them; [`tangential`] fits e_T to measured launch angles and spins.
//!
//! [`batter`] fits a batter's reference swing and exponent to the bat speeds of the same sessions.

pub mod batter;
pub mod cor_speed;
mod lm;
pub mod statcast;
pub mod tangential;

use std::collections::BTreeMap;
use std::path::Path;

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use sweetspot_bag::reader::read_bag;
use sweetspot_bag::BagError;
use sweetspot_model::convert::{ball_from_params, bat_from_params_capped, swing_input, BallModel};
use sweetspot_model::engine::SwingInput;
use sweetspot_model::settings::ModelSettings;
use sweetspot_msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use sweetspot_msgs::{decode_cdr, RosMessage};
use sweetspot_physics::oblique::TangentialContact;
use sweetspot_physics::{Ball, Bat, CollisionOptions, Impact, ModeSet, PhysicsError};

/// Errors of calibration.
#[derive(Debug, thiserror::Error)]
pub enum CalibrateError {
    /// Reading the bag failed.
    #[error("reading the bag: {0}")]
    Bag(#[from] BagError),
    /// The bag holds nothing to fit.
    #[error("{0}")]
    NoData(String),
    /// A message in the bag does not describe a valid bat, ball or swing.
    #[error("{context}: {source}")]
    Physics {
        context: String,
        #[source]
        source: PhysicsError,
    },
    /// The normal equations are singular (a parameter the data does not constrain).
    #[error("the fit is degenerate: {0}")]
    Degenerate(String),
}

/// One measured swing: the inputs the rig reported and the exit speed it measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Observation {
    /// The swing's id.
    pub swing_id: u64,
    /// The bat it was hit with (a key of [`Problem::bats`]).
    pub bat_id: String,
    /// The inputs along the bat's path (`input.impact`).
    pub impact: Impact,
    /// Everything the swing carried: the oblique geometry and the tracker's launch readings too.
    pub input: SwingInput,
    /// Measured exit speed, m/s.
    pub measured_exit_speed: f64,
}

/// A bat of the problem with the mode count it is computed with.
#[derive(Debug, Clone, PartialEq)]
pub struct ProblemBat {
    /// The bat (its shell Young's modulus is the start value when fitting it).
    pub bat: Bat,
    /// Vibrational modes computed and integrated.
    pub modes: usize,
    /// The BatParams it came from, kept so a fitted bat is written back with the same id.
    pub params: BatParams,
}

/// What to fit: the bats, the ball, and the measured swings.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Bats by bat_id.
    pub bats: BTreeMap<String, ProblemBat>,
    /// The ball's id and its start value (its COR is fitted).
    pub ball_id: String,
    /// The ball.
    pub ball: Ball,
    /// The ball's tangential contact as its BallParams gave it to the node (oblique swings' exit speeds use
    /// it; `--fit-tangential` starts from it).
    pub contact: TangentialContact,
    /// The measured swings with that ball.
    pub observations: Vec<Observation>,
    /// RK4 time step, s.
    pub time_step: f64,
    /// Inputs left out, with the reason (invalid params, swings the node would reject, unknown bats).
    pub skipped: Vec<String>,
}

/// How to fit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Fit each bat's shell Young's modulus too.
    pub fit_youngs: bool,
    /// Iteration limit.
    pub max_iterations: usize,
    /// Stop when the relative step of every parameter is below this.
    pub tolerance: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions { fit_youngs: false, max_iterations: 30, tolerance: 1e-6 }
    }
}

/// One fitted parameter.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FittedParameter {
    /// Name, e.g. `cor` or `youngs_modulus[r161]`.
    pub name: String,
    /// Unit.
    pub unit: &'static str,
    /// Start value.
    pub initial: f64,
    /// Fitted value.
    pub value: f64,
    /// Standard uncertainty (1σ).
    pub std_error: f64,
}

/// One residual at the optimum.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Residual {
    /// The swing.
    pub swing_id: u64,
    /// Its bat.
    pub bat_id: String,
    /// Impact point, m from the knob.
    pub impact_z: f64,
    /// Measured exit speed, m/s.
    pub measured: f64,
    /// Predicted with the start parameters, m/s.
    pub predicted_before: f64,
    /// Predicted with the fitted parameters, m/s.
    pub predicted: f64,
    /// measured − predicted, m/s.
    pub residual: f64,
}

/// The result of a fit.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// Fitted parameters.
    pub parameters: Vec<FittedParameter>,
    /// Residuals, one per observation.
    pub residuals: Vec<Residual>,
    /// RMS residual before the fit, m/s.
    pub rms_before: f64,
    /// RMS residual after, m/s.
    pub rms: f64,
    /// Residual standard deviation s = √(Σr²/(n − p)), m/s.
    pub residual_sigma: f64,
    /// Degrees of freedom n − p.
    pub dof: usize,
    /// Iterations done.
    pub iterations: usize,
    /// Whether the step tolerance was met.
    pub converged: bool,
    /// The ball with the fitted COR.
    pub ball: Ball,
    /// The bats with the fitted moduli (only when fitted).
    pub bats: BTreeMap<String, Bat>,
}

impl Fit {
    /// The fitted parameter named `name`.
    pub fn parameter(&self, name: &str) -> Option<&FittedParameter> {
        self.parameters.iter().find(|p| p.name == name)
    }
}

/// Predicted exit speeds of `problem` for a ball COR and per-bat Young's moduli (None = the bat's own).
fn predict(
    problem: &Problem,
    cor: f64,
    youngs: &BTreeMap<String, f64>,
    only_bat: Option<&str>,
) -> Result<Vec<Option<f64>>, CalibrateError> {
    let ball = Ball { cor, ..problem.ball };
    let mut modes: BTreeMap<&str, ModeSet> = BTreeMap::new();
    for (id, pb) in &problem.bats {
        if only_bat.is_some_and(|b| b != id) {
            continue;
        }
        let mut bat = pb.bat.clone();
        if let Some(&e) = youngs.get(id) {
            bat.shell.youngs_modulus = e;
        }
        let set = ModeSet::compute(&bat, pb.modes)
            .map_err(|source| CalibrateError::Physics { context: format!("bat '{id}'"), source })?;
        modes.insert(id.as_str(), set);
    }
    problem
        .observations
        .par_iter()
        .map(|o| match modes.get(o.bat_id.as_str()) {
            None => Ok(None),
            Some(set) => {
                let options = CollisionOptions { modes: problem.bats[&o.bat_id].modes, time_step: problem.time_step };
                tangential::exit_speed(set, &problem.bats[&o.bat_id].bat, &ball, &problem.contact, &o.input, &options)
                    .map(Some)
                    .map_err(|source| CalibrateError::Physics { context: format!("swing {}", o.swing_id), source })
            }
        })
        .collect()
}

/// The parameter vector and how to apply it.
struct Layout {
    names: Vec<String>,
    units: Vec<&'static str>,
    start: Vec<f64>,
    bat_of: Vec<Option<String>>,
}

impl Layout {
    fn new(problem: &Problem, options: &FitOptions) -> Layout {
        let mut l =
            Layout { names: vec!["cor".into()], units: vec![""], start: vec![problem.ball.cor], bat_of: vec![None] };
        if options.fit_youngs {
            for (id, pb) in &problem.bats {
                if problem.observations.iter().any(|o| &o.bat_id == id) {
                    l.names.push(format!("youngs_modulus[{id}]"));
                    l.units.push("Pa");
                    l.start.push(pb.bat.shell.youngs_modulus);
                    l.bat_of.push(Some(id.clone()));
                }
            }
        }
        l
    }

    /// (cor, moduli) for scaled parameters x (θ = x·start).
    fn unpack(&self, x: &DVector<f64>) -> (f64, BTreeMap<String, f64>) {
        let mut youngs = BTreeMap::new();
        for (k, bat) in self.bat_of.iter().enumerate().skip(1) {
            if let Some(b) = bat {
                youngs.insert(b.clone(), x[k] * self.start[k]);
            }
        }
        (x[0] * self.start[0], youngs)
    }
}

fn residuals_of(problem: &Problem, predicted: &[Option<f64>]) -> DVector<f64> {
    DVector::from_iterator(
        predicted.len(),
        problem.observations.iter().zip(predicted).map(|(o, p)| o.measured_exit_speed - p.unwrap_or(f64::NAN)),
    )
}

/// Fits `problem` by Levenberg–Marquardt (see the module docs).
pub fn fit(problem: &Problem, options: &FitOptions) -> Result<Fit, CalibrateError> {
    let layout = Layout::new(problem, options);
    let p = layout.start.len();
    let n = problem.observations.len();
    if n <= p {
        return Err(CalibrateError::NoData(format!(
            "{n} measured swings cannot determine {p} parameter(s); need at least {}",
            p + 1
        )));
    }
    let evaluate = |x: &DVector<f64>| {
        let predicted = layout.predict(problem, x, None)?;
        Ok((residuals_of(problem, &predicted), predicted))
    };
    let jacobian =
        |x: &DVector<f64>, r: &DVector<f64>, current: &Vec<Option<f64>>| layout.jacobian(problem, x, r, current);
    let start = DVector::from_element(p, 1.0);
    let minimum = lm::minimize(start, evaluate, jacobian, options.max_iterations, options.tolerance)?;
    let errors = minimum.standard_errors().ok_or_else(|| {
        CalibrateError::Degenerate("JᵀJ is singular; the data do not constrain every parameter".into())
    })?;
    let (x, r, dof) = (&minimum.x, &minimum.residuals, minimum.dof());
    let (before, current) = (&minimum.predicted_at_start, &minimum.predicted);
    let ssr = r.norm_squared();
    let rms_before = (residuals_of(problem, before).norm_squared() / n as f64).sqrt();
    let (cor, youngs) = layout.unpack(x);
    Ok(Fit {
        parameters: layout.parameters(x, &errors),
        residuals: residual_rows(problem, before, current, r),
        rms_before,
        rms: (ssr / n as f64).sqrt(),
        residual_sigma: minimum.residual_variance().sqrt(),
        dof,
        iterations: minimum.iterations,
        converged: minimum.converged,
        ball: Ball { cor, ..problem.ball },
        bats: bats_with_moduli(problem, &youngs),
    })
}

impl Layout {
    /// Predicted exit speeds at scaled parameters `x` (of `only` that bat's swings when given); all None
    /// outside the physical range.
    fn predict(
        &self,
        problem: &Problem,
        x: &DVector<f64>,
        only: Option<&str>,
    ) -> Result<Vec<Option<f64>>, CalibrateError> {
        let (cor, youngs) = self.unpack(x);
        if !(cor > 0.0 && cor <= 1.0) || youngs.values().any(|&e| e.is_nan() || e <= 0.0) {
            return Ok(vec![None; problem.observations.len()]);
        }
        predict(problem, cor, &youngs, only)
    }

    /// Forward differences; a bat's modulus moves only its own swings, so only those are recomputed.
    fn jacobian(
        &self,
        problem: &Problem,
        x: &DVector<f64>,
        r: &DVector<f64>,
        current: &[Option<f64>],
    ) -> Result<DMatrix<f64>, CalibrateError> {
        let step = 1e-4;
        let (n, p) = (problem.observations.len(), self.start.len());
        let mut j = DMatrix::zeros(n, p);
        for k in 0..p {
            let mut xk = x.clone();
            xk[k] += step;
            let only = self.bat_of[k].as_deref();
            let shifted = self.predict(problem, &xk, only)?;
            for i in 0..n {
                // ∂(predicted)/∂x_k; observations of other bats do not depend on bat k's modulus.
                let moved = shifted[i].or(if only.is_some() { current[i] } else { None });
                let base = problem.observations[i].measured_exit_speed - r[i];
                j[(i, k)] = moved.map(|m| (m - base) / step).unwrap_or(0.0);
            }
        }
        Ok(j)
    }

    fn parameters(&self, x: &DVector<f64>, errors: &[f64]) -> Vec<FittedParameter> {
        (0..self.start.len())
            .map(|k| FittedParameter {
                name: self.names[k].clone(),
                unit: self.units[k],
                initial: self.start[k],
                value: x[k] * self.start[k],
                std_error: errors[k] * self.start[k],
            })
            .collect()
    }
}

fn residual_rows(
    problem: &Problem,
    before: &[Option<f64>],
    current: &[Option<f64>],
    r: &DVector<f64>,
) -> Vec<Residual> {
    problem
        .observations
        .iter()
        .enumerate()
        .map(|(i, o)| Residual {
            swing_id: o.swing_id,
            bat_id: o.bat_id.clone(),
            impact_z: o.impact.impact_z,
            measured: o.measured_exit_speed,
            predicted_before: before[i].unwrap_or(f64::NAN),
            predicted: current[i].unwrap_or(f64::NAN),
            residual: r[i],
        })
        .collect()
}

/// The session's bats with their fitted shell moduli.
fn bats_with_moduli(problem: &Problem, youngs: &BTreeMap<String, f64>) -> BTreeMap<String, Bat> {
    youngs
        .iter()
        .filter_map(|(id, &e)| {
            problem.bats.get(id).map(|pb| {
                let mut bat = pb.bat.clone();
                bat.shell.youngs_modulus = e;
                (id.clone(), bat)
            })
        })
        .collect()
}

/// The bat a BatParams describes and the modes the node integrates for it, by the node's rules
/// ([`sweetspot_model::convert::bat_from_params_capped`], [`ModelSettings::modes_for`]); the error is the
/// node's rejection.
pub fn problem_bat(params: &BatParams, settings: &ModelSettings) -> Result<ProblemBat, String> {
    let built = bat_from_params_capped(params, settings.max_bat_slices)?;
    let modes = settings.modes_for(&built.bat, built.max_modes);
    Ok(ProblemBat { bat: built.bat, modes, params: params.clone() })
}

/// Inputs of a recorded session, in log-time order, before they are turned into a [`Problem`].
#[derive(Debug, Clone, Default)]
pub struct RecordedInputs {
    /// (log time ns, message).
    pub bats: Vec<(u64, BatParams)>,
    /// (log time ns, message).
    pub balls: Vec<(u64, BallParams)>,
    /// (log time ns, message).
    pub swings: Vec<(u64, Swing)>,
    /// The settings the node ran with (the bag's `custom_data`; defaults for a bag without them).
    pub settings: ModelSettings,
}

/// Reads every BatParams, BallParams and Swing from a bag (by type, whatever the namespace).
pub fn read_inputs(path: &Path) -> Result<RecordedInputs, CalibrateError> {
    let mut inputs = RecordedInputs::default();
    let mut undecodable = 0u64;
    let scans = read_bag(path, |m| {
        let t = m.log_time_ns;
        let ty = m.channel.topic.type_name.as_str();
        let ok = if ty == BatParams::TYPE_NAME {
            decode_cdr::<BatParams>(m.data).map(|v| inputs.bats.push((t, v))).is_ok()
        } else if ty == BallParams::TYPE_NAME {
            decode_cdr::<BallParams>(m.data).map(|v| inputs.balls.push((t, v))).is_ok()
        } else if ty == Swing::TYPE_NAME {
            decode_cdr::<Swing>(m.data).map(|v| inputs.swings.push((t, v))).is_ok()
        } else {
            true
        };
        if !ok {
            undecodable += 1;
        }
    })?;
    if undecodable > 0 {
        tracing::warn!("{undecodable} input messages in the bag could not be decoded and were skipped");
    }
    inputs.bats.sort_by_key(|(t, _)| *t);
    inputs.balls.sort_by_key(|(t, _)| *t);
    inputs.swings.sort_by_key(|(t, _)| *t);
    inputs.settings = ModelSettings::from_custom_data(&sweetspot_bag::info::custom_data_of(&scans));
    Ok(inputs)
}

/// The fitting problem of recorded inputs: swings with a measured exit speed, resolved to the bat and ball
/// in force when they were received (empty ids = the latest received, else the recorded default bat and
/// ball, as the node does), computed with the recorded settings ([`RecordedInputs::settings`]). Only swings with
/// `ball_id` (None = the ball most measured swings used) are kept.
pub fn problem_from_inputs(inputs: &RecordedInputs, ball_id: Option<&str>) -> Result<Problem, CalibrateError> {
    let mut skipped = Vec::new();
    let settings = &inputs.settings;
    let (mut bats, bat_times) = announced_bats(inputs, &mut skipped);
    let (balls, ball_times) = announced_balls(inputs, &mut skipped);
    let mut by_ball = observations_by_ball(inputs, &mut bats, &bat_times, &ball_times, &mut skipped);
    let chosen = match ball_id {
        Some(id) => id.to_string(),
        None => by_ball.iter().max_by_key(|(_, v)| v.len()).map(|(k, _)| k.clone()).ok_or_else(|| {
            CalibrateError::NoData(
                "the bag holds no swing with a measured exit speed (measured_exit_speed is NaN in all)".into(),
            )
        })?,
    };
    let mut observations = by_ball.remove(&chosen).unwrap_or_default();
    retain_fittable(&mut observations, &bats, &mut skipped);
    if observations.is_empty() {
        return Err(CalibrateError::NoData(format!("no measured swing used ball '{chosen}'")));
    }
    let BallModel { ball, contact } = *balls.get(&chosen).ok_or_else(|| {
        CalibrateError::NoData(format!("ball '{chosen}' was never announced on ball/params in this bag"))
    })?;
    let used: std::collections::BTreeSet<&str> = observations.iter().map(|o| o.bat_id.as_str()).collect();
    bats.retain(|id, _| used.contains(id.as_str()));
    Ok(Problem { bats, ball_id: chosen, ball, contact, observations, time_step: settings.time_step, skipped })
}

/// (log time, id) of accepted params: only those become "the latest received" for empty ids.
type Announcements = Vec<(u64, String)>;

/// The id announced last at or before `t`.
fn latest_at(list: &[(u64, String)], t: u64) -> Option<String> {
    list.iter().rev().find(|(lt, _)| *lt <= t).map(|(_, id)| id.clone())
}

/// The bats announced in the bag, by id, and when each was accepted.
fn announced_bats(inputs: &RecordedInputs, skipped: &mut Vec<String>) -> (BTreeMap<String, ProblemBat>, Announcements) {
    // Params re-announced under the same id replace the old ones; we fit against the last version of each.
    let mut bats: BTreeMap<String, ProblemBat> = BTreeMap::new();
    let mut bat_times = Vec::new();
    for (t, params) in &inputs.bats {
        // The node rejects bad params and keeps the previous ones in force; so do we, by its own rules (e.g. a
        // mode count beyond the bat's, a bat finer than the recorded `max_bat_slices`).
        match problem_bat(params, &inputs.settings) {
            Ok(bat) => {
                bats.insert(params.bat_id.clone(), bat);
                bat_times.push((*t, params.bat_id.clone()));
            }
            Err(reason) => skipped.push(reason),
        }
    }
    (bats, bat_times)
}

/// The balls known to the session (the presets and those announced), by id, and when each was announced.
fn announced_balls(inputs: &RecordedInputs, skipped: &mut Vec<String>) -> (BTreeMap<String, BallModel>, Announcements) {
    let mut balls: BTreeMap<String, BallModel> = BTreeMap::new();
    // The built-in balls answer to their names without params, as in the node.
    for name in Ball::preset_names() {
        if let Ok(ball) = Ball::preset(name) {
            balls.insert(name.to_string(), ball.into());
        }
    }
    let mut ball_times = Vec::new();
    for (t, params) in &inputs.balls {
        match ball_from_params(params) {
            Ok(ball) => {
                balls.insert(params.ball_id.clone(), ball);
                ball_times.push((*t, params.ball_id.clone()));
            }
            Err(reason) => skipped.push(reason),
        }
    }
    (balls, ball_times)
}

/// The swings with a measured exit speed and a known bat, grouped by the ball they used; a preset bat a
/// swing names without its announcement is added to `bats`.
fn observations_by_ball(
    inputs: &RecordedInputs,
    bats: &mut BTreeMap<String, ProblemBat>,
    bat_times: &[(u64, String)],
    ball_times: &[(u64, String)],
    skipped: &mut Vec<String>,
) -> BTreeMap<String, Vec<Observation>> {
    let settings = &inputs.settings;
    let mut by_ball: BTreeMap<String, Vec<Observation>> = BTreeMap::new();
    for (t, s) in &inputs.swings {
        if !s.measured_exit_speed.is_finite() {
            continue;
        }
        let bat_id = if s.bat_id.is_empty() {
            latest_at(bat_times, *t).unwrap_or_else(|| settings.default_bat.clone())
        } else {
            s.bat_id.clone()
        };
        let ball = if s.ball_id.is_empty() {
            latest_at(ball_times, *t).unwrap_or_else(|| settings.default_ball.clone())
        } else {
            s.ball_id.clone()
        };
        if s.undercut.is_nan() {
            skipped.push(format!("swing {}: undercut not measured (only the e_T fit uses it)", s.swing_id));
            continue;
        }
        if !bats.contains_key(&bat_id) {
            if let Ok(bat) = Bat::preset(&bat_id) {
                // A swing naming a preset bat that was never announced: the node resolves it the same way.
                let modes = settings.modes_for(&bat, None);
                let params = BatParams { bat_id: bat_id.clone(), preset: bat_id.clone(), ..Default::default() };
                bats.insert(bat_id.clone(), ProblemBat { bat, modes, params });
            } else {
                skipped.push(format!("swing {}: unknown bat '{bat_id}'", s.swing_id));
                continue;
            }
        }
        by_ball.entry(ball).or_default().push(Observation {
            swing_id: s.swing_id,
            bat_id,
            impact: swing_input(s).impact,
            input: swing_input(s),
            measured_exit_speed: s.measured_exit_speed,
        });
    }
    by_ball
}

/// Swings the node would reject (impact off the bat, bat and ball not approaching, …) cannot be fitted.
fn retain_fittable(
    observations: &mut Vec<Observation>,
    bats: &BTreeMap<String, ProblemBat>,
    skipped: &mut Vec<String>,
) {
    let mut modes_of: BTreeMap<&str, Option<ModeSet>> = BTreeMap::new();
    for (id, pb) in bats {
        modes_of.insert(id.as_str(), ModeSet::compute(&pb.bat, pb.modes).ok());
    }
    observations.retain(|o| match modes_of.get(o.bat_id.as_str()) {
        Some(Some(modes)) => match o.impact.validate(modes) {
            Ok(()) => true,
            Err(e) => {
                skipped.push(format!("swing {}: {e}", o.swing_id));
                false
            }
        },
        _ => {
            skipped.push(format!("swing {}: the modes of bat '{}' cannot be computed", o.swing_id, o.bat_id));
            false
        }
    });
}

/// Reads a bag and builds its fitting problem (see [`problem_from_inputs`]).
pub fn problem_from_bag(path: &Path, ball_id: Option<&str>) -> Result<Problem, CalibrateError> {
    problem_from_inputs(&read_inputs(path)?, ball_id)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sweetspot_model::convert::{params_from_bat, params_of_preset};
    use sweetspot_msgs::std_msgs::msg::Header;

    fn measured_swing(id: u64, bat_id: &str) -> Swing {
        Swing {
            swing_id: id,
            bat_id: bat_id.into(),
            ball_speed: 40.0,
            bat_cm_speed: 20.0,
            bat_angular_speed: 50.0,
            impact_z: 0.6,
            measured_exit_speed: 45.0,
            ..Swing::default()
        }
    }

    #[test]
    fn bats_are_read_by_the_nodes_rules() {
        let r161 = Bat::preset("r161").unwrap();
        // More modes than a 9-slice bat has (fuzz F1): the node refuses it, so the fit must leave it out.
        let coarse = BatParams { slice_length: 0.84 / 9.0, ..params_from_bat("coarse", &r161, 100, Header::default()) };
        // With a preset the node ignores max_modes and integrates its default.
        let preset = BatParams { max_modes: 6, ..params_of_preset("game", "torpedo", Header::default()) };
        let inputs = RecordedInputs {
            bats: vec![(1, coarse), (2, preset)],
            swings: vec![(3, measured_swing(1, "coarse")), (4, measured_swing(2, "game"))],
            ..RecordedInputs::default()
        };
        let problem = problem_from_inputs(&inputs, None).unwrap();
        assert!(
            problem.skipped.iter().any(|s| s.starts_with("BatParams 'coarse':") && s.contains("max_modes")),
            "{:?}",
            problem.skipped
        );
        assert!(!problem.bats.contains_key("coarse"));
        assert_eq!(problem.bats["game"].modes, 18, "the node's default_modes");
        assert_eq!(problem.observations.len(), 1);
    }

    #[test]
    fn the_problem_is_computed_with_the_settings_the_bag_recorded() {
        use sweetspot_bag::{RecordedQos, Recorder, RecorderConfig, TopicInfo};
        use sweetspot_msgs::encode_cdr;
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("run");
        let recorded = ModelSettings {
            default_bat: "torpedo".into(),
            default_modes: 7,
            time_step: 2.5e-6,
            max_bat_slices: 300,
            ..ModelSettings::default()
        };
        let rec = Recorder::start(RecorderConfig::new(&dir)).unwrap();
        for (key, value) in recorded.custom_data() {
            rec.set_custom_data(key, value);
        }
        let qos = RecordedQos { reliable: true, transient_local: false, depth: 10 };
        let bat_t = rec.register_topic(TopicInfo::of::<BatParams>("/bat/params", qos)).unwrap();
        let swing_t = rec.register_topic(TopicInfo::of::<Swing>("/swing", qos)).unwrap();
        // 0.84 m at 2 mm: 420 slices, over the recorded cap of 300, so the node refused it.
        let fine = BatParams {
            slice_length: 0.002,
            ..params_from_bat("fine", &Bat::preset("r161").unwrap(), 0, Header::default())
        };
        assert!(rec.record(bat_t, encode_cdr(&fine).unwrap(), 1, 1));
        // No bat_id and no BatParams in force: the node's default_bat.
        assert!(rec.record(swing_t, encode_cdr(&measured_swing(1, "")).unwrap(), 2, 2));
        assert!(rec.record(swing_t, encode_cdr(&measured_swing(2, "fine")).unwrap(), 3, 3));
        rec.finish().unwrap();

        let inputs = read_inputs(&dir).unwrap();
        assert_eq!(inputs.settings, recorded);
        let problem = problem_from_inputs(&inputs, None).unwrap();
        assert_eq!(problem.time_step, 2.5e-6);
        assert!(problem.skipped.iter().any(|s| s.contains("max_bat_slices = 300")), "{:?}", problem.skipped);
        assert_eq!(problem.observations.len(), 1);
        assert_eq!(problem.observations[0].bat_id, "torpedo");
        assert_eq!(problem.bats["torpedo"].modes, 7);
    }
}
