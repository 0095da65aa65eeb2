//! A simulated batting rig: a seeded, pure generator of realistic batting sessions.
//!
//! A real rig measures each swing with four sensors; [`SensorReading`] holds exactly those readings, in SI
//! units and with the sign conventions of [`sweetspot_physics`], and [`SensorReading::to_swing`] maps them onto
//! the `Swing` message the node consumes:
//!
//! | sensor | reading | Swing field |
//! |---|---|---|
//! | radar gun behind the batter (pitch) | ball speed, m/s, positive toward the bat | `ball_speed` |
//! | bat-speed sensor on the knob (gyro) | angular rate ω, rad/s, positive when the barrel leads | `bat_angular_speed` |
//! | same sensor (integrated accelerometer) | knob speed, m/s, positive toward the ball | `bat_cm_speed = knob_speed + ω·z_cm` |
//! | high-speed camera or vibration sensors | impact distance from the barrel end, m | `impact_z = L − distance` |
//! | radar gun in front of the plate (exit) | exit speed, m/s, positive away from the bat | `measured_exit_speed` |
//!
//! The bat moves as a rigid body before contact, so the speed of any point z (m from the knob) toward the
//! ball is `knob_speed + ω·z = bat_cm_speed + ω·(z − z_cm)` — the convention of [`sweetspot_physics`].
//!
//! **The simulated swing.** Bat speeds are drawn at the barrel (the point 6 in from the barrel end, as in
//! the BESR protocol), uniformly between the configured limits (60–80 mph by default); the bat rotates about
//! an instantaneous pivot [`PIVOT_Z`] (6 in from the knob, near the hands), so ω = v_barrel/(z_barrel −
//! z_pivot) and the knob moves slightly backwards (−ω·z_pivot). With a batter ([`RigConfig::batter`], the
//! demo's default) each bat is instead swung at the effort of the batter's reference swing: the bat's centre-
//! of-mass and angular speeds are those [`Batter::predict`] gives for its swing weight, scaled swing by swing
//! by the drawn speed over the midpoint of the configured limits (so the session's mean swing with each bat
//! is the batter's prediction, and its spread is that of the limits). Pitches are uniform in 80–100 mph. Impact
//! points are normally distributed around 6 in from the barrel end (σ 2 in), clipped to 1.5–13 in from the
//! end. The true exit speed is the physics ([`sweetspot_physics::collide`]) with the rig's true ball; each
//! reading then gets independent Gaussian noise of the standard deviations in [`SensorNoise`].
//!
//! **Oblique swings** ([`RigConfig::launch`], the demo's default; `None` keeps every swing head-on). Each
//! swing also draws an undercut, an attack angle, the pitch's descent angle and its backspin from the normal
//! distributions of [`LaunchConditions`] (conventions of [`sweetspot_physics::oblique`]); the truth is then
//! [`collide_oblique`] with the rig's true tangential contact, and the rig adds a ball tracker:
//!
//! | sensor | reading | Swing field |
//! |---|---|---|
//! | high-speed camera at the plate | undercut, m | `undercut` |
//! | bat sensor (knob) | attack angle, rad | `attack_angle` |
//! | pitch tracker | descent angle, rad; backspin about the bat's axis, rad/s | `pitch_angle`, `pitch_spin` |
//! | ball tracker (exit) | launch angle, rad; spin, rad/s, backspin positive | `measured_launch_angle`, `measured_spin` |
//!
//! each with independent Gaussian noise ([`LaunchNoise`]). The rig can also leave the undercut unreported
//! (NaN, [`LaunchConditions::report_undercut`]), as a rig without the plate camera would; `calibrate` then
//! fits it swing by swing.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, Normal};

use sweetspot_model::convert::{params_from_ball, params_of_preset};
use sweetspot_msgs::builtin_interfaces::msg::Time;
use sweetspot_msgs::std_msgs::msg::Header;
use sweetspot_msgs::sweetspot_msgs::msg::{BallParams, BatParams, Swing};
use sweetspot_physics::batter::{Batter, SwingPrediction};
use sweetspot_physics::oblique::{collide_oblique, ObliqueImpact, ObliqueResult, TangentialContact};
use sweetspot_physics::units::{rpm_to_rad_per_s, INCH, MPH};
use sweetspot_physics::{
    collide, Ball, Bat, CollisionOptions, CollisionResult, Impact, MassProperties, ModeSet, PhysicsError,
};

/// Instantaneous pivot of the simulated swing, m from the knob (6 in, near the hands).
pub const PIVOT_Z: f64 = 6.0 * INCH;
/// Where bat speed is quoted ("at the barrel"): this far from the barrel end, m (6 in).
pub const BARREL_SPEED_POINT_FROM_END: f64 = 6.0 * INCH;
/// Mean impact distance from the barrel end, m (6 in).
pub const IMPACT_MEAN_FROM_END: f64 = 6.0 * INCH;
/// Standard deviation of the impact distance from the barrel end, m (2 in).
pub const IMPACT_SIGMA: f64 = 2.0 * INCH;
/// Impacts are clipped to this range of distances from the barrel end, m (1.5 in to 13 in).
pub const IMPACT_RANGE_FROM_END: (f64, f64) = (1.5 * INCH, 13.0 * INCH);
/// ball_id the rig publishes its ball under.
pub const RIG_BALL_ID: &str = "rig-ball";

/// Errors of the rig simulator.
#[derive(Debug, thiserror::Error)]
pub enum RigError {
    /// A configuration value out of range.
    #[error("rig config: {field} = {value} is out of range ({allowed})")]
    OutOfRange { field: &'static str, value: String, allowed: String },
    /// The physics refused a bat, ball or swing.
    #[error("rig physics: {0}")]
    Physics(#[from] PhysicsError),
}

fn out_of_range(field: &'static str, value: impl std::fmt::Display, allowed: impl Into<String>) -> RigError {
    RigError::OutOfRange { field, value: value.to_string(), allowed: allowed.into() }
}

/// Standard deviations of the rig's sensors (Gaussian, independent, zero mean).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SensorNoise {
    /// Pitch radar, m/s (default 0.2 m/s ≈ 0.45 mph).
    pub ball_speed: f64,
    /// Knob gyro, relative (default 0.01 = 1 % of ω).
    pub angular_rate_relative: f64,
    /// Knob speed, m/s (default 0.1 m/s).
    pub knob_speed: f64,
    /// Impact location, m (default 0.005 m = 5 mm, a 1000-fps camera).
    pub impact: f64,
    /// Exit radar, m/s (default 0.45 m/s ≈ 1 mph, the accuracy sports radars quote).
    pub exit_speed: f64,
}

impl Default for SensorNoise {
    fn default() -> Self {
        SensorNoise { ball_speed: 0.2, angular_rate_relative: 0.01, knob_speed: 0.1, impact: 0.005, exit_speed: 0.45 }
    }
}

impl SensorNoise {
    /// No noise at all (the readings are the truth).
    pub fn none() -> SensorNoise {
        SensorNoise { ball_speed: 0.0, angular_rate_relative: 0.0, knob_speed: 0.0, impact: 0.0, exit_speed: 0.0 }
    }

    /// Checks every σ is finite and ≥ 0 (and below physically silly values).
    pub fn validate(&self) -> Result<(), RigError> {
        let check = |field: &'static str, v: f64, max: f64| {
            if v.is_finite() && (0.0..=max).contains(&v) {
                Ok(())
            } else {
                Err(out_of_range(field, v, format!("0 ≤ {field} ≤ {max}")))
            }
        };
        check("noise.ball_speed", self.ball_speed, 10.0)?;
        check("noise.angular_rate_relative", self.angular_rate_relative, 0.5)?;
        check("noise.knob_speed", self.knob_speed, 10.0)?;
        check("noise.impact", self.impact, 0.1)?;
        check("noise.exit_speed", self.exit_speed, 10.0)
    }
}

/// A normal distribution: mean and standard deviation, in the unit of the quantity drawn.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Spread {
    /// Mean.
    pub mean: f64,
    /// Standard deviation (≥ 0).
    pub sigma: f64,
}

impl Spread {
    /// A normal distribution of mean `mean` and standard deviation `sigma`.
    pub const fn new(mean: f64, sigma: f64) -> Spread {
        Spread { mean, sigma }
    }

    fn draw(&self, rng: &mut StdRng) -> f64 {
        self.mean + self.sigma * standard_normal(rng)
    }
}

/// Standard deviations of the oblique sensors and the ball tracker (Gaussian, independent, zero mean).
///
/// No tracker's published accuracy for launch angle and spin could be found for this project: the defaults
/// (1° and 100 rpm) are a stated assumption, of the order of the tolerances trackers are discussed with.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LaunchNoise {
    /// Undercut camera, m (default 2 mm).
    pub undercut: f64,
    /// Attack angle from the bat sensor, rad (default 1°).
    pub attack_angle: f64,
    /// Pitch descent angle from the pitch tracker, rad (default 0.5°).
    pub pitch_angle: f64,
    /// Pitch spin from the pitch tracker, rad/s (default 50 rpm).
    pub pitch_spin: f64,
    /// Ball tracker's launch angle, rad (default 1°).
    pub launch_angle: f64,
    /// Ball tracker's spin, rad/s (default 100 rpm).
    pub spin: f64,
}

impl Default for LaunchNoise {
    fn default() -> Self {
        LaunchNoise {
            undercut: 0.002,
            attack_angle: 1f64.to_radians(),
            pitch_angle: 0.5f64.to_radians(),
            pitch_spin: rpm_to_rad_per_s(50.0),
            launch_angle: 1f64.to_radians(),
            spin: rpm_to_rad_per_s(100.0),
        }
    }
}

impl LaunchNoise {
    /// No noise at all (the readings are the truth).
    pub fn none() -> LaunchNoise {
        LaunchNoise {
            undercut: 0.0,
            attack_angle: 0.0,
            pitch_angle: 0.0,
            pitch_spin: 0.0,
            launch_angle: 0.0,
            spin: 0.0,
        }
    }
}

/// How the rig's oblique swings are drawn and measured (units of [`sweetspot_physics::oblique`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LaunchConditions {
    /// Undercut, m (default 0 ± 1 cm), clipped to ±[`LaunchConditions::max_undercut_fraction`] of the
    /// ball's plus the barrel's radius.
    pub undercut: Spread,
    /// Attack angle of the bat's path, rad (default +10° ± 4°: an upward swing).
    pub attack_angle: Spread,
    /// Pitch descent angle, rad (default 6° ± 1°: a fastball's descent at the plate).
    pub pitch_angle: Spread,
    /// Pitch backspin about the bat's axis as the pitch arrives, rad/s (default 2000 ± 200 rpm: a fastball).
    pub pitch_spin: Spread,
    /// Largest |undercut| drawn as a fraction of ball radius + barrel radius (default 0.5: line-of-centres
    /// angles up to 30°, short of the sliding and grazing contacts the model extrapolates to).
    pub max_undercut_fraction: f64,
    /// Sensor noise.
    pub noise: LaunchNoise,
    /// Whether the rig reports the undercut (otherwise `Swing.undercut` is NaN: not measured).
    pub report_undercut: bool,
    /// The true tangential contact of the rig's balls on its bats.
    pub contact: TangentialContact,
}

impl Default for LaunchConditions {
    fn default() -> Self {
        LaunchConditions {
            undercut: Spread::new(0.0, 0.01),
            attack_angle: Spread::new(10f64.to_radians(), 4f64.to_radians()),
            pitch_angle: Spread::new(6f64.to_radians(), 1f64.to_radians()),
            pitch_spin: Spread::new(rpm_to_rad_per_s(2000.0), rpm_to_rad_per_s(200.0)),
            max_undercut_fraction: 0.5,
            noise: LaunchNoise::default(),
            report_undercut: true,
            contact: TangentialContact::default(),
        }
    }
}

impl LaunchConditions {
    /// Checks ranges (finite spreads, noise ≥ 0, the clip fraction in (0, 1), the contact law).
    pub fn validate(&self) -> Result<(), RigError> {
        let spreads = [
            ("launch.undercut", self.undercut),
            ("launch.attack_angle", self.attack_angle),
            ("launch.pitch_angle", self.pitch_angle),
            ("launch.pitch_spin", self.pitch_spin),
        ];
        for (field, s) in spreads {
            if !(s.mean.is_finite() && s.sigma.is_finite() && s.sigma >= 0.0) {
                return Err(out_of_range(field, format!("{} ± {}", s.mean, s.sigma), "a finite mean and σ ≥ 0"));
            }
        }
        let n = self.noise;
        let noises = [
            ("launch.noise.undercut", n.undercut),
            ("launch.noise.attack_angle", n.attack_angle),
            ("launch.noise.pitch_angle", n.pitch_angle),
            ("launch.noise.pitch_spin", n.pitch_spin),
            ("launch.noise.launch_angle", n.launch_angle),
            ("launch.noise.spin", n.spin),
        ];
        for (field, v) in noises {
            if !(v.is_finite() && v >= 0.0) {
                return Err(out_of_range(field, v, "a finite σ ≥ 0"));
            }
        }
        let f = self.max_undercut_fraction;
        if !(f.is_finite() && f > 0.0 && f < 1.0) {
            return Err(out_of_range("launch.max_undercut_fraction", f, "0 < fraction < 1"));
        }
        self.contact.validate()?;
        Ok(())
    }
}

/// The oblique part of one simulated swing: the drawn geometry, the tracker's readings and the true launch.
#[derive(Debug, Clone, PartialEq)]
pub struct RigLaunch {
    /// The true oblique impact (its `impact` is [`RigSwing::truth`]).
    pub truth: ObliqueImpact,
    /// The true oblique collision.
    pub result: ObliqueResult,
    /// Undercut as reported, m (NaN when the rig does not report it).
    pub undercut: f64,
    /// Attack angle as measured, rad.
    pub attack_angle: f64,
    /// Pitch descent angle as measured, rad.
    pub pitch_angle: f64,
    /// Pitch spin as measured, rad/s.
    pub pitch_spin: f64,
    /// Launch angle as the tracker measured it, rad.
    pub launch_angle: f64,
    /// Spin as the tracker measured it, rad/s, backspin positive.
    pub spin: f64,
}

/// What the rig simulates.
#[derive(Debug, Clone, PartialEq)]
pub struct RigConfig {
    /// Bat presets swung, in session order (see [`Bat::preset_names`]).
    pub bats: Vec<String>,
    /// The ball the rig announces on `ball/params` (its nominal, catalogue properties).
    pub ball: Ball,
    /// The COR of the balls really used, if it differs from the announced one (what calibration finds).
    pub true_cor: Option<f64>,
    /// Pitch speeds, m/s (min, max), uniform.
    pub pitch_speed: (f64, f64),
    /// Bat speeds at the barrel, m/s (min, max), uniform.
    pub barrel_speed: (f64, f64),
    /// Sensor noise.
    pub noise: SensorNoise,
    /// Random seed: the same seed gives the same session.
    pub seed: u64,
    /// Vibrational modes computed and integrated per bat, and the time step. The bats are announced by preset
    /// name, for which the node integrates its `default_modes` (BatParams.msg ignores max_modes with a
    /// preset): keep the two equal (18 by default) for the node's answers to match the rig's truth.
    pub options: CollisionOptions,
    /// The batter swinging every bat at equal effort (see the module docs); `None`: every bat at the same
    /// bat speed at the barrel.
    pub batter: Option<Batter>,
    /// Oblique swings: undercut, angles, pitch spin and a ball tracker (see the module docs); `None`: every
    /// swing head-on, nothing but the exit speed tracked.
    pub launch: Option<LaunchConditions>,
}

impl Default for RigConfig {
    fn default() -> Self {
        RigConfig {
            bats: Bat::preset_names().iter().map(|s| s.to_string()).collect(),
            ball: Ball::game(),
            true_cor: None,
            pitch_speed: (80.0 * MPH, 100.0 * MPH),
            barrel_speed: (60.0 * MPH, 80.0 * MPH),
            noise: SensorNoise::default(),
            seed: 2000,
            options: CollisionOptions::default(),
            batter: None,
            launch: None,
        }
    }
}

impl RigConfig {
    /// Checks ranges (speeds, noise, COR, bats non-empty).
    pub fn validate(&self) -> Result<(), RigError> {
        if self.bats.is_empty() {
            return Err(out_of_range("bats", "[]", "at least one preset"));
        }
        self.noise.validate()?;
        let range = |field: &'static str, (lo, hi): (f64, f64), max: f64| {
            if lo.is_finite() && hi.is_finite() && 0.0 < lo && lo <= hi && hi <= max {
                Ok(())
            } else {
                Err(out_of_range(field, format!("{lo}..{hi}"), format!("0 < min ≤ max ≤ {max} m/s")))
            }
        };
        range("pitch_speed", self.pitch_speed, 70.0)?;
        range("barrel_speed", self.barrel_speed, 70.0)?;
        if let Some(cor) = self.true_cor {
            if !(cor.is_finite() && cor > 0.0 && cor <= 1.0) {
                return Err(out_of_range("true_cor", cor, "0 < true_cor ≤ 1"));
            }
        }
        if let Some(batter) = &self.batter {
            batter.validate()?;
        }
        if let Some(launch) = &self.launch {
            launch.validate()?;
        }
        if !(1..=60).contains(&self.options.modes) {
            return Err(out_of_range("modes", self.options.modes, "1 ≤ modes ≤ 60"));
        }
        Ok(())
    }

    /// The ball really used (the announced one with `true_cor` if set).
    pub fn true_ball(&self) -> Ball {
        Ball { cor: self.true_cor.unwrap_or(self.ball.cor), ..self.ball }
    }
}

/// The readings of one swing, as the rig's sensors give them (SI units, conventions in the module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SensorReading {
    /// Pitch radar: ball speed toward the bat, m/s.
    pub ball_speed: f64,
    /// Knob gyro: bat angular speed, rad/s, positive when the barrel leads.
    pub angular_rate: f64,
    /// Knob sensor: speed of the knob toward the ball, m/s (slightly negative when the hands pivot).
    pub knob_speed: f64,
    /// Camera / vibration sensors: impact distance from the barrel end along the axis, m.
    pub impact_from_end: f64,
    /// Exit radar: exit speed away from the bat, m/s (NaN when not measured).
    pub exit_speed: f64,
}

impl SensorReading {
    /// The physics' initial conditions for a bat with mass properties `mp`: v_cm = v_knob + ω·z_cm,
    /// impact_z = L − distance from the end.
    pub fn to_impact(&self, mp: &MassProperties) -> Impact {
        Impact {
            ball_speed: self.ball_speed,
            bat_cm_speed: self.knob_speed + self.angular_rate * mp.center_of_mass,
            bat_angular_speed: self.angular_rate,
            impact_z: mp.length - self.impact_from_end,
        }
    }

    /// The `Swing` message for these readings (see [`SensorReading::to_impact`]).
    pub fn to_swing(&self, mp: &MassProperties, swing_id: u64, bat_id: &str, ball_id: &str, stamp: Time) -> Swing {
        let impact = self.to_impact(mp);
        Swing {
            header: Header { stamp, frame_id: String::new() },
            swing_id,
            bat_id: bat_id.to_string(),
            ball_id: ball_id.to_string(),
            ball_speed: impact.ball_speed,
            bat_cm_speed: impact.bat_cm_speed,
            bat_angular_speed: impact.bat_angular_speed,
            impact_z: impact.impact_z,
            measured_exit_speed: self.exit_speed,
            ..Swing::default()
        }
    }
}

/// One simulated swing: the truth, what the sensors read, and the physics' answer for the truth.
#[derive(Debug, Clone, PartialEq)]
pub struct RigSwing {
    /// Counter from 1.
    pub swing_id: u64,
    /// The bat preset swung.
    pub bat_id: String,
    /// The true initial conditions.
    pub truth: Impact,
    /// The noisy readings.
    pub reading: SensorReading,
    /// The readings as the physics' initial conditions (what the node will compute with).
    pub measured: Impact,
    /// The true collision (with the true ball); for an oblique swing, its normal part.
    pub result: CollisionResult,
    /// The oblique part, when the rig simulates oblique swings ([`RigConfig::launch`]).
    pub launch: Option<RigLaunch>,
}

/// One bat of the session with its modes.
#[derive(Debug, Clone)]
pub struct RigBat {
    /// Preset name, used as bat_id.
    pub bat_id: String,
    /// The bat.
    pub bat: Bat,
    /// Its modes.
    pub modes: ModeSet,
    /// The rig batter's swing of this bat at the reference effort (`None` without a batter).
    pub swing: Option<SwingPrediction>,
}

/// Generates a session swing by swing: bats in blocks of `swings_per_bat` (a hitter takes a round with each
/// bat), deterministic for a given seed.
pub struct SessionGenerator {
    config: RigConfig,
    bats: Vec<RigBat>,
    rng: StdRng,
    next_id: u64,
    block: usize,
}

impl SessionGenerator {
    /// Builds the bats and their modes (a few tens of ms per bat).
    pub fn new(config: RigConfig) -> Result<SessionGenerator, RigError> {
        config.validate()?;
        config.true_ball().validate()?;
        let bats = config
            .bats
            .iter()
            .map(|name| -> Result<RigBat, RigError> {
                let bat = Bat::preset(name)?;
                let modes = ModeSet::compute(&bat, config.options.modes)?;
                let swing = config.batter.map(|b| b.predict(&modes.mass_properties())).transpose()?;
                Ok(RigBat { bat_id: name.clone(), bat, modes, swing })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let rng = StdRng::seed_from_u64(config.seed);
        Ok(SessionGenerator { config, bats, rng, next_id: 1, block: 5 })
    }

    /// Sets how many consecutive swings each bat gets before the next bat (default 5; ≥ 1).
    pub fn with_block(mut self, swings_per_bat: usize) -> SessionGenerator {
        self.block = swings_per_bat.max(1);
        self
    }

    /// The configuration.
    pub fn config(&self) -> &RigConfig {
        &self.config
    }

    /// The session's bats, in order.
    pub fn bats(&self) -> &[RigBat] {
        &self.bats
    }

    /// The BatParams the rig announces for each bat (by preset name).
    pub fn bat_params(&self, stamp: Time) -> Vec<BatParams> {
        self.bats
            .iter()
            .map(|b| {
                let header = Header { stamp: stamp.clone(), frame_id: String::new() };
                params_of_preset(&b.bat_id, &b.bat_id, header)
            })
            .collect()
    }

    /// The BallParams the rig announces (the nominal ball, under [`RIG_BALL_ID`]).
    pub fn ball_params(&self, stamp: Time) -> BallParams {
        ball_params(RIG_BALL_ID, &self.config.ball, stamp)
    }

    /// Simulates the next swing.
    pub fn next_swing(&mut self) -> Result<RigSwing, RigError> {
        let swing_id = self.next_id;
        self.next_id += 1;
        let bat_index = ((swing_id - 1) as usize / self.block) % self.bats.len();
        let cfg = &self.config;
        let bat = &self.bats[bat_index];
        let mp = bat.modes.mass_properties();
        let rng = &mut self.rng;

        let ball_speed = uniform(rng, cfg.pitch_speed);
        let barrel_speed = uniform(rng, cfg.barrel_speed);
        let (lo, hi) = IMPACT_RANGE_FROM_END;
        let from_end = (IMPACT_MEAN_FROM_END + IMPACT_SIGMA * standard_normal(rng)).clamp(lo, hi);
        let (omega, knob_speed, truth) = true_swing(cfg, bat, ball_speed, barrel_speed, from_end);
        // Head-on sessions draw nothing more here, so their random stream is unchanged by the oblique option.
        let oblique = match &cfg.launch {
            Some(launch) => Some(draw_oblique(rng, cfg, bat, launch, truth)?),
            None => None,
        };
        let (result, true_exit_speed) = match &oblique {
            Some((_, _, r)) => (r.normal.clone(), r.exit_speed),
            None => {
                let r = collide(&bat.modes, &cfg.true_ball(), &truth, &cfg.options)?;
                let exit = r.exit_speed;
                (r, exit)
            }
        };

        let n = cfg.noise;
        let reading = SensorReading {
            ball_speed: ball_speed + n.ball_speed * standard_normal(rng),
            angular_rate: omega * (1.0 + n.angular_rate_relative * standard_normal(rng)),
            knob_speed: knob_speed + n.knob_speed * standard_normal(rng),
            impact_from_end: (from_end + n.impact * standard_normal(rng)).clamp(0.0, mp.length),
            exit_speed: true_exit_speed + n.exit_speed * standard_normal(rng),
        };
        let launch = oblique.map(|(launch, truth, result)| noisy_launch(rng, launch, truth, result));
        let measured = reading.to_impact(&mp);
        Ok(RigSwing { swing_id, bat_id: bat.bat_id.clone(), truth, reading, measured, result, launch })
    }

    /// The `Swing` message of a simulated swing (its sensor readings, under the rig's ball).
    pub fn swing_message(&self, swing: &RigSwing, stamp: Time) -> Swing {
        let mp = self.bats.iter().find(|b| b.bat_id == swing.bat_id).map(|b| b.modes.mass_properties());
        let message = match mp {
            Some(mp) => swing.reading.to_swing(&mp, swing.swing_id, &swing.bat_id, RIG_BALL_ID, stamp),
            None => Swing {
                header: Header { stamp, frame_id: String::new() },
                swing_id: swing.swing_id,
                bat_id: swing.bat_id.clone(),
                ball_id: RIG_BALL_ID.to_string(),
                ball_speed: swing.measured.ball_speed,
                bat_cm_speed: swing.measured.bat_cm_speed,
                bat_angular_speed: swing.measured.bat_angular_speed,
                impact_z: swing.measured.impact_z,
                measured_exit_speed: swing.reading.exit_speed,
                ..Swing::default()
            },
        };
        match &swing.launch {
            Some(l) => Swing {
                undercut: l.undercut,
                attack_angle: l.attack_angle,
                pitch_angle: l.pitch_angle,
                pitch_spin: l.pitch_spin,
                measured_launch_angle: l.launch_angle,
                measured_spin: l.spin,
                ..message
            },
            None => message,
        }
    }
}

/// The true initial conditions of a swing `effort` times the batter's reference effort (`swing`, predicted
/// for this bat), meeting a ball at `ball_speed` (m/s) at `impact_z` (m from the knob). Effort 1 is exactly
/// the prediction.
pub fn equal_effort_impact(swing: &SwingPrediction, effort: f64, ball_speed: f64, impact_z: f64) -> Impact {
    Impact {
        ball_speed,
        bat_cm_speed: effort * swing.bat_cm_speed,
        bat_angular_speed: effort * swing.bat_angular_speed,
        impact_z,
    }
}

/// A BallParams message for `ball` under `ball_id`. Its tangential contact fields are 0 (the node's
/// defaults): a rig measures launch angles and spins, not the ball's grip; `calibrate --fit-tangential` fits it.
pub fn ball_params(ball_id: &str, ball: &Ball, stamp: Time) -> BallParams {
    params_from_ball(ball_id, ball, None, Header { stamp, frame_id: String::new() })
}

/// The swing's true (ω, knob speed, impact): the bat's batter swings it with the effort of `barrel_speed`,
/// or, without a batter, the bat turns about [`PIVOT_Z`].
fn true_swing(cfg: &RigConfig, bat: &RigBat, ball_speed: f64, barrel_speed: f64, from_end: f64) -> (f64, f64, Impact) {
    let mp = bat.modes.mass_properties();
    match &bat.swing {
        Some(swing) => {
            let effort = barrel_speed / (0.5 * (cfg.barrel_speed.0 + cfg.barrel_speed.1));
            let truth = equal_effort_impact(swing, effort, ball_speed, mp.length - from_end);
            let knob_speed = truth.bat_cm_speed - truth.bat_angular_speed * mp.center_of_mass;
            (truth.bat_angular_speed, knob_speed, truth)
        }
        None => {
            let omega = barrel_speed / (mp.length - BARREL_SPEED_POINT_FROM_END - PIVOT_Z);
            let knob_speed = -omega * PIVOT_Z;
            let reading = SensorReading {
                ball_speed,
                angular_rate: omega,
                knob_speed,
                impact_from_end: from_end,
                exit_speed: 0.0,
            };
            (omega, knob_speed, reading.to_impact(&mp))
        }
    }
}

/// Draws the swing's undercut, angles and pitch spin and collides obliquely.
fn draw_oblique<'a>(
    rng: &mut StdRng,
    cfg: &RigConfig,
    bat: &RigBat,
    launch: &'a LaunchConditions,
    truth: Impact,
) -> Result<(&'a LaunchConditions, ObliqueImpact, ObliqueResult), RigError> {
    let barrel_radius = bat.bat.radii_at(truth.impact_z).0;
    let reach = launch.max_undercut_fraction * (cfg.ball.radius + barrel_radius);
    let oblique = ObliqueImpact {
        impact: truth,
        barrel_radius,
        undercut: launch.undercut.draw(rng).clamp(-reach, reach),
        attack_angle: launch.attack_angle.draw(rng),
        pitch_angle: launch.pitch_angle.draw(rng),
        pitch_spin: launch.pitch_spin.draw(rng),
    };
    let result = collide_oblique(&bat.modes, &cfg.true_ball(), &oblique, &launch.contact, &cfg.options)?;
    Ok((launch, oblique, result))
}

/// The launch as the rig's tracker and undercut camera report it.
fn noisy_launch(rng: &mut StdRng, launch: &LaunchConditions, truth: ObliqueImpact, result: ObliqueResult) -> RigLaunch {
    let n = launch.noise;
    let undercut = truth.undercut + n.undercut * standard_normal(rng);
    RigLaunch {
        undercut: if launch.report_undercut { undercut } else { f64::NAN },
        attack_angle: truth.attack_angle + n.attack_angle * standard_normal(rng),
        pitch_angle: truth.pitch_angle + n.pitch_angle * standard_normal(rng),
        pitch_spin: truth.pitch_spin + n.pitch_spin * standard_normal(rng),
        launch_angle: result.launch_angle + n.launch_angle * standard_normal(rng),
        spin: result.spin + n.spin * standard_normal(rng),
        truth,
        result,
    }
}

fn uniform(rng: &mut StdRng, (lo, hi): (f64, f64)) -> f64 {
    if hi > lo {
        rng.gen_range(lo..hi)
    } else {
        lo
    }
}

fn standard_normal(rng: &mut StdRng) -> f64 {
    // Normal::new(0, 1) cannot fail; fall back to 0 rather than panic if the crate ever changes that.
    Normal::new(0.0, 1.0).map(|d| d.sample(rng)).unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sessions_are_reproducible_and_realistic() {
        let cfg = RigConfig { seed: 7, ..RigConfig::default() };
        let mut a = SessionGenerator::new(cfg.clone()).unwrap();
        let mut b = SessionGenerator::new(cfg).unwrap();
        let mut seen = std::collections::BTreeSet::new();
        for _ in 0..40 {
            let (x, y) = (a.next_swing().unwrap(), b.next_swing().unwrap());
            assert_eq!(x, y);
            seen.insert(x.bat_id.clone());
            assert!((80.0 * MPH..100.0 * MPH).contains(&x.truth.ball_speed));
            let bat = a.bats().iter().find(|bt| bt.bat_id == x.bat_id).unwrap();
            let mp = bat.modes.mass_properties();
            let barrel = sweetspot_physics::rigid::bat_speed_at(
                &mp,
                &Impact { impact_z: mp.length - BARREL_SPEED_POINT_FROM_END, ..x.truth },
            );
            assert!((60.0 * MPH - 1e-9..80.0 * MPH + 1e-9).contains(&barrel), "barrel speed {barrel}");
            // Exit speeds of a real session: roughly 60–120 mph (27–54 m/s).
            assert!((25.0..55.0).contains(&x.result.exit_speed), "exit {} ({})", x.result.exit_speed, x.bat_id);
            assert!((x.reading.exit_speed - x.result.exit_speed).abs() < 5.0 * 0.45);
        }
        assert_eq!(seen.len(), 4);
    }

    #[test]
    fn readings_map_to_the_physics_convention() {
        let mp = Bat::r161().unwrap().mass_properties();
        let r = SensorReading {
            ball_speed: 40.0,
            angular_rate: 50.0,
            knob_speed: -7.0,
            impact_from_end: 0.15,
            exit_speed: 45.0,
        };
        let i = r.to_impact(&mp);
        assert!((i.impact_z - (mp.length - 0.15)).abs() < 1e-12);
        // The speed at the knob (z = 0) computed the physics' way is the knob reading.
        let knob = i.bat_cm_speed + i.bat_angular_speed * (0.0 - mp.center_of_mass);
        assert!((knob - r.knob_speed).abs() < 1e-12);
        let s = r.to_swing(&mp, 3, "r161", RIG_BALL_ID, Time::default());
        assert_eq!((s.swing_id, s.measured_exit_speed), (3, 45.0));
    }

    #[test]
    fn oblique_sessions_draw_the_geometry_and_track_the_launch() {
        let cfg = RigConfig {
            seed: 9,
            bats: vec!["r161".into()],
            options: CollisionOptions { modes: 8, ..CollisionOptions::default() },
            launch: Some(LaunchConditions::default()),
            ..RigConfig::default()
        };
        let (mut a, mut b) = (SessionGenerator::new(cfg.clone()).unwrap(), SessionGenerator::new(cfg).unwrap());
        let n = 30;
        let mut launch_sum = 0.0;
        for _ in 0..n {
            let x = a.next_swing().unwrap();
            assert_eq!(x, b.next_swing().unwrap(), "deterministic for its seed");
            let l = x.launch.as_ref().expect("oblique");
            assert!(l.truth.undercut.abs() <= 0.5 * (a.config().ball.radius + l.truth.barrel_radius) + 1e-15);
            assert_eq!(l.truth.impact, x.truth);
            assert_eq!(x.result, l.result.normal);
            // The radar sees the oblique exit speed, the tracker the launch, each within 5σ of its noise.
            assert!((x.reading.exit_speed - l.result.exit_speed).abs() < 5.0 * 0.45);
            assert!((l.launch_angle - l.result.launch_angle).abs() < 5f64.to_radians());
            assert!((l.spin - l.result.spin).abs() < rpm_to_rad_per_s(500.0));
            let msg = a.swing_message(&x, Time::default());
            assert_eq!((msg.undercut, msg.pitch_spin, msg.measured_spin), (l.undercut, l.pitch_spin, l.spin));
            launch_sum += l.result.launch_angle;
        }
        // Bat path +10° on average, undercuts centred on 0: balls leave upward on average.
        let mean = (launch_sum / n as f64).to_degrees();
        assert!((2.0..30.0).contains(&mean), "mean launch angle {mean}°");
    }

    #[test]
    fn head_on_sessions_publish_no_oblique_fields() {
        let cfg = RigConfig { seed: 9, bats: vec!["r161".into()], ..RigConfig::default() };
        let mut rig = SessionGenerator::new(cfg).unwrap();
        let x = rig.next_swing().unwrap();
        assert!(x.launch.is_none());
        let msg = rig.swing_message(&x, Time::default());
        assert_eq!((msg.undercut, msg.attack_angle, msg.pitch_angle, msg.pitch_spin), (0.0, 0.0, 0.0, 0.0));
        assert!(msg.measured_launch_angle.is_nan() && msg.measured_spin.is_nan());
    }

    #[test]
    fn bad_config_is_a_typed_error() {
        let cfg = RigConfig { true_cor: Some(1.5), ..RigConfig::default() };
        assert!(matches!(SessionGenerator::new(cfg), Err(RigError::OutOfRange { field: "true_cor", .. })));
        let cfg = RigConfig { bats: vec!["nope".into()], ..RigConfig::default() };
        assert!(matches!(SessionGenerator::new(cfg), Err(RigError::Physics(_))));
    }
}
