//! `sweetspot bench`: end-to-end latency against raw DDS, sustained rate with recording, recorder against dd,
//! node memory. Runs only inside a private network namespace (`scripts/bench` makes one).

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::Context as _;

use crate::bench::{self, BenchOptions};

/// Arguments of `sweetspot bench`.
#[derive(Debug, clap::Args)]
#[command(
    after_help = "Run it through scripts/bench, which builds in release mode and enters a private network namespace:\n  scripts/bench --quick\n  scripts/bench --json bench.json"
)]
pub struct BenchArgs {
    /// Short runs: the whole bench in under a minute (numbers are noisier).
    #[arg(long)]
    pub quick: bool,
    /// Also write the report as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Scratch directory on the disk to measure (bags and the dd file go there, and are removed).
    #[arg(long, value_name = "DIR", default_value = "bench-work")]
    pub work_dir: PathBuf,
    /// First DDS domain used (the node on it, the raw echo on the next one).
    #[arg(long, default_value_t = 77, value_parser = clap::value_parser!(u16).range(0..=231))]
    pub domain: u16,
    /// Soak length for the memory-flatness measurement, s (default 60, 10 with --quick).
    #[arg(long, value_name = "SECONDS")]
    pub soak: Option<u64>,
    /// Run only this part: `sustained` = the node's sustained-rate search alone; `latency` = the raw echo and
    /// the node (and any --compare nodes) at 100, 1,000 and 10,000 swings/s, all up at once and measured in
    /// interleaved blocks (about 30 s per server; 5 s with --quick); `recorder` = the recorder against dd
    /// (no DDS). Default: everything.
    #[arg(long, value_enum, value_name = "PART")]
    pub only: Option<BenchPart>,
    /// With `--only latency`: also measure the node of another executable, e.g. the build before a change
    /// (`--compare before=/tmp/sweetspot-old`); repeatable.
    #[arg(long, value_name = "LABEL=EXE", value_parser = parse_compare, requires = "only")]
    pub compare: Vec<(String, PathBuf)>,
    /// With `--only latency`: the rates to measure, swings/s (default 100,1000,10000).
    #[arg(long, value_name = "RATES", value_delimiter = ',', requires = "only", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub rates: Vec<u32>,
    /// With `--only latency`: seconds per server and rate (default 20 at 100/s, 5 above; 2 and 1 with --quick),
    /// in blocks of 2 s (≤ 100/s) or 0.5 s.
    #[arg(long, value_name = "SECONDS", requires = "only", value_parser = parse_seconds)]
    pub seconds: Option<f64>,
    /// Start this executable as the node (full bench and `--only sustained`), e.g. an older build.
    #[arg(long, value_name = "EXE")]
    pub node_exe: Option<PathBuf>,
    /// Attach a Foxglove WebSocket client to the node's live server (`foxglove_port`), subscribed to every
    /// channel: `reading` keeps up, `stalled` stops reading once subscribed. With `--only latency` it is an
    /// extra node, `node+foxglove`, measured in the same interleaved blocks as the bare node; otherwise the
    /// node itself carries it.
    #[arg(long, value_enum, value_name = "MODE")]
    pub foxglove_client: Option<bench::ClientMode>,
    /// Internal: run the raw ros2-client echo server (started by the bench itself).
    #[arg(long, hide = true)]
    pub echo_server: bool,
    /// Internal, with --echo-server: busy-work per swing before answering, µs (to see what the node's
    /// ~10 µs of physics per swing costs any server in tail latency on this machine).
    #[arg(long, hide = true, default_value_t = 0)]
    pub echo_work_us: u64,
}

fn parse_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if (0.5..=3600.0).contains(&s) => Ok(s),
        _ => Err(format!("expected seconds between 0.5 and 3600, got '{text}'")),
    }
}

fn parse_compare(text: &str) -> Result<(String, PathBuf), String> {
    match text.split_once('=') {
        Some((label, exe)) if !label.is_empty() && !exe.is_empty() => Ok((label.to_string(), PathBuf::from(exe))),
        _ => Err(format!("expected LABEL=EXECUTABLE, got '{text}'")),
    }
}

/// A part of the bench that `--only` can pick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchPart {
    /// swing → exit_velocity latency, raw echo against the node.
    Latency,
    /// The highest rate the node sustains with recording on.
    Sustained,
    /// The bag recorder against `dd` on the work dir's disk.
    Recorder,
}

/// Runs the bench (or, with `--echo-server`, the raw echo it starts as a child).
pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    if args.echo_server {
        return bench::run_echo_server(args.domain, Duration::from_micros(args.echo_work_us));
    }
    let exe = std::env::current_exe().context("locating the sweetspot executable")?;
    if let Some(json) = &args.json {
        // Before anything runs: the report never lands on an executable the bench starts.
        let mut inputs = vec![exe.clone()];
        inputs.extend(args.node_exe.iter().cloned());
        inputs.extend(args.compare.iter().map(|(_, exe)| exe.clone()));
        crate::files::refuse_clobber("--json", json, &inputs, &[]).map_err(anyhow::Error::msg)?;
    }
    let soak = Duration::from_secs(args.soak.unwrap_or(if args.quick { 10 } else { 60 }));
    // Absolute, because the node children run with the work dir as their current directory and record
    // into a path under it: a relative one would land in <work dir>/<work dir>/ and escape the clean-up.
    let work_dir = std::path::absolute(&args.work_dir)
        .with_context(|| format!("resolving --work-dir {}", args.work_dir.display()))?;
    let opts = BenchOptions {
        quick: args.quick,
        work_dir,
        domain: args.domain,
        exe,
        soak,
        compare: args.compare,
        node_exe: args.node_exe,
        sustained_only: args.only == Some(BenchPart::Sustained),
        latency_rates: args.rates,
        latency_seconds: args.seconds,
        foxglove_client: args.foxglove_client,
    };
    match args.only {
        Some(BenchPart::Recorder) => {
            let before = bench::loadavg();
            let disk = bench::disk_bench(&opts.work_dir, if opts.quick { 1_000_000 } else { 5_000_000 })?;
            crate::outln!("load average before: {before}, after: {}\n{}", bench::loadavg(), bench::disk_table(&disk))?;
            write_json(args.json.as_deref(), &disk)
        }
        Some(BenchPart::Latency) => {
            let report = bench::run_latency_interleaved(&opts)?;
            crate::outln!("{}", bench::interleaved_table(&report))?;
            write_json(args.json.as_deref(), &report)
        }
        Some(BenchPart::Sustained) | None => {
            let report = bench::run(&opts)?;
            crate::outln!("{}", bench::table(&report))?;
            write_json(args.json.as_deref(), &report)
        }
    }
}

/// Writes `value` as pretty JSON to `path`, if given.
fn write_json(path: Option<&Path>, value: &impl serde::Serialize) -> anyhow::Result<()> {
    if let Some(path) = path {
        let text = serde_json::to_string_pretty(value)?;
        std::fs::write(path, text + "\n").with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}
