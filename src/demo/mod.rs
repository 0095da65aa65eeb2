//! `sweetspot demo`: the whole system in one command, with nothing else installed.
//!
//! It starts `sweetspot node` as a child process of the same binary (recording to a fresh bag), runs the
//! simulated rig in this process, and pushes a realistic session through the real DDS path: the rig
//! publishes its ball and bats (latched) and one Swing per swing; the node answers each with an
//! ExitVelocity and ModalEnergies and publishes a SweetSpot per bat; the demo listens to the answers like
//! any other ROS 2 client. Discovery is loopback-only unless asked otherwise (the demo talks only to
//! itself). At the end the node is stopped with SIGTERM (so it closes the bag), the bag is read back, and
//! the demo prints a table per bat and writes figures next to the bag.

mod figures;
mod summary;

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};

pub use figures::{figures_dir, write_demo_figures};
pub use summary::{summarize, table, Answers, BatRow};

use crate::child::{ChildCommand, ChildProcess};
use crate::model::time::{now_ns, RosTime};
use crate::msgs::builtin_interfaces::msg::Time;
use crate::msgs::sweetspot_msgs::msg::{ExitVelocity, Swing};
use crate::msgs::RosMessage;
use crate::physics::units::{rad_per_s_to_rpm, INCH, MPH};
use crate::report::plot::ImageFormat;
use crate::rig::dds::{context, AnswerListener, RigPublisher};
use crate::rig::{LaunchConditions, RigConfig, RigSwing, SessionGenerator};
use crate::ros::{DdsConfig, DiscoveryRange};

/// A line of the report on stdout; a closed pipe (`demo | head`) drops the rest quietly (see
/// [`crate::report::stdout`]), and so does any other failure to write it: the session and its bag stand.
macro_rules! outln {
    () => {
        let _ = crate::report::stdout::emit("\n");
    };
    ($($arg:tt)*) => {
        let _ = crate::report::stdout::emit(&format!("{}\n", format_args!($($arg)*)));
    };
}

/// Node name of the demo's node.
pub const DEMO_NODE_NAME: &str = "sweetspot_demo";
/// Environment variable naming the `sweetspot` executable to start the node with (default: this one).
pub const ENV_EXE: &str = "SWEETSPOT_EXE";
/// Swings in flight (sent but not answered) when no rate is given: enough to keep the node's workers busy.
const WINDOW: u64 = 32;

/// What a demo session runs and where it writes.
#[derive(Debug, Clone)]
pub struct DemoSettings {
    /// The simulated rig: its bats, ball, sensors and seed.
    pub rig: RigConfig,
    /// Consecutive swings with each bat before the next one.
    pub swings_per_bat: usize,
    /// Swings in the session (at least one).
    pub swings: u64,
    /// Swings per second, positive and finite; `None`: as fast as the node answers.
    pub rate: Option<f64>,
    /// Directory the bag (and its figures) are written under.
    pub out: PathBuf,
    /// Namespace of the node and the rig.
    pub namespace: String,
    /// Format of the figures; `None`: no figures.
    pub figures: Option<ImageFormat>,
    /// Takes the DDS discovery range from the environment instead of loopback only.
    pub env_discovery: bool,
    /// How long to wait for the node to start, and for any answer, before giving up.
    pub timeout: Duration,
}

/// Starts `exe` as the demo's node in `namespace`, recording to `bag`, its output in `log`.
fn start_node(
    exe: &Path,
    namespace: &str,
    bag: &Path,
    log: &Path,
    range: Option<DiscoveryRange>,
) -> Result<ChildProcess> {
    let mut command = ChildCommand::node(exe)
        .remap("__ns", namespace)
        .remap("__node", DEMO_NODE_NAME)
        .param("record_path", bag.display())
        .log_to(log);
    if let Some(range) = range {
        command = command.env(crate::ros::ENV_DISCOVERY_RANGE, range.as_str());
    }
    command.spawn()
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

/// A demo stopped by Ctrl-C (SIGINT) or SIGTERM: it printed what it had (a partial report) and exits with
/// status 130, as a shell reports a command interrupted by SIGINT.
#[derive(Debug, thiserror::Error)]
#[error("interrupted after {answered} of {total} swings answered (partial report above; the bag keeps them)")]
pub struct Interrupted {
    /// Swings answered before the interruption.
    pub answered: u64,
    /// Swings the session was to have.
    pub total: u64,
}

/// Why the session cannot go on, if it cannot: an interruption (Ctrl-C reaches the node too, so a node that
/// exits right after one is part of it, not a failure), or the node's own early exit.
fn stop_reason(node: &mut ChildProcess, interrupted: &AtomicBool) -> Option<String> {
    if interrupted.load(Ordering::Relaxed) {
        return Some(INTERRUPTED.into());
    }
    let reason = node.exited()?;
    // The node may have seen the terminal's SIGINT before our signal thread did.
    std::thread::sleep(Duration::from_millis(300));
    Some(if interrupted.load(Ordering::Relaxed) { INTERRUPTED.into() } else { reason })
}

/// The reason [`stop_reason`] gives for an interruption.
const INTERRUPTED: &str = "interrupted";

/// The rig's side of a session while the node runs: what it publishes on, what it has heard back.
struct Session<'a> {
    rig: SessionGenerator,
    publisher: RigPublisher,
    listener: AnswerListener,
    node: &'a mut ChildProcess,
    answers: Answers,
    timeout: Duration,
    interrupted: Arc<AtomicBool>,
    total: u64,
}

impl Session<'_> {
    /// Fails when the session cannot go on: [`Interrupted`], or the node's early exit.
    fn check(&mut self) -> Result<()> {
        match stop_reason(self.node, &self.interrupted) {
            None => Ok(()),
            Some(reason) if reason == INTERRUPTED => {
                Err(Interrupted { answered: self.answers.exits.len() as u64, total: self.total }.into())
            }
            Some(reason) => bail!("{reason}"),
        }
    }

    /// Publishes the ball, then the bats, and waits until the node has published a SweetSpot for every bat.
    fn announce(&mut self) -> Result<()> {
        // Ball first: the node computes each bat's SweetSpot with the latest ball, and we wait for those.
        let stamp = Time::from_unix_ns(now_ns());
        self.publisher.publish_ball(self.rig.ball_params(stamp.clone()))?;
        if !self.publisher.wait_acknowledged(self.timeout) {
            bail!("the node did not acknowledge the ball params within {:.0} s", self.timeout.as_secs_f64());
        }
        // Acknowledged means received by the node's DDS reader; let its loop take the ball before the bats arrive.
        std::thread::sleep(Duration::from_millis(200));
        for p in self.rig.bat_params(stamp) {
            self.publisher.publish_bat(p)?;
        }
        let wait_start = Instant::now();
        while self.rig.bats().iter().any(|b| !self.answers.sweet_spots.contains_key(&b.bat_id)) {
            self.check()?;
            if wait_start.elapsed() > self.timeout {
                bail!("the node published no SweetSpot for every bat within {:.0} s", self.timeout.as_secs_f64());
            }
            self.answers.absorb(self.listener.poll());
            std::thread::sleep(Duration::from_millis(10));
        }
        Ok(())
    }

    /// Swings `total` times at `rate`, or as fast as the node answers with a bounded window in flight, until
    /// every swing is answered; returns each swing's truth and message by swing_id.
    fn swing(&mut self, total: u64, rate: Option<f64>) -> Result<BTreeMap<u64, (RigSwing, Swing)>> {
        let mut truths = BTreeMap::new();
        let mut progress = Progress::new(total);
        let outcome = self.swing_until_answered(total, rate, &mut truths, &mut progress);
        if outcome.is_ok() {
            // ModalEnergies travel on their own topic; give the last ones a moment.
            let settle = Instant::now();
            while (self.answers.modals.len() as u64) < total && settle.elapsed() < Duration::from_secs(2) {
                self.answers.absorb(self.listener.poll());
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        progress.finish();
        outcome.map(|()| truths)
    }

    fn swing_until_answered(
        &mut self,
        total: u64,
        rate: Option<f64>,
        truths: &mut BTreeMap<u64, (RigSwing, Swing)>,
        progress: &mut Progress,
    ) -> Result<()> {
        let session_start = Instant::now();
        let mut last_answer = Instant::now();
        let mut sent = 0u64;
        let mut answered = 0usize;
        while (self.answers.exits.len() as u64) < total {
            self.check()?;
            let due = match rate {
                Some(rate) => session_start + crate::model::time::saturating_secs(sent as f64 / rate) <= Instant::now(),
                None => sent < self.answers.exits.len() as u64 + WINDOW,
            };
            if sent < total && due {
                let swing = self.rig.next_swing().context("simulating a swing")?;
                let msg = self.rig.swing_message(&swing, Time::from_unix_ns(now_ns()));
                self.publisher.publish_swing(msg.clone())?;
                truths.insert(swing.swing_id, (swing, msg));
                sent += 1;
                continue;
            }
            self.answers.absorb(self.listener.poll());
            if self.answers.exits.len() > answered {
                answered = self.answers.exits.len();
                last_answer = Instant::now();
                progress.set(answered as u64);
            } else if last_answer.elapsed() > self.timeout {
                bail!(
                    "no answer from the node for {:.0} s ({answered} of {total} swings answered)",
                    self.timeout.as_secs_f64()
                );
            } else {
                std::thread::sleep(Duration::from_millis(2));
            }
        }
        Ok(())
    }
}

/// Runs a demo session: node, rig and recorder over real DDS, then the table, the bag and the figures.
pub fn run(settings: DemoSettings) -> Result<()> {
    let started = Instant::now();
    let rig = demo_rig(&settings)?;
    let (dds, forced_range) = demo_dds(&settings)?;
    std::fs::create_dir_all(&settings.out).with_context(|| format!("cannot create '{}'", settings.out.display()))?;
    let bag = fresh_bag_dir(&settings.out);
    let log = PathBuf::from(format!("{}.node.log", bag.display()));
    let exe = match std::env::var_os(ENV_EXE) {
        Some(p) => PathBuf::from(p),
        None => std::env::current_exe().context("cannot find the sweetspot executable to start the node")?,
    };
    say(&format!(
        "starting the node (namespace {}, DDS domain {}, discovery {}), recording to {}",
        settings.namespace,
        dds.domain_id,
        dds.range,
        bag.display()
    ));
    // Ctrl-C reaches the node too (same process group); we stop with a partial report, not "node exited".
    let interrupted = crate::ros::interrupt_flag();
    let mut node = start_node(&exe, &settings.namespace, &bag, &log, forced_range)?;
    let ctx = context(&dds)?;
    let session = connect_rig(&settings, &ctx, rig, &mut node, &interrupted, started)?;
    let (rig, answers, truths) = run_session(session, &settings, started, &bag, &log)?;
    report(&settings, &rig, &answers, &truths, &bag, &log, started)
}

/// The rig of `settings`: it swings obliquely and tracks launch angle and spin unless its config says how
/// already.
fn demo_rig(settings: &DemoSettings) -> Result<SessionGenerator> {
    let mut rig_config = settings.rig.clone();
    rig_config.launch = rig_config.launch.or(Some(LaunchConditions::default()));
    Ok(SessionGenerator::new(rig_config).context("building the rig's bats")?.with_block(settings.swings_per_bat))
}

/// The DDS config from the environment, and the discovery range forced on it (localhost unless the
/// environment's is asked for).
fn demo_dds(settings: &DemoSettings) -> Result<(DdsConfig, Option<DiscoveryRange>)> {
    let mut dds = DdsConfig::from_env()?;
    let forced_range = (!settings.env_discovery).then_some(DiscoveryRange::Localhost);
    if let Some(range) = forced_range {
        dds.range = range;
    }
    Ok((dds, forced_range))
}

/// The rig's publisher and listener, once the node subscribes: a session ready to announce.
fn connect_rig<'a>(
    settings: &DemoSettings,
    ctx: &ros2_client::Context,
    rig: SessionGenerator,
    node: &'a mut ChildProcess,
    interrupted: &Arc<AtomicBool>,
    started: Instant,
) -> Result<Session<'a>> {
    let total = settings.swings;
    let mut publisher = RigPublisher::new(ctx, &settings.namespace)?;
    let listener = AnswerListener::new(ctx, &publisher.names)?;
    let waited = publisher.wait_for_subscribers(1, settings.timeout, || stop_reason(node, interrupted));
    if waited.is_err() && interrupted.load(Ordering::Relaxed) {
        let _ = node.stop(Duration::from_secs(10));
        return Err(Interrupted { answered: 0, total }.into());
    }
    waited?;
    say(&format!(
        "node is up after {:.1} s; the rig announces its ball and {} bats",
        started.elapsed().as_secs_f64(),
        rig.bats().len()
    ));
    Ok(Session {
        rig,
        publisher,
        listener,
        node,
        answers: Answers::default(),
        timeout: settings.timeout,
        interrupted: interrupted.clone(),
        total,
    })
}

/// Each swing's truth and message by swing_id (see [`Session::swing`]).
type Truths = BTreeMap<u64, (RigSwing, Swing)>;

/// Announces, swings every swing and stops the node; on an interruption prints the partial report first.
fn run_session(
    mut session: Session<'_>,
    settings: &DemoSettings,
    started: Instant,
    bag: &Path,
    log: &Path,
) -> Result<(SessionGenerator, Answers, Truths)> {
    let total = settings.swings;
    let mut session_start = Instant::now();
    let swung = match session.announce() {
        Ok(()) => {
            say(&format!("modes and sweet spots ready after {:.1} s; swinging", started.elapsed().as_secs_f64()));
            session_start = Instant::now();
            session.swing(total, settings.rate)
        }
        Err(e) => Err(e),
    };
    let truths = match swung {
        Ok(truths) => truths,
        Err(e) if e.is::<Interrupted>() => {
            // The partial report: what was answered, and the bag the node finished on the way out.
            let Session { rig, answers, node, .. } = session;
            let _ = node.stop(Duration::from_secs(10));
            print_summary(&rig, &answers, answers.exits.len() as u64);
            outln!("bag:      {} (interrupted after {:.1} s)", bag.display(), session_start.elapsed().as_secs_f64());
            outln!("node log: {}", log.display());
            return Err(e);
        }
        Err(e) => return Err(e),
    };
    let session_time = session_start.elapsed();
    say(&format!(
        "{total} swings answered in {:.2} s ({:.0} swings/s); stopping the node",
        session_time.as_secs_f64(),
        total as f64 / session_time.as_secs_f64().max(1e-9)
    ));
    let Session { rig, answers, node, .. } = session;
    node.stop(Duration::from_secs(10))?;
    Ok((rig, answers, truths))
}

/// The table, the bag read back, the figures and what to try next; fails if the bag misses a swing or an
/// answer, or an answer could not be decoded.
fn report(
    settings: &DemoSettings,
    rig: &SessionGenerator,
    answers: &Answers,
    truths: &Truths,
    bag: &Path,
    log: &Path,
    started: Instant,
) -> Result<()> {
    let total = settings.swings;
    let info = crate::bag::info::bag_info(bag).with_context(|| format!("reading back the bag '{}'", bag.display()))?;
    let count_of = |ty: &str| info.topics.iter().filter(|t| t.type_name == ty).map(|t| t.count).sum::<u64>();
    let (bag_swings, bag_exits) = (count_of(Swing::TYPE_NAME), count_of(ExitVelocity::TYPE_NAME));

    print_summary(rig, answers, total);
    outln!(
        "bag:      {}  ({} swings, {} exit velocities, {} messages)",
        bag.display(),
        bag_swings,
        bag_exits,
        info.messages
    );
    outln!("node log: {}", log.display());

    if let Some(format) = settings.figures {
        let dir = figures_dir(bag);
        let files = write_demo_figures(&dir, rig, truths, answers, format)?;
        outln!("figures:  {}/ ({})", dir.display(), files.join(", "));
    }
    outln!();
    outln!("next:     sweetspot bag info {}", bag.display());
    outln!("          sweetspot bag replay {}", bag.display());
    outln!("          sweetspot calibrate {} --fit-tangential", bag.display());
    outln!("(demo took {:.1} s)", started.elapsed().as_secs_f64());
    if bag_swings != total || bag_exits != total {
        bail!("the bag holds {bag_swings} swings and {bag_exits} exit velocities, expected {total} of each");
    }
    if answers.undecodable > 0 {
        bail!("{} answers could not be decoded", answers.undecodable);
    }
    Ok(())
}

/// The session's head line, the table per bat and how to read it.
fn print_summary(rig: &SessionGenerator, answers: &Answers, total: u64) {
    let config = rig.config();
    outln!();
    outln!(
        "sweetspot demo — {total} swings, {} bats, pitches {:.0}–{:.0} mph, bat speed {:.0}–{:.0} mph at the barrel, seed {}",
        rig.bats().len(),
        config.pitch_speed.0 / MPH,
        config.pitch_speed.1 / MPH,
        config.barrel_speed.0 / MPH,
        config.barrel_speed.1 / MPH,
        config.seed
    );
    if let Some(batter) = &config.batter {
        outln!(
            "batter: {:.1} mph at {:.0} in from the barrel end with a bat of swing weight {:.4} kg·m², n = {}; each bat \
             is swung at equal effort (v ∝ I^(−n)), the spread above scaled around that speed",
            batter.reference_speed() / MPH,
            batter.impact_from_barrel_end / INCH,
            batter.reference_swing_weight(),
            batter.exponent
        );
    }
    outln!();
    outln!("{}", table(&summarize(rig, answers)).trim_end_matches('\n'));
    outln!();
    outln!(
        "exit speeds are the node's model; \"measured − model\" compares them with the rig's radar (σ {} m/s). Sweet spot\n\
         and BBCOR come from the node's SweetSpot messages (its reference swing); vibration is the mean share of the\n\
         collision energy left ringing in the bat (ModalEnergies). Bat speed is the batter's at its usual impact point\n\
         for the bat's swing weight; time gained is how much later than with the first bat the swing can start.",
        config.noise.exit_speed
    );
    if let Some(launch) = &config.launch {
        outln!(
            "launch angle and spin (backspin positive) are session means, the node's model / the rig's ball tracker\n\
             (σ {:.1}° and {:.0} rpm); the rig draws undercut {:.1} ± {:.1} cm, attack angle {:.0}° ± {:.0}°, pitch\n\
             descent {:.0}° ± {:.0}° and pitch backspin {:.0} ± {:.0} rpm.",
            launch.noise.launch_angle.to_degrees(),
            rad_per_s_to_rpm(launch.noise.spin),
            100.0 * launch.undercut.mean,
            100.0 * launch.undercut.sigma,
            launch.attack_angle.mean.to_degrees(),
            launch.attack_angle.sigma.to_degrees(),
            launch.pitch_angle.mean.to_degrees(),
            launch.pitch_angle.sigma.to_degrees(),
            rad_per_s_to_rpm(launch.pitch_spin.mean),
            rad_per_s_to_rpm(launch.pitch_spin.sigma),
        );
    }
    outln!();
}

#[cfg(test)]
mod tests {
    use crate::physics::batter::Batter;
    use crate::physics::Bat;
    use crate::rig::{RigConfig, SensorNoise, SessionGenerator};

    /// With no spread in effort and perfect sensors, every simulated swing of every bat is the batter
    /// model's prediction for that bat, bit for bit (no DDS involved).
    #[test]
    fn the_rig_batter_swings_each_bat_at_its_predicted_equal_effort_speed() {
        let batter = Batter::typical(Bat::r161().unwrap().mass_properties()).unwrap();
        let v = batter.reference_speed();
        let config = RigConfig {
            batter: Some(batter),
            barrel_speed: (v, v),
            noise: SensorNoise::none(),
            options: crate::physics::CollisionOptions { modes: 4, ..Default::default() },
            ..RigConfig::default()
        };
        let mut rig = SessionGenerator::new(config).unwrap().with_block(1);
        let mut speeds = Vec::new();
        for _ in 0..rig.bats().len() {
            let swing = rig.next_swing().unwrap();
            let bat = rig.bats().iter().find(|b| b.bat_id == swing.bat_id).unwrap();
            let predicted = batter.predict(&bat.modes.mass_properties()).unwrap();
            assert_eq!(swing.truth.bat_cm_speed, predicted.bat_cm_speed, "{}", swing.bat_id);
            assert_eq!(swing.truth.bat_angular_speed, predicted.bat_angular_speed, "{}", swing.bat_id);
            // The speed the rig's knob sensor and gyro report reproduces the prediction at the usual point.
            let mp = bat.modes.mass_properties();
            let at_usual = swing.reading.knob_speed + swing.reading.angular_rate * predicted.impact_z;
            assert!((at_usual - predicted.bat_speed).abs() < 1e-9 * predicted.bat_speed, "{}", swing.bat_id);
            assert!(mp.length > predicted.impact_z);
            speeds.push((swing.bat_id.clone(), predicted.bat_speed));
        }
        // The reference bat (r161) is swung at the batter's reference speed; the lighter-swinging corked bat
        // faster (its swing weight is lower), so the bats are not all at one speed.
        assert_eq!(speeds[0], ("r161".to_string(), v));
        assert!(speeds[1].0 == "r161-corked" && speeds[1].1 > v, "{speeds:?}");
    }
}
