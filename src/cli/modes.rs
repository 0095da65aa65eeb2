//! `sweetspot modes`: mass properties and the vibrational modes of a bat.

use anyhow::{bail, Context, Result};
use clap::Args;
use serde::Serialize;

use super::common::{emit, print_json, BatArgs, OutputArgs, MAX_MODES};
use crate::physics::ModeSet;
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

/// The JSON document of `sweetspot modes --json`.
#[derive(Debug, Serialize)]
pub struct ModesJson {
    /// Mass properties of the discretised bat.
    pub bat: BatJson,
    /// Vibrational modes, ascending frequency (the two rigid-body modes are not listed).
    pub modes: Vec<ModeJson>,
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
    Ok(ModesJson { bat: BatJson::new(&bat.name, &props), modes })
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
    emit(&out)
}
