//! `sweetspot bbcor`: the bat's BBCOR under the certification protocol implemented by the physics core.

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;

use super::common::{print_json, BatArgs, NumericArgs, OutputArgs};
use super::output::{num, BatJson, OptionsJson, Table};
use crate::physics::metrics::bbcor;
use crate::physics::ModeSet;

/// Arguments of `sweetspot bbcor`.
#[derive(Debug, Args)]
pub struct BbcorArgs {
    #[command(flatten)]
    pub bat: BatArgs,
    #[command(flatten)]
    pub numeric: NumericArgs,
    #[command(flatten)]
    pub output: OutputArgs,
}

/// The JSON document of `sweetspot bbcor --json`.
#[derive(Debug, Serialize)]
pub struct BbcorJson {
    /// The bat's mass properties.
    pub bat: BatJson,
    /// Numerical options.
    pub options: OptionsJson,
    /// BBCOR, dimensionless.
    pub bbcor: f64,
}

/// Computes the document for `sweetspot bbcor`.
pub fn bbcor_document(bat: &crate::physics::Bat, options: &crate::physics::CollisionOptions) -> Result<BbcorJson> {
    let modes = ModeSet::compute(bat, options.modes).with_context(|| format!("normal modes of bat '{}'", bat.name))?;
    let value = bbcor(&modes, options).context("BBCOR")?;
    Ok(BbcorJson { bat: BatJson::new(&bat.name, &modes.mass_properties()), options: options.into(), bbcor: value })
}

/// Runs `sweetspot bbcor`.
pub fn run(args: BbcorArgs) -> Result<()> {
    let bat = args.bat.load()?;
    let options = args.numeric.options()?;
    let doc = bbcor_document(&bat, &options)?;
    if args.output.json {
        return print_json(&doc);
    }
    print!("{}", doc.bat.table().render());
    println!();
    let mut t = Table::new(["metric", "value"]);
    t.row(["BBCOR".to_string(), num(doc.bbcor, 4)]);
    print!("{}", t.render());
    Ok(())
}
