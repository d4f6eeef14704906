//! The turf as a representative volume beyond uniaxial compression: the
//! transverse and longitudinal-shear responses an indenter's edge imposes, which the axial
//! platen drive ([`super::drive`]) does not see.
//!
//! Both tests start from the relaxed turf (no platen; the top is free, so the normal stress on
//! it vanishes) and follow a nominal strain path ε_k ([`strain_path`]), each step an
//! equilibrium ([`StaticSolver`]) warm-started from an affine predictor:
//!
//! - **Lateral** compression: the periodic period along x shrinks, L_x = L_x⁰(1 − ε) (L_y
//!   fixed); each tube's clamp moves rigidly with its base, x_b ↦ x_b (1 − ε) (so the clamped
//!   segment keeps its length), the free nodes follow (affinely or with their base, whichever
//!   starts lower in energy) and relax. The deformation is F = diag(1 − ε, 1, λ_z) with λ_z free.
//!   Contacts between two base segments (segments touching a clamped node, the lowest
//!   2 segments of each tube) are left out: the generator places bases as close as 2r + 0.34 nm,
//!   and the clamps, moved with the box, would push such a pair through each other within a few
//!   per cent — the substrate's approach, not the turf's (measured: docs/discrete-compression.md).
//! - **Shear** (longitudinal, x–z): the tube tips (each tube's last node) are held in x and y
//!   and moved together by u = ε H₀ in x (H₀ the turf's top), tips free in z; the bases stay
//!   clamped, the box fixed. The free nodes follow the shear linearly in height along each tube,
//!   then relax. F = [[1, 0, ε], [0, 1, 0], [0, 0, λ_z]], λ_z free.
//!
//! Stress, nominal, from the equilibrium energy E*(ε) (aJ) of the volume V₀ = A H₀ (A the box
//! area): σ = (1/V₀) dE*/dε, GPa, positive in compression (lateral) and along +x on the top
//! (shear). At equilibrium only the explicit dependence on ε is left (the free nodes are
//! stationary), so dE*/dε is exact from the configuration:
//!
//! - lateral: dE*/dε = −L_x⁰ ∂E/∂L_x − Σ_c x⁰_base(c) ∂E/∂x_c, the image pairs' virial
//!   ([`super::vdw_term::VdwTerm::box_gradient`]) plus the clamps' reactions times their
//!   velocity;
//! - shear: dE*/dε = H₀ Σ_tips ∂E/∂x_tip, the tips' reaction forces, so σ = F_x/A.
//!
//! Tests check both against central differences of E*.

use super::broadphase::PeriodicBox;
use super::drive::{solve_step, strain_path, CompressionParams, DriveError};
use super::energy::EnergyTerm;
use super::model::{State, StaticSolver, TurfSystem};
use super::solve::Cost;
use serde::Serialize;

/// Which deformation of the volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RveLoading {
    /// the periodic box shrinks in x
    Lateral,
    /// the tips move in x relative to the clamped bases
    Shear,
}

/// Deepest overlap of two tube surfaces (negative gap, nm) an RVE state may have. Squeezed
/// contacts sit on the van der Waals wall within a few tenths of a nanometre of touching (the
/// 1 µm quickstart turf compressed laterally by 8 %: −0.10 nm); tubes driven into each other
/// overlap by nanometres to tens of nanometres (the 9-tube turf at 74 % lateral strain: −11.9
/// nm). One nanometre, three van der Waals spacings, lies between.
pub const OVERLAP_LIMIT_NM: f64 = 1.0;

/// The equilibria an RVE test reached, and why it stopped early if it did.
#[derive(Debug, Clone, PartialEq)]
pub struct RveRun {
    /// every step reached, from the relaxed state (step 0)
    pub records: Vec<RveRecord>,
    /// why the drive stopped before the end of its path (the steps before are kept)
    pub stopped: Option<String>,
}

/// One equilibrium of an RVE test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RveRecord {
    /// step index, 0 = the relaxed turf
    pub step: usize,
    /// true on the way out (and at step 0), false on the way back
    pub loading: bool,
    /// nominal strain: lateral compression 1 − L_x/L_x⁰, or shear u/H₀
    pub strain: f64,
    /// nominal stress (1/V₀) dE*/dε, GPa
    pub stress: f64,
    /// total equilibrium energy E*, aJ
    pub energy: f64,
    /// mean fall of the tube tips since step 0, nm (λ_z − 1 ≈ −tip_drop/H₀)
    pub tip_drop: f64,
    /// energies and contacts at equilibrium
    pub state: State,
    /// what the step's solve cost (zero at step 0)
    #[serde(skip)]
    pub cost: Cost,
}

/// The reference geometry of the test.
struct Reference {
    /// the relaxed configuration, nm
    x0: Vec<f64>,
    /// the turf's top H₀, nm
    height: f64,
    /// V₀ = A H₀, nm³
    volume: f64,
    /// L_x⁰ (lateral only), nm
    lx0: f64,
    /// the clamped nodes, each with its tube's base x⁰ (nm): a tube's clamp moves rigidly
    /// with its base, x = x⁰ − ε x⁰_base, so the clamped segments keep their shape
    clamps: Vec<(usize, f64)>,
    /// each tube's last node
    tips: Vec<usize>,
    /// per tube: (first node, nodes, height of its highest clamped node nm)
    tubes: Vec<(usize, usize, f64)>,
}

/// Drive the relaxed turf at `x` (nm; the final configuration on return) along `params` in the
/// deformation `loading`, solving each step with `solver`; `observe` sees every record as it is
/// reached. The system's platen is removed; with `Shear` the tips' x and y are held during the
/// drive (the system's own supports are restored on return). Returns the records, step 0
/// first.
pub fn drive_rve(
    sys: &mut TurfSystem,
    x: &mut [f64],
    loading: RveLoading,
    params: &CompressionParams,
    solver: &StaticSolver,
    observe: &mut dyn FnMut(&RveRecord),
) -> Result<RveRun, DriveError> {
    params.check()?;
    sys.model.platen = None;
    let reference = reference(sys, x, loading)?;
    let supports = sys.fixed.clone();
    match loading {
        RveLoading::Shear => {
            for &t in &reference.tips {
                sys.fixed.fix(3 * t).fix(3 * t + 1);
            }
        }
        RveLoading::Lateral => {
            let fixed = &sys.fixed;
            if let Some(v) = sys.model.vdw.as_mut() {
                v.exclude_pairs_among(&|n| fixed.is_fixed(3 * n), x);
            }
        }
    }
    let result = run(sys, x, loading, params, solver, &reference, observe);
    sys.fixed = supports;
    result
}

fn reference(sys: &TurfSystem, x: &[f64], loading: RveLoading) -> Result<Reference, DriveError> {
    let periods = sys.model.vdw.as_ref().map(|v| v.periodic_box());
    let lx0 = match (loading, periods) {
        (RveLoading::Lateral, Some(PeriodicBox { lx: Some(lx), .. })) => lx,
        (RveLoading::Lateral, _) => {
            return Err(DriveError::Invalid(
                "lateral compression needs tube–tube contacts in a box periodic in x: nothing \
                 else carries a lateral load (turf.periodic = true and [turf.vdw])"
                    .into(),
            ))
        }
        (RveLoading::Shear, _) => 0.0,
    };
    let height = sys.height(x);
    let clamped = |n: usize| sys.fixed.is_fixed(3 * n);
    let mut tubes = Vec::new();
    for rod in sys.model.rods.rods() {
        let (first, nodes) = (rod.first_node(), rod.nodes());
        let base = (first..first + nodes)
            .filter(|&n| clamped(n))
            .map(|n| x[3 * n + 2])
            .fold(0.0, f64::max);
        if clamped(first + nodes - 1) {
            return Err(DriveError::Invalid(format!(
                "tube starting at node {first} is held at its tip: the RVE tests move the tips"
            )));
        }
        tubes.push((first, nodes, base));
    }
    Ok(Reference {
        x0: x.to_vec(),
        height,
        volume: sys.area * height,
        lx0,
        clamps: tubes
            .iter()
            .flat_map(|&(first, nodes, _)| {
                (first..first + nodes)
                    .filter(|&n| clamped(n))
                    .map(move |n| (n, x[3 * first]))
            })
            .collect(),
        tips: tubes.iter().map(|&(f, n, _)| f + n - 1).collect(),
        tubes,
    })
}

fn run(
    sys: &mut TurfSystem,
    x: &mut [f64],
    loading: RveLoading,
    params: &CompressionParams,
    solver: &StaticSolver,
    r: &Reference,
    observe: &mut dyn FnMut(&RveRecord),
) -> Result<RveRun, DriveError> {
    let mut records: Vec<RveRecord> = Vec::new();
    let mut last = 0.0;
    for (step, (strain, out)) in strain_path(params).into_iter().enumerate() {
        let cost = if step == 0 {
            Cost::default()
        } else {
            match loading {
                RveLoading::Lateral => compress_box(sys, x, r, last, strain),
                RveLoading::Shear => shear_tips(x, r, last, strain),
            }
            solve_step(sys, x, solver, step, strain)?
        };
        last = strain;
        let state = sys.state(x);
        if state.min_gap < -OVERLAP_LIMIT_NM {
            // the equilibrium the solver found has tubes pushed into each other: the box or
            // the tips were driven faster than the tubes could get out of each other's way
            let stopped = format!(
                "step {step} (strain {strain:.3}): tubes interpenetrate (smallest surface gap \
                 {:.3} nm, beyond the {OVERLAP_LIMIT_NM} nm a squeezed contact reaches), so this \
                 state and those beyond it are unphysical; the {} steps before it are kept",
                state.min_gap,
                records.len()
            );
            return Ok(RveRun {
                records,
                stopped: Some(stopped),
            });
        }
        let tip_drop = r
            .tips
            .iter()
            .map(|&t| r.x0[3 * t + 2] - x[3 * t + 2])
            .sum::<f64>()
            / r.tips.len() as f64;
        let rec = RveRecord {
            step,
            loading: out,
            strain,
            stress: strain_derivative(sys, x, loading, r) / r.volume,
            energy: state.energy.elastic() + state.energy.vdw + state.energy.walls,
            tip_drop,
            state,
            cost,
        };
        observe(&rec);
        records.push(rec);
    }
    Ok(RveRun {
        records,
        stopped: None,
    })
}

/// Lateral step from strain `from` to `to`: the period L_x⁰(1 − ε), the clamps moved with
/// their bases, and the free nodes started from the lower-energy of two predictors — every node
/// scaled in x about the origin (affine: contacts kept, tilted tubes shortened), or each tube
/// translated with its base (rigid: lengths kept, contacts between tubes of distant bases
/// squeezed).
fn compress_box(sys: &mut TurfSystem, x: &mut [f64], r: &Reference, from: f64, to: f64) {
    if let Some(v) = sys.model.vdw.as_mut() {
        let pbox = PeriodicBox {
            lx: Some(r.lx0 * (1.0 - to)),
            ..v.periodic_box()
        };
        v.set_box(pbox, x);
    }
    let mut rigid = x.to_vec();
    for &(first, nodes, _) in &r.tubes {
        let shift = -(to - from) * r.x0[3 * first];
        for n in first..first + nodes {
            rigid[3 * n] += shift;
        }
    }
    let scale = (1.0 - to) / (1.0 - from);
    for node in x.chunks_exact_mut(3) {
        node[0] *= scale;
    }
    for &(c, base) in &r.clamps {
        x[3 * c] = r.x0[3 * c] - to * base;
        rigid[3 * c] = x[3 * c];
    }
    let e_rigid = sys.energy(&rigid);
    if e_rigid.is_finite() && e_rigid < sys.energy(x) {
        x.copy_from_slice(&rigid);
    }
}

/// Shear step from strain `from` to `to`: the tips at x⁰ + ε H₀, each tube's free nodes moved
/// by the increment in proportion to their height above its clamp.
fn shear_tips(x: &mut [f64], r: &Reference, from: f64, to: f64) {
    let du = (to - from) * r.height;
    for &(first, nodes, base) in &r.tubes {
        let tip = first + nodes - 1;
        let span = x[3 * tip + 2] - base;
        for n in first..tip {
            let z = x[3 * n + 2];
            if z > base && span > 0.0 {
                x[3 * n] += du * ((z - base) / span).min(1.0);
            }
        }
        x[3 * tip] = r.x0[3 * tip] + to * r.height;
    }
}

/// dE*/dε at the equilibrium `x`, aJ (module doc).
fn strain_derivative(sys: &mut TurfSystem, x: &[f64], loading: RveLoading, r: &Reference) -> f64 {
    sys.model.prepare(x);
    let mut grad = vec![0.0; x.len()];
    sys.model.energy_gradient(x, &mut grad);
    match loading {
        RveLoading::Lateral => {
            let box_term = sys
                .model
                .vdw
                .as_ref()
                .map_or(0.0, |v| -r.lx0 * v.box_gradient(x)[0]);
            let clamps: f64 = r.clamps.iter().map(|&(c, base)| base * grad[3 * c]).sum();
            box_term - clamps
        }
        RveLoading::Shear => r.height * r.tips.iter().map(|&t| grad[3 * t]).sum::<f64>(),
    }
}
