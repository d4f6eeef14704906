//! `turf bench`: the speed–accuracy ladder and refinement sweeps, written as
//! `bench.json`, `bench.md` and `plots/*.svg|png` in the output folder.

use clap::Args;
use std::io::IsTerminal;
use std::path::PathBuf;
use turf::bench::{self, BenchOptions};

/// Arguments of `turf bench`.
#[derive(Args)]
pub struct BenchArgs {
    /// Skip the FE pull-offs at μ = 2, the turf chain and the finest sweep points (about a
    /// minute in release instead of several).
    #[arg(long)]
    pub quick: bool,
    /// Also run the turf indentation rung: a 1 µm turf (≈ 100 tubes) indented by a sphere
    /// discretely (four turfs) and through the cards fitted to its RVE tests, with tips
    /// sliding, held, and held by an adhesive sphere (loads and pull-off)
    /// (scenes/turf_sphere.toml; ≈ 55 min cold, its discrete stages cached under the output
    /// folder for re-runs: docs/benchmarks.md "Turf indentation rung").
    #[arg(long)]
    pub turf_indent: bool,
    /// Output folder (default runs/bench).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the report as JSON on stdout (no progress bar, no table).
    #[arg(long)]
    pub json: bool,
}

/// Run the bench, write its files, print the table (or the JSON).
pub fn run(args: BenchArgs) -> anyhow::Result<()> {
    let out = args.out.unwrap_or_else(|| PathBuf::from("runs/bench"));
    let opts = BenchOptions {
        quick: args.quick,
        out: out.clone(),
        turf_indent: args.turf_indent,
    };
    let bar = (!args.json && std::io::stderr().is_terminal())
        .then(|| turf::pipeline::progress_bar(bench::task_count(&opts) as u64, "tasks"));
    let report = bench::run(&opts, &mut |name| {
        if let Some(b) = &bar {
            if !b.message().is_empty() {
                b.inc(1);
            }
            b.set_message(name.to_string());
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    bench::write(&report, &out)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!("{}", report.to_markdown());
        eprintln!("written to {}", out.display());
    }
    Ok(())
}
