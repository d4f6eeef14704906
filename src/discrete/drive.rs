//! Quasi-static platen compression of the turf (seed §2.4 and ch. 5: the
//! compressive stress–strain curve that homogenisation turns into a card).
//!
//! The platen starts at the top of the relaxed turf, H₀ = max(z + r) over the free nodes (an
//! adhesive sphere z₀ above it: [`TurfSystem::start_height`]), and
//! moves to H_k = H₀(1 − ε_k), ε_k = ε_max k/n for k = 1 … n, then (when unloading) back along
//! the same strains to ε = 0 and (an adhesive sphere's retract, [`Retract`]) on above its first
//! touch, H₀ + d k/m for k = 1 … m, where the tips it holds are pulled off. Each step is a static equilibrium ([`StaticSolver`]) warm-started
//! from the previous one; before the solve, nodes the platen has overtaken are put back just
//! under it (a feasible start, so the penalty starts at zero). Recorded per step: nominal
//! strain ε = (H₀ − H)/H₀, the platen force F = −∂E/∂H and the nominal stress σ = F/A (A the
//! box area), the energy split, the contacts, the solver's cost.
//!
//! A drive can start part-way ([`Resume`], from a [`super::checkpoint::Checkpoint`]): the steps
//! already reached are taken from their saved configurations (their records recomputed, which
//! is exact: a record is a function of the configuration and the platen height), and the
//! solves continue from the last one, so the curve is the one of an uninterrupted drive.

use super::model::{State, StaticSolver, TurfSystem};
use super::solve::{Cost, SolveError};
use super::sphere_stick::Anchor;
use serde::Serialize;

/// The strain path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompressionParams {
    /// final nominal compressive strain, in (0, 1)
    pub strain_max: f64,
    /// steps to reach it (≥ 1)
    pub steps: usize,
    /// also unload back to zero strain in as many steps
    pub unload: bool,
    /// then raise the platen above its first touch (an adhesive sphere's pull-off)
    pub retract: Option<Retract>,
}

/// The retract after the unloading: the platen raised `distance` above its start height H₀ in
/// `steps` equal steps (recorded as unloading, at negative strains −d k/(m H₀)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Retract {
    /// how far above H₀, nm (> 0)
    pub distance: f64,
    /// its steps (≥ 1)
    pub steps: usize,
}

impl CompressionParams {
    /// The strain in (0, 1) and at least one step.
    pub fn check(&self) -> Result<(), DriveError> {
        if !(self.strain_max > 0.0 && self.strain_max < 1.0) || self.steps == 0 {
            return Err(DriveError::Invalid(format!(
                "strain {} must be in (0, 1) and steps {} at least 1",
                self.strain_max, self.steps
            )));
        }
        if let Some(r) = self.retract {
            if !(r.distance > 0.0 && r.distance.is_finite()) || r.steps == 0 || !self.unload {
                return Err(DriveError::Invalid(format!(
                    "a retract of {} nm in {} steps must be > 0, in at least 1 step, after an unloading",
                    r.distance, r.steps
                )));
            }
        }
        Ok(())
    }
}

/// One equilibrium of the drive.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepRecord {
    /// step index, 0 = the relaxed turf at the platen's first touch
    pub step: usize,
    /// true on the way down (and at step 0), false on the way back
    pub loading: bool,
    /// nominal compressive strain (H₀ − H)/H₀
    pub strain: f64,
    /// platen height H, nm
    pub height: f64,
    /// nominal compressive stress F/A, GPa
    pub stress: f64,
    /// energies, contacts, platen force at equilibrium
    pub state: State,
    /// what the step's solve cost (zero at step 0)
    #[serde(skip)]
    pub cost: Cost,
}

/// A step reached: its configuration, the nodes the sphere held during its solve and what the
/// solve cost.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SavedStep {
    /// what the solve cost (zero at step 0)
    pub cost: Cost,
    /// node coordinates at equilibrium, nm
    pub x: Vec<f64>,
    /// the sphere's anchors frozen during the step (empty without the stick option)
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub anchors: Vec<Anchor>,
}

/// A drive already done up to some step: the platen's start height and the steps reached,
/// step 0 first.
#[derive(Debug, Clone, PartialEq)]
pub struct Resume {
    /// H₀, nm
    pub start_height: f64,
    /// steps 0 … k
    pub steps: Vec<SavedStep>,
}

/// Why the drive stopped.
#[derive(Debug, thiserror::Error)]
pub enum DriveError {
    /// a bad strain path
    #[error("compression: {0}")]
    Invalid(String),
    /// a step did not reach equilibrium
    #[error("compression step {step} (strain {strain:.4}): {source}")]
    Step {
        /// the step
        step: usize,
        /// its target strain
        strain: f64,
        /// the solver's diagnostics
        source: SolveError,
    },
    /// an interrupt was requested ([`crate::interrupt`]): the drive stopped after this step
    #[error("compression interrupted after step {step} (strain {strain:.4})")]
    Interrupted {
        /// the last step reached
        step: usize,
        /// its strain
        strain: f64,
    },
}

/// The strains of the path, step 0 (ε = 0) first; `true` while loading. A retract's strains
/// are those of the drive from the start height `h0` ([`retract_path`]).
pub fn strain_path(p: &CompressionParams) -> Vec<(f64, bool)> {
    let n = p.steps;
    let mut path: Vec<(f64, bool)> = (0..=n)
        .map(|k| (p.strain_max * k as f64 / n as f64, true))
        .collect();
    if p.unload {
        path.extend(
            (0..n)
                .rev()
                .map(|k| (p.strain_max * k as f64 / n as f64, false)),
        );
    }
    path
}

/// The strains of the retract of `p` above the start height `h0` (none without one).
pub fn retract_path(p: &CompressionParams, h0: f64) -> Vec<(f64, bool)> {
    p.retract.map_or_else(Vec::new, |r| {
        (1..=r.steps)
            .map(|k| (-r.distance * k as f64 / (r.steps as f64 * h0), false))
            .collect()
    })
}

/// Compress the relaxed turf at `x` (nm; the final configuration on return) along `params`,
/// solving each step with `solver`; with `resume`, the steps it holds are taken as reached and
/// the drive continues after the last of them. `observe` sees every step's record and saved
/// state (configuration, anchors) as it is reached (progress, VTK output, checkpoints). With
/// the sphere's stick option the anchors are frozen during each solve and updated after it
/// ([`TurfSystem::update_stick`]): the path-dependent state the drive carries. Returns the
/// records, step 0 first; an interrupt ([`crate::interrupt::requested`]) stops the drive after
/// the step being solved, once `observe` has seen it.
pub fn compress(
    sys: &mut TurfSystem,
    x: &mut [f64],
    params: &CompressionParams,
    solver: &StaticSolver,
    resume: Option<&Resume>,
    observe: &mut dyn FnMut(&StepRecord, &SavedStep),
) -> Result<Vec<StepRecord>, DriveError> {
    params.check()?;
    let (h0, saved) = match resume {
        Some(r) => (r.start_height, r.steps.as_slice()),
        None => (sys.start_height(x), &[][..]),
    };
    let mut path = strain_path(params);
    path.extend(retract_path(params, h0));
    let total = path.len();
    if saved.len() > path.len() || saved.iter().any(|s| s.x.len() != x.len()) {
        return Err(DriveError::Invalid(format!(
            "the resumed drive holds {} steps of a path of {} (or configurations of another size)",
            saved.len(),
            path.len()
        )));
    }
    let mut records: Vec<StepRecord> = Vec::new();
    // the equilibrium before the current one, for the secant predictor
    let mut before: Option<(Vec<f64>, f64)> = None;
    for (step, (strain, loading)) in path.into_iter().enumerate() {
        let h = h0 * (1.0 - strain);
        sys.set_platen(h);
        let last = records.last().map(|r| (r.height, r.loading));
        let x_last = x.to_vec();
        let cost = if let Some(s) = saved.get(step) {
            x.copy_from_slice(&s.x);
            sys.set_anchors(&s.anchors);
            s.cost
        } else if step == 0 {
            Cost::default()
        } else {
            match (&before, last) {
                (Some((x_before, h_before)), Some((h_last, loading_last)))
                    if loading_last == loading && h_last != *h_before =>
                {
                    secant_start(sys, x, x_before, (h - h_last) / (h_last - h_before))
                }
                _ => push_below(sys, x),
            }
            solve_step(sys, x, solver, step, strain)?
        };
        let state = sys.state(x);
        let rec = StepRecord {
            step,
            loading,
            strain,
            height: h,
            stress: state.platen_force / sys.area,
            state,
            cost,
        };
        observe(
            &rec,
            &SavedStep {
                cost,
                x: x.to_vec(),
                anchors: sys.anchors(),
            },
        );
        sys.update_stick(x);
        before = last.map(|(h_last, _)| (x_last, h_last));
        records.push(rec);
        if crate::interrupt::requested() && step + 1 < total {
            return Err(DriveError::Interrupted { step, strain });
        }
    }
    Ok(records)
}

/// Solve the equilibrium of step `step` (at `strain`) from `x`; a failure names the step.
pub(crate) fn solve_step(
    sys: &mut TurfSystem,
    x: &mut [f64],
    solver: &StaticSolver,
    step: usize,
    strain: f64,
) -> Result<Cost, DriveError> {
    sys.solve(x, solver)
        .map(|info| info.cost)
        .map_err(|source| DriveError::Step {
            step,
            strain,
            source,
        })
}

/// Secant predictor along the drive: the configuration extrapolated linearly in the platen
/// height from the last two equilibria, x + r (x − x_before) with r = Δh_next/Δh_last, replaces
/// the plain start (`x` with [`push_below`]) when its energy is lower. On a smooth branch this
/// starts Newton next to the solution; where the branch snaps (contacts forming, tubes
/// buckling) the extrapolation can be worse, and the plain start is kept.
fn secant_start(sys: &mut TurfSystem, x: &mut [f64], x_before: &[f64], r: f64) {
    let mut predicted: Vec<f64> = x
        .iter()
        .zip(x_before)
        .map(|(a, b)| a + r * (a - b))
        .collect();
    push_below(sys, x);
    push_below(sys, &mut predicted);
    let e_plain = sys.energy(x);
    let e_predicted = sys.energy(&predicted);
    if e_predicted.is_finite() && e_predicted < e_plain {
        x.copy_from_slice(&predicted);
    }
}

/// Predictor: every tube the platen (flat or sphere) has overtaken is shortened affinely along
/// z about its clamped base — the heights of its free nodes above the base scaled by the one
/// factor that brings its most overtaken node just under the platen — and any node still inside
/// (a tube folded above its top) is then moved straight down. A tube of height L shortened by δ
/// this way stores ½(EA/L)δ², where moving its top node alone would fold its top segment (length
/// l) and store ½(EA/l)δ²: L/l times more, a start Newton needs many iterations to leave.
fn push_below(sys: &TurfSystem, x: &mut [f64]) {
    let Some(platen) = &sys.model.platen else {
        return;
    };
    let wall = &sys.wall_nodes;
    for rod in sys.model.rods.rods() {
        let (first, end) = (rod.first_node(), rod.first_node() + rod.nodes());
        let free =
            &wall[wall.partition_point(|w| w.0 < first)..wall.partition_point(|w| w.0 < end)];
        // the pivot: the highest clamped node of the tube, else the substrate
        let base = (first..end)
            .filter(|&n| sys.fixed.is_fixed(3 * n + 2))
            .map(|n| x[3 * n + 2])
            .fold(0.0, f64::max);
        let scale = free
            .iter()
            .filter_map(|&(n, r)| {
                let z = x[3 * n + 2];
                let top = platen.ceiling(x[3 * n], x[3 * n + 1], r)?;
                (z > top && z > base && top > base).then(|| (top - base) / (z - base))
            })
            .fold(1.0, f64::min);
        for &(n, r) in free {
            let z = &mut x[3 * n + 2];
            if scale < 1.0 && *z > base {
                *z = base + (*z - base) * scale;
            }
            if let Some(top) = platen.ceiling(x[3 * n], x[3 * n + 1], r) {
                let z = &mut x[3 * n + 2];
                *z = z.min(top);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_loads_and_unloads_on_the_same_strains() {
        let p = CompressionParams {
            strain_max: 0.3,
            steps: 3,
            unload: true,
            retract: None,
        };
        let path = strain_path(&p);
        let strains: Vec<f64> = path.iter().map(|s| s.0).collect();
        let expect = [0.0, 0.1, 0.2, 0.3, 0.2, 0.1, 0.0];
        assert_eq!(strains.len(), expect.len());
        for (a, b) in strains.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15);
        }
        assert_eq!(path.iter().filter(|s| s.1).count(), 4);
    }

    #[test]
    fn a_retract_raises_the_platen_above_its_start_in_equal_steps() {
        let mut p = CompressionParams {
            strain_max: 0.3,
            steps: 3,
            unload: true,
            retract: Some(Retract {
                distance: 10.0,
                steps: 4,
            }),
        };
        let h0 = 1000.0;
        let heights: Vec<f64> = retract_path(&p, h0)
            .iter()
            .map(|&(e, loading)| {
                assert!(!loading);
                h0 * (1.0 - e)
            })
            .collect();
        let expect = [1002.5, 1005.0, 1007.5, 1010.0];
        assert_eq!(heights.len(), expect.len());
        for (a, b) in heights.iter().zip(expect) {
            assert!((a - b).abs() < 1e-9, "{a} against {b}");
        }
        assert!(p.check().is_ok());
        p.unload = false;
        assert!(p.check().is_err(), "a retract without an unloading");
        p.unload = true;
        p.retract = Some(Retract {
            distance: -1.0,
            steps: 4,
        });
        assert!(p.check().is_err(), "a retract downwards");
        p.retract = None;
        assert!(retract_path(&p, h0).is_empty());
    }
}
