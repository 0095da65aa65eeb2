//! `sweetspot rig`: the simulated batting rig as its own process, publishing over DDS the way a real sensor
//! rig would — its bats and ball once (latched), then one Swing per measured swing at a steady rate.

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::Args;

use super::common::stdout_closed;
use crate::model::time::{now_ns, period_of, saturating_secs, scaled, RosTime};
use crate::msgs::builtin_interfaces::msg::Time;
use crate::physics::units::MPH;
use crate::physics::Bat;
use crate::rig::dds::{context, RigPublisher};
use crate::rig::{RigConfig, SensorNoise, SessionGenerator};
use crate::ros::DdsConfig;

/// What the simulated rig swings and how noisy its sensors are (shared by `rig` and `demo`).
#[derive(Debug, Clone, Args)]
pub struct RigOptions {
    /// Bat presets swung, comma-separated, in session order.
    #[arg(long, value_delimiter = ',', default_value = "r161,r161-corked,aluminum,torpedo", value_name = "PRESETS")]
    pub bats: Vec<String>,
    /// Consecutive swings with each bat before the next one.
    #[arg(long, default_value_t = 5, value_name = "N")]
    pub swings_per_bat: usize,
    /// Random seed (the same seed gives the same session).
    #[arg(long, default_value_t = 2000)]
    pub seed: u64,
    /// Multiplies every sensor's noise σ (0 = perfect sensors; 1 = the documented defaults: pitch radar
    /// 0.2 m/s, knob gyro 1 %, knob speed 0.1 m/s, impact 5 mm, exit radar 0.45 m/s).
    #[arg(long, default_value_t = 1.0, value_name = "SCALE")]
    pub noise: f64,
    /// The COR of the balls really hit, when it differs from the announced regulation ball's 0.53 (what
    /// `sweetspot calibrate` should then find).
    #[arg(long, value_name = "COR")]
    pub true_cor: Option<f64>,
    /// Pitch speeds, mph: MIN,MAX.
    #[arg(long, value_delimiter = ',', default_values_t = [80.0, 100.0], value_name = "MIN,MAX")]
    pub pitch_mph: Vec<f64>,
    /// Bat speeds at the barrel (6 in from the end), mph: MIN,MAX.
    #[arg(long, value_delimiter = ',', default_values_t = [60.0, 80.0], value_name = "MIN,MAX")]
    pub bat_mph: Vec<f64>,
}

impl RigOptions {
    /// The rig configuration these options describe (validated).
    pub fn config(&self) -> Result<RigConfig> {
        for b in &self.bats {
            if !Bat::preset_names().contains(&b.as_str()) {
                bail!("--bats: unknown preset '{b}' (presets: {})", Bat::preset_names().join(", "));
            }
        }
        if !(self.noise.is_finite() && (0.0..=20.0).contains(&self.noise)) {
            bail!("--noise must be between 0 and 20, got {}", self.noise);
        }
        let d = SensorNoise::default();
        let k = self.noise;
        let noise = SensorNoise {
            ball_speed: d.ball_speed * k,
            angular_rate_relative: d.angular_rate_relative * k,
            knob_speed: d.knob_speed * k,
            impact: d.impact * k,
            exit_speed: d.exit_speed * k,
        };
        for (flag, v) in [("--pitch-mph", &self.pitch_mph), ("--bat-mph", &self.bat_mph)] {
            if v.len() != 2 {
                bail!("{flag} takes two speeds MIN,MAX in mph (e.g. {flag} 80,100), got {} value(s)", v.len());
            }
        }
        let pair = |v: &[f64]| (v[0] * MPH, v[1] * MPH);
        let config = RigConfig {
            bats: self.bats.clone(),
            true_cor: self.true_cor,
            pitch_speed: pair(&self.pitch_mph),
            barrel_speed: pair(&self.bat_mph),
            noise,
            seed: self.seed,
            ..RigConfig::default()
        };
        config.validate().context("rig options")?;
        Ok(config)
    }
}

/// Arguments of `sweetspot rig`.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  sweetspot rig --rate 5                          # forever, 5 swings/s, to a node in the root namespace
  sweetspot rig --count 200 --namespace /rig3 --seed 7 --true-cor 0.50
DDS: ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE (LOCALHOST, SUBNET, OFF), ROS_LOCALHOST_ONLY.")]
pub struct RigArgs {
    #[command(flatten)]
    pub rig: RigOptions,
    /// Swings per second (at most 10000).
    #[arg(long, default_value_t = 2.0, value_name = "HZ", value_parser = super::common::swing_rate_hz)]
    pub rate: f64,
    /// Swings to publish, then exit (default: until Ctrl-C).
    #[arg(long, value_name = "N")]
    pub count: Option<u64>,
    /// Namespace of the node this rig feeds (one node per rig namespace, e.g. /rig3).
    #[arg(long, visible_alias = "ns", default_value = "/", value_name = "NS")]
    pub namespace: String,
    /// Seconds to wait for a node to subscribe before giving up (0 = publish without waiting, inf = no limit).
    #[arg(long, default_value_t = 30.0, value_name = "S", value_parser = super::common::seconds_at_least_zero)]
    pub wait: f64,
    /// Print nothing per swing.
    #[arg(long)]
    pub quiet: bool,
}

/// Runs `sweetspot rig`.
pub fn run(args: RigArgs) -> Result<()> {
    // --rate and --wait are checked by their value parsers (model::time): --wait inf waits for ever.
    let config = args.rig.config()?;
    let mut rig = SessionGenerator::new(config).context("building the rig's bats")?.with_block(args.rig.swings_per_bat);
    let dds = DdsConfig::from_env()?;
    let ctx = context(&dds)?;
    let mut publisher = RigPublisher::new(&ctx, &args.namespace)?;
    let interrupted = interrupt_flag();
    eprintln!(
        "rig: {} bats ({}), publishing on {} (domain {}, discovery {})",
        rig.bats().len(),
        args.rig.bats.join(", "),
        publisher.names.swing,
        dds.domain_id,
        dds.range
    );
    if args.wait > 0.0 {
        eprintln!("rig: waiting up to {:.0} s for a node to subscribe…", args.wait);
        let flag = interrupted.clone();
        publisher.wait_for_subscribers(1, saturating_secs(args.wait), || {
            flag.load(Ordering::Relaxed).then(|| "interrupted".to_string())
        })?;
    }
    let now = now_ns();
    publisher.publish_ball(rig.ball_params(Time::from_unix_ns(now)))?;
    for p in rig.bat_params(Time::from_unix_ns(now)) {
        publisher.publish_bat(p)?;
    }
    if args.wait > 0.0 && !publisher.wait_params_acknowledged(Duration::from_secs(5)) {
        eprintln!("rig: warning: not every subscriber acknowledged the bat and ball params within 5 s");
    }
    let period = period_of(args.rate);
    let start = Instant::now();
    let mut sent = 0u64;
    // A closed stdout (`rig … | head`) ends the session as Ctrl-C does.
    while args.count.is_none_or(|c| sent < c) && !interrupted.load(Ordering::Relaxed) && !stdout_closed() {
        let due = start + scaled(period, sent as f64);
        if let Some(wait) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(wait);
        }
        let swing = rig.next_swing().context("simulating a swing")?;
        let msg = rig.swing_message(&swing, Time::from_unix_ns(now_ns()));
        if !args.quiet {
            crate::outln!(
                "swing {:>5}  {:<12} pitch {:5.1} mph  barrel ω {:5.1} rad/s  impact {:.3} m  measured exit {:5.1} mph",
                msg.swing_id,
                msg.bat_id,
                msg.ball_speed / MPH,
                msg.bat_angular_speed,
                msg.impact_z,
                msg.measured_exit_speed / MPH
            )?;
        }
        publisher.publish_swing(msg)?;
        sent += 1;
    }
    if !publisher.wait_acknowledged(Duration::from_secs(5)) {
        eprintln!("rig: warning: not every subscriber acknowledged every message within 5 s");
    }
    // Acknowledged is not yet taken: a RustDDS reader drops the untaken samples of a participant that left.
    std::thread::sleep(Duration::from_millis(500));
    eprintln!("rig: published {sent} swings");
    Ok(())
}

pub use crate::ros::interrupt_flag;
