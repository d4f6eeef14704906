//! `[adhesion]`: Lennard-Jones adhesion between the indenter and the surface (seed eqs. 4.1,
//! 5.10; `turf::laws`), optionally thermally shifted (seed §5.2, eq. 5.9) and with contact
//! damping (seed eq. 4.4). Its absence means no contact search and no LJ law are built.

use super::check::Checker;
use super::quantity::{Length, Number, Temperature};
use super::quantity::{Quantity, SurfaceEnergy};
use crate::continuum::contact::SurfaceArea;
use crate::laws::{LawError, LjKind, SurfaceLaw, ThermallyShifted};
use crate::theory::TheoryError;
use crate::units::Dimension;
use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::fmt;

/// Why the thermal shift of `[adhesion]` could not be computed or applied.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ThermalShiftError {
    /// `thermal_shift = true` without a `[turf]` to take the tubes from
    #[error(
        "needs [turf] (turf.growth.length, turf.tube.r_o, turf.tube.r_i, turf.tube.youngs) to \
         compute the amplitude u (seed eq. 5.9); give a length instead, e.g. \"5 nm\""
    )]
    NoTurf,
    /// the tubes' thermal amplitude could not be computed
    #[error("the thermal amplitude of the [turf] tubes (seed eq. 5.9): {0}")]
    Amplitude(#[from] TheoryError),
    /// the shifted law could not be built
    #[error(transparent)]
    Law(#[from] LawError),
}

/// The thermal shift of the attractive branch (seed §5.2): off, computed from the tubes'
/// thermal amplitude u (eq. 5.9, needs `[turf]`), or a given length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ThermalShift {
    /// `false`: the plain LJ law
    Off,
    /// `true`: u from the `[turf]` tubes at `adhesion.temperature`
    FromTubes,
    /// a length: the shift u, nm
    Amplitude(Length),
}

impl Serialize for ThermalShift {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            ThermalShift::Off => s.serialize_bool(false),
            ThermalShift::FromTubes => s.serialize_bool(true),
            ThermalShift::Amplitude(u) => u.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for ThermalShift {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = ThermalShift;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("false, true (u from the [turf] tubes, seed eq. 5.9) or a length such as \"5 nm\"")
            }
            fn visit_bool<E: de::Error>(self, v: bool) -> Result<ThermalShift, E> {
                Ok(if v {
                    ThermalShift::FromTubes
                } else {
                    ThermalShift::Off
                })
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<ThermalShift, E> {
                Ok(ThermalShift::Amplitude(Length(v as f64)))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<ThermalShift, E> {
                Ok(ThermalShift::Amplitude(Length(v as f64)))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<ThermalShift, E> {
                if v.is_finite() {
                    Ok(ThermalShift::Amplitude(Length(v)))
                } else {
                    Err(E::custom(format!("{v} is not a finite length")))
                }
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<ThermalShift, E> {
                super::quantity::parse_text(v, Dimension::Length)
                    .map(|u| ThermalShift::Amplitude(Length(u)))
                    .map_err(E::custom)
            }
        }
        d.deserialize_any(V)
    }
}

/// `[adhesion.damping]`: contact damping c(g) (seed eq. 4.4) — c₀ for g ≤ η g′, falling
/// linearly to 0 at g = g′; the damping pressure is c(g)·ġ. It only carries a quasi-static
/// Newton solution through jump-to-contact; a converged answer must not depend on it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactDamping {
    /// Damping coefficient c₀, GPa·s/nm (a pressure per unit gap velocity). A number in
    /// internal units: the unit parser has no dimension for it. Required, positive.
    pub c0: Number,
    /// Gap g′ beyond which there is no damping, nm. Required, larger than `adhesion.z0`.
    pub gap: Length,
    /// Fraction η of g′ up to which the damping is full, in [0, 1). Default 0.5.
    #[serde(default = "default_eta")]
    pub eta: Number,
}

fn default_eta() -> Number {
    Number(0.5)
}

/// `[adhesion]`: the indenter–surface force–separation law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Adhesion {
    /// `"lj93"` (integrated half-spaces, seed eq. 4.1) or `"lj104"` (a monolayer, seed eq.
    /// 5.10). Default `"lj93"`.
    #[serde(default = "default_law")]
    pub law: LjKind,
    /// Work of adhesion γ, J/m² (= nN/nm). Required, positive.
    pub gamma: SurfaceEnergy,
    /// Equilibrium separation z₀, nm. Required, positive (0.34 nm for graphitic surfaces).
    pub z0: Length,
    /// Thermal shift of the attractive branch: `false` (default), `true` (u from the `[turf]`
    /// tubes, seed eq. 5.9) or a length u.
    #[serde(default = "default_shift")]
    pub thermal_shift: ThermalShift,
    /// Temperature for `thermal_shift = true`, K. Default 300 K.
    #[serde(default = "default_temperature")]
    pub temperature: Temperature,
    /// Contact damping; absent means none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<ContactDamping>,
    /// The area the law's energy per area is integrated over under finite deformation:
    /// `"reference"` (default: the surface's atoms — the tube ends — are conserved) or
    /// `"current"` (the stretched surface; mesh-dependent under strong adhesion on a compliant
    /// solid, kept for comparison). Small strain always uses the reference surface.
    #[serde(default)]
    pub area: SurfaceArea,
}

fn default_law() -> LjKind {
    LjKind::Lj93
}
fn default_shift() -> ThermalShift {
    ThermalShift::Off
}
fn default_temperature() -> Temperature {
    Temperature(300.0)
}

impl Adhesion {
    pub(crate) fn check(&self, c: &mut Checker) {
        c.positive("adhesion.gamma", self.gamma);
        c.positive("adhesion.z0", self.z0);
        c.positive("adhesion.temperature", self.temperature);
        if let ThermalShift::Amplitude(u) = self.thermal_shift {
            if u.value() < 0.0 {
                c.bad(
                    "adhesion.thermal_shift",
                    format!(
                        "{} nm is not allowed: the shift u must be >= 0 (or false / true)",
                        u.0
                    ),
                );
            }
        }
        if let Some(d) = &self.damping {
            c.number_in("adhesion.damping.c0", d.c0.0, 0.0, f64::INFINITY, true);
            c.number_in("adhesion.damping.eta", d.eta.0, 0.0, 1.0, false);
            if d.gap.0 <= self.z0.0 {
                c.bad(
                    "adhesion.damping.gap",
                    format!(
                        "{} nm is not allowed: the damping range g' must exceed z0 = {} nm",
                        d.gap.0, self.z0.0
                    ),
                );
            }
        }
    }

    /// The shift u of the attractive branch, nm: 0 when off, the given length, or (`true`) the
    /// RMS tip amplitude of the `[turf]` tubes at `adhesion.temperature` (seed eq. 5.9).
    pub fn shift_nm(&self, turf: Option<&super::turf::Turf>) -> Result<f64, ThermalShiftError> {
        match self.thermal_shift {
            ThermalShift::Off => Ok(0.0),
            ThermalShift::Amplitude(u) => Ok(u.0),
            ThermalShift::FromTubes => Ok(turf
                .ok_or(ThermalShiftError::NoTurf)?
                .thermal_cantilever()
                .rms_tip_amplitude(self.temperature.0)?),
        }
    }

    /// The unshifted law as `turf::laws` builds it.
    pub fn law(&self) -> crate::laws::LennardJones {
        crate::laws::LennardJones::new(self.law, self.gamma.0, self.z0.0)
    }

    /// The law the engines take: `adhesion.law`, thermally shifted by [`Self::shift_nm`] when
    /// the shift is positive (seed §5.2).
    pub fn surface_law(
        &self,
        turf: Option<&super::turf::Turf>,
    ) -> Result<SurfaceLaw, ThermalShiftError> {
        self.surface_law_of(self.law, turf)
    }

    /// [`Self::surface_law`] with the exponents `kind` in place of `adhesion.law`.
    pub fn surface_law_of(
        &self,
        kind: LjKind,
        turf: Option<&super::turf::Turf>,
    ) -> Result<SurfaceLaw, ThermalShiftError> {
        let base = crate::laws::LennardJones::new(kind, self.gamma.0, self.z0.0);
        match self.shift_nm(turf)? {
            u if u > 0.0 => Ok(ThermallyShifted::new(base, u).map(SurfaceLaw::from)?),
            _ => Ok(base.into()),
        }
    }
}
