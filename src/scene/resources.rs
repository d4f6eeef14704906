//! Resources: the memory each stage of a resolved scene would allocate, estimated before
//! anything is built, against a ceiling — every size a user can type is bounded here, so a
//! scene that cannot be allocated is refused by `turf check` and before `turf run` starts,
//! with the keys that drive the size, the estimate and how to lower it (the way
//! `mesh.max_elements` bounds the FE mesh, [`crate::continuum::mesh::MeshError::TooLarge`]).
//!
//! Estimates (bytes, orders of magnitude rather than exact counts):
//! - discrete: nodes N = Σ tubes (segments + 1), each with its positions, gradients, sparse
//!   Hessian rows and contacts ([`DISCRETE_BYTES_PER_NODE`]) and its coordinates in the
//!   checkpoint after every saved step (24 B per node per step); a `[turf]` has
//!   density × box area tubes of ⌈length/segment⌉ segments, and an ensemble
//!   (`turf.realisations`) holds min(realisations, threads) turfs at once;
//! - halfspace: the dense influence matrix, the bordered Jacobian, its LU factor and the
//!   previous grid's matrix while remeshing, 4 × 8n² for the n nodes of the finest grid
//!   ([`crate::halfspace::trace_grid::estimated_nodes`]);
//! - continuum: [`FE_BYTES_PER_ELEMENT`] per element up to `mesh.max_elements` (the mesh
//!   generator stops at that count before allocating more).
//!
//! The ceiling is `TURF_MAX_MEMORY` (environment; bytes, or a number with B, kB, MB, GB, TB,
//! KiB, MiB, GiB, TiB) when set, else half of `MemTotal` in `/proc/meminfo`, else
//! [`FALLBACK_CEILING`].

use super::check::sig;
use super::check::Checker;
use super::stage::Stage;
use super::Scene;
use serde::Serialize;

/// Environment variable that sets the memory ceiling.
pub const CEILING_VAR: &str = "TURF_MAX_MEMORY";
/// Ceiling when neither `TURF_MAX_MEMORY` nor `/proc/meminfo` gives one: 4 GiB.
pub const FALLBACK_CEILING: f64 = 4.0 * GIB;
/// Memory of one discrete node (3 coordinates): state and gradient vectors, its rows of the
/// sparse Hessian and of its factor, and its share of the contact lists, bytes (an upper
/// estimate).
pub const DISCRETE_BYTES_PER_NODE: f64 = 2048.0;
/// Memory of one FE element in the solve, bytes (the 214,769-element Hertz mesh took 615 MB,
/// docs/validation.md "Extremes").
pub const FE_BYTES_PER_ELEMENT: f64 = 3000.0;
/// Dense n × n matrices the half-space solver holds at once.
const HALFSPACE_MATRICES: f64 = 4.0;
/// Bytes of one node's coordinates in a checkpointed step.
const CHECKPOINT_BYTES_PER_NODE: f64 = 24.0;
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The memory ceiling and where it comes from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ceiling {
    /// bytes
    pub bytes: f64,
    /// `TURF_MAX_MEMORY`, half of `MemTotal`, or the fallback
    pub source: String,
}

/// The memory a stage would allocate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StageMemory {
    /// the stage
    pub stage: Stage,
    /// estimated peak bytes
    pub bytes: f64,
    /// what the estimate counts, naming the keys that set it
    pub detail: String,
}

/// The memory budget of a scene: the ceiling and each sized stage's estimate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Memory {
    /// the ceiling the estimates are held to
    pub ceiling: Ceiling,
    /// one entry per stage whose size the scene sets
    pub stages: Vec<StageMemory>,
}

impl Memory {
    /// The most FE elements the continuum stage may mesh: `mesh.max_elements` (default
    /// [`crate::continuum::mesh::DEFAULT_MAX_ELEMENTS`]) and no more than the ceiling holds.
    pub fn max_elements(&self, scene: &Scene) -> usize {
        let given = scene.mesh.as_ref().and_then(|m| m.max_elements);
        let wanted = given.map_or(crate::continuum::mesh::DEFAULT_MAX_ELEMENTS as f64, |n| {
            n as f64
        });
        wanted.min(elements_within(self.ceiling.bytes)) as usize
    }
}

/// A byte count for messages: "3.2 GB".
pub fn bytes_text(b: f64) -> String {
    if b >= 1e15 {
        return format!("{b:.3e} bytes");
    }
    let units = [(1e12, "TB"), (1e9, "GB"), (1e6, "MB"), (1e3, "kB")];
    units
        .iter()
        .find(|(u, _)| b >= *u)
        .map_or_else(
            || format!("{} B", sig(b)),
            |(u, n)| format!("{:.3} {n}", b / u),
        )
        .replace(".000 ", " ")
}

/// A count for messages: whole below a million, else "1.234e14".
fn count_text(n: f64) -> String {
    if n < 1e6 {
        format!("{}", n.round())
    } else {
        format!("{n:.3e}")
    }
}

/// Parse a memory size: bytes, or a number with a unit (B, kB, MB, GB, TB, KiB, MiB, GiB, TiB).
pub fn parse_bytes(text: &str) -> Option<f64> {
    let t = text.trim();
    let split = t
        .find(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
        .unwrap_or(t.len());
    let (number, unit) = t.split_at(split);
    let factor = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1.0,
        "kb" => 1e3,
        "mb" => 1e6,
        "gb" => 1e9,
        "tb" => 1e12,
        "kib" => 1024.0,
        "mib" => 1024.0 * 1024.0,
        "gib" => GIB,
        "tib" => 1024.0 * GIB,
        _ => return None,
    };
    let v = number.trim().parse::<f64>().ok()? * factor;
    (v.is_finite() && v > 0.0).then_some(v)
}

/// A malformed `TURF_MAX_MEMORY`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}=\"{value}\" is not a memory size: give bytes or a number with B, kB, MB, GB, TB, KiB, MiB, GiB or TiB, e.g. \"8 GB\"", CEILING_VAR)]
pub struct CeilingError {
    /// the variable's value
    pub value: String,
}

/// The ceiling: `TURF_MAX_MEMORY`, else half the machine's memory, else the fallback.
/// A malformed `TURF_MAX_MEMORY` is an error naming it.
pub fn ceiling() -> Result<Ceiling, CeilingError> {
    if let Ok(v) = std::env::var(CEILING_VAR) {
        return parse_bytes(&v)
            .map(|bytes| Ceiling {
                bytes,
                source: format!("{CEILING_VAR}={v}"),
            })
            .ok_or(CeilingError { value: v });
    }
    Ok(machine_memory().map_or_else(
        || Ceiling {
            bytes: FALLBACK_CEILING,
            source: format!(
                "the fallback {}, machine memory unknown; {CEILING_VAR} overrides",
                bytes_text(FALLBACK_CEILING)
            ),
        },
        |total| Ceiling {
            bytes: 0.5 * total,
            source: format!(
                "half of this machine's {}; {CEILING_VAR} overrides",
                bytes_text(total)
            ),
        },
    ))
}

/// `MemTotal` from `/proc/meminfo`, bytes.
fn machine_memory() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// Elements the continuum stage can hold within `bytes`.
fn elements_within(bytes: f64) -> f64 {
    (bytes / FE_BYTES_PER_ELEMENT).floor()
}

/// Estimate each sized stage's memory and refuse (in `c`, naming the keys) what exceeds the
/// ceiling. Run on a scene whose sections passed their own checks.
pub(crate) fn estimate(scene: &Scene, c: &mut Checker) -> Memory {
    let ceiling = match ceiling() {
        Ok(x) => x,
        Err(m) => {
            c.bad(CEILING_VAR, m.to_string());
            Ceiling {
                bytes: FALLBACK_CEILING,
                source: "the fallback".into(),
            }
        }
    };
    let budget = Budget {
        limit: ceiling.bytes,
        source: &ceiling.source,
    };
    let saved_steps = scene
        .compression
        .as_ref()
        .map_or(1.0, |k| k.path_steps() as f64 + 1.0);
    let nodes = NodeCost {
        bytes: DISCRETE_BYTES_PER_NODE + CHECKPOINT_BYTES_PER_NODE * saved_steps,
        lower_steps: if scene.compression.is_some() {
            ", fewer compression.steps"
        } else {
            ""
        },
    };
    let mut stages = Vec::new();
    if let Some(t) = &scene.turf {
        stages.push(turf_memory(t, &nodes, &budget, c));
    }
    if let Some(r) = &scene.rods {
        stages.push(rods_memory(r, &nodes, &budget, c));
    }
    if let Some(est) = halfspace_nodes(scene) {
        stages.push(halfspace_memory(scene, est, &budget, c));
    }
    if scene.schedule.is_some() {
        stages.push(continuum_memory(scene, &budget, c));
    }
    Memory { ceiling, stages }
}

/// The memory ceiling, for the stages' refusals.
struct Budget<'a> {
    /// bytes
    limit: f64,
    /// where it comes from
    source: &'a str,
}

impl Budget<'_> {
    /// Whether `bytes` exceed the ceiling (a NaN estimate counts as over).
    fn over(&self, bytes: f64) -> bool {
        bytes.is_nan() || bytes > self.limit
    }

    /// A stage's refusal: the key that drives its size, the estimate and how to lower it.
    fn refuse(
        &self,
        c: &mut Checker,
        key: String,
        stage: &str,
        bytes: f64,
        detail: &str,
        advice: &str,
    ) {
        c.bad(
            key,
            format!(
                "the {stage} stage would need about {} for {detail}, beyond the memory ceiling {} ({}): {advice}",
                bytes_text(bytes),
                bytes_text(self.limit),
                self.source
            ),
        );
    }
}

/// What a node of the discrete engine costs, with its saved steps.
struct NodeCost {
    bytes: f64,
    /// the advice to save fewer steps, if the scene saves them
    lower_steps: &'static str,
}

/// The discrete engine on a generated turf.
fn turf_memory(
    t: &super::turf::Turf,
    nodes: &NodeCost,
    budget: &Budget,
    c: &mut Checker,
) -> StageMemory {
    let tubes = t.tube_count();
    let segment = t.tube.segment.map_or(t.growth.length.0 / 20.0, |s| s.0);
    let per_tube = (t.growth.length.0 / segment).ceil().max(2.0);
    let count = tubes * (per_tube + 1.0);
    // the realisations of an ensemble run one per thread
    let at_once = t.realisations.min(rayon::current_num_threads()).max(1);
    let bytes = count * nodes.bytes * at_once as f64;
    let mut detail = format!(
        "{} tubes (turf.density × turf.box) × {} segments (turf.growth.length / turf.tube.segment)",
        count_text(tubes),
        count_text(per_tube)
    );
    let mut fewer = "";
    if at_once > 1 {
        detail.push_str(&format!(
            " × {at_once} realisations at once (turf.realisations, one per thread)"
        ));
        fewer = ", fewer threads (RAYON_NUM_THREADS)";
    }
    if budget.over(bytes) {
        let advice = format!(
            "use a smaller turf.box or turf.density, longer turf.tube.segment{}{fewer}",
            nodes.lower_steps
        );
        budget.refuse(c, "turf.box".into(), "discrete", bytes, &detail, &advice);
    }
    StageMemory {
        stage: Stage::Discrete,
        bytes,
        detail,
    }
}

/// The discrete engine on the scene's rods.
fn rods_memory(
    r: &super::rods::Rods,
    nodes: &NodeCost,
    budget: &Budget,
    c: &mut Checker,
) -> StageMemory {
    let count: f64 = r.rod.iter().map(|r| r.segments as f64 + 1.0).sum();
    let bytes = count * nodes.bytes;
    let detail = format!("{} rod nodes (rods.rod[i].segments + 1)", count_text(count));
    if budget.over(bytes) {
        let i = (0..r.rod.len())
            .max_by_key(|&i| r.rod[i].segments)
            .unwrap_or(0);
        let advice = format!("use fewer segments{}", nodes.lower_steps);
        let key = format!("rods.rod[{i}].segments");
        budget.refuse(c, key, "discrete", bytes, &detail, &advice);
    }
    StageMemory {
        stage: Stage::Discrete,
        bytes,
        detail,
    }
}

/// The half-space solver's dense matrices on `est` grid nodes.
fn halfspace_memory(scene: &Scene, est: f64, budget: &Budget, c: &mut Checker) -> StageMemory {
    let bytes = HALFSPACE_MATRICES * 8.0 * est * est;
    let detail = format!(
        "about {} grid nodes (halfspace.cells_per_zone{}), dense matrices",
        count_text(est),
        if scene.halfspace.as_ref().is_some_and(|h| h.refinement) {
            ", finest grid of halfspace.refinement"
        } else {
            ""
        }
    );
    if budget.over(bytes) {
        let advice =
            "lower halfspace.cells_per_zone (default 12) or set halfspace.refinement = false";
        budget.refuse(
            c,
            "halfspace.cells_per_zone".into(),
            "halfspace",
            bytes,
            &detail,
            advice,
        );
    }
    StageMemory {
        stage: Stage::Halfspace,
        bytes,
        detail,
    }
}

/// The FE mesh at its element cap.
fn continuum_memory(scene: &Scene, budget: &Budget, c: &mut Checker) -> StageMemory {
    let given = scene.mesh.as_ref().and_then(|m| m.max_elements);
    let n = given.map_or(crate::continuum::mesh::DEFAULT_MAX_ELEMENTS as f64, |n| {
        n as f64
    });
    let bytes = n * FE_BYTES_PER_ELEMENT;
    if given.is_some() && budget.over(bytes) {
        c.bad(
            "mesh.max_elements",
            format!(
                "{} elements would need about {}, beyond the memory ceiling {} ({}): at most {} on this machine",
                count_text(n),
                bytes_text(bytes),
                bytes_text(budget.limit),
                budget.source,
                count_text(elements_within(budget.limit))
            ),
        );
    }
    let cap = n.min(elements_within(budget.limit));
    StageMemory {
        stage: Stage::Continuum,
        bytes: cap * FE_BYTES_PER_ELEMENT,
        detail: format!("at most {} elements (mesh.max_elements)", count_text(cap)),
    }
}

/// Nodes of the half-space's finest grid, when the scene has a `[halfspace]` it can build.
fn halfspace_nodes(scene: &Scene) -> Option<f64> {
    let (hs, a, i, m) = (
        scene.halfspace.as_ref()?,
        scene.adhesion.as_ref()?,
        scene.indenter.as_ref()?,
        scene.material.as_ref()?,
    );
    let (e, nu) = m.initial_elastic()?;
    let law = a
        .surface_law_of(hs.law.unwrap_or(a.law), scene.turf.as_ref())
        .ok()?;
    let problem = crate::halfspace::Problem::new(i.radius.0, e / (1.0 - nu * nu), law).ok()?;
    let params = crate::halfspace::HalfspaceParams {
        cells_per_zone: hs.cells_per_zone,
        ..crate::halfspace::HalfspaceParams::default()
    };
    Some(crate::halfspace::trace_grid::estimated_nodes(
        &problem,
        &params,
        hs.refinement,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_sizes_parse_with_and_without_units() {
        assert_eq!(parse_bytes("1000"), Some(1000.0));
        assert_eq!(parse_bytes("2e9"), Some(2e9));
        assert_eq!(parse_bytes("8 GB"), Some(8e9));
        assert_eq!(parse_bytes("1GiB"), Some(GIB));
        assert_eq!(parse_bytes("512 MiB"), Some(512.0 * 1024.0 * 1024.0));
        for bad in ["", "GB", "8 parsecs", "-1", "0", "inf"] {
            assert_eq!(parse_bytes(bad), None, "{bad}");
        }
    }

    #[test]
    fn byte_counts_read_in_decimal_units() {
        assert_eq!(bytes_text(3.2e9), "3.200 GB");
        assert_eq!(bytes_text(2e14), "200 TB");
        assert_eq!(bytes_text(2e18), "2.000e18 bytes");
        assert_eq!(bytes_text(12.0), "12 B");
    }
}
