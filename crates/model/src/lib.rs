//! The model: how sweetspot's messages become physics and back, and the state that decides what a swing is
//! answered with. Everything here is pure and synchronous (no DDS, no files); it sits between
//! [`sweetspot_physics`] and everything that serves it.
//!
//! - [`convert`]: BatParams/BallParams → Bat/Ball (validated, the one rule set), Bat → BatParams, Swing →
//!   Impact, results → ExitVelocity / ModalEnergies / SweetSpot;
//! - [`engine`]: the bat/ball [`engine::Registry`] (bounded by [`lru::LruMap`]), swing planning
//!   ([`engine::plan_swing`]), computing ([`engine::compute`]) and bat summaries ([`engine::summarize_bat`]);
//! - [`settings`]: [`settings::ModelSettings`] (time step, default bat and modes, limits) and the rosbag2
//!   `custom_data` keys it is recorded under;
//! - [`limits`]: the longest strings and profiles a peer may send, what rejection texts quote of them, the
//!   physical limits of a ball's compression and a measured speed, and how numbers are printed;
//! - [`time`]: ROS `Time` ↔ Unix nanoseconds; [`topics`]: the node's topic names.
//! - [`scene`]: the swing drawn (a `visualization_msgs/MarkerArray` for Foxglove's 3D panel).
//!
//! Used by the node (live), `bag replay` and `bag export` (recorded), `calibrate` (fitting recorded swings),
//! the rig (its BatParams) and the fuzz targets, so that none of them can decide differently. It imports only
//! [`sweetspot_physics`] and [`sweetspot_msgs`].
//!
//! Two rules every layer above shares live here too: [`files`] (the files a user names: regular inputs under a
//! size cap, no output onto an input) and [`yaml`] (every YAML text loaded under a depth and alias budget).

pub mod convert;
pub mod engine;
pub mod files;
pub mod limits;
pub mod lru;
pub mod scene;
pub mod settings;
pub mod time;
pub mod topics;
pub mod yaml;
