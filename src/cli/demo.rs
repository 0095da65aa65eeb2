//! `sweetspot demo`: its arguments, checked and handed to [`crate::demo::run`].

use std::path::PathBuf;

use anyhow::{bail, Result};

use super::figures::FigureFormat;
use super::rig::RigOptions;
use crate::demo::DemoSettings;

/// Arguments of `sweetspot demo`.
#[derive(Debug, clap::Args)]
#[command(after_help = "Examples:
  cargo run --release -- demo
  sweetspot demo --swings 400 --true-cor 0.50     # then: sweetspot calibrate <the bag it prints>
  sweetspot demo --bats r161,aluminum --format svg --out /tmp/bags
  sweetspot demo --batter my-batter.toml          # each bat at this batter's equal-effort speed")]
pub struct DemoArgs {
    #[command(flatten)]
    pub rig: RigOptions,
    /// Swings in the session.
    #[arg(long, default_value_t = 200, value_name = "N")]
    pub swings: u64,
    /// Swings per second, at most 10000 (default: as fast as the node answers).
    #[arg(long, value_name = "HZ", value_parser = super::common::swing_rate_hz)]
    pub rate: Option<f64>,
    /// Directory the bag (and its figures) are written under.
    #[arg(long, default_value = "bags", value_name = "DIR")]
    pub out: PathBuf,
    /// Namespace of the demo's node and rig.
    #[arg(long, visible_alias = "ns", default_value = "/demo", value_name = "NS")]
    pub namespace: String,
    /// Figure format.
    #[arg(long, value_enum, default_value_t = FigureFormat::Png)]
    pub format: FigureFormat,
    /// Skip the figures.
    #[arg(long)]
    pub no_figures: bool,
    /// Use ROS_AUTOMATIC_DISCOVERY_RANGE from the environment instead of LOCALHOST (e.g. to watch the demo
    /// from Foxglove or `ros2 topic echo` on another machine).
    #[arg(long)]
    pub env_discovery: bool,
    /// Batter file (TOML, the format of `sweetspot compare --batter`) of the batter who swings every bat at
    /// equal effort [default: the Statcast-average batter with the r161, v ∝ I^(−0.25)].
    #[arg(long, value_name = "FILE")]
    pub batter: Option<PathBuf>,
    /// Swing every bat at the same bat speed (the `--bat-mph` range at the barrel) instead of at equal effort.
    #[arg(long, conflicts_with = "batter")]
    pub equal_bat_speed: bool,
    /// Seconds to wait for the node to start, and for any answer before giving up (inf: no limit).
    #[arg(long, default_value_t = 60.0, value_name = "S", value_parser = super::common::seconds_above_zero)]
    pub timeout: f64,
}

/// Runs `sweetspot demo`.
pub fn run(args: DemoArgs) -> Result<()> {
    if args.swings == 0 || args.swings > 1_000_000 {
        bail!("--swings must be between 1 and 1000000, got {}", args.swings);
    }
    let mut rig = args.rig.config()?;
    if !args.equal_bat_speed {
        let (batter, _) = match &args.batter {
            Some(path) => super::compare::load_batter_file(path)?,
            None => super::compare::batter_from_spec(&super::compare::BatterSpec::default(), None)?,
        };
        rig.batter = Some(batter);
    }
    // Before anything starts: the directory the session goes into is no input (the batter file).
    crate::files::refuse_clobber("--out", &args.out, &args.batter.iter().cloned().collect::<Vec<_>>(), &[])
        .map_err(anyhow::Error::msg)?;
    crate::demo::run(DemoSettings {
        rig,
        swings_per_bat: args.rig.swings_per_bat,
        swings: args.swings,
        rate: args.rate,
        out: args.out,
        namespace: args.namespace,
        figures: (!args.no_figures).then(|| args.format.into()),
        env_discovery: args.env_discovery,
        timeout: crate::model::time::saturating_secs(args.timeout),
    })
}
