//! The answer of `sweetspot compare` (and Python's `compare`): bats compared as one batter swings them — at equal effort, not at equal bat speed.
//!
//! For each bat: swing weight (moment of inertia about the 6-in pivot), the bat speed the batter model
//! (`physics::batter`) predicts for it, the sweet spot and best exit speed for that swing, the exit speed at
//! the batter's usual impact point, BBCOR, the swing's duration and the reaction time gained against the
//! first bat (with the distance the pitch travels meanwhile).
//!
//! The batter file (`--batter FILE`, TOML; every key optional, the defaults are the Statcast average batter
//! of `Batter::typical`):
//!
//! ```toml
//! reference_bat = "r161"          # preset or bat file (relative to this file) the swing was measured with
//! bat_speed = 31.96               # m/s at the usual impact point of the reference bat
//! impact_from_barrel_end = 0.1524 # m: the usual impact point, the same distance from the end on every bat
//! pivot_z = 0.0                   # m from the knob: the swing's instantaneous centre at contact
//! exponent = 0.25                 # n of v ∝ I^(−n), 0 ≤ n ≤ 0.5
//! swing_length = 2.225            # m: arc of the impact point from the start of the swing to contact
//! shape = "same-pivot"            # or "same-ratio" (ω/V kept; with exponent 0, today's equal-speed comparison)
//! ```

// Negated comparisons (`!(a < b)`) are deliberate: they also reject NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use std::path::Path;

use anyhow::{bail, Context, Result};
use serde::{Deserialize, Serialize};

use super::inputs::resolve_bat;
use crate::report::json::{BallJson, OptionsJson};
use crate::report::table::{num, Table};
use sweetspot_physics::batter::{
    pitch_travel, reaction_time_gained, Batter, ReferenceSwing, SwingPrediction, SwingShape, DEFAULT_EXPONENT,
    DEFAULT_IMPACT_FROM_BARREL_END, DEFAULT_PIVOT_Z, DEFAULT_REFERENCE_SPEED, DEFAULT_SWING_LENGTH,
    SWING_WEIGHT_PIVOT_Z,
};
use sweetspot_physics::metrics::{bbcor, sweet_spots};
use sweetspot_physics::{collide, Ball, Bat, CollisionOptions, ModeSet};

/// The bats compared when `--bats` is not given.
pub const DEFAULT_BATS: &str = "r161,r161-corked,aluminum,torpedo";
/// The bat the default batter's reference swing was measured with.
pub const DEFAULT_REFERENCE_BAT: &str = "r161";
/// Most bats one comparison accepts.
pub const MAX_BATS: usize = 32;
/// Impact points per bat in the `--figure` chart.
pub const FIGURE_POINTS: usize = 100;

/// The TOML document of a batter file; every key is optional.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BatterSpec {
    /// Preset or bat file the reference swing was measured with [default r161].
    pub reference_bat: Option<String>,
    /// Reference bat speed at the usual impact point, m/s [default 71.5 mph].
    pub bat_speed: Option<f64>,
    /// Distance of the usual impact point from the barrel end, m [default 0.1524].
    pub impact_from_barrel_end: Option<f64>,
    /// Instantaneous centre of the swing at contact, m from the knob [default 0].
    pub pivot_z: Option<f64>,
    /// Exponent n of v ∝ I^(−n) [default 0.25].
    pub exponent: Option<f64>,
    /// Arc length of the usual impact point from the start of the swing to contact, m [default 2.225].
    pub swing_length: Option<f64>,
    /// How the swing keeps its shape on another bat [default same-pivot].
    pub shape: Option<SwingShape>,
}

/// The batter as used, in the JSON document.
#[derive(Debug, Clone, Serialize)]
pub struct BatterJson {
    /// Name of the bat the reference swing was measured with.
    pub reference_bat: String,
    /// Swing weight of the reference bat, kg·m².
    pub reference_swing_weight: f64,
    /// Reference bat speed at the usual impact point, m/s.
    pub bat_speed: f64,
    /// Reference bat centre-of-mass speed, m/s.
    pub bat_cm_speed: f64,
    /// Reference bat angular speed, rad/s.
    pub bat_angular_speed: f64,
    /// Distance of the usual impact point from the barrel end, m.
    pub impact_from_barrel_end: f64,
    /// Exponent n of v ∝ I^(−n).
    pub exponent: f64,
    /// Arc length of the usual impact point from the start of the swing to contact, m.
    pub swing_length: f64,
    /// How the swing keeps its shape on another bat.
    pub shape: SwingShape,
    /// Pivot of the swing weight, m from the knob.
    pub swing_weight_pivot_z: f64,
}

/// One bat at the batter's effort.
#[derive(Debug, Clone, Serialize)]
pub struct CompareBatJson {
    /// Bat name.
    pub name: String,
    /// Mass, kg.
    pub mass: f64,
    /// Length, m.
    pub length: f64,
    /// Centre of mass, m from the knob.
    pub center_of_mass: f64,
    /// Moment of inertia about the centre of mass, kg·m².
    pub moment_of_inertia: f64,
    /// Swing weight (moment of inertia about the 6-in pivot), kg·m².
    pub swing_weight: f64,
    /// Predicted speed ratio to the reference swing.
    pub speed_ratio: f64,
    /// Predicted bat speed at the usual impact point, m/s.
    pub bat_speed: f64,
    /// Predicted centre-of-mass speed, m/s.
    pub bat_cm_speed: f64,
    /// Predicted angular speed, rad/s.
    pub bat_angular_speed: f64,
    /// The usual impact point on this bat, m from the knob.
    pub impact_z: f64,
    /// Exit speed at the usual impact point, m/s.
    pub exit_speed_at_impact: f64,
    /// Impact point of maximum exit speed for this swing, m from the knob.
    pub sweet_spot_z: f64,
    /// That maximum exit speed, m/s.
    pub max_exit_speed: f64,
    /// BBCOR under the certification protocol.
    pub bbcor: f64,
    /// Duration of the swing from its start to contact, s.
    pub swing_time: f64,
    /// How much later than with the first bat the swing can start for the same contact, s.
    pub reaction_time_gained: f64,
    /// Distance the pitch travels during that time, m.
    pub pitch_travel: f64,
}

/// The JSON document of `sweetspot compare --json`.
#[derive(Debug, Serialize)]
pub struct CompareJson {
    /// The batter.
    pub batter: BatterJson,
    /// Pitch speed, m/s.
    pub pitch_speed: f64,
    /// The ball.
    pub ball: BallJson,
    /// Numerical options.
    pub options: OptionsJson,
    /// One entry per bat, in the order given; the first is the baseline.
    pub bats: Vec<CompareBatJson>,
}

/// Reads a batter file; relative bat paths in it are taken relative to the file.
pub fn load_batter_file(path: &Path) -> Result<(Batter, String)> {
    let text = sweetspot_model::files::read_text(path, "batter file")?;
    let spec: BatterSpec = toml::from_str(&text).with_context(|| format!("batter file '{}'", path.display()))?;
    batter_from_spec(&spec, path.parent()).with_context(|| format!("batter file '{}'", path.display()))
}

/// The batter of `spec` (defaults filled in) and the name of its reference bat.
pub fn batter_from_spec(spec: &BatterSpec, base: Option<&Path>) -> Result<(Batter, String)> {
    let bat_name = spec.reference_bat.as_deref().unwrap_or(DEFAULT_REFERENCE_BAT);
    let bat = resolve_bat(bat_name, base).context("reference_bat")?;
    let props = bat.mass_properties();
    let from_end = spec.impact_from_barrel_end.unwrap_or(DEFAULT_IMPACT_FROM_BARREL_END);
    // Checked before the reference swing is built from it: an impact off the bat would be blamed on pivot_z.
    if !(from_end >= 0.0 && from_end < props.length) {
        return Err(sweetspot_physics::PhysicsError::out_of_range(
            "impact_from_barrel_end",
            from_end,
            format!("0 ≤ d < reference bat length = {} m", props.length),
        )
        .into());
    }
    let reference = ReferenceSwing::from_speed_at(
        props,
        spec.bat_speed.unwrap_or(DEFAULT_REFERENCE_SPEED),
        props.length - from_end,
        spec.pivot_z.unwrap_or(DEFAULT_PIVOT_Z),
    )?;
    let batter = Batter::new(
        reference,
        spec.exponent.unwrap_or(DEFAULT_EXPONENT),
        from_end,
        spec.swing_length.unwrap_or(DEFAULT_SWING_LENGTH),
        spec.shape.unwrap_or_default(),
    )?;
    Ok((batter, bat.name))
}

/// Compares `bats` as `batter` swings them against a pitch at `pitch_speed` (m/s).
pub fn compare(
    batter: &Batter,
    reference_name: &str,
    bats: &[Bat],
    ball: &Ball,
    pitch_speed: f64,
    options: &CollisionOptions,
) -> Result<CompareJson> {
    let mut rows = Vec::with_capacity(bats.len());
    let mut baseline: Option<SwingPrediction> = None;
    for bat in bats {
        let modes =
            ModeSet::compute(bat, options.modes).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
        let props = modes.mass_properties();
        let swing = batter.predict(&props).with_context(|| format!("batter swinging bat '{}'", bat.name))?;
        let first = *baseline.get_or_insert(swing);
        let impact = swing.impact(pitch_speed);
        let at_impact = collide(&modes, ball, &impact, options)
            .with_context(|| format!("bat '{}' at its usual impact point {} m", bat.name, swing.impact_z))?;
        let spots =
            sweet_spots(&modes, ball, &impact, options).with_context(|| format!("sweet spots of '{}'", bat.name))?;
        let bbcor = bbcor(&modes, options).with_context(|| format!("BBCOR of '{}'", bat.name))?;
        let gained = reaction_time_gained(&first, &swing);
        rows.push(CompareBatJson {
            name: bat.name.clone(),
            mass: props.mass,
            length: props.length,
            center_of_mass: props.center_of_mass,
            moment_of_inertia: props.moment_of_inertia,
            swing_weight: swing.swing_weight,
            speed_ratio: swing.speed_ratio,
            bat_speed: swing.bat_speed,
            bat_cm_speed: swing.bat_cm_speed,
            bat_angular_speed: swing.bat_angular_speed,
            impact_z: swing.impact_z,
            exit_speed_at_impact: at_impact.exit_speed,
            sweet_spot_z: spots.max_exit_speed_z,
            max_exit_speed: spots.max_exit_speed,
            bbcor,
            swing_time: swing.swing_time,
            reaction_time_gained: gained,
            pitch_travel: pitch_travel(gained, pitch_speed)?,
        });
    }
    let reference = &batter.reference;
    Ok(CompareJson {
        batter: BatterJson {
            reference_bat: reference_name.to_string(),
            reference_swing_weight: batter.reference_swing_weight(),
            bat_speed: batter.reference_speed(),
            bat_cm_speed: reference.bat_cm_speed,
            bat_angular_speed: reference.bat_angular_speed,
            impact_from_barrel_end: batter.impact_from_barrel_end,
            exponent: batter.exponent,
            swing_length: batter.swing_length,
            shape: batter.shape,
            swing_weight_pivot_z: SWING_WEIGHT_PIVOT_Z,
        },
        pitch_speed,
        ball: ball.into(),
        options: options.into(),
        bats: rows,
    })
}

/// The human-readable report.
pub fn render(doc: &CompareJson) -> String {
    let b = &doc.batter;
    let mut out = format!(
        "batter: {} m/s at {} m from the barrel end of {} (swing weight {} kg·m² about {} m), n = {}, \
         swing length {} m, shape {}\npitch: {} m/s; equal effort: v ∝ I^(−n), swing time T = 2·length/v\n\n",
        num(b.bat_speed, 4),
        num(b.impact_from_barrel_end, 4),
        b.reference_bat,
        num(b.reference_swing_weight, 4),
        num(b.swing_weight_pivot_z, 4),
        num(b.exponent, 4),
        num(b.swing_length, 4),
        match b.shape {
            SwingShape::SamePivot => "same-pivot",
            SwingShape::SameRatio => "same-ratio",
        },
        num(doc.pitch_speed, 4),
    );
    let mut t = Table::new([
        "bat",
        "swing weight (kg·m²)",
        "bat speed (m/s)",
        "sweet spot (m)",
        "best exit (m/s)",
        "exit at usual (m/s)",
        "BBCOR",
        "swing (ms)",
        "gained (ms)",
        "pitch travel (m)",
    ]);
    for r in &doc.bats {
        t.row([
            r.name.clone(),
            num(r.swing_weight, 4),
            num(r.bat_speed, 4),
            num(r.sweet_spot_z, 4),
            num(r.max_exit_speed, 4),
            num(r.exit_speed_at_impact, 4),
            num(r.bbcor, 4),
            num(r.swing_time * 1e3, 4),
            num(r.reaction_time_gained * 1e3, 3),
            num(r.pitch_travel, 3),
        ]);
    }
    out.push_str(&t.render());
    out
}

/// Splits `--bats` and loads each bat.
pub fn parse_bats(list: &str) -> Result<Vec<Bat>> {
    let names: Vec<&str> = list.split(',').map(str::trim).filter(|s| !s.is_empty()).collect();
    if names.is_empty() || names.len() > MAX_BATS {
        bail!("--bats: {} bats given, expected 1 to {MAX_BATS} (comma-separated)", names.len());
    }
    names.iter().map(|name| resolve_bat(name, None).with_context(|| format!("--bats: '{name}'"))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batter_file_keys_are_optional_and_unknown_keys_refused() {
        let spec: BatterSpec = toml::from_str("exponent = 0.3\nshape = \"same-ratio\"\n").expect("spec");
        assert_eq!(spec.exponent, Some(0.3));
        assert_eq!(spec.shape, Some(SwingShape::SameRatio));
        assert!(toml::from_str::<BatterSpec>("exponnent = 0.3\n").is_err());
        let (batter, name) = batter_from_spec(&spec, None).expect("batter");
        assert_eq!(name, "r161");
        assert_eq!(batter.exponent, 0.3);
        let bad = BatterSpec { exponent: Some(0.9), ..BatterSpec::default() };
        assert!(batter_from_spec(&bad, None).is_err());
    }

    #[test]
    fn bat_list_is_parsed_and_bounded() {
        assert_eq!(parse_bats("r161, torpedo").expect("bats").len(), 2);
        assert!(parse_bats(" , ").is_err());
        assert!(parse_bats("r161,nonesuch").is_err());
    }
}
