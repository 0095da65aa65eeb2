//! `calibrate --fit-cor-exponent`: the ball's COR as a function of impact speed, e0(v) =
//! cor·(v/v_ref)^(−p) ([`Ball::cor_at`]), fitted to the measured exit speeds of sessions at several pitch
//! speeds.
//!
//! Two parameters: e0 at the reference speed v_ref and the exponent p. v_ref is held fixed — the ball's own when
//! its BallParams already carries a law, else the mean head-on approach speed of the measured swings (ball
//! speed plus the bat's speed at the impact point), where e0 and the exponent are least correlated. Each swing
//! is predicted as the node answers it (its collision takes e0 at its own normal approach speed), the sum
//! of squared exit-speed residuals is minimised by [`super::lm`] (forward-difference Jacobian), and the
//! uncertainties are the linearised s²·(JᵀJ)⁻¹ of the other fits. An exponent needs swings that differ in
//! approach speed: sessions spanning less than [`MIN_SPEED_SPAN`] are refused rather than fitted to noise.

use std::collections::BTreeMap;

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use super::{lm, tangential, CalibrateError, FitOptions, FittedParameter, Problem};
use sweetspot_physics::ball::MAX_COR_SPEED_EXPONENT;
use sweetspot_physics::{rigid, Ball, CollisionOptions, ModeSet};

/// Smallest spread of head-on approach speeds (max − min) an exponent is fitted from, m/s.
pub const MIN_SPEED_SPAN: f64 = 5.0;
/// Scale of the exponent in the minimiser's parameter vector (p = x₁·EXPONENT_SCALE).
const EXPONENT_SCALE: f64 = 0.1;

/// The fitted speed law.
#[derive(Debug, Clone, PartialEq)]
pub struct CorLawFit {
    /// e0 at [`CorLawFit::reference_speed`] and the exponent p, with their 1σ.
    pub parameters: Vec<FittedParameter>,
    /// The speed at which e0 = `cor`, m/s (held fixed).
    pub reference_speed: f64,
    /// Lowest and highest head-on approach speed of the swings fitted, m/s.
    pub speed_range: (f64, f64),
    /// RMS exit-speed residual before and after, m/s.
    pub rms_before: f64,
    /// After.
    pub rms: f64,
    /// s = √(Σr²/(n − 2)), m/s.
    pub residual_sigma: f64,
    /// Degrees of freedom n − 2.
    pub dof: usize,
    /// Iterations done.
    pub iterations: usize,
    /// Whether the step tolerance was met.
    pub converged: bool,
    /// The ball with the fitted law.
    pub ball: Ball,
}

/// Fits e0(v) to `problem`'s measured exit speeds (see the module docs); `options.fit_youngs` is ignored.
pub fn fit_cor_law(problem: &Problem, options: &FitOptions) -> Result<CorLawFit, CalibrateError> {
    let n = problem.observations.len();
    if n <= 2 {
        return Err(CalibrateError::NoData(format!(
            "{n} measured swings cannot determine e0 and its exponent; need 3"
        )));
    }
    let modes = bat_mode_sets(problem)?;
    let speeds = approach_speeds(problem, &modes)?;
    let (low, high) = speed_span(&speeds)?;
    let start_ball = problem.ball;
    let reference_speed = if start_ball.cor_speed_exponent != 0.0 {
        start_ball.cor_reference_speed
    } else {
        (speeds.iter().sum::<f64>() / n as f64 * 10.0).round() / 10.0
    };
    let model = CorLawModel { problem, modes, start_ball, reference_speed, cor0: start_ball.cor_at(reference_speed) };
    let evaluate = |x: &DVector<f64>| {
        let predicted = model.predict(x)?;
        Ok((model.residuals(&predicted), predicted))
    };
    let jacobian = |x: &DVector<f64>, r: &DVector<f64>, _: &Vec<Option<f64>>| model.jacobian(x, r);
    let start = DVector::from_vec(vec![1.0, start_ball.cor_speed_exponent / EXPONENT_SCALE]);
    let minimum = lm::minimize(start.clone(), evaluate, jacobian, options.max_iterations, options.tolerance)?;
    let errors = minimum.standard_errors().ok_or_else(|| {
        CalibrateError::Degenerate("JᵀJ is singular; the swings do not constrain both e0 and its exponent".into())
    })?;
    let x = &minimum.x;
    let rms = |p: &[Option<f64>]| (model.residuals(p).norm_squared() / n as f64).sqrt();
    Ok(CorLawFit {
        parameters: model.parameters(x, &errors),
        reference_speed,
        speed_range: (low, high),
        rms_before: rms(&minimum.predicted_at_start),
        rms: rms(&minimum.predicted),
        residual_sigma: minimum.residual_variance().sqrt(),
        dof: minimum.dof(),
        iterations: minimum.iterations,
        converged: minimum.converged,
        ball: model.ball_of(x),
    })
}

fn bat_mode_sets(problem: &Problem) -> Result<BTreeMap<&str, ModeSet>, CalibrateError> {
    let mut modes: BTreeMap<&str, ModeSet> = BTreeMap::new();
    for (id, pb) in &problem.bats {
        let set = ModeSet::compute(&pb.bat, pb.modes)
            .map_err(|source| CalibrateError::Physics { context: format!("bat '{id}'"), source })?;
        modes.insert(id.as_str(), set);
    }
    Ok(modes)
}

/// Each swing's head-on approach speed (ball plus bat at the impact point), m/s.
fn approach_speeds(problem: &Problem, modes: &BTreeMap<&str, ModeSet>) -> Result<Vec<f64>, CalibrateError> {
    let mut speeds = Vec::with_capacity(problem.observations.len());
    for o in &problem.observations {
        let set = modes.get(o.bat_id.as_str()).ok_or_else(|| {
            CalibrateError::NoData(format!(
                "swing {} refers to bat '{}', which the session lacks",
                o.swing_id, o.bat_id
            ))
        })?;
        speeds.push(o.impact.ball_speed + rigid::bat_speed_at(&set.mass_properties(), &o.impact));
    }
    Ok(speeds)
}

/// The lowest and highest approach speed; an error when they are too close to separate e0 from its exponent.
fn speed_span(speeds: &[f64]) -> Result<(f64, f64), CalibrateError> {
    let (low, high) = speeds.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
    let span = high - low;
    if span.is_nan() || span < MIN_SPEED_SPAN {
        return Err(CalibrateError::NoData(format!(
            "a COR exponent needs swings at several approach speeds: these span {:.2} m/s ({low:.2}–{high:.2}), \
             at least {MIN_SPEED_SPAN} m/s are needed (record sessions at different pitch speeds)",
            high - low
        )));
    }
    Ok((low, high))
}

/// The speed law's model: parameters x = (e0/cor0, p/[`EXPONENT_SCALE`]), predictions the exit speeds.
struct CorLawModel<'a> {
    problem: &'a Problem,
    modes: BTreeMap<&'a str, ModeSet>,
    start_ball: Ball,
    reference_speed: f64,
    /// e0 of the start ball at the reference speed.
    cor0: f64,
}

impl CorLawModel<'_> {
    fn ball_of(&self, x: &DVector<f64>) -> Ball {
        Ball {
            cor: x[0] * self.cor0,
            cor_speed_exponent: x[1] * EXPONENT_SCALE,
            cor_reference_speed: self.reference_speed,
            ..self.start_ball
        }
    }

    fn predict(&self, x: &DVector<f64>) -> Result<Vec<Option<f64>>, CalibrateError> {
        let problem = self.problem;
        let ball = self.ball_of(x);
        if !(ball.cor > 0.05 && ball.cor <= 1.0 && (0.0..=MAX_COR_SPEED_EXPONENT).contains(&ball.cor_speed_exponent)) {
            return Ok(vec![None; problem.observations.len()]);
        }
        problem
            .observations
            .par_iter()
            .map(|o| {
                let pb = &problem.bats[&o.bat_id];
                let options = CollisionOptions { modes: pb.modes, time_step: problem.time_step };
                let modes = &self.modes[o.bat_id.as_str()];
                tangential::exit_speed(modes, &pb.bat, &ball, &problem.contact, &o.input, &options)
                    .map(Some)
                    .map_err(|source| CalibrateError::Physics { context: format!("swing {}", o.swing_id), source })
            })
            .collect()
    }

    fn residuals(&self, predicted: &[Option<f64>]) -> DVector<f64> {
        let observations = &self.problem.observations;
        DVector::from_iterator(
            observations.len(),
            observations.iter().zip(predicted).map(|(o, p)| o.measured_exit_speed - p.unwrap_or(f64::NAN)),
        )
    }

    /// Forward differences of the predictions.
    fn jacobian(&self, x: &DVector<f64>, r: &DVector<f64>) -> Result<DMatrix<f64>, CalibrateError> {
        let step = 1e-4;
        let observations = &self.problem.observations;
        let n = observations.len();
        let mut j = DMatrix::zeros(n, 2);
        for k in 0..2 {
            let mut xk = x.clone();
            xk[k] += step;
            let shifted = self.predict(&xk)?;
            for i in 0..n {
                let base = observations[i].measured_exit_speed - r[i];
                j[(i, k)] = shifted[i].map(|m| (m - base) / step).unwrap_or(0.0);
            }
        }
        Ok(j)
    }

    fn parameters(&self, x: &DVector<f64>, errors: &[f64]) -> Vec<FittedParameter> {
        let cor0 = self.cor0;
        vec![
            FittedParameter {
                name: "cor".into(),
                unit: "",
                initial: cor0,
                value: x[0] * cor0,
                std_error: errors[0] * cor0,
            },
            FittedParameter {
                name: "cor_speed_exponent".into(),
                unit: "",
                initial: self.start_ball.cor_speed_exponent,
                value: x[1] * EXPONENT_SCALE,
                std_error: errors[1] * EXPONENT_SCALE,
            },
        ]
    }
}

/// The human-readable report of a speed-law fit.
pub fn report(fit: &CorLawFit) -> String {
    use crate::report::table::{num, Table};
    let mut out = format!(
        "COR against impact speed: e0(v) = cor·(v / {} m/s)^(−cor_speed_exponent), swings at {}–{} m/s approach; \
         {} iteration(s){}\n\n",
        num(fit.reference_speed, 4),
        num(fit.speed_range.0, 4),
        num(fit.speed_range.1, 4),
        fit.iterations,
        if fit.converged { ", converged" } else { ", NOT converged (raise --max-iterations)" }
    );
    let mut t = Table::new(["parameter", "start", "fitted", "± 1σ", "unit"]);
    for p in &fit.parameters {
        t.row([p.name.clone(), num(p.initial, 5), num(p.value, 5), num(p.std_error, 2), p.unit.to_string()]);
    }
    out.push_str(&t.render());
    out.push_str(&format!(
        "\nresiduals: RMS {} m/s before, {} m/s after; s = {} m/s on {} degrees of freedom\n",
        num(fit.rms_before, 3),
        num(fit.rms, 3),
        num(fit.residual_sigma, 3),
        fit.dof
    ));
    out
}
