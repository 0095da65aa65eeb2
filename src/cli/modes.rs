//! `sweetspot modes`: mass properties and the vibrational modes of a bat, and for hollow bats the hoop
//! (n = 2 shell) frequency of the barrel wall along the barrel and at the sweet spot.

pub use crate::answer::modes::*;
use anyhow::Result;
use clap::Args;

use super::common::{emit, print_json, BatArgs, OutputArgs};
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
