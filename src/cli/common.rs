//! Arguments shared by the physics commands (`--bat`, ball overrides, `--modes`, `--dt`, swing speeds) and
//! their resolution into physics values.

pub use crate::answer::inputs::*;

use anyhow::{Context, Result};
use clap::Args;

use crate::physics::{Ball, Bat, BatterSide, CollisionOptions, Impact};

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

/// Parses seconds from 0 to `max` (clap value parser) for a wait that must end: +∞ and anything longer are
/// refused with the range.
fn seconds_up_to(text: &str, max: f64) -> std::result::Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("'{text}' is not a number of seconds"))?;
    if (0.0..=max).contains(&value) {
        return Ok(value);
    }
    let value = crate::model::limits::number(value);
    Err(format!("{value} s is out of range: expected seconds from 0 to {max} (a wait that ends)"))
}

/// Parses `--spin-time` (clap value parser): 0 to [`crate::client::MAX_SPIN_TIME_SECS`].
pub fn spin_seconds(text: &str) -> std::result::Result<f64, String> {
    seconds_up_to(text, crate::client::MAX_SPIN_TIME_SECS)
}

/// Parses a service call's `--timeout` (clap value parser): 0 to [`crate::client::MAX_CALL_TIMEOUT_SECS`].
pub fn call_timeout_seconds(text: &str) -> std::result::Result<f64, String> {
    seconds_up_to(text, crate::client::MAX_CALL_TIMEOUT_SECS)
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
        BallOverrides {
            preset: self.ball_preset.clone(),
            mass: self.ball_mass,
            radius: self.ball_radius,
            cor: self.ball_cor,
            stiffness: self.ball_stiffness,
            exponent: self.ball_exponent,
            cor_speed_exponent: self.ball_cor_exponent,
            cor_reference_speed: self.ball_cor_speed,
        }
        .apply(base)
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
        self.flags().inputs()
    }

    /// The flags as given, in the command line's units.
    pub fn flags(&self) -> ObliqueFlags {
        ObliqueFlags {
            undercut: self.undercut,
            attack_angle: self.attack_angle,
            pitch_angle: self.pitch_angle,
            pitch_spin: self.pitch_spin,
            tangential_cor: self.tangential_cor,
            friction: self.friction,
            tangential_stiffness_ratio: self.tangential_stiffness_ratio,
            bat_tilt: self.bat_tilt,
            swing_direction: self.swing_direction,
            batter_side: self.batter_side,
        }
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
