//! `turf run` and `turf check`.

use clap::Args;
use std::path::PathBuf;

/// Arguments of `turf run`.
#[derive(Args)]
pub struct RunArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Output folder (default: runs/<scene name>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON and stay quiet otherwise.
    #[arg(long)]
    pub json: bool,
    /// Override a scene key, e.g. --set adhesion.gamma="0.2 J/m^2" (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// Arguments of `turf check`.
#[derive(Args)]
pub struct CheckArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Print the plan as JSON.
    #[arg(long)]
    pub json: bool,
    /// Override a scene key (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// `turf run`.
pub fn run(_args: RunArgs) -> anyhow::Result<()> {
    anyhow::bail!("`turf run` is not built yet")
}

/// `turf check`.
pub fn check(_args: CheckArgs) -> anyhow::Result<()> {
    anyhow::bail!("`turf check` is not built yet")
}
