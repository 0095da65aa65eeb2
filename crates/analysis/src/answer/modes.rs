//! The answer of `sweetspot modes` (and Python's `Bat.modes`): mass properties and the vibrational modes of a bat, and for hollow bats the hoop
//! (n = 2 shell) frequency of the barrel wall along the barrel and at the sweet spot.

use anyhow::{bail, Context, Result};
use serde::Serialize;

use super::inputs::MAX_MODES;
use crate::report::json::BatJson;
use sweetspot_physics::metrics::sweet_spots;
use sweetspot_physics::{Ball, CollisionOptions, ModeSet};

/// One vibrational mode in the JSON document.
#[derive(Debug, Clone, Serialize)]
pub struct ModeJson {
    /// 1-based mode number.
    pub mode: usize,
    /// Hz.
    pub frequency_hz: f64,
    /// Node positions (zeros of the transverse displacement), m from the knob, ascending.
    pub nodes: Vec<f64>,
    /// Modal mass, kg: Σ m_i y_i² + Σ J_i φ_i² with the shape scaled to a peak displacement of 1.
    pub modal_mass: f64,
}

/// The barrel wall's hoop (n = 2) mode at one point.
#[derive(Debug, Clone, Serialize)]
pub struct HoopPointJson {
    /// m from the knob.
    pub z: f64,
    /// Hoop frequency f_h, Hz.
    pub frequency_hz: f64,
    /// Wall thickness, m.
    pub wall_thickness: f64,
    /// Hoop stiffness k_h, N/m.
    pub stiffness: f64,
    /// Effective mass m_h, kg.
    pub effective_mass: f64,
}

/// The hoop mode along a hollow barrel.
#[derive(Debug, Clone, Serialize)]
pub struct HoopAlongJson {
    /// At a few points along the barrel (0.35 m to 0.05 m before the barrel end, every 0.05 m), where the
    /// section has a hoop mode.
    pub along: Vec<HoopPointJson>,
    /// At the sweet spot (maximum exit speed for the default swing), if the section there has one.
    pub sweet_spot: Option<HoopPointJson>,
}

/// The JSON document of `sweetspot modes --json`.
#[derive(Debug, Serialize)]
pub struct ModesJson {
    /// Mass properties of the discretised bat.
    pub bat: BatJson,
    /// Vibrational modes, ascending frequency (the two rigid-body modes are not listed).
    pub modes: Vec<ModeJson>,
    /// The barrel wall's hoop mode (hollow bats only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hoop: Option<HoopAlongJson>,
}

/// The hoop mode at `z`, if the section there has one.
fn hoop_point(set: &ModeSet, z: f64) -> Option<HoopPointJson> {
    set.hoop_at(z).map(|h| HoopPointJson {
        z,
        frequency_hz: h.frequency_hz(),
        wall_thickness: h.wall_thickness,
        stiffness: h.stiffness,
        effective_mass: h.effective_mass,
    })
}

/// The hoop mode along the barrel and at the sweet spot (maximum exit speed for the default swing and ball,
/// with the listed modes, at most the default number), or `None` for a bat without one.
fn hoop_along(set: &ModeSet, count: usize) -> Result<Option<HoopAlongJson>> {
    let length = set.length();
    let along: Vec<HoopPointJson> = (0..7).filter_map(|k| hoop_point(set, length - 0.35 + 0.05 * k as f64)).collect();
    if along.is_empty() {
        return Ok(None);
    }
    let defaults = CollisionOptions::default();
    let options = CollisionOptions { modes: count.min(defaults.modes), ..defaults };
    let swing = super::inputs::default_swing(f64::NAN);
    let spots = sweet_spots(set, &Ball::game(), &swing, &options).context("sweet spot for the hoop frequency")?;
    Ok(Some(HoopAlongJson { along, sweet_spot: hoop_point(set, spots.max_exit_speed_z) }))
}

/// Computes the document for `sweetspot modes`.
pub fn modes_document(bat: &sweetspot_physics::Bat, count: usize) -> Result<ModesJson> {
    if !(1..=MAX_MODES).contains(&count) {
        bail!("--modes = {count} is out of range: expected 1 ≤ modes ≤ {MAX_MODES}");
    }
    let set = ModeSet::compute(bat, count).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
    let props = set.mass_properties();
    let modes = set
        .frequencies_hz()
        .into_iter()
        .take(count)
        .enumerate()
        .map(|(i, frequency_hz)| ModeJson {
            mode: i + 1,
            frequency_hz,
            nodes: set.nodes(i + 1),
            // ModeSet indexes all modes: 0 translation, 1 rotation, 2… vibrational.
            modal_mass: set.modal_mass(i + 2),
        })
        .collect();
    let hoop = hoop_along(&set, count)?;
    Ok(ModesJson { bat: BatJson::new(&bat.name, &props), modes, hoop })
}
