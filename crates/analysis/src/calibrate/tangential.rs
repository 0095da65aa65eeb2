//! Calibration of the tangential contact: fit the tangential COR e_T (and the undercut of every swing whose
//! rig did not measure it) to the launch angles and spins a ball tracker measured.
//!
//! The model is [`collide_oblique`] with the swing's measured inputs, the bat's modes and the ball (its COR
//! as given, e.g. the one the exit-speed fit found), and [`TangentialContact`] with e_T free (μ and the
//! ball's inertia ratio kept at the start contact's). For parameters θ = (e_T, D_1 … D_k), the undercuts of
//! the swings, the residuals are
//!
//!   (measured − predicted launch angle)/σ_θ,   (measured − predicted spin)/σ_ω,   (reported − D_j)/σ_D
//!
//! for every measured value (NaN = not measured), with σ_θ, σ_ω the tracker's accuracies and σ_D the
//! undercut camera's ([`TangentialOptions`], default 1°, 100 rpm and 2 mm). A swing whose `Swing.undercut`
//! is NaN has no third residual: its D_j is found from its launch angle and spin alone. The undercuts are
//! fitted even where reported because the spin is steep in D (≈ 250 rpm/mm for a wood bat): taking a noisy
//! reported undercut as exact biases e_T low, by the ratio of the undercut's noise variance to its spread
//! (errors in variables; ≈ −0.05 for 2 mm noise on a 1 cm spread). With σ_D = 0 the reported undercuts are
//! taken as exact. Σ r² is minimised by Levenberg–Marquardt with
//! forward-difference Jacobians, as the exit-speed fit of [`super`] does; a D_j moves only its own swing's
//! residuals, so its Jacobian column costs one collision, and the Jacobian is block-sparse (a swing's rows
//! depend on e_T and its own D_j). The normal equations are solved as such: each D_j is eliminated onto e_T
//! (the Schur complement), the same step and covariance as the dense solve at a cost linear in the swings.
//!
//! **Uncertainty** as in [`super`]: s² = Σ r²/(n − p), Cov θ = s² (JᵀJ)⁻¹, σ_k = √Cov_kk. Only the ratio
//! σ_θ/σ_ω matters (s² absorbs their common scale); the measured swing inputs are treated as exact, so noise
//! in them shows as a larger s², not as a separate term.
//!
//! **What it needs.** e_T moves the spin far more than the launch angle: a session of spins measured at
//! contacts that grip (line-of-centres angles below ~35°, see [`sweetspot_physics::oblique`]) constrains it; a
//! swing that slides throughout does not (its spin is the friction cap's). A swing whose undercut is fitted
//! needs both its launch angle and its spin measured (one unknown, two readings), and others with measured
//! undercuts or many such swings to separate e_T from the undercuts.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use super::{lm, read_inputs, CalibrateError, FittedParameter, Observation, Problem, RecordedInputs};
use sweetspot_model::engine::SwingInput;
use sweetspot_physics::oblique::{
    collide_oblique, rad_per_s_to_rpm, rpm_to_rad_per_s, ObliqueImpact, TangentialContact,
};
use sweetspot_physics::{collide, Ball, Bat, CollisionOptions, ModeSet, PhysicsError};

/// The exit speed the node computes for a swing (m/s): the head-on collision for a head-on swing (bit for
/// bit), else the oblique one with the ball's tangential contact `contact`. `bat` gives the barrel radius.
pub fn exit_speed(
    modes: &ModeSet,
    bat: &Bat,
    ball: &Ball,
    contact: &TangentialContact,
    input: &SwingInput,
    options: &CollisionOptions,
) -> Result<f64, PhysicsError> {
    if input.is_head_on() {
        return collide(modes, ball, &input.impact, options).map(|r| r.exit_speed);
    }
    collide_oblique(modes, ball, &oblique_impact(bat, input, input.undercut), contact, options).map(|r| r.exit_speed)
}

/// The oblique impact of a swing on `bat` with undercut `undercut` (m).
fn oblique_impact(bat: &Bat, input: &SwingInput, undercut: f64) -> ObliqueImpact {
    ObliqueImpact {
        impact: input.impact,
        barrel_radius: bat.radii_at(input.impact.impact_z).0,
        undercut,
        attack_angle: input.attack_angle,
        pitch_angle: input.pitch_angle,
        pitch_spin: input.pitch_spin,
    }
}

/// How to fit e_T.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TangentialOptions {
    /// The tracker's launch-angle accuracy σ_θ, rad (weights the launch-angle residuals; default 1°).
    pub launch_angle_sigma: f64,
    /// The tracker's spin accuracy σ_ω, rad/s (weights the spin residuals; default 100 rpm).
    pub spin_sigma: f64,
    /// Accuracy σ_D of the reported undercuts, m (default 2 mm): each reported undercut is then fitted too,
    /// held to its reported value by the residual (reported − D)/σ_D; 0 takes them as exact.
    pub undercut_sigma: f64,
    /// Start contact: e_T is the start value, μ and the ball's inertia ratio are kept.
    pub contact: TangentialContact,
    /// Iteration limit.
    pub max_iterations: usize,
    /// Stop when every parameter's step is below this (e_T absolute; undercuts in units of 1 cm).
    pub tolerance: f64,
}

impl Default for TangentialOptions {
    fn default() -> Self {
        TangentialOptions {
            launch_angle_sigma: 1f64.to_radians(),
            spin_sigma: rpm_to_rad_per_s(100.0),
            undercut_sigma: 0.002,
            contact: TangentialContact::default(),
            max_iterations: 40,
            tolerance: 1e-6,
        }
    }
}

/// One swing's launch residuals at the optimum.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LaunchResidual {
    /// The swing.
    pub swing_id: u64,
    /// Its bat.
    pub bat_id: String,
    /// Undercut used, m (measured, or fitted when the rig did not measure it).
    pub undercut: f64,
    /// Whether the undercut was fitted without a reported value (the rig did not measure it).
    pub undercut_fitted: bool,
    /// Measured − predicted launch angle, rad (NaN when not measured).
    pub launch_angle: f64,
    /// Measured − predicted spin, rad/s (NaN when not measured).
    pub spin: f64,
}

/// The result of an e_T fit.
#[derive(Debug, Clone, PartialEq)]
pub struct TangentialFit {
    /// `tangential_cor`, then `undercut[swing_id]` (m) for each swing whose undercut was fitted (every swing
    /// with [`TangentialOptions::undercut_sigma`] > 0; `initial` is the reported value, NaN when unreported).
    pub parameters: Vec<FittedParameter>,
    /// One row per swing used.
    pub residuals: Vec<LaunchResidual>,
    /// RMS launch-angle residual before / after the fit, rad.
    pub rms_launch_angle: (f64, f64),
    /// RMS spin residual before / after the fit, rad/s.
    pub rms_spin: (f64, f64),
    /// s = √(Σr²/(n − p)) of the weighted residuals (≈ 1 when the tracker's σ are right and the model fits).
    pub residual_sigma: f64,
    /// Degrees of freedom n − p.
    pub dof: usize,
    /// Iterations done.
    pub iterations: usize,
    /// Whether the step tolerance was met.
    pub converged: bool,
    /// The contact with the fitted e_T.
    pub contact: TangentialContact,
    /// Swings left out, with the reason.
    pub skipped: Vec<String>,
}

impl TangentialFit {
    /// The fitted parameter named `name`.
    pub fn parameter(&self, name: &str) -> Option<&FittedParameter> {
        self.parameters.iter().find(|p| p.name == name)
    }
}

/// The fitting problem of recorded inputs for both fits: [`super::problem_from_inputs`], with the swings
/// whose undercut was not measured (NaN) kept — the exit-speed fit leaves them out — and their undercut NaN.
pub fn problem_from_inputs(inputs: &RecordedInputs, ball_id: Option<&str>) -> Result<Problem, CalibrateError> {
    let mut inputs = inputs.clone();
    let mut unmeasured = std::collections::BTreeSet::new();
    for (_, swing) in &mut inputs.swings {
        if swing.undercut.is_nan() {
            unmeasured.insert(swing.swing_id);
            swing.undercut = 0.0;
        }
    }
    let mut problem = super::problem_from_inputs(&inputs, ball_id)?;
    for o in &mut problem.observations {
        if unmeasured.contains(&o.swing_id) {
            o.input.undercut = f64::NAN;
        }
    }
    Ok(problem)
}

/// Reads a bag and builds its fitting problem (see [`problem_from_inputs`]).
pub fn problem_from_bag(path: &Path, ball_id: Option<&str>) -> Result<Problem, CalibrateError> {
    problem_from_inputs(&read_inputs(path)?, ball_id)
}

/// Predicted (launch angle rad, spin rad/s) of a swing.
type Launch = (f64, f64);

/// A swing of the e_T fit.
struct LaunchSwing<'a> {
    observation: &'a Observation,
    /// Index of its undercut in the parameter vector, when fitted.
    undercut_index: Option<usize>,
}

/// What a minimisation found, whichever solver found it.
struct Solved {
    x: DVector<f64>,
    predicted: Vec<Option<Launch>>,
    predicted_at_start: Vec<Option<Launch>>,
    sigmas: Option<Vec<f64>>,
    residual_variance: f64,
    dof: usize,
    iterations: usize,
    converged: bool,
}

impl Solved {
    fn of<J: lm::Linearisation>(m: lm::Minimum<Vec<Option<Launch>>, J>) -> Solved {
        Solved {
            sigmas: m.standard_errors(),
            residual_variance: m.residual_variance(),
            dof: m.dof(),
            iterations: m.iterations,
            converged: m.converged,
            x: m.x,
            predicted: m.predicted,
            predicted_at_start: m.predicted_at_start,
        }
    }
}

pub use lm::Progress;

/// Fits e_T (and unmeasured undercuts) of `problem` with the ball `ball` (see the module docs).
pub fn fit_tangential(
    problem: &Problem,
    ball: &Ball,
    options: &TangentialOptions,
) -> Result<TangentialFit, CalibrateError> {
    fit_tangential_with_progress(problem, ball, options, |_| {})
}

/// [`fit_tangential`], calling `progress` after every evaluation of the residuals or the Jacobian (each
/// costs one or two collisions per swing). The normal equations are solved block by block (each swing's
/// undercut eliminated onto e_T), so the cost grows linearly with the number of swings.
pub fn fit_tangential_with_progress(
    problem: &Problem,
    ball: &Ball,
    options: &TangentialOptions,
    progress: impl FnMut(Progress),
) -> Result<TangentialFit, CalibrateError> {
    fit_with(problem, ball, options, false, progress)
}

/// The fit, with the dense solver (`dense`, the reference the block solver is tested against) or the block one.
fn fit_with(
    problem: &Problem,
    ball: &Ball,
    options: &TangentialOptions,
    dense: bool,
    progress: impl FnMut(Progress),
) -> Result<TangentialFit, CalibrateError> {
    check_options(options)?;
    let undercut_prior = options.undercut_sigma > 0.0;
    let (swings, skipped, p) = select_swings(problem, undercut_prior);
    let fit = LaunchModel::new(problem, ball, options, swings, p)?;
    let minimum = fit.minimize(dense, progress)?;
    let sigmas = minimum.sigmas.clone().ok_or_else(|| {
        CalibrateError::Degenerate(
            "JᵀJ is singular: the launch angles and spins do not constrain e_T (every swing slides, or no spin is \
             measured) or an unmeasured undercut"
                .into(),
        )
    })?;
    Ok(fit.result(&minimum, &sigmas, skipped))
}

fn check_options(options: &TangentialOptions) -> Result<(), CalibrateError> {
    options.contact.validate().map_err(|source| CalibrateError::Physics { context: "start contact".into(), source })?;
    if !(options.launch_angle_sigma > 0.0 && options.spin_sigma > 0.0 && options.undercut_sigma >= 0.0) {
        return Err(CalibrateError::NoData(
            "the tracker's σ for launch angle and spin must be positive, the undercut's σ ≥ 0".into(),
        ));
    }
    Ok(())
}

/// The swings with a launch angle or spin measured, the reasons others were skipped, and the number of
/// parameters (e_T and one per fitted undercut).
fn select_swings(problem: &Problem, undercut_prior: bool) -> (Vec<LaunchSwing<'_>>, Vec<String>, usize) {
    let mut skipped = Vec::new();
    let mut swings = Vec::new();
    let mut p = 1;
    for o in &problem.observations {
        let (la, spin) = (o.input.measured_launch_angle.is_finite(), o.input.measured_spin.is_finite());
        if !la && !spin {
            continue;
        }
        let undercut_index = if o.input.undercut.is_nan() {
            if !(la && spin) {
                skipped.push(format!(
                    "swing {}: undercut not measured and only one of launch angle and spin measured",
                    o.swing_id
                ));
                continue;
            }
            p += 1;
            Some(p - 1)
        } else if undercut_prior {
            p += 1;
            Some(p - 1)
        } else {
            None
        };
        swings.push(LaunchSwing { observation: o, undercut_index });
    }
    (swings, skipped, p)
}

/// Parameters are scaled to order 1: e_T as is, undercuts in cm.
const UNDERCUT_UNIT: f64 = 0.01;
/// Forward-difference step of the Jacobian, in scaled parameters.
const JACOBIAN_STEP: f64 = 1e-4;

/// The undercut (m) of a swing at parameters `x`: fitted, or as reported.
fn undercut_of(s: &LaunchSwing, x: &DVector<f64>) -> f64 {
    match s.undercut_index {
        Some(k) => x[k] * UNDERCUT_UNIT,
        None => s.observation.input.undercut,
    }
}

/// The e_T fit's model: the selected swings, their bats' modes and the layout of the residual rows.
struct LaunchModel<'a> {
    problem: &'a Problem,
    ball: &'a Ball,
    options: &'a TangentialOptions,
    undercut_prior: bool,
    swings: Vec<LaunchSwing<'a>>,
    modes: BTreeMap<&'a str, ModeSet>,
    /// Rows of each swing's residuals.
    rows: Vec<Range<usize>>,
    /// Residual rows in all.
    n: usize,
    /// Parameters in all.
    p: usize,
}

impl<'a> LaunchModel<'a> {
    fn new(
        problem: &'a Problem,
        ball: &'a Ball,
        options: &'a TangentialOptions,
        swings: Vec<LaunchSwing<'a>>,
        p: usize,
    ) -> Result<Self, CalibrateError> {
        let mut model = LaunchModel {
            problem,
            ball,
            options,
            undercut_prior: options.undercut_sigma > 0.0,
            swings,
            modes: BTreeMap::new(),
            rows: Vec::new(),
            n: 0,
            p,
        };
        model.n = model.swings.iter().map(|s| model.rows_of(s)).sum();
        if model.n <= p {
            return Err(CalibrateError::NoData(format!(
                "{} measured launch angles and spins cannot determine {p} parameter(s) (e_T and the unmeasured \
                 undercuts); need at least {}",
                model.n,
                p + 1
            )));
        }
        model.modes = bat_modes(problem, &model.swings)?;
        model.rows = model.row_ranges();
        Ok(model)
    }

    /// Residual rows of a swing: its measured launch angle and spin, and its reported undercut when fitted.
    fn rows_of(&self, s: &LaunchSwing) -> usize {
        let input = &s.observation.input;
        usize::from(input.measured_launch_angle.is_finite())
            + usize::from(input.measured_spin.is_finite())
            + usize::from(self.undercut_prior && input.undercut.is_finite())
    }

    fn row_ranges(&self) -> Vec<Range<usize>> {
        let mut rows = Vec::with_capacity(self.swings.len());
        let mut row = 0;
        for s in &self.swings {
            let k = self.rows_of(s);
            rows.push(row..row + k);
            row += k;
        }
        rows
    }

    fn start(&self) -> DVector<f64> {
        let mut start = vec![0.0; self.p];
        start[0] = self.options.contact.tangential_cor;
        for s in &self.swings {
            if let Some(k) = s.undercut_index {
                let reported = s.observation.input.undercut;
                start[k] = if reported.is_finite() { reported / UNDERCUT_UNIT } else { 0.0 };
            }
        }
        DVector::from_vec(start)
    }

    /// Predicted (launch angle, spin) of one swing at e_T and undercut D (m); None when outside the model's range.
    fn predict_at(&self, s: &LaunchSwing, e_t: f64, undercut: f64) -> Option<Launch> {
        let o = s.observation;
        let pb = &self.problem.bats[o.bat_id.as_str()];
        let contact = TangentialContact { tangential_cor: e_t, ..self.options.contact };
        let collision = CollisionOptions { modes: pb.modes, time_step: self.problem.time_step };
        let oblique = oblique_impact(&pb.bat, &o.input, undercut);
        collide_oblique(&self.modes[o.bat_id.as_str()], self.ball, &oblique, &contact, &collision)
            .ok()
            .map(|r| (r.launch_angle, r.spin))
    }

    fn predict_all(&self, x: &DVector<f64>) -> Vec<Option<Launch>> {
        if !(0.0..=1.0).contains(&x[0]) {
            return vec![None; self.swings.len()];
        }
        self.swings.par_iter().map(|s| self.predict_at(s, x[0], undercut_of(s, x))).collect()
    }

    /// One swing's weighted residuals: launch angle, spin (measured values only), reported undercut.
    fn swing_residuals(&self, s: &LaunchSwing, predicted: Option<Launch>, undercut: f64, out: &mut Vec<f64>) {
        let input = &s.observation.input;
        let options = self.options;
        let (la, spin) = predicted.unwrap_or((f64::NAN, f64::NAN));
        if input.measured_launch_angle.is_finite() {
            out.push((input.measured_launch_angle - la) / options.launch_angle_sigma);
        }
        if input.measured_spin.is_finite() {
            out.push((input.measured_spin - spin) / options.spin_sigma);
        }
        if self.undercut_prior && input.undercut.is_finite() {
            out.push((input.undercut - undercut) / options.undercut_sigma);
        }
    }

    /// Weighted residuals, in swing order.
    fn residuals(&self, predicted: &[Option<Launch>], x: &DVector<f64>) -> DVector<f64> {
        let mut r = Vec::with_capacity(self.n);
        for (s, p) in self.swings.iter().zip(predicted) {
            self.swing_residuals(s, *p, undercut_of(s, x), &mut r);
        }
        DVector::from_vec(r)
    }

    /// The Jacobian is block-sparse: a swing's rows depend on e_T and on its own undercut only. One block per
    /// swing; its e_T column from one shifted evaluation of every swing, its undercut column from one
    /// collision of its own (both forward differences, r = (measured − predicted)/σ so J = −∂r/∂θ).
    fn jacobian(&self, x: &DVector<f64>, r: &DVector<f64>) -> lm::BlockJacobian {
        let step = JACOBIAN_STEP;
        let mut xe = x.clone();
        xe[0] += if x[0] + step <= 1.0 { step } else { -step };
        let h0 = xe[0] - x[0];
        let shifted = self.residuals(&self.predict_all(&xe), &xe);
        let blocks = self
            .swings
            .par_iter()
            .zip(&self.rows)
            .map(|(s, rows)| {
                let global =
                    DMatrix::from_fn(rows.len(), 1, |i, _| -(shifted[rows.start + i] - r[rows.start + i]) / h0);
                let (locals, local) = match s.undercut_index {
                    None => (Vec::new(), DMatrix::zeros(rows.len(), 0)),
                    Some(k) => (vec![k], self.undercut_column(s, rows, x, k, r)),
                };
                lm::JacobianBlock { rows: rows.clone(), locals, global, local }
            })
            .collect();
        lm::BlockJacobian { globals: 1, parameters: self.p, blocks }
    }

    /// A swing's Jacobian column for its own undercut (parameter `k`), from one collision of its own.
    fn undercut_column(
        &self,
        s: &LaunchSwing,
        rows: &Range<usize>,
        x: &DVector<f64>,
        k: usize,
        r: &DVector<f64>,
    ) -> DMatrix<f64> {
        let step = JACOBIAN_STEP;
        let undercut = (x[k] + step) * UNDERCUT_UNIT;
        let mut moved = Vec::with_capacity(rows.len());
        self.swing_residuals(s, self.predict_at(s, x[0], undercut), undercut, &mut moved);
        DMatrix::from_fn(rows.len(), 1, |i, _| {
            let (m, r) = (moved[i], r[rows.start + i]);
            if m.is_finite() {
                -(m - r) / step
            } else {
                0.0
            }
        })
    }

    fn minimize(&self, dense: bool, progress: impl FnMut(Progress)) -> Result<Solved, CalibrateError> {
        let evaluate = |x: &DVector<f64>| {
            let predicted = self.predict_all(x);
            Ok((self.residuals(&predicted, x), predicted))
        };
        let start = self.start();
        let (max_iterations, tolerance) = (self.options.max_iterations, self.options.tolerance);
        Ok(if dense {
            let jacobian =
                |x: &DVector<f64>, r: &DVector<f64>, _: &Vec<Option<Launch>>| Ok(self.jacobian(x, r).to_dense());
            Solved::of(lm::minimize_with(start, evaluate, jacobian, max_iterations, tolerance, progress)?)
        } else {
            let jacobian = |x: &DVector<f64>, r: &DVector<f64>, _: &Vec<Option<Launch>>| Ok(self.jacobian(x, r));
            Solved::of(lm::minimize_with(start, evaluate, jacobian, max_iterations, tolerance, progress)?)
        })
    }

    fn result(&self, minimum: &Solved, sigmas: &[f64], skipped: Vec<String>) -> TangentialFit {
        let (x, before, current) = (&minimum.x, &minimum.predicted_at_start, &minimum.predicted);
        TangentialFit {
            parameters: self.parameters(x, sigmas),
            residuals: self.residual_rows(x, current),
            rms_launch_angle: (self.rms(before, false), self.rms(current, false)),
            rms_spin: (self.rms(before, true), self.rms(current, true)),
            residual_sigma: minimum.residual_variance.sqrt(),
            dof: minimum.dof,
            iterations: minimum.iterations,
            converged: minimum.converged,
            contact: TangentialContact { tangential_cor: x[0], ..self.options.contact },
            skipped,
        }
    }

    fn parameters(&self, x: &DVector<f64>, sigmas: &[f64]) -> Vec<FittedParameter> {
        let mut parameters = vec![FittedParameter {
            name: "tangential_cor".into(),
            unit: "",
            initial: self.options.contact.tangential_cor,
            value: x[0],
            std_error: sigmas[0],
        }];
        for s in &self.swings {
            if let Some(k) = s.undercut_index {
                parameters.push(FittedParameter {
                    name: format!("undercut[{}]", s.observation.swing_id),
                    unit: "m",
                    initial: s.observation.input.undercut,
                    value: x[k] * UNDERCUT_UNIT,
                    std_error: sigmas[k] * UNDERCUT_UNIT,
                });
            }
        }
        parameters
    }

    /// RMS of the measured-minus-predicted spins (`spin`) or launch angles over the swings that have both.
    fn rms(&self, predicted: &[Option<Launch>], spin: bool) -> f64 {
        let values: Vec<f64> = self
            .swings
            .iter()
            .zip(predicted)
            .map(|(s, p)| {
                let input = &s.observation.input;
                let (la, w) = p.unwrap_or((f64::NAN, f64::NAN));
                if spin {
                    input.measured_spin - w
                } else {
                    input.measured_launch_angle - la
                }
            })
            .filter(|v| v.is_finite())
            .collect();
        (values.iter().map(|v| v * v).sum::<f64>() / values.len().max(1) as f64).sqrt()
    }

    fn residual_rows(&self, x: &DVector<f64>, current: &[Option<Launch>]) -> Vec<LaunchResidual> {
        self.swings
            .iter()
            .zip(current)
            .map(|(s, p)| {
                let input = &s.observation.input;
                let (la, spin) = p.unwrap_or((f64::NAN, f64::NAN));
                LaunchResidual {
                    swing_id: s.observation.swing_id,
                    bat_id: s.observation.bat_id.clone(),
                    undercut: undercut_of(s, x),
                    undercut_fitted: s.observation.input.undercut.is_nan(),
                    launch_angle: input.measured_launch_angle - la,
                    spin: input.measured_spin - spin,
                }
            })
            .collect()
    }
}

/// The modes of every bat a swing uses, computed once per bat.
fn bat_modes<'a>(
    problem: &'a Problem,
    swings: &[LaunchSwing<'a>],
) -> Result<BTreeMap<&'a str, ModeSet>, CalibrateError> {
    let mut modes: BTreeMap<&str, ModeSet> = BTreeMap::new();
    for s in swings {
        let id = s.observation.bat_id.as_str();
        if !modes.contains_key(id) {
            let pb = &problem.bats[id];
            let set = ModeSet::compute(&pb.bat, pb.modes)
                .map_err(|source| CalibrateError::Physics { context: format!("bat '{id}'"), source })?;
            modes.insert(id, set);
        }
    }
    Ok(modes)
}

/// A short text report of an e_T fit: the parameter, the residuals before and after.
pub fn report(fit: &TangentialFit) -> String {
    let mut out = String::new();
    if let Some(e) = fit.parameter("tangential_cor") {
        out.push_str(&format!(
            "tangential COR e_T = {:.4} ± {:.4} (start {:.3}; {} swings, {} undercuts fitted, dof {}, {} iterations{})\n",
            e.value,
            e.std_error,
            e.initial,
            fit.residuals.len(),
            fit.parameters.len() - 1,
            fit.dof,
            fit.iterations,
            if fit.converged { "" } else { ", NOT converged" }
        ));
    }
    out.push_str(&format!(
        "launch angle RMS residual {:.2}° → {:.2}°, spin RMS residual {:.0} → {:.0} rpm, weighted s = {:.2}\n",
        fit.rms_launch_angle.0.to_degrees(),
        fit.rms_launch_angle.1.to_degrees(),
        rad_per_s_to_rpm(fit.rms_spin.0),
        rad_per_s_to_rpm(fit.rms_spin.1),
        fit.residual_sigma
    ));
    for s in &fit.skipped {
        out.push_str(&format!("skipped: {s}\n"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibrate::RecordedInputs;
    use crate::rig::{LaunchConditions, RigConfig, SessionGenerator};
    use sweetspot_model::time::RosTime;
    use sweetspot_msgs::builtin_interfaces::msg::Time;

    /// A small noisy session of the rig (true e_T 0.30), as the fit reads it from a bag.
    fn session(swings: usize, report_undercut: bool) -> Problem {
        let launch = LaunchConditions {
            contact: TangentialContact { tangential_cor: 0.30, ..TangentialContact::default() },
            report_undercut,
            ..LaunchConditions::default()
        };
        let config = RigConfig {
            bats: vec!["r161".into(), "r161-corked".into()],
            seed: 11,
            options: CollisionOptions { modes: 18, ..CollisionOptions::default() },
            launch: Some(launch),
            ..RigConfig::default()
        };
        let mut rig = SessionGenerator::new(config).unwrap().with_block(4);
        let mut t = 1_700_000_000_000_000_000u64;
        let mut inputs = RecordedInputs {
            bats: rig.bat_params(Time::from_unix_ns(t)).into_iter().map(|b| (t, b)).collect(),
            balls: vec![(t, rig.ball_params(Time::from_unix_ns(t)))],
            ..RecordedInputs::default()
        };
        for _ in 0..swings {
            t += 1_000_000;
            let swing = rig.next_swing().unwrap();
            inputs.swings.push((t, rig.swing_message(&swing, Time::from_unix_ns(t))));
        }
        problem_from_inputs(&inputs, None).unwrap()
    }

    /// The block (Schur-complement) solver takes the dense solver's steps: same iterations, same e_T and
    /// undercuts, same standard errors, with reported undercuts held by their prior and with none reported.
    #[test]
    fn the_block_solver_agrees_with_the_dense_one() {
        for report_undercut in [true, false] {
            let problem = session(24, report_undercut);
            let options = TangentialOptions { contact: problem.contact, ..TangentialOptions::default() };
            let dense = fit_with(&problem, &problem.ball, &options, true, |_| {}).unwrap();
            let block = fit_with(&problem, &problem.ball, &options, false, |_| {}).unwrap();
            assert_eq!(dense.iterations, block.iterations);
            assert_eq!(dense.converged, block.converged);
            assert_eq!(dense.parameters.len(), block.parameters.len());
            assert!(dense.parameters.len() > 20, "the undercuts are fitted too");
            for (d, b) in dense.parameters.iter().zip(&block.parameters) {
                assert_eq!(d.name, b.name);
                let scale = d.value.abs().max(d.std_error).max(1e-6);
                assert!((d.value - b.value).abs() < 1e-9 * scale, "{}: {} vs {}", d.name, d.value, b.value);
                assert!(
                    (d.std_error - b.std_error).abs() < 1e-7 * d.std_error,
                    "{}: σ {} vs {}",
                    d.name,
                    d.std_error,
                    b.std_error
                );
            }
        }
    }

    /// `max_iterations` is honoured: 0 runs none (the start comes back, not converged), 1 runs one.
    #[test]
    fn the_iteration_limit_is_honoured() {
        let problem = session(12, true);
        for limit in [0, 1] {
            let options =
                TangentialOptions { contact: problem.contact, max_iterations: limit, ..TangentialOptions::default() };
            let mut evaluations = 0;
            let fit = fit_tangential_with_progress(&problem, &problem.ball, &options, |p| evaluations = p.evaluations)
                .unwrap();
            assert_eq!(fit.iterations, limit);
            assert!(!fit.converged);
            if limit == 0 {
                assert_eq!(fit.parameters[0].value, problem.contact.tangential_cor);
                // One evaluation of the residuals and one Jacobian for the uncertainties at the start.
                assert_eq!(evaluations, 2);
            }
        }
    }
}
