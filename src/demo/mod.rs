//! `sweetspot demo`: the whole system in one command, with nothing else installed.
//!
//! It starts `sweetspot node` as a child process of the same binary (recording to a fresh bag), runs the
//! simulated rig in this process, and pushes a realistic session through the real DDS path: the rig
//! publishes its ball and bats (latched) and one Swing per swing; the node answers each with an
//! ExitVelocity and ModalEnergies and publishes a SweetSpot per bat; the demo listens to the answers like
//! any other ROS 2 client. Discovery is loopback-only unless `--env-discovery` is given (the demo talks only
//! to itself). At the end the node is stopped with SIGTERM (so it closes the bag), the bag is read back, and
//! the demo prints a table per bat and writes figures next to the bag.

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, Context, Result};

use crate::cli::figures::{write_figures, FigureFormat, FigureSettings, EXIT_SPEED_LABEL, Z_LABEL};
use crate::cli::output::{num, Table};
use crate::cli::plot::{draw_panels, ImageFormat, LineChart, LineKind, Series, VerticalMarker};
use crate::cli::rig::RigOptions;
use crate::model::time::{now_ns, RosTime};
use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, ModalEnergies, SweetSpot, Swing};
use crate::msgs::RosMessage;
use crate::physics::metrics::{linspace, sweep};
use crate::physics::Impact;
use crate::rig::dds::{context, Answer, AnswerListener, RigPublisher};
use crate::rig::{RigSwing, SessionGenerator, INCH, MPH, RIG_BALL_ID};
use crate::ros::{DdsConfig, DiscoveryRange};

/// Node name of the demo's node.
pub const DEMO_NODE_NAME: &str = "sweetspot_demo";
/// Environment variable naming the `sweetspot` executable to start the node with (default: this one).
pub const ENV_EXE: &str = "SWEETSPOT_EXE";
/// Swings in flight (sent but not answered) when no rate is given: enough to keep the node's workers busy.
const WINDOW: u64 = 32;

/// Arguments of `sweetspot demo`.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  cargo run --release -- demo
  sweetspot demo --swings 400 --true-cor 0.50     # then: sweetspot calibrate <the bag it prints>
  sweetspot demo --bats r161,aluminum --format svg --out /tmp/bags")]
pub struct DemoArgs {
    #[command(flatten)]
    pub rig: RigOptions,
    /// Swings in the session.
    #[arg(long, default_value_t = 200, value_name = "N")]
    pub swings: u64,
    /// Swings per second (default: as fast as the node answers).
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// Directory the bag (and its figures) are written under.
    #[arg(long, default_value = "bags", value_name = "DIR")]
    pub out: PathBuf,
    /// Namespace of the demo's node and rig.
    #[arg(long, alias = "ns", default_value = "/demo", value_name = "NS")]
    pub namespace: String,
    /// Figure format.
    #[arg(long, value_enum, default_value_t = FigureFormat::Png)]
    pub format: FigureFormat,
    /// Skip the figures.
    #[arg(long)]
    pub no_figures: bool,
    /// Use ROS_AUTOMATIC_DISCOVERY_RANGE from the environment instead of LOCALHOST (e.g. to watch the demo
    /// from Foxglove or `ros2 topic echo` on another machine).
    #[arg(long)]
    pub env_discovery: bool,
    /// Seconds to wait for the node to start, and for any answer before giving up.
    #[arg(long, default_value_t = 60.0, value_name = "S")]
    pub timeout: f64,
}

/// Everything the node answered, keyed the way the report needs it.
#[derive(Debug, Default)]
pub struct Answers {
    /// ExitVelocity by swing_id.
    pub exits: BTreeMap<u64, ExitVelocity>,
    /// ModalEnergies by swing_id.
    pub modals: BTreeMap<u64, ModalEnergies>,
    /// Latest SweetSpot per bat (the one computed with the rig's ball once it arrived).
    pub sweet_spots: BTreeMap<String, SweetSpot>,
    /// Undecodable samples.
    pub undecodable: u64,
}

impl Answers {
    fn absorb(&mut self, (answers, bad): (Vec<Answer>, u64)) {
        self.undecodable += bad;
        for a in answers {
            match a {
                Answer::Exit(e) => {
                    self.exits.insert(e.swing_id, e);
                }
                Answer::Modal(m) => {
                    self.modals.insert(m.swing_id, m);
                }
                // Prefer the SweetSpot computed with the rig's ball; one with another ball stands in until then.
                Answer::SweetSpot(s) => {
                    let keep_old = self
                        .sweet_spots
                        .get(&s.bat_id)
                        .is_some_and(|old| old.ball_id == RIG_BALL_ID && s.ball_id != RIG_BALL_ID);
                    if !keep_old {
                        self.sweet_spots.insert(s.bat_id.clone(), s);
                    }
                }
            }
        }
    }
}

/// One row of the demo's table.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct BatRow {
    /// bat_id.
    pub bat_id: String,
    /// Swings answered OK.
    pub swings: usize,
    /// Swings rejected.
    pub rejected: usize,
    /// Mean predicted exit speed, m/s.
    pub mean_exit_speed: f64,
    /// Best predicted exit speed, m/s.
    pub best_exit_speed: f64,
    /// Sweet spot (maximum exit speed for the node's reference swing), m from the knob.
    pub sweet_spot_z: f64,
    /// Bat length, m.
    pub length: f64,
    /// BBCOR.
    pub bbcor: f64,
    /// Mean share of the collision energy left in bat vibration.
    pub vibration_share: f64,
    /// Mean of measured − predicted, m/s.
    pub mean_error: f64,
    /// RMS of measured − predicted, m/s.
    pub rms_error: f64,
}

/// The per-bat summary of a session: answers joined with the rig's bats.
pub fn summarize(rig: &SessionGenerator, answers: &Answers) -> Vec<BatRow> {
    rig.bats()
        .iter()
        .map(|b| {
            let exits: Vec<&ExitVelocity> = answers.exits.values().filter(|e| e.bat_id == b.bat_id).collect();
            let ok: Vec<&&ExitVelocity> = exits.iter().filter(|e| e.status == ExitVelocity::STATUS_OK).collect();
            let n = ok.len().max(1) as f64;
            let speeds = ok.iter().map(|e| e.exit_speed);
            let errors: Vec<f64> =
                ok.iter().map(|e| e.measured_exit_speed - e.exit_speed).filter(|r| r.is_finite()).collect();
            let ne = errors.len().max(1) as f64;
            let shares: Vec<f64> = answers
                .modals
                .values()
                .filter(|m| m.bat_id == b.bat_id)
                .map(|m| m.fraction.iter().sum::<f64>())
                .filter(|v| v.is_finite())
                .collect();
            let spot = answers.sweet_spots.get(&b.bat_id);
            BatRow {
                bat_id: b.bat_id.clone(),
                swings: ok.len(),
                rejected: exits.len() - ok.len(),
                mean_exit_speed: speeds.clone().sum::<f64>() / n,
                best_exit_speed: speeds.fold(f64::NAN, f64::max),
                sweet_spot_z: spot.map(|s| s.max_exit_speed_z).unwrap_or(f64::NAN),
                length: b.modes.length(),
                bbcor: spot.map(|s| s.bbcor).unwrap_or(f64::NAN),
                vibration_share: shares.iter().sum::<f64>() / shares.len().max(1) as f64,
                mean_error: errors.iter().sum::<f64>() / ne,
                rms_error: (errors.iter().map(|r| r * r).sum::<f64>() / ne).sqrt(),
            }
        })
        .collect()
}

/// The table of [`summarize`] as text.
pub fn table(rows: &[BatRow]) -> String {
    let mut t =
        Table::new(["bat", "swings", "mean exit", "best exit", "sweet spot", "BBCOR", "vibration", "measured − model"]);
    t.row(["", "", "m/s (mph)", "m/s (mph)", "m from knob (in from end)", "", "energy share", "mean ± RMS m/s"]);
    for r in rows {
        t.row([
            if r.rejected > 0 { format!("{} ({} rejected)", r.bat_id, r.rejected) } else { r.bat_id.clone() },
            r.swings.to_string(),
            format!("{:.1} ({:.1})", r.mean_exit_speed, r.mean_exit_speed / MPH),
            format!("{:.1} ({:.1})", r.best_exit_speed, r.best_exit_speed / MPH),
            format!("{:.3} ({:.1})", r.sweet_spot_z, (r.length - r.sweet_spot_z) / INCH),
            num(r.bbcor, 3),
            format!("{:.1} %", 100.0 * r.vibration_share),
            format!("{:+.2} ± {:.2}", r.mean_error, r.rms_error),
        ]);
    }
    t.render()
}

/// The node child process; stopped with SIGTERM (then killed) when dropped.
struct NodeProcess {
    child: Child,
    log: PathBuf,
}

impl NodeProcess {
    fn start(
        exe: &Path,
        namespace: &str,
        bag: &Path,
        log: &Path,
        range: Option<DiscoveryRange>,
    ) -> Result<NodeProcess> {
        let log_file = std::fs::File::create(log).with_context(|| format!("cannot create '{}'", log.display()))?;
        let mut cmd = Command::new(exe);
        cmd.arg("node")
            .arg("--ros-args")
            .args(["-r", &format!("__ns:={namespace}")])
            .args(["-r", &format!("__node:={DEMO_NODE_NAME}")])
            .args(["-p", &format!("record_path:={}", bag.display())])
            .stdin(Stdio::null())
            .stdout(log_file.try_clone().context("node log")?)
            .stderr(log_file);
        if let Some(range) = range {
            cmd.env(crate::ros::ENV_DISCOVERY_RANGE, range.as_str());
        }
        let child = cmd.spawn().with_context(|| format!("cannot start the node ('{} node')", exe.display()))?;
        Ok(NodeProcess { child, log: log.to_path_buf() })
    }

    /// Why the node is gone, if it is.
    fn exited(&mut self) -> Option<String> {
        match self.child.try_wait() {
            Ok(Some(status)) => Some(format!("the node exited early ({status}); its log:\n{}", self.log_tail())),
            Ok(None) => None,
            Err(e) => Some(format!("cannot watch the node process: {e}")),
        }
    }

    fn log_tail(&self) -> String {
        let text = std::fs::read_to_string(&self.log).unwrap_or_default();
        let lines: Vec<&str> = text.lines().collect();
        lines[lines.len().saturating_sub(15)..].join("\n")
    }

    /// SIGTERM, then wait up to `grace` for a clean exit (the bag is finished on the way out).
    fn stop(&mut self, grace: Duration) -> Result<()> {
        if self.child.try_wait().ok().flatten().is_none() {
            let _ = Command::new("kill").args(["-TERM", &self.child.id().to_string()]).status();
        }
        let start = Instant::now();
        loop {
            match self.child.try_wait() {
                Ok(Some(status)) if status.success() => return Ok(()),
                Ok(Some(status)) => bail!("the node ended with {status}; its log:\n{}", self.log_tail()),
                Ok(None) if start.elapsed() < grace => std::thread::sleep(Duration::from_millis(20)),
                Ok(None) => {
                    let _ = self.child.kill();
                    let _ = self.child.wait();
                    bail!("the node did not stop within {:.0} s of SIGTERM and was killed", grace.as_secs_f64());
                }
                Err(e) => bail!("waiting for the node: {e}"),
            }
        }
    }
}

impl Drop for NodeProcess {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            let _ = self.stop(Duration::from_secs(3));
        }
    }
}

/// Progress shown while the session runs: a bar on a terminal, a few plain lines otherwise.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
    total: u64,
    last_line: u64,
}

impl Progress {
    fn new(total: u64) -> Progress {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = indicatif::ProgressBar::new(total);
            if let Ok(style) =
                indicatif::ProgressStyle::with_template("{spinner} {msg:<28} [{bar:40}] {pos}/{len} swings ({elapsed})")
            {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_message("swings answered by the node");
            bar
        });
        Progress { bar, total, last_line: 0 }
    }

    fn set(&mut self, done: u64) {
        match &self.bar {
            Some(bar) => bar.set_position(done),
            None => {
                // Plain lines at every 25 % for logs and pipes.
                let quarter = (done * 4 / self.total.max(1)).min(4);
                if quarter > self.last_line {
                    self.last_line = quarter;
                    eprintln!("demo: {done}/{} swings answered", self.total);
                }
            }
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

fn say(text: &str) {
    eprintln!("demo: {text}");
}

/// A fresh directory name under `out`: `demo_<UTC time>` (with `-2`, `-3`… if taken).
fn fresh_bag_dir(out: &Path) -> PathBuf {
    let base = crate::bag::default_bag_dir(out, "demo", std::time::SystemTime::now());
    let mut dir = base.clone();
    let mut n = 2;
    while dir.exists() || figures_dir(&dir).exists() {
        dir = PathBuf::from(format!("{}-{n}", base.display()));
        n += 1;
    }
    dir
}

/// Where the figures of the bag `bag` go: a sibling directory `<bag>_figures`.
pub fn figures_dir(bag: &Path) -> PathBuf {
    PathBuf::from(format!("{}_figures", bag.display()))
}

/// Runs `sweetspot demo`.
pub fn run(args: DemoArgs) -> Result<()> {
    let started = Instant::now();
    if args.swings == 0 || args.swings > 1_000_000 {
        bail!("--swings must be between 1 and 1000000, got {}", args.swings);
    }
    if let Some(rate) = args.rate {
        if !(rate.is_finite() && rate > 0.0 && rate <= 10_000.0) {
            bail!("--rate must be in (0, 10000] swings per second, got {rate}");
        }
    }
    if !(args.timeout.is_finite() && args.timeout > 0.0) {
        bail!("--timeout must be positive seconds, got {}", args.timeout);
    }
    let timeout = Duration::from_secs_f64(args.timeout);
    let config = args.rig.config()?;
    let mut rig = SessionGenerator::new(config).context("building the rig's bats")?.with_block(args.rig.swings_per_bat);

    let mut dds = DdsConfig::from_env()?;
    let forced_range = (!args.env_discovery).then_some(DiscoveryRange::Localhost);
    if let Some(range) = forced_range {
        dds.range = range;
    }
    std::fs::create_dir_all(&args.out).with_context(|| format!("cannot create '{}'", args.out.display()))?;
    let bag = fresh_bag_dir(&args.out);
    let log = PathBuf::from(format!("{}.node.log", bag.display()));
    let exe = match std::env::var_os(ENV_EXE) {
        Some(p) => PathBuf::from(p),
        None => std::env::current_exe().context("cannot find the sweetspot executable to start the node")?,
    };
    say(&format!(
        "starting the node (namespace {}, DDS domain {}, discovery {}), recording to {}",
        args.namespace,
        dds.domain_id,
        dds.range,
        bag.display()
    ));
    let mut node = NodeProcess::start(&exe, &args.namespace, &bag, &log, forced_range)?;

    let ctx = context(&dds)?;
    let mut publisher = RigPublisher::new(&ctx, &args.namespace)?;
    let listener = AnswerListener::new(&ctx, &publisher.names)?;
    publisher.wait_for_subscribers(1, timeout, || node.exited())?;
    say(&format!(
        "node is up after {:.1} s; the rig announces its ball and {} bats",
        started.elapsed().as_secs_f64(),
        rig.bats().len()
    ));

    // Ball first: the node computes each bat's SweetSpot with the latest ball, and we wait for those.
    let stamp = Time::from_unix_ns(now_ns());
    publisher.publish_ball(rig.ball_params(stamp.clone()))?;
    if !publisher.wait_acknowledged(timeout) {
        bail!("the node did not acknowledge the ball params within {:.0} s", args.timeout);
    }
    // Acknowledged means received by the node's DDS reader; let its loop take the ball before the bats arrive.
    std::thread::sleep(Duration::from_millis(200));
    for p in rig.bat_params(stamp) {
        publisher.publish_bat(p)?;
    }
    let mut answers = Answers::default();
    let wait_start = Instant::now();
    while rig.bats().iter().any(|b| !answers.sweet_spots.contains_key(&b.bat_id)) {
        if let Some(reason) = node.exited() {
            bail!("{reason}");
        }
        if wait_start.elapsed() > timeout {
            bail!("the node published no SweetSpot for every bat within {:.0} s", args.timeout);
        }
        answers.absorb(listener.poll());
        std::thread::sleep(Duration::from_millis(10));
    }
    say(&format!("modes and sweet spots ready after {:.1} s; swinging", started.elapsed().as_secs_f64()));

    // The session: swings at the rate, or as fast as the node answers with a bounded window in flight.
    let total = args.swings;
    let mut truths: BTreeMap<u64, (RigSwing, Swing)> = BTreeMap::new();
    let mut progress = Progress::new(total);
    let session_start = Instant::now();
    let mut last_answer = Instant::now();
    let mut sent = 0u64;
    let mut answered = 0usize;
    while (answers.exits.len() as u64) < total {
        if let Some(reason) = node.exited() {
            progress.finish();
            bail!("{reason}");
        }
        let due = match args.rate {
            Some(rate) => session_start + Duration::from_secs_f64(sent as f64 / rate) <= Instant::now(),
            None => sent < answers.exits.len() as u64 + WINDOW,
        };
        if sent < total && due {
            let swing = rig.next_swing().context("simulating a swing")?;
            let msg = rig.swing_message(&swing, Time::from_unix_ns(now_ns()));
            publisher.publish_swing(msg.clone())?;
            truths.insert(swing.swing_id, (swing, msg));
            sent += 1;
            continue;
        }
        answers.absorb(listener.poll());
        if answers.exits.len() > answered {
            answered = answers.exits.len();
            last_answer = Instant::now();
            progress.set(answered as u64);
        } else if last_answer.elapsed() > timeout {
            progress.finish();
            bail!("no answer from the node for {:.0} s ({answered} of {total} swings answered)", args.timeout);
        } else {
            std::thread::sleep(Duration::from_millis(2));
        }
    }
    // ModalEnergies travel on their own topic; give the last ones a moment.
    let settle = Instant::now();
    while (answers.modals.len() as u64) < total && settle.elapsed() < Duration::from_secs(2) {
        answers.absorb(listener.poll());
        std::thread::sleep(Duration::from_millis(5));
    }
    progress.finish();
    let session_time = session_start.elapsed();
    say(&format!(
        "{total} swings answered in {:.2} s ({:.0} swings/s); stopping the node",
        session_time.as_secs_f64(),
        total as f64 / session_time.as_secs_f64().max(1e-9)
    ));
    node.stop(Duration::from_secs(10))?;

    let info = crate::bag::info::bag_info(&bag).with_context(|| format!("reading back the bag '{}'", bag.display()))?;
    let count_of = |ty: &str| info.topics.iter().filter(|t| t.type_name == ty).map(|t| t.count).sum::<u64>();
    let (bag_swings, bag_exits) = (count_of(Swing::TYPE_NAME), count_of(ExitVelocity::TYPE_NAME));

    let rows = summarize(&rig, &answers);
    println!();
    println!(
        "sweetspot demo — {total} swings, {} bats, pitches {:.0}–{:.0} mph, bat speed {:.0}–{:.0} mph at the barrel, seed {}",
        rig.bats().len(),
        rig.config().pitch_speed.0 / MPH,
        rig.config().pitch_speed.1 / MPH,
        rig.config().barrel_speed.0 / MPH,
        rig.config().barrel_speed.1 / MPH,
        rig.config().seed
    );
    println!();
    print!("{}", table(&rows));
    println!();
    println!(
        "exit speeds are the node's model; \"measured − model\" compares them with the rig's radar (σ {} m/s). Sweet spot\n\
         and BBCOR come from the node's SweetSpot messages (its reference swing); vibration is the mean share of the\n\
         collision energy left ringing in the bat (ModalEnergies).",
        rig.config().noise.exit_speed
    );
    println!();
    println!(
        "bag:      {}  ({} swings, {} exit velocities, {} messages)",
        bag.display(),
        bag_swings,
        bag_exits,
        info.messages
    );
    println!("node log: {}", log.display());

    if !args.no_figures {
        let dir = figures_dir(&bag);
        let files = write_demo_figures(&dir, &rig, &truths, &answers, args.format)?;
        println!("figures:  {}/ ({})", dir.display(), files.join(", "));
    }
    println!();
    println!("next:     sweetspot bag info {}", bag.display());
    println!("          sweetspot bag replay {}", bag.display());
    println!("          sweetspot calibrate {}", bag.display());
    println!("(demo took {:.1} s)", started.elapsed().as_secs_f64());
    if bag_swings != total || bag_exits != total {
        bail!("the bag holds {bag_swings} swings and {bag_exits} exit velocities, expected {total} of each");
    }
    if answers.undecodable > 0 {
        bail!("{} answers could not be decoded", answers.undecodable);
    }
    Ok(())
}

/// The demo's figures: exit speed against impact point per bat (measured, model, and the model's curve for
/// the session's mean swing), then `sweetspot figures`' seed comparisons and mode shapes. Returns the files.
pub fn write_demo_figures(
    dir: &Path,
    rig: &SessionGenerator,
    truths: &BTreeMap<u64, (RigSwing, Swing)>,
    answers: &Answers,
    format: FigureFormat,
) -> Result<Vec<String>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create '{}'", dir.display()))?;
    let image: ImageFormat = format.into();
    let ext = image.extension();
    let ball = rig.config().ball;
    let options = rig.config().options;
    let mut panels = Vec::new();
    let mut all_swings: Vec<Impact> = Vec::new();
    for (i, b) in rig.bats().iter().enumerate() {
        let swings: Vec<&(RigSwing, Swing)> = truths.values().filter(|(s, _)| s.bat_id == b.bat_id).collect();
        if swings.is_empty() {
            continue;
        }
        let n = swings.len() as f64;
        let mean = Impact {
            ball_speed: swings.iter().map(|(s, _)| s.measured.ball_speed).sum::<f64>() / n,
            bat_cm_speed: swings.iter().map(|(s, _)| s.measured.bat_cm_speed).sum::<f64>() / n,
            bat_angular_speed: swings.iter().map(|(s, _)| s.measured.bat_angular_speed).sum::<f64>() / n,
            impact_z: f64::NAN,
        };
        all_swings.push(mean);
        let length = b.modes.length();
        let zs = linspace(0.5 * length, length - 0.02, 60);
        let curve =
            sweep(&b.modes, &ball, &mean, &zs, &options).with_context(|| format!("model curve of '{}'", b.bat_id))?;
        let measured: Vec<(f64, f64)> =
            swings.iter().map(|(s, _)| (s.measured.impact_z, s.reading.exit_speed)).collect();
        let model: Vec<(f64, f64)> = swings
            .iter()
            .filter_map(|(s, m)| {
                answers
                    .exits
                    .get(&m.swing_id)
                    .filter(|e| e.status == ExitVelocity::STATUS_OK)
                    .map(|e| (s.measured.impact_z, e.exit_speed))
            })
            .collect();
        let mut chart = LineChart {
            title: format!("{} ({} swings)", b.bat_id, swings.len()),
            x_label: Z_LABEL.into(),
            y_label: EXIT_SPEED_LABEL.into(),
            series: vec![
                Series { label: "rig radar (measured)".into(), points: measured, color: 6, kind: LineKind::Points },
                Series {
                    label: "node (model, same swing)".into(),
                    points: model,
                    color: i % 6,
                    kind: LineKind::Points,
                },
                Series::solid(
                    format!(
                        "model, mean swing ({:.0} mph pitch, ω {:.0} rad/s)",
                        mean.ball_speed / MPH,
                        mean.bat_angular_speed
                    ),
                    i % 6,
                    curve.iter().map(|p| (p.impact_z, p.result.exit_speed)).collect(),
                ),
            ],
            ..Default::default()
        };
        if let Some(s) = answers.sweet_spots.get(&b.bat_id) {
            chart.markers.push(VerticalMarker {
                x: s.max_exit_speed_z,
                label: "sweet spot (reference swing)".into(),
                color: 4,
                dashed: true,
            });
        }
        panels.push(chart);
    }
    let mut files = Vec::new();
    if !panels.is_empty() {
        let file = format!("demo-exit-speed-vs-impact.{ext}");
        draw_panels(&dir.join(&file), &panels, 2, Some("Demo session: exit speed against impact point"))?;
        files.push(file);
    }
    // The seed's comparisons and the mode shapes, for the session's typical swing.
    let n = all_swings.len().max(1) as f64;
    let typical = Impact {
        ball_speed: all_swings.iter().map(|s| s.ball_speed).sum::<f64>() / n,
        bat_cm_speed: all_swings.iter().map(|s| s.bat_cm_speed).sum::<f64>() / n,
        bat_angular_speed: all_swings.iter().map(|s| s.bat_angular_speed).sum::<f64>() / n,
        impact_z: f64::NAN,
    };
    let settings = FigureSettings { format: image, points: 60, swing: typical, ball, options };
    let entries = write_figures(dir, &settings).map_err(|e| anyhow!("seed figures: {e:#}"))?;
    files.extend(entries.into_iter().map(|e| e.file));
    Ok(files)
}
