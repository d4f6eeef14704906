//! The discrete turf as the `discrete` stage builds it from a scene (its compression and its
//! lateral and shear RVE tests alike): the `[turf]` section as generation parameters, the
//! `[turf.vdw]` contacts, the `[turf.packing]` of a dense turf (rigid-body chains, cargo feature
//! `rapier`), the `[compression]` sphere's adhesion and hold, the turf's system, and the static
//! solver.

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

/// A turf as the stages build it: the tubes, their system (contacts, indenter), the contact
/// parameters, and what the packing did when `[turf.packing]` asked for one.
pub(super) struct Built {
    pub turf: Turf,
    pub sys: TurfSystem,
    pub vdw: Option<VdwParams>,
    pub packed: Option<Packed>,
}

/// What `[turf.packing]` did to the grown turf.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Packed {
    /// the density reached, tubes/nm²
    pub density: f64,
    /// the packed box's side along x, nm
    pub box_x: f64,
    /// the smallest tube surface gap of the packed turf (radius r_o, all images), nm
    pub min_gap: f64,
    /// rigid-body steps taken
    pub steps: usize,
    /// wall time of the packing, s
    pub wall_s: f64,
}

impl Packed {
    /// The packing as summary values: the density and box reached, the packed turf's smallest
    /// surface gap, the rigid-body steps and the wall time.
    pub fn values(&self) -> [(&'static str, f64); 5] {
        [
            ("packed_density_per_nm2", self.density),
            ("packed_box_nm", self.box_x),
            ("packed_min_gap_nm", self.min_gap),
            ("packing_steps", self.steps as f64),
            ("wall_time_packing_s", self.wall_s),
        ]
    }
}

/// Generate the turf of `seed` (and pack it, with `[turf.packing]`) and build its system:
/// tubes, contacts (with their parameters), the indenter of `[compression]` over the box centre.
pub(super) fn turf_system(
    s: &crate::scene::Scene,
    t: &crate::scene::turf::Turf,
    k: &Compression,
    seed: u64,
) -> Result<Built, StageError> {
    let mut turf = generate_turf(&turf_params(t, seed)).map_err(|e| failed(e.to_string()))?;
    if !t.periodic {
        turf.periodic = PeriodicBox::default();
    }
    let packed = match &t.packing {
        Some(p) => {
            let (dense, packed) = pack(&turf, t.tube.youngs.0, p.density.0)?;
            turf = dense;
            Some(packed)
        }
        None => None,
    };
    // the box the tubes stand in: the scene's, or the packing's smaller one
    let (box_x, box_y) = (
        turf.periodic.lx.unwrap_or(t.box_size[0].0),
        turf.periodic.ly.unwrap_or(t.box_size[1].0),
    );
    let vdw = t.vdw.as_ref().map(vdw_params).transpose()?;
    let mut sys = TurfSystem::from_turf(
        &turf,
        t.tube.youngs.0,
        vdw.as_ref(),
        DEFAULT_WALL_STIFFNESS,
        box_x * box_y,
    )
    .map_err(|e| failed(e.to_string()))?;
    if let (Indenter::Sphere, Some(r)) = (k.indenter, k.sphere_radius) {
        sys.indenter = Shape::Sphere {
            radius: r.0,
            x: 0.5 * box_x,
            y: 0.5 * box_y,
        };
        let contact = sphere_contact(s, k)?;
        sys.set_sphere_contact(&contact, &turf.layout(), &turf.coordinates());
    }
    Ok(Built {
        turf,
        sys,
        vdw,
        packed,
    })
}

/// The grown `turf` packed to `density` (tubes/nm²) on rigid-body chains; a packing that
/// stops short of it (a jam, an opened joint) is an error naming the densest clean state.
#[cfg(feature = "rapier")]
fn pack(turf: &Turf, youngs: f64, density: f64) -> Result<(Turf, Packed), StageError> {
    use crate::discrete::rapier_packing::{pack_turf, PackingParams};
    let p = PackingParams {
        densities: vec![density],
        ..PackingParams::default()
    };
    let why = |e: String| failed(format!("turf.packing to {:.4e} /cm^2: {e}", density * 1e14));
    let packing = pack_turf(turf, youngs, &p).map_err(|e| why(e.to_string()))?;
    let last = packing.states.into_iter().last();
    match (packing.stopped, last) {
        (None, Some(st)) => {
            // pack_turf refuses a turf without a periodic box, so the packed one has one
            let box_x = st
                .turf
                .periodic
                .lx
                .ok_or_else(|| why("no periodic box".into()))?;
            let packed = Packed {
                density: st.density,
                box_x,
                min_gap: st.min_gap,
                steps: st.steps,
                wall_s: st.wall_s,
            };
            Ok((st.turf, packed))
        }
        (stopped, last) => {
            let densest = last.map_or(String::from("none recorded"), |st| {
                format!("{:.4e} /cm^2", st.density * 1e14)
            });
            Err(why(format!(
                "the packing stopped short: {}; the densest clean state: {densest} — lower \
                 turf.packing.density",
                stopped.unwrap_or_else(|| "no state recorded".into())
            )))
        }
    }
}

/// Without the `rapier` feature the scene check refuses `[turf.packing]`; this says so again
/// should a caller skip the check.
#[cfg(not(feature = "rapier"))]
fn pack(_: &Turf, _: f64, _: f64) -> Result<(Turf, Packed), StageError> {
    Err(failed(
        "turf.packing needs turf built with the cargo feature `rapier`".into(),
    ))
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

/// Realisation `index` of a scene's `[turf]` as the discrete stage grows it (before any
/// `[turf.packing]`), for tools outside the stages (the rigid-body packing, `examples/rapier_packing.rs`): the turf, the
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

/// The packing as the stages use it (cargo feature `rapier`; CI runs these with the packing's
/// own tests, `cargo test --features rapier --lib rapier_packing`).
#[cfg(all(test, feature = "rapier"))]
mod tests {
    use super::*;
    use crate::scene::load_str;
    use std::path::Path;

    /// The quickstart's turf alone (its `[scene]`, `[turf]` and `[compression]`), one
    /// realisation of 9 tubes in its 300 nm box at 10¹⁰ /cm², packed to `density`; compressed
    /// by 2 % in two steps, no plots.
    fn packed_scene(density: &str) -> crate::scene::Loaded {
        let mut doc: toml::Table = include_str!("../../scenes/quickstart.toml")
            .parse()
            .unwrap();
        doc.retain(|k, _| matches!(k, "scene" | "turf" | "compression"));
        let sets = [
            "turf.realisations=1".to_string(),
            format!("turf.packing.density=\"{density}\""),
            "compression.to=0.02".into(),
            "compression.steps=2".into(),
            "output.plots=false".into(),
        ];
        load_str(&doc.to_string(), Path::new("packed.toml"), &sets).unwrap()
    }

    #[test]
    fn rapier_packing_of_a_scene_turf_shrinks_its_box_to_the_density() {
        let loaded = packed_scene("2e10 1/cm^2");
        let s = &loaded.base.scene;
        let (t, k) = (s.turf.as_ref().unwrap(), s.compression.as_ref().unwrap());
        let built = turf_system(s, t, k, 3).unwrap();
        let packed = built.packed.unwrap();
        // 9 tubes at 2e-4 /nm²: a box of √(9/2e-4) = 212.13 nm, the same in x and y
        let side = (9.0_f64 / 2e-4).sqrt();
        assert_eq!(built.turf.tubes.len(), 9);
        assert!((packed.density / 2e-4 - 1.0).abs() < 1e-9, "{packed:?}");
        assert!((packed.box_x / side - 1.0).abs() < 1e-9, "{packed:?}");
        assert_eq!(built.turf.periodic.lx, built.turf.periodic.ly);
        // the stress is force over the packed box's area, not the grown one's
        assert!((built.sys.area / (side * side) - 1.0).abs() < 1e-9);
        // clear of each other at the van der Waals gap (capsules of r_o + 0.17 nm touching)
        assert!(packed.min_gap > 0.0, "{packed:?}");
        assert!(packed.steps > 0 && packed.wall_s > 0.0);

        // the stage runs on the packed turf and reports the packing beside the compression
        let dir = std::env::temp_dir().join(format!("turf-packed-{}", std::process::id()));
        std::fs::remove_dir_all(&dir).ok();
        let opts = crate::pipeline::RunOptions {
            out: Some(dir.clone()),
            progress: false,
            resume: false,
        };
        let report = crate::pipeline::run(&loaded, &opts).unwrap();
        assert!(report.failure.is_none(), "{:?}", report.failure);
        let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let summary: serde_json::Value = serde_json::from_str(&text).unwrap();
        let v = &summary["stages"][0]["values"];
        assert_eq!(v["packed_density_per_nm2"].as_f64(), Some(packed.density));
        assert_eq!(v["packed_box_nm"].as_f64(), Some(packed.box_x));
        assert_eq!(v["box_area_nm2"].as_f64(), Some(built.sys.area));
        assert!(v["relaxed_min_gap_nm"].as_f64().unwrap() >= 0.0, "{v}");
        // the tallest tube is pressed 40 nm: the platen carries a load
        assert!(v["peak_stress_GPa"].as_f64().unwrap() > 0.0, "{v}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn rapier_packing_that_jams_is_an_error_naming_the_densest_state() {
        // the 9 tubes lock near 4.3e10 /cm² (docs/benchmarks.md "rapier3d")
        let loaded = packed_scene("6e10 1/cm^2");
        let s = &loaded.base.scene;
        let (t, k) = (s.turf.as_ref().unwrap(), s.compression.as_ref().unwrap());
        let e = turf_system(s, t, k, 3).err().unwrap().to_string();
        for part in [
            "turf.packing to 6.0000e10 /cm^2",
            "stopped short",
            "jammed",
            "the densest clean state: 4.",
            "lower turf.packing.density",
        ] {
            assert!(e.contains(part), "{part:?} missing from: {e}");
        }
    }
}
