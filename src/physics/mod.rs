//! Pure, synchronous bat–ball physics in SI units: no I/O, no async, no ROS types.
//!
//! Conventions (used everywhere in sweetspot):
//! - `z` is measured in metres from the knob (handle end) along the bat's long axis;
//! - ball speed is positive toward the bat;
//! - bat centre-of-mass speed is positive toward the ball;
//! - bat angular speed (rad/s) is positive when the barrel end moves faster (toward the ball) than the handle;
//! - exit speed is positive away from the bat.
//!
//! Pipeline: [`bat::Bat`] → [`modes::ModeSet`] (computed once per bat) → [`collision::collide`] with a
//! [`ball::Ball`] and an [`collision::Impact`] → [`collision::CollisionResult`]; [`metrics`] builds sweet
//! spots, BBCOR/BESR and sweeps on top, and [`rigid`] holds the closed-form rigid-bat (Brody) model.

pub mod ball;
pub mod bat;
pub mod collision;
pub mod error;
pub mod metrics;
pub mod modes;
pub mod rigid;

pub use ball::Ball;
pub use bat::{Bat, CoreFill, MassProperties, Material, Slice, Station};
pub use collision::{collide, CollisionOptions, CollisionResult, EnergyBudget, Impact, ModeEnergy};
pub use error::PhysicsError;
pub use metrics::{BbcorReport, BesrReport, SweetSpotSet, SweepPoint};
pub use modes::{BeamMatrices, LinkRule, Mode, ModeSet};
pub use rigid::RigidBat;
