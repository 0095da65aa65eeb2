//! The node's topic names, relative so `-r __ns:=` moves them, except `/diagnostics` and `/rosout`, which are
//! absolute by convention. Every program that talks to the node (the node itself, `pub`/`echo`, the rig, `bag
//! export`/`replay`) takes them from here.

/// BatParams in.
pub const BAT_PARAMS: &str = "bat/params";
/// BallParams in.
pub const BALL_PARAMS: &str = "ball/params";
/// Swing in.
pub const SWING: &str = "swing";
/// ExitVelocity out.
pub const EXIT_VELOCITY: &str = "exit_velocity";
/// ModalEnergies out.
pub const MODAL_ENERGIES: &str = "modal_energies";
/// visualization_msgs/MarkerArray out: the swing drawn (DDS with the `swing_scene` parameter; Foxglove always).
pub const SWING_SCENE: &str = "swing_scene";
/// SweetSpot out (latched).
pub const SWEET_SPOT: &str = "sweet_spot";
/// DiagnosticArray out.
pub const DIAGNOSTICS: &str = "/diagnostics";
/// rcl_interfaces/Log out (ros2-client's rosout).
pub const ROSOUT: &str = "/rosout";
