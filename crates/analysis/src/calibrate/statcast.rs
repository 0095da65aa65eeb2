//! The game ball fitted to real games: the ball's e0(v) law ([`Ball::cor_at`]) fitted to the upper envelope of
//! Statcast's collision efficiency q = (EV − bat)/(plate pitch + bat) (issue 32 §2).
//!
//! Each target is one bin of real balls in play (`validation/statcast_q.csv`): its median bat speed 6 in from
//! the head, its median pitch speed at the plate, and the 99th percentile of q (the middle of the suite's
//! [97th, 99.8th] band: the best-struck balls reach the true maximum; measurement noise puts a few above it).
//! The model's number is [`statcast_q_max`]: the R161 swung about its knob at the bin's bat speed, struck at its
//! point of largest exit speed. The two parameters — e0 at [`MLB_COR_SPEED`] (MLB's specification speed, so
//! the fitted `cor` is directly comparable with the specified 0.514–0.578) and the exponent p — are found by
//! [`super::lm`] with a forward-difference Jacobian; their covariance is s²·(JᵀJ)⁻¹, as in the other fits.
//! Fitting on one half of a season and checking on the other is the calibration the validation suite expects.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

use super::{lm, CalibrateError, FitOptions, FittedParameter};
use sweetspot_physics::ball::{MAX_COR_SPEED_EXPONENT, MLB_COR_SPEED};
use sweetspot_physics::batter::ReferenceSwing;
use sweetspot_physics::metrics::sweet_spots;
use sweetspot_physics::units::INCH;
use sweetspot_physics::{Ball, CollisionOptions, Impact, ModeSet, PhysicsError};

/// Where Statcast measures bat speed: 6 in from the head, m.
const SIX_INCHES: f64 = 6.0 * INCH;
/// Scale of the exponent in the minimiser's parameter vector (p = x₁·EXPONENT_SCALE).
const EXPONENT_SCALE: f64 = 0.1;

/// Statcast's q = (v_exit − v_bat)/(v_pitch + v_bat) at the point of largest exit speed of `modes`' bat swung
/// about its knob at `bat_speed` m/s 6 in from the head against a pitch of `pitch_speed` m/s, and that point's
/// distance from the barrel end, m.
pub fn statcast_q_max(
    modes: &ModeSet,
    ball: &Ball,
    bat_speed: f64,
    pitch_speed: f64,
    options: &CollisionOptions,
) -> Result<(f64, f64), PhysicsError> {
    let z6 = modes.length() - SIX_INCHES;
    let swing = ReferenceSwing::from_speed_at(modes.mass_properties(), bat_speed, z6, 0.0)?;
    let template = Impact {
        ball_speed: pitch_speed,
        bat_cm_speed: swing.bat_cm_speed,
        bat_angular_speed: swing.bat_angular_speed,
        impact_z: z6,
    };
    let spots = sweet_spots(modes, ball, &template, options)?;
    Ok(((spots.max_exit_speed - bat_speed) / (pitch_speed + bat_speed), modes.length() - spots.max_exit_speed_z))
}

/// One bin of real balls the law is fitted to.
#[derive(Debug, Clone, PartialEq)]
pub struct QTarget {
    /// What the bin is (for reports).
    pub label: String,
    /// Median bat speed 6 in from the head, m/s.
    pub bat_speed: f64,
    /// Median pitch speed at the plate, m/s.
    pub pitch_speed: f64,
    /// The q the model's largest q is fitted to (the bin's 99th percentile).
    pub q: f64,
}

/// The fitted law.
#[derive(Debug, Clone, PartialEq)]
pub struct GameBallFit {
    /// e0 at [`MLB_COR_SPEED`] and the exponent p, with their 1σ.
    pub parameters: Vec<FittedParameter>,
    /// Correlation of the two parameters' errors.
    pub correlation: f64,
    /// Covariance of (cor, exponent).
    pub covariance: [[f64; 2]; 2],
    /// The model's largest q per target at the start and at the end.
    pub q_before: Vec<f64>,
    /// At the end.
    pub q_after: Vec<f64>,
    /// RMS q residual before and after.
    pub rms_before: f64,
    /// After.
    pub rms: f64,
    /// Degrees of freedom n − 2.
    pub dof: usize,
    /// Iterations done.
    pub iterations: usize,
    /// Whether the step tolerance was met.
    pub converged: bool,
    /// The ball with the fitted law (e0 = `cor` at [`MLB_COR_SPEED`]).
    pub ball: Ball,
}

impl GameBallFit {
    /// e0 of the fitted law at normal approach speed `speed` (m/s) and its 1σ (propagated through the
    /// covariance of the two parameters).
    pub fn cor_at(&self, speed: f64) -> (f64, f64) {
        let e = self.ball.cor_at(speed);
        // e = cor·(v/v_ref)^(−p): ∂e/∂cor = e/cor, ∂e/∂p = −e·ln(v/v_ref).
        let g = [e / self.ball.cor, -e * (speed / self.ball.cor_reference_speed).ln()];
        let c = &self.covariance;
        let var = g[0] * g[0] * c[0][0] + 2.0 * g[0] * g[1] * c[0][1] + g[1] * g[1] * c[1][1];
        (e, var.max(0.0).sqrt())
    }
}

/// Fits e0(v) of `start` (mass, radius and force law kept) to `targets` on `modes`' bat.
pub fn fit_game_ball(
    modes: &ModeSet,
    start: Ball,
    targets: &[QTarget],
    collision: &CollisionOptions,
    options: &FitOptions,
) -> Result<GameBallFit, CalibrateError> {
    let n = targets.len();
    if n <= 2 {
        return Err(CalibrateError::NoData(format!("{n} bins cannot determine e0 and its exponent; need 3")));
    }
    let model = GameBallModel { modes, start, targets, collision, cor0: start.cor_at(MLB_COR_SPEED) };
    let evaluate = |x: &DVector<f64>| {
        let p = model.predict(x)?;
        Ok((model.residuals(&p), p))
    };
    let jacobian = |x: &DVector<f64>, _: &DVector<f64>, base: &Vec<f64>| model.jacobian(x, base);
    let start_x = DVector::from_vec(vec![1.0, start.cor_speed_exponent / EXPONENT_SCALE]);
    let minimum = lm::minimize(start_x, evaluate, jacobian, options.max_iterations, options.tolerance)?;
    let covariance = model.covariance(&minimum)?;
    let x = &minimum.x;
    let rms = |p: &[f64]| (model.residuals(p).norm_squared() / n as f64).sqrt();
    Ok(GameBallFit {
        correlation: covariance[0][1] / (covariance[0][0] * covariance[1][1]).sqrt(),
        covariance,
        parameters: model.parameters(x, &covariance),
        rms_before: rms(&minimum.predicted_at_start),
        rms: rms(&minimum.predicted),
        q_before: minimum.predicted_at_start.clone(),
        q_after: minimum.predicted.clone(),
        dof: minimum.dof(),
        iterations: minimum.iterations,
        converged: minimum.converged,
        ball: model.ball_of(x),
    })
}

/// The game-ball fit's model: parameters x = (e0/cor0, p/[`EXPONENT_SCALE`]) at [`MLB_COR_SPEED`],
/// predictions each bin's q.
struct GameBallModel<'a> {
    modes: &'a ModeSet,
    start: Ball,
    targets: &'a [QTarget],
    collision: &'a CollisionOptions,
    /// e0 of the start ball at [`MLB_COR_SPEED`].
    cor0: f64,
}

impl GameBallModel<'_> {
    fn ball_of(&self, x: &DVector<f64>) -> Ball {
        Ball {
            cor: x[0] * self.cor0,
            cor_speed_exponent: x[1] * EXPONENT_SCALE,
            cor_reference_speed: MLB_COR_SPEED,
            ..self.start
        }
    }

    fn predict(&self, x: &DVector<f64>) -> Result<Vec<f64>, CalibrateError> {
        let ball = self.ball_of(x);
        if !(ball.cor > 0.05 && ball.cor <= 1.0 && (0.0..=MAX_COR_SPEED_EXPONENT).contains(&ball.cor_speed_exponent)) {
            return Ok(vec![f64::NAN; self.targets.len()]);
        }
        self.targets
            .par_iter()
            .map(|t| {
                statcast_q_max(self.modes, &ball, t.bat_speed, t.pitch_speed, self.collision)
                    .map(|(q, _)| q)
                    .map_err(|source| CalibrateError::Physics { context: format!("bin {}", t.label), source })
            })
            .collect()
    }

    fn residuals(&self, p: &[f64]) -> DVector<f64> {
        DVector::from_iterator(self.targets.len(), self.targets.iter().zip(p).map(|(t, q)| t.q - q))
    }

    /// Forward differences from the predictions `base` at `x`.
    fn jacobian(&self, x: &DVector<f64>, base: &[f64]) -> Result<DMatrix<f64>, CalibrateError> {
        let step = 1e-4;
        let n = self.targets.len();
        let mut j = DMatrix::zeros(n, 2);
        for k in 0..2 {
            let mut xk = x.clone();
            xk[k] += step;
            let shifted = self.predict(&xk)?;
            for i in 0..n {
                let d = (shifted[i] - base[i]) / step;
                j[(i, k)] = if d.is_finite() { d } else { 0.0 };
            }
        }
        Ok(j)
    }

    /// Cov of (cor, exponent) in their own units: s² (JᵀJ)⁻¹ scaled back from the minimiser's parameters.
    fn covariance(&self, minimum: &lm::Minimum<Vec<f64>>) -> Result<[[f64; 2]; 2], CalibrateError> {
        let s2 = minimum.residual_variance();
        let jtj = minimum.jacobian.transpose() * &minimum.jacobian;
        let inv = jtj.try_inverse().ok_or_else(|| {
            CalibrateError::Degenerate("JᵀJ is singular; the bins do not constrain both e0 and its exponent".into())
        })?;
        let scale = [self.cor0, EXPONENT_SCALE];
        let mut covariance = [[0.0; 2]; 2];
        for (a, row) in covariance.iter_mut().enumerate() {
            for (b, c) in row.iter_mut().enumerate() {
                *c = s2 * inv[(a, b)] * scale[a] * scale[b];
            }
        }
        Ok(covariance)
    }

    fn parameters(&self, x: &DVector<f64>, covariance: &[[f64; 2]; 2]) -> Vec<FittedParameter> {
        vec![
            FittedParameter {
                name: "cor".into(),
                unit: "",
                initial: self.cor0,
                value: x[0] * self.cor0,
                std_error: covariance[0][0].sqrt(),
            },
            FittedParameter {
                name: "cor_speed_exponent".into(),
                unit: "",
                initial: self.start.cor_speed_exponent,
                value: x[1] * EXPONENT_SCALE,
                std_error: covariance[1][1].sqrt(),
            },
        ]
    }
}
