//! `turf fit-indentation`: K₁, K₂, η of the seed's indentation law from a measured record.

use clap::Args;
use std::path::PathBuf;
use turf::experiment::{self, indentation_fit::Machine};
use turf::units::{parse_quantity, Dimension};

/// Arguments of `turf fit-indentation`.
#[derive(Args)]
pub struct FitIndentationArgs {
    /// The record: CSV (time_s, load_uN|load_nN|load_mN, depth_nm) or a nanoindenter text
    /// export (tab-separated "Depth (nm)", "Load (µN)", "Time (s)"); see docs/fit-indentation.md.
    pub data: PathBuf,
    /// Support springs k1 of the transducer, e.g. "200 N/m" (default 0: the record's load
    /// reaches the specimen).
    #[arg(long, value_name = "STIFFNESS")]
    pub k1: Option<String>,
    /// Load-frame spring k2 in series with the specimen, e.g. "1e6 N/m" (default: rigid).
    #[arg(long, value_name = "STIFFNESS")]
    pub k2: Option<String>,
    /// Output folder (default runs/fit_<file stem>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print fit.json and stay quiet otherwise.
    #[arg(long)]
    pub json: bool,
}

/// `turf fit-indentation`.
pub fn run(args: FitIndentationArgs) -> anyhow::Result<()> {
    let stiffness = |flag: &str, v: &Option<String>| -> anyhow::Result<Option<f64>> {
        v.as_deref()
            .map(|s| {
                parse_quantity(s, Dimension::Stiffness).map_err(|e| anyhow::anyhow!("{flag}: {e}"))
            })
            .transpose()
    };
    let machine = Machine {
        k1: stiffness("--k1", &args.k1)?.unwrap_or(0.0),
        k2: stiffness("--k2", &args.k2)?,
    };
    let record = experiment::read_record(&args.data)?;
    let fit = experiment::indentation_fit::fit(&record, &machine)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.data.display()))?;
    let dir = args
        .out
        .unwrap_or_else(|| experiment::default_out_dir(&args.data));
    let summary = experiment::write_outputs(&args.data, &record, &fit, &dir)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return Ok(());
    }
    let se = |f: fn(&experiment::indentation_fit::Specimen) -> f64| {
        fit.std_errors
            .as_ref()
            .map_or(String::new(), |s| format!(" ± {:.3e}", f(s)))
    };
    let sp = &fit.specimen;
    println!(
        "{} samples ({:?}); machine k1 = {} nN/nm, k2 = {} (chi = {:.6e} nN/nm)",
        fit.samples,
        record.format,
        machine.k1,
        machine.k2.map_or("rigid".into(), |k| format!("{k} nN/nm")),
        fit.chi
    );
    println!("K1  = {:.6e}{} nN/nm", sp.k1, se(|s| s.k1));
    println!("K2  = {:.6e}{} nN/nm", sp.k2, se(|s| s.k2));
    println!("eta = {:.6e}{} nN*s/nm", sp.eta, se(|s| s.eta));
    println!(
        "tau = {:.6e}{} s (seed 2.5)",
        fit.tau_s,
        fit.tau_std_error_s
            .map_or(String::new(), |s| format!(" ± {s:.3e}"))
    );
    println!(
        "rms residual = {:.4e} nm, R^2 = {:.8}; {} of {} starts converged, {} evaluations",
        fit.rms_residual_nm, fit.r_squared, fit.converged_starts, fit.starts, fit.evaluations
    );
    for (name, check, what) in [
        ("initial loading slope", &fit.initial_slope, "K1 (2.7)"),
        ("hold slope", &fit.hold_slope, "-chi (2.6)"),
    ] {
        match check {
            Some(c) => println!(
                "{name} dQ/d(delta) = {:.6e} nN/nm (fitted curve {:.6e}; {what} = {:.6e}) over {} samples from {}",
                c.measured,
                c.fitted_curve,
                c.seed_value,
                c.samples,
                c.first_sample
            ),
            None => println!("{name}: no window found in the record"),
        }
    }
    for w in &fit.warnings {
        println!("warning: {w}");
    }
    println!("wrote {}", dir.display());
    Ok(())
}
