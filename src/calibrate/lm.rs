//! The Levenberg–Marquardt minimiser both fits share: damped Gauss–Newton steps on Σ r², with the caller's
//! residuals and Jacobian, and the linearised covariance at the optimum.
//!
//! Conventions: r = measured − predicted (weighted or not), J = ∂predicted/∂θ, so the Gauss–Newton step is
//! δ = (JᵀJ)⁻¹ Jᵀ r. The damping is Marquardt's, λ·diag(JᵀJ) (each diagonal floored at 1e-12), starting at
//! λ = 1e-3, × 10 after a rejected step (at most 12 per iteration), ÷ 10 after an accepted one (floored at
//! 1e-9). A step is accepted when it does not raise the cost; a cost with any non-finite residual is +∞
//! (the model has no prediction there). No downhill step at any damping means the minimum has been reached
//! to the model's precision, which counts as converged.

use nalgebra::{DMatrix, DVector};

use super::CalibrateError;

/// Where a minimisation ended.
pub struct Minimum<P> {
    /// The parameters.
    pub x: DVector<f64>,
    /// Residuals at `x`.
    pub residuals: DVector<f64>,
    /// The predictions at `x` (what the caller's evaluation returned with the residuals).
    pub predicted: P,
    /// The predictions at the start.
    pub predicted_at_start: P,
    /// Jacobian at `x` when converged, else at the last iterate's start.
    pub jacobian: DMatrix<f64>,
    /// Iterations done.
    pub iterations: usize,
    /// Whether a step below the tolerance (or no downhill step) ended it.
    pub converged: bool,
}

impl<P> Minimum<P> {
    /// Degrees of freedom n − p (the caller checked n > p).
    pub fn dof(&self) -> usize {
        self.residuals.len() - self.x.len()
    }

    /// s² = Σr²/(n − p), the residual variance.
    pub fn residual_variance(&self) -> f64 {
        self.residuals.norm_squared() / self.dof() as f64
    }

    /// Standard uncertainty of each parameter, √(s²·(JᵀJ)⁻¹)_kk; `None` when JᵀJ is singular (the data do not
    /// constrain every parameter).
    pub fn standard_errors(&self) -> Option<Vec<f64>> {
        let s2 = self.residual_variance();
        let inverse = (self.jacobian.transpose() * &self.jacobian).try_inverse()?;
        Some((0..self.x.len()).map(|k| (s2 * inverse[(k, k)]).max(0.0).sqrt()).collect())
    }
}

/// Σr², or +∞ when a residual is not finite.
fn cost(r: &DVector<f64>) -> f64 {
    if r.iter().all(|v| v.is_finite()) {
        r.norm_squared()
    } else {
        f64::INFINITY
    }
}

/// Minimises Σr² from `start`. `evaluate(x)` gives the residuals at x and the predictions behind them;
/// `jacobian(x, r, predicted)` gives J at x (r and predicted are `evaluate(x)`'s). Stops after
/// `max_iterations` or when every component of an accepted step is below `tolerance`.
pub fn minimize<P: Clone>(
    start: DVector<f64>,
    evaluate: impl Fn(&DVector<f64>) -> Result<(DVector<f64>, P), CalibrateError>,
    jacobian: impl Fn(&DVector<f64>, &DVector<f64>, &P) -> Result<DMatrix<f64>, CalibrateError>,
    max_iterations: usize,
    tolerance: f64,
) -> Result<Minimum<P>, CalibrateError> {
    let p = start.len();
    let mut x = start;
    let (mut r, mut predicted) = evaluate(&x)?;
    if !cost(&r).is_finite() {
        return Err(CalibrateError::NoData("the start parameters give no prediction for some swings".into()));
    }
    let predicted_at_start = predicted.clone();
    let mut lambda = 1e-3;
    let (mut iterations, mut converged) = (0, false);
    let mut j = DMatrix::zeros(r.len(), p);
    while iterations < max_iterations {
        iterations += 1;
        j = jacobian(&x, &r, &predicted)?;
        let jtj = j.transpose() * &j;
        let jtr = j.transpose() * &r;
        let mut accepted = false;
        for _ in 0..12 {
            let mut a = jtj.clone();
            for k in 0..p {
                a[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(delta) = a.cholesky().map(|c| c.solve(&jtr)) else {
                lambda *= 10.0;
                continue;
            };
            let trial = &x + &delta;
            let (r_trial, predicted_trial) = evaluate(&trial)?;
            if cost(&r_trial) <= cost(&r) {
                converged = delta.iter().all(|d| d.abs() < tolerance);
                x = trial;
                r = r_trial;
                predicted = predicted_trial;
                lambda = (lambda / 10.0).max(1e-9);
                accepted = true;
                break;
            }
            lambda *= 10.0;
        }
        if !accepted {
            converged = true;
        }
        if converged {
            break;
        }
    }
    if converged {
        j = jacobian(&x, &r, &predicted)?;
    }
    Ok(Minimum { x, residuals: r, predicted, predicted_at_start, jacobian: j, iterations, converged })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fitting y = a·exp(b·t) to exact data from a = 2, b = −0.5 finds them, with standard errors that vanish
    /// with the residuals.
    #[test]
    fn an_exponential_is_recovered_from_exact_data() {
        let t: Vec<f64> = (0..20).map(|i| i as f64 * 0.25).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * (-0.5 * t).exp()).collect();
        let evaluate = |x: &DVector<f64>| {
            let predicted: Vec<f64> = t.iter().map(|t| x[0] * (x[1] * t).exp()).collect();
            Ok((DVector::from_iterator(t.len(), y.iter().zip(&predicted).map(|(y, p)| y - p)), predicted))
        };
        let jacobian = |x: &DVector<f64>, _: &DVector<f64>, _: &Vec<f64>| {
            Ok(DMatrix::from_fn(t.len(), 2, |i, k| {
                if k == 0 {
                    (x[1] * t[i]).exp()
                } else {
                    x[0] * t[i] * (x[1] * t[i]).exp()
                }
            }))
        };
        let m = minimize(DVector::from_vec(vec![1.0, 0.0]), evaluate, jacobian, 100, 1e-12).unwrap();
        assert!(m.converged);
        assert!((m.x[0] - 2.0).abs() < 1e-9 && (m.x[1] + 0.5).abs() < 1e-9, "{}", m.x);
        assert!(m.standard_errors().unwrap().iter().all(|s| *s < 1e-6));
    }

    /// For a straight line y = a + b·t the least-squares solution and its standard errors have a closed form:
    /// b = Sxy/Sxx, a = ȳ − b·t̄, σ_b = s/√Sxx, σ_a = s·√(1/n + t̄²/Sxx), s² = Σr²/(n − 2).
    #[test]
    fn a_line_matches_the_closed_form_fit_and_its_uncertainties() {
        let t: Vec<f64> = (0..12).map(|i| i as f64).collect();
        let wobble = [0.3, -0.2, 0.1, 0.4, -0.5, 0.2, -0.1, 0.0, 0.3, -0.4, 0.2, -0.1];
        let y: Vec<f64> = t.iter().zip(wobble).map(|(t, w)| 1.5 + 0.8 * t + w).collect();
        let n = t.len() as f64;
        let (tm, ym) = (t.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
        let sxx: f64 = t.iter().map(|t| (t - tm).powi(2)).sum();
        let sxy: f64 = t.iter().zip(&y).map(|(t, y)| (t - tm) * (y - ym)).sum();
        let b = sxy / sxx;
        let a = ym - b * tm;
        let ssr: f64 = t.iter().zip(&y).map(|(t, y)| (y - a - b * t).powi(2)).sum();
        let s = (ssr / (n - 2.0)).sqrt();
        let evaluate = |x: &DVector<f64>| {
            Ok((DVector::from_iterator(t.len(), t.iter().zip(&y).map(|(t, y)| y - x[0] - x[1] * t)), ()))
        };
        let jacobian = |_: &DVector<f64>, _: &DVector<f64>, _: &()| {
            Ok(DMatrix::from_fn(t.len(), 2, |i, k| if k == 0 { 1.0 } else { t[i] }))
        };
        let m = minimize(DVector::from_vec(vec![0.0, 0.0]), evaluate, jacobian, 50, 1e-12).unwrap();
        assert!((m.x[0] - a).abs() < 1e-9 && (m.x[1] - b).abs() < 1e-9, "{} vs ({a}, {b})", m.x);
        assert_eq!(m.dof(), 10);
        let errors = m.standard_errors().unwrap();
        assert!((errors[0] - s * (1.0 / n + tm * tm / sxx).sqrt()).abs() < 1e-9, "{errors:?}");
        assert!((errors[1] - s / sxx.sqrt()).abs() < 1e-9, "{errors:?}");
    }

    #[test]
    fn a_start_without_a_prediction_is_refused() {
        let evaluate = |_: &DVector<f64>| Ok((DVector::from_vec(vec![f64::NAN, 1.0, 2.0]), ()));
        let jacobian = |_: &DVector<f64>, _: &DVector<f64>, _: &()| Ok(DMatrix::zeros(3, 1));
        let e = minimize(DVector::from_vec(vec![1.0]), evaluate, jacobian, 5, 1e-6).err().unwrap();
        assert!(matches!(e, CalibrateError::NoData(_)), "{e}");
    }
}
