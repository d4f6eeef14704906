//! `[machine]`: how the indenter is driven (seed §2.3, §6.2). Under displacement control the
//! drive moves at a prescribed rate and pushes the indenter through a spring K (seed: 1 µN/nm);
//! under load control a Hysitron-type transducer applies a force P̂ to a plate held by support
//! springs k₁ (in parallel with the specimen) that reaches the indenter through the load frame
//! k₂ (in series): P̂ = k₁h + Q, h = δ + Q/k₂ (seed eqs. 2.1–2.7, the labelling under which
//! (2.4) ω = k₁(1/χ + 1/K₁) holds; during a hold dQ/dδ = −χ, χ = (1/k₁ + 1/k₂)⁻¹). The seed's
//! Fig 6.11 caption gives k₁ = 210 mN/nm, k₂ = 100 nN/nm, which under this labelling would let
//! the support springs carry all but ~10⁻⁶ of the force: its values are read as swapped
//! (a transducer's springs are ~100 N/m, its frame stiff; docs/scenes.md). No section means a
//! rigid displacement drive.

use super::check::Checker;
use super::quantity::Stiffness;
use serde::{Deserialize, Serialize};

/// What the machine controls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Control {
    /// the drive's displacement is prescribed (schedule targets are depths)
    Displacement,
    /// the applied load is prescribed (schedule targets are loads)
    Load,
}

/// `[machine]`: control mode and springs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Machine {
    /// `"displacement"` or `"load"`. Default `"displacement"`.
    #[serde(default = "default_control")]
    pub control: Control,
    /// Spring between drive and indenter under displacement control, nN/nm. Default: rigid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stiffness: Option<Stiffness>,
    /// Load control: the transducer's support springs k₁ (plate to frame, in parallel with the
    /// specimen), nN/nm (given together with `k2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1: Option<Stiffness>,
    /// Load control: the load-frame spring k₂ (plate to indenter, in series with the
    /// specimen), nN/nm (given together with `k1`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2: Option<Stiffness>,
}

fn default_control() -> Control {
    Control::Displacement
}

impl Default for Machine {
    fn default() -> Self {
        Machine {
            control: default_control(),
            stiffness: None,
            k1: None,
            k2: None,
        }
    }
}

impl Machine {
    pub(crate) fn check(&self, c: &mut Checker) {
        c.positive_opt("machine.stiffness", self.stiffness);
        c.positive_opt("machine.k1", self.k1);
        c.positive_opt("machine.k2", self.k2);
        match self.control {
            Control::Displacement => {
                for (key, v) in [("machine.k1", self.k1), ("machine.k2", self.k2)] {
                    if v.is_some() {
                        c.unused(
                            key,
                            "with control = \"displacement\" (use machine.stiffness)",
                        );
                    }
                }
            }
            Control::Load => {
                if self.stiffness.is_some() {
                    c.unused(
                        "machine.stiffness",
                        "with control = \"load\" (the load-control springs are k1 and k2)",
                    );
                }
                if self.k1.is_some() != self.k2.is_some() {
                    c.bad(
                        "machine.k1",
                        "k1 and k2 go together: give both springs of the load-control model or neither",
                    );
                }
            }
        }
    }

    /// The machine compliance's stiffness χ = (1/k₁ + 1/k₂)⁻¹ under load control, nN/nm.
    pub fn series_stiffness(&self) -> Option<f64> {
        Some(1.0 / (1.0 / self.k1?.0 + 1.0 / self.k2?.0))
    }
}
