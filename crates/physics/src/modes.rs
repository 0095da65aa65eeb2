//! Normal modes of the free–free, non-uniform Timoshenko beam (symmetric K, diagonal M).
//!
//! The derivation (energy method, link convention, and its check against Nathan's own matrix) is in the
//! module docs of [`crate`]. Coordinates are ordered `[y_1 … y_N, φ_1 … φ_N]`; y_i is the transverse
//! displacement of slice i's centre (m) and φ_i its rotation (rad, positive in the sense of +dy/dz).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::bat::{mass_properties_of, Slice};
use super::hoop::{HoopMode, HoopProfile};
use super::{Bat, MassProperties, PhysicsError};

/// One normal mode, mass-normalised: Σ m_i y_i² + Σ J_i φ_i² = 1 (units of y: m per √kg of modal amplitude).
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// Angular frequency ω, rad/s (0 for the two rigid-body modes).
    pub angular_frequency: f64,
    /// Transverse displacement at each slice centre, per unit modal amplitude.
    pub displacement: Vec<f64>,
    /// Rotation φ of each slice, rad per unit modal amplitude.
    pub rotation: Vec<f64>,
}

impl Mode {
    /// Frequency f = ω/2π, Hz.
    pub fn frequency_hz(&self) -> f64 {
        self.angular_frequency / (2.0 * std::f64::consts::PI)
    }
}

/// Which slice's section a link between slices i and i+1 uses for its (YI) and (SA).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LinkRule {
    /// The knob-side slice i: Nathan's convention, reproduces his published matrix entry by entry.
    #[default]
    KnobSide,
    /// The arithmetic mean of slices i and i+1 (second-order accurate for a smoothly varying profile).
    Mean,
}

/// How [`ModeSet`] solves the eigenproblem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EigenSolver {
    /// Inverse iteration for up to 40 kept modes or large bats, dense otherwise.
    #[default]
    Auto,
    /// nalgebra's dense symmetric eigen-decomposition (all eigenvectors) of M^{-1/2} K M^{-1/2}.
    Dense,
    /// Eigenvalues of the banded M^{-1/2} K M^{-1/2} (band → tridiagonal reduction, Sturm bisection), then
    /// each kept mode's vector by inverse iteration on the banded pencil K − λM (band LU with partial
    /// pivoting, O(N) per mode). Under `Auto`, near-repeated eigenvalues fall back to `Dense`.
    InverseIteration,
}

/// Largest number of kept modes for which [`EigenSolver::Auto`] uses inverse iteration.
pub const INVERSE_ITERATION_MAX_MODES: usize = 40;

/// Largest 2N for which [`EigenSolver::Auto`] may pick the dense solver (memory and time grow as N², N³).
pub const DENSE_MAX_SIZE: usize = 1200;

/// Half-bandwidth of K and M in the interleaved ordering (y_1, φ_1, y_2, φ_2, …).
const HALF_BAND: usize = 3;
/// Width of a band-LU row: the band plus the fill-in of partial pivoting.
const LU_WIDTH: usize = 3 * HALF_BAND + 1;

/// K and M in the interleaved ordering, as bands, for inverse iteration and Rayleigh quotients.
struct BandPencil {
    /// Number of coordinates 2N.
    size: usize,
    /// k[r][d] = K(r, r − HALF_BAND + d), interleaved indices.
    k: Vec<[f64; 2 * HALF_BAND + 1]>,
    /// Diagonal of M, interleaved.
    m: Vec<f64>,
}

impl BandPencil {
    fn from_slices(slices: &[Slice], dz: f64, rule: LinkRule) -> BandPencil {
        let size = 2 * slices.len();
        // Interleaved order: y_i → 2i, φ_i → 2i + 1.
        let index = |(is_y, i): (bool, usize)| if is_y { 2 * i } else { 2 * i + 1 };
        let mut k = vec![[0.0; 2 * HALF_BAND + 1]; size];
        for_each_stiffness_term(slices, dz, rule, |r, c, v| {
            let (r, c) = (index(r), index(c));
            k[r][c + HALF_BAND - r] += v;
        });
        let m = slices.iter().flat_map(|s| [s.mass, s.rotary_inertia]).collect();
        BandPencil { size, k, m }
    }

    /// Σ K-energy xᵀKx for the mode (y, φ) in block form.
    fn stiffness_energy(&self, y: &[f64], phi: &[f64]) -> f64 {
        let x = |r: usize| if r & 1 == 0 { y[r / 2] } else { phi[r / 2] };
        let mut e = 0.0;
        for r in 0..self.size {
            let mut kr = 0.0;
            for d in 0..=2 * HALF_BAND {
                let c = r as isize - HALF_BAND as isize + d as isize;
                if c >= 0 && (c as usize) < self.size {
                    kr += self.k[r][d] * x(c as usize);
                }
            }
            e += x(r) * kr;
        }
        e
    }

    /// The eigenvector of K v = λ M v for the eigenvalue nearest `lambda` (an eigenvalue of the symmetric
    /// form M^{-1/2} K M^{-1/2}, which has the same spectrum), by inverse iteration with a band LU of K − λM; returned in block form.
    fn inverse_iteration(&self, lambda: f64) -> Result<(Vec<f64>, Vec<f64>), PhysicsError> {
        let size = self.size;
        // Band LU with partial pivoting. Row r holds columns r − HALF_BAND … r − HALF_BAND + LU_WIDTH − 1.
        let mut lu = vec![[0.0; LU_WIDTH]; size];
        for r in 0..size {
            for d in 0..=2 * HALF_BAND {
                lu[r][d] = self.k[r][d];
            }
            lu[r][HALF_BAND] -= lambda * self.m[r];
        }
        let scale = self.k.iter().flat_map(|row| row.iter()).fold(0.0_f64, |a, &v| a.max(v.abs()));
        let tiny = f64::EPSILON * scale.max(f64::MIN_POSITIVE);
        let at = |r: usize, c: usize| c + HALF_BAND - r; // column c of row r → slot (valid when in window)
        let mut pivots = vec![0usize; size];
        let mut multipliers = vec![[0.0; HALF_BAND]; size];
        for i in 0..size {
            let last_row = (i + HALF_BAND).min(size - 1);
            let last_col = (i + 2 * HALF_BAND).min(size - 1);
            let mut p = i;
            for r in i + 1..=last_row {
                if lu[r][at(r, i)].abs() > lu[p][at(p, i)].abs() {
                    p = r;
                }
            }
            pivots[i] = p;
            if p != i {
                for c in i..=last_col {
                    let (si, sp) = (at(i, c), at(p, c));
                    let tmp = lu[i][si];
                    lu[i][si] = lu[p][sp];
                    lu[p][sp] = tmp;
                }
            }
            if lu[i][at(i, i)].abs() < tiny {
                lu[i][at(i, i)] = tiny;
            }
            let pivot = lu[i][at(i, i)];
            for r in i + 1..=last_row {
                let l = lu[r][at(r, i)] / pivot;
                multipliers[i][r - i - 1] = l;
                lu[r][at(r, i)] = 0.0;
                if l != 0.0 {
                    for c in i + 1..=last_col {
                        lu[r][at(r, c)] -= l * lu[i][at(i, c)];
                    }
                }
            }
        }
        let solve = |b: &mut [f64]| {
            for i in 0..size {
                b.swap(i, pivots[i]);
                let last_row = (i + HALF_BAND).min(size - 1);
                for r in i + 1..=last_row {
                    b[r] -= multipliers[i][r - i - 1] * b[i];
                }
            }
            for i in (0..size).rev() {
                let last_col = (i + 2 * HALF_BAND).min(size - 1);
                let mut acc = b[i];
                for c in i + 1..=last_col {
                    acc -= lu[i][at(i, c)] * b[c];
                }
                b[i] = acc / lu[i][at(i, i)];
            }
        };
        // A start vector with components along every mode (no symmetry of the bat can cancel it).
        let mut x: Vec<f64> = (0..size).map(|r| 1.0 + 0.5 * ((r as f64) * 0.7548776662).sin()).collect();
        for _ in 0..3 {
            let mut b: Vec<f64> = (0..size).map(|r| self.m[r] * x[r]).collect();
            solve(&mut b);
            let norm = (0..size).map(|r| self.m[r] * b[r] * b[r]).sum::<f64>().sqrt();
            if !(norm.is_finite() && norm > 0.0) {
                return Err(PhysicsError::Numerical("inverse iteration broke down".into()));
            }
            x = b.iter().map(|v| v / norm).collect();
        }
        let n = size / 2;
        Ok(((0..n).map(|i| x[2 * i]).collect(), (0..n).map(|i| x[2 * i + 1]).collect()))
    }
}

/// The indices of `eigenvalues` in ascending order, once the lowest two are zero to the solver's rounding
/// (≈ ε·√n·λ_max, the two rigid modes) and the third clearly above it; otherwise the bat is too
/// ill-conditioned for double precision.
fn ascending_with_rigid_null_space(eigenvalues: &DVector<f64>) -> Result<Vec<usize>, PhysicsError> {
    let size = eigenvalues.len();
    let mut order: Vec<usize> = (0..size).collect();
    order.sort_by(|&i, &j| eigenvalues[i].total_cmp(&eigenvalues[j]));
    let lambda_max = eigenvalues.iter().fold(0.0_f64, |acc, &l| acc.max(l.abs()));
    if !lambda_max.is_finite() {
        return Err(PhysicsError::Numerical("non-finite eigenvalue".into()));
    }
    let zero_tol = 64.0 * f64::EPSILON * (size as f64).sqrt() * lambda_max;
    if !(eigenvalues[order[0]].abs() <= zero_tol && eigenvalues[order[1]].abs() <= zero_tol)
        || eigenvalues[order[2]] <= zero_tol
    {
        return Err(PhysicsError::Numerical(format!(
            "stiffness null space is not exactly the two rigid modes (lowest eigenvalues {:e}, {:e}, {:e})",
            eigenvalues[order[0]], eigenvalues[order[1]], eigenvalues[order[2]]
        )));
    }
    Ok(order)
}

/// Removes from the mode shape (y, φ) its M-projection on each of `kept` and returns its M-norm.
fn m_orthogonalise(slices: &[Slice], kept: &[Mode], y: &mut [f64], phi: &mut [f64]) -> f64 {
    for r in kept {
        let c = m_inner(slices, y, phi, &r.displacement, &r.rotation);
        for i in 0..y.len() {
            y[i] -= c * r.displacement[i];
            phi[i] -= c * r.rotation[i];
        }
    }
    m_inner(slices, y, phi, y, phi).sqrt()
}

/// The mode of shape (y, φ) and M-norm `norm`: scaled to unit modal mass with a positive displacement at the
/// barrel end, its ω (rad/s) from the Rayleigh quotient (accurate to relative rounding).
fn unit_mode(band: &BandPencil, mut y: Vec<f64>, mut phi: Vec<f64>, norm: f64) -> Result<Mode, PhysicsError> {
    if !(norm.is_finite() && norm > 0.0) {
        return Err(PhysicsError::Numerical("degenerate mode from the eigen-solver".into()));
    }
    let sign = if y[y.len() - 1] < 0.0 { -1.0 } else { 1.0 };
    let scale = sign / norm;
    y.iter_mut().for_each(|v| *v *= scale);
    phi.iter_mut().for_each(|v| *v *= scale);
    let omega = band.stiffness_energy(&y, &phi).max(0.0).sqrt();
    if !omega.is_finite() {
        return Err(PhysicsError::Numerical("non-finite mode frequency".into()));
    }
    Ok(Mode { angular_frequency: omega, displacement: y, rotation: phi })
}

/// The lowest `count` eigenvalues (ascending; the rest set to an upper bound of the spectrum) of
/// M^{-1/2} K M^{-1/2}, which has half-bandwidth [`HALF_BAND`] in the interleaved order: band reduction to
/// tridiagonal form by Givens rotations with bulge chasing (orthogonal, O(N²)), then Sturm bisection on the
/// tridiagonal matrix (relative accuracy 1e-13; inverse iteration and the Rayleigh quotient polish them).
fn band_eigenvalues(pencil: &BandPencil, count: usize) -> DVector<f64> {
    let (diag, off2) = tridiagonalize(pencil);
    bisect_tridiagonal(&diag, &off2, count)
}

/// M^{-1/2} K M^{-1/2} reduced to tridiagonal form: its diagonal and the squares of its off-diagonal.
fn tridiagonalize(pencil: &BandPencil) -> (Vec<f64>, Vec<f64>) {
    let size = pencil.size;
    let b = HALF_BAND;
    // Banded working copy of M^{-1/2} K M^{-1/2} in the interleaved order, one extra diagonal on each side
    // for the bulge the chase moves along: entry (i, j), |i − j| ≤ b + 1, at t[i·w + j + b + 1 − i].
    let half = b + 1;
    let w = 2 * half + 1;
    let at = move |i: usize, j: usize| -> Option<usize> { (i.abs_diff(j) <= half).then(|| i * w + j + half - i) };
    let mut t = vec![0.0; size * w];
    let inv_sqrt_m: Vec<f64> = pencil.m.iter().map(|m| 1.0 / m.sqrt()).collect();
    for r in 0..size {
        for c in r.saturating_sub(b)..=(r + b).min(size - 1) {
            if let Some(k) = at(r, c) {
                t[k] = pencil.k[r][c + b - r] * inv_sqrt_m[r] * inv_sqrt_m[c];
            }
        }
    }
    let get = |t: &[f64], i: usize, j: usize| at(i, j).map_or(0.0, |k| t[k]);
    let rotate = |t: &mut [f64], p: usize, q: usize, cos: f64, sin: f64| {
        let lo = p.saturating_sub(half);
        let hi = (q + half).min(size - 1);
        for j in lo..=hi {
            let (x, y) = (get(t, p, j), get(t, q, j));
            if let Some(k) = at(p, j) {
                t[k] = cos * x + sin * y;
            }
            if let Some(k) = at(q, j) {
                t[k] = -sin * x + cos * y;
            }
        }
        for i in lo..=hi {
            let (x, y) = (get(t, i, p), get(t, i, q));
            if let Some(k) = at(i, p) {
                t[k] = cos * x + sin * y;
            }
            if let Some(k) = at(i, q) {
                t[k] = -sin * x + cos * y;
            }
        }
    };
    // Zeroes t[q][col] against t[q−1][col] by a rotation in the plane (q−1, q).
    let annihilate = |t: &mut [f64], q: usize, col: usize| {
        let (x, y) = (get(t, q - 1, col), get(t, q, col));
        if y != 0.0 {
            let r = x.hypot(y);
            rotate(t, q - 1, q, x / r, y / r);
            for (i, j) in [(q, col), (col, q)] {
                if let Some(k) = at(i, j) {
                    t[k] = 0.0;
                }
            }
        }
    };
    for k in 0..size.saturating_sub(2) {
        for l in ((k + 2)..=(k + b).min(size - 1)).rev() {
            annihilate(&mut t, l, k);
            // The rotation in (l−1, l) leaves a bulge at (l+b, l−1); chase it off the end.
            let mut q = l + b;
            let mut col = l - 1;
            while q < size {
                annihilate(&mut t, q, col);
                col = q - 1;
                q += b;
            }
        }
    }
    let diag: Vec<f64> = (0..size).map(|i| get(&t, i, i)).collect();
    let off2: Vec<f64> = (0..size.saturating_sub(1)).map(|i| get(&t, i, i + 1).powi(2)).collect();
    (diag, off2)
}

/// The lowest `count` eigenvalues of the symmetric tridiagonal matrix with diagonal `diag` and squared
/// off-diagonal `off2` (ascending; the rest set to its Gershgorin upper bound), by Sturm bisection to a relative
/// 1e-13.
fn bisect_tridiagonal(diag: &[f64], off2: &[f64], count: usize) -> DVector<f64> {
    let size = diag.len();
    // Gershgorin bounds.
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for i in 0..size {
        let r = if i > 0 { off2[i - 1].sqrt() } else { 0.0 } + if i + 1 < size { off2[i].sqrt() } else { 0.0 };
        lo = lo.min(diag[i] - r);
        hi = hi.max(diag[i] + r);
    }
    // Parallel bisection: eigenvalue k keeps a bracket [a_k, b_k] with (Sturm count below a_k) ≤ k <
    // (count below b_k). All brackets are halved together, which interleaves the independent LDLᵀ
    // recurrences (each a chain of divisions) instead of running them one after another.
    let count = count.min(size);
    let mut values = DVector::from_element(size, hi);
    let mut left = vec![lo; count];
    let mut right = vec![hi; count];
    let mut mid = vec![0.0; count];
    let mut d = vec![0.0; count];
    let mut below = vec![0usize; count];
    let tolerance = |a: f64, b: f64| b - a <= 1e-13 * a.abs().max(b.abs()) + 8.0 * f64::EPSILON * hi.abs();
    for _ in 0..200 {
        let active: Vec<usize> = (0..count).filter(|&k| !tolerance(left[k], right[k])).collect();
        if active.is_empty() {
            break;
        }
        for &k in &active {
            mid[k] = 0.5 * (left[k] + right[k]);
            d[k] = 1.0;
            below[k] = 0;
        }
        for i in 0..size {
            let e2 = if i > 0 { off2[i - 1] } else { 0.0 };
            for &k in &active {
                let mut v = diag[i] - mid[k] - e2 / d[k];
                if v == 0.0 {
                    v = -f64::EPSILON * (diag[i].abs() + mid[k].abs()).max(f64::MIN_POSITIVE);
                }
                d[k] = v;
                below[k] += (v < 0.0) as usize;
            }
        }
        for &k in &active {
            if below[k] > k {
                right[k] = mid[k];
            } else {
                left[k] = mid[k];
            }
        }
    }
    for k in 0..count {
        values[k] = 0.5 * (left[k] + right[k]);
    }
    values
}

/// Calls `add((is_y, slice), (is_y, slice), value)` for every contribution of the links to K
/// (see the module docs of [`crate`] for the energy it comes from).
fn for_each_stiffness_term(
    slices: &[Slice],
    dz: f64,
    rule: LinkRule,
    mut add: impl FnMut((bool, usize), (bool, usize), f64),
) {
    for i in 0..slices.len().saturating_sub(1) {
        let (a, b) = (&slices[i], &slices[i + 1]);
        let (yi, sa) = match rule {
            LinkRule::KnobSide => (a.bending_stiffness, a.shear_stiffness),
            LinkRule::Mean => {
                (0.5 * (a.bending_stiffness + b.bending_stiffness), 0.5 * (a.shear_stiffness + b.shear_stiffness))
            }
        };
        // Bending: ½ (YI) Δz ((φ_{i+1} − φ_i)/Δz)².
        let kb = yi / dz;
        let (p, q) = ((false, i), (false, i + 1));
        add(p, p, kb);
        add(q, q, kb);
        add(p, q, -kb);
        add(q, p, -kb);
        // Shear: ½ (SA) Δz (gᵀx/Δz)² with gᵀx = y_{i+1} − y_i − Δz (φ_i + φ_{i+1})/2.
        let ks = sa / dz;
        let g = [((true, i), -1.0), ((true, i + 1), 1.0), (p, -0.5 * dz), (q, -0.5 * dz)];
        for &(r, gr) in &g {
            for &(c, gc) in &g {
                add(r, c, ks * gr * gc);
            }
        }
    }
}

/// The assembled beam: symmetric stiffness K (2N×2N, order [y…, φ…]) and diagonal mass M.
#[derive(Debug, Clone)]
pub struct BeamMatrices {
    /// Stiffness K, N/m (y–y), N (y–φ), N·m (φ–φ).
    pub stiffness: DMatrix<f64>,
    /// Diagonal of M: slice masses m_i (kg) then rotary inertias J_i (kg·m²).
    pub mass: DVector<f64>,
    /// Slice thickness Δz, m.
    pub slice_length: f64,
}

impl BeamMatrices {
    /// Assembles K and M of `bat` with the link property rule `rule`.
    pub fn assemble(bat: &Bat, rule: LinkRule) -> Result<BeamMatrices, PhysicsError> {
        bat.validate()?;
        Ok(Self::from_slices(&bat.slices(), bat.actual_slice_length(), rule))
    }

    fn from_slices(slices: &[Slice], dz: f64, rule: LinkRule) -> BeamMatrices {
        let n = slices.len();
        let mut k = DMatrix::<f64>::zeros(2 * n, 2 * n);
        let mut m = DVector::<f64>::zeros(2 * n);
        for (i, s) in slices.iter().enumerate() {
            m[i] = s.mass;
            m[n + i] = s.rotary_inertia;
        }
        // Block order: y_i → i, φ_i → n + i.
        for_each_stiffness_term(slices, dz, rule, |(ry, ri), (cy, ci), v| {
            let r = if ry { ri } else { n + ri };
            let c = if cy { ci } else { n + ci };
            k[(r, c)] += v;
        });
        BeamMatrices { stiffness: k, mass: m, slice_length: dz }
    }

    /// Nathan's H = −M⁻¹K in his variables [y; Φ] with Φ_i = −φ_i Δz (his rotation has the opposite sign).
    pub fn nathan_h(&self) -> DMatrix<f64> {
        let n2 = self.mass.len();
        let n = n2 / 2;
        let dz = self.slice_length;
        // x = T ξ with ξ = [y; Φ], T = diag(1, −1/Δz); ξ̈ = −T⁻¹ M⁻¹ K T ξ.
        let t = |i: usize| if i < n { 1.0 } else { -1.0 / dz };
        DMatrix::from_fn(n2, n2, |r, c| -self.stiffness[(r, c)] * t(c) / (self.mass[r] * t(r)))
    }
}

/// The normal modes of one bat, computed once and reused for every swing.
#[derive(Debug, Clone)]
pub struct ModeSet {
    name: String,
    slices: Vec<Slice>,
    slice_length: f64,
    length: f64,
    mass_properties: MassProperties,
    /// [translation, rotation, vibrational 1, 2, …], each mass-normalised.
    modes: Vec<Mode>,
    /// The wall's hoop (n = 2 shell) mode along the bat, for hollow bats.
    hoop: HoopProfile,
}

impl ModeSet {
    /// Solves the eigenproblem for `bat`, keeping at most `max_modes` vibrational modes (plus the two rigid ones).
    pub fn compute(bat: &Bat, max_modes: usize) -> Result<ModeSet, PhysicsError> {
        Self::compute_with(bat, max_modes, LinkRule::default())
    }

    /// As [`ModeSet::compute`] with an explicit link property rule.
    pub fn compute_with(bat: &Bat, max_modes: usize, rule: LinkRule) -> Result<ModeSet, PhysicsError> {
        Self::compute_with_solver(bat, max_modes, rule, EigenSolver::Auto)
    }

    /// As [`ModeSet::compute_with`] with an explicit eigen-solver strategy.
    pub fn compute_with_solver(
        bat: &Bat,
        max_modes: usize,
        rule: LinkRule,
        solver: EigenSolver,
    ) -> Result<ModeSet, PhysicsError> {
        bat.validate()?;
        let slices = bat.slices();
        let n = slices.len();
        let dz = bat.actual_slice_length();
        let mp = mass_properties_of(&slices, bat.length());
        let keep = max_modes.min(2 * n - 2);

        let auto = solver == EigenSolver::Auto;
        let solver = match solver {
            EigenSolver::Auto if keep <= INVERSE_ITERATION_MAX_MODES || 2 * n > DENSE_MAX_SIZE => {
                EigenSolver::InverseIteration
            }
            EigenSolver::Auto => EigenSolver::Dense,
            other => other,
        };
        // Symmetric form A = M^{-1/2} K M^{-1/2}; its orthonormal eigenvectors x give v = M^{-1/2} x.
        let band = BandPencil::from_slices(&slices, dz, rule);
        let inv_sqrt_m = DVector::from_iterator(
            2 * n,
            slices.iter().map(|s| s.mass).chain(slices.iter().map(|s| s.rotary_inertia)).map(|m| 1.0 / m.sqrt()),
        );
        let (eigenvalues, eigenvectors) = if solver == EigenSolver::Dense {
            let beam = BeamMatrices::from_slices(&slices, dz, rule);
            let a = DMatrix::from_fn(2 * n, 2 * n, |r, c| beam.stiffness[(r, c)] * inv_sqrt_m[r] * inv_sqrt_m[c]);
            let eig = SymmetricEigen::try_new(a, 1e-14, 0)
                .ok_or_else(|| PhysicsError::Numerical("symmetric eigen-solver did not converge".into()))?;
            (eig.eigenvalues, Some(eig.eigenvectors))
        } else {
            (band_eigenvalues(&band, keep + 3), None)
        };
        let order = ascending_with_rigid_null_space(&eigenvalues)?;

        let rigid = rigid_modes(&slices, &mp);
        let mut modes = Vec::with_capacity(keep + 2);
        modes.extend(rigid.iter().cloned());
        for &idx in order.iter().skip(2).take(keep) {
            let (mut y, mut phi) = match &eigenvectors {
                Some(vectors) => {
                    let x = vectors.column(idx);
                    (
                        (0..n).map(|i| x[i] * inv_sqrt_m[i]).collect(),
                        (0..n).map(|i| x[n + i] * inv_sqrt_m[n + i]).collect(),
                    )
                }
                None => match band.inverse_iteration(eigenvalues[idx]) {
                    Ok(v) => v,
                    Err(_) if auto => return Self::compute_with_solver(bat, max_modes, rule, EigenSolver::Dense),
                    Err(e) => return Err(e),
                },
            };
            // M-orthogonalise against the exact rigid modes and the modes already kept, then renormalise.
            let norm = m_orthogonalise(&slices, &modes, &mut y, &mut phi);
            // Both solvers deliver unit-M-norm vectors that are already orthogonal to the kept ones; a vector
            // that loses norm here came from inverse iteration on (nearly) repeated eigenvalues.
            if eigenvectors.is_none() && auto && !(norm > 0.99) {
                return Self::compute_with_solver(bat, max_modes, rule, EigenSolver::Dense);
            }
            modes.push(unit_mode(&band, y, phi, norm)?);
        }
        Ok(ModeSet {
            name: bat.name.clone(),
            slices,
            slice_length: dz,
            length: bat.length(),
            mass_properties: mp,
            modes,
            hoop: HoopProfile::of(bat),
        })
    }

    /// Rigid-body mass properties of the discretised bat.
    pub fn mass_properties(&self) -> MassProperties {
        self.mass_properties
    }

    /// Vibrational frequencies, Hz, ascending (rigid modes excluded).
    pub fn frequencies_hz(&self) -> Vec<f64> {
        self.vibrational_modes().iter().map(Mode::frequency_hz).collect()
    }

    /// Node positions (zeros of the displacement) of vibrational mode `n` (1-based), m from the knob.
    /// Sign changes between neighbouring slice centres, linearly interpolated; empty if `n` is out of range.
    pub fn nodes(&self, n: usize) -> Vec<f64> {
        let Some(mode) = (n >= 1).then(|| self.modes.get(n + 1)).flatten() else { return Vec::new() };
        let y = &mode.displacement;
        let mut nodes = Vec::new();
        for i in 0..y.len().saturating_sub(1) {
            let (a, b) = (y[i], y[i + 1]);
            if a == 0.0 {
                nodes.push(self.slices[i].z);
            } else if a * b < 0.0 {
                let t = a / (a - b);
                nodes.push(self.slices[i].z + t * self.slice_length);
            }
        }
        nodes
    }

    /// Length of the bat, m.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Name of the bat the modes belong to.
    pub fn bat_name(&self) -> &str {
        &self.name
    }

    /// Slice thickness Δz, m.
    pub fn slice_length(&self) -> f64 {
        self.slice_length
    }

    /// The slices of the discretised bat (knob first).
    pub fn slices(&self) -> &[Slice] {
        &self.slices
    }

    /// Number of vibrational modes kept.
    pub fn vibrational_count(&self) -> usize {
        self.modes.len() - 2
    }

    /// The two exact rigid modes: [translation, rotation about the CM], mass-normalised.
    pub fn rigid_modes(&self) -> &[Mode] {
        &self.modes[..2]
    }

    /// The vibrational modes kept, ascending in frequency, mass-normalised.
    pub fn vibrational_modes(&self) -> &[Mode] {
        &self.modes[2..]
    }

    /// All modes: translation, rotation, then the vibrational ones.
    pub fn all_modes(&self) -> &[Mode] {
        &self.modes
    }

    /// Interpolation weights of `z`: (i, t) such that f(z) = (1−t)·f_i + t·f_{i+1} over slice centres
    /// (linear extrapolation in the half slices at both ends).
    pub fn interpolation(&self, z: f64) -> (usize, f64) {
        let n = self.slices.len();
        let s = z / self.slice_length - 0.5;
        let i = (s.floor().max(0.0) as usize).min(n.saturating_sub(2));
        (i, s - i as f64)
    }

    /// Displacement of mode `index` (0 translation, 1 rotation, 2… vibrational) at `z`, per unit amplitude;
    /// 0 if `index` is out of range.
    pub fn shape_at(&self, index: usize, z: f64) -> f64 {
        let Some(mode) = self.modes.get(index) else { return 0.0 };
        let (i, t) = self.interpolation(z);
        (1.0 - t) * mode.displacement[i] + t * mode.displacement[i + 1]
    }

    /// The wall's hoop (n = 2 shell) mode at `z` (m from the knob), `None` where the section has no hoop
    /// compliance (solid, filled or wooden; see [`crate::hoop`]).
    pub fn hoop_at(&self, z: f64) -> Option<HoopMode> {
        self.hoop.at(z)
    }

    /// Hoop frequency of the wall at `z` (m from the knob), Hz; `None` where there is no hoop mode.
    pub fn hoop_frequency_at(&self, z: f64) -> Option<f64> {
        self.hoop.at(z).map(|h| h.frequency_hz())
    }

    /// Effective mass of mode `index` at `z`, kg: 1/Y(z)² for the mass-normalised shape (infinite at a node).
    pub fn effective_mass_at(&self, index: usize, z: f64) -> f64 {
        let y = self.shape_at(index, z);
        1.0 / (y * y)
    }

    /// Modal mass of mode `index` with its shape scaled to unit peak displacement, kg
    /// (Σ m y² + Σ J φ² for that scaling; 0 if `index` is out of range).
    pub fn modal_mass(&self, index: usize) -> f64 {
        let Some(mode) = self.modes.get(index) else { return 0.0 };
        let peak = mode.displacement.iter().fold(0.0_f64, |a, &v| a.max(v.abs()));
        if peak > 0.0 {
            1.0 / (peak * peak)
        } else {
            0.0
        }
    }
}

fn m_inner(slices: &[Slice], y1: &[f64], p1: &[f64], y2: &[f64], p2: &[f64]) -> f64 {
    slices.iter().enumerate().map(|(i, s)| s.mass * y1[i] * y2[i] + s.rotary_inertia * p1[i] * p2[i]).sum()
}

/// Exact, mass-normalised rigid modes: translation y = 1/√M, and rotation about the CM
/// y = (z − z_cm)/√I, φ = 1/√I.
fn rigid_modes(slices: &[Slice], mp: &MassProperties) -> [Mode; 2] {
    let n = slices.len();
    let st = 1.0 / mp.mass.sqrt();
    let sr = 1.0 / mp.moment_of_inertia.sqrt();
    [
        Mode { angular_frequency: 0.0, displacement: vec![st; n], rotation: vec![0.0; n] },
        Mode {
            angular_frequency: 0.0,
            displacement: slices.iter().map(|s| (s.z - mp.center_of_mass) * sr).collect(),
            rotation: vec![sr; n],
        },
    ]
}
