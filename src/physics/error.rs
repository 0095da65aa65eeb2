//! Typed errors of the physics core; every message names the field and its allowed range.

/// An input the physics core refuses, or a computation that could not produce a finite result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// A numeric field is NaN, infinite or outside its allowed range.
    #[error("{field} = {value} is out of range: expected {allowed}")]
    OutOfRange { field: String, value: f64, allowed: String },
    /// The bat's profile is malformed (too few stations, z not strictly increasing, inner ≥ outer, …).
    #[error("bad bat profile: {0}")]
    BadProfile(String),
    /// No built-in preset has this name.
    #[error("unknown bat preset '{name}' (known: {known})")]
    UnknownPreset { name: String, known: String },
    /// No built-in ball has this name.
    #[error("unknown ball preset '{name}' (known: {known})")]
    UnknownBallPreset { name: String, known: String },
    /// The impact point is not on the bat.
    #[error("impact_z = {impact_z} m is off the bat: expected {min} ≤ impact_z ≤ {max} m")]
    ImpactOffBat { impact_z: f64, min: f64, max: f64 },
    /// A numerical procedure failed (eigen-solver, integration that never separated, non-finite state).
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl PhysicsError {
    /// Builds an [`PhysicsError::OutOfRange`] for `field`.
    pub fn out_of_range(field: impl Into<String>, value: f64, allowed: impl Into<String>) -> Self {
        PhysicsError::OutOfRange { field: field.into(), value, allowed: allowed.into() }
    }
}
