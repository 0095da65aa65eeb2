//! The ball: a nonlinear hysteretic spring (loading k1·u^α, unloading k2·u^β).

use super::PhysicsError;

/// A ball, SI units. Loading force k1·u^α; unloading k2·u^β with β = (1+α)/e0² − 1.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ball {
    /// Mass, kg.
    pub mass: f64,
    /// Radius, m.
    pub radius: f64,
    /// Loading stiffness k1, N/m^α.
    pub stiffness: f64,
    /// Loading exponent α, dimensionless.
    pub exponent: f64,
    /// Coefficient of restitution e0 against a rigid wall, in (0, 1].
    pub cor: f64,
}

impl Default for Ball {
    /// A regulation baseball: 0.145 kg, 0.0366 m, k1 = 6.53e7 N/m^α, α = 1.84, e0 = 0.53.
    fn default() -> Self {
        Ball {
            mass: 0.145,
            radius: 0.0366,
            stiffness: 6.53e7,
            exponent: 1.84,
            cor: 0.53,
        }
    }
}

impl Ball {
    /// Checks every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), PhysicsError> {
        todo!("physics: validate ball")
    }
}
