//! The stages of the pipeline a scene can ask for, in the order they run.

use serde::Serialize;

/// A stage of the pipeline, in the order stages run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    /// closed forms: Hertz, JKR, DMT, Maugis–Dugdale (microseconds)
    Theory,
    /// small-strain half-space with LJ tractions (milliseconds to seconds)
    Halfspace,
    /// the turf or rods as tubes (minutes to hours)
    Discrete,
    /// fit a material card to a stress–strain curve
    Homogenize,
    /// axisymmetric finite-deformation FE indentation (seconds to minutes)
    Continuum,
}

impl Stage {
    /// The stage's name as printed and in `summary.json`.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Theory => "theory",
            Stage::Halfspace => "halfspace",
            Stage::Discrete => "discrete",
            Stage::Homogenize => "homogenize",
            Stage::Continuum => "continuum",
        }
    }
}
