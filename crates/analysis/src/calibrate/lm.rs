//! The Levenberg–Marquardt minimiser both fits share: damped Gauss–Newton steps on Σ r², with the caller's
//! residuals and Jacobian, and the linearised covariance at the optimum.
//!
//! Conventions: r = measured − predicted (weighted or not), J = ∂predicted/∂θ, so the Gauss–Newton step is
//! δ = (JᵀJ)⁻¹ Jᵀ r. The damping is Marquardt's, λ·diag(JᵀJ) (each diagonal floored at 1e-12), starting at
//! λ = 1e-3, × 10 after a rejected step (at most 12 per iteration), ÷ 10 after an accepted one (floored at
//! 1e-9). A step is accepted when it does not raise the cost; a cost with any non-finite residual is +∞
//! (the model has no prediction there). No downhill step at any damping means the minimum has been reached
//! to the model's precision, which counts as converged.

use std::ops::Range;

use nalgebra::{DMatrix, DVector};

use super::CalibrateError;

/// The linearised problem at an iterate: what a Levenberg–Marquardt step and the covariance need of J.
pub trait Linearisation {
    /// The damped Gauss–Newton step δ = (JᵀJ + λ·diag(JᵀJ))⁻¹ Jᵀ r (each diagonal floored at 1e-12);
    /// `None` when the damped matrix is not positive definite.
    fn step(&self, r: &DVector<f64>, lambda: f64) -> Option<DVector<f64>>;
    /// The diagonal of (JᵀJ)⁻¹; `None` when JᵀJ is singular.
    fn inverse_diagonal(&self) -> Option<Vec<f64>>;
}

impl Linearisation for DMatrix<f64> {
    fn step(&self, r: &DVector<f64>, lambda: f64) -> Option<DVector<f64>> {
        let jtj = self.transpose() * self;
        let jtr = self.transpose() * r;
        let mut a = jtj.clone();
        for k in 0..a.nrows() {
            a[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
        }
        a.cholesky().map(|c| c.solve(&jtr))
    }

    fn inverse_diagonal(&self) -> Option<Vec<f64>> {
        let inverse = (self.transpose() * self).try_inverse()?;
        Some((0..inverse.nrows()).map(|k| inverse[(k, k)]).collect())
    }
}

/// One block of a [`BlockJacobian`]: residual rows that depend on the global parameters and on parameters
/// of their own (`locals`) that no other block's rows depend on.
#[derive(Debug, Clone, PartialEq)]
pub struct JacobianBlock {
    /// Its residual rows.
    pub rows: Range<usize>,
    /// Indices in x of its own parameters (none, for rows that depend on the globals only).
    pub locals: Vec<usize>,
    /// ∂predicted/∂(globals), `rows.len()` × globals.
    pub global: DMatrix<f64>,
    /// ∂predicted/∂(locals), `rows.len()` × `locals.len()`.
    pub local: DMatrix<f64>,
}

/// A Jacobian with the block-sparse structure of per-item unknowns: the first `globals` parameters move
/// every row, every other parameter moves one block's rows only, and the blocks cover every row once.
/// Its normal equations are solved by eliminating each block's own parameters (the Schur complement onto
/// the globals), so a step costs O(blocks), not O(p³): the same step as the dense solve, arranged so.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockJacobian {
    /// Number of global parameters (x[0..globals]).
    pub globals: usize,
    /// Total number of parameters.
    pub parameters: usize,
    /// The blocks, covering every residual row once.
    pub blocks: Vec<JacobianBlock>,
}

/// A block after elimination: B = GᵀL and the Cholesky factor of its damped D = LᵀL (none without locals).
type EliminatedBlock = (DMatrix<f64>, Option<nalgebra::Cholesky<f64, nalgebra::Dyn>>);

/// The normal equations with every block's locals eliminated.
struct Eliminated {
    /// Schur complement S = A − Σ B D⁻¹ Bᵀ.
    schur: DMatrix<f64>,
    /// Per block, as [`EliminatedBlock`].
    blocks: Vec<EliminatedBlock>,
}

impl BlockJacobian {
    /// The dense matrix (rows × parameters) this stands for.
    pub fn to_dense(&self) -> DMatrix<f64> {
        let n = self.blocks.iter().map(|b| b.rows.end).max().unwrap_or(0);
        let mut j = DMatrix::zeros(n, self.parameters);
        for b in &self.blocks {
            for (i, row) in b.rows.clone().enumerate() {
                for g in 0..self.globals {
                    j[(row, g)] = b.global[(i, g)];
                }
                for (l, &k) in b.locals.iter().enumerate() {
                    j[(row, k)] = b.local[(i, l)];
                }
            }
        }
        j
    }

    /// Eliminates the locals from JᵀJ + λ·diag (damped as [`Linearisation::step`] damps); `None` when a
    /// block's matrix is not positive definite (the whole matrix then is not either).
    fn eliminate(&self, lambda: f64) -> Option<Eliminated> {
        let g = self.globals;
        let damp = |m: &mut DMatrix<f64>| {
            for k in 0..m.nrows() {
                m[(k, k)] += lambda * m[(k, k)].max(1e-12);
            }
        };
        // A's damping uses the diagonal of the whole A (the sum over blocks), as the dense solve does.
        let mut a = DMatrix::zeros(g, g);
        for b in &self.blocks {
            a += b.global.transpose() * &b.global;
        }
        if lambda != 0.0 {
            let diagonal: Vec<f64> = (0..g).map(|k| a[(k, k)]).collect();
            for (k, d) in diagonal.into_iter().enumerate() {
                a[(k, k)] += lambda * d.max(1e-12);
            }
        }
        let mut blocks = Vec::with_capacity(self.blocks.len());
        for b in &self.blocks {
            if b.locals.is_empty() {
                blocks.push((DMatrix::zeros(g, 0), None));
                continue;
            }
            let mut d = b.local.transpose() * &b.local;
            if lambda != 0.0 {
                damp(&mut d);
            }
            let bg = b.global.transpose() * &b.local;
            let chol = d.cholesky()?;
            let dinv_bt = chol.solve(&bg.transpose());
            a -= &bg * dinv_bt;
            blocks.push((bg, Some(chol)));
        }
        Some(Eliminated { schur: a, blocks })
    }
}

impl Linearisation for BlockJacobian {
    fn step(&self, r: &DVector<f64>, lambda: f64) -> Option<DVector<f64>> {
        let g = self.globals;
        let e = self.eliminate(lambda)?;
        // Right-hand sides: c_g = Σ Gᵀr_b, c_b = Lᵀr_b; reduced c_g − Σ B D⁻¹ c_b.
        let mut rhs = DVector::zeros(g);
        let mut local_rhs = Vec::with_capacity(self.blocks.len());
        for (b, (bg, chol)) in self.blocks.iter().zip(&e.blocks) {
            let rb = r.rows(b.rows.start, b.rows.len());
            rhs += b.global.transpose() * rb;
            let cb = b.local.transpose() * rb;
            if let Some(chol) = chol {
                rhs -= bg * chol.solve(&cb);
            }
            local_rhs.push(cb);
        }
        let dg = e.schur.cholesky()?.solve(&rhs);
        let mut delta = DVector::zeros(self.parameters);
        delta.rows_mut(0, g).copy_from(&dg);
        for ((b, (bg, chol)), cb) in self.blocks.iter().zip(&e.blocks).zip(local_rhs) {
            if let Some(chol) = chol {
                let dl = chol.solve(&(cb - bg.transpose() * &dg));
                for (l, &k) in b.locals.iter().enumerate() {
                    delta[k] = dl[l];
                }
            }
        }
        Some(delta)
    }

    fn inverse_diagonal(&self) -> Option<Vec<f64>> {
        // (JᵀJ)⁻¹ = [[S⁻¹, −S⁻¹ B D⁻¹], [·, D⁻¹ + D⁻¹Bᵀ S⁻¹ B D⁻¹]] per block.
        let g = self.globals;
        let e = self.eliminate(0.0)?;
        let s_inverse = e.schur.try_inverse()?;
        let mut diagonal = vec![0.0; self.parameters];
        for k in 0..g {
            diagonal[k] = s_inverse[(k, k)];
        }
        for (b, (bg, chol)) in self.blocks.iter().zip(&e.blocks) {
            let Some(chol) = chol else { continue };
            let d_inverse = chol.inverse();
            let w = bg * &d_inverse; // g × l: B D⁻¹
            let extra = w.transpose() * &s_inverse * &w;
            for (l, &k) in b.locals.iter().enumerate() {
                diagonal[k] = d_inverse[(l, l)] + extra[(l, l)];
            }
        }
        Some(diagonal)
    }
}

/// Where a minimisation ended.
pub struct Minimum<P, J = DMatrix<f64>> {
    /// The parameters.
    pub x: DVector<f64>,
    /// Residuals at `x`.
    pub residuals: DVector<f64>,
    /// The predictions at `x` (what the caller's evaluation returned with the residuals).
    pub predicted: P,
    /// The predictions at the start.
    pub predicted_at_start: P,
    /// Jacobian at `x` when converged or no iteration ran, else at the last iterate's start.
    pub jacobian: J,
    /// Iterations done.
    pub iterations: usize,
    /// Whether a step below the tolerance (or no downhill step) ended it.
    pub converged: bool,
}

impl<P, J: Linearisation> Minimum<P, J> {
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
        let diagonal = self.jacobian.inverse_diagonal()?;
        Some(diagonal.into_iter().map(|d| (s2 * d).max(0.0).sqrt()).collect())
    }
}

/// Where a minimisation is, for progress reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Iterations begun.
    pub iteration: usize,
    /// Evaluations of the residuals (and of the Jacobian) so far.
    pub evaluations: usize,
    /// Σr² of the current iterate.
    pub cost: f64,
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
/// `max_iterations` (0: none, the start is returned with J there) or when every component of an accepted
/// step is below `tolerance`.
pub fn minimize<P: Clone>(
    start: DVector<f64>,
    evaluate: impl Fn(&DVector<f64>) -> Result<(DVector<f64>, P), CalibrateError>,
    jacobian: impl Fn(&DVector<f64>, &DVector<f64>, &P) -> Result<DMatrix<f64>, CalibrateError>,
    max_iterations: usize,
    tolerance: f64,
) -> Result<Minimum<P>, CalibrateError> {
    minimize_with(start, evaluate, jacobian, max_iterations, tolerance, |_| {})
}

/// [`minimize`] for any [`Linearisation`] of J (e.g. a [`BlockJacobian`]), calling `progress` after every
/// evaluation of the residuals or of J.
pub fn minimize_with<P: Clone, J: Linearisation>(
    start: DVector<f64>,
    evaluate: impl Fn(&DVector<f64>) -> Result<(DVector<f64>, P), CalibrateError>,
    jacobian: impl Fn(&DVector<f64>, &DVector<f64>, &P) -> Result<J, CalibrateError>,
    max_iterations: usize,
    tolerance: f64,
    mut progress: impl FnMut(Progress),
) -> Result<Minimum<P, J>, CalibrateError> {
    let mut x = start;
    let (mut r, mut predicted) = evaluate(&x)?;
    if !cost(&r).is_finite() {
        return Err(CalibrateError::NoData("the start parameters give no prediction for some swings".into()));
    }
    let mut state = Progress { iteration: 0, evaluations: 1, cost: cost(&r) };
    progress(state);
    let predicted_at_start = predicted.clone();
    let mut lambda = 1e-3;
    let (mut iterations, mut converged) = (0, false);
    // J at the current x, when it is there (no step since it was computed).
    let mut j: Option<(J, bool)> = None;
    while iterations < max_iterations {
        iterations += 1;
        state.iteration = iterations;
        let jac = jacobian(&x, &r, &predicted)?;
        state.evaluations += 1;
        progress(state);
        let mut accepted = false;
        for _ in 0..12 {
            let Some(delta) = jac.step(&r, lambda) else {
                lambda *= 10.0;
                continue;
            };
            let trial = &x + &delta;
            let (r_trial, predicted_trial) = evaluate(&trial)?;
            state.evaluations += 1;
            if cost(&r_trial) <= cost(&r) {
                converged = delta.iter().all(|d| d.abs() < tolerance);
                x = trial;
                r = r_trial;
                predicted = predicted_trial;
                lambda = (lambda / 10.0).max(1e-9);
                accepted = true;
                state.cost = cost(&r);
                progress(state);
                break;
            }
            progress(state);
            lambda *= 10.0;
        }
        j = Some((jac, !accepted));
        if !accepted {
            converged = true;
        }
        if converged {
            break;
        }
    }
    let jacobian = match j {
        Some((j, at_x)) if at_x || !converged => j,
        _ => {
            let j = jacobian(&x, &r, &predicted)?;
            state.evaluations += 1;
            progress(state);
            j
        }
    };
    Ok(Minimum { x, residuals: r, predicted, predicted_at_start, jacobian, iterations, converged })
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

    /// A block-sparse Jacobian (2 globals; blocks of 3 rows with 0, 1 or 2 own parameters), filled with
    /// arbitrary numbers.
    fn block_jacobian() -> BlockJacobian {
        let mut blocks = Vec::new();
        let (mut row, mut k) = (0, 2);
        let value = |i: usize| ((i as f64 * 0.7543).sin() * 3.0).round() / 2.0 + (i as f64 * 0.131).cos();
        let mut seed = 0;
        for b in 0..7 {
            let locals: Vec<usize> = (0..b % 3).map(|l| k + l).collect();
            k += locals.len();
            let global = DMatrix::from_fn(3, 2, |_, _| {
                seed += 1;
                value(seed)
            });
            let local = DMatrix::from_fn(3, locals.len(), |_, _| {
                seed += 1;
                value(seed)
            });
            blocks.push(JacobianBlock { rows: row..row + 3, locals, global, local });
            row += 3;
        }
        BlockJacobian { globals: 2, parameters: k, blocks }
    }

    /// The Schur-complement step and covariance diagonal are the dense normal equations' (solved by
    /// Cholesky and by LU on the assembled matrix), at several dampings.
    #[test]
    fn the_block_solve_is_the_dense_solve() {
        let jb = block_jacobian();
        let jd = jb.to_dense();
        assert_eq!(jd.ncols(), jb.parameters);
        let r = DVector::from_fn(jd.nrows(), |i, _| (i as f64 * 1.37).sin());
        for lambda in [0.0, 1e-3, 10.0] {
            let (sb, sd) = (jb.step(&r, lambda).unwrap(), jd.step(&r, lambda).unwrap());
            assert!((&sb - &sd).amax() < 1e-10 * sd.amax().max(1.0), "λ {lambda}: {sb} vs {sd}");
        }
        let (cb, cd) = (jb.inverse_diagonal().unwrap(), jd.inverse_diagonal().unwrap());
        for (b, d) in cb.iter().zip(&cd) {
            assert!((b - d).abs() < 1e-10 * d.abs().max(1.0), "{cb:?} vs {cd:?}");
        }
    }

    /// A local parameter no row depends on makes JᵀJ singular for both solvers.
    #[test]
    fn an_unconstrained_local_is_singular_in_both() {
        let mut jb = block_jacobian();
        jb.blocks[1].local.fill(0.0);
        assert!(jb.inverse_diagonal().is_none());
        assert!(jb.to_dense().inverse_diagonal().is_none());
    }

    /// No iteration: the start comes back, not converged, with J at the start.
    #[test]
    fn zero_iterations_return_the_start() {
        let evaluate = |x: &DVector<f64>| Ok((DVector::from_vec(vec![1.0 - x[0], 2.0 - x[0]]), ()));
        let jacobian = |_: &DVector<f64>, _: &DVector<f64>, _: &()| Ok(DMatrix::from_element(2, 1, 1.0));
        let m = minimize(DVector::from_vec(vec![0.0]), evaluate, jacobian, 0, 1e-9).unwrap();
        assert_eq!((m.iterations, m.converged, m.x[0]), (0, false, 0.0));
        assert_eq!(m.jacobian, DMatrix::from_element(2, 1, 1.0));
    }

    #[test]
    fn a_start_without_a_prediction_is_refused() {
        let evaluate = |_: &DVector<f64>| Ok((DVector::from_vec(vec![f64::NAN, 1.0, 2.0]), ()));
        let jacobian = |_: &DVector<f64>, _: &DVector<f64>, _: &()| Ok(DMatrix::zeros(3, 1));
        let e = minimize(DVector::from_vec(vec![1.0]), evaluate, jacobian, 5, 1e-6).err().unwrap();
        assert!(matches!(e, CalibrateError::NoData(_)), "{e}");
    }
}
