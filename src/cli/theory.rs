//! `turf theory`: closed-form calculators (Hertz, JKR, DMT, Maugis–Dugdale, Tabor, thermal
//! amplitude, micromechanics, the quasi-rheological indentation law, surface laws).
//!
//! Every quantity flag takes a unit string (`--radius "1.8 um"`, `--modulus "1 GPa"`); a bare
//! number is in internal units (nm, nN, s, GPa, J/m²). `--json` prints the result as JSON on
//! stdout; otherwise a short human summary is printed.

use super::theory_law::LawName;
use anyhow::{bail, Context};
use clap::{Args, Subcommand, ValueEnum};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use turf::laws::{LennardJones, LjKind, SurfaceLaw};
use turf::report::csv::Table;
use turf::report::plot::{Plot, Series};
use turf::theory::indentation_law::{Rheology, Segment};
use turf::theory::micromech::{Segments, ShapeFactor};
use turf::theory::thermal::Cantilever;
use turf::theory::{self, dmt, hertz, jkr, positive, tabor, Control, Model, Sphere};
use turf::units::{parse_quantity, Dimension};

/// Arguments of `turf theory`.
#[derive(Args)]
pub struct TheoryArgs {
    #[command(subcommand)]
    command: TheoryCommand,
}

#[derive(Subcommand)]
enum TheoryCommand {
    /// Normalised pull-off P/(πγR) of JKR, DMT or Maugis–Dugdale.
    Pulloff(PulloffArgs),
    /// Load–approach–contact-radius curve of a sphere: CSV and plot.
    Curve(CurveArgs),
    /// Tabor's μ and Maugis' λ of a sphere and a Lennard-Jones law.
    Tabor(TaborArgs),
    /// RMS thermal amplitude of a free tube end (seed 5.9).
    Thermal(ThermalArgs),
    /// Stress and energy of the bent-segment micromechanical model (seed 2.8–2.14).
    Micromech(MicromechArgs),
    /// The quasi-rheological indentation law under a load–hold–unload schedule (seed 2.1–2.7).
    IndentationLaw(IndentationLawArgs),
    /// Pull-off of an elastic half-space with LJ tractions (numerical, small strain), with its
    /// grid-refinement error estimate and cost.
    Halfspace(HalfspaceArgs),
    /// A surface law, plain or thermally shifted (seed §5.2): stretch, peak tension, range,
    /// process zone; p(h) as CSV and plot with --out (the seed's Fig 5.3).
    Law(super::theory_law::LawArgs),
}

#[derive(Args)]
struct HalfspaceArgs {
    /// Tabor's μ = (Rγ²/(E*² z₀³))^(1/3)
    #[arg(long)]
    mu: String,
    /// the surface law
    #[arg(long, value_enum, default_value = "lj93")]
    law: LawName,
    /// print JSON
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum ModelName {
    Hertz,
    Jkr,
    Dmt,
    Maugis,
}

#[derive(Clone, Copy, ValueEnum)]
enum ControlName {
    Load,
    Displacement,
}

impl From<ControlName> for Control {
    fn from(c: ControlName) -> Control {
        match c {
            ControlName::Load => Control::Load,
            ControlName::Displacement => Control::Displacement,
        }
    }
}

#[derive(Args)]
struct PulloffArgs {
    /// jkr, dmt or maugis
    #[arg(long, value_enum)]
    model: ModelName,
    /// Maugis' λ (maugis only)
    #[arg(long, conflicts_with = "mu")]
    lambda: Option<String>,
    /// Tabor's μ, converted to λ = 1.157 μ through the LJ 9-3 law's σ₀ (maugis only)
    #[arg(long)]
    mu: Option<String>,
    /// load (pull-off at min P) or displacement (jump-off where dδ/da = 0)
    #[arg(long, value_enum, default_value = "load")]
    control: ControlName,
    /// print JSON
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct CurveArgs {
    /// hertz, jkr, dmt or maugis
    #[arg(long, value_enum)]
    model: ModelName,
    /// sphere radius R (effective), e.g. "1.8 um"
    #[arg(long)]
    radius: String,
    /// plane-strain modulus E*, e.g. "1 GPa"
    #[arg(long)]
    modulus: String,
    /// work of adhesion γ, e.g. "0.46 J/m^2" (all but hertz)
    #[arg(long)]
    gamma: Option<String>,
    /// Maugis' λ (maugis; or give --z0)
    #[arg(long, conflicts_with = "z0")]
    lambda: Option<String>,
    /// equilibrium separation z₀ of the LJ law giving σ₀ (maugis)
    #[arg(long)]
    z0: Option<String>,
    /// the LJ law used with --z0
    #[arg(long, value_enum, default_value = "lj93")]
    law: LawName,
    /// largest contact radius (default 3 in ā, or R/10 for hertz)
    #[arg(long)]
    a_max: Option<String>,
    /// number of points, 2 to 10⁷
    #[arg(long, default_value_t = 200)]
    points: usize,
    /// output folder (curve.csv, plots/curve.svg, plots/curve.png)
    #[arg(long)]
    out: PathBuf,
    /// print a JSON summary
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct TaborArgs {
    /// sphere radius R
    #[arg(long)]
    radius: String,
    /// plane-strain modulus E*
    #[arg(long)]
    modulus: String,
    /// work of adhesion γ
    #[arg(long)]
    gamma: String,
    /// equilibrium separation z₀
    #[arg(long)]
    z0: String,
    /// the law whose maximum tension is Maugis' σ₀
    #[arg(long, value_enum, default_value = "lj93")]
    law: LawName,
    /// print JSON
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct ThermalArgs {
    /// free tube length l, e.g. "7 um"
    #[arg(long)]
    length: String,
    /// outer radius r_o
    #[arg(long)]
    ro: String,
    /// inner radius r_i
    #[arg(long)]
    ri: String,
    /// Young's modulus of the tube Y, e.g. "0.4 TPa"
    #[arg(long)]
    youngs: String,
    /// temperature, e.g. "300 K"
    #[arg(long, default_value = "300 K")]
    temperature: String,
    /// print JSON
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct MicromechArgs {
    /// n: free segments per unit volume, in 1/nm³ (a bare number)
    #[arg(long)]
    density: String,
    /// l: free segment length
    #[arg(long)]
    free_length: String,
    /// a: contact patch length
    #[arg(long)]
    contact_length: String,
    /// K = Y·I: tube bending stiffness, e.g. "2.21e-20 N*m^2"
    #[arg(long)]
    bending_stiffness: String,
    /// γ_L: contact energy per unit length, e.g. "1 nJ/m"
    #[arg(long)]
    line_energy: String,
    /// 1/κ: radius of curvature of the free segments (κ₀ for the threshold σ₀)
    #[arg(long)]
    radius_of_curvature: String,
    /// θ of the segment geometry (rad), 0 ≤ θ < atan(a/l)
    #[arg(long)]
    theta: String,
    /// print JSON
    #[arg(long)]
    json: bool,
}

#[derive(Args)]
struct IndentationLawArgs {
    /// k₁: transducer support springs, e.g. "200 N/m"
    #[arg(long)]
    machine_k1: String,
    /// k₂: load-frame spring
    #[arg(long)]
    machine_k2: String,
    /// K₁: specimen instantaneous spring
    #[arg(long)]
    specimen_k1: String,
    /// K₂: specimen Kelvin spring
    #[arg(long)]
    specimen_k2: String,
    /// η: specimen dashpot, e.g. "1 uN*s/nm"
    #[arg(long)]
    viscosity: String,
    /// peak applied force, e.g. "10 uN"
    #[arg(long)]
    peak: String,
    /// duration of the loading ramp
    #[arg(long)]
    load_time: String,
    /// duration of the hold at the peak
    #[arg(long)]
    hold_time: String,
    /// duration of the unloading ramp
    #[arg(long)]
    unload_time: String,
    /// samples per segment, 1 to 10⁷
    #[arg(long, default_value_t = 100)]
    samples: usize,
    /// output folder (indentation_law.csv)
    #[arg(long)]
    out: PathBuf,
    /// print a JSON summary
    #[arg(long)]
    json: bool,
}

/// `turf theory`.
pub fn run(args: TheoryArgs) -> anyhow::Result<()> {
    let (value, json) = match args.command {
        TheoryCommand::Pulloff(a) => (pulloff(&a)?, a.json),
        TheoryCommand::Curve(a) => (curve(&a)?, a.json),
        TheoryCommand::Tabor(a) => (tabor_cmd(&a)?, a.json),
        TheoryCommand::Thermal(a) => (thermal(&a)?, a.json),
        TheoryCommand::Micromech(a) => (micromech(&a)?, a.json),
        TheoryCommand::IndentationLaw(a) => (indentation_law(&a)?, a.json),
        TheoryCommand::Halfspace(a) => (halfspace(&a)?, a.json),
        TheoryCommand::Law(a) => (super::theory_law::law(&a)?, a.json),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&value)?);
    } else if let Value::Object(map) = value {
        for (k, v) in map {
            println!("{k:>24} = {v}");
        }
    }
    Ok(())
}

/// Parse `text` given to `--flag` as a quantity of dimension `dim`, in internal units.
fn quantity(flag: &str, text: &str, dim: Dimension) -> anyhow::Result<f64> {
    parse_quantity(text, dim).with_context(|| format!("--{flag}: expected {dim}"))
}

fn sphere(radius: &str, modulus: &str, gamma: f64) -> anyhow::Result<Sphere> {
    Ok(Sphere::new(
        quantity("radius", radius, Dimension::Length)?,
        quantity("modulus", modulus, Dimension::Pressure)?,
        gamma,
    )?)
}

fn pulloff(a: &PulloffArgs) -> anyhow::Result<Value> {
    let control = Control::from(a.control);
    let (name, model, lambda, mu) = match a.model {
        ModelName::Jkr => ("jkr", Model::Jkr, None, None),
        ModelName::Dmt => ("dmt", Model::Dmt, None, None),
        ModelName::Hertz => {
            bail!("--model hertz has no adhesion and no pull-off; use jkr, dmt or maugis")
        }
        ModelName::Maugis => {
            let per_mu = tabor::lambda_per_mu(LjKind::Lj93);
            let (lambda, mu) = match (&a.lambda, &a.mu) {
                (Some(l), _) => {
                    let l = positive("λ", quantity("lambda", l, Dimension::Dimensionless)?)?;
                    (l, l / per_mu)
                }
                (None, Some(m)) => {
                    let m = positive("μ", quantity("mu", m, Dimension::Dimensionless)?)?;
                    (m * per_mu, m)
                }
                (None, None) => bail!("--model maugis needs --lambda or --mu"),
            };
            ("maugis", Model::Maugis { lambda }, Some(lambda), Some(mu))
        }
    };
    let p = model.pull_off(control)?;
    Ok(json!({
        "model": name,
        "control": match control { Control::Load => "load", Control::Displacement => "displacement" },
        "lambda": lambda,
        "mu": mu,
        "pull_off_normalized": p,
    }))
}

fn halfspace(a: &HalfspaceArgs) -> anyhow::Result<Value> {
    let mu = positive("μ", quantity("mu", &a.mu, Dimension::Dimensionless)?)?;
    let kind = LjKind::from(a.law);
    let problem = turf::halfspace::Problem::scaled(mu, kind)?;
    let p = turf::halfspace::pull_off(&problem, &turf::halfspace::HalfspaceParams::default())
        .context("half-space pull-off")?;
    let levels: Vec<Value> = p
        .levels
        .iter()
        .map(|l| json!({"nodes": l.nodes, "pull_off_normalized": l.pull_off, "wall_time_s": l.wall_time}))
        .collect();
    let jump = |p: Option<turf::halfspace::CurvePoint>| {
        p.map(|p| json!({"load_normalized": p.load, "approach_z0": p.approach, "contact_radius_scaled": p.contact_radius}))
    };
    Ok(json!({
        "model": "halfspace",
        "law": match kind { LjKind::Lj93 => "lj93", LjKind::Lj104 => "lj104" },
        "mu": mu,
        "lambda": mu * tabor::lambda_per_mu(kind),
        "pull_off_normalized": p.normalized,
        "error_estimate": p.error_estimate,
        "contact_radius_scaled": p.contact_radius,
        "jump_in": jump(p.jump_in),
        "jump_out": jump(p.jump_out),
        "levels": levels,
        "cost": {
            "newton_iterations": p.cost.newton_iterations,
            "solves": p.cost.solves,
            "max_nodes": p.cost.max_nodes,
            "wall_time_s": p.cost.wall_time,
        },
    }))
}

fn curve(a: &CurveArgs) -> anyhow::Result<Value> {
    super::bounded_count("points", a.points, 2)?;
    let gamma = match (&a.gamma, a.model) {
        (Some(g), _) => Some(positive(
            "γ",
            quantity("gamma", g, Dimension::SurfaceEnergy)?,
        )?),
        (None, ModelName::Hertz) => None,
        (None, _) => bail!("--gamma is needed for an adhesive model"),
    };
    // Hertz without γ: any positive γ only sets the (unused) normalisation
    let s = sphere(&a.radius, &a.modulus, gamma.unwrap_or(1.0))?;
    let sc = s.scales();
    let (name, model, lambda) = match a.model {
        ModelName::Hertz => ("hertz", Model::Hertz, None),
        ModelName::Jkr => ("jkr", Model::Jkr, None),
        ModelName::Dmt => ("dmt", Model::Dmt, None),
        ModelName::Maugis => {
            let lambda = match (&a.lambda, &a.z0) {
                (Some(l), _) => positive("λ", quantity("lambda", l, Dimension::Dimensionless)?)?,
                (None, Some(z)) => {
                    let z0 = positive("z₀", quantity("z0", z, Dimension::Length)?)?;
                    let law = SurfaceLaw::from(LennardJones::new(a.law.into(), s.gamma, z0));
                    tabor::lambda_from_law(&s, &law)?
                }
                (None, None) => bail!("--model maugis needs --lambda or --z0"),
            };
            ("maugis", Model::Maugis { lambda }, Some(lambda))
        }
    };
    let a_max = match &a.a_max {
        Some(t) => positive("a_max", quantity("a-max", t, Dimension::Length)?)?,
        None if gamma.is_none() => 0.1 * s.radius,
        None => 3.0 * sc.length,
    };
    let n = a.points;
    // quadratic spacing resolves the steep small-a end of the adhesive curves
    let radii: Vec<f64> = (1..=n)
        .map(|i| a_max * (i as f64 / n as f64).powi(2))
        .collect();
    let (mut depth, mut load, mut ab, mut pb, mut db) = (vec![], vec![], vec![], vec![], vec![]);
    for &r in &radii {
        let (d, p, norm) = match model {
            Model::Hertz => (
                hertz::depth(r, s.radius),
                hertz::load(r, s.radius, s.modulus),
                hertz::normalized(r / sc.length),
            ),
            Model::Jkr => (
                jkr::depth(&s, r),
                jkr::load(&s, r),
                jkr::normalized(r / sc.length),
            ),
            Model::Dmt => (
                hertz::depth(r, s.radius),
                dmt::load(&s, r),
                dmt::normalized(r / sc.length),
            ),
            Model::Maugis { .. } => {
                let pt = model.point(r / sc.length)?;
                (pt.delta_bar * sc.depth, pt.p_bar * sc.force, pt)
            }
        };
        depth.push(d);
        load.push(p);
        ab.push(norm.a_bar);
        pb.push(norm.p_bar);
        db.push(norm.delta_bar);
    }
    let mut table = Table::new()
        .column("depth_nm", depth.clone())
        .column("load_nN", load.clone())
        .column("contact_radius_nm", radii);
    if gamma.is_some() {
        table = table
            .column("a_bar", ab)
            .column("p_bar", pb)
            .column("delta_bar", db);
    }
    let csv = a.out.join("curve.csv");
    table.write(&csv)?;
    Plot::new(
        &format!("{name}: load against approach"),
        "depth (nm)",
        "load (nN)",
    )
    .with(Series::line(name, depth, load))
    .write(&a.out.join("plots"), "curve")?;
    let pull_off = match model {
        Model::Hertz => None,
        m => Some(m.pull_off(Control::Load)?),
    };
    Ok(json!({
        "model": name,
        "lambda": lambda,
        "points": n,
        "csv": path_str(&csv),
        "pull_off_normalized": pull_off,
        "pull_off_load_nN": pull_off.map(|p| p * sc.force),
    }))
}

fn path_str(p: &Path) -> String {
    p.display().to_string()
}

fn tabor_cmd(a: &TaborArgs) -> anyhow::Result<Value> {
    let gamma = quantity("gamma", &a.gamma, Dimension::SurfaceEnergy)?;
    let s = sphere(&a.radius, &a.modulus, gamma)?;
    let z0 = positive("z₀", quantity("z0", &a.z0, Dimension::Length)?)?;
    let kind = LjKind::from(a.law);
    let law = SurfaceLaw::from(LennardJones::new(kind, s.gamma, z0));
    Ok(json!({
        "law": match kind { LjKind::Lj93 => "lj93", LjKind::Lj104 => "lj104" },
        "mu": tabor::tabor_mu(&s, z0)?,
        "lambda": tabor::lambda_from_law(&s, &law)?,
        "sigma0_GPa": law.max_tension(),
    }))
}

fn thermal(a: &ThermalArgs) -> anyhow::Result<Value> {
    let c = Cantilever {
        length: quantity("length", &a.length, Dimension::Length)?,
        r_outer: quantity("ro", &a.ro, Dimension::Length)?,
        r_inner: quantity("ri", &a.ri, Dimension::Length)?,
        youngs: quantity("youngs", &a.youngs, Dimension::Pressure)?,
    };
    let t = quantity("temperature", &a.temperature, Dimension::Temperature)?;
    let u = c.rms_tip_amplitude(t).with_context(|| {
        format!(
            "--length {}, --ro {}, --ri {}, --youngs {}, --temperature {}",
            a.length, a.ro, a.ri, a.youngs, a.temperature
        )
    })?;
    let k = c.bending_stiffness();
    if !k.is_finite() {
        bail!(
            "bending stiffness Y·π(r_o⁴ − r_i⁴)/4 = {k} is not finite for --ro {}, --ri {}, \
             --youngs {}: the inputs overflow double precision",
            a.ro,
            a.ri,
            a.youngs
        );
    }
    Ok(json!({
        "u_rms_nm": u,
        "bending_stiffness_nN_nm2": k,
    }))
}

fn micromech(a: &MicromechArgs) -> anyhow::Result<Value> {
    let seg = Segments {
        number_density: quantity("density", &a.density, Dimension::Dimensionless)?,
        free_length: quantity("free-length", &a.free_length, Dimension::Length)?,
        contact_length: quantity("contact-length", &a.contact_length, Dimension::Length)?,
        bending_stiffness: quantity(
            "bending-stiffness",
            &a.bending_stiffness,
            Dimension::BendingStiffness,
        )?,
        line_energy: quantity("line-energy", &a.line_energy, Dimension::LineEnergy)?,
    };
    let kappa = 1.0
        / positive(
            "radius of curvature",
            quantity(
                "radius-of-curvature",
                &a.radius_of_curvature,
                Dimension::Length,
            )?,
        )?;
    let theta = quantity("theta", &a.theta, Dimension::Dimensionless)?;
    // the arc's form is given beside the printed one, or the reason it has no value here
    let arc = |v: Result<f64, theory::TheoryError>| match v {
        Ok(v) => json!(v),
        Err(e) => json!(e.to_string()),
    };
    Ok(json!({
        "phi": seg.phi(),
        "f_theta": ShapeFactor::Printed.value(theta, seg.phi())?,
        "stress_GPa": seg.stress(kappa, theta, ShapeFactor::Printed)?,
        "f_theta_arc": arc(ShapeFactor::Arc.value(theta, seg.phi())),
        "stress_arc_GPa": arc(seg.stress(kappa, theta, ShapeFactor::Arc)),
        "energy_density_GPa": seg.energy_density(kappa),
    }))
}

fn indentation_law(a: &IndentationLawArgs) -> anyhow::Result<Value> {
    let k = |flag: &str, t: &str| quantity(flag, t, Dimension::Stiffness);
    let r = Rheology {
        machine_k1: k("machine-k1", &a.machine_k1)?,
        machine_k2: k("machine-k2", &a.machine_k2)?,
        specimen_k1: k("specimen-k1", &a.specimen_k1)?,
        specimen_k2: k("specimen-k2", &a.specimen_k2)?,
        viscosity: quantity("viscosity", &a.viscosity, Dimension::Damping)?,
    };
    let peak = quantity("peak", &a.peak, Dimension::Force)?;
    let time = |flag: &str, t: &str| quantity(flag, t, Dimension::Time);
    let schedule = Segment::load_hold_unload(
        peak,
        time("load-time", &a.load_time)?,
        time("hold-time", &a.hold_time)?,
        time("unload-time", &a.unload_time)?,
    );
    let samples = r.simulate(&schedule, super::bounded_count("samples", a.samples, 1)?)?;
    let col =
        |f: fn(&theory::indentation_law::Sample) -> f64| samples.iter().map(f).collect::<Vec<_>>();
    let csv = a.out.join("indentation_law.csv");
    Table::new()
        .column("time_s", col(|s| s.t))
        .column("applied_load_nN", col(|s| s.p))
        .column("specimen_load_nN", col(|s| s.q))
        .column("depth_nm", col(|s| s.delta))
        .column("plate_displacement_nm", col(|s| s.h))
        .write(&csv)?;
    let max_depth = samples
        .iter()
        .map(|s| s.delta)
        .fold(f64::NEG_INFINITY, f64::max);
    Ok(json!({
        "chi_nN_per_nm": r.chi(),
        "omega": r.omega(),
        "tau_s": r.tau(),
        "max_depth_nm": max_depth,
        "csv": path_str(&csv),
    }))
}
