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

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::pin::pin;
use std::process::{Child, Command, Stdio};
use std::sync::{mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{bail, Context as _};
use futures::StreamExt;
use hdrhistogram::Histogram;
use ros2_client::qos::{History, Reliability, WhenFull};
use ros2_client::{NodeName, NodeOptions, Publisher};
use serde_json::json;

use crate::msgs::diagnostic_msgs::msg::DiagnosticArray;
use crate::msgs::std_msgs::msg::Header;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
use crate::ros::{DdsConfig, DiscoveryRange};

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
}

/// Latency figures of one paced run, µs.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct RunResult {
    /// Target rate, swings/s.
    pub target_rate: u32,
    /// Rate the client actually published at, swings/s.
    pub achieved_rate: f64,
    /// Swings sent.
    pub sent: u64,
    /// Answers received.
    pub answered: u64,
    /// Median latency, µs.
    pub p50_us: u64,
    /// 99th percentile latency, µs.
    pub p99_us: u64,
    /// Worst latency, µs.
    pub max_us: u64,
    /// Time from the last publish to the last answer, ms (a growing backlog shows here).
    pub drain_ms: f64,
}

/// One step of the sustained-rate search.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StepResult {
    /// Latencies and counts of the step.
    pub run: RunResult,
    /// Swings the node dropped during the step (diagnostics `swings_dropped`).
    pub node_dropped: u64,
    /// Messages the recorder dropped during the step (diagnostics `recorder_dropped`).
    pub recorder_dropped: u64,
    /// Whether the step counts as sustained: no loss anywhere (answers, node drops, transport, recorder), rate
    /// reached, p99 ≤ 100 ms, no backlog.
    pub sustained: bool,
    /// Why not, if not.
    pub verdict: String,
}

/// Recorder against `dd`: one message type and storage, with `dd` of the same bytes.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DiskResult {
    /// ROS type recorded (`sweetspot_msgs/msg/Swing`, `…/ExitVelocity`, or `per swing: …` for the node's mix).
    pub message_type: String,
    /// Mean CDR size of one message, bytes.
    pub message_bytes: u64,
    /// Storage: a chunk compression (`zstd:1`, `none`, …) or a rosbag2 preset (`fastwrite`, …).
    pub storage: String,
    /// Messages recorded.
    pub messages: u64,
    /// Message bytes recorded (CDR payloads, as the recorder counts them).
    pub payload_bytes: u64,
    /// Bytes of the bag files on disk (MCAP framing, indexes and summary included; compressed chunks).
    pub bag_bytes: u64,
    /// Recorder wall time including the final fsync, s.
    pub recorder_s: f64,
    /// Recorder throughput, MB/s (10^6 message bytes per second).
    pub recorder_mb_s: f64,
    /// Bag bytes written per second, MB/s.
    pub recorder_disk_mb_s: f64,
    /// Recorder messages per second.
    pub recorder_msgs_s: f64,
    /// `dd` throughput writing as many bytes as the messages (1 MiB blocks, fdatasync), MB/s: the faster of
    /// the runs right before and right after the recorder.
    pub dd_mb_s: f64,
    /// Both `dd` runs (before, after), MB/s.
    pub dd_runs_mb_s: Vec<f64>,
    /// recorder_mb_s / dd_mb_s.
    pub ratio: f64,
}

/// The message a recorder bench records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BenchMessage {
    /// The node's input, 84 B of CDR: the worst case (most messages per byte).
    Swing,
    /// The node's main output, ~156 B of CDR (ids and ten doubles).
    ExitVelocity,
    /// What the node records for each answered swing, in turn on three topics: the Swing (84 B), its
    /// ExitVelocity (~156 B) and its ModalEnergies (18 modes, ~520 B).
    PerSwing,
}

impl BenchMessage {
    /// How the report names it.
    fn label(self) -> &'static str {
        match self {
            BenchMessage::Swing => <Swing as crate::msgs::RosMessage>::TYPE_NAME,
            BenchMessage::ExitVelocity => <ExitVelocity as crate::msgs::RosMessage>::TYPE_NAME,
            BenchMessage::PerSwing => "per swing: Swing + ExitVelocity + ModalEnergies",
        }
    }
}

/// Memory of the node process.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct MemoryResult {
    /// VmHWM after the 10,000/s run, kB.
    pub peak_rss_kb_at_10k: u64,
    /// Rate of the soak, swings/s.
    pub soak_rate: u32,
    /// Soak length, s.
    pub soak_s: f64,
    /// VmRSS sampled once a second during the soak, kB.
    pub soak_rss_kb: Vec<u64>,
    /// Median RSS of the first and of the last quarter of the soak, kB.
    pub soak_first_quarter_kb: u64,
    /// See `soak_first_quarter_kb`.
    pub soak_last_quarter_kb: u64,
    /// Answers missing at the end of the soak.
    pub soak_lost: u64,
}

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
    }
}

fn dds<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("{e:?}")
}

fn dds_config(domain: u16) -> DdsConfig {
    DdsConfig { domain_id: domain, range: DiscoveryRange::Localhost }
}

/// Refuses to run DDS unless in a private network namespace whose only interface is `lo`.
pub fn require_private_network() -> anyhow::Result<()> {
    crate::ros::network_guard()
        .context("sweetspot bench runs DDS only inside a private network namespace (use scripts/bench)")?;
    Ok(())
}

// ---------------------------------------------------------------------------------------------------------
// The raw echo server (child process).
// ---------------------------------------------------------------------------------------------------------

/// Runs the raw ros2-client echo on `domain` until killed: every `Swing` on `/swing` is answered on
/// `/exit_velocity` with an `ExitVelocity` carrying its ids, with the node's QoS on both sides — at once, or
/// after spinning for `work`.
pub fn run_echo_server(domain: u16, work: Duration) -> anyhow::Result<()> {
    require_private_network()?;
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
    let context = crate::ros::context(&dds_config(domain))?;
    let mut node = context
        .new_node(
            NodeName::new("/", "sweetspot_raw_echo").map_err(|e| anyhow::anyhow!("{e:?}"))?,
            NodeOptions::new().enable_rosout(false),
        )
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let swing_topic = crate::ros::create_topic::<Swing>(&node, "/swing", &crate::ros::swing_qos())?;
    let ev_topic = crate::ros::create_topic::<ExitVelocity>(&node, "/exit_velocity", &crate::ros::results_qos())?;
    let reader_qos = crate::ros::swing_qos().history(History::KeepLast { depth: 16_384 });
    let sub =
        node.create_subscription::<Swing>(&swing_topic, Some(reader_qos)).map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let writer_qos = crate::ros::results_qos()
        .history(History::KeepLast { depth: 1000 })
        .reliability(Reliability::Reliable { when_full: WhenFull::Wait(Duration::from_millis(500)) });
    let publisher =
        node.create_publisher::<ExitVelocity>(&ev_topic, Some(writer_qos)).map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let spinner = node.spinner().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    rt.spawn(spinner.spin());
    eprintln!("raw echo up on domain {domain}");
    rt.block_on(async move {
        let mut stream = pin!(sub.async_stream());
        while let Some(received) = stream.next().await {
            if let Ok((swing, _)) = received {
                // Spin rather than sleep: the node's physics keeps the core busy for as long.
                let start = Instant::now();
                while start.elapsed() < work {
                    std::hint::spin_loop();
                }
                let ev = ExitVelocity {
                    header: swing.header.clone(),
                    swing_id: swing.swing_id,
                    bat_id: swing.bat_id,
                    ball_id: swing.ball_id,
                    impact_z: swing.impact_z,
                    measured_exit_speed: swing.measured_exit_speed,
                    ..ExitVelocity::default()
                };
                let _ = publisher.publish(ev);
            }
        }
    });
    Ok(())
}

// ---------------------------------------------------------------------------------------------------------
// Child processes.
// ---------------------------------------------------------------------------------------------------------

/// A child process killed (SIGKILL) when dropped unless stopped before.
struct ChildProc {
    child: Option<Child>,
    stderr: Arc<Mutex<Vec<String>>>,
}

impl ChildProc {
    fn spawn(exe: &Path, args: &[String], domain: u16, cwd: &Path) -> anyhow::Result<ChildProc> {
        let mut child = Command::new(exe)
            .args(args)
            .current_dir(cwd)
            .env("ROS_DOMAIN_ID", domain.to_string())
            .env("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
            .env("RUST_LOG", "warn,rustdds=error,ros2_client=error")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .with_context(|| format!("starting {}", exe.display()))?;
        let stderr = Arc::new(Mutex::new(Vec::new()));
        if let Some(pipe) = child.stderr.take() {
            let lines = Arc::clone(&stderr);
            std::thread::spawn(move || {
                use std::io::BufRead;
                for line in std::io::BufReader::new(pipe).lines().map_while(Result::ok) {
                    if let Ok(mut l) = lines.lock() {
                        l.push(line);
                    }
                }
            });
        }
        Ok(ChildProc { child: Some(child), stderr })
    }

    fn pid(&self) -> u32 {
        self.child.as_ref().map(|c| c.id()).unwrap_or(0)
    }

    fn log(&self) -> String {
        self.stderr.lock().map(|l| l.join("\n")).unwrap_or_default()
    }

    /// SIGTERM, then waits up to 20 s; returns the stderr lines.
    fn terminate(mut self) -> String {
        if let Some(mut child) = self.child.take() {
            let _ = Command::new("kill").arg("-TERM").arg(child.id().to_string()).status();
            let start = Instant::now();
            while child.try_wait().ok().flatten().is_none() && start.elapsed() < Duration::from_secs(20) {
                std::thread::sleep(Duration::from_millis(20));
            }
            let _ = child.kill();
            let _ = child.wait();
            std::thread::sleep(Duration::from_millis(100));
        }
        self.log()
    }
}

impl Drop for ChildProc {
    fn drop(&mut self) {
        if let Some(mut child) = self.child.take() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// A field of `/proc/<pid>/status` in kB (e.g. `VmRSS`, `VmHWM`).
pub fn proc_status_kb(pid: u32, field: &str) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    status
        .lines()
        .find(|l| l.starts_with(field) && l[field.len()..].starts_with(':'))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|v| v.parse().ok())
}

// ---------------------------------------------------------------------------------------------------------
// The client.
// ---------------------------------------------------------------------------------------------------------

/// The in-process ros2-client peer that drives the node or the echo on one domain.
pub struct Client {
    rt: tokio::runtime::Runtime,
    node: ros2_client::Node,
    publisher: Publisher<Swing>,
    answers: mpsc::Receiver<(u64, Instant)>,
    diagnostics: Arc<Mutex<BTreeMap<String, String>>>,
    next_id: u64,
}

impl Client {
    /// A client on `domain` (loopback only).
    pub fn new(domain: u16) -> anyhow::Result<Client> {
        require_private_network()?;
        let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build()?;
        let context = crate::ros::context(&dds_config(domain))?;
        let mut node = context
            .new_node(NodeName::new("/", "sweetspot_bench").map_err(dds)?, NodeOptions::new().enable_rosout(false))
            .map_err(dds)?;
        let swing_topic = crate::ros::create_topic::<Swing>(&node, "/swing", &crate::ros::swing_qos())?;
        let ev_topic = crate::ros::create_topic::<ExitVelocity>(&node, "/exit_velocity", &crate::ros::results_qos())?;
        let diag_topic =
            crate::ros::create_topic::<DiagnosticArray>(&node, "/diagnostics", &crate::ros::diagnostics_qos())?;
        let writer_qos = crate::ros::swing_qos().reliability(Reliability::Reliable { when_full: WhenFull::Block });
        let publisher = node.create_publisher::<Swing>(&swing_topic, Some(writer_qos)).map_err(dds)?;
        let reader_qos = crate::ros::results_qos().history(History::KeepLast { depth: 65_536 });
        let ev_sub = node.create_subscription::<ExitVelocity>(&ev_topic, Some(reader_qos)).map_err(dds)?;
        let diag_sub = node.create_subscription::<DiagnosticArray>(&diag_topic, None).map_err(dds)?;
        let spinner = node.spinner().map_err(dds)?;
        rt.spawn(spinner.spin());
        let (tx, answers) = mpsc::channel();
        rt.spawn(async move {
            let mut stream = pin!(ev_sub.async_stream());
            while let Some(received) = stream.next().await {
                if let Ok((ev, _)) = received {
                    if tx.send((ev.swing_id, Instant::now())).is_err() {
                        break;
                    }
                }
            }
        });
        let diagnostics = Arc::new(Mutex::new(BTreeMap::new()));
        let latest = Arc::clone(&diagnostics);
        rt.spawn(async move {
            let mut stream = pin!(diag_sub.async_stream());
            while let Some(received) = stream.next().await {
                if let Ok((array, _)) = received {
                    if let Ok(mut map) = latest.lock() {
                        for status in array.status {
                            for kv in status.values {
                                map.insert(kv.key, kv.value);
                            }
                        }
                    }
                }
            }
        });
        Ok(Client { rt, node, publisher, answers, diagnostics, next_id: 1 })
    }

    /// Waits for the server to match and answer a few swings.
    pub fn warm_up(&mut self, limit: Duration) -> anyhow::Result<()> {
        let matched = self
            .rt
            .block_on(async { tokio::time::timeout(limit, self.publisher.wait_for_subscription(&self.node)).await });
        if matched.is_err() {
            bail!("no subscriber on /swing matched within {limit:?}");
        }
        let start = Instant::now();
        while start.elapsed() < limit {
            let run = self.run(200, 40, Duration::from_secs(2))?;
            if run.answered == run.sent {
                return Ok(());
            }
        }
        bail!("the server did not answer within {limit:?}")
    }

    /// The latest diagnostics value `key` as an integer (0 if absent).
    pub fn diagnostic(&self, key: &str) -> u64 {
        self.diagnostics.lock().ok().and_then(|m| m.get(key).and_then(|v| v.parse().ok())).unwrap_or(0)
    }

    /// Publishes `count` swings paced at `rate`/s, then waits for their answers (at most `quiet` without a
    /// new one), and returns the latencies.
    pub fn run(&mut self, rate: u32, count: u64, quiet: Duration) -> anyhow::Result<RunResult> {
        Ok(self.run_histogram(rate, count, quiet)?.0)
    }

    /// [`Client::run`], also returning the histogram of latencies (µs) so runs can be merged.
    pub fn run_histogram(
        &mut self,
        rate: u32,
        count: u64,
        quiet: Duration,
    ) -> anyhow::Result<(RunResult, Histogram<u64>)> {
        while self.answers.try_recv().is_ok() {}
        let first = self.next_id;
        self.next_id += count;
        let mut sent_at: Vec<Option<Instant>> = vec![None; count as usize];
        let interval = Duration::from_secs_f64(1.0 / f64::from(rate.max(1)));
        let mut histogram = Histogram::<u64>::new_with_bounds(1, 600_000_000, 3)?;
        let mut answered = 0u64;
        let mut last_answer = None;
        let take = |id: u64,
                    at: Instant,
                    sent_at: &[Option<Instant>],
                    h: &mut Histogram<u64>,
                    n: &mut u64,
                    last: &mut Option<Instant>| {
            if id >= first && id < first + count {
                if let Some(sent) = sent_at[(id - first) as usize] {
                    let _ = h.record(at.saturating_duration_since(sent).as_micros().max(1) as u64);
                    *n += 1;
                    *last = Some(at);
                }
            }
        };
        let start = Instant::now();
        for i in 0..count {
            let due = start + interval.mul_f64(i as f64);
            loop {
                let now = Instant::now();
                if now >= due {
                    break;
                }
                let wait = due - now;
                if wait > Duration::from_micros(200) {
                    std::thread::sleep(wait - Duration::from_micros(100));
                } else {
                    std::thread::yield_now();
                }
            }
            sent_at[i as usize] = Some(Instant::now());
            if let Err(e) = self.publisher.publish(bench_swing(first + i)) {
                bail!("publishing swing {}: {e:?}", first + i);
            }
            while let Ok((id, at)) = self.answers.try_recv() {
                take(id, at, &sent_at, &mut histogram, &mut answered, &mut last_answer);
            }
        }
        let send_end = Instant::now();
        let achieved = count as f64 / send_end.duration_since(start).as_secs_f64().max(1e-9);
        while answered < count {
            match self.answers.recv_timeout(quiet) {
                Ok((id, at)) => take(id, at, &sent_at, &mut histogram, &mut answered, &mut last_answer),
                Err(_) => break,
            }
        }
        let drain_ms =
            last_answer.map(|t| t.saturating_duration_since(send_end).as_secs_f64() * 1e3).unwrap_or(f64::NAN);
        let result = RunResult {
            target_rate: rate,
            achieved_rate: achieved,
            sent: count,
            answered,
            p50_us: histogram.value_at_quantile(0.5),
            p99_us: histogram.value_at_quantile(0.99),
            max_us: histogram.max(),
            drain_ms,
        };
        Ok((result, histogram))
    }
}

// ---------------------------------------------------------------------------------------------------------
// The bench.
// ---------------------------------------------------------------------------------------------------------

fn run_seconds(quick: bool, rate: u32) -> f64 {
    match (quick, rate) {
        (true, r) if r <= 100 => 2.0,
        (true, _) => 1.0,
        (false, r) if r <= 100 => 20.0,
        (false, _) => 5.0,
    }
}

fn count_for(rate: u32, seconds: f64) -> u64 {
    ((f64::from(rate) * seconds).round() as u64).max(10)
}

/// Machine description: CPU model, nproc, load average, kernel.
pub fn machine() -> BTreeMap<String, String> {
    let mut m = BTreeMap::new();
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model =
        cpuinfo.lines().find(|l| l.starts_with("model name")).and_then(|l| l.split(':').nth(1)).unwrap_or("?").trim();
    m.insert("cpu".into(), model.to_string());
    m.insert("nproc".into(), std::thread::available_parallelism().map(|n| n.get().to_string()).unwrap_or_default());
    m.insert("loadavg".into(), std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim().to_string());
    m.insert(
        "kernel".into(),
        std::fs::read_to_string("/proc/sys/kernel/osrelease").unwrap_or_default().trim().to_string(),
    );
    m.insert("profile".into(), if cfg!(debug_assertions) { "debug".into() } else { "release".into() });
    m.insert("utc".into(), chrono::Utc::now().format("%Y-%m-%dT%H:%M:%SZ").to_string());
    m
}

fn log(msg: &str) {
    eprintln!("[bench {}] {msg}", chrono::Utc::now().format("%H:%M:%S"));
}

/// Runs every measurement once and returns the report.
/// Starts `exe` as `sweetspot node` on `domain`, recording to a fresh `bag_dir`, diagnostics every 0.5 s.
fn spawn_recording_node(exe: &Path, bag_dir: &Path, domain: u16, work_dir: &Path) -> anyhow::Result<ChildProc> {
    let _ = std::fs::remove_dir_all(bag_dir);
    let args: Vec<String> = vec![
        "node".into(),
        "--ros-args".into(),
        "-p".into(),
        format!("record_path:={}", bag_dir.display()),
        "-p".into(),
        "diagnostics_period:=0.5".into(),
    ];
    ChildProc::spawn(exe, &args, domain, work_dir)
}

pub fn run(opts: &BenchOptions) -> anyhow::Result<BenchReport> {
    require_private_network()?;
    std::fs::create_dir_all(&opts.work_dir).with_context(|| format!("creating {}", opts.work_dir.display()))?;
    let machine_before = machine();
    let quiet = Duration::from_secs(3);

    // 1. Raw ros2-client echo.
    log("raw echo: starting");
    let echo = ChildProc::spawn(
        &opts.exe,
        &["bench".into(), "--echo-server".into(), "--domain".into(), (opts.domain + 1).to_string()],
        opts.domain + 1,
        &opts.work_dir,
    )?;
    let mut raw_client = Client::new(opts.domain + 1)?;
    raw_client.warm_up(Duration::from_secs(30)).with_context(|| format!("raw echo: {}", echo.log()))?;
    let latency_rates: &[u32] = if opts.sustained_only { &[] } else { &LATENCY_RATES };
    let mut raw = Vec::new();
    for &rate in latency_rates {
        let r = raw_client.run(rate, count_for(rate, run_seconds(opts.quick, rate)), quiet)?;
        log(&format!(
            "raw  {rate:>6}/s: p50 {} µs p99 {} µs max {} µs ({}/{})",
            r.p50_us, r.p99_us, r.max_us, r.answered, r.sent
        ));
        raw.push(r);
    }
    drop(raw_client);
    drop(echo.terminate());

    // 2. The node, recording on.
    log("node: starting (recording on)");
    let bag_dir = opts.work_dir.join(format!("node_bag_{}", std::process::id()));
    let node_exe = opts.node_exe.as_deref().unwrap_or(&opts.exe);
    log(&format!("node executable: {}", node_exe.display()));
    let node = spawn_recording_node(node_exe, &bag_dir, opts.domain, &opts.work_dir)?;
    let mut client = Client::new(opts.domain)?;
    client.warm_up(Duration::from_secs(60)).with_context(|| format!("node: {}", node.log()))?;
    let mut node_runs = Vec::new();
    let mut memory = MemoryResult::default();
    for &rate in latency_rates {
        let r = client.run(rate, count_for(rate, run_seconds(opts.quick, rate)), quiet)?;
        log(&format!(
            "node {rate:>6}/s: p50 {} µs p99 {} µs max {} µs ({}/{})",
            r.p50_us, r.p99_us, r.max_us, r.answered, r.sent
        ));
        if rate == 10_000 {
            memory.peak_rss_kb_at_10k = proc_status_kb(node.pid(), "VmHWM").unwrap_or(0);
        }
        node_runs.push(r);
    }
    let p99_ratio =
        raw.iter().zip(&node_runs).map(|(r, n)| (r.target_rate, n.p99_us as f64 / r.p99_us.max(1) as f64)).collect();

    // 3. Highest sustained rate with recording on.
    let step_rates: &[u32] =
        if opts.quick { &[5_000, 10_000, 20_000] } else { &[2_000, 5_000, 10_000, 15_000, 20_000, 30_000, 40_000] };
    let step_seconds = if opts.quick { 2.0 } else { 5.0 };
    let mut steps = Vec::new();
    let mut max_sustained = 0;
    for &rate in step_rates {
        // A shared machine can stall any few seconds; a failed step is retried once before the search stops.
        for attempt in 0..2 {
            std::thread::sleep(Duration::from_millis(1200)); // fresh diagnostics before the step
            let (dropped0, rec_dropped0) = (client.diagnostic("swings_dropped"), client.diagnostic("recorder_dropped"));
            let lost0 = client.diagnostic("swings_lost_in_transport");
            let r = client.run(rate, count_for(rate, step_seconds), quiet)?;
            std::thread::sleep(Duration::from_millis(1200)); // diagnostics after the step
            let node_dropped = client.diagnostic("swings_dropped").saturating_sub(dropped0);
            let recorder_dropped = client.diagnostic("recorder_dropped").saturating_sub(rec_dropped0);
            let mut why = Vec::new();
            if r.answered < r.sent {
                why.push(format!("{} answers missing", r.sent - r.answered));
            }
            if node_dropped > 0 {
                why.push(format!("node dropped {node_dropped}"));
            }
            let lost = client.diagnostic("swings_lost_in_transport").saturating_sub(lost0);
            if lost > 0 {
                why.push(format!("{lost} swings lost in transport"));
            }
            if recorder_dropped > 0 {
                why.push(format!("recorder dropped {recorder_dropped}"));
            }
            if r.achieved_rate < 0.95 * f64::from(rate) {
                why.push(format!("client reached only {:.0}/s", r.achieved_rate));
            }
            if r.p99_us > 100_000 {
                why.push(format!("lag: p99 {} ms", r.p99_us / 1000));
            }
            // NaN (no answer at all) counts as a backlog too.
            if r.drain_ms.is_nan() || r.drain_ms >= 500.0 {
                why.push(format!("backlog: last answer {:.0} ms after the last swing", r.drain_ms));
            }
            let sustained = why.is_empty();
            let verdict = if sustained { "sustained".to_string() } else { why.join("; ") };
            log(&format!("step {rate:>6}/s (attempt {}): {verdict} (p99 {} µs)", attempt + 1, r.p99_us));
            steps.push(StepResult { run: r, node_dropped, recorder_dropped, sustained, verdict });
            if sustained {
                max_sustained = rate;
                break;
            }
        }
        if max_sustained != rate {
            break;
        }
    }

    if opts.sustained_only {
        log(&format!("swings answered inline by the node: {}", client.diagnostic("swings_answered_inline")));
    } else {
        soak(&mut client, node.pid(), max_sustained, opts.soak, quiet, &mut memory)?;
    }
    drop(client);
    let node_log = node.terminate();
    if let Some(line) = node_log.lines().rev().find(|l| l.contains("bag") && l.contains("closed")) {
        log(line);
    }
    let _ = std::fs::remove_dir_all(&bag_dir);

    // 5. Recorder against dd.
    let disk = if opts.sustained_only {
        Vec::new()
    } else {
        disk_bench(&opts.work_dir, if opts.quick { 1_000_000 } else { 5_000_000 })?
    };

    let mut machine = machine_before;
    machine.insert(
        "loadavg_after".into(),
        std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim().to_string(),
    );
    Ok(BenchReport { machine, raw, node: node_runs, p99_ratio, steps, max_sustained_rate: max_sustained, memory, disk })
}

/// Step 4 of [`run`]: the memory soak — `soak` at 5,000/s (1,000/s if the node sustained less), the node's RSS
/// sampled once a second, into `memory`.
fn soak(
    client: &mut Client,
    pid: u32,
    max_sustained: u32,
    soak: Duration,
    quiet: Duration,
    memory: &mut MemoryResult,
) -> anyhow::Result<()> {
    let soak_rate = if max_sustained >= 5_000 { 5_000 } else { 1_000 };
    memory.soak_rate = soak_rate;
    memory.soak_s = soak.as_secs_f64();
    log(&format!("soak: {soak_rate}/s for {:.0} s", memory.soak_s));
    let stop = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let sampler = {
        let stop = Arc::clone(&stop);
        std::thread::spawn(move || {
            let mut samples = Vec::new();
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                samples.push(proc_status_kb(pid, "VmRSS").unwrap_or(0));
                std::thread::sleep(Duration::from_secs(1));
            }
            samples
        })
    };
    let soak = client.run(soak_rate, count_for(soak_rate, memory.soak_s), quiet)?;
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    memory.soak_rss_kb = sampler.join().unwrap_or_default();
    memory.soak_lost = soak.sent - soak.answered;
    let quarter = (memory.soak_rss_kb.len() / 4).max(1);
    memory.soak_first_quarter_kb = median(&memory.soak_rss_kb[..quarter.min(memory.soak_rss_kb.len())]);
    memory.soak_last_quarter_kb = median(&memory.soak_rss_kb[memory.soak_rss_kb.len().saturating_sub(quarter)..]);
    log(&format!(
        "soak: RSS first quarter {} kB, last quarter {} kB, {} lost",
        memory.soak_first_quarter_kb, memory.soak_last_quarter_kb, memory.soak_lost
    ));
    Ok(())
}

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
/// raw echo, this executable's node, and `opts.compare`'s (all recording, as in [`run`]).
pub fn run_latency_interleaved(opts: &BenchOptions) -> anyhow::Result<InterleavedReport> {
    require_private_network()?;
    std::fs::create_dir_all(&opts.work_dir).with_context(|| format!("creating {}", opts.work_dir.display()))?;
    let machine_before = machine();
    let quiet = Duration::from_secs(3);
    let mut nodes = vec![("node".to_string(), opts.exe.clone())];
    nodes.extend(opts.compare.iter().cloned());
    if usize::from(opts.domain) + 1 + nodes.len() > 232 {
        let last = usize::from(opts.domain) + nodes.len();
        bail!("domains {}..={last} do not all exist (ROS_DOMAIN_ID ≤ 232)", opts.domain);
    }
    struct Server {
        label: String,
        process: ChildProc,
        client: Client,
        bag_dir: Option<PathBuf>,
    }
    let mut servers = Vec::new();
    let echo_domain = opts.domain + 1;
    log("raw echo: starting");
    let echo = ChildProc::spawn(
        &opts.exe,
        &["bench".into(), "--echo-server".into(), "--domain".into(), echo_domain.to_string()],
        echo_domain,
        &opts.work_dir,
    )?;
    let mut client = Client::new(echo_domain)?;
    client.warm_up(Duration::from_secs(30)).with_context(|| format!("raw echo: {}", echo.log()))?;
    servers.push(Server { label: "raw".into(), process: echo, client, bag_dir: None });
    for (k, (label, exe)) in nodes.iter().enumerate() {
        // The node on opts.domain, the others after the echo's domain.
        let domain = if k == 0 { opts.domain } else { opts.domain + 1 + k as u16 };
        log(&format!("{label}: starting {} on domain {domain} (recording on)", exe.display()));
        let bag_dir = opts.work_dir.join(format!("node_bag_{}_{k}", std::process::id()));
        let process = spawn_recording_node(exe, &bag_dir, domain, &opts.work_dir)?;
        let mut client = Client::new(domain)?;
        client.warm_up(Duration::from_secs(60)).with_context(|| format!("{label}: {}", process.log()))?;
        servers.push(Server { label: label.clone(), process, client, bag_dir: Some(bag_dir) });
    }

    let mut merged: Vec<Vec<RunResult>> = vec![Vec::new(); servers.len()];
    let mut block_seconds = Vec::new();
    let rates: &[u32] = if opts.latency_rates.is_empty() { &LATENCY_RATES } else { &opts.latency_rates };
    for &rate in rates {
        let total = opts.latency_seconds.unwrap_or_else(|| run_seconds(opts.quick, rate));
        let block = if rate <= 100 { total.min(2.0) } else { total.min(0.5) };
        let blocks = (total / block).round().max(1.0) as usize;
        block_seconds.push((rate, block));
        let mut histograms: Vec<Histogram<u64>> =
            (0..servers.len()).map(|_| Histogram::new_with_bounds(1, 600_000_000, 3)).collect::<Result<_, _>>()?;
        let mut totals = vec![RunResult { target_rate: rate, ..RunResult::default() }; servers.len()];
        for b in 0..blocks {
            for i in 0..servers.len() {
                let k = (b + i) % servers.len();
                let (r, h) = servers[k].client.run_histogram(rate, count_for(rate, block), quiet)?;
                histograms[k].add(&h)?;
                let t = &mut totals[k];
                t.sent += r.sent;
                t.answered += r.answered;
                t.achieved_rate += r.achieved_rate / blocks as f64;
                // NaN (a block without any answer) stays NaN, as in `run`.
                t.drain_ms =
                    if t.drain_ms.is_nan() || r.drain_ms.is_nan() { f64::NAN } else { t.drain_ms.max(r.drain_ms) };
            }
        }
        for (k, (mut t, h)) in totals.into_iter().zip(histograms).enumerate() {
            t.p50_us = h.value_at_quantile(0.5);
            t.p99_us = h.value_at_quantile(0.99);
            t.max_us = h.max();
            log(&format!(
                "{:>6} {rate:>6}/s: p50 {} µs p99 {} µs max {} µs ({}/{}, {blocks} blocks of {block} s)",
                servers[k].label, t.p50_us, t.p99_us, t.max_us, t.answered, t.sent
            ));
            merged[k].push(t);
        }
        for server in &servers[1..] {
            log(&format!(
                "{:>6}: {} swings answered inline so far (diagnostics; 0 for builds without the inline path)",
                server.label,
                server.client.diagnostic("swings_answered_inline")
            ));
        }
    }
    let raw = merged[0].clone();
    let targets = servers
        .iter()
        .zip(&merged)
        .map(|(server, runs)| InterleavedTarget {
            label: server.label.clone(),
            runs: runs.clone(),
            p99_ratio: runs
                .iter()
                .zip(&raw)
                .map(|(n, r)| (r.target_rate, n.p99_us as f64 / r.p99_us.max(1) as f64))
                .collect(),
        })
        .collect();
    for server in servers {
        drop(server.client);
        let stderr = server.process.terminate();
        // The node's own receive-to-publish latency (its shutdown summary), to tell its work from transport.
        if let Some(line) = stderr.lines().rev().find(|l| l.contains("latency p50")) {
            log(&format!("{}: {line}", server.label));
        }
        if let Some(dir) = server.bag_dir {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
    let mut machine = machine_before;
    machine.insert(
        "loadavg_after".into(),
        std::fs::read_to_string("/proc/loadavg").unwrap_or_default().trim().to_string(),
    );
    Ok(InterleavedReport { machine, block_seconds, targets })
}

/// The machine and its load before and after, one line (the head of both reports).
fn machine_line(m: &BTreeMap<String, String>) -> String {
    let get = |key: &str| m.get(key).map(String::as_str).unwrap_or("?");
    format!(
        "machine: {} × {} ({}), load before: {}, after: {}, build: {}",
        get("nproc"),
        get("cpu"),
        get("kernel"),
        get("loadavg"),
        get("loadavg_after"),
        get("profile")
    )
}

/// [`InterleavedReport`] as a table: per rate, each server's p50/p99/max and p99 ratio to the raw echo.
pub fn interleaved_table(r: &InterleavedReport) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "{}", machine_line(&r.machine));
    let _ = writeln!(s, "\nswing → exit_velocity over DDS/loopback, servers interleaved in blocks (nodes recording)");
    let _ = writeln!(
        s,
        "{:>8} | {:>10} | {:>9} {:>9} {:>9} | {:>9} | answered",
        "rate/s", "server", "p50", "p99", "max", "p99/raw"
    );
    for (i, (rate, _)) in r.block_seconds.iter().enumerate() {
        for t in &r.targets {
            let run = &t.runs[i];
            let _ = writeln!(
                s,
                "{:>8} | {:>10} | {:>7}µs {:>7}µs {:>7}µs | {:>8.2}× | {}/{}",
                rate, t.label, run.p50_us, run.p99_us, run.max_us, t.p99_ratio[i].1, run.answered, run.sent
            );
        }
    }
    s
}

fn median(values: &[u64]) -> u64 {
    let mut v = values.to_vec();
    v.sort_unstable();
    v.get(v.len() / 2).copied().unwrap_or(0)
}

/// The recorder against `dd` for Swing messages, ExitVelocity messages and the node's per-swing mix, each
/// with zstd chunks (the default), uncompressed chunks and unchunked (rosbag2's `fastwrite`).
pub fn disk_bench(dir: &Path, messages: u64) -> anyhow::Result<Vec<DiskResult>> {
    let storages = ["zstd", "none", "fastwrite"].map(|s| storage_spec(s).map_err(anyhow::Error::from));
    disk_bench_with(dir, messages, &storages.into_iter().collect::<Result<Vec<_>, _>>()?)
}

/// A storage the recorder bench can use, by name: a rosbag2 preset (`none`, `fastwrite`, `zstd_fast`,
/// `zstd_small`) or a chunk compression (`zstd`, `zstd:LEVEL`, `lz4`).
pub fn storage_spec(name: &str) -> Result<(String, crate::bag::StorageOptions), crate::bag::BagError> {
    use crate::bag::{StorageOptions, StoragePreset};
    let storage = if name.parse::<StoragePreset>().is_ok() {
        StorageOptions::preset(name)?
    } else {
        StorageOptions::from_parameters("", name)?
    };
    Ok((name.to_string(), storage))
}

/// [`disk_bench`] with the given storages, as (label, options).
pub fn disk_bench_with(
    dir: &Path,
    messages: u64,
    storages: &[(String, crate::bag::StorageOptions)],
) -> anyhow::Result<Vec<DiskResult>> {
    let mut results = Vec::new();
    for message in [BenchMessage::Swing, BenchMessage::ExitVelocity, BenchMessage::PerSwing] {
        for (label, storage) in storages {
            let r = disk_bench_one(dir, message, messages, label, *storage)?;
            log(&format!(
                "recorder {} {}: {:.1} MB/s of messages ({:.0} msg/s, {:.1} MB/s on disk) vs dd {:.1} MB/s: {:.0} %",
                r.message_type,
                r.storage,
                r.recorder_mb_s,
                r.recorder_msgs_s,
                r.recorder_disk_mb_s,
                r.dd_mb_s,
                r.ratio * 100.0
            ));
            results.push(r);
        }
    }
    Ok(results)
}

/// Distinct CDR payloads of `message` with random measured values. 65,536 of them (5–10 MB), more than
/// any zstd window of the levels used, so the compressor sees no exact repeats, as with real swings.
const BENCH_PAYLOADS: u64 = 65_536;

/// The topics a recorder bench records, each with [`BENCH_PAYLOADS`] CDR payloads: one topic, or for
/// [`BenchMessage::PerSwing`] three, recorded in turn.
fn bench_streams(message: BenchMessage) -> Vec<(crate::bag::TopicInfo, Vec<Vec<u8>>)> {
    use crate::bag::TopicInfo;
    use crate::msgs::sweetspot_msgs::msg::ModalEnergies;
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(7);
    let (mut swings, mut exits, mut energies) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..BENCH_PAYLOADS {
        let swing = Swing {
            ball_speed: rng.gen_range(30.0..45.0),
            bat_cm_speed: rng.gen_range(15.0..25.0),
            bat_angular_speed: rng.gen_range(30.0..60.0),
            impact_z: rng.gen_range(0.4..0.8),
            measured_exit_speed: rng.gen_range(30.0..50.0),
            ..bench_swing(i)
        };
        let exit_speed = rng.gen_range(35.0..50.0);
        let exit = ExitVelocity {
            header: swing.header.clone(),
            swing_id: swing.swing_id,
            bat_id: "r161".into(),
            ball_id: "baseball".into(),
            status: ExitVelocity::STATUS_OK,
            impact_z: swing.impact_z,
            exit_speed,
            rigid_exit_speed: exit_speed * rng.gen_range(1.0..1.1),
            effective_cor: rng.gen_range(0.3..0.5),
            collision_efficiency: rng.gen_range(0.1..0.3),
            contact_time: rng.gen_range(0.0006..0.0012),
            peak_force: rng.gen_range(1.0e4..3.0e4),
            impulse: rng.gen_range(10.0..15.0),
            max_compression: rng.gen_range(0.005..0.02),
            measured_exit_speed: swing.measured_exit_speed,
            residual: swing.measured_exit_speed - exit_speed,
            ..ExitVelocity::default()
        };
        let modes = 18;
        let energy: Vec<f64> = (0..modes).map(|_| rng.gen_range(0.0..2.0)).collect();
        let total: f64 = energy.iter().sum();
        let modal = ModalEnergies {
            header: swing.header.clone(),
            swing_id: swing.swing_id,
            bat_id: "r161".into(),
            frequency: (0..modes).map(|m| 170.0 * (m + 1) as f64 * rng.gen_range(0.99..1.01)).collect(),
            fraction: energy.iter().map(|e| e / total.max(1e-12)).collect(),
            energy,
            vibration_energy: total,
            hysteresis_loss: rng.gen_range(20.0..40.0),
            energy_residual: rng.gen_range(-1e-5..1e-5),
        };
        match message {
            BenchMessage::Swing => swings.push(crate::msgs::encode_cdr(&swing).unwrap_or_default()),
            BenchMessage::ExitVelocity => exits.push(crate::msgs::encode_cdr(&exit).unwrap_or_default()),
            BenchMessage::PerSwing => {
                swings.push(crate::msgs::encode_cdr(&swing).unwrap_or_default());
                exits.push(crate::msgs::encode_cdr(&exit).unwrap_or_default());
                energies.push(crate::msgs::encode_cdr(&modal).unwrap_or_default());
            }
        }
    }
    let swing_topic = TopicInfo::of::<Swing>("/swing", crate::node::recording::recorded_qos(&crate::ros::swing_qos()));
    let results_qos = crate::node::recording::recorded_qos(&crate::ros::results_qos());
    let exit_topic = TopicInfo::of::<ExitVelocity>("/exit_velocity", results_qos);
    let modal_topic = TopicInfo::of::<ModalEnergies>("/modal_energies", results_qos);
    match message {
        BenchMessage::Swing => vec![(swing_topic, swings)],
        BenchMessage::ExitVelocity => vec![(exit_topic, exits)],
        BenchMessage::PerSwing => vec![(swing_topic, swings), (exit_topic, exits), (modal_topic, energies)],
    }
}

/// Records `messages` messages (as the node records them) with the bag recorder into `dir`; right before and
/// right after, writes the same number of message bytes with `dd … conv=fdatasync` to the same directory.
pub fn disk_bench_one(
    dir: &Path,
    message: BenchMessage,
    messages: u64,
    label: &str,
    storage: crate::bag::StorageOptions,
) -> anyhow::Result<DiskResult> {
    use crate::bag::RecorderConfig;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let bag = dir.join(format!("recorder_bench_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&bag);
    let (topic_infos, payloads): (Vec<_>, Vec<_>) = bench_streams(message).into_iter().unzip();
    let streams = payloads.len().max(1) as u64;
    let payload_bytes: u64 = (0..messages)
        .map(|i| payloads[(i % streams) as usize][((i / streams) % BENCH_PAYLOADS) as usize].len() as u64)
        .sum();
    let dd_before = dd_mb_s(dir, payload_bytes)?;
    let mut config = RecorderConfig::new(&bag);
    config.queue_capacity = 65_536;
    let t0 = crate::model::time::now_ns();
    let start = Instant::now();
    let recorder = crate::bag::Recorder::start_with(config, storage)?;
    let topics = topic_infos.into_iter().map(|t| recorder.register_topic(t)).collect::<Result<Vec<_>, _>>()?;
    for i in 0..messages {
        let stream = (i % streams) as usize;
        let cdr = &payloads[stream][((i / streams) % BENCH_PAYLOADS) as usize];
        let stamp = t0 + i * 1000;
        // The recorder never waits for its writer (a full queue is a counted drop); to measure its
        // throughput, retry until the writer thread has made room. Sleeping rather than spinning leaves
        // the writer the core while it catches up (this machine has two).
        while !recorder.record_bytes(topics[stream], cdr, stamp, stamp) {
            std::thread::sleep(Duration::from_micros(50));
        }
    }
    let stats = recorder.finish()?;
    let recorder_s = start.elapsed().as_secs_f64();
    let bag_bytes = dir_bytes(&bag);
    let _ = std::fs::remove_dir_all(&bag);

    let dd_after = dd_mb_s(dir, stats.bytes)?;
    let recorder_mb_s = stats.bytes as f64 / 1e6 / recorder_s;
    // The faster dd is the reference: on this VM's disk a dd writing where nothing was written lately runs at
    // a quarter of its speed on blocks just freed, and which one comes out fast depends on what ran before.
    let dd_mb_s = dd_before.max(dd_after);
    Ok(DiskResult {
        message_type: message.label().to_string(),
        message_bytes: payloads.iter().flatten().map(|p| p.len() as u64).sum::<u64>()
            / payloads.iter().map(Vec::len).sum::<usize>().max(1) as u64,
        storage: label.to_string(),
        messages: stats.written,
        payload_bytes: stats.bytes,
        bag_bytes,
        recorder_s,
        recorder_mb_s,
        recorder_disk_mb_s: bag_bytes as f64 / 1e6 / recorder_s,
        recorder_msgs_s: stats.written as f64 / recorder_s,
        dd_mb_s,
        dd_runs_mb_s: vec![dd_before, dd_after],
        ratio: recorder_mb_s / dd_mb_s,
    })
}

/// `dd if=/dev/zero bs=1M conv=fdatasync` of `bytes` (whole MiB, at least one) into `dir`, MB/s.
fn dd_mb_s(dir: &Path, bytes: u64) -> anyhow::Result<f64> {
    let dd_file = dir.join(format!("dd_bench_{}", std::process::id()));
    let mib = (bytes / (1 << 20)).max(1);
    let start = Instant::now();
    let status = Command::new("dd")
        .arg("if=/dev/zero")
        .arg(format!("of={}", dd_file.display()))
        .arg("bs=1M")
        .arg(format!("count={mib}"))
        .arg("conv=fdatasync")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .context("running dd")?;
    let seconds = start.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&dd_file);
    if !status.success() {
        bail!("dd failed: {status}");
    }
    Ok((mib << 20) as f64 / 1e6 / seconds)
}

fn dir_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .map(|entries| entries.filter_map(Result::ok).filter_map(|e| e.metadata().ok()).map(|m| m.len()).sum())
        .unwrap_or(0)
}

// ---------------------------------------------------------------------------------------------------------
// Output.
// ---------------------------------------------------------------------------------------------------------

/// The report as a human-readable table.
pub fn table(r: &BenchReport) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "{}", machine_line(&r.machine));
    let _ = writeln!(s, "\nswing → exit_velocity over DDS/loopback (node recording; child processes)");
    let _ = writeln!(
        s,
        "{:>8} | {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9} | {:>9}",
        "rate/s", "raw p50", "raw p99", "raw max", "node p50", "node p99", "node max", "p99 ratio"
    );
    for ((raw, node), (_, ratio)) in r.raw.iter().zip(&r.node).zip(&r.p99_ratio) {
        let _ = writeln!(
            s,
            "{:>8} | {:>7}µs {:>7}µs {:>7}µs | {:>7}µs {:>7}µs {:>7}µs | {:>8.2}×{}",
            raw.target_rate,
            raw.p50_us,
            raw.p99_us,
            raw.max_us,
            node.p50_us,
            node.p99_us,
            node.max_us,
            ratio,
            if node.answered < node.sent || raw.answered < raw.sent {
                format!("  (lost: raw {}, node {})", raw.sent - raw.answered, node.sent - node.answered)
            } else {
                String::new()
            }
        );
    }
    let _ = writeln!(s, "\nsustained rate, recording on (target ≥ 10000/s): {}/s", r.max_sustained_rate);
    for st in &r.steps {
        let _ = writeln!(
            s,
            "  {:>6}/s: sent at {:>7.0}/s, {}/{} answered, p99 {} µs, drain {:.0} ms — {}",
            st.run.target_rate,
            st.run.achieved_rate,
            st.run.answered,
            st.run.sent,
            st.run.p99_us,
            st.run.drain_ms,
            st.verdict
        );
    }
    let mm = &r.memory;
    let _ = writeln!(s, "\nnode memory: peak RSS (VmHWM) after 10000/s: {:.1} MB; soak {}/s × {:.0} s: RSS first quarter {:.1} MB, last quarter {:.1} MB, {} answers lost", mm.peak_rss_kb_at_10k as f64 / 1024.0, mm.soak_rate, mm.soak_s, mm.soak_first_quarter_kb as f64 / 1024.0, mm.soak_last_quarter_kb as f64 / 1024.0, mm.soak_lost);
    s.push('\n');
    s.push_str(&disk_table(&r.disk));
    s
}

/// The recorder-against-dd rows as text (the full report's last part, and `--only recorder`).
pub fn disk_table(disk: &[DiskResult]) -> String {
    use std::fmt::Write;
    let mut s =
        String::from("recorder against dd (1 MiB blocks, fdatasync, same bytes as the messages), target ≥ 80 %:\n");
    for d in disk {
        let _ = writeln!(
            s,
            "  {} ({} B) {}: {} messages, {:.1} MB of messages ({:.1} MB on disk) in {:.2} s incl. fsync = {:.1} MB/s, \
             {:.0} msg/s; dd {:.1} MB/s (faster of {}); ratio {:.0} % (bytes on disk: {:.0} % of dd)",
            d.message_type,
            d.message_bytes,
            d.storage,
            d.messages,
            d.payload_bytes as f64 / 1e6,
            d.bag_bytes as f64 / 1e6,
            d.recorder_s,
            d.recorder_mb_s,
            d.recorder_msgs_s,
            d.dd_mb_s,
            d.dd_runs_mb_s.iter().map(|v| format!("{v:.0}")).collect::<Vec<_>>().join(", "),
            d.ratio * 100.0,
            d.recorder_disk_mb_s / d.dd_mb_s * 100.0
        );
    }
    s
}

/// The report as JSON.
pub fn to_json(r: &BenchReport) -> serde_json::Value {
    json!(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_this_process_rss_and_peak_from_proc() {
        let rss = proc_status_kb(std::process::id(), "VmRSS").expect("VmRSS");
        let peak = proc_status_kb(std::process::id(), "VmHWM").expect("VmHWM");
        assert!(rss > 0 && peak >= rss, "rss {rss} kB, peak {peak} kB");
        assert_eq!(proc_status_kb(std::process::id(), "NoSuchField"), None);
    }

    #[test]
    fn the_per_swing_mix_records_swing_exit_velocity_and_modal_energies_in_turn() {
        let streams = bench_streams(BenchMessage::PerSwing);
        let names: Vec<&str> = streams.iter().map(|(t, _)| t.name.as_str()).collect();
        assert_eq!(names, ["/swing", "/exit_velocity", "/modal_energies"]);
        let sizes: Vec<usize> = streams.iter().map(|(_, p)| p[0].len()).collect();
        // CDR sizes as the node publishes them: 84 B, ids and ten doubles, three arrays of 18 doubles.
        assert_eq!(sizes[0], 84, "{sizes:?}");
        assert!((140..200).contains(&sizes[1]) && (450..600).contains(&sizes[2]), "{sizes:?}");
        assert!(streams.iter().all(|(_, p)| p.len() as u64 == BENCH_PAYLOADS));

        let dir = tempfile::tempdir().unwrap();
        let r =
            disk_bench_one(dir.path(), BenchMessage::PerSwing, 3_000, "zstd", crate::bag::StorageOptions::default())
                .unwrap();
        assert_eq!(r.messages, 3_000);
        let per_swing: usize = sizes.iter().sum();
        assert_eq!(r.payload_bytes, 1_000 * per_swing as u64, "1,000 swings of three messages each");
        assert_eq!(r.message_bytes, (per_swing / 3) as u64);
        assert!(r.ratio > 0.0 && r.dd_mb_s > 0.0, "{r:?}");
        assert!(disk_table(&[r]).contains("per swing: Swing + ExitVelocity + ModalEnergies"));
    }

    #[test]
    fn median_of_samples() {
        assert_eq!(median(&[]), 0);
        assert_eq!(median(&[5]), 5);
        assert_eq!(median(&[9, 1, 5]), 5);
    }
}
