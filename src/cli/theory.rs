//! `turf theory`: closed-form calculators.

use clap::Args;

/// Arguments of `turf theory`.
#[derive(Args)]
pub struct TheoryArgs {}

/// `turf theory`.
pub fn run(_args: TheoryArgs) -> anyhow::Result<()> {
    anyhow::bail!("`turf theory` is not built yet")
}
