//! The latency comparison with every server up at once, measured in interleaved blocks.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{bail, Context as _};
use hdrhistogram::Histogram;

use super::client::{Client, RunResult};
use super::foxglove::{free_port, LiveClient};
use super::machine::{machine, with_load_after};
use super::servers::{start_echo, start_recording_node, stop};
use super::{count_for, log, require_private_network, run_seconds, BenchOptions, LATENCY_RATES, QUIET};
use crate::child::ChildProcess;

/// The label of the node that carries `--foxglove-client`'s viewer.
pub const FOXGLOVE_LABEL: &str = "node+foxglove";

/// One server's latencies in [`run_latency_interleaved`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct InterleavedTarget {
    /// `raw`, `node`, or a `--compare` label.
    pub label: String,
    /// Merged over its blocks, one per rate measured.
    pub runs: Vec<RunResult>,
    /// p99 / the raw echo's p99 at each rate.
    pub p99_ratio: Vec<(u32, f64)>,
}

/// What [`run_latency_interleaved`] measured.
#[derive(Debug, Clone, serde::Serialize)]
pub struct InterleavedReport {
    /// Machine and conditions.
    pub machine: BTreeMap<String, String>,
    /// Block length at each rate, s.
    pub block_seconds: Vec<(u32, f64)>,
    /// The raw echo first, then the nodes.
    pub targets: Vec<InterleavedTarget>,
}

/// The latency comparison with every server up at once, each on its own domain with its own client, measured
/// in short blocks taken in turn (the order rotating every block) and merged per server. On a shared machine
/// a burst of someone else's load then hits every server alike, so the ratios compare like with like (a
/// sequential raw-then-node run on this 2-core VM swung the p99 ratio between 0.2× and 10×). Servers: the
/// raw echo, this executable's node, and `opts.compare`'s (all recording, as in [`super::run`]).
pub fn run_latency_interleaved(opts: &BenchOptions) -> anyhow::Result<InterleavedReport> {
    require_private_network()?;
    std::fs::create_dir_all(&opts.work_dir).with_context(|| format!("creating {}", opts.work_dir.display()))?;
    let machine_before = machine();
    let nodes = nodes_to_compare(opts)?;
    let mut servers = start_servers(opts, &nodes)?;
    let mut merged: Vec<Vec<RunResult>> = vec![Vec::new(); servers.len()];
    let mut block_seconds = Vec::new();
    let rates: &[u32] = if opts.latency_rates.is_empty() { &LATENCY_RATES } else { &opts.latency_rates };
    for &rate in rates {
        let (block, totals) = measure_in_blocks(opts, &mut servers, rate)?;
        block_seconds.push((rate, block));
        for (runs, t) in merged.iter_mut().zip(totals) {
            runs.push(t);
        }
    }
    let targets = targets_of(&servers, &merged);
    stop_servers(servers)?;
    Ok(InterleavedReport { machine: with_load_after(machine_before), block_seconds, targets })
}

/// The nodes measured beside the raw echo: this executable's, `--compare`'s, and the one carrying the
/// Foxglove viewer; refused if their domains run past the last one ROS has.
fn nodes_to_compare(opts: &BenchOptions) -> anyhow::Result<Vec<(String, PathBuf)>> {
    let mut nodes = vec![("node".to_string(), opts.exe.clone())];
    nodes.extend(opts.compare.iter().cloned());
    if opts.foxglove_client.is_some() {
        nodes.push((FOXGLOVE_LABEL.to_string(), opts.exe.clone()));
    }
    if usize::from(opts.domain) + 1 + nodes.len() > 232 {
        let last = usize::from(opts.domain) + nodes.len();
        bail!("domains {}..={last} do not all exist (ROS_DOMAIN_ID ≤ 232)", opts.domain);
    }
    Ok(nodes)
}

/// One server under test, with its own client (and viewer, for [`FOXGLOVE_LABEL`]).
struct Server {
    label: String,
    process: ChildProcess,
    client: Client,
    bag_dir: Option<PathBuf>,
    viewer: Option<LiveClient>,
}

/// Starts the raw echo, then each node, every one on its own domain and warmed up.
fn start_servers(opts: &BenchOptions, nodes: &[(String, PathBuf)]) -> anyhow::Result<Vec<Server>> {
    let mut servers = Vec::new();
    let echo_domain = opts.domain + 1;
    log("raw echo: starting");
    let echo = start_echo(&opts.exe, echo_domain, &opts.work_dir)?;
    let mut client = Client::new(echo_domain)?;
    client.warm_up(Duration::from_secs(30)).with_context(|| format!("raw echo: {}", echo.output()))?;
    servers.push(Server { label: "raw".into(), process: echo, client, bag_dir: None, viewer: None });
    for (k, (label, exe)) in nodes.iter().enumerate() {
        servers.push(start_node(opts, k, label, exe)?);
    }
    Ok(servers)
}

/// Starts the `k`th node (recording), warms its client up and connects its viewer if it carries one.
fn start_node(opts: &BenchOptions, k: usize, label: &str, exe: &std::path::Path) -> anyhow::Result<Server> {
    // The node on opts.domain, the others after the echo's domain.
    let domain = if k == 0 { opts.domain } else { opts.domain + 1 + k as u16 };
    log(&format!("{label}: starting {} on domain {domain} (recording on)", exe.display()));
    let bag_dir = opts.work_dir.join(format!("node_bag_{}_{k}", std::process::id()));
    let viewer_mode = opts.foxglove_client.filter(|_| label == FOXGLOVE_LABEL);
    let port = viewer_mode.map(|_| free_port()).transpose()?;
    let process = start_recording_node(exe, &bag_dir, domain, &opts.work_dir, port)?;
    let mut client = Client::new(domain)?;
    client.warm_up(Duration::from_secs(60)).with_context(|| format!("{label}: {}", process.output()))?;
    let viewer = match (viewer_mode, port) {
        (Some(mode), Some(port)) => {
            let viewer = LiveClient::connect(port, mode, Duration::from_millis(500))
                .with_context(|| format!("{label}: {}", process.output()))?;
            log(&format!("{label}: Foxglove client ({mode:?}) subscribed to {} channels", viewer.counts().channels));
            Some(viewer)
        }
        _ => None,
    };
    Ok(Server { label: label.to_string(), process, client, bag_dir: Some(bag_dir), viewer })
}

/// Measures every server at `rate` in blocks taken in turn, the order rotating every block; the block length
/// and each server's merged result.
fn measure_in_blocks(opts: &BenchOptions, servers: &mut [Server], rate: u32) -> anyhow::Result<(f64, Vec<RunResult>)> {
    let total = opts.latency_seconds.unwrap_or_else(|| run_seconds(opts.quick, rate));
    let block = if rate <= 100 { total.min(2.0) } else { total.min(0.5) };
    let blocks = (total / block).round().max(1.0) as usize;
    let mut histograms: Vec<Histogram<u64>> =
        (0..servers.len()).map(|_| Histogram::new_with_bounds(1, 600_000_000, 3)).collect::<Result<_, _>>()?;
    let mut totals = vec![RunResult { target_rate: rate, ..RunResult::default() }; servers.len()];
    for b in 0..blocks {
        for i in 0..servers.len() {
            let k = (b + i) % servers.len();
            let (r, h) = servers[k].client.run_histogram(rate, count_for(rate, block), QUIET)?;
            histograms[k].add(&h)?;
            let t = &mut totals[k];
            t.sent += r.sent;
            t.answered += r.answered;
            t.achieved_rate += r.achieved_rate / blocks as f64;
            // NaN (a block without any answer) stays NaN, as in `run`.
            t.drain_ms = if t.drain_ms.is_nan() || r.drain_ms.is_nan() { f64::NAN } else { t.drain_ms.max(r.drain_ms) };
        }
    }
    for (k, (t, h)) in totals.iter_mut().zip(histograms).enumerate() {
        t.p50_us = h.value_at_quantile(0.5);
        t.p99_us = h.value_at_quantile(0.99);
        t.max_us = h.max();
        log(&format!(
            "{:>6} {rate:>6}/s: p50 {} µs p99 {} µs max {} µs ({}/{}, {blocks} blocks of {block} s)",
            servers[k].label, t.p50_us, t.p99_us, t.max_us, t.answered, t.sent
        ));
    }
    for server in &servers[1..] {
        log(&format!(
            "{:>6}: {} swings answered inline so far (diagnostics; 0 for builds without the inline path)",
            server.label,
            server.client.diagnostic("swings_answered_inline")
        ));
    }
    Ok((block, totals))
}

/// Each server's runs with its p99 over the raw echo's (the first server's) at each rate.
fn targets_of(servers: &[Server], merged: &[Vec<RunResult>]) -> Vec<InterleavedTarget> {
    let raw = &merged[0];
    servers
        .iter()
        .zip(merged)
        .map(|(server, runs)| InterleavedTarget {
            label: server.label.clone(),
            runs: runs.clone(),
            p99_ratio: runs
                .iter()
                .zip(raw)
                .map(|(n, r)| (r.target_rate, n.p99_us as f64 / r.p99_us.max(1) as f64))
                .collect(),
        })
        .collect()
}

/// Stops every server, logging what its viewer read and the node's own latency summary; removes the bags.
fn stop_servers(servers: Vec<Server>) -> anyhow::Result<()> {
    for server in servers {
        drop(server.client);
        if let Some(viewer) = server.viewer {
            let counts = viewer.finish()?;
            log(&format!(
                "{}: the Foxglove client read {} messages ({} bytes)",
                server.label, counts.messages, counts.bytes
            ));
        }
        let stderr = stop(server.process);
        // The node's own receive-to-publish latency (its shutdown summary), to tell its work from transport.
        if let Some(line) = stderr.lines().rev().find(|l| l.contains("latency p50")) {
            log(&format!("{}: {line}", server.label));
        }
        if let Some(dir) = server.bag_dir {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
    Ok(())
}
