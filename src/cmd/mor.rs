//! `emdstar mor` (being implemented).

/// Arguments of `emdstar mor`.
#[derive(clap::Args)]
pub struct MorArgs {}

pub fn run(_args: &MorArgs) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
