//! The discrete turf as the `discrete` stage builds it from a scene (its compression and its
//! lateral and shear RVE tests alike): the `[turf]` section as generation parameters, the
//! `[turf.vdw]` contacts, the `[compression]` sphere's adhesion and hold, the generated turf's
//! system, and the static solver.

use super::StageError;
use crate::discrete::broadphase::PeriodicBox;
use crate::discrete::model::{SphereContact, StaticSolver, StickSettings, TurfSystem};
use crate::discrete::platen::{Shape, DEFAULT_WALL_STIFFNESS};
use crate::discrete::solve_fire::FireParams;
use crate::discrete::solve_newton::NewtonParams;
use crate::discrete::turf::{generate_turf, Turf, TurfParams};
use crate::discrete::vdw::{VdwKernel, VdwParams};
use crate::laws::SurfaceLaw;
use crate::scene::compression::{
    Compression, DiscreteSolver, Indenter, SphereAdhesion, Tangential, DEFAULT_STICK_STIFFNESS,
};
use crate::scene::Stage;

/// Segments per tube when `[turf.tube] segment` is not given (the scene reference's default).
const DEFAULT_SEGMENTS_PER_TUBE: f64 = 20.0;

/// A failure of the discrete stage.
pub(super) fn failed(message: String) -> StageError {
    StageError::Failed {
        stage: Stage::Discrete,
        message,
    }
}

/// The sphere's adhesion (the `[adhesion]` law, shifted or not) and tangential hold.
fn sphere_contact(s: &crate::scene::Scene, k: &Compression) -> Result<SphereContact, StageError> {
    let adhesion = match (k.sphere_adhesion, &s.adhesion) {
        (SphereAdhesion::None, _) => None,
        (_, None) => {
            return Err(failed(
                "compression.sphere_adhesion needs [adhesion]".into(),
            ))
        }
        (SphereAdhesion::Lj, Some(a)) => Some(SurfaceLaw::from(a.law())),
        (SphereAdhesion::LjShifted, Some(a)) => Some(
            a.surface_law(s.turf.as_ref())
                .map_err(|e| failed(format!("adhesion.thermal_shift: {e}")))?,
        ),
    };
    let stick = (k.sphere_tangential == Tangential::Stick).then(|| StickSettings {
        stiffness: k.stick_stiffness.map_or(DEFAULT_STICK_STIFFNESS, |v| v.0),
        release: k.stick_release.map(|f| f.0),
    });
    Ok(SphereContact { adhesion, stick })
}

/// Generate the turf of `seed` and build its system: tubes, contacts (with their parameters),
/// the indenter of `[compression]`.
pub(super) fn turf_system(
    s: &crate::scene::Scene,
    t: &crate::scene::turf::Turf,
    k: &Compression,
    seed: u64,
) -> Result<(Turf, TurfSystem, Option<VdwParams>), StageError> {
    let mut turf = generate_turf(&turf_params(t, seed)).map_err(|e| failed(e.to_string()))?;
    if !t.periodic {
        turf.periodic = PeriodicBox::default();
    }
    let vdw = t.vdw.as_ref().map(vdw_params).transpose()?;
    let mut sys = TurfSystem::from_turf(
        &turf,
        t.tube.youngs.0,
        vdw.as_ref(),
        DEFAULT_WALL_STIFFNESS,
        t.box_size[0].0 * t.box_size[1].0,
    )
    .map_err(|e| failed(e.to_string()))?;
    if let (Indenter::Sphere, Some(r)) = (k.indenter, k.sphere_radius) {
        sys.indenter = Shape::Sphere {
            radius: r.0,
            x: 0.5 * t.box_size[0].0,
            y: 0.5 * t.box_size[1].0,
        };
        let contact = sphere_contact(s, k)?;
        sys.set_sphere_contact(&contact, &turf.layout(), &turf.coordinates());
    }
    Ok((turf, sys, vdw))
}

/// The `[turf]` section as generation parameters (no radius scatter: the scene has none).
fn turf_params(t: &crate::scene::turf::Turf, seed: u64) -> TurfParams {
    let g = &t.growth;
    TurfParams {
        density: t.density.0,
        box_x: t.box_size[0].0,
        box_y: t.box_size[1].0,
        radius_outer: t.tube.r_o.0,
        radius_inner: t.tube.r_i.0,
        radius_cv: 0.0,
        length_mean: g.length.0,
        length_cv: g.length_spread.0,
        tilt_spread: g.tilt.0,
        mean_tilt: g.mean_tilt.0,
        mean_azimuth: g.mean_azimuth.0,
        wave_amplitude: g.waviness.0,
        wave_coherence: g.wave_coherence.0,
        // a straight tube (waviness 0) ignores the wavelength
        wave_length: g.wavelength.map_or(g.length.0, |w| w.0),
        segment_length: t
            .tube
            .segment
            .map_or(g.length.0 / DEFAULT_SEGMENTS_PER_TUBE, |l| l.0),
        seed,
    }
}

/// `[turf.vdw]` as interaction parameters: γ_L at the scene's tube radius, the equilibrium
/// gap, the cutoff; the smooth switch-off starts at the engine's default gap (1 nm) or, for a
/// shorter cutoff, half-way between the equilibrium gap and the cutoff.
pub(super) fn vdw_params(v: &crate::scene::turf::Vdw) -> Result<VdwParams, StageError> {
    let d = VdwParams::default();
    let cut = v.cutoff.map_or(d.gap_cut, |c| c.0);
    let gap = v.separation.0;
    let p = VdwParams {
        gamma_l: v.gamma_line.0,
        gap_eq: gap,
        gap_cut: cut,
        gap_switch: d.gap_switch.min(0.5 * (gap + cut)),
        kernel: match v.kernel {
            crate::scene::turf::VdwKernel::Quadrature => VdwKernel::Quadrature,
            crate::scene::turf::VdwKernel::Tabulated => VdwKernel::Tabulated,
        },
        ..d
    };
    p.validate().map_err(|e| failed(e.to_string()))?;
    Ok(p)
}

/// The scene's solver with its tolerance (absolute, nN) and iteration limit.
pub(super) fn static_solver(k: &Compression) -> StaticSolver {
    match k.solver {
        DiscreteSolver::Fire => StaticSolver::Fire(FireParams {
            atol: k.tolerance.0,
            rtol: 0.0,
            max_iterations: k.max_iterations,
            ..FireParams::default()
        }),
        DiscreteSolver::Newton => StaticSolver::Newton(NewtonParams {
            atol: k.tolerance.0,
            rtol: 0.0,
            max_iterations: k.max_iterations,
            ..NewtonParams::default()
        }),
    }
}

/// Realisation `index` of a scene's `[turf]` as the discrete stage generates it, for tools
/// outside the stages (the rigid-body packing, `examples/rapier_packing.rs`): the turf, the
/// tubes' Young's modulus (GPa), the contact parameters and the `[compression]` solver.
pub fn scene_turf(
    s: &crate::scene::Scene,
    index: usize,
) -> Result<(Turf, f64, Option<VdwParams>, StaticSolver), StageError> {
    let t = s
        .turf
        .as_ref()
        .ok_or_else(|| failed("the scene has no [turf]".into()))?;
    let k = s
        .compression
        .as_ref()
        .ok_or_else(|| failed("the scene has no [compression]".into()))?;
    let seed = super::ensemble::realisation_seed(s.scene.seed, index);
    let mut turf = generate_turf(&turf_params(t, seed)).map_err(|e| failed(e.to_string()))?;
    if !t.periodic {
        turf.periodic = PeriodicBox::default();
    }
    let vdw = t.vdw.as_ref().map(vdw_params).transpose()?;
    Ok((turf, t.tube.youngs.0, vdw, static_solver(k)))
}
