//! `[rods]`: explicit tubes for single-rod and few-rod problems (elastica benchmarks, two-tube
//! adhesion): each `[[rods.rod]]` is a polyline of points, with end conditions and an end
//! load, discretised into elastica segments.

use super::check::Checker;
use super::quantity::{Force, Length};
use super::turf::{Tube, Vdw};
use serde::{Deserialize, Serialize};

/// Boundary condition at one end of a rod.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum End {
    /// position and tangent fixed
    Clamped,
    /// position fixed, free to rotate
    Pinned,
    /// free
    Free,
}

/// `[[rods.rod]]`: one rod.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rod {
    /// Points of the rod's undeformed centre line, each [x, y, z] in nm; at least two, with no
    /// two consecutive points equal.
    pub points: Vec<[Length; 3]>,
    /// Conditions at the first and last point: `"clamped"`, `"pinned"` or `"free"`. Default
    /// `["clamped", "free"]` (a cantilever).
    #[serde(default = "default_ends")]
    pub ends: [End; 2],
    /// Force on the last point [Fx, Fy, Fz], nN. Default none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub load: Option<[Force; 3]>,
    /// Elastica segments along the rod, ≥ 1. Default 20.
    #[serde(default = "default_segments")]
    pub segments: usize,
}

fn default_ends() -> [End; 2] {
    [End::Clamped, End::Free]
}
fn default_segments() -> usize {
    20
}

/// `[rods]`: explicit rods sharing one cross-section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rods {
    /// The rods' cross-section and modulus (`segment` is ignored: use `segments` per rod).
    pub tube: Tube,
    /// Rod–rod contact; absent: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vdw: Option<Vdw>,
    /// The rods. At least one.
    #[serde(default)]
    pub rod: Vec<Rod>,
}

impl Rods {
    pub(crate) fn check(&mut self, c: &mut Checker, compressed: bool) {
        self.tube.check(c, "rods.tube");
        if self.tube.segment.is_some() {
            c.unused("rods.tube.segment", "for rods (give rods.rod[i].segments)");
        }
        if let Some(v) = &mut self.vdw {
            v.check(c, "rods.vdw");
        }
        if self.rod.is_empty() {
            c.bad("rods.rod", "is empty: give at least one [[rods.rod]]");
        }
        for (i, r) in self.rod.iter().enumerate() {
            let key = |k: &str| format!("rods.rod[{i}].{k}");
            if r.points.len() < 2 {
                c.bad(
                    key("points"),
                    format!("has {} point(s): a rod needs at least two", r.points.len()),
                );
            }
            for (j, w) in r.points.windows(2).enumerate() {
                let d2: f64 = (0..3).map(|k| (w[1][k].0 - w[0][k].0).powi(2)).sum();
                if d2 == 0.0 {
                    c.bad(
                        format!("rods.rod[{i}].points[{}]", j + 1),
                        "repeats the previous point: consecutive points must differ",
                    );
                }
            }
            c.count_at_least(&key("segments"), r.segments, 1);
            if r.ends == [End::Free, End::Free] && !compressed {
                c.bad(
                    key("ends"),
                    "[\"free\", \"free\"] is not allowed without [compression]: the rod would be unconstrained",
                );
            }
        }
    }
}
