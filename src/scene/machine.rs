//! `[machine]`: how the indenter is driven (seed §2.3, §6.2). Under displacement control the
//! drive moves at a prescribed rate and pushes the indenter through a spring K (seed: 1 µN/nm);
//! under load control a Hysitron-type transducer applies a force through springs k₁ and k₂
//! (seed eqs. 2.1–2.7: k₁ = 210 mN/nm, k₂ = 100 nN/nm; during a hold dQ/dδ equals
//! χ = (1/k₁ + 1/k₂)⁻¹). No section means a rigid displacement drive.

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
    /// Load control: the first machine spring k₁, nN/nm (given together with `k2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1: Option<Stiffness>,
    /// Load control: the second machine spring k₂, nN/nm (given together with `k1`).
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
