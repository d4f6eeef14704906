//! The plan: which stages a scene asks for and which physics each builds — "model only what a
//! scene requires" (DESIGN.md) — and the values resolved from the scene before anything runs
//! (defaults filled, derived sizes, the dimensionless numbers that decide the physics).
//!
//! Derived numbers (PHYSICS.md), each computed by `crate::theory`: E* = E/(1 − ν²) against a
//! rigid indenter; Tabor μ = (Rγ²/(E*² z₀³))^(1/3); Maugis λ = σ₀(9R/(2πγE*²))^(1/3) with σ₀
//! the largest tension of the law as the engines take it (thermally shifted where the scene
//! asks); JKR contact radius at zero load a₀ = (9πγR²/(2E*))^(1/3); thermal amplitude of the
//! tube ends u = (0.4243 l³ kT / (Y(r_o⁴ − r_i⁴)))^(1/2) (seed eq. 5.9); the process zone
//! ℓ = E*γ/σ_peak² that sizes adhesive meshes.

use super::adhesion::ThermalShift;
pub use super::check::sig;
use super::check::Checker;
use super::homogenize::Curve;
use super::indenter::{Shape, BERKOVICH_EQUIVALENT_CONE_DEG};
use super::machine::{Control, Machine};
use super::material::MaterialModel;
use super::mesh::{
    Mesh, DEPTH_PER_CONTACT_RADIUS, ELEMENTS_PER_CONTACT_RADIUS, ELEMENTS_PER_PROCESS_ZONE,
    WIDTH_PER_CONTACT_RADIUS,
};
use super::resources::Memory;
use super::schedule::ScheduleTotals;
use super::solver::{Kinematics, Solver};
pub use super::stage::Stage;
use super::Scene;
use crate::continuum::contact::SurfaceArea;
use crate::theory::process_zone::process_zone;
use crate::theory::{hertz, jkr, tabor, Sphere};
use serde::Serialize;
use std::fmt;
use std::path::PathBuf;

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A stage in the plan and why the scene asks for it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedStage {
    /// the stage
    pub stage: Stage,
    /// which sections ask for it and what it computes
    pub why: String,
}

/// A piece of physics switched on or off by the scene's sections.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Switch {
    /// short name (`lj_adhesion`, `viscoelastic`, ...)
    pub name: &'static str,
    /// built or not
    pub on: bool,
    /// what it is and which key decides it
    pub detail: String,
}

/// A value resolved from the scene, in internal units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Resolved {
    /// key path or derived name
    pub key: String,
    /// value in internal units
    pub value: f64,
    /// the internal unit ("" for pure numbers)
    pub unit: &'static str,
    /// where it comes from
    pub note: String,
}

/// Stages, physics and key values of a scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// the stages, in the order they run
    pub stages: Vec<PlannedStage>,
    /// physics built or not
    pub physics: Vec<Switch>,
    /// key values in internal units
    pub values: Vec<Resolved>,
    /// the memory each sized stage would allocate and the ceiling it is held to (absent when
    /// the scene has other problems)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub memory: Option<Memory>,
}

impl Plan {
    /// Whether the plan has `stage`.
    pub fn has(&self, stage: Stage) -> bool {
        self.stages.iter().any(|s| s.stage == stage)
    }
}

/// Numbers derived from the scene that engines use; `None` where the scene does not define
/// them.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Derived {
    /// contact modulus E* = E/(1 − ν²) against the rigid indenter (initial, for hyperfoam), GPa
    #[serde(skip_serializing_if = "Option::is_none")]
    pub effective_modulus_gpa: Option<f64>,
    /// Tabor parameter μ = (Rγ²/(E*² z₀³))^(1/3)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tabor_mu: Option<f64>,
    /// Maugis parameter λ = σ₀(9R/(2πγE*²))^(1/3)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub maugis_lambda: Option<f64>,
    /// JKR contact radius at zero load (9πγR²/(2E*))^(1/3), nm
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jkr_radius_nm: Option<f64>,
    /// the thermal shift of the LJ law, nm (0: none)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub thermal_shift_nm: Option<f64>,
    /// the largest tension of the law as the engines take it (σ_max/b once shifted), GPa
    #[serde(skip_serializing_if = "Option::is_none")]
    pub peak_tension_gpa: Option<f64>,
    /// the law's process zone ℓ = E*γ/σ_peak² (PHYSICS.md), nm
    #[serde(skip_serializing_if = "Option::is_none")]
    pub process_zone_nm: Option<f64>,
    /// expected contact radius at the deepest point of the schedule, nm
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_radius_nm: Option<f64>,
    /// mesh sizes, defaults filled
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<MeshSizes>,
    /// schedule totals
    #[serde(skip_serializing_if = "Option::is_none")]
    pub schedule: Option<ScheduleTotals>,
    /// load control: machine stiffness χ = (1/k₁ + 1/k₂)⁻¹, nN/nm
    #[serde(skip_serializing_if = "Option::is_none")]
    pub machine_series_stiffness: Option<f64>,
    /// tube bending stiffness K = Y·π(r_o⁴ − r_i⁴)/4, nN·nm²
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tube_bending_stiffness: Option<f64>,
    /// number of tubes in the turf's box
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tube_count: Option<f64>,
}

/// Mesh sizes with every default filled, nm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeshSizes {
    /// radius of the body, nm
    pub width_nm: f64,
    /// depth of the body, nm
    pub depth_nm: f64,
    /// smallest element, nm
    pub smallest_nm: f64,
    /// growth factor
    pub grading: f64,
    /// depth of the smallest elements' zone, nm (None: the FE default, half the contact radius)
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fine_depth_nm: Option<f64>,
}

/// A validated scene with defaults filled, its derived numbers and its plan.
#[derive(Debug, Clone, Serialize)]
pub struct ResolvedScene {
    /// the scene file
    pub file: PathBuf,
    /// the scene, in internal units, every default filled
    pub scene: Scene,
    /// derived numbers
    pub derived: Derived,
    /// what will run
    pub plan: Plan,
}

impl ResolvedScene {
    /// The scene's name (the file name when `[scene] name` is absent).
    pub fn name(&self) -> &str {
        self.scene.scene.name.as_deref().unwrap_or("scene")
    }
}

/// Decide the stages and physics of a checked scene and derive its numbers. Cross-section
/// problems (a section that needs another, or that nothing uses) go to `c`.
pub(crate) fn plan(
    scene: &mut Scene,
    totals: Option<ScheduleTotals>,
    c: &mut Checker,
) -> (Plan, Derived) {
    let mut d = Derived {
        schedule: totals,
        ..Derived::default()
    };
    let mut stages = Vec::new();
    let sphere = scene.indenter.as_ref().map(|i| i.shape == Shape::Sphere);
    let model = scene.material.as_ref().map(|m| m.model);
    let linear_sphere = sphere == Some(true) && model == Some(MaterialModel::Linear);
    derive_contact(scene, &mut d);
    check_contact_range(scene, &d, c);

    if linear_sphere {
        let why = match d.tabor_mu {
            Some(mu) => format!(
                "sphere on a linear solid: Hertz, JKR, DMT and Maugis–Dugdale at Tabor μ = {mu:.4}"
            ),
            None => "sphere on a linear solid without [adhesion]: Hertz".to_string(),
        };
        stages.push(PlannedStage {
            stage: Stage::Theory,
            why,
        });
    }
    if scene.halfspace.is_some() {
        let max_mu = crate::halfspace::MAX_VALIDATED_MU;
        if let Some(mu) = d.tabor_mu.filter(|mu| *mu > max_mu * (1.0 + 1e-9)) {
            c.bad(
                "halfspace",
                format!(
                    "Tabor μ = {} (from indenter.radius, adhesion.gamma, adhesion.z0 and the \
                     [material]) is beyond the half-space solver's validated range μ ≤ {max_mu} \
                     (docs/validation-halfspace.md); there JKR, which the theory stage reports, \
                     is within 0.6 % of its pull-off: remove [halfspace] or lower μ",
                    sig(mu)
                ),
            );
        } else if linear_sphere && scene.adhesion.is_some() {
            stages.push(PlannedStage {
                stage: Stage::Halfspace,
                why: "[halfspace]: LJ-adhesive S-curve of a linear half-space under the sphere"
                    .into(),
            });
        } else {
            c.bad(
                "halfspace",
                "needs a sphere [indenter], a linear [material] and [adhesion]",
            );
        }
    }
    plan_discrete(scene, &mut stages, &mut d, c);
    plan_homogenize(scene, &mut stages, c);
    let continuum = plan_continuum(scene, &mut stages, &mut d, c);
    check_users(scene, linear_sphere, continuum, &stages, c);
    if stages.is_empty() && c.problems.is_empty() {
        c.bad(
            "scene",
            "asks for nothing to run: add [indenter] + [material] (theory), [schedule] (continuum), [halfspace], [turf] or [rods] (discrete), or [homogenize]",
        );
    }
    if let Some(field) = first_non_finite(&d).filter(|_| c.problems.is_empty()) {
        c.bad(
            "scene",
            format!("the derived value {field} is not a finite number: some values are out of any sensible range"),
        );
    }
    let physics = switches(scene, continuum, &d);
    let values = values(scene, &d);
    // sizes are estimated only from sections that passed their own checks
    let memory = c
        .problems
        .is_empty()
        .then(|| super::resources::estimate(scene, c));
    (
        Plan {
            stages,
            physics,
            values,
            memory,
        },
        d,
    )
}

/// The first derived number that is NaN or infinite (serde_json writes them as null).
fn first_non_finite(d: &Derived) -> Option<String> {
    let v = serde_json::to_value(d).ok()?;
    let serde_json::Value::Object(map) = v else {
        return None;
    };
    map.iter().find_map(|(k, x)| match x {
        serde_json::Value::Null => Some(k.clone()),
        serde_json::Value::Object(inner) => inner
            .iter()
            .find(|(_, y)| y.is_null())
            .map(|(j, _)| format!("{k}.{j}")),
        _ => None,
    })
}

/// E*, μ, λ, the JKR radius, the thermal shift and the process zone (from `crate::theory`).
fn derive_contact(scene: &Scene, d: &mut Derived) {
    let elastic = scene.material.as_ref().and_then(|m| m.initial_elastic());
    d.effective_modulus_gpa = elastic.map(|(e, nu)| e / (1.0 - nu * nu));
    let Some(a) = &scene.adhesion else {
        return;
    };
    // an error (no [turf]) is reported by check_users; the derived values are then absent
    d.thermal_shift_nm = a.shift_nm(scene.turf.as_ref()).ok();
    let Ok(law) = a.surface_law(scene.turf.as_ref()) else {
        return;
    };
    d.peak_tension_gpa = Some(law.max_tension());
    let Some(es) = d.effective_modulus_gpa else {
        return;
    };
    d.process_zone_nm = process_zone(&law, es).ok();
    if let Some(i) = &scene.indenter {
        if let Ok(s) = Sphere::new(i.radius.0, es, law.gamma()) {
            d.tabor_mu = tabor::tabor_mu(&s, law.z0()).ok();
            d.maugis_lambda = tabor::lambda_from_law(&s, &law).ok();
            d.jkr_radius_nm = Some(jkr::zero_load_radius(&s));
        }
    }
}

/// The dimensionless contact numbers must come out finite and positive: a modulus so large
/// that E*² overflows double precision gives μ = λ = 0, which no engine can use (the theory
/// stage would fail at run time without naming a key).
fn check_contact_range(scene: &Scene, d: &Derived, c: &mut Checker) {
    let bad = [
        ("Tabor μ", d.tabor_mu),
        ("Maugis λ", d.maugis_lambda),
        ("JKR radius a0", d.jkr_radius_nm),
        ("process zone ℓ", d.process_zone_nm),
    ]
    .into_iter()
    .find_map(|(name, v)| {
        v.filter(|v| !(v.is_finite() && *v > 0.0))
            .map(|v| (name, v))
    });
    let (Some((name, v)), Some(m)) = (bad, &scene.material) else {
        return;
    };
    let key = if m.youngs.is_some() {
        "material.youngs"
    } else {
        "material"
    };
    c.bad(
        key,
        format!(
            "gives E* = {} GPa and {name} = {v} with indenter.radius, adhesion.gamma and adhesion.z0: \
             the numbers leave the range of double precision; use a modulus (and radius, γ, z0) \
             within many orders of magnitude of each other",
            d.effective_modulus_gpa
                .map_or("?".into(), |e| format!("{e:.4e}"))
        ),
    );
}

fn plan_discrete(scene: &Scene, stages: &mut Vec<PlannedStage>, d: &mut Derived, c: &mut Checker) {
    match (&scene.turf, &scene.rods) {
        (Some(_), Some(_)) => c.bad(
            "rods",
            "cannot be combined with [turf]: explicit rods and a generated turf are alternatives",
        ),
        (Some(t), None) => {
            d.tube_bending_stiffness = Some(t.tube.bending_stiffness());
            d.tube_count = Some(t.tube_count());
            match &scene.compression {
                Some(k) => stages.push(PlannedStage {
                    stage: Stage::Discrete,
                    why: format!(
                        "[turf] + [compression]: {} tubes{} {} {}{}{}",
                        t.tube_count(),
                        t.packing.as_ref().map_or(String::new(), |p| format!(
                            " packed to {:.3e} /cm^2 (rigid-body chains)",
                            p.density.0 * 1e14
                        )),
                        match k.mode {
                            crate::scene::compression::Mode::Axial => "compressed to strain",
                            crate::scene::compression::Mode::Lateral =>
                                "compressed across the tubes (the box in x) to strain",
                            crate::scene::compression::Mode::Shear =>
                                "sheared along the tubes (the tips in x) to shear",
                        },
                        k.to.0,
                        if k.unload { " and unloaded" } else { "" },
                        if t.realisations > 1 {
                            format!(
                                ", {} realisations (mean and 95 % confidence interval)",
                                t.realisations
                            )
                        } else {
                            String::new()
                        }
                    ),
                }),
                None => c.bad("turf", "needs [compression] to say how the turf is driven"),
            }
        }
        (None, Some(r)) => {
            d.tube_bending_stiffness = Some(r.tube.bending_stiffness());
            let what = if scene.compression.is_some() {
                "compressed by the platen"
            } else {
                "in equilibrium under their end loads"
            };
            stages.push(PlannedStage {
                stage: Stage::Discrete,
                why: format!("[rods]: {} rod(s) {what}", r.rod.len()),
            });
        }
        (None, None) => {
            if scene.compression.is_some() {
                c.bad("compression", "needs [turf] or [rods] to compress");
            }
        }
    }
}

fn plan_homogenize(scene: &Scene, stages: &mut Vec<PlannedStage>, c: &mut Checker) {
    let Some(h) = &scene.homogenize else {
        return;
    };
    let discrete = stages.iter().any(|s| s.stage == Stage::Discrete);
    let why = match h.curve {
        Curve::TangentLaw => "[homogenize]: hyperfoam card fitted to the tangent-modulus law",
        Curve::Loading | Curve::Unloading => {
            if !discrete || scene.compression.is_none() {
                c.bad(
                    "homogenize.curve",
                    "\"loading\" and \"unloading\" fit the discrete stage's curve: add [turf] + [compression], or use \"tangent-law\"",
                );
            }
            if scene
                .compression
                .as_ref()
                .is_some_and(|k| k.mode != crate::scene::compression::Mode::Axial)
            {
                c.bad(
                    "compression.mode",
                    "only \"axial\" gives the curve [homogenize] fits (the lateral and shear \
                     tests measure the transverse response): set mode = \"axial\" or remove \
                     [homogenize]",
                );
            }
            if h.curve == Curve::Unloading && !scene.compression.as_ref().is_some_and(|k| k.unload)
            {
                c.bad(
                    "homogenize.curve",
                    "\"unloading\" needs compression.unload = true",
                );
            }
            "[homogenize]: hyperfoam card fitted to the discrete stage's curve"
        }
    };
    stages.push(PlannedStage {
        stage: Stage::Homogenize,
        why: why.into(),
    });
}

/// The continuum stage and the mesh defaults; returns whether it runs.
fn plan_continuum(
    scene: &mut Scene,
    stages: &mut Vec<PlannedStage>,
    d: &mut Derived,
    c: &mut Checker,
) -> bool {
    if scene.schedule.is_none() {
        return false;
    }
    let (Some(ind), Some(mat)) = (&scene.indenter, &scene.material) else {
        c.bad(
            "schedule",
            "needs [indenter] and [material]: the continuum stage indents a solid",
        );
        return false;
    };
    if mat.model == MaterialModel::Card && mat.card.is_none() && scene.homogenize.is_none() {
        c.bad(
            "material.card",
            "is missing: model = \"card\" needs a card file, or [homogenize] to fit one in this run",
        );
    }
    if mat.model == MaterialModel::Card && mat.card.is_some() && scene.homogenize.is_some() {
        c.bad(
            "material.card",
            "is given while [homogenize] fits a card in this run: remove one of them",
        );
    }
    let machine = scene.machine.get_or_insert_with(Machine::default).clone();
    let solver = scene.solver.get_or_insert_with(Solver::default).clone();
    let mesh = scene.mesh.get_or_insert_with(Mesh::default).clone();
    let totals = d.schedule.unwrap_or(ScheduleTotals {
        duration_s: 0.0,
        max_depth_nm: 0.0,
        max_load_nn: 0.0,
    });
    let (r, shape) = (ind.radius.0, ind.shape);
    let tip_depth = ind.tip_depth.map_or(f64::INFINITY, |t| t.0);
    let a = match machine.control {
        Control::Displacement => Some(radius_at_depth(r, shape, tip_depth, totals.max_depth_nm)),
        Control::Load => d
            .effective_modulus_gpa
            .and_then(|es| hertz::contact_radius(totals.max_load_nn, r, es).ok()),
    };
    let a = match (a, d.jkr_radius_nm) {
        (Some(a), Some(a0)) => Some(a.max(a0)),
        (a, _) => a,
    }
    .filter(|a| *a > 0.0);
    d.contact_radius_nm = a;
    d.machine_series_stiffness = machine.series_stiffness();
    let process_zone = d.process_zone_nm;
    let pick = |given: Option<super::quantity::Length>,
                factor: Option<f64>,
                key: &str,
                c: &mut Checker| match (given, factor) {
        (Some(v), _) => v.0,
        (None, Some(v)) => v,
        (None, None) => {
            c.bad(
                key,
                "is missing: the expected contact radius is unknown before the run (the schedule never indents), so give mesh.width, mesh.depth and mesh.smallest",
            );
            f64::NAN
        }
    };
    let smallest_default = a.map(|a| {
        let by_contact = a / ELEMENTS_PER_CONTACT_RADIUS;
        process_zone.map_or(by_contact, |p| {
            by_contact.min(p / ELEMENTS_PER_PROCESS_ZONE)
        })
    });
    // a card's moduli are known only when the run reads it: the sizes the scene does not
    // give are then derived by the FE engine from the card (the same rules, with E*)
    let card = mat.model == MaterialModel::Card;
    let all_given = mesh.width.is_some() && mesh.depth.is_some() && mesh.smallest.is_some();
    d.mesh = (!card || all_given).then(|| MeshSizes {
        width_nm: pick(
            mesh.width,
            a.map(|a| WIDTH_PER_CONTACT_RADIUS * a),
            "mesh.width",
            c,
        ),
        depth_nm: pick(
            mesh.depth,
            a.map(|a| DEPTH_PER_CONTACT_RADIUS * a),
            "mesh.depth",
            c,
        ),
        smallest_nm: pick(mesh.smallest, smallest_default, "mesh.smallest", c),
        grading: mesh.grading.0,
        fine_depth_nm: mesh.fine_depth.map(|l| l.0),
    });
    let kin = match solver.kinematics {
        Kinematics::Finite => "finite deformation",
        Kinematics::Small => "small strain",
    };
    let sizing = if d.mesh.is_none() {
        "; mesh sizes not given are derived at run time from the card's initial moduli"
    } else {
        ""
    };
    stages.push(PlannedStage {
        stage: Stage::Continuum,
        why: format!(
            "[schedule] + [indenter] + [material]: axisymmetric FE indentation, {kin}, {} solver, {} control{sizing}",
            match solver.method {
                super::solver::Method::Newton => "Newton",
                super::solver::Method::Riks => "Riks arc-length",
            },
            match machine.control {
                Control::Displacement => "displacement",
                Control::Load => "load",
            }
        ),
    });
    true
}

/// Contact radius of the rigid indenter at depth δ by geometry: √(Rδ) on the spherical tip,
/// then along the equivalent cone for a blunt Berkovich.
fn radius_at_depth(r: f64, shape: Shape, tip_depth: f64, depth: f64) -> f64 {
    let depth = depth.max(0.0);
    match shape {
        Shape::Sphere => (r * depth).sqrt(),
        Shape::BerkovichBlunt if depth <= tip_depth => (r * depth).sqrt(),
        Shape::BerkovichBlunt => {
            let cone = BERKOVICH_EQUIVALENT_CONE_DEG.to_radians().tan();
            (r * tip_depth).sqrt() + (depth - tip_depth) * cone
        }
    }
}

/// Sections that only some stages use must have one of them.
fn check_users(
    scene: &Scene,
    linear_sphere: bool,
    continuum: bool,
    stages: &[PlannedStage],
    c: &mut Checker,
) {
    let homogenize = stages.iter().any(|s| s.stage == Stage::Homogenize);
    let uses_indenter = continuum || linear_sphere;
    if !uses_indenter {
        if scene.indenter.is_some() {
            c.bad("indenter", "is not used by any stage: add [schedule] (continuum), or use a sphere on a linear [material] (theory)");
        }
        if scene.material.is_some() {
            c.bad("material", "is not used by any stage: add [indenter] and [schedule] (continuum), or model = \"linear\" under a sphere (theory)");
        }
        let discrete_sphere = scene
            .compression
            .as_ref()
            .is_some_and(|k| k.sphere_adhesion != super::compression::SphereAdhesion::None);
        if scene.adhesion.is_some() && !discrete_sphere {
            c.bad(
                "adhesion",
                "is not used by any stage: it acts between an [indenter] and a [material], or \
                 the discrete sphere (compression.sphere_adhesion)",
            );
        }
    }
    if scene.viscoelastic.is_some() && !continuum && !homogenize {
        c.bad("viscoelastic", "is not used by any stage: relaxation acts in the continuum stage ([schedule]) or goes into a [homogenize] card");
    }
    if !continuum {
        for (name, present) in [
            ("machine", scene.machine.is_some()),
            ("mesh", scene.mesh.is_some()),
            ("solver", scene.solver.is_some()),
        ] {
            if present {
                c.bad(
                    name,
                    "is only used by the continuum stage, which needs [schedule]",
                );
            }
        }
        if scene.adhesion.as_ref().is_some_and(|a| a.damping.is_some()) {
            c.bad(
                "adhesion.damping",
                "is only used by the continuum stage, which needs [schedule]",
            );
        }
    }
    if let Some(a) = &scene.adhesion {
        if a.thermal_shift == ThermalShift::FromTubes && scene.turf.is_none() {
            c.bad(
                "adhesion.thermal_shift",
                "true needs [turf] (turf.growth.length, turf.tube.r_o, turf.tube.r_i, turf.tube.youngs) to compute the amplitude u (seed eq. 5.9); give a length instead, e.g. \"5 nm\"",
            );
        }
    }
}

fn switches(scene: &Scene, continuum: bool, d: &Derived) -> Vec<Switch> {
    let mut s = Vec::new();
    let mut push = |name, on, detail: String| s.push(Switch { name, on, detail });
    surface_switches(scene, d, &mut push);
    if continuum {
        machine_switches(scene, d, &mut push);
    }
    discrete_switches(scene, &mut push);
    s
}

/// A switch's name, whether it is on, and what it is.
type Push<'a> = dyn FnMut(&'static str, bool, String) + 'a;

/// Adhesion, its thermal shift, contact damping and viscoelasticity.
fn surface_switches(scene: &Scene, d: &Derived, push: &mut Push) {
    match &scene.adhesion {
        Some(a) => push(
            "lj_adhesion",
            true,
            format!(
                "[adhesion]: {:?} law, γ = {} J/m^2, z0 = {} nm; contact search on",
                a.law,
                sig(a.gamma.0),
                sig(a.z0.0)
            )
            .replace("Lj93", "LJ 9-3")
            .replace("Lj104", "LJ 10-4"),
        ),
        None => push(
            "lj_adhesion",
            false,
            "no [adhesion]: no contact search, no LJ law".into(),
        ),
    }
    let shift = d.thermal_shift_nm.unwrap_or(0.0);
    push(
        "thermal_shift",
        shift > 0.0,
        if shift > 0.0 {
            format!("adhesion.thermal_shift: attractive branch moved out by u = {shift:.4} nm")
        } else {
            "no thermal shift of the LJ law".into()
        },
    );
    let damping = scene.adhesion.as_ref().and_then(|a| a.damping.as_ref());
    push(
        "contact_damping",
        damping.is_some(),
        match damping {
            Some(dm) => format!(
                "[adhesion.damping]: c0 = {} GPa*s/nm up to g' = {} nm",
                dm.c0.0, dm.gap.0
            ),
            None => "no contact damping".into(),
        },
    );
    push(
        "viscoelastic",
        scene.viscoelastic.is_some(),
        match &scene.viscoelastic {
            Some(v) => format!(
                "[viscoelastic]: {} Prony term(s), long-term fraction {}",
                v.g.len(),
                v.long_term_fraction()
            ),
            None => "no [viscoelastic]: no internal variables".into(),
        },
    );
}

/// The FE's machine and kinematics.
fn machine_switches(scene: &Scene, d: &Derived, push: &mut Push) {
    let m = scene.machine.clone().unwrap_or_default();
    let detail = match (m.control, m.stiffness, d.machine_series_stiffness) {
        (Control::Displacement, Some(k), _) => {
            format!(
                "displacement control through a spring K = {} nN/nm",
                sig(k.0)
            )
        }
        (Control::Displacement, None, _) => "displacement control, rigid drive".into(),
        (Control::Load, _, Some(chi)) => {
            format!(
                "load control through springs k1, k2 (χ = {} nN/nm)",
                sig(chi)
            )
        }
        (Control::Load, _, None) => "load control, no machine springs".into(),
    };
    push("machine", true, detail);
    let small = scene
        .solver
        .as_ref()
        .is_some_and(|s| s.kinematics == Kinematics::Small);
    push(
        "finite_kinematics",
        !small,
        if small {
            "small strain (solver.kinematics = \"small\")".into()
        } else {
            match &scene.adhesion {
                Some(a) => format!(
                    "finite deformation, total Lagrangian; the LJ law on the {} surface \
                     (adhesion.area)",
                    match a.area {
                        SurfaceArea::Reference => "reference",
                        SurfaceArea::Current => "current",
                    }
                ),
                None => "finite deformation, total Lagrangian".into(),
            }
        },
    );
}

/// The discrete engine's tube contacts, periodicity and sphere contact.
fn discrete_switches(scene: &Scene, push: &mut Push) {
    let vdw = scene
        .turf
        .as_ref()
        .and_then(|t| t.vdw.as_ref())
        .or(scene.rods.as_ref().and_then(|r| r.vdw.as_ref()));
    if scene.turf.is_some() || scene.rods.is_some() {
        push(
            "tube_contacts",
            vdw.is_some(),
            match vdw {
                Some(v) => format!(
                    "vdW line contacts, γ_L = {} nN, {} kernel, broadphase search",
                    v.gamma_line.0,
                    match v.kernel {
                        crate::scene::turf::VdwKernel::Tabulated => "tabulated",
                        crate::scene::turf::VdwKernel::Quadrature => "quadrature",
                    }
                ),
                None => "no [turf.vdw]/[rods.vdw]: tubes do not interact".into(),
            },
        );
    }
    if let Some(t) = &scene.turf {
        push(
            "periodic",
            t.periodic,
            format!("turf.periodic = {}", t.periodic),
        );
    }
    if let Some(k) = scene
        .compression
        .as_ref()
        .filter(|k| k.indenter == super::compression::Indenter::Sphere)
    {
        use super::compression::{SphereAdhesion, Tangential};
        let adhesion = match k.sphere_adhesion {
            SphereAdhesion::None => "non-adhesive penalty sphere",
            SphereAdhesion::Lj => {
                "LJ adhesion ([adhesion] law, unshifted) across and along the tubes"
            }
            SphereAdhesion::LjShifted => {
                "LJ adhesion ([adhesion] law, thermally shifted) across and along the tubes"
            }
        };
        let tangential = match k.sphere_tangential {
            Tangential::Frictionless => "frictionless",
            Tangential::Stick => "touched nodes held where they touch (stick)",
        };
        push(
            "sphere_contact",
            k.sphere_adhesion != SphereAdhesion::None || k.sphere_tangential == Tangential::Stick,
            format!("discrete sphere: {adhesion}; {tangential}"),
        );
    }
}

fn values(scene: &Scene, d: &Derived) -> Vec<Resolved> {
    let mut v = Vec::new();
    let mut put = |key: &str, value: f64, unit: &'static str, note: &str| {
        if value.is_finite() {
            v.push(Resolved {
                key: key.into(),
                value,
                unit,
                note: note.into(),
            });
        }
    };
    indenter_values(scene, d, &mut put);
    adhesion_values(scene, d, &mut put);
    size_values(scene, d, &mut put);
    v
}

/// A resolved value: key, value, unit, note.
type Put<'a> = dyn FnMut(&str, f64, &'static str, &str) + 'a;

/// The indenter and the material, with E*.
fn indenter_values(scene: &Scene, d: &Derived, put: &mut Put) {
    if let Some(i) = &scene.indenter {
        put("indenter.radius", i.radius.0, "nm", "");
        if let Some(t) = i.tip_depth {
            put("indenter.tip_depth", t.0, "nm", "sphere–cone transition");
        }
    }
    if let Some(m) = &scene.material {
        if let Some(e) = m.youngs {
            put("material.youngs", e.0, "GPa", "");
        }
        if let Some(nu) = m.poisson {
            put("material.poisson", nu.0, "", "");
        }
        if let Some(mu) = &m.mu {
            for (k, x) in mu.iter().enumerate() {
                put(&format!("material.mu[{k}]"), x.0, "GPa", "");
            }
        }
    }
    if let Some(es) = d.effective_modulus_gpa {
        put("E*", es, "GPa", "E/(1 - ν²), rigid indenter");
    }
}

/// The adhesion law, its shift, and the adhesion parameters it gives (Tabor, Maugis, JKR, the
/// process zone).
fn adhesion_values(scene: &Scene, d: &Derived, put: &mut Put) {
    if let Some(a) = &scene.adhesion {
        put("adhesion.gamma", a.gamma.0, "J/m^2", "");
        put("adhesion.z0", a.z0.0, "nm", "");
        put(
            "adhesion.sigma0",
            a.law().max_tension(),
            "GPa",
            "largest tension of the unshifted law",
        );
    }
    if let (Some(u), Some(a)) = (d.thermal_shift_nm, &scene.adhesion) {
        let note = match a.thermal_shift {
            ThermalShift::FromTubes => format!(
                "seed eq. 5.9: RMS tip amplitude of the [turf] tubes at {} K",
                sig(a.temperature.0)
            ),
            ThermalShift::Amplitude(_) => "given (adhesion.thermal_shift)".into(),
            ThermalShift::Off => "none (adhesion.thermal_shift = false)".into(),
        };
        put("thermal shift u", u, "nm", &note);
    }
    if let Some(x) = d.tabor_mu {
        put("Tabor μ", x, "", "(Rγ²/(E*² z0³))^(1/3)");
    }
    if let Some(x) = d.maugis_lambda {
        put("Maugis λ", x, "", "σ0 (9R/(2πγE*²))^(1/3)");
    }
    if let Some(x) = d.jkr_radius_nm {
        put("JKR a0", x, "nm", "contact radius at zero load");
    }
    if let Some(x) = d.peak_tension_gpa {
        put(
            "peak tension",
            x,
            "GPa",
            "of the law the engines take (σ_max/b once shifted)",
        );
    }
    if let Some(x) = d.process_zone_nm {
        put(
            "process zone ℓ",
            x,
            "nm",
            "E*γ/σ_peak²: adhesive meshes resolve it",
        );
    }
}

/// The schedule, the mesh, the machine and the turf's sizes.
fn size_values(scene: &Scene, d: &Derived, put: &mut Put) {
    if let Some(t) = &d.schedule {
        put("schedule duration", t.duration_s, "s", "");
        put("schedule max depth", t.max_depth_nm, "nm", "");
        if t.max_load_nn > 0.0 {
            put("schedule max load", t.max_load_nn, "nN", "");
        }
    }
    if let Some(a) = d.contact_radius_nm {
        let note = if d.mesh.is_some() {
            "sets the mesh defaults"
        } else {
            "by geometry; the mesh is sized at run time from the card"
        };
        put("expected contact radius", a, "nm", note);
    }
    if let Some(m) = &d.mesh {
        put("mesh.width", m.width_nm, "nm", "");
        put("mesh.depth", m.depth_nm, "nm", "");
        put("mesh.smallest", m.smallest_nm, "nm", "");
        if let Some(f) = m.fine_depth_nm {
            put("mesh.fine_depth", f, "nm", "zone of smallest elements");
        }
    }
    if let Some(k) = d.machine_series_stiffness {
        put("machine χ", k, "nN/nm", "(1/k1 + 1/k2)⁻¹");
    }
    if let Some(k) = d.tube_bending_stiffness {
        put(
            "tube bending stiffness",
            k,
            "nN*nm^2",
            "Y π (r_o⁴ - r_i⁴)/4",
        );
    }
    if let Some(n) = d.tube_count {
        put("tube count", n, "", "density × box area");
    }
    if let Some(h) = &scene.halfspace {
        put("halfspace.cells_per_zone", h.cells_per_zone, "", "");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sig_keeps_six_figures_and_never_prints_hundreds_of_digits() {
        assert_eq!(sig(0.46), "0.46");
        assert_eq!(sig(1.0 / 3.0), "0.333333");
        assert_eq!(sig(84852.81374), "84852.8");
        assert_eq!(sig(1e-300), "1e-300");
        assert_eq!(sig(2.5e15), "2.5e15");
        assert_eq!(sig(0.0), "0");
        assert!(sig(-1.234567e-9).len() < 12);
    }

    #[test]
    fn blunt_berkovich_radius_is_continuous_at_the_tip_depth() {
        let (r, h) = (1800.0, 105.0);
        let below = radius_at_depth(r, Shape::BerkovichBlunt, h, h - 1e-9);
        let above = radius_at_depth(r, Shape::BerkovichBlunt, h, h + 1e-9);
        assert!((below - above).abs() < 1e-6);
        assert_eq!(
            radius_at_depth(r, Shape::Sphere, h, 10.0),
            (r * 10.0).sqrt()
        );
    }
}
