//! Derived metrics: sweet-spot set, BBCOR / BESR, exit speed swept over impact points.

use super::{Ball, CollisionOptions, CollisionResult, Impact, ModeSet, PhysicsError};

/// The several "sweet spots" of a bat for one swing, m from the knob.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweetSpotSet {
    /// Impact point of maximum flexible-bat exit speed, m.
    pub max_exit_speed_z: f64,
    /// That maximum exit speed, m/s.
    pub max_exit_speed: f64,
    /// The seed's closed-form rigid optimum, m.
    pub rigid_optimum_z: f64,
    /// Node of the first vibrational mode nearest the barrel, m.
    pub node1_z: f64,
    /// Node of the second vibrational mode nearest the barrel, m.
    pub node2_z: f64,
    /// Centre of percussion for a pivot 6 in (0.1524 m) from the knob, m.
    pub center_of_percussion_z: f64,
}

/// One point of an exit-speed sweep.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweepPoint {
    /// Impact point, m from the knob.
    pub impact_z: f64,
    /// The collision at that point.
    pub result: CollisionResult,
}

/// Exit speed over `impact_zs`, run in parallel; `template` gives the speeds (its impact_z is ignored).
pub fn sweep(
    modes: &ModeSet,
    ball: &Ball,
    template: &Impact,
    impact_zs: &[f64],
    options: &CollisionOptions,
) -> Result<Vec<SweepPoint>, PhysicsError> {
    let _ = (modes, ball, template, impact_zs, options);
    todo!("physics")
}

/// The sweet-spot set of `modes` for the swing `template`.
pub fn sweet_spots(
    modes: &ModeSet,
    ball: &Ball,
    template: &Impact,
    options: &CollisionOptions,
) -> Result<SweetSpotSet, PhysicsError> {
    let _ = (modes, ball, template, options);
    todo!("physics")
}

/// BBCOR of `modes` per the NCAA protocol implemented here (see the function body docs).
pub fn bbcor(modes: &ModeSet, options: &CollisionOptions) -> Result<f64, PhysicsError> {
    let _ = (modes, options);
    todo!("physics")
}
