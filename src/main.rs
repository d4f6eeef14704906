//! The `turf` command line: parses arguments and hands over to the library.

mod cli;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// turf — mechanics of carbon-nanotube turfs, from tubes to nanoindentation.
#[derive(Parser)]
#[command(name = "turf", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run every stage a scene asks for and write the results.
    Run(cli::run::RunArgs),
    /// Validate a scene and print the plan; run nothing.
    Check(cli::run::CheckArgs),
    /// Assemble the folders of `turf run SCENE --shard I/N` into one output tree and summary.
    Merge(cli::merge::MergeArgs),
    /// Closed-form calculators (Hertz, JKR, DMT, Maugis–Dugdale, Tabor, ...).
    Theory(cli::theory::TheoryArgs),
    /// Fit a material card from a stress–strain curve or a tangent law.
    Homogenize(cli::homogenize::HomogenizeArgs),
    /// Fit K1, K2, eta of the seed's indentation law (2.1)-(2.7) to a force-controlled record.
    FitIndentation(cli::fit_indentation::FitIndentationArgs),
    /// The speed–accuracy ladder: each fidelity's answer, error and cost, and refinement sweeps.
    Bench(cli::bench::BenchArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(a) => cli::run::run(a),
        Command::Check(a) => cli::run::check(a),
        Command::Merge(a) => cli::merge::run(a),
        Command::Theory(a) => cli::theory::run(a),
        Command::Homogenize(a) => cli::homogenize::run(a),
        Command::FitIndentation(a) => cli::fit_indentation::run(a),
        Command::Bench(a) => cli::bench::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
