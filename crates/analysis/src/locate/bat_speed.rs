//! The bat-speed fit of `locate --fit-bat-speed` (the module docs of [`super`], "Bat speed"): for a swing
//! whose bat speed the import assumed, the impact point, undercut and a scale on the bat's speeds fitted
//! together to exit speed, launch angle and spin.

use sweetspot_msgs::sweetspot_msgs::msg::Swing;

use super::{measured_of, LocateOptions, Outcome, Side, SwingModel};

/// Largest standard uncertainty of the fitted bat-speed scale reported as a number (25 % of the assumed
/// bat speed, a 95 % interval of ±50 %): beyond it the measurements do not separate the bat speed from the
/// impact point and undercut, and the linearised uncertainty no longer describes what is known.
pub const MAX_SCALE_SIGMA: f64 = 0.25;
/// Largest standard uncertainty of the impact point in a bat-speed fit reported as a number, m.
pub const MAX_FIT_Z_SIGMA: f64 = 0.05;
/// Bat-speed scales the fit is kept within.
const SCALE_RANGE: (f64, f64) = (0.3, 2.0);

/// One (z, D, bat-speed scale) that reproduces exit speed, launch angle and spin exactly.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BatSpeedSolution {
    /// Impact point, m from the knob.
    pub impact_z: f64,
    /// Its standard uncertainty, m.
    pub impact_z_sigma: f64,
    /// Undercut, m.
    pub undercut: f64,
    /// Its standard uncertainty, m.
    pub undercut_sigma: f64,
    /// Fitted bat speed over the assumed one (both the centre-of-mass and the angular speed), 1.
    pub scale: f64,
    /// Its standard uncertainty, 1.
    pub scale_sigma: f64,
    /// Fitted bat centre-of-mass speed, m/s.
    pub bat_cm_speed: f64,
    /// Fitted bat angular speed, rad/s.
    pub bat_angular_speed: f64,
    /// Side of the sweet spot (at the fitted undercut and bat speed).
    pub side: Side,
    /// χ² = Σ of the squared weighted residuals at the solution.
    pub chi2: f64,
}

/// The bat-speed fit of one swing (`LocateOptions::fit_bat_speed`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum BatSpeedFit {
    /// Solutions whose three unknowns the measurements separate, handle side first.
    Fitted {
        /// The separable solutions.
        solutions: Vec<BatSpeedSolution>,
        /// Further solutions found but not separable (left out).
        not_separable: usize,
    },
    /// Every solution found is ill-conditioned: the numbers would mean nothing.
    NotSeparable {
        /// Why, with the uncertainties the linearisation gives.
        reason: String,
    },
    /// Not attempted for this swing.
    NotFitted {
        /// Why.
        reason: String,
    },
    /// Attempted, but no (z, D, scale) reproduces the three measurements.
    Failed {
        /// Why.
        reason: String,
    },
}

/// A 3×3 matrix (row major).
type Matrix3 = [[f64; 3]; 3];

/// Inverse of a 3×3 matrix (adjugate over determinant), None when singular.
fn invert3(a: &[[f64; 3]; 3]) -> Option<[[f64; 3]; 3]> {
    let c = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]
    };
    let det = a[0][0] * c(0, 0) + a[0][1] * c(0, 1) + a[0][2] * c(0, 2);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let mut inv = [[0.0; 3]; 3];
    for (i, row) in inv.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            // Cofactors by cyclic index carry their sign; the inverse is the transposed cofactor matrix / det.
            *x = c(j, i) / det;
        }
    }
    Some(inv)
}

impl SwingModel<'_> {
    /// Weighted residuals of exit speed, launch angle and spin at (z, d, scale).
    fn residuals3(&self, x: [f64; 3], measured: &[f64; 3], sigma: &[f64; 3]) -> Option<[f64; 3]> {
        let p = self.predict_scaled(x[0], x[1], x[2]).ok()?;
        let r = [0, 1, 2].map(|k| (p[k] - measured[k]) / sigma[k]);
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    /// Levenberg–Marquardt in (z, D, scale) from `start`, z kept within `bounds` (one side of the sweet spot);
    /// the solution and Cov = (JᵀJ)⁻¹ (None if singular).
    fn fit3(
        &self,
        start: [f64; 3],
        bounds: (f64, f64),
        measured: &[f64; 3],
        sigma: &[f64; 3],
    ) -> Option<([f64; 3], Option<Matrix3>)> {
        let (lo, hi) = bounds;
        let clamp = |x: [f64; 3]| {
            let z = x[0].clamp(lo, hi);
            let reach = self.reach(z);
            [z, x[1].clamp(-reach, reach), x[2].clamp(SCALE_RANGE.0, SCALE_RANGE.1)]
        };
        let steps = [1e-5, 1e-6, 1e-6];
        let jacobian = |x: [f64; 3], r: &[f64; 3]| -> Option<[[f64; 3]; 3]> {
            let mut j = [[0.0; 3]; 3];
            for (p, h) in steps.iter().enumerate() {
                let mut xp = x;
                xp[p] += h;
                let rp = self.residuals3(xp, measured, sigma)?;
                for i in 0..3 {
                    j[i][p] = (rp[i] - r[i]) / h;
                }
            }
            Some(j)
        };
        let normal = |j: &[[f64; 3]; 3]| {
            let mut a = [[0.0; 3]; 3];
            for row in j {
                for p in 0..3 {
                    for q in 0..3 {
                        a[p][q] += row[p] * row[q];
                    }
                }
            }
            a
        };
        let cost = |r: &[f64; 3]| r.iter().map(|x| x * x).sum::<f64>();
        let mut x = clamp(start);
        let mut r = self.residuals3(x, measured, sigma)?;
        let mut jac = jacobian(x, &r)?;
        let mut lambda = 1e-3;
        for _ in 0..100 {
            let a = normal(&jac);
            let mut g = [0.0; 3];
            for (row, ri) in jac.iter().zip(&r) {
                for p in 0..3 {
                    g[p] += row[p] * ri;
                }
            }
            let mut damped = a;
            for (p, row) in damped.iter_mut().enumerate() {
                row[p] *= 1.0 + lambda;
            }
            let inv = invert3(&damped)?;
            let step = [0, 1, 2].map(|p| -(0..3).map(|q| inv[p][q] * g[q]).sum::<f64>());
            let next = clamp([x[0] + step[0], x[1] + step[1], x[2] + step[2]]);
            match self.residuals3(next, measured, sigma) {
                Some(nr) if cost(&nr) < cost(&r) => {
                    let moved = (0..3).map(|p| (next[p] - x[p]).abs()).fold(0.0, f64::max);
                    x = next;
                    r = nr;
                    lambda = (lambda * 0.3).max(1e-9);
                    jac = jacobian(x, &r)?;
                    if moved < 1e-9 || cost(&r) < 1e-20 {
                        break;
                    }
                }
                _ => {
                    lambda *= 10.0;
                    if lambda > 1e10 {
                        break;
                    }
                }
            }
        }
        Some((x, invert3(&normal(&jac))))
    }
}

/// A fit's unknowns (z, D, scale), their covariance (None if singular) and χ².
type Found = ([f64; 3], Option<Matrix3>, f64);
/// Where fits start, (z, D, scale), each with the side of the sweet spot it is kept on.
type Starts = Vec<([f64; 3], Side)>;

/// Fits the bat speed of one swing together with its impact point and undercut, from the 2-unknown
/// solutions of `outcome` (or the sweet spot for a swing too fast for the assumed bat speed).
pub(super) fn fit_bat_speed(
    model: &SwingModel<'_>,
    swing: &Swing,
    outcome: &Outcome,
    options: &LocateOptions,
) -> BatSpeedFit {
    let measured = measured_of(swing);
    let sigma = [options.exit_speed_sigma, options.launch_angle_sigma, options.spin_sigma];
    let not_fitted = |reason: &str| BatSpeedFit::NotFitted { reason: reason.into() };
    if !measured[0].is_finite() {
        return not_fitted("no exit speed measured");
    }
    if !measured[2].is_finite() {
        return not_fitted("no spin measured: two measurements cannot fix three unknowns");
    }
    if !measured[1].is_finite() {
        return not_fitted("no launch angle measured: two measurements cannot fix three unknowns");
    }
    let (starts, peak_z) = match starts(model, outcome, &measured) {
        Ok(starts) => starts,
        Err(reason) => return not_fitted(&reason),
    };
    let (found, best) = solve_from(model, starts, peak_z, &measured, &sigma);
    if found.is_empty() {
        let closest = best.map_or(String::new(), |(x, chi2)| {
            format!(
                " (closest: χ² = {chi2:.1} at z = {:.3} m, D = {:+.1} mm, bat speed × {:.2})",
                x[0],
                x[1] * 1e3,
                x[2]
            )
        });
        return BatSpeedFit::Failed {
            reason: format!(
                "no impact point, undercut and bat speed reproduce exit speed, launch angle and spin together{closest}"
            ),
        };
    }
    separable(model, &found, peak_z)
}

/// Where the fits start, each with the side of the sweet spot it is kept on, and the sweet spot; or why
/// there is nothing to start from.
fn starts(model: &SwingModel<'_>, outcome: &Outcome, measured: &[f64; 3]) -> Result<(Starts, f64), String> {
    // One start per side of the sweet spot, each fit kept on its side: with z as loosely held as it is near
    // the sweet spot, a free fit would wander to the mirror solution and leave its own side unexplored.
    let (mut starts, peak_z): (Starts, f64) = match outcome {
        // A fit that misses at the assumed bat speed is where a fitted one starts too.
        Outcome::Located { solutions, .. } | Outcome::NotReproducible { solutions, .. } if !solutions.is_empty() => {
            (solutions.iter().map(|s| ([s.impact_z, s.undercut, 1.0], s.side)).collect(), solutions[0].sweet_spot_z)
        }
        Outcome::Located { .. } | Outcome::NotReproducible { .. } => return Err("no fit to start from".into()),
        Outcome::TooFast { max_exit_speed, excess, sweet_spot_z } => {
            // Faster than the assumed bat allows: a faster bat, either side of the sweet spot.
            let d = model.undercut_for_launch_angle(*sweet_spot_z, 0.0, measured[1]);
            let scale = 1.0 + excess / max_exit_speed;
            let h = 0.03;
            (
                vec![([sweet_spot_z - h, d, scale], Side::Handle), ([sweet_spot_z + h, d, scale], Side::End)],
                *sweet_spot_z,
            )
        }
        Outcome::NotMeasured => return Err("no exit speed measured".into()),
        Outcome::Failed { reason } => return Err(format!("the swing was not located: {reason}")),
    };
    // Near the sweet spot the exit speed barely moves with z, and a fit started there at the assumed bat speed
    // can stall against the sweet spot while the solution lies a few cm out at another bat speed: each side
    // is also started 5 cm from the sweet spot at a bat 15 % slower and 15 % faster.
    for side in [Side::Handle, Side::End] {
        let Some(d) = starts.iter().find(|(_, s)| *s == side).map(|(x, _)| x[1]) else { continue };
        let z = match side {
            Side::Handle => peak_z - 0.05,
            Side::End => peak_z + 0.05,
        };
        for scale in [0.85, 1.15] {
            starts.push(([z, d, scale], side));
        }
    }
    Ok((starts, peak_z))
}

/// The distinct solutions that reproduce all three measurements, fitted from each start on its side of the
/// sweet spot at `peak_z`, and the closest miss (unknowns, χ²) for the report when there is none.
fn solve_from(
    model: &SwingModel<'_>,
    starts: Starts,
    peak_z: f64,
    measured: &[f64; 3],
    sigma: &[f64; 3],
) -> (Vec<Found>, Option<([f64; 3], f64)>) {
    let (lo, hi) = model.range();
    let mut found: Vec<Found> = Vec::new();
    let mut best: Option<([f64; 3], f64)> = None;
    for (start, side) in starts {
        let bounds = match side {
            Side::Handle => (lo, peak_z.min(hi)),
            Side::End => (peak_z.max(lo), hi),
        };
        let Some((x, cov)) = model.fit3(start, bounds, measured, sigma) else { continue };
        let Some(r) = model.residuals3(x, measured, sigma) else { continue };
        let chi2 = r.iter().map(|v| v * v).sum::<f64>();
        if best.is_none_or(|(_, c)| chi2 < c) {
            best = Some((x, chi2));
        }
        // Three measurements, three unknowns: a solution reproduces them all.
        if chi2 > 1e-6 || found.iter().any(|(y, _, _)| (y[0] - x[0]).abs() < 1e-3 && (y[1] - x[1]).abs() < 1e-3) {
            continue;
        }
        found.push((x, cov, chi2));
    }
    (found, best)
}

/// The solutions whose unknowns the measurements separate ([`MAX_SCALE_SIGMA`], [`MAX_FIT_Z_SIGMA`]), or
/// why none is.
fn separable(model: &SwingModel<'_>, found: &[Found], peak_z: f64) -> BatSpeedFit {
    let mut solutions = Vec::new();
    let mut worst = String::new();
    for (x, cov, chi2) in found {
        let sig = cov.map(|c| [c[0][0].sqrt(), c[1][1].sqrt(), c[2][2].sqrt()]);
        match sig {
            Some(s) if s[2] <= MAX_SCALE_SIGMA && s[0] <= MAX_FIT_Z_SIGMA && s.iter().all(|v| v.is_finite()) => {
                let mut input = model.input;
                input.impact.bat_cm_speed *= x[2];
                input.impact.bat_angular_speed *= x[2];
                let scaled = SwingModel { input, ..*model };
                let (sweet, _) = scaled.sweet_spot_near(x[1], peak_z);
                solutions.push(BatSpeedSolution {
                    impact_z: x[0],
                    impact_z_sigma: s[0],
                    undercut: x[1],
                    undercut_sigma: s[1],
                    scale: x[2],
                    scale_sigma: s[2],
                    bat_cm_speed: scaled.input.impact.bat_cm_speed,
                    bat_angular_speed: scaled.input.impact.bat_angular_speed,
                    side: if x[0] < sweet { Side::Handle } else { Side::End },
                    chi2: *chi2,
                });
            }
            Some(s) => {
                worst = format!(
                    "at z = {:.3} m the linearised uncertainties are σ_z = {:.3} m, σ(bat speed) = {:.0} % \
                     (exit speed, launch angle and spin do not separate impact point, undercut and bat speed there)",
                    x[0],
                    s[0],
                    s[2] * 100.0
                );
            }
            None => {
                worst = format!("at z = {:.3} m the Jacobian is singular", x[0]);
            }
        }
    }
    let not_separable = found.len() - solutions.len();
    if solutions.is_empty() {
        return BatSpeedFit::NotSeparable { reason: worst };
    }
    solutions.sort_by(|a, b| a.impact_z.total_cmp(&b.impact_z));
    BatSpeedFit::Fitted { solutions, not_separable }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Index loops read as the matrix algebra they check.
    #[allow(clippy::needless_range_loop)]
    #[test]
    fn invert3_gives_the_textbook_inverse_and_refuses_a_singular_matrix() {
        // [[2, -1, 0], [-1, 2, -1], [0, -1, 2]]⁻¹ = [[3, 2, 1], [2, 4, 2], [1, 2, 3]] / 4 (the 1-D Laplacian).
        let a = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]];
        let expected = [[0.75, 0.5, 0.25], [0.5, 1.0, 0.5], [0.25, 0.5, 0.75]];
        let inv = invert3(&a).expect("regular");
        for i in 0..3 {
            for j in 0..3 {
                assert!((inv[i][j] - expected[i][j]).abs() < 1e-15, "({i}, {j}): {}", inv[i][j]);
            }
        }
        // An unsymmetric one: A·A⁻¹ = I.
        let b = [[1.0, 2.0, 3.0], [0.0, 1.0, 4.0], [5.0, 6.0, 0.0]];
        let inv = invert3(&b).expect("regular");
        for i in 0..3 {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| b[i][k] * inv[k][j]).sum();
                assert!((p - f64::from(u8::from(i == j))).abs() < 1e-12, "({i}, {j}): {p}");
            }
        }
        assert!(invert3(&[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]]).is_none());
    }
}
