//! `turf run` and `turf check`.

use clap::Args;
use std::io::IsTerminal;
use std::path::PathBuf;
use turf::pipeline::shard::Shard;
use turf::pipeline::{self, RunOptions, RunReport};
use turf::scene::plan::{sig, Plan};
use turf::scene::resources::{bytes_text, FE_BYTES_PER_ELEMENT};
use turf::scene::{self, Loaded, ResolvedScene};

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
    /// Continue an interrupted run from the checkpoint in the output folder (the discrete
    /// compression saves one after every strain step); same curve as an uninterrupted run.
    #[arg(long)]
    pub resume: bool,
    /// Run only the I-th of N slices of the scene's work items (sweep points × realisations),
    /// for a scheduler's job array; `turf merge` assembles the slices' folders.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
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
pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let loaded = scene::load(&args.scene, &args.set)?;
    let opts = RunOptions {
        out: args.out,
        progress: !args.json && std::io::stderr().is_terminal(),
        resume: args.resume,
    };
    if !opts.resume {
        let dir = scene::output_dir(&loaded.base, opts.out.as_deref());
        if let Some(note) = interrupted_run_note(&dir) {
            eprintln!(
                "note: {note}; `turf run {} --resume` continues it, this run starts over",
                args.scene.display()
            );
        }
    }
    // Ctrl-C / SIGTERM stop long stages at their next step, keeping what they reached
    turf::interrupt::install();
    if let Some(shard) = args.shard {
        let m = pipeline::shard::run_shard(&loaded, &args.scene, &args.set, shard, &opts)?;
        let dir = scene::output_dir(&loaded.base, opts.out.as_deref());
        let failed = m.outcomes.iter().filter(|o| o.error.is_some()).count();
        if args.json {
            println!("{}", serde_json::to_string_pretty(&m)?);
        } else {
            println!(
                "shard {}: {} of {} item(s) done ({failed} failed) in {}; `turf merge` \
                 assembles all {} shards",
                m.shard,
                m.outcomes.len(),
                m.items,
                dir.display(),
                shard.count
            );
        }
        if !m.complete {
            anyhow::bail!("shard {} stopped before its last item", m.shard);
        }
        return Ok(());
    }
    #[cfg(not(feature = "mpi"))]
    if let Some(ranks) = launched_ranks() {
        anyhow::bail!(
            "turf was started as one of {ranks} MPI ranks but built without the `mpi` feature: \
             each rank would run the whole scene into the same folder. Build with `cargo build \
             --release --features mpi` (docs/scaling.md), or run without mpirun"
        );
    }
    #[cfg(feature = "mpi")]
    if pipeline::mpi::launched() {
        return match pipeline::mpi::run(&loaded, &opts)? {
            Some(report) => print_report(report, args.json),
            None => Ok(()),
        };
    }
    print_report(pipeline::run(&loaded, &opts)?, args.json)
}

/// The ranks a launcher (`mpirun`, `srun` with PMI) started, when more than one.
#[cfg(not(feature = "mpi"))]
fn launched_ranks() -> Option<usize> {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]
        .iter()
        .find_map(|v| std::env::var(v).ok()?.parse::<usize>().ok())
        .filter(|&n| n > 1)
}

/// Print what a run did (every stage's time, evaluations and values, or the summary as JSON
/// with `json`); an error when it did not finish.
pub fn print_report(report: RunReport, json: bool) -> anyhow::Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(&report.summary)?);
    } else {
        for r in report.summary.stages.iter().chain(
            report
                .summary
                .sweep
                .iter()
                .flat_map(|s| s.points.iter().flat_map(|p| &p.stages)),
        ) {
            println!(
                "{:<11} {:>10.3} s  {:>10} evaluations",
                r.stage.name(),
                r.wall_time_s,
                r.evaluations
            );
            for (k, v) in &r.values {
                println!("    {k} = {v}");
            }
        }
    }
    let summary = report.out_dir.join("summary.json");
    let error = report.failure.map(|e| e.to_string());
    match error.or(report.summary.error) {
        None => {
            if !json {
                println!("results in {}", report.out_dir.display());
            }
            Ok(())
        }
        Some(e) => Err(anyhow::anyhow!(
            "{e} (what finished is in {})",
            summary.display()
        )),
    }
}

/// Whether `dir` holds the checkpoint of a discrete compression that did not finish (no
/// summary, or one that is not `complete` and records no finished `discrete` stage): a plain
/// re-run starts over, and the user should know `--resume` exists. A run whose discrete stage
/// finished and a later stage failed keeps its checkpoint as one of that stage's files; a
/// re-run reuses the stage from the cache, so there is nothing to resume.
fn interrupted_run_note(dir: &std::path::Path) -> Option<String> {
    if !dir.join(pipeline::CHECKPOINT).is_file() {
        return None;
    }
    let summary = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    let finished = summary.is_some_and(|v| {
        v["complete"].as_bool() == Some(true)
            || v["stages"]
                .as_array()
                .is_some_and(|s| s.iter().any(|r| r["stage"] == "discrete"))
    });
    (!finished).then(|| {
        format!(
            "{} holds the checkpoint of an interrupted run ({})",
            dir.display(),
            pipeline::CHECKPOINT
        )
    })
}

/// `turf check`.
pub fn check(args: CheckArgs) -> anyhow::Result<()> {
    let loaded = match scene::load(&args.scene, &args.set) {
        Ok(l) => l,
        Err(e) if args.json => {
            println!(
                "{}",
                serde_json::to_string_pretty(&error_json(&args.scene, &e))?
            );
            return Err(e.into());
        }
        Err(e) => return Err(e.into()),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&check_json(&loaded))?);
    } else {
        print!("{}", check_text(&loaded));
    }
    Ok(())
}

/// `turf check --json` of a refused scene: `valid: false`, the error and, for invalid keys,
/// each problem with its key, line and message.
fn error_json(file: &std::path::Path, e: &scene::SceneError) -> serde_json::Value {
    let problems: Vec<_> = e
        .problems()
        .iter()
        .map(|p| {
            serde_json::json!({
                "key": p.key,
                "line": p.line,
                "from_command_line": p.is_from_command_line,
                "message": p.message,
            })
        })
        .collect();
    let mut error = e.to_string();
    let mut source = std::error::Error::source(e);
    while let Some(s) = source {
        error.push_str(&format!(": {s}"));
        source = s.source();
    }
    serde_json::json!({
        "file": file.display().to_string(),
        "valid": false,
        "error": error,
        "problems": problems,
    })
}

fn check_json(loaded: &Loaded) -> serde_json::Value {
    let b = &loaded.base;
    let mut v = serde_json::json!({
        "valid": true,
        "file": b.file.display().to_string(),
        "name": b.name(),
        "output": scene::output_dir(b, None).display().to_string(),
        "plan": b.plan,
        "derived": b.derived,
        "scene": b.scene,
    });
    match pipeline::mesh_preview(b) {
        Some(Ok(m)) => v["fe_mesh"] = serde_json::json!(m),
        Some(Err(e)) => v["fe_mesh_error"] = serde_json::json!(e),
        None => {}
    }
    if !loaded.sweep.is_empty() {
        v["sweep"] = serde_json::json!(loaded
            .sweep
            .iter()
            .map(|p| serde_json::json!({"value": p.value, "plan": p.scene.plan, "derived": p.scene.derived}))
            .collect::<Vec<_>>());
    }
    v
}

fn check_text(loaded: &Loaded) -> String {
    let b = &loaded.base;
    let mut s = format!("scene '{}' ({}) is valid\n", b.name(), b.file.display());
    if !b.scene.scene.description.is_empty() {
        s.push_str(&format!("  {}\n", b.scene.scene.description));
    }
    s.push_str(&format!(
        "output: {}\n",
        scene::output_dir(b, None).display()
    ));
    s.push_str(&plan_text(&b.plan));
    s.push_str(&memory_text(&b.plan));
    s.push_str(&mesh_text(b));
    if let Some(sw) = &b.scene.sweep {
        s.push_str(&format!(
            "\nsweep over {} ({} values):\n",
            sw.key,
            loaded.sweep.len()
        ));
        for p in &loaded.sweep {
            s.push_str(&format!(
                "  {} = {}{}\n",
                sw.key,
                p.value,
                headline(&p.scene)
            ));
        }
    }
    s.push_str("\nnothing was run (turf run runs the stages)\n");
    s
}

/// Each sized stage's memory estimate against the ceiling.
fn memory_text(plan: &Plan) -> String {
    let Some(m) = &plan.memory else {
        return String::new();
    };
    let mut s = format!(
        "\nmemory (estimates; ceiling {}, {}):\n",
        bytes_text(m.ceiling.bytes),
        m.ceiling.source
    );
    for st in &m.stages {
        s.push_str(&format!(
            "  {:<11} {:>12}   {}\n",
            st.stage.name(),
            bytes_text(st.bytes),
            st.detail
        ));
    }
    s
}

/// The FE mesh the run would build: process zone, smallest element and element count.
fn mesh_text(scene: &ResolvedScene) -> String {
    match pipeline::mesh_preview(scene) {
        None => String::new(),
        Some(Err(e)) => format!("\nFE mesh: would be refused: {e}\n"),
        Some(Ok(m)) => {
            let zone = m.process_zone_nm.map_or(String::new(), |l| {
                format!(
                    "process zone ℓ = {} nm, smallest element {} nm (ℓ/{:.1}), ",
                    sig(l),
                    sig(m.smallest_nm),
                    l / m.smallest_nm
                )
            });
            let kind = m.adaptive_band_nm.map_or(String::new(), |w| {
                format!(
                    "adaptive: a band ±{} nm about the contact edge follows it (mesh.adaptive), first mesh ",
                    sig(w)
                )
            });
            format!(
                "\nFE mesh: {zone}{kind}{} elements, {} nodes (contact radius {} nm), about {} in the solve\n",
                m.elements,
                m.nodes,
                sig(m.contact_radius_nm),
                bytes_text(m.elements as f64 * FE_BYTES_PER_ELEMENT)
            )
        }
    }
}

fn headline(scene: &ResolvedScene) -> String {
    match scene.derived.tabor_mu {
        Some(mu) => format!("  (Tabor μ = {mu:.4})"),
        None => String::new(),
    }
}

fn plan_text(plan: &Plan) -> String {
    let mut s = String::from("\nstages, in order:\n");
    for (i, st) in plan.stages.iter().enumerate() {
        s.push_str(&format!(
            "  {}. {:<11} {}\n",
            i + 1,
            st.stage.name(),
            st.why
        ));
    }
    s.push_str("\nphysics:\n");
    for sw in &plan.physics {
        s.push_str(&format!(
            "  [{}] {:<18} {}\n",
            if sw.on { "on " } else { "off" },
            sw.name,
            sw.detail
        ));
    }
    s.push_str("\nresolved values (internal units):\n");
    for v in &plan.values {
        let unit = if v.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", v.unit)
        };
        let note = if v.note.is_empty() {
            String::new()
        } else {
            format!("   ({})", v.note)
        };
        s.push_str(&format!("  {:<26} = {:.6e}{unit}{note}\n", v.key, v.value));
    }
    s
}
