//! The ROS 2 shell (`sweetspot node`): topics, QoS, parameters, diagnostics, recording.
//!
//! Data flows one way: message → physics → result → publish + record. What a message means and what a swing
//! is answered with is decided by [`crate::model`] (conversions, registry, planning, computing); the node's
//! own pure parts ([`settings`], [`stats`], [`convert`], [`pipeline`], [`recording`]) are plain functions and
//! threads tested without DDS; the DDS wiring lives in [`runtime`], the receive loop and its handlers in
//! `receive_loop`.
//!
//! ```text
//! sweetspot node [--no-record] [--ros-args -r __ns:=/rig3 -r __node:=NAME -r FROM:=TO -p NAME:=VALUE --params-file FILE]
//! ```
//!
//! # Topics (relative names move with `-r __ns:=`)
//!
//! | topic            | type                               | direction | QoS                                           |
//! |------------------|------------------------------------|-----------|-----------------------------------------------|
//! | `bat/params`     | sweetspot_msgs/BatParams           | in        | reliable, transient-local (late joiners get it) |
//! | `ball/params`    | sweetspot_msgs/BallParams          | in        | reliable, transient-local                     |
//! | `swing`          | sweetspot_msgs/Swing               | in        | reliable, keep-last 1000 (reader cache = `queue_capacity`) |
//! | `exit_velocity`  | sweetspot_msgs/ExitVelocity        | out       | reliable; one per swing taken, in swing order; REJECTED + reason for bad input; DROPPED (at once) when the queue is full |
//! | `modal_energies` | sweetspot_msgs/ModalEnergies       | out       | reliable; one per OK swing, published while a subscription is matched, always recorded |
//! | `sweet_spot`     | sweetspot_msgs/SweetSpot           | out       | reliable, transient-local; on every bat change |
//! | `swing_scene`    | visualization_msgs/MarkerArray     | out       | reliable; one per OK swing ([`crate::model::scene`]); DDS and recorded with `swing_scene:=true`, Foxglove always |
//! | `/diagnostics`   | diagnostic_msgs/DiagnosticArray    | out       | 1 Hz (`diagnostics_period`)                   |
//! | `/rosout`        | rcl_interfaces/Log                 | out       | ros2-client's rosout (and the Foxglove server's, with `foxglove_port`) |
//!
//! Service: `~/simulate_swing` (sweetspot_msgs/srv/SimulateSwing), one answer per call with the node's
//! registry and settings, not a swing of the session ([`service`]).
//!
//! # Behaviour
//!
//! - A swing's bat/ball: its `bat_id`/`ball_id`, empty = the latest received, before any params the
//!   `default_bat` (preset `r161`) and the regulation `baseball`; any preset name is a valid bat_id.
//! - Modes are computed once per bat (on first use, off the DDS thread) and cached; new params for a bat_id
//!   replace its entry and publish a new SweetSpot. A swing's bat and ball are resolved when the node takes it
//!   from DDS, so swings already taken keep the params they were taken with. Params are taken ahead of
//!   swings, but first every swing already waiting whose DDS source timestamp is earlier than the params' is
//!   taken (`take_swings_sent_before`): the swings one publisher sent before its params are answered with the
//!   old ones, those sent after with the new (across publishers, their clocks decide).
//! - At most `max_bats` bats and `max_balls` balls are kept ([`crate::model::lru::LruMap`]): the least recently used is
//!   forgotten first, never the latest received; a swing naming a forgotten id is REJECTED saying so (a
//!   preset is solved again instead); evictions are warned about and counted on /diagnostics. A BatParams of
//!   more than `max_bat_slices` slices is REJECTED before its modes are solved.
//! - Collisions run on `workers` threads behind a bounded pipeline of `queue_capacity` swings in flight;
//!   results are published in swing order. A swing that finds the pipeline idle and its bat's modes solved
//!   is answered on the receive task itself ([`pipeline::Pipeline::answer_inline`], paced by
//!   [`pipeline::InlinePacing`] to half that task's time), which saves two thread wake-ups per answer. Its
//!   ExitVelocity publish then runs on the receive task. A subscriber that stops acknowledging holds it once
//!   8,192 results are unacknowledged (RustDDS's reliable window): each publish then waits up to 500 ms and
//!   fails, counted and logged, until that reader's lease expires (docs/node.md, "What the node promises").
//! - ModalEnergies are published only while the topic has a matched subscription (re-checked on every
//!   discovery event; `modal_energies_published` on /diagnostics, and `modal_energies_unsent` apart from the
//!   swing's answer) and recorded always: a DDS write costs every answer latency even with no reader. A swing
//!   arriving when the pipeline is full is dropped, counted (`swings_dropped`), warned about on /rosout
//!   (rate-limited) and answered at once with status DROPPED, without waiting for room in the send window (so
//!   every swing taken gets exactly one answer); gaps in a publisher's DDS sequence numbers are counted as
//!   `swings_lost_in_transport` (those swings never reached the node and get no answer). A failed publish
//!   is counted (`publish_failures`) and logged, rate-limited, with DDS's reason.
//! - Bad params are answered by an ExitVelocity REJECTED naming the message, id and field; the previous
//!   params stay in force. Bad swings get REJECTED with the physics' error text; numbers are NaN.
//! - One verdict per swing, decided before anything is computed or published
//!   ([`crate::model::convert::plan_swing_message`]): a swing whose strings or measured speed are refused (a
//!   `header.frame_id` over 256 bytes, say) is REJECTED, gets no ModalEnergies or scene, on DDS or in the bag,
//!   and counts as `swings_rejected`. Every id and `frame_id` an answer echoes is at most 256 bytes
//!   ([`crate::model::limits::echo`]), so no input can make an answer too large to send.
//! - Latency (p50/p99/max on /diagnostics and in the summary) counts from the last moment the swing reader
//!   was seen empty (drained, or the loop idle), not from when the loop took the swing: time the receive loop
//!   spent on other work while a swing waited is in it (an upper bound on the wait, exact when idle).
//! - Every input (as received) and output (as published) is recorded in-process to a rosbag2 MCAP directory,
//!   `bags/<node>_<UTC time>/` unless `record_path` is set, off with `--no-record` or `-p record:=false`.
//!   The default directory gets a suffix (`_2`, `_3`, …) when it already exists, so two nodes started
//!   within one second never share one ([`recording::start_backend_unique`]).
//! - SIGINT/SIGTERM: stop taking swings, let queued ones finish for up to 0.6 s, close the bag, print (once,
//!   whatever the log level; also on /rosout) a summary (`summary_line`: swings received = answered OK + rejected + dropped + unsent
//!   (publish failed) + still queued at shutdown; lost in transport, latency p50/p99/max, mode-cache
//!   hits/misses) and exit 0.
//! - Liveness: every diagnostics tick asks whether the DDS participant's background threads still run
//!   (RustDDS `is_alive`, through the `receive_loop::Liveness` seam a test can make report dead). When they
//!   stopped, the node can no longer send or receive: it logs an ERROR saying so, publishes a /diagnostics
//!   ERROR (best effort), shuts down as on SIGINT (bag closed with its summary) and exits non-zero.
//! - Another participant announcing a node with our fully-qualified name (read from `ros_discovery_info`)
//!   is warned about on /rosout, and /diagnostics is at least WARN (`duplicate_node_name`) while it stays.
//!
//! # Parameters
//!
//! See [`settings::PARAMETERS`] (name, unit, meaning, default, range: what `ros2 param describe` shows); the
//! read-only ones ([`settings::is_read_only`]) are refused by `ros2 param set` on a running node.

pub mod convert;
mod live_settings;
mod outputs;
pub mod pipeline;
mod receive_loop;
pub mod recording;
/// The `--ros-args` parser now lives in the shared DDS layer ([`crate::ros::args`]); this path stays for callers.
pub use crate::ros::args as ros_args;
pub mod runtime;
pub mod service;
pub mod settings;
pub mod stats;
pub mod type_description;
