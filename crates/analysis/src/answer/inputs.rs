//! The inputs the one-shot answers share, in SI units: the default swing, bounds on the numerical options,
//! the oblique and 3-D inputs ([`ObliqueInputs`]) and how a bat is named (a preset or a bat file). The command
//! line's flags and the Python package's keywords both resolve into these.

use std::path::Path;

use anyhow::{bail, Context, Result};

use crate::bat_file::load_bat_file;
use crate::report::table::num;
use sweetspot_model::limits::{MAX_PITCH_SPIN, MAX_SWING_ANGLE};
use sweetspot_physics::collision::TIME_STEP_RANGE;
use sweetspot_physics::oblique::{rad_per_s_to_rpm, rpm_to_rad_per_s, TangentialContact};
use sweetspot_physics::{Ball, Bat, BatterSide, CollisionOptions, Impact, ObliqueImpact, SpatialImpact};

/// Default ball speed toward the bat, m/s (about 89 mph).
pub const DEFAULT_BALL_SPEED: f64 = 40.0;
/// Default bat centre-of-mass speed toward the ball, m/s.
pub const DEFAULT_BAT_CM_SPEED: f64 = 25.0;
/// Default bat angular speed, rad/s: with the CM speed above the R161 turns about a point near its knob,
/// and the barrel 0.15 m beyond the CM moves at about 32 m/s (71 mph).
pub const DEFAULT_BAT_ANGULAR_SPEED: f64 = 45.0;
/// Largest number of vibrational modes the CLI accepts.
pub const MAX_MODES: usize = 200;

/// The default swing (ball 40 m/s toward the bat, bat centre of mass 25 m/s, 45 rad/s) at `impact_z`, m from
/// the knob.
pub fn default_swing(impact_z: f64) -> Impact {
    Impact {
        ball_speed: DEFAULT_BALL_SPEED,
        bat_cm_speed: DEFAULT_BAT_CM_SPEED,
        bat_angular_speed: DEFAULT_BAT_ANGULAR_SPEED,
        impact_z,
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

/// The oblique and 3-D inputs in the command line's units (undercut m, angles degrees, spin rpm), `None` = not
/// given: what `simulate`'s flags and Python's keywords say, checked alike by [`ObliqueFlags::inputs`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ObliqueFlags {
    /// Undercut, m.
    pub undercut: Option<f64>,
    /// Attack angle, degrees.
    pub attack_angle: Option<f64>,
    /// Pitch descent angle, degrees.
    pub pitch_angle: Option<f64>,
    /// Pitch backspin, rpm.
    pub pitch_spin: Option<f64>,
    /// Tangential COR e_T.
    pub tangential_cor: Option<f64>,
    /// Friction coefficient μ.
    pub friction: Option<f64>,
    /// Tangential-to-normal stiffness ratio η².
    pub tangential_stiffness_ratio: Option<f64>,
    /// Bat tilt, degrees (barrel below the hands).
    pub bat_tilt: Option<f64>,
    /// Swing direction, degrees.
    pub swing_direction: Option<f64>,
    /// Batter side.
    pub batter_side: Option<BatterSide>,
}

impl ObliqueFlags {
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

/// A ball named by a preset (or the caller's base ball) with some of its fields replaced, SI units: what
/// `--ball NAME --ball-mass KG …` and Python's `Ball.preset(name, mass=…)` say.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BallOverrides {
    /// A built-in ball to start from instead of the base (`Ball::preset_names`).
    pub preset: Option<String>,
    /// Mass, kg.
    pub mass: Option<f64>,
    /// Radius, m.
    pub radius: Option<f64>,
    /// Coefficient of restitution e0 against a rigid wall.
    pub cor: Option<f64>,
    /// Loading stiffness k1, N/m^α.
    pub stiffness: Option<f64>,
    /// Loading exponent α.
    pub exponent: Option<f64>,
    /// Exponent p of e0 ∝ v^(−p).
    pub cor_speed_exponent: Option<f64>,
    /// Normal approach speed at which e0 is `cor`, m/s.
    pub cor_reference_speed: Option<f64>,
}

impl BallOverrides {
    /// `base` (or the preset) with the overrides applied, validated.
    pub fn apply(&self, base: Ball) -> Result<Ball> {
        let base = match &self.preset {
            Some(name) => Ball::preset(name).context("--ball")?,
            None => base,
        };
        let ball = Ball {
            mass: self.mass.unwrap_or(base.mass),
            radius: self.radius.unwrap_or(base.radius),
            stiffness: self.stiffness.unwrap_or(base.stiffness),
            exponent: self.exponent.unwrap_or(base.exponent),
            cor: self.cor.unwrap_or(base.cor),
            cor_speed_exponent: self.cor_speed_exponent.unwrap_or(base.cor_speed_exponent),
            cor_reference_speed: self.cor_reference_speed.unwrap_or(base.cor_reference_speed),
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
                ..ObliqueImpact::head_on(default_swing(0.0), 0.0)
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
