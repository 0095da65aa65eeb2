//! `sweetspot pub` and `sweetspot echo` (owned by the msgs/DDS work).

/// Arguments of `sweetspot pub`.
#[derive(Debug, clap::Args)]
pub struct PubArgs {}

/// Arguments of `sweetspot echo`.
#[derive(Debug, clap::Args)]
pub struct EchoArgs {}

/// Publishes messages.
pub fn run_pub(_args: PubArgs) -> anyhow::Result<()> {
    anyhow::bail!("sweetspot pub is not built yet")
}

/// Prints what arrives on a topic.
pub fn run_echo(_args: EchoArgs) -> anyhow::Result<()> {
    anyhow::bail!("sweetspot echo is not built yet")
}
