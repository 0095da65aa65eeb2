//! Typed errors of the physics core; every message names the field and its allowed range.

/// An input the physics core refuses, or a computation that could not produce a finite result.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PhysicsError {
    /// A numeric field is NaN, infinite or outside its allowed range.
    #[error("{field} = {} is out of range: expected {allowed}", readable(*.value))]
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
    #[error("impact_z = {} m is off the bat: expected {min} ≤ impact_z ≤ {max} m", readable(*.impact_z))]
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

/// `v` for a message: plain decimals for 1e-4 ≤ |v| < 1e6 (and 0), else shortest scientific (`1e300`), so that
/// no number in an error text runs to hundreds of digits.
pub fn readable(v: f64) -> impl std::fmt::Display {
    struct Readable(f64);
    impl std::fmt::Display for Readable {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            let magnitude = self.0.abs();
            if magnitude == 0.0 || !magnitude.is_finite() || (1e-4..1e6).contains(&magnitude) {
                write!(f, "{}", self.0)
            } else {
                write!(f, "{:e}", self.0)
            }
        }
    }
    Readable(v)
}
