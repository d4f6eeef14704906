//! `turf homogenize`: material cards from curves or tangent laws.

use clap::Args;
use std::path::PathBuf;
use turf::homogenize::{self, tangent_law::TangentLaw, HomogenizeParams, Relaxation, Source};
use turf::scene::plan::sig;
use turf::units::{parse_quantity, Dimension};

/// Arguments of `turf homogenize`.
#[derive(Args)]
pub struct HomogenizeArgs {
    /// The idealised tangent law (5.1), e.g. E0=700MPa,Einf=70MPa,eps0=0.05.
    #[arg(
        long,
        value_name = "E0=..,Einf=..,eps0=..",
        conflicts_with = "curve",
        required_unless_present = "curve"
    )]
    pub tangent_law: Option<String>,
    /// A compressive stress-strain curve (CSV: strain, stress_MPa|stress_GPa|..., optional lateral_strain).
    #[arg(long, value_name = "CSV")]
    pub curve: Option<PathBuf>,
    /// Hyperfoam terms N (1 to 3, as `homogenize.terms` in a scene).
    #[arg(long, default_value_t = 1)]
    pub terms: usize,
    /// Upper end of the fitted nominal compressive strain (default 0.3: reproduces seed Table 5.1).
    #[arg(long, default_value_t = homogenize::fit_hyperfoam::DEFAULT_STRAIN_MAX)]
    pub strain_max: f64,
    /// Points at which a tangent law is sampled (at most 10⁷).
    #[arg(long, default_value_t = homogenize::DEFAULT_SAMPLES)]
    pub samples: usize,
    /// Hold the hyperfoam's initial modulus at the tangent law's E0 (default: yes for
    /// --tangent-law, no for --curve).
    #[arg(long, value_name = "BOOL")]
    pub pin_e0: Option<bool>,
    /// One-term relaxation (5.8), e.g. mu_bar=0.4,tau=3s.
    #[arg(
        long,
        value_name = "mu_bar=..,tau=..",
        conflicts_with = "relaxation_curve"
    )]
    pub relaxation: Option<String>,
    /// A relaxation curve to fit a Prony series to (CSV: time_s and g or a stress column).
    #[arg(long, value_name = "CSV")]
    pub relaxation_curve: Option<PathBuf>,
    /// Prony terms fitted to --relaxation-curve.
    #[arg(long, default_value_t = 1)]
    pub prony_terms: usize,
    /// The turf's lateral compression curve (CSV: strain, stress_GPa; e.g.
    /// discrete_rve_lateral_loading.csv of `compression.mode = "lateral"`): with --shear-curve
    /// and --curve (the axial curve), also fit the transversely isotropic card
    /// (material_transverse.json; --terms matrix and fibre terms).
    #[arg(long, value_name = "CSV", requires_all = ["shear_curve", "curve"])]
    pub lateral_curve: Option<PathBuf>,
    /// The turf's longitudinal shear curve (CSV: strain = γ, stress_GPa = τ; e.g.
    /// discrete_rve_shear_loading.csv of `compression.mode = "shear"`).
    #[arg(long, value_name = "CSV", requires_all = ["lateral_curve", "curve"])]
    pub shear_curve: Option<PathBuf>,
    /// Output folder (default runs/homogenize).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

fn parse_relaxation(text: &str) -> anyhow::Result<Relaxation> {
    let (mut mu_bar, mut tau) = (None, None);
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (k, v) = item.split_once('=').ok_or_else(|| {
            anyhow::anyhow!("--relaxation: \"{item}\" is not KEY=VALUE (mu_bar, tau)")
        })?;
        match k.trim() {
            "mu_bar" => mu_bar = Some(parse_quantity(v, Dimension::Dimensionless)?),
            "tau" => tau = Some(parse_quantity(v, Dimension::Time)?),
            other => anyhow::bail!("--relaxation: unknown key \"{other}\" (mu_bar, tau)"),
        }
    }
    Ok(Relaxation::Law {
        mu_bar: mu_bar.ok_or_else(|| anyhow::anyhow!("--relaxation: missing mu_bar"))?,
        tau: tau.ok_or_else(|| anyhow::anyhow!("--relaxation: missing tau"))?,
    })
}

/// `turf homogenize`.
pub fn run(args: HomogenizeArgs) -> anyhow::Result<()> {
    let source = match (&args.tangent_law, &args.curve) {
        (Some(t), None) => Source::TangentLaw(TangentLaw::parse(t)?),
        (None, Some(p)) => Source::Curve {
            curve: homogenize::read_curve(p)?,
            name: p.display().to_string(),
        },
        _ => anyhow::bail!("give exactly one of --tangent-law or --curve"),
    };
    let max_terms = homogenize::fit_hyperfoam::MAX_FIT_TERMS;
    if !(1..=max_terms).contains(&args.terms) {
        anyhow::bail!(
            "--terms {} is not allowed: must lie in 1..={max_terms}",
            args.terms
        );
    }
    super::bounded_count("samples", args.samples, 1)?;
    let mut params = HomogenizeParams::new(source);
    params.terms = args.terms;
    params.strain_max = args.strain_max;
    params.samples = args.samples;
    params.pin_initial_modulus = args.pin_e0;
    params.relaxation = match (&args.relaxation, &args.relaxation_curve) {
        (Some(r), _) => Some(parse_relaxation(r)?),
        (None, Some(p)) => Some(Relaxation::Curve {
            curve: homogenize::read_relaxation(p)?,
            name: p.display().to_string(),
            terms: args.prony_terms,
        }),
        (None, None) => None,
    };
    let out = homogenize::run(&params)?;
    let dir = args.out.clone().unwrap_or_else(homogenize::default_out_dir);
    let summary = homogenize::write_outputs(&out, &dir)?;
    if let (Some(axial), Some(lateral), Some(shear)) =
        (&args.curve, &args.lateral_curve, &args.shear_curve)
    {
        transverse(axial, lateral, shear, &args, &dir)?;
    }
    // on stderr, so that they show with --json too
    for w in &summary.warnings {
        eprintln!("warning: {w}");
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return Ok(());
    }
    let m = &out.hyperfoam_fit.material;
    let law = out.tangent_law;
    println!(
        "tangent law (5.1): E0 = {} MPa, Einf = {} MPa, eps0 = {}{}",
        sig(law.e0 * 1e3),
        sig(law.e_inf * 1e3),
        sig(law.eps0),
        if out.tangent_fit.is_some() {
            " (fitted)"
        } else {
            ""
        }
    );
    if let Some(se) = out.tangent_fit.as_ref().and_then(|f| f.std_errors) {
        println!(
            "  std errors: E0 ± {:.4} MPa, Einf ± {:.4} MPa, eps0 ± {:.4e}",
            se[0] * 1e3,
            se[1] * 1e3,
            se[2]
        );
    }
    println!(
        "hyperfoam N = {} ({} requested) on 0 < strain <= {} ({} points), nu = {:.4}:",
        m.terms.len(),
        summary.terms_requested,
        out.hyperfoam_fit.strain_max,
        out.hyperfoam_fit.points,
        out.hyperfoam_fit.nu
    );
    for (i, t) in m.terms.iter().enumerate() {
        let se = out.hyperfoam_fit.std_errors.as_ref();
        println!(
            "  term {}: mu = {:.6} MPa{}, alpha = {:.6}{}, beta = {:.6}",
            i + 1,
            t.mu * 1e3,
            se.map_or(String::new(), |s| format!(" ± {:.3e}", s.mu[i] * 1e3)),
            t.alpha,
            se.map_or(String::new(), |s| format!(" ± {:.3e}", s.alpha[i])),
            t.beta
        );
    }
    println!(
        "  fit rms (relative) = {:.3e}, max = {:.3e}",
        out.hyperfoam_fit.rms_rel, out.hyperfoam_fit.max_rel
    );
    if let Some(p) = &out.card.prony {
        println!("prony: g = {:?}, k = {:?}, tau = {:?} s", p.g, p.k, p.tau);
    }
    println!("wrote {} ({})", dir.display(), summary.files.join(", "));
    Ok(())
}

/// Fit the transversely isotropic card to the three curves, print it and write
/// `material_transverse.json` into `dir`.
fn transverse(
    axial: &std::path::Path,
    lateral: &std::path::Path,
    shear: &std::path::Path,
    args: &HomogenizeArgs,
    dir: &std::path::Path,
) -> anyhow::Result<()> {
    use turf::homogenize::transverse_foam::{fit_transverse, TransverseFitParams};
    let fit = fit_transverse(
        &homogenize::read_curve(axial)?,
        &homogenize::read_curve(lateral)?,
        &homogenize::read_curve(shear)?,
        &TransverseFitParams {
            matrix_terms: args.terms,
            fibre_terms: args.terms,
            strain_max: args.strain_max,
        },
    )?;
    for w in &fit.warnings {
        eprintln!("warning: transverse card: {w}");
    }
    let sources = [axial, lateral, shear].map(|p| p.display().to_string());
    let file = dir.join(homogenize::transverse_foam::CARD_JSON);
    turf::report::write_json(&file, &fit.card_json(&sources))?;
    let m = &fit.material;
    let mpa = |v: f64| sig(v * 1e3);
    println!("transversely isotropic card (axis = tube axis z):");
    for (what, foam) in [("matrix", &m.matrix), ("fibre", &m.fibre)] {
        for t in &foam.terms {
            println!("  {what}: mu = {} MPa, alpha = {}", mpa(t.mu), sig(t.alpha));
        }
    }
    let [e_a, e_t, g_l] = fit.material.initial_moduli();
    println!(
        "  shear: mu_s = {} MPa; initial E_A = {} MPa, E_T = {} MPa, G_L = {} MPa",
        mpa(m.shear),
        mpa(e_a),
        mpa(e_t),
        mpa(g_l)
    );
    println!(
        "  fit rms (relative): axial {:.3e}, lateral {:.3e}, shear {:.3e}",
        fit.rms_rel[0], fit.rms_rel[1], fit.rms_rel[2]
    );
    println!("wrote {}", file.display());
    Ok(())
}
