//! `turf theory law`: a surface law as the engines take it — plain Lennard-Jones or thermally
//! shifted (seed §5.2, PHYSICS.md "Thermally shifted law") — with its stretch, peak tension,
//! range and, given E\*, its process zone; with `--out`, p(h) of the base and shifted laws as a
//! CSV and a plot (the seed's lost Fig 5.3).

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use serde_json::{json, Value};
use std::path::PathBuf;
use turf::laws::{LennardJones, LjKind, SurfaceLaw, ThermallyShifted};
use turf::report::csv::Table;
use turf::report::plot::{Plot, Series};
use turf::theory::positive;
use turf::theory::process_zone::process_zone;
use turf::theory::thermal::Cantilever;
use turf::units::{parse_quantity, Dimension};

/// The Lennard-Jones law a `theory` command takes (`--law`).
#[derive(Clone, Copy, ValueEnum)]
pub(super) enum LawName {
    Lj93,
    Lj104,
}

impl From<LawName> for LjKind {
    fn from(l: LawName) -> LjKind {
        match l {
            LawName::Lj93 => LjKind::Lj93,
            LawName::Lj104 => LjKind::Lj104,
        }
    }
}

/// Points of the p(h) table.
const TABLE_POINTS: usize = 600;
/// The table runs from just inside the repulsion (where p is a few peak tensions of the base
/// law) out to this many shifted intercepts.
const TABLE_REACH: f64 = 2.5;
/// Its first gap, as a fraction of z₀.
const TABLE_START: f64 = 0.98;

/// Arguments of `turf theory law`.
#[derive(Args)]
pub struct LawArgs {
    /// the Lennard-Jones exponents: lj93 or lj104
    #[arg(long, value_enum, default_value = "lj104")]
    law: LawName,
    /// work of adhesion γ, e.g. "0.46 J/m^2"
    #[arg(long)]
    gamma: String,
    /// equilibrium separation z₀, e.g. "0.34 nm"
    #[arg(long)]
    z0: String,
    /// thermal amplitude u by which the attraction's range is moved out, e.g. "4.6 nm"
    #[arg(long, conflicts_with = "thermal_tube")]
    shift: Option<String>,
    /// u from a tube's thermal vibration (seed eq. 5.9): "length,r_o,r_i,Y,T", e.g.
    /// "7 um,20 nm,17.3 nm,0.4 TPa,300 K"
    #[arg(long)]
    thermal_tube: Option<String>,
    /// plane-strain modulus E* of the solid, e.g. "700 MPa": adds the process zone E*γ/σ_peak²
    #[arg(long)]
    modulus: Option<String>,
    /// output folder: law.csv (p(h) of the base and shifted laws) and plots/law.svg|png
    #[arg(long)]
    out: Option<PathBuf>,
    /// print JSON
    #[arg(long)]
    pub json: bool,
}

fn quantity(flag: &str, text: &str, dim: Dimension) -> anyhow::Result<f64> {
    parse_quantity(text, dim).with_context(|| format!("--{flag}: expected {dim}"))
}

/// The thermal amplitude of `--thermal-tube`.
fn tube_amplitude(text: &str) -> anyhow::Result<f64> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [l, ro, ri, y, t] = parts[..] else {
        bail!(
            "--thermal-tube: expected five comma-separated quantities \"length,r_o,r_i,Y,T\", \
             e.g. \"7 um,20 nm,17.3 nm,0.4 TPa,300 K\"; got {} in {text:?}",
            parts.len()
        );
    };
    let tube = Cantilever {
        length: quantity("thermal-tube (length)", l, Dimension::Length)?,
        r_outer: quantity("thermal-tube (r_o)", ro, Dimension::Length)?,
        r_inner: quantity("thermal-tube (r_i)", ri, Dimension::Length)?,
        youngs: quantity("thermal-tube (Y)", y, Dimension::Pressure)?,
    };
    let temperature = quantity("thermal-tube (T)", t, Dimension::Temperature)?;
    Ok(tube.rms_tip_amplitude(temperature)?)
}

/// `turf theory law`.
pub fn law(a: &LawArgs) -> anyhow::Result<Value> {
    let kind = LjKind::from(a.law);
    let gamma = positive("γ", quantity("gamma", &a.gamma, Dimension::SurfaceEnergy)?)?;
    let z0 = positive("z₀", quantity("z0", &a.z0, Dimension::Length)?)?;
    let u = match (&a.shift, &a.thermal_tube) {
        (Some(s), _) => quantity("shift", s, Dimension::Length)?,
        (None, Some(t)) => tube_amplitude(t)?,
        (None, None) => 0.0,
    };
    let base = LennardJones::new(kind, gamma, z0);
    let law = SurfaceLaw::from(ThermallyShifted::new(base, u).context("--shift")?);
    let zone = match &a.modulus {
        Some(m) => {
            let e_star = quantity("modulus", m, Dimension::Pressure)?;
            Some(process_zone(&law, e_star)?)
        }
        None => None,
    };
    let mut v = json!({
        "law": match kind { LjKind::Lj93 => "lj93", LjKind::Lj104 => "lj104" },
        "gamma_J_m2": gamma,
        "z0_nm": z0,
        "u_nm": u,
        "stretch": law.stretch(),
        "peak_tension_GPa": law.max_tension(),
        "base_peak_tension_GPa": base.max_tension(),
        "gap_at_peak_nm": law.gap_at_max_tension(),
        "tangent_intercept_nm": law.tangent_intercept(),
    });
    if let Some(l) = zone {
        v["process_zone_nm"] = json!(l);
    }
    if let Some(dir) = &a.out {
        let csv = write_table(&law, dir)?;
        v["csv"] = json!(csv.display().to_string());
    }
    Ok(v)
}

/// p(h) of the base and the shifted law (and their energies) over the attraction's range.
fn write_table(law: &SurfaceLaw, dir: &std::path::Path) -> anyhow::Result<PathBuf> {
    let base = SurfaceLaw::from(*law.base());
    let z0 = law.z0();
    let (h0, h1) = (
        TABLE_START * z0,
        z0 + TABLE_REACH * (law.tangent_intercept() - z0),
    );
    // quadratic spacing: the base law's peak lies within a fraction of z₀ of the start
    let gaps: Vec<f64> = (0..TABLE_POINTS)
        .map(|i| h0 + (h1 - h0) * (i as f64 / (TABLE_POINTS - 1) as f64).powi(2))
        .collect();
    let column = |l: &SurfaceLaw, f: fn(&SurfaceLaw, f64) -> f64| -> Vec<f64> {
        gaps.iter().map(|&h| f(l, h)).collect()
    };
    let (pb, ps) = (
        column(&base, SurfaceLaw::pressure),
        column(law, SurfaceLaw::pressure),
    );
    let csv = dir.join("law.csv");
    Table::new()
        .column("gap_nm", gaps.clone())
        .column("base_pressure_GPa", pb.clone())
        .column("shifted_pressure_GPa", ps.clone())
        .column("base_energy_J_m2", column(&base, SurfaceLaw::energy))
        .column("shifted_energy_J_m2", column(law, SurfaceLaw::energy))
        .write(&csv)?;
    Plot::new(
        &format!(
            "surface law: base and shifted by u = {:.3} nm (b = {:.2})",
            law.shift(),
            law.stretch()
        ),
        "gap h (nm)",
        "pressure p (GPa, > 0 repulsive)",
    )
    .with(Series::dashed("base law", gaps.clone(), pb))
    .with(Series::line("thermally shifted", gaps, ps))
    .write(&dir.join("plots"), "law")?;
    Ok(csv)
}
