//! sweetspot's analyses of recorded and measured swings: everything between a bag (or a tracker's export) and
//! an answer a person reads, with no DDS, no async runtime and no server.
//!
//! - [`answer`]: the documents `simulate`, `bbcor`, `compare` and `modes` answer with (the command line
//!   prints them, the Python package returns them), from the inputs they share ([`answer::inputs`]);
//! - [`bat_file`]: the bat file format (TOML, with its profile inline or in a CSV beside it);
//! - [`report`]: tables, JSON documents, plots and the seed's figures;
//! - [`import`]: tracker exports (TrackMan, Statcast, HitTrax, mapped CSV) into bags of swings;
//! - [`calibrate`]: fitting the ball's COR, the tangential contact and batters to recorded swings;
//! - [`locate`]: where on the bat each recorded ball was hit;
//! - [`validate`]: the model against published measurements;
//! - [`rig`]: a simulated test rig's sessions of swings (its DDS publisher lives with the node).
//!
//! It builds on [`sweetspot_physics`], [`sweetspot_msgs`], [`sweetspot_model`] and [`sweetspot_bag`].
pub mod answer;
pub mod bat_file;
pub mod calibrate;
pub mod import;
pub mod locate;
pub mod report;
pub mod rig;
pub mod validate;
