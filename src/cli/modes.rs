//! `sweetspot modes`: mass properties and the vibrational modes of a bat, and for hollow bats the hoop
//! (n = 2 shell) frequency of the barrel wall along the barrel and at the sweet spot.

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;

use super::common::{emit, print_json, BatArgs, OutputArgs, SwingArgs, MAX_MODES};
use crate::physics::metrics::sweet_spots;
use crate::physics::{Ball, CollisionOptions, ModeSet};
use crate::report::json::BatJson;
use crate::report::table::{num, Table};

/// Arguments of `sweetspot modes`.
#[derive(Debug, Args)]
pub struct ModesArgs {
    #[command(flatten)]
    pub bat: BatArgs,
    /// Number of vibrational modes listed, 1..=200.
    #[arg(long, value_name = "N", default_value_t = 8)]
    pub modes: usize,
    #[command(flatten)]
    pub output: OutputArgs,
}

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
    let swing = SwingArgs::defaults().impact(f64::NAN);
    let spots = sweet_spots(set, &Ball::game(), &swing, &options).context("sweet spot for the hoop frequency")?;
    Ok(Some(HoopAlongJson { along, sweet_spot: hoop_point(set, spots.max_exit_speed_z) }))
}

/// Computes the document for `sweetspot modes`.
pub fn modes_document(bat: &crate::physics::Bat, count: usize) -> Result<ModesJson> {
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

/// Runs `sweetspot modes`.
pub fn run(args: ModesArgs) -> Result<()> {
    let bat = args.bat.load()?;
    let doc = modes_document(&bat, args.modes)?;
    if args.output.json {
        return print_json(&doc);
    }
    let mut out = doc.bat.table().render();
    out.push('\n');
    let mut t = Table::new(["n", "frequency (Hz)", "modal mass (kg)", "nodes (m from knob)"]);
    for m in &doc.modes {
        let nodes = m.nodes.iter().map(|z| num(*z, 4)).collect::<Vec<_>>().join(" ");
        t.row([m.mode.to_string(), num(m.frequency_hz, 5), num(m.modal_mass, 4), nodes]);
    }
    out.push_str(&t.render());
    if let Some(hoop) = &doc.hoop {
        out.push_str("\nhoop (n = 2) mode of the barrel wall\n");
        let mut t = Table::new(["z (m from knob)", "f_h (Hz)", "wall (mm)", "k_h (N/m)", "m_h (g)"]);
        let cells = |label: String, p: &HoopPointJson| {
            [
                label,
                num(p.frequency_hz, 5),
                num(p.wall_thickness * 1e3, 3),
                num(p.stiffness, 4),
                num(p.effective_mass * 1e3, 4),
            ]
        };
        for p in &hoop.along {
            t.row(cells(num(p.z, 4), p));
        }
        if let Some(p) = &hoop.sweet_spot {
            t.row(cells(format!("{} (sweet spot)", num(p.z, 4)), p));
        }
        out.push_str(&t.render());
    }
    emit(&out)
}
