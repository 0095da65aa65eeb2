//! The node's topic names, relative (they move with `-r __ns:=`), except `/diagnostics`. The node subscribes
//! and publishes under them; `bag export` and `bag replay` find a recorded topic's namespace by them.

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
/// SweetSpot out (latched).
pub const SWEET_SPOT: &str = "sweet_spot";
/// DiagnosticArray out.
pub const DIAGNOSTICS: &str = "/diagnostics";
