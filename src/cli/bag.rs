//! `sweetspot bag …` (owned by the bag work).

/// The `bag` subcommands.
#[derive(Debug, clap::Subcommand)]
pub enum BagCommand {
    /// Topics, types, counts, duration and size of a bag.
    Info { path: std::path::PathBuf },
}

/// Runs one `bag` subcommand.
pub fn run(_cmd: BagCommand) -> anyhow::Result<()> {
    anyhow::bail!("sweetspot bag is not built yet")
}
