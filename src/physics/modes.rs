//! Normal modes of the free–free, non-uniform Timoshenko beam (symmetric K, diagonal M).
//!
//! The derivation (energy method, link convention, and its check against Nathan's own matrix) is in the
//! module docs of [`crate::physics`]. Coordinates are ordered `[y_1 … y_N, φ_1 … φ_N]`; y_i is the transverse
//! displacement of slice i's centre (m) and φ_i its rotation (rad, positive in the sense of +dy/dz).

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use super::bat::{mass_properties_of, Slice};
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
        for i in 0..n.saturating_sub(1) {
            let (a, b) = (&slices[i], &slices[i + 1]);
            let (yi, sa) = match rule {
                LinkRule::KnobSide => (a.bending_stiffness, a.shear_stiffness),
                LinkRule::Mean => (
                    0.5 * (a.bending_stiffness + b.bending_stiffness),
                    0.5 * (a.shear_stiffness + b.shear_stiffness),
                ),
            };
            // Bending: ½ (YI) Δz ((φ_{i+1} − φ_i)/Δz)².
            let kb = yi / dz;
            let (p, q) = (n + i, n + i + 1);
            k[(p, p)] += kb;
            k[(q, q)] += kb;
            k[(p, q)] -= kb;
            k[(q, p)] -= kb;
            // Shear: ½ (SA) Δz (gᵀx/Δz)² with gᵀx = y_{i+1} − y_i − Δz (φ_i + φ_{i+1})/2.
            let ks = sa / dz;
            let g = [(i, -1.0), (i + 1, 1.0), (p, -0.5 * dz), (q, -0.5 * dz)];
            for &(r, gr) in &g {
                for &(c, gc) in &g {
                    k[(r, c)] += ks * gr * gc;
                }
            }
        }
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
}

impl ModeSet {
    /// Solves the eigenproblem for `bat`, keeping at most `max_modes` vibrational modes (plus the two rigid ones).
    pub fn compute(bat: &Bat, max_modes: usize) -> Result<ModeSet, PhysicsError> {
        Self::compute_with(bat, max_modes, LinkRule::default())
    }

    /// As [`ModeSet::compute`] with an explicit link property rule.
    pub fn compute_with(bat: &Bat, max_modes: usize, rule: LinkRule) -> Result<ModeSet, PhysicsError> {
        bat.validate()?;
        let slices = bat.slices();
        let n = slices.len();
        let dz = bat.actual_slice_length();
        let beam = BeamMatrices::from_slices(&slices, dz, rule);
        let mp = mass_properties_of(&slices, bat.length());
        let keep = max_modes.min(2 * n - 2);

        // Symmetric form A = M^{-1/2} K M^{-1/2}; its orthonormal eigenvectors x give v = M^{-1/2} x.
        let inv_sqrt_m = beam.mass.map(|m| 1.0 / m.sqrt());
        let a = DMatrix::from_fn(2 * n, 2 * n, |r, c| beam.stiffness[(r, c)] * inv_sqrt_m[r] * inv_sqrt_m[c]);
        let eig = SymmetricEigen::try_new(a, 1e-14, 0)
            .ok_or_else(|| PhysicsError::Numerical("symmetric eigen-solver did not converge".into()))?;
        let mut order: Vec<usize> = (0..2 * n).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        let lambda_max = eig.eigenvalues.iter().fold(0.0_f64, |acc, &l| acc.max(l.abs()));
        // The two rigid modes must be numerically zero and well separated from the first vibration.
        let zero_tol = 1e-9 * lambda_max;
        if !(eig.eigenvalues[order[0]].abs() <= zero_tol && eig.eigenvalues[order[1]].abs() <= zero_tol)
            || (n >= 2 && 2 * n > 2 && eig.eigenvalues[order[2]] <= zero_tol)
        {
            return Err(PhysicsError::Numerical(format!(
                "stiffness null space is not exactly the two rigid modes (lowest eigenvalues {:e}, {:e}, {:e})",
                eig.eigenvalues[order[0]],
                eig.eigenvalues[order[1]],
                eig.eigenvalues.get(order[2]).copied().unwrap_or(f64::NAN)
            )));
        }

        let rigid = rigid_modes(&slices, &mp);
        let mut modes = Vec::with_capacity(keep + 2);
        modes.extend(rigid.iter().cloned());
        for &idx in order.iter().skip(2).take(keep) {
            let x = eig.eigenvectors.column(idx);
            let mut y: Vec<f64> = (0..n).map(|i| x[i] * inv_sqrt_m[i]).collect();
            let mut phi: Vec<f64> = (0..n).map(|i| x[n + i] * inv_sqrt_m[n + i]).collect();
            // M-orthogonalise against the exact rigid modes, then renormalise.
            for r in &rigid {
                let c = m_inner(&slices, &y, &phi, &r.displacement, &r.rotation);
                for i in 0..n {
                    y[i] -= c * r.displacement[i];
                    phi[i] -= c * r.rotation[i];
                }
            }
            let norm = m_inner(&slices, &y, &phi, &y, &phi).sqrt();
            // Deterministic sign: positive displacement at the barrel end.
            let sign = if y[n - 1] < 0.0 { -1.0 } else { 1.0 };
            let scale = sign / norm;
            y.iter_mut().for_each(|v| *v *= scale);
            phi.iter_mut().for_each(|v| *v *= scale);
            let omega = eig.eigenvalues[idx].max(0.0).sqrt();
            if !(omega.is_finite() && norm.is_finite() && norm > 0.0) {
                return Err(PhysicsError::Numerical("non-finite mode from the eigen-solver".into()));
            }
            modes.push(Mode { angular_frequency: omega, displacement: y, rotation: phi });
        }
        Ok(ModeSet { name: bat.name.clone(), slices, slice_length: dz, length: bat.length(), mass_properties: mp, modes })
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
    slices
        .iter()
        .enumerate()
        .map(|(i, s)| s.mass * y1[i] * y2[i] + s.rotary_inertia * p1[i] * p2[i])
        .sum()
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
