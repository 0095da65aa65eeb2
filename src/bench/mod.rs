//! `sweetspot bench`: end-to-end measurements of the node over DDS on loopback, against a raw ros2-client
//! echo of the same messages, plus the recorder against `dd` and the node's memory.
//!
//! Both the node and the raw echo run as **child processes** of the bench (this executable with `node` and
//! with `bench --echo-server`), each on its own DDS domain, and the same in-process client (a ros2-client
//! node) drives both: it publishes `Swing`s on `/swing` at a paced rate and takes `ExitVelocity`s from
//! `/exit_velocity`, matching them by `swing_id`. The raw echo answers each `Swing` with an `ExitVelocity`
//! carrying the same ids straight from its receive task, so the two paths differ only by what the node does
//! (queueing, physics, in-order publication, recording, the second result topic).
//!
//! Latency is measured from just before `publish` to the moment the client's receive task takes the answer
//! (both in the client process, monotonic clock), into an HDR histogram (µs, 3 significant digits).

//!
//! Parts: [`servers`] (the raw echo and the recording node as child processes), [`client`] (the paced
//! driver and its latency histogram), [`full`] (everything in order: latency, [`sustained`] rate search,
//! [`soak`] memory, [`recorder`] against `dd`), [`latency`] (the interleaved latency comparison),
//! [`machine`] and [`tables`] (the machine line and the text reports), [`foxglove`] (a Foxglove client
//! attached to the node's live server, `--foxglove-client`).

mod client;
mod foxglove;
mod full;
mod latency;
mod machine;
mod recorder;
mod servers;
mod soak;
mod sustained;
mod tables;

use std::path::PathBuf;
use std::time::Duration;

use anyhow::Context as _;

use crate::msgs::std_msgs::msg::Header;
use crate::msgs::sweetspot_msgs::msg::Swing;

pub use client::{Client, RunResult};
pub use foxglove::{ClientCounts, ClientMode, LiveClient};
pub use full::{run, BenchReport};
pub use latency::{run_latency_interleaved, InterleavedReport, InterleavedTarget};
pub use machine::{loadavg, machine};
pub use recorder::{
    bench_streams, disk_bench, disk_bench_one, disk_bench_with, storage_spec, BenchMessage, DiskResult, BENCH_PAYLOADS,
};
pub use servers::run_echo_server;
pub use soak::{proc_status_kb, MemoryResult};
pub use sustained::StepResult;
pub use tables::{disk_table, interleaved_table, table};

/// What to measure and where.
#[derive(Debug, Clone)]
pub struct BenchOptions {
    /// Short runs (the whole bench in under a minute).
    pub quick: bool,
    /// Scratch directory on the disk under test (bags, the `dd` file); created if missing.
    pub work_dir: PathBuf,
    /// First of the two DDS domains used (node on it, raw echo on the next).
    pub domain: u16,
    /// The `sweetspot` executable to start as node and echo server.
    pub exe: PathBuf,
    /// Soak duration for the RSS-flatness measurement.
    pub soak: Duration,
    /// More nodes for [`run_latency_interleaved`], as (label, executable): e.g. the build before a change,
    /// measured in the same interleaved blocks as this one and the raw echo.
    pub compare: Vec<(String, PathBuf)>,
    /// Executable started as the node by [`run`] (default `exe`), e.g. an older build to compare with.
    pub node_exe: Option<PathBuf>,
    /// [`run`] measures only the sustained-rate search (no latency comparison, soak or recorder bench).
    pub sustained_only: bool,
    /// Rates of [`run_latency_interleaved`] (empty: [`LATENCY_RATES`]), swings/s.
    pub latency_rates: Vec<u32>,
    /// Seconds per server and rate in [`run_latency_interleaved`] (default 20 s at ≤ 100/s, else 5 s): longer
    /// runs put more of the VM's rare stalls into every server's p99, so the ratios spread less.
    pub latency_seconds: Option<f64>,
    /// A Foxglove client attached to the node's live server: in [`run_latency_interleaved`] an extra node
    /// (`node+foxglove`) of the same executable carries it, measured in the same blocks as the bare one; in
    /// [`run`] the node itself carries it.
    pub foxglove_client: Option<ClientMode>,
}

/// The rates of the latency comparison.
pub const LATENCY_RATES: [u32; 3] = [100, 1_000, 10_000];

/// A swing the default bat and ball answer (the node computes the collision; the echo just copies ids).
pub fn bench_swing(id: u64) -> Swing {
    Swing {
        header: Header::default(),
        swing_id: id,
        bat_id: String::new(),
        ball_id: String::new(),
        ball_speed: 40.0,
        bat_cm_speed: 20.0,
        bat_angular_speed: 50.0,
        impact_z: 0.55 + (id % 16) as f64 * 0.005,
        measured_exit_speed: f64::NAN,
        ..Swing::default()
    }
}

/// How long a run waits for a missing answer before it counts as lost.
const QUIET: Duration = Duration::from_secs(3);

/// Seconds of one latency run at `rate` (low rates run longer to collect as many samples of the tail).
fn run_seconds(quick: bool, rate: u32) -> f64 {
    match (quick, rate) {
        (true, r) if r <= 100 => 2.0,
        (true, _) => 1.0,
        (false, r) if r <= 100 => 20.0,
        (false, _) => 5.0,
    }
}

/// Swings in `seconds` at `rate`, at least ten.
fn count_for(rate: u32, seconds: f64) -> u64 {
    ((f64::from(rate) * seconds).round() as u64).max(10)
}

/// A progress line on stderr, with the time (the report itself goes to stdout).
fn log(msg: &str) {
    eprintln!("[bench {}] {msg}", chrono::Utc::now().format("%H:%M:%S"));
}

/// Refuses to run DDS unless in a private network namespace whose only interface is `lo`.
pub fn require_private_network() -> anyhow::Result<()> {
    crate::ros::network_guard()
        .context("sweetspot bench runs DDS only inside a private network namespace (use scripts/bench)")?;
    Ok(())
}
