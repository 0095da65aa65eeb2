//! Arguments shared by the physics commands (`--bat`, ball overrides, `--modes`, `--dt`, swing speeds) and
//! their resolution into physics values.

use std::path::Path;

use anyhow::{bail, Context, Result};
use clap::Args;

use super::bat_file::load_bat_file;
use crate::model::limits::{MAX_PITCH_SPIN, MAX_SWING_ANGLE};
use crate::physics::collision::TIME_STEP_RANGE;
use crate::physics::oblique::{rad_per_s_to_rpm, rpm_to_rad_per_s, TangentialContact};
use crate::physics::{Ball, Bat, BatterSide, CollisionOptions, Impact, ObliqueImpact, SpatialImpact};
use crate::report::table::num;

/// Default ball speed toward the bat, m/s (about 89 mph).
pub const DEFAULT_BALL_SPEED: f64 = 40.0;
/// Default bat centre-of-mass speed toward the ball, m/s.
pub const DEFAULT_BAT_CM_SPEED: f64 = 25.0;
/// Default bat angular speed, rad/s: with the CM speed above the R161 turns about a point near its knob,
/// and the barrel 0.15 m beyond the CM moves at about 32 m/s (71 mph).
pub const DEFAULT_BAT_ANGULAR_SPEED: f64 = 45.0;
/// Largest number of vibrational modes the CLI accepts.
pub const MAX_MODES: usize = 200;

/// Parses a finite floating-point number (clap value parser), refusing NaN and ±∞.
pub fn finite_f64(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("{value} is not allowed: expected a finite number"))
    }
}

/// Parses a number of seconds ≥ 0 (clap value parser; +∞ and huge values mean for ever, see
/// [`crate::model::time`]).
pub fn seconds_at_least_zero(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a number of seconds"))?;
    crate::model::time::check_seconds(value, crate::model::time::Least::Zero)
}

/// Parses a number of seconds > 0 (clap value parser; +∞ and huge values mean for ever).
pub fn seconds_above_zero(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a number of seconds"))?;
    crate::model::time::check_seconds(value, crate::model::time::Least::AboveZero)
}

/// Parses a span of seconds ≥ 0 that is not a limit (clap value parser; finite: +∞ is a range error, see
/// [`crate::model::time::check_finite_seconds`]).
pub fn finite_seconds_at_least_zero(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a number of seconds"))?;
    crate::model::time::check_finite_seconds(value, crate::model::time::Least::Zero)
}

/// Parses a swing rate in Hz (clap value parser): a rate of at most
/// [`crate::model::time::MAX_SWING_RATE_HZ`].
pub fn swing_rate_hz(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a rate"))?;
    crate::model::time::check_swing_rate(value)
}

/// Parses a rate in Hz (clap value parser): finite, at least one per 100 years.
pub fn rate_hz(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a rate"))?;
    crate::model::time::check_rate(value)
}

/// Parses a time scale (clap value parser): finite and > 0 (a scale that makes a wait longer than 100 years
/// waits for ever).
pub fn time_scale(text: &str) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a number"))?;
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(format!("{value} is out of range: expected a finite time scale > 0"))
    }
}

/// Parses a batter side (clap value parser): `right` or `left`.
pub fn batter_side(text: &str) -> std::result::Result<BatterSide, String> {
    match text.trim().to_ascii_lowercase().as_str() {
        "right" => Ok(BatterSide::Right),
        "left" => Ok(BatterSide::Left),
        _ => Err(format!("'{text}' is not a batter side: expected right or left")),
    }
}

/// `--bat PRESET|FILE`.
#[derive(Debug, Clone, Args)]
pub struct BatArgs {
    /// Bat: a preset name (r161, r161-corked, aluminum, torpedo) or a bat file (.toml, see docs/file-formats.md).
    #[arg(long, value_name = "PRESET|FILE", default_value = "r161")]
    pub bat: String,
}

impl BatArgs {
    /// Loads the preset or the file.
    pub fn load(&self) -> Result<Bat> {
        resolve_bat(&self.bat, None)
    }
}

/// A bat named by a preset or a path (relative paths are taken relative to `base`, if given).
pub fn resolve_bat(spec: &str, base: Option<&Path>) -> Result<Bat> {
    if Bat::preset_names().contains(&spec) {
        return Bat::preset(spec).with_context(|| format!("bat preset '{spec}'"));
    }
    let path = match base {
        Some(dir) => dir.join(spec),
        None => Path::new(spec).to_path_buf(),
    };
    // Anything that exists goes to the reader, whose rules (a regular file under the size cap) name what it is.
    if path.exists() {
        return load_bat_file(&path);
    }
    bail!(
        "--bat / bat: '{spec}' is neither a preset (known: {}) nor a bat file that exists",
        Bat::preset_names().join(", ")
    )
}

/// Ball overrides; what is not given keeps the command's ball (the game ball `mlb2024` unless `--ball` says).
#[derive(Debug, Clone, Default, Args)]
pub struct BallArgs {
    /// Ball mass, kg [default 0.145].
    #[arg(long, value_name = "KG", value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_mass: Option<f64>,
    /// Ball radius, m [default 0.0366].
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_radius: Option<f64>,
    /// Ball coefficient of restitution e0 against a rigid wall, in (0, 1] [default 0.5327, at 85 ft/s].
    #[arg(long, value_name = "E0", value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_cor: Option<f64>,
    /// Ball loading stiffness k1, N/m^α [default 6.53e7].
    #[arg(long, value_name = "N/M^A", value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_stiffness: Option<f64>,
    /// Ball loading exponent α [default 1.84].
    #[arg(long, value_name = "ALPHA", value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_exponent: Option<f64>,
    /// A built-in ball to start from (baseball, bbcor, mlb, mlb2024) [default mlb2024, the game ball fitted to
    /// the 2024 MLB season]; the other --ball-* flags override its fields.
    #[arg(long = "ball", value_name = "NAME")]
    pub ball_preset: Option<String>,
    /// Exponent p of e0 ∝ v^(−p) in the normal approach speed v, 0..=1 (0 = constant COR) [default 0.0487].
    #[arg(long, value_name = "P", value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_cor_exponent: Option<f64>,
    /// Normal approach speed at which e0 = --ball-cor, m/s (with --ball-cor-exponent) [default 25.908: 85 ft/s].
    #[arg(long, value_name = "M/S", value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_cor_speed: Option<f64>,
}

impl BallArgs {
    /// `base` with the overrides applied, validated.
    pub fn apply(&self, base: Ball) -> Result<Ball> {
        let base = match &self.ball_preset {
            Some(name) => Ball::preset(name).context("--ball")?,
            None => base,
        };
        let ball = Ball {
            mass: self.ball_mass.unwrap_or(base.mass),
            radius: self.ball_radius.unwrap_or(base.radius),
            stiffness: self.ball_stiffness.unwrap_or(base.stiffness),
            exponent: self.ball_exponent.unwrap_or(base.exponent),
            cor: self.ball_cor.unwrap_or(base.cor),
            cor_speed_exponent: self.ball_cor_exponent.unwrap_or(base.cor_speed_exponent),
            cor_reference_speed: self.ball_cor_speed.unwrap_or(base.cor_reference_speed),
        };
        ball.validate().context(
            "invalid ball (--ball-mass/--ball-radius/--ball-cor/--ball-stiffness/--ball-exponent/\
             --ball-cor-exponent/--ball-cor-speed)",
        )?;
        Ok(ball)
    }
}

/// The ball's e0 for a report (its JSON form): the number for a constant-COR ball, the law for one whose COR
/// falls with speed.
pub fn cor_text(ball: &crate::report::json::BallJson) -> String {
    if ball.cor_speed_exponent == 0.0 {
        num(ball.cor, 4)
    } else {
        format!(
            "{}·(v / {} m/s)^−{} (v: normal approach speed)",
            num(ball.cor, 4),
            num(ball.cor_reference_speed, 4),
            num(ball.cor_speed_exponent, 4)
        )
    }
}

/// `--modes N` and `--dt S`.
#[derive(Debug, Clone, Args)]
pub struct NumericArgs {
    /// Number of vibrational modes integrated, 0..=200 (0 = rigid bat).
    #[arg(long, value_name = "N", default_value_t = 18)]
    pub modes: usize,
    /// RK4 time step, s (1e-8 ≤ dt ≤ 1e-4).
    #[arg(long, value_name = "S", default_value_t = 5e-6, value_parser = finite_f64, allow_negative_numbers = true)]
    pub dt: f64,
}

impl NumericArgs {
    /// The collision options, checked.
    pub fn options(&self) -> Result<CollisionOptions> {
        check_options(CollisionOptions { modes: self.modes, time_step: self.dt })
    }
}

/// Checks the CLI's limits on the numerical options; the error names the field and its range.
pub fn check_options(options: CollisionOptions) -> Result<CollisionOptions> {
    if options.modes > MAX_MODES {
        bail!("--modes / modes = {} is out of range: expected 0 ≤ modes ≤ {MAX_MODES}", options.modes);
    }
    let (lo, hi) = TIME_STEP_RANGE;
    if !(options.time_step >= lo && options.time_step <= hi) {
        bail!("--dt / time_step = {} s is out of range: expected {lo:e} ≤ time_step ≤ {hi:e} s", options.time_step);
    }
    Ok(options)
}

/// The swing: ball speed, bat CM speed and angular speed.
#[derive(Debug, Clone, Args)]
pub struct SwingArgs {
    /// Ball speed toward the bat, m/s.
    #[arg(long, value_name = "M/S", default_value_t = DEFAULT_BALL_SPEED, value_parser = finite_f64, allow_negative_numbers = true)]
    pub ball_speed: f64,
    /// Bat centre-of-mass speed toward the ball, m/s.
    #[arg(long, value_name = "M/S", default_value_t = DEFAULT_BAT_CM_SPEED, value_parser = finite_f64, allow_negative_numbers = true)]
    pub bat_cm_speed: f64,
    /// Bat angular speed about its centre of mass, rad/s, positive when the barrel leads.
    #[arg(long, value_name = "RAD/S", default_value_t = DEFAULT_BAT_ANGULAR_SPEED, value_parser = finite_f64, allow_negative_numbers = true)]
    pub bat_angular_speed: f64,
}

impl SwingArgs {
    /// The default swing (ball 40 m/s, bat CM 25 m/s, 45 rad/s).
    pub fn defaults() -> SwingArgs {
        SwingArgs {
            ball_speed: DEFAULT_BALL_SPEED,
            bat_cm_speed: DEFAULT_BAT_CM_SPEED,
            bat_angular_speed: DEFAULT_BAT_ANGULAR_SPEED,
        }
    }

    /// An impact template at `impact_z`.
    pub fn impact(&self, impact_z: f64) -> Impact {
        Impact {
            ball_speed: self.ball_speed,
            bat_cm_speed: self.bat_cm_speed,
            bat_angular_speed: self.bat_angular_speed,
            impact_z,
        }
    }
}

/// The oblique inputs: undercut, attack and pitch angles, pitch spin, and the tangential contact overrides.
#[derive(Debug, Clone, Default, Args)]
pub struct ObliqueArgs {
    /// Undercut D, m: the ball's centre above (+, backspin, higher launch) or below (−) the bat's path at
    /// contact [default 0].
    #[arg(long, value_name = "M", value_parser = finite_f64, allow_negative_numbers = true)]
    pub undercut: Option<f64>,
    /// Attack angle of the bat's path above the horizontal, degrees (positive for an upward swing) [default 0].
    #[arg(long, value_name = "DEG", value_parser = finite_f64, allow_negative_numbers = true)]
    pub attack_angle: Option<f64>,
    /// Descent angle of the pitch below the horizontal, degrees (positive for a descending pitch) [default 0].
    #[arg(long, value_name = "DEG", value_parser = finite_f64, allow_negative_numbers = true)]
    pub pitch_angle: Option<f64>,
    /// Pitch spin about the bat's axis, rpm, backspin (relative to the pitch's travel) positive [default 0].
    #[arg(long, value_name = "RPM", value_parser = finite_f64, allow_negative_numbers = true)]
    pub pitch_spin: Option<f64>,
    /// Tangential coefficient of restitution e_T, 0..=1 (0 = rolling contact) [default 0.405].
    #[arg(long, value_name = "E_T", value_parser = finite_f64, allow_negative_numbers = true)]
    pub tangential_cor: Option<f64>,
    /// Coulomb friction coefficient μ between ball and bat, 0..=2 [default 0.15].
    #[arg(long, value_name = "MU", value_parser = finite_f64, allow_negative_numbers = true)]
    pub friction: Option<f64>,
    /// The compliant tangential law instead of a constant e_T: a tangential spring of stiffness
    /// (dF_n/du)/ETA2 through the contact, 0.1..=100 (KNS 2017's baseball: 4.75; docs/physics-spin.md)
    /// [default: constant e_T].
    #[arg(long, value_name = "ETA2", value_parser = finite_f64, allow_negative_numbers = true)]
    pub tangential_stiffness_ratio: Option<f64>,
    /// Tilt of the bat's long axis below the horizontal at contact, degrees (barrel below the hands
    /// positive); non-zero makes the collision three-dimensional [default 0].
    #[arg(long, value_name = "DEG", value_parser = finite_f64, allow_negative_numbers = true)]
    pub bat_tilt: Option<f64>,
    /// Horizontal direction of the bat's path at contact, degrees, positive toward the right-field
    /// (first-base) side; non-zero makes the collision three-dimensional [default 0].
    #[arg(long, value_name = "DEG", value_parser = finite_f64, allow_negative_numbers = true)]
    pub swing_direction: Option<f64>,
    /// The batter's side: right or left (a left-handed swing is the mirror image of a right-handed one, so
    /// the angles keep their field meaning) [default right].
    #[arg(long, value_name = "SIDE", value_parser = batter_side)]
    pub batter_side: Option<BatterSide>,
}

impl ObliqueArgs {
    /// The inputs in SI units (degrees → rad, rpm → rad/s), the contact checked.
    pub fn inputs(&self) -> Result<ObliqueInputs> {
        ObliqueInputs::from_cli_units(
            self.undercut,
            self.attack_angle,
            self.pitch_angle,
            self.pitch_spin,
            self.tangential_cor,
            self.friction,
            self.tangential_stiffness_ratio,
        )
        .context(
            "--undercut/--attack-angle/--pitch-angle/--pitch-spin/--tangential-cor/--friction/\
             --tangential-stiffness-ratio",
        )?
        .with_spatial(self.bat_tilt, self.swing_direction, self.batter_side)
    }
}

/// The oblique inputs of a run, SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObliqueInputs {
    /// Undercut D, m.
    pub undercut: f64,
    /// Attack angle, rad.
    pub attack_angle: f64,
    /// Pitch descent angle, rad.
    pub pitch_angle: f64,
    /// Pitch spin, rad/s, backspin positive.
    pub pitch_spin: f64,
    /// The tangential contact law.
    pub contact: TangentialContact,
    /// Tilt of the bat's long axis below the horizontal, rad (barrel below the hands positive).
    pub bat_tilt: f64,
    /// Horizontal direction of the bat's path, rad, positive toward the right-field side.
    pub swing_direction: f64,
    /// The batter's side.
    pub batter_side: BatterSide,
    /// Whether the run is oblique: a geometry input is non-zero or a contact parameter was given. When
    /// false the run is the head-on collision and its output is exactly the head-on one.
    pub active: bool,
}

impl Default for ObliqueInputs {
    /// Head-on, default contact, inactive.
    fn default() -> Self {
        ObliqueInputs {
            undercut: 0.0,
            attack_angle: 0.0,
            pitch_angle: 0.0,
            pitch_spin: 0.0,
            contact: TangentialContact::default(),
            bat_tilt: 0.0,
            swing_direction: 0.0,
            batter_side: BatterSide::Right,
            active: false,
        }
    }
}

impl ObliqueInputs {
    /// From the user's units: undercut m, angles degrees, spin rpm; absent means 0 (geometry) or the
    /// published default (contact).
    pub fn from_cli_units(
        undercut: Option<f64>,
        attack_angle_deg: Option<f64>,
        pitch_angle_deg: Option<f64>,
        pitch_spin_rpm: Option<f64>,
        tangential_cor: Option<f64>,
        friction: Option<f64>,
        stiffness_ratio: Option<f64>,
    ) -> Result<ObliqueInputs> {
        let defaults = TangentialContact::default();
        let contact = TangentialContact {
            tangential_cor: tangential_cor.unwrap_or(defaults.tangential_cor),
            friction: friction.unwrap_or(defaults.friction),
            stiffness_ratio,
            ..defaults
        };
        contact.validate()?;
        let geometry = [undercut, attack_angle_deg, pitch_angle_deg, pitch_spin_rpm].map(|v| v.unwrap_or(0.0));
        if let Some(bad) = geometry.iter().find(|v| !v.is_finite()) {
            bail!("{bad} is not allowed: expected a finite number");
        }
        // The node's limits (model::limits), quoted in the units the flags take.
        let max_angle = MAX_SWING_ANGLE.to_degrees();
        for (flag, v) in [("--attack-angle", geometry[1]), ("--pitch-angle", geometry[2])] {
            if v.abs() > max_angle {
                bail!("{flag} {v}° is out of range: expected |{}| ≤ {max_angle:.0}°", &flag[2..]);
            }
        }
        let max_rpm = rad_per_s_to_rpm(MAX_PITCH_SPIN);
        if geometry[3].abs() > max_rpm {
            bail!(
                "--pitch-spin {} rpm is out of range: expected |pitch-spin| ≤ {max_rpm:.0} rpm ({MAX_PITCH_SPIN} rad/s, \
                 the node's limit)",
                geometry[3]
            );
        }
        let active = geometry.iter().any(|v| *v != 0.0)
            || tangential_cor.is_some()
            || friction.is_some()
            || stiffness_ratio.is_some();
        Ok(ObliqueInputs {
            undercut: geometry[0],
            attack_angle: geometry[1].to_radians(),
            pitch_angle: geometry[2].to_radians(),
            pitch_spin: rpm_to_rad_per_s(geometry[3]),
            contact,
            active,
            ..ObliqueInputs::default()
        })
    }

    /// These inputs with the bat's tilt and the swing's direction (degrees; absent means 0) and the batter's
    /// side (absent: right). A non-zero angle or a side given makes the run oblique, as a contact override
    /// does; the limits are the collision's (|angle| ≤ 80°, |tilt| + |attack angle| < 90°).
    pub fn with_spatial(
        self,
        bat_tilt_deg: Option<f64>,
        swing_direction_deg: Option<f64>,
        batter_side: Option<BatterSide>,
    ) -> Result<ObliqueInputs> {
        let max_angle = MAX_SWING_ANGLE.to_degrees();
        let [tilt, direction] = [
            ("--bat-tilt / bat_tilt_deg", bat_tilt_deg.unwrap_or(0.0)),
            ("--swing-direction / swing_direction_deg", swing_direction_deg.unwrap_or(0.0)),
        ];
        for (name, v) in [tilt, direction] {
            if !(v.is_finite() && v.abs() <= max_angle) {
                bail!("{name} = {v}° is out of range: expected a finite angle, |angle| ≤ {max_angle:.0}°");
            }
        }
        let (bat_tilt, swing_direction) = (tilt.1.to_radians(), direction.1.to_radians());
        // The collision's own check of the bat's reach (its rule, quoted here in degrees).
        let swing = SpatialImpact {
            oblique: ObliqueImpact {
                attack_angle: self.attack_angle,
                ..ObliqueImpact::head_on(SwingArgs::defaults().impact(0.0), 0.0)
            },
            bat_tilt,
            swing_direction,
            batter_side: BatterSide::Right,
        };
        if swing.validate().is_err() {
            let attack_deg = self.attack_angle.to_degrees();
            bail!(
                "{} = {}° with an attack angle of {attack_deg}° is out of range: expected |bat tilt| + |attack angle| \
                 < 90° (a bat perpendicular to its path cannot be tilted further)",
                tilt.0,
                tilt.1
            );
        }
        Ok(ObliqueInputs {
            bat_tilt,
            swing_direction,
            batter_side: batter_side.unwrap_or_default(),
            active: self.active || tilt.1 != 0.0 || direction.1 != 0.0 || batter_side.is_some(),
            ..self
        })
    }

    /// True when the swing lies in one vertical plane (no tilt, no swing direction): the planar model's case,
    /// whichever the batter's side.
    pub fn is_planar(&self) -> bool {
        self.bat_tilt == 0.0 && self.swing_direction == 0.0
    }
}

/// `--json`.
#[derive(Debug, Clone, Args)]
pub struct OutputArgs {
    /// Print one JSON document (snake_case fields, SI units; see docs/file-formats.md) instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// Prints `value` as pretty JSON on stdout.
pub fn print_json<T: serde::Serialize>(value: &T) -> Result<()> {
    let mut text = serde_json::to_string_pretty(value).context("cannot serialise the output as JSON")?;
    text.push('\n');
    emit(&text)
}

pub use crate::report::stdout::{closed as stdout_closed, emit, Stdout};

/// Prints a line to stdout through [`emit`] (a closed pipe ends the output quietly): `println!` for the CLI.
#[macro_export]
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::cli::common::emit(&format!("{}\n", format_args!($($arg)*)))
    };
}

/// `n thing` or `n things`.
pub(crate) fn plural(n: u64, thing: &str) -> String {
    if n == 1 {
        format!("{n} {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finite_parser_refuses_nan_and_infinity() {
        assert_eq!(finite_f64("1.5"), Ok(1.5));
        assert!(finite_f64("NaN").is_err());
        assert!(finite_f64("inf").is_err());
        assert!(finite_f64("fast").is_err());
    }

    #[test]
    fn options_are_bounded() {
        assert!(check_options(CollisionOptions { modes: 18, time_step: 5e-6 }).is_ok());
        let err = check_options(CollisionOptions { modes: 100_000, time_step: 5e-6 }).unwrap_err();
        assert!(err.to_string().contains("modes"));
        let err = check_options(CollisionOptions { modes: 18, time_step: 0.0 }).unwrap_err();
        assert!(err.to_string().contains("time_step"));
    }
}
