//! Explicit rods: a few given tubes, each a polyline resampled into equal
//! elastica segments, with clamped, pinned or free ends, a dead load on the last point, and
//! optionally van der Waals contacts between them — the single- and few-tube problems
//! (Bisshopp–Drucker cantilever, two adhered tubes) set up from plain data.
//!
//! Ends as in [`super::constraints`]: clamped = end node pinned + [`ClampedEnd`] (the clamp
//! exactly at the node, second order), pinned = end node fixed, free = nothing. The rest shape
//! is the given polyline (its corners become natural curvature).

use super::constraints::{ClampedEnd, FixedDofs, PointLoads, RodEnd};
use super::energy::EnergyTerm;
use super::rod::{Rod, RodError, RodSet, RodStiffness};
use super::vdw::{VdwError, VdwParams};
use super::vdw_term::{TubeLayout, VdwTerm};
use crate::discrete::broadphase::PeriodicBox;

/// Condition at one end of a rod.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EndCondition {
    /// position and tangent fixed
    Clamped,
    /// position fixed
    Pinned,
    /// free
    Free,
}

/// One rod as given.
#[derive(Debug, Clone, PartialEq)]
pub struct RodSpec {
    /// the undeformed centre line, nm (at least two points, consecutive points distinct)
    pub points: Vec<[f64; 3]>,
    /// conditions at the first and the last point
    pub ends: [EndCondition; 2],
    /// dead force on the last point, nN
    pub load: Option<[f64; 3]>,
    /// elastica segments (≥ 1)
    pub segments: usize,
}

/// Why the rods could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum ExplicitRodsError {
    /// a rod is not valid
    #[error("rod {rod}: {source}")]
    Rod {
        /// which
        rod: usize,
        /// cause
        source: RodError,
    },
    /// zero segments or a polyline of zero length
    #[error("rod {0}: needs at least one segment and a positive length")]
    Degenerate(usize),
    /// the contact model could not be set up
    #[error(transparent)]
    Vdw(#[from] VdwError),
}

/// Resample the polyline `points` at `n + 1` points equally spaced in arclength.
pub fn resample(points: &[[f64; 3]], n: usize) -> Option<Vec<[f64; 3]>> {
    let seg = |w: &[[f64; 3]]| {
        (0..3)
            .map(|a| (w[1][a] - w[0][a]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let lengths: Vec<f64> = points.windows(2).map(seg).collect();
    let total: f64 = lengths.iter().sum();
    if n == 0 || points.len() < 2 || total.is_nan() || total <= 0.0 {
        return None;
    }
    let mut out = Vec::with_capacity(n + 1);
    let (mut j, mut start) = (0, 0.0);
    for k in 0..=n {
        let s = total * k as f64 / n as f64;
        while j + 1 < lengths.len() && s > start + lengths[j] {
            start += lengths[j];
            j += 1;
        }
        let t = if lengths[j] > 0.0 {
            ((s - start) / lengths[j]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push([0, 1, 2].map(|a| points[j][a] + t * (points[j + 1][a] - points[j][a])));
    }
    Some(out)
}

/// The energy of explicit rods: elastic, tangent clamps, dead loads, contacts.
pub struct RodsModel {
    /// the rods
    pub rods: RodSet,
    /// tangent clamps of the clamped ends
    pub clamps: Vec<ClampedEnd>,
    /// dead loads
    pub loads: PointLoads,
    /// contacts; `None`: the rods do not interact
    pub vdw: Option<VdwTerm>,
}

impl EnergyTerm for RodsModel {
    fn prepare(&mut self, x: &[f64]) {
        if let Some(v) = self.vdw.as_mut() {
            v.prepare(x);
        }
    }

    fn energy_gradient(&self, x: &[f64], grad: &mut [f64]) -> f64 {
        let mut e = self.rods.energy_gradient(x, grad);
        for c in &self.clamps {
            e += c.energy_gradient(x, grad);
        }
        e += self.loads.energy_gradient(x, grad);
        if let Some(v) = &self.vdw {
            e += v.energy_gradient(x, grad);
        }
        e
    }

    fn hessian(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for t in self.terms() {
            t.hessian(x, out);
        }
    }

    fn hessian_lower(&self, x: &[f64], out: &mut Vec<(usize, usize, f64)>) {
        for t in self.terms() {
            t.hessian_lower(x, out);
        }
    }
}

impl RodsModel {
    /// Every term, in the order the Hessian lists them: the rods, the clamps, the loads and
    /// the contacts.
    fn terms(&self) -> impl Iterator<Item = &dyn EnergyTerm> {
        let rods: &dyn EnergyTerm = &self.rods;
        let loads: &dyn EnergyTerm = &self.loads;
        std::iter::once(rods)
            .chain(self.clamps.iter().map(|c| c as &dyn EnergyTerm))
            .chain(std::iter::once(loads))
            .chain(self.vdw.as_ref().map(|v| v as &dyn EnergyTerm))
    }
}

/// Explicit rods ready to solve.
pub struct ExplicitRods {
    /// the energy
    pub model: RodsModel,
    /// supports
    pub fixed: FixedDofs,
    /// the reference configuration, nm
    pub x0: Vec<f64>,
    /// where each rod's nodes are
    pub layout: Vec<TubeLayout>,
}

impl ExplicitRods {
    /// Set up `specs` with one cross-section (`stiffness`, outer radius `radius` nm) and
    /// contacts from `vdw` (none if `None`; open box).
    pub fn new(
        specs: &[RodSpec],
        stiffness: RodStiffness,
        radius: f64,
        vdw: Option<&VdwParams>,
    ) -> Result<Self, ExplicitRodsError> {
        let mut x0 = Vec::new();
        let mut rods = Vec::new();
        let mut layout = Vec::new();
        let mut loads = PointLoads::new();
        let mut pending = Vec::new();
        for (i, spec) in specs.iter().enumerate() {
            let pts =
                resample(&spec.points, spec.segments).ok_or(ExplicitRodsError::Degenerate(i))?;
            let first = x0.len() / 3;
            let rod = Rod::natural(first, &pts, stiffness)
                .map_err(|source| ExplicitRodsError::Rod { rod: i, source })?;
            let last = first + rod.nodes() - 1;
            layout.push(TubeLayout {
                first_node: first,
                nodes: rod.nodes(),
                radius,
            });
            x0.extend(pts.iter().flatten());
            if let Some(f) = spec.load {
                loads.add(last, f);
            }
            pending.push((rods.len(), spec.ends, first, last));
            rods.push(rod);
        }
        let mut fixed = FixedDofs::free(x0.len() / 3);
        let mut clamps = Vec::new();
        for (r, ends, first, last) in pending {
            for (cond, node, end) in [
                (ends[0], first, RodEnd::First),
                (ends[1], last, RodEnd::Last),
            ] {
                match cond {
                    EndCondition::Clamped => {
                        fixed.pin(node);
                        clamps.push(ClampedEnd::new(&rods[r], end, &x0));
                    }
                    EndCondition::Pinned => {
                        fixed.pin(node);
                    }
                    EndCondition::Free => {}
                }
            }
        }
        let vdw = match vdw {
            Some(p) => Some(VdwTerm::new(p, &layout, &x0, PeriodicBox::default())?),
            None => None,
        };
        Ok(ExplicitRods {
            model: RodsModel {
                rods: RodSet::new(rods),
                clamps,
                loads,
                vdw,
            },
            fixed,
            x0,
            layout,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_is_equal_in_arclength_and_keeps_the_ends() {
        // an L of legs 3 and 1: total 4, four segments of 1
        let p = resample(&[[0.0; 3], [3.0, 0.0, 0.0], [3.0, 1.0, 0.0]], 4).unwrap();
        let expect = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [3.0, 1.0]];
        assert_eq!(p.len(), 5);
        for (a, b) in p.iter().zip(expect) {
            assert!(
                (a[0] - b[0]).abs() < 1e-14 && (a[1] - b[1]).abs() < 1e-14,
                "{a:?}"
            );
        }
        assert!(resample(&[[0.0; 3], [0.0; 3]], 3).is_none());
        assert!(resample(&[[0.0; 3], [1.0, 0.0, 0.0]], 0).is_none());
    }

    #[test]
    fn ends_fix_what_they_say() {
        let spec = |ends| RodSpec {
            points: vec![[0.0; 3], [100.0, 0.0, 0.0]],
            ends,
            load: Some([0.0, -1.0, 0.0]),
            segments: 4,
        };
        let s = ExplicitRods::new(
            &[
                spec([EndCondition::Clamped, EndCondition::Free]),
                spec([EndCondition::Pinned, EndCondition::Pinned]),
            ],
            RodStiffness::turf_tube(),
            20.0,
            None,
        )
        .unwrap();
        let fixed_nodes: Vec<usize> = (0..10).filter(|&n| s.fixed.is_fixed(3 * n)).collect();
        assert_eq!(fixed_nodes, [0, 5, 9]);
        assert_eq!(s.model.clamps.len(), 1);
    }
}
