//! The rigid-bat (Brody) model: closed-form exit speed and its optimum impact point.

use super::PhysicsError;

/// A bat reduced to rigid-body parameters plus an effective COR (the seed's Tables 1 and 2).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RigidBat {
    /// Name.
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Length, m.
    pub length: f64,
    /// Centre of mass, m from the knob.
    pub center_of_mass: f64,
    /// Moment of inertia about the centre of mass, kg·m².
    pub moment_of_inertia: f64,
    /// Effective COR used in the closed form.
    pub effective_cor: f64,
}

impl RigidBat {
    /// Names of the seed's rigid-parameter bats.
    pub fn preset_names() -> &'static [&'static str] {
        todo!("physics")
    }

    /// A seed table bat by name.
    pub fn preset(name: &str) -> Result<RigidBat, PhysicsError> {
        let _ = name;
        todo!("physics")
    }
}
