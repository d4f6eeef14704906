//! `[turf]`: the discrete turf — tubes as elastica chains grown from a substrate, interacting
//! by van der Waals line contacts (seed ch. 2.4). Tubes are hollow cylinders with bending
//! stiffness K = Y·π(r_o⁴ − r_i⁴)/4 (the axial moment; seed values Y = 0.4 TPa, r_o = 20 nm,
//! r_i = 17.3 nm, K = 2.21×10⁷ nN·nm²), about 7 µm long, at an areal density of order
//! 10¹⁰ cm⁻². Tube–tube adhesion: γ_L of order 1 nN at an axis separation 2r_o + 0.34 nm.

use super::check::Checker;
use super::quantity::{ArealDensity, Length, LineEnergy, Number, Pressure};
use serde::{Deserialize, Serialize};

/// `[turf.tube]` / `[rods.tube]`: the cross-section and modulus of a tube.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tube {
    /// Outer radius r_o, nm. Required, positive.
    pub r_o: Length,
    /// Inner radius r_i, nm, 0 ≤ r_i < r_o. Required.
    pub r_i: Length,
    /// Young's modulus of the wall Y, GPa. Required, positive.
    pub youngs: Pressure,
    /// Length of one chain segment (the discretisation), nm. Default: a twentieth of the tube
    /// length (`[turf]`) or of the rod (`[rods]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segment: Option<Length>,
}

impl Tube {
    pub(crate) fn check(&self, c: &mut Checker, section: &str) {
        c.positive(&format!("{section}.r_o"), self.r_o);
        c.positive(&format!("{section}.youngs"), self.youngs);
        c.positive_opt(&format!("{section}.segment"), self.segment);
        if self.r_i.0 < 0.0 || self.r_i.0 >= self.r_o.0 {
            c.bad(
                format!("{section}.r_i"),
                format!(
                    "{} nm is not allowed: the inner radius must satisfy 0 <= r_i < r_o = {} nm",
                    self.r_i.0, self.r_o.0
                ),
            );
        }
    }

    /// Bending stiffness K = Y·π(r_o⁴ − r_i⁴)/4, nN·nm².
    pub fn bending_stiffness(&self) -> f64 {
        self.youngs.0 * std::f64::consts::PI * (self.r_o.0.powi(4) - self.r_i.0.powi(4)) / 4.0
    }
}

/// `[turf.growth]`: how the tubes grow from the substrate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Growth {
    /// Mean tube length (the turf height), nm. Required, positive.
    pub length: Length,
    /// Relative standard deviation of the lengths, in [0, 1). Default 0.
    #[serde(default)]
    pub length_spread: Number,
    /// Spread of each tube's growth direction about the turf's mean direction: the standard
    /// deviation of each of its two tilt components, radians, in [0, π/2). Default 0.
    #[serde(default)]
    pub tilt: Number,
    /// Tilt of the turf-wide mean growth direction from the normal, radians, in [0, 80°)
    /// (the tubes of a turf lean together). Default 0 (vertical).
    #[serde(default)]
    pub mean_tilt: Number,
    /// Azimuth of the mean growth direction, radians from x. Default 0.
    #[serde(default)]
    pub mean_azimuth: Number,
    /// Amplitude of the tubes' waviness, nm, ≥ 0. Default 0 (straight).
    #[serde(default)]
    pub waviness: Length,
    /// Wavelength of the waviness, nm. Required when `waviness` > 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelength: Option<Length>,
    /// Coherence c of the waviness, in [0, 1]: every tube waves by c × `waviness` along one
    /// turf-wide wave plus √(1 − c²) × `waviness` along its own. Default 0 (independent).
    #[serde(default)]
    pub wave_coherence: Number,
}

/// Largest mean tilt, radians (80°: the engine's bound, tubes must rise from the substrate).
const MAX_MEAN_TILT: f64 = 80.0 * std::f64::consts::PI / 180.0;

/// `[turf.vdw]` / `[rods.vdw]`: tube–tube van der Waals contact. Absent: tubes do not interact
/// (no contact search).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Vdw {
    /// Contact energy per unit length γ_L of two parallel tubes in contact, nN (= nJ/m).
    /// Required, positive.
    pub gamma_line: LineEnergy,
    /// Equilibrium wall-to-wall gap, nm. Default 0.34 nm (graphite interlayer).
    #[serde(default = "default_separation")]
    pub separation: Length,
    /// Wall-to-wall gap beyond which contacts are ignored, nm. Default 10 × `separation`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutoff: Option<Length>,
    /// How a segment pair's double line integral is evaluated: `"tabulated"` (default; Gauss
    /// points on one segment, the integral over the other from a table of G(d, x), tubes of
    /// one radius; 2.4× faster on the quickstart and at least as accurate,
    /// docs/discrete-contacts.md) or `"quadrature"` (Gauss points on both segments, the
    /// reference the table is checked against). Left out of the serialised scene when
    /// `"quadrature"`: cache keys and checkpoint fingerprints without it were computed with
    /// the quadrature, so they stay valid for it and a tabulated run never reuses them.
    #[serde(default, skip_serializing_if = "VdwKernel::is_quadrature")]
    pub kernel: VdwKernel,
}

/// `[turf.vdw] kernel`: how the contact energy of a segment pair is integrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum VdwKernel {
    /// Gauss points on both segments
    Quadrature,
    /// Gauss points on one segment, a table for the other
    #[default]
    Tabulated,
}

impl VdwKernel {
    fn is_quadrature(&self) -> bool {
        *self == VdwKernel::Quadrature
    }
}

fn default_separation() -> Length {
    Length(0.34)
}

impl Vdw {
    pub(crate) fn check(&mut self, c: &mut Checker, section: &str) {
        c.positive(&format!("{section}.gamma_line"), self.gamma_line);
        c.positive(&format!("{section}.separation"), self.separation);
        let cut = *self.cutoff.get_or_insert(Length(10.0 * self.separation.0));
        if cut.0 <= self.separation.0 {
            c.bad(
                format!("{section}.cutoff"),
                format!(
                    "{} nm is not allowed: must exceed the separation {} nm",
                    cut.0, self.separation.0
                ),
            );
        }
    }
}

/// `[turf.packing]`: the grown turf squeezed in x and y on rigid-body capsule chains
/// ([`crate::discrete::rapier_packing`], cargo feature `rapier`) from `turf.density` to a
/// higher density, where the growth would jam (overlap-free sequential growth of the
/// quickstart's tubes stops near 1.1 × 10¹⁰ cm⁻²; the packing reaches 3.8 × 10¹⁰ on 100 of
/// them, docs/benchmarks.md "rapier3d"). The box shrinks by the same factor in x and y, the
/// tubes bend around each other without adhesion, and the packed shape is the tubes' natural
/// (stress-free) shape for the relaxation that follows: a dense turf as grown, not a grown turf
/// compressed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Packing {
    /// Areal density to pack to, 1/nm² (e.g. `"3e10 1/cm^2"`). Required, above `turf.density`.
    pub density: ArealDensity,
}

impl Packing {
    fn check(&self, c: &mut Checker, grown: f64, diameter: f64, periodic: bool) {
        c.positive("turf.packing.density", self.density);
        if !cfg!(feature = "rapier") {
            c.bad(
                "turf.packing",
                "needs turf built with the cargo feature `rapier` (`cargo build --release \
                 --features rapier`); this binary was built without it",
            );
        }
        if !periodic {
            c.bad(
                "turf.packing",
                "needs a periodic box (turf.periodic = true): the box is what shrinks",
            );
        }
        let d = self.density.0;
        if d > 0.0 && d <= grown {
            c.bad(
                "turf.packing.density",
                format!(
                    "{d} /nm^2 is not allowed: must exceed turf.density ({grown} /nm^2), the \
                     density the tubes are grown at"
                ),
            );
        }
        if d > 0.0 && 1.0 / d.sqrt() <= diameter {
            c.bad(
                "turf.packing.density",
                format!(
                    "{d} /nm^2 is not allowed: the mean spacing {:.3} nm is less than a tube \
                     diameter {diameter} nm",
                    1.0 / d.sqrt()
                ),
            );
        }
    }
}

/// `[turf]`: a generated turf.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Turf {
    /// Areal number density of tubes, 1/nm² (e.g. `"1e10 1/cm^2"`). Required, positive.
    pub density: ArealDensity,
    /// Lateral size of the modelled patch [x, y], nm. Required, positive.
    #[serde(rename = "box")]
    pub box_size: [Length; 2],
    /// Periodic in x and y. Default true.
    #[serde(default = "default_periodic")]
    pub periodic: bool,
    /// The tubes' cross-section and modulus.
    pub tube: Tube,
    /// The tubes' length and shape.
    pub growth: Growth,
    /// Tube–tube contact; absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vdw: Option<Vdw>,
    /// The grown turf packed to a higher density before it is relaxed; absent: as grown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub packing: Option<Packing>,
    /// Realisations of the turf, an ensemble: each is generated with its own seed
    /// (realisation 0 with `scene.seed` itself, realisation k with a seed derived from it,
    /// [`crate::pipeline::ensemble::realisation_seed`]) and compressed; the discrete stage
    /// reports their mean and 95 % confidence interval. Default 1 (one turf, as without the
    /// key), at most [`MAX_REALISATIONS`]. Written into the resolved scene only when above 1,
    /// so a one-realisation scene resolves (and caches) exactly as before the key existed.
    #[serde(
        default = "default_realisations",
        skip_serializing_if = "is_one",
        deserialize_with = "realisations_from"
    )]
    pub realisations: usize,
}

/// Most realisations an ensemble may have: the confidence interval narrows as 1/√N, so a
/// thousand realisations already pin the mean to 3 % of the realisations' scatter; beyond
/// that, split the work (`--shard`, a `[sweep]`) rather than one stage.
pub const MAX_REALISATIONS: usize = 1000;

fn default_periodic() -> bool {
    true
}

fn default_realisations() -> usize {
    1
}

fn is_one(n: &usize) -> bool {
    *n == 1
}

/// Why a realisation count `value` (as written) is refused, naming what is allowed.
fn realisations_refused(value: impl std::fmt::Display) -> String {
    format!(
        "{value} is not allowed: an ensemble has 1 to {MAX_REALISATIONS} realisations, a whole \
         number (1 = a single turf, the default)"
    )
}

/// `turf.realisations` as written: a whole number from 1 to [`MAX_REALISATIONS`]; anything
/// else (0, negative, fractional, a string) is refused with what is allowed.
fn realisations_from<'de, D: serde::Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    let v = toml::Value::deserialize(d)?;
    match v.as_integer() {
        Some(n) if (1..=MAX_REALISATIONS as i64).contains(&n) => Ok(n as usize),
        _ => Err(serde::de::Error::custom(realisations_refused(v))),
    }
}

impl Turf {
    /// The tubes as cantilevers of the thermal-amplitude formula (seed eq. 5.9): free length
    /// `growth.length`, radii `tube.r_o`, `tube.r_i`, modulus `tube.youngs`.
    pub fn thermal_cantilever(&self) -> crate::theory::thermal::Cantilever {
        crate::theory::thermal::Cantilever {
            length: self.growth.length.0,
            r_outer: self.tube.r_o.0,
            r_inner: self.tube.r_i.0,
            youngs: self.tube.youngs.0,
        }
    }

    /// Number of tubes in the box: density × area, rounded.
    pub fn tube_count(&self) -> f64 {
        (self.density.0 * self.box_size[0].0 * self.box_size[1].0).round()
    }

    pub(crate) fn check(&mut self, c: &mut Checker) {
        c.positive("turf.density", self.density);
        c.positive("turf.box[0]", self.box_size[0]);
        c.positive("turf.box[1]", self.box_size[1]);
        self.tube.check(c, "turf.tube");
        let g = &self.growth;
        c.positive("turf.growth.length", g.length);
        c.number_in(
            "turf.growth.length_spread",
            g.length_spread.0,
            0.0,
            1.0,
            false,
        );
        c.number_in(
            "turf.growth.tilt",
            g.tilt.0,
            0.0,
            std::f64::consts::FRAC_PI_2,
            false,
        );
        c.number_in(
            "turf.growth.mean_tilt",
            g.mean_tilt.0,
            0.0,
            MAX_MEAN_TILT,
            false,
        );
        if !g.mean_azimuth.0.is_finite() {
            c.bad(
                "turf.growth.mean_azimuth",
                format!("{} is not allowed: must be finite", g.mean_azimuth.0),
            );
        }
        if !(0.0..=1.0).contains(&g.wave_coherence.0) {
            c.bad(
                "turf.growth.wave_coherence",
                format!("{} is not allowed: must lie in [0, 1]", g.wave_coherence.0),
            );
        }
        if g.waviness.0 < 0.0 {
            c.bad(
                "turf.growth.waviness",
                format!("{} nm is not allowed: must be >= 0", g.waviness.0),
            );
        }
        match g.wavelength {
            Some(w) => c.positive("turf.growth.wavelength", w),
            None if g.waviness.0 > 0.0 => c.bad(
                "turf.growth.wavelength",
                "is missing: a wavy tube (waviness > 0) needs the wavelength",
            ),
            None => {}
        }
        if let Some(s) = self.tube.segment {
            if s.0 >= g.length.0 {
                c.bad(
                    "turf.tube.segment",
                    format!(
                        "{} nm is not allowed: must be shorter than the tube length {} nm",
                        s.0, g.length.0
                    ),
                );
            }
        }
        if let Some(v) = &mut self.vdw {
            v.check(c, "turf.vdw");
        }
        if let Some(p) = &self.packing {
            p.check(c, self.density.0, 2.0 * self.tube.r_o.0, self.periodic);
        }
        if !(1..=MAX_REALISATIONS).contains(&self.realisations) {
            c.bad("turf.realisations", realisations_refused(self.realisations));
        }
        if self.density.0 > 0.0 && self.box_size.iter().all(|b| b.0 > 0.0) {
            let n = self.tube_count();
            if n < 1.0 {
                c.bad(
                    "turf.box",
                    format!("holds {n} tubes at this density: make the box larger (density × area >= 1)"),
                );
            }
            let spacing = 1.0 / self.density.0.sqrt();
            if spacing <= 2.0 * self.tube.r_o.0 {
                c.bad(
                    "turf.density",
                    format!(
                        "{} /nm^2 is not allowed: the mean spacing {spacing:.3} nm is less than a tube diameter {} nm",
                        self.density.0,
                        2.0 * self.tube.r_o.0
                    ),
                );
            }
        }
    }
}
