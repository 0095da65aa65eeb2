//! `sweetspot node`: arguments and runner (owned by the node work).

/// Arguments of `sweetspot node`.
#[derive(Debug, clap::Args)]
pub struct NodeArgs {}

/// Runs the node until SIGINT/SIGTERM.
pub fn run(_args: NodeArgs) -> anyhow::Result<()> {
    anyhow::bail!("sweetspot node is not built yet")
}
