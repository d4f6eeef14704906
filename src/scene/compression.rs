//! `[compression]`: the discrete drive — a rigid platen (or, with `indenter = "sphere"`, a rigid
//! sphere of radius `sphere_radius` over the box centre) pressed onto the turf (or
//! rods) along a nominal-strain path, optionally unloaded again to measure reversibility; each step is
//! relaxed to equilibrium by FIRE or Newton. The sphere is frictionless and non-adhesive unless
//! `sphere_adhesion` gives it the `[adhesion]` law (`crate::discrete::sphere_adhesion`) and
//! `sphere_tangential = "stick"` holds the nodes it touches (`crate::discrete::sphere_stick`).

use super::adhesion::{Adhesion, ThermalShift};
use super::check::Checker;
use super::quantity::{Force, Length, Number, Stiffness};
use serde::{Deserialize, Serialize};

/// How the platen meets the tube tops.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Platen {
    /// the tops slide freely on the platen
    Frictionless,
    /// the tops move with the platen
    Bonded,
}

/// What presses on the turf.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Indenter {
    /// a flat platen over the whole box (stress–strain curve)
    Platen,
    /// a rigid frictionless sphere over the box centre (load–depth curve)
    Sphere,
}

/// The sphere's adhesion to the tubes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SphereAdhesion {
    /// none: the penalty contact alone
    #[default]
    None,
    /// the `[adhesion]` law (`adhesion.law`, `gamma`, `z0`) without thermal shift
    Lj,
    /// the `[adhesion]` law thermally shifted by `adhesion.thermal_shift` (seed §5.2), as the
    /// continuum's
    LjShifted,
}

/// The tangential contact of a sphere on the tubes (`compression.sphere_tangential`) or of the
/// FE's indenter on the continuum (`indenter.tangential`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Tangential {
    /// the surface (the nodes) slides freely
    #[default]
    Frictionless,
    /// held tangentially where it first touched (a penalty spring moving with the indenter)
    /// until it leaves contact (a tube's node also when it pulls beyond `stick_release`)
    Stick,
}

/// Default tangential stiffness of the stick option, nN/nm: a held node carrying 1 nN
/// tangentially is 0.01 nm from its anchor, four orders of magnitude stiffer than the lateral
/// bending stiffness 3YI/L³ of a 1 µm seed tube (0.07 nN/nm).
pub const DEFAULT_STICK_STIFFNESS: f64 = 100.0;

fn is_default<T: Default + PartialEq>(v: &T) -> bool {
    *v == T::default()
}

/// Which deformation the drive imposes on the turf.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// the platen (or sphere) pressed down along the tubes
    #[default]
    Axial,
    /// the periodic box shrinks in x, the top free (`crate::discrete::rve`)
    Lateral,
    /// the tips moved in x relative to the clamped bases, free in z (`crate::discrete::rve`)
    Shear,
}

/// Equilibrium solver of each step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DiscreteSolver {
    /// FIRE relaxation (robust through buckling and contact changes)
    Fire,
    /// Newton with line search (fast near equilibrium)
    Newton,
}

/// `[compression]`: the strain path and its solver.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Compression {
    /// `"axial"` (the platen or sphere), `"lateral"` (the box compressed in x) or `"shear"`
    /// (the tips moved in x, longitudinal shear); `to` is then the lateral or shear strain.
    /// The lateral and shear tests need the flat platen's defaults (no sphere) and the loading
    /// curve they give is not fitted by `[homogenize]`. Default `"axial"`.
    #[serde(default, skip_serializing_if = "is_default")]
    pub mode: Mode,
    /// `"frictionless"` or `"bonded"`. Default `"frictionless"`.
    #[serde(default = "default_platen")]
    pub platen: Platen,
    /// `"platen"` or `"sphere"`. Default `"platen"`.
    #[serde(default = "default_indenter")]
    pub indenter: Indenter,
    /// Radius of the sphere, > 0; required with `indenter = "sphere"`, not allowed otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere_radius: Option<Length>,
    /// The sphere's adhesion, only with `indenter = "sphere"`: `"none"`, `"lj"` (the
    /// `[adhesion]` law unshifted) or `"lj_shifted"` (shifted by `adhesion.thermal_shift`,
    /// which must then not be false). Needs `[adhesion]` unless `"none"`. Default `"none"`.
    #[serde(default, skip_serializing_if = "is_default")]
    pub sphere_adhesion: SphereAdhesion,
    /// The sphere's tangential contact, only with `indenter = "sphere"`: `"frictionless"` or
    /// `"stick"`. Default `"frictionless"`.
    #[serde(default, skip_serializing_if = "is_default")]
    pub sphere_tangential: Tangential,
    /// Tangential stiffness of `"stick"`, > 0 (a stiffness, e.g. "100 nN/nm"). Default 100
    /// nN/nm; only with `sphere_tangential = "stick"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stick_stiffness: Option<Stiffness>,
    /// Tensile normal force beyond which a held node is let go, ≥ 0 (a force). Default: held
    /// until it leaves contact; only with `sphere_tangential = "stick"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stick_release: Option<Force>,
    /// Final nominal compressive strain, in (0, 1). Required.
    pub to: Number,
    /// Strain steps to reach `to`, ≥ 1. Default 20.
    #[serde(default = "default_steps")]
    pub steps: usize,
    /// Also unload back to zero strain, in as many steps. Default false.
    #[serde(default)]
    pub unload: bool,
    /// After unloading, raise the adhesive sphere this far (a length > 0) above its first
    /// touch, in `retract_steps` steps: the pull-off. Only with `indenter = "sphere"`,
    /// `sphere_adhesion` other than `"none"` and `unload = true`. Default: no retract.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub retract: Option<Length>,
    /// Steps of the retract, ≥ 1. Default 20; only with `retract`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub retract_steps: Option<usize>,
    /// `"fire"` or `"newton"`. Default `"fire"`.
    #[serde(default = "default_solver")]
    pub solver: DiscreteSolver,
    /// Largest residual force on a node at equilibrium, nN. Default 1e-3 nN.
    #[serde(default = "default_tolerance")]
    pub tolerance: Force,
    /// Iterations per step before the stage gives up, ≥ 1. Default 100000.
    #[serde(default = "default_iterations")]
    pub max_iterations: usize,
}

fn default_platen() -> Platen {
    Platen::Frictionless
}
fn default_indenter() -> Indenter {
    Indenter::Platen
}
fn default_steps() -> usize {
    20
}
fn default_solver() -> DiscreteSolver {
    DiscreteSolver::Fire
}
fn default_tolerance() -> Force {
    Force(1e-3)
}
/// Steps of a retract when `retract_steps` is not given.
pub const DEFAULT_RETRACT_STEPS: usize = 20;

fn default_iterations() -> usize {
    100_000
}

impl Compression {
    /// Check the keys; `adhesion` is the scene's `[adhesion]`, which `sphere_adhesion` uses.
    pub(crate) fn check(&self, c: &mut Checker, adhesion: Option<&Adhesion>) {
        c.number_in("compression.to", self.to.0, 0.0, 1.0, true);
        match (self.indenter, self.sphere_radius) {
            (Indenter::Sphere, None) => c.bad(
                "compression.sphere_radius",
                "is required with indenter = \"sphere\" (a length > 0)",
            ),
            (Indenter::Sphere, r) => c.positive_opt("compression.sphere_radius", r),
            (Indenter::Platen, Some(_)) => c.unused(
                "compression.sphere_radius",
                "with indenter = \"platen\" (allowed: \"platen\", \"sphere\")",
            ),
            (Indenter::Platen, None) => {}
        }
        self.check_sphere_contact(c, adhesion);
        self.check_retract(c);
        if self.mode != Mode::Axial {
            let name = if self.mode == Mode::Lateral {
                "lateral"
            } else {
                "shear"
            };
            if self.indenter != Indenter::Platen {
                c.bad(
                    "compression.mode",
                    format!(
                        "\"{name}\" deforms the box, not an indenter: it needs indenter = \"platen\" \
                         (allowed modes with a sphere: \"axial\")"
                    ),
                );
            }
            if self.platen != Platen::Frictionless {
                c.unused(
                    "compression.platen",
                    &format!("with mode = \"{name}\" (no platen)"),
                );
            }
        }
        c.count_at_least("compression.steps", self.steps, 1);
        c.positive("compression.tolerance", self.tolerance);
        c.count_at_least("compression.max_iterations", self.max_iterations, 1);
    }

    /// Steps of the whole path after the start: loading, unloading and retract.
    pub fn path_steps(&self) -> usize {
        self.steps * if self.unload { 2 } else { 1 } + self.retract_steps()
    }

    /// Steps of the retract (0 without one).
    pub fn retract_steps(&self) -> usize {
        match self.retract {
            Some(_) => self.retract_steps.unwrap_or(DEFAULT_RETRACT_STEPS),
            None => 0,
        }
    }

    /// The retract keys: a pull-off needs an adhesive sphere that has unloaded.
    fn check_retract(&self, c: &mut Checker) {
        let Some(r) = self.retract else {
            if self.retract_steps.is_some() {
                c.unused("compression.retract_steps", "without compression.retract");
            }
            return;
        };
        c.positive_opt("compression.retract", Some(r));
        if self.indenter != Indenter::Sphere || self.sphere_adhesion == SphereAdhesion::None {
            c.bad(
                "compression.retract",
                "measures the pull-off of an adhesive sphere: it needs indenter = \"sphere\" and \
                 sphere_adhesion = \"lj\" or \"lj_shifted\" (without adhesion nothing holds \
                 the sphere above its first touch)",
            );
        }
        if !self.unload {
            c.bad(
                "compression.retract",
                "continues the unloading above the first touch: it needs unload = true",
            );
        }
        if let Some(n) = self.retract_steps {
            c.count_at_least("compression.retract_steps", n, 1);
        }
    }

    /// The sphere's adhesion and tangential keys.
    fn check_sphere_contact(&self, c: &mut Checker, adhesion: Option<&Adhesion>) {
        let sphere = self.indenter == Indenter::Sphere;
        let why =
            "with indenter = \"platen\" (the sphere's contact options need indenter = \"sphere\")";
        if !sphere && self.sphere_adhesion != SphereAdhesion::None {
            c.unused("compression.sphere_adhesion", why);
        }
        if !sphere && self.sphere_tangential != Tangential::Frictionless {
            c.unused("compression.sphere_tangential", why);
        }
        match (self.sphere_adhesion, adhesion) {
            (SphereAdhesion::None, _) => {}
            (_, None) => c.bad(
                "compression.sphere_adhesion",
                "needs [adhesion] (law, gamma, z0 and, for \"lj_shifted\", thermal_shift); \
                 allowed: \"none\", \"lj\", \"lj_shifted\"",
            ),
            (SphereAdhesion::LjShifted, Some(a)) if a.thermal_shift == ThermalShift::Off => c.bad(
                "compression.sphere_adhesion",
                "\"lj_shifted\" needs adhesion.thermal_shift = true or a length (it is false); \
                 use \"lj\" for the unshifted law",
            ),
            _ => {}
        }
        if self.sphere_tangential != Tangential::Stick {
            let why = "without sphere_tangential = \"stick\"";
            if self.stick_stiffness.is_some() {
                c.unused("compression.stick_stiffness", why);
            }
            if self.stick_release.is_some() {
                c.unused("compression.stick_release", why);
            }
        }
        c.positive_opt("compression.stick_stiffness", self.stick_stiffness);
        if let Some(f) = self.stick_release {
            if !(f.0 >= 0.0 && f.0.is_finite()) {
                c.bad(
                    "compression.stick_release",
                    format!("{} nN is not allowed: must be >= 0 and finite", f.0),
                );
            }
        }
    }
}
