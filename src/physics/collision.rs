//! Ball–bat collision in modal space: fixed-step RK4 from first contact to separation.

use super::{Ball, ModeSet, PhysicsError};

/// Initial conditions of one collision (conventions in the module docs of [`crate::physics`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Impact {
    /// Ball speed toward the bat, m/s.
    pub ball_speed: f64,
    /// Bat centre-of-mass speed toward the ball, m/s.
    pub bat_cm_speed: f64,
    /// Bat angular speed about its centre of mass, rad/s, positive when the barrel leads.
    pub bat_angular_speed: f64,
    /// Impact point, m from the knob.
    pub impact_z: f64,
}

/// Numerical options of a collision.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CollisionOptions {
    /// Number of vibrational modes integrated (default 18).
    pub modes: usize,
    /// RK4 time step, s (default 5 µs).
    pub time_step: f64,
}

impl Default for CollisionOptions {
    fn default() -> Self {
        CollisionOptions {
            modes: 18,
            time_step: 5e-6,
        }
    }
}

/// Energy left in one vibrational mode after separation.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModeEnergy {
    /// Mode frequency, Hz.
    pub frequency: f64,
    /// Energy after separation, J.
    pub energy: f64,
}

/// Where the initial kinetic energy went, J.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct EnergyBudget {
    /// Total kinetic energy before contact, J.
    pub initial: f64,
    /// Ball kinetic energy after separation, J.
    pub ball: f64,
    /// Bat rigid-body (translation + rotation) kinetic energy after separation, J.
    pub bat_rigid: f64,
    /// Vibrational energy of the bat after separation, J.
    pub vibration: f64,
    /// Energy dissipated by the ball's hysteresis, J.
    pub hysteresis_loss: f64,
    /// initial − (ball + bat_rigid + vibration + hysteresis_loss), J.
    pub residual: f64,
}

/// Outcome of one collision, SI units.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CollisionResult {
    /// Ball exit speed away from the bat, m/s.
    pub exit_speed: f64,
    /// Exit speed from the closed-form rigid-bat formula with the ball's e0, m/s.
    pub rigid_exit_speed: f64,
    /// Effective COR e_eff of the flexible bat at this impact point.
    pub effective_cor: f64,
    /// Collision efficiency e_A = (exit_speed − bat speed at impact)/(ball_speed + bat speed at impact).
    pub collision_efficiency: f64,
    /// Contact time, s.
    pub contact_time: f64,
    /// Peak contact force, N.
    pub peak_force: f64,
    /// Impulse delivered to the ball, N·s.
    pub impulse: f64,
    /// Maximum compression of the ball, m.
    pub max_compression: f64,
    /// Energy in each integrated vibrational mode after separation.
    pub mode_energies: Vec<ModeEnergy>,
    /// The energy budget and its residual.
    pub energy: EnergyBudget,
}

/// Runs one collision of `ball` with the bat described by `modes`.
pub fn collide(
    modes: &ModeSet,
    ball: &Ball,
    impact: &Impact,
    options: &CollisionOptions,
) -> Result<CollisionResult, PhysicsError> {
    let _ = (modes, ball, impact, options);
    todo!("physics: collide")
}
