//! Normal modes of the free–free, non-uniform Timoshenko beam (symmetric K, diagonal M).

use super::{Bat, MassProperties, PhysicsError};

/// One normal mode, mass-normalised (Σ m_i y_i² + Σ J_i φ_i² = 1 kg·m²… see docs of ModeSet).
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// Angular frequency ω, rad/s (0 for the two rigid-body modes).
    pub angular_frequency: f64,
    /// Transverse displacement at each slice centre, per unit modal amplitude.
    pub displacement: Vec<f64>,
    /// Rotation φ of each slice, rad per unit modal amplitude.
    pub rotation: Vec<f64>,
}

/// The normal modes of one bat, computed once and reused for every swing.
#[derive(Debug, Clone)]
pub struct ModeSet {
    _private: (),
}

impl ModeSet {
    /// Solves the eigenproblem for `bat`, keeping at most `max_modes` vibrational modes (plus the two rigid ones).
    pub fn compute(bat: &Bat, max_modes: usize) -> Result<ModeSet, PhysicsError> {
        let _ = (bat, max_modes);
        todo!("physics: modes")
    }

    /// Rigid-body mass properties of the discretised bat.
    pub fn mass_properties(&self) -> MassProperties {
        todo!("physics")
    }

    /// Vibrational frequencies, Hz, ascending (rigid modes excluded).
    pub fn frequencies_hz(&self) -> Vec<f64> {
        todo!("physics")
    }

    /// Node positions (zeros of the displacement) of vibrational mode `n` (1-based), m from the knob.
    pub fn nodes(&self, n: usize) -> Vec<f64> {
        let _ = n;
        todo!("physics")
    }

    /// Length of the bat, m.
    pub fn length(&self) -> f64 {
        todo!("physics")
    }
}
