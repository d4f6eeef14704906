//! `turf homogenize`: material cards from curves or tangent laws.

use clap::Args;

/// Arguments of `turf homogenize`.
#[derive(Args)]
pub struct HomogenizeArgs {}

/// `turf homogenize`.
pub fn run(_args: HomogenizeArgs) -> anyhow::Result<()> {
    anyhow::bail!("`turf homogenize` is not built yet")
}
