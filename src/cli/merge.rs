//! `turf merge`: the folders of `turf run SCENE --shard I/N` assembled into the output tree
//! and summary of a serial run.

use clap::Args;
use std::path::PathBuf;
use turf::pipeline::RunOptions;

/// Arguments of `turf merge`.
#[derive(Args)]
pub struct MergeArgs {
    /// The shards' output folders, one per slice.
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// Output folder (default: runs/<scene name>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON and stay quiet otherwise.
    #[arg(long)]
    pub json: bool,
}

/// `turf merge`.
pub fn run(args: MergeArgs) -> anyhow::Result<()> {
    let opts = RunOptions::default();
    let report = turf::pipeline::shard::merge(&args.dirs, args.out.as_deref(), &opts)?;
    super::run::print_report(report, args.json)
}
