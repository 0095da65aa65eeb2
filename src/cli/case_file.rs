//! The case file of `sweetspot simulate --case FILE`: one bat, one ball, one swing, one or more impact
//! points, as JSON or YAML (the same fields; a `.yaml`/`.yml` file, or any file that is not JSON). Missing
//! fields take the command's defaults; unknown fields are an error naming them.
//!
//! ```json
//! {
//!   "bat": "r161",
//!   "ball": {"preset": "mlb", "cor": 0.5},
//!   "ball_speed": 40.0,
//!   "bat_cm_speed": 25.0,
//!   "bat_angular_speed": 45.0,
//!   "impact_z": [0.65, 0.70, 0.75],
//!   "modes": 18,
//!   "time_step": 5e-6
//! }
//! ```
//!
//! The oblique inputs are optional (absent or zero: a head-on swing), in the units their names carry:
//! `undercut` (m, ball centre above the bat's path positive), `attack_angle_deg` (bat path above the
//! horizontal, degrees), `pitch_angle_deg` (pitch descent below the horizontal, degrees), `pitch_spin_rpm`
//! (rpm, backspin positive), and the tangential contact overrides `tangential_cor` (e_T), `friction` (μ) and
//! `tangential_stiffness_ratio` (η², the compliant law instead of a constant e_T). The swing in three
//! dimensions adds `bat_tilt_deg` (the bat's long axis below the horizontal, barrel below the hands positive),
//! `swing_direction_deg` (the bat's path, right-field side positive) and `batter_side` (`right` or `left`).
//!
//! `ball` is a preset name (`"mlb"`; baseball, bbcor, mlb, mlb2024) or an object of overrides (`mass`, `radius`,
//! `stiffness`, `exponent`, `cor`, `cor_speed_exponent`, `cor_reference_speed`) over the ball `preset` it names
//! (default mlb2024, the game ball).
//!
//! `bat` is a preset name (r161, r161-corked, aluminum, torpedo), a path to a bat file (relative to the case
//! file), or a bat object with the
//! fields of the bat file format (`name`, `slice_length`, `shell`, optional `core`, and `station` as a list
//! of `{z, outer_radius, inner_radius}`, or `profile` naming a CSV relative to the case file).

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use serde::Deserialize;

use super::bat_file::BatSpec;
use super::common::{
    check_options, resolve_bat, ObliqueInputs, DEFAULT_BALL_SPEED, DEFAULT_BAT_ANGULAR_SPEED, DEFAULT_BAT_CM_SPEED,
};
use crate::physics::{Ball, Bat, BatterSide, CollisionOptions, Impact};

/// The raw JSON document.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    /// Preset name, bat file path, or bat object.
    #[serde(default)]
    pub bat: Option<serde_json::Value>,
    /// Ball preset name, or ball object (a preset and overrides).
    #[serde(default)]
    pub ball: Option<serde_json::Value>,
    /// m/s toward the bat.
    #[serde(default)]
    pub ball_speed: Option<f64>,
    /// m/s toward the ball.
    #[serde(default)]
    pub bat_cm_speed: Option<f64>,
    /// rad/s, positive when the barrel leads.
    #[serde(default)]
    pub bat_angular_speed: Option<f64>,
    /// One impact point or a list, m from the knob.
    #[serde(default)]
    pub impact_z: Option<serde_json::Value>,
    /// Vibrational modes integrated.
    #[serde(default)]
    pub modes: Option<usize>,
    /// RK4 step, s.
    #[serde(default)]
    pub time_step: Option<f64>,
    /// Undercut, m (ball centre above the bat's path positive).
    #[serde(default)]
    pub undercut: Option<f64>,
    /// Attack angle of the bat's path above the horizontal, degrees.
    #[serde(default)]
    pub attack_angle_deg: Option<f64>,
    /// Descent angle of the pitch below the horizontal, degrees.
    #[serde(default)]
    pub pitch_angle_deg: Option<f64>,
    /// Pitch spin about the bat's axis, rpm, backspin positive.
    #[serde(default)]
    pub pitch_spin_rpm: Option<f64>,
    /// Tangential coefficient of restitution e_T.
    #[serde(default)]
    pub tangential_cor: Option<f64>,
    /// Coulomb friction coefficient μ.
    #[serde(default)]
    pub friction: Option<f64>,
    /// η² = k_n/k_t of the compliant tangential law.
    #[serde(default)]
    pub tangential_stiffness_ratio: Option<f64>,
    /// Tilt of the bat's long axis below the horizontal, degrees (barrel below the hands positive).
    #[serde(default)]
    pub bat_tilt_deg: Option<f64>,
    /// Horizontal direction of the bat's path, degrees, positive toward the right-field side.
    #[serde(default)]
    pub swing_direction_deg: Option<f64>,
    /// The batter's side, `right` or `left`.
    #[serde(default)]
    pub batter_side: Option<BatterSide>,
}

/// Ball fields, each optional, over a preset.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BallSpec {
    /// The preset the other fields override (baseball, bbcor, mlb, mlb2024) [default mlb2024, the game ball].
    pub preset: Option<String>,
    /// kg.
    pub mass: Option<f64>,
    /// m.
    pub radius: Option<f64>,
    /// k1, N/m^α.
    pub stiffness: Option<f64>,
    /// α.
    pub exponent: Option<f64>,
    /// e0 (at `cor_reference_speed` when `cor_speed_exponent` is given).
    pub cor: Option<f64>,
    /// p of e0 ∝ v^(−p) (0 = constant COR).
    pub cor_speed_exponent: Option<f64>,
    /// Normal approach speed at which e0 = `cor`, m/s.
    pub cor_reference_speed: Option<f64>,
}

/// A resolved case, ready to simulate.
#[derive(Debug, Clone)]
pub struct Case {
    /// The bat.
    pub bat: Bat,
    /// The ball (validated).
    pub ball: Ball,
    /// The swing; `impact_z` is taken from `impact_zs`.
    pub swing: Impact,
    /// The oblique inputs, SI units (inactive for a head-on case).
    pub oblique: ObliqueInputs,
    /// Impact points, m from the knob; empty means "use the command's default".
    pub impact_zs: Vec<f64>,
    /// Numerical options.
    pub options: CollisionOptions,
}

/// YAML's `.nan` and `.inf` reach a case as the strings the message decoder accepts, which no number field of a
/// case takes: say so instead of serde's 'invalid type: string "nan"'.
fn non_finite_reason(serde_reason: &str) -> Option<String> {
    ["nan", "inf", "-inf"]
        .into_iter()
        .find(|word| serde_reason.starts_with(&format!("invalid type: string \"{word}\"")))
        .map(|word| {
            format!("{word} is not a number a case takes: give a finite value in the field's range (docs/cli.md)")
        })
}

/// Parses and resolves a case from its JSON or YAML text; relative bat paths are resolved against `base`.
pub fn parse_case(text: &str, base: &Path) -> Result<Case> {
    let value = crate::client::values::parse_document(text, "the case")?;
    let spec: CaseSpec = serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let reason = non_finite_reason(&e.inner().to_string()).unwrap_or_else(|| e.inner().to_string());
        if path.is_empty() || path == "." {
            anyhow!("{reason}")
        } else {
            anyhow!("field `{path}`: {reason}")
        }
    })?;
    let bat = case_bat(spec.bat.as_ref(), base)?;
    let ball = case_ball(spec.ball)?;
    let swing = Impact {
        ball_speed: spec.ball_speed.unwrap_or(DEFAULT_BALL_SPEED),
        bat_cm_speed: spec.bat_cm_speed.unwrap_or(DEFAULT_BAT_CM_SPEED),
        bat_angular_speed: spec.bat_angular_speed.unwrap_or(DEFAULT_BAT_ANGULAR_SPEED),
        impact_z: f64::NAN,
    };
    let impact_zs = match &spec.impact_z {
        None => Vec::new(),
        Some(value) => impact_list(value)?,
    };
    let defaults = CollisionOptions::default();
    let options = check_options(CollisionOptions {
        modes: spec.modes.unwrap_or(defaults.modes),
        time_step: spec.time_step.unwrap_or(defaults.time_step),
    })?;
    let oblique = ObliqueInputs::from_cli_units(
        spec.undercut,
        spec.attack_angle_deg,
        spec.pitch_angle_deg,
        spec.pitch_spin_rpm,
        spec.tangential_cor,
        spec.friction,
        spec.tangential_stiffness_ratio,
    )
    .context(
        "fields `undercut`/`attack_angle_deg`/`pitch_angle_deg`/`pitch_spin_rpm`/`tangential_cor`/`friction`/\
         `tangential_stiffness_ratio`",
    )?
    .with_spatial(spec.bat_tilt_deg, spec.swing_direction_deg, spec.batter_side)
    .context("fields `bat_tilt_deg`/`swing_direction_deg`")?;
    Ok(Case { bat, ball, swing, oblique, impact_zs, options })
}

/// The case's `bat`: a preset name or a bat file path (relative to `base`), a bat object, or the default.
fn case_bat(value: Option<&serde_json::Value>, base: &Path) -> Result<Bat> {
    Ok(match value {
        None => Bat::preset("r161")?,
        Some(serde_json::Value::String(name)) => resolve_bat(name, Some(base)).context("field `bat`")?,
        Some(value @ serde_json::Value::Object(_)) => {
            let bat_spec: BatSpec = serde_json::from_value(value.clone()).map_err(|e| anyhow!("field `bat`: {e}"))?;
            bat_spec
                .into_bat("case-bat", |file| {
                    let path = base.join(file);
                    Ok(crate::files::read_text(&path, "bat profile")?)
                })
                .context("field `bat`")?
        }
        Some(other) => bail!("field `bat`: expected a preset name, a bat file path or a bat object, found {other}"),
    })
}

/// The case's `ball`: a preset name, or an object whose fields override its `preset` (default: the game
/// ball); checked.
fn case_ball(value: Option<serde_json::Value>) -> Result<Ball> {
    let overrides = match value {
        None => BallSpec::default(),
        Some(serde_json::Value::String(name)) => BallSpec { preset: Some(name), ..BallSpec::default() },
        Some(value @ serde_json::Value::Object(_)) => {
            serde_json::from_value(value).map_err(|e| anyhow!("field `ball`: {e}"))?
        }
        Some(other) => {
            bail!(
                "field `ball`: expected a preset name ({}) or a ball object, found {other}",
                Ball::preset_names().join(", ")
            )
        }
    };
    let default = match &overrides.preset {
        None => Ball::game(),
        Some(name) => Ball::preset(name).context("field `ball`")?,
    };
    let ball = Ball {
        mass: overrides.mass.unwrap_or(default.mass),
        radius: overrides.radius.unwrap_or(default.radius),
        stiffness: overrides.stiffness.unwrap_or(default.stiffness),
        exponent: overrides.exponent.unwrap_or(default.exponent),
        cor: overrides.cor.unwrap_or(default.cor),
        cor_speed_exponent: overrides.cor_speed_exponent.unwrap_or(default.cor_speed_exponent),
        cor_reference_speed: overrides.cor_reference_speed.unwrap_or(default.cor_reference_speed),
    };
    ball.validate().context("field `ball`")?;
    Ok(ball)
}

/// `impact_z` as a list: one number or a non-empty list of numbers, m.
fn impact_list(value: &serde_json::Value) -> Result<Vec<f64>> {
    let expected = "expected a number or a non-empty list of numbers (m from the knob)";
    match value {
        serde_json::Value::Number(n) => Ok(vec![n.as_f64().ok_or_else(|| anyhow!("field `impact_z`: {expected}"))?]),
        serde_json::Value::Array(items) if !items.is_empty() => items
            .iter()
            .enumerate()
            .map(|(i, item)| item.as_f64().ok_or_else(|| anyhow!("field `impact_z[{i}]` = {item}: {expected}")))
            .collect(),
        other => bail!("field `impact_z` = {other}: {expected}"),
    }
}

/// Reads and resolves a case file.
pub fn load_case(path: &Path) -> Result<Case> {
    let text = crate::files::read_text(path, "case file")?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    parse_case(&text, &base).with_context(|| format!("case file '{}'", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_fields_are_named() {
        let err = parse_case(r#"{"ball_speeed": 40}"#, Path::new(".")).unwrap_err();
        assert!(format!("{err:#}").contains("ball_speeed"), "{err:#}");
        let err = parse_case(r#"{"ball": {"e0": 0.5}}"#, Path::new(".")).unwrap_err();
        assert!(format!("{err:#}").contains("e0"), "{err:#}");
    }

    #[test]
    fn malformed_json_is_an_error() {
        assert!(parse_case("{\"bat\": ", Path::new(".")).is_err());
        assert!(parse_case(r#"{"impact_z": "far"}"#, Path::new(".")).is_err());
        assert!(parse_case(r#"{"bat": 3}"#, Path::new(".")).is_err());
        assert!(parse_case(r#"{"impact_z": []}"#, Path::new(".")).is_err());
    }

    #[test]
    fn inline_bat_object_parses() {
        let text = r#"{"bat": {"name": "stick", "slice_length": 0.01,
            "shell": {"density": 700, "youngs_modulus": 1.5e10, "shear_modulus": 1e9},
            "station": [{"z": 0.0, "outer_radius": 0.02}, {"z": 0.8, "outer_radius": 0.03}]},
            "impact_z": 0.7, "modes": 4}"#;
        let case = parse_case(text, Path::new(".")).unwrap_or_else(|err| panic!("{err:#}"));
        assert_eq!(case.bat.name, "stick");
        assert_eq!(case.impact_zs, vec![0.7]);
        assert_eq!(case.options.modes, 4);
        assert!(!case.oblique.active);
    }

    #[test]
    fn oblique_fields_are_read_in_their_named_units() {
        let text = r#"{"undercut": 0.01, "attack_angle_deg": 45, "pitch_spin_rpm": 60, "friction": 0.3}"#;
        let case = parse_case(text, Path::new(".")).unwrap_or_else(|err| panic!("{err:#}"));
        assert!(case.oblique.active);
        assert_eq!(case.oblique.undercut, 0.01);
        assert!((case.oblique.attack_angle - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
        // Beyond the node's 80° the case is refused in the unit it was given in.
        let err = parse_case(r#"{"attack_angle_deg": 90}"#, Path::new(".")).unwrap_err();
        assert!(format!("{err:#}").contains("90° is out of range"), "{err:#}");
        assert!((case.oblique.pitch_spin - std::f64::consts::TAU).abs() < 1e-12, "60 rpm is one turn a second");
        assert_eq!(case.oblique.contact.friction, 0.3);
        let err = parse_case(r#"{"tangential_cor": 2}"#, Path::new(".")).unwrap_err();
        assert!(format!("{err:#}").contains("tangential_cor"), "{err:#}");
    }

    #[test]
    fn a_ball_is_named_by_preset_or_given_inline_over_one() {
        // "ball": "mlb" once failed with "expected struct BallSpec".
        let case =
            parse_case(r#"{"ball": "mlb", "bat": "aluminum"}"#, Path::new(".")).unwrap_or_else(|e| panic!("{e:#}"));
        assert_eq!(case.ball, Ball::mlb());
        assert_eq!(case.bat.name, "aluminum");
        let case = parse_case(r#"{"ball": {"preset": "bbcor", "cor": 0.5}}"#, Path::new(".")).unwrap();
        assert_eq!(case.ball, Ball { cor: 0.5, ..Ball::bbcor_protocol() });
        // Without a preset the overrides apply to the game ball, the default of every command.
        let case = parse_case(r#"{"ball": {"cor": 0.5}}"#, Path::new(".")).unwrap();
        assert_eq!(case.ball, Ball { cor: 0.5, ..Ball::mlb2024() });
        let err = format!("{:#}", parse_case(r#"{"ball": "softball"}"#, Path::new(".")).unwrap_err());
        assert!(err.contains("softball") && err.contains("mlb"), "{err}");
        let err = format!("{:#}", parse_case(r#"{"ball": 3}"#, Path::new(".")).unwrap_err());
        assert!(err.contains("preset name"), "{err}");
    }

    #[test]
    fn a_yaml_nan_or_inf_is_named_as_such() {
        for (yaml, word) in [("tangential_stiffness_ratio: .nan\n", "nan"), ("ball_speed: -.inf\n", "-inf")] {
            let err = format!("{:#}", parse_case(yaml, Path::new(".")).unwrap_err());
            assert!(err.contains(&format!("{word} is not a number a case takes")), "{err}");
            assert!(!err.contains("invalid type"), "{err}");
        }
    }

    #[test]
    fn a_yaml_case_reads_as_its_json_twin() {
        let yaml = "bat: torpedo\nball: mlb\nball_speed: 38.5\nimpact_z: [0.65, 0.7]\nmodes: 6\ntime_step: 5.0e-6\n";
        let json = r#"{"bat": "torpedo", "ball": "mlb", "ball_speed": 38.5, "impact_z": [0.65, 0.7], "modes": 6,
            "time_step": 5e-6}"#;
        let (a, b) = (parse_case(yaml, Path::new(".")).unwrap(), parse_case(json, Path::new(".")).unwrap());
        assert_eq!((a.bat.name.as_str(), a.ball, a.impact_zs.clone()), ("torpedo", Ball::mlb(), vec![0.65, 0.7]));
        assert_eq!((a.swing.ball_speed, a.options.modes, a.options.time_step), (38.5, 6, 5e-6));
        assert_eq!((a.ball, a.swing.ball_speed, a.impact_zs), (b.ball, b.swing.ball_speed, b.impact_zs));
        let err = format!("{:#}", parse_case("ball_speeed: 40\n", Path::new(".")).unwrap_err());
        assert!(err.contains("ball_speeed"), "{err}");
    }
}
