//! The whole bench in order: latency of the raw echo and of the node (one after the other), the node's
//! highest sustained rate, its memory over a soak, and the recorder against `dd`.

use std::collections::BTreeMap;
use std::time::Duration;

use anyhow::Context as _;

use super::client::{Client, RunResult};
use super::foxglove::{free_port, ClientCounts, LiveClient};
use super::machine::{machine, with_load_after};
use super::recorder::{disk_bench, DiskResult};
use super::servers::{start_echo, start_recording_node, stop};
use super::soak::{proc_status_kb, soak, MemoryResult};
use super::sustained::{sustained_search, StepResult};
use super::{count_for, log, require_private_network, run_seconds, BenchOptions, LATENCY_RATES, QUIET};

/// Everything one `sweetspot bench` run measured.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BenchReport {
    /// Machine and conditions.
    pub machine: BTreeMap<String, String>,
    /// Raw ros2-client echo at each rate.
    pub raw: Vec<RunResult>,
    /// The node (recording on) at each rate.
    pub node: Vec<RunResult>,
    /// node p99 / raw p99 at each rate.
    pub p99_ratio: Vec<(u32, f64)>,
    /// Sustained-rate search with recording on.
    pub steps: Vec<StepResult>,
    /// Highest sustained rate found, swings/s (0 if none).
    pub max_sustained_rate: u32,
    /// Memory.
    pub memory: MemoryResult,
    /// Recorder against dd: Swing and ExitVelocity, zstd and uncompressed.
    pub disk: Vec<DiskResult>,
    /// What the attached Foxglove client (`--foxglove-client`) read, if one was attached.
    pub foxglove_client: Option<ClientCounts>,
}

/// Runs every measurement once and returns the report.
pub fn run(opts: &BenchOptions) -> anyhow::Result<BenchReport> {
    require_private_network()?;
    std::fs::create_dir_all(&opts.work_dir).with_context(|| format!("creating {}", opts.work_dir.display()))?;
    let machine_before = machine();
    let latency_rates: &[u32] = if opts.sustained_only { &[] } else { &LATENCY_RATES };

    log("raw echo: starting");
    let echo = start_echo(&opts.exe, opts.domain + 1, &opts.work_dir)?;
    let mut raw_client = Client::new(opts.domain + 1)?;
    raw_client.warm_up(Duration::from_secs(30)).with_context(|| format!("raw echo: {}", echo.output()))?;
    let mut raw = Vec::new();
    for &rate in latency_rates {
        raw.push(latency_run(&mut raw_client, "raw ", rate, opts.quick)?);
    }
    drop(raw_client);
    stop(echo);

    log("node: starting (recording on)");
    let bag_dir = opts.work_dir.join(format!("node_bag_{}", std::process::id()));
    let node_exe = opts.node_exe.as_deref().unwrap_or(&opts.exe);
    log(&format!("node executable: {}", node_exe.display()));
    let port = opts.foxglove_client.map(|_| free_port()).transpose()?;
    let node = start_recording_node(node_exe, &bag_dir, opts.domain, &opts.work_dir, port)?;
    let mut client = Client::new(opts.domain)?;
    client.warm_up(Duration::from_secs(60)).with_context(|| format!("node: {}", node.output()))?;
    let viewer = match (opts.foxglove_client, port) {
        (Some(mode), Some(port)) => {
            let viewer = LiveClient::connect(port, mode, Duration::from_millis(500))
                .with_context(|| format!("node: {}", node.output()))?;
            log(&format!("node: Foxglove client ({mode:?}) subscribed to {} channels", viewer.counts().channels));
            Some(viewer)
        }
        _ => None,
    };
    let mut node_runs = Vec::new();
    let mut memory = MemoryResult::default();
    for &rate in latency_rates {
        node_runs.push(latency_run(&mut client, "node", rate, opts.quick)?);
        if rate == 10_000 {
            memory.peak_rss_kb_at_10k = proc_status_kb(node.pid(), "VmHWM").unwrap_or(0);
        }
    }
    let p99_ratio =
        raw.iter().zip(&node_runs).map(|(r, n)| (r.target_rate, n.p99_us as f64 / r.p99_us.max(1) as f64)).collect();

    let (steps, max_sustained) = sustained_search(&mut client, opts.quick)?;
    if opts.sustained_only {
        log(&format!("swings answered inline by the node: {}", client.diagnostic("swings_answered_inline")));
    } else {
        soak(&mut client, node.pid(), max_sustained, opts.soak, &mut memory)?;
    }
    drop(client);
    let foxglove_client = viewer.map(LiveClient::finish).transpose()?;
    if let Some(counts) = &foxglove_client {
        log(&format!("node: the Foxglove client read {} messages ({} bytes)", counts.messages, counts.bytes));
    }
    let node_log = stop(node);
    if let Some(line) = node_log.lines().rev().find(|l| l.contains("bag") && l.contains("closed")) {
        log(line);
    }
    let _ = std::fs::remove_dir_all(&bag_dir);

    let disk = if opts.sustained_only {
        Vec::new()
    } else {
        disk_bench(&opts.work_dir, if opts.quick { 1_000_000 } else { 5_000_000 })?
    };
    Ok(BenchReport {
        machine: with_load_after(machine_before),
        raw,
        node: node_runs,
        p99_ratio,
        steps,
        max_sustained_rate: max_sustained,
        memory,
        disk,
        foxglove_client,
    })
}

/// One paced latency run of `client`'s server at `rate`, logged under `label`.
fn latency_run(client: &mut Client, label: &str, rate: u32, quick: bool) -> anyhow::Result<RunResult> {
    let r = client.run(rate, count_for(rate, run_seconds(quick, rate)), QUIET)?;
    log(&format!(
        "{label} {rate:>6}/s: p50 {} µs p99 {} µs max {} µs ({}/{})",
        r.p50_us, r.p99_us, r.max_us, r.answered, r.sent
    ));
    Ok(r)
}
