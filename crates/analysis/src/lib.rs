//! sweetspot's analyses of recorded and measured swings: everything between a bag (or a tracker's export) and
//! an answer a person reads, with no DDS, no async runtime and no server.
//!
//! - [`report`]: tables, JSON documents, plots and the seed's figures;
//! - [`import`]: tracker exports (TrackMan, Statcast, HitTrax, mapped CSV) into bags of swings;
//! - [`calibrate`]: fitting the ball's COR, the tangential contact and batters to recorded swings;
//! - [`locate`]: where on the bat each recorded ball was hit;
//! - [`validate`]: the model against published measurements;
//! - [`rig`]: a simulated test rig's sessions of swings (its DDS publisher lives with the node).
//!
//! It builds on [`sweetspot_physics`], [`sweetspot_msgs`], [`sweetspot_model`] and [`sweetspot_bag`].
pub mod calibrate;
pub mod import;
pub mod locate;
pub mod report;
pub mod rig;
pub mod validate;
