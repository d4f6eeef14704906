//! Checkpoints of the platen drive: a long compression saves its state after
//! every strain step, and an interrupted run resumes from the last saved step with the same
//! curve as an uninterrupted one (`turf run … --resume`).
//!
//! The drive is a sequence of static equilibria, each warm-started from the previous one, and
//! every step's record (strain, stress, energies, contacts) is a function of its configuration
//! alone (the contact list is sorted and rebuilt from the positions, so its history does not
//! change a sum). A checkpoint therefore holds no random numbers and no solver state: the
//! platen's start height H₀, and for every step reached its node positions, the nodes the
//! sphere held during its solve (the stick option's anchors: path-dependent state, absent from
//! the file without that option) and what its solve cost. The positions read back bit for bit (serde_json's `float_roundtrip`): the resumed
//! solve must start from the very same configuration. With them the checkpoint holds the relaxation's report and the text of the
//! scene's `[turf]` and `[compression]` sections, so that a checkpoint of another scene is
//! refused rather than continued.

use super::drive::SavedStep;
use super::sphere_stick::Anchor;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Format version written into every checkpoint; a different one is refused.
const FORMAT: u32 = 2;

/// What the drive has done so far.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// [`FORMAT`]
    pub format: u32,
    /// the scene sections the run was started from (compared as text on resume)
    pub scene: String,
    /// the relaxation's report
    pub relaxation: SavedRelaxation,
    /// platen start height H₀, nm
    pub start_height: f64,
    /// steps reached, step 0 (the relaxed turf) first
    pub steps: Vec<SavedStep>,
}

/// The relaxation as reported in the summary (its configuration is step 0's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SavedRelaxation {
    /// Newton / FIRE iterations
    pub iterations: usize,
    /// energy + gradient evaluations
    pub gradient_evaluations: usize,
    /// wall time, s
    pub seconds: f64,
}

/// Why a checkpoint could not be used.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// reading or writing the file
    #[error("checkpoint {path}: {cause}")]
    Io {
        /// the file
        path: String,
        /// the cause (in the message, so not chained again as the error's source)
        cause: std::io::Error,
    },
    /// not a checkpoint of this format
    #[error("checkpoint {path} cannot be read: {reason}")]
    Invalid {
        /// the file
        path: String,
        /// what is wrong
        reason: String,
    },
    /// written for another scene or another number of nodes
    #[error(
        "checkpoint {path} belongs to another run: {reason}; remove it or run without --resume"
    )]
    Mismatch {
        /// the file
        path: String,
        /// what differs
        reason: String,
    },
}

impl Checkpoint {
    /// A checkpoint of `scene` after the relaxation and the steps `steps` from height `h0`.
    pub fn new(scene: &str, relaxation: SavedRelaxation, h0: f64, steps: &[SavedStep]) -> Self {
        Checkpoint {
            format: FORMAT,
            scene: scene.to_string(),
            relaxation,
            start_height: h0,
            steps: steps.to_vec(),
        }
    }

    /// Platen start height H₀, nm.
    pub fn start_height(&self) -> f64 {
        self.start_height
    }

    /// The saved steps, step 0 first.
    pub fn saved_steps(&self) -> Vec<SavedStep> {
        self.steps.clone()
    }

    /// Write to `path` atomically (a temporary file renamed over the old one), so that an
    /// interruption during the write leaves the previous checkpoint intact.
    pub fn save(&self, path: &Path) -> Result<(), CheckpointError> {
        let io = |cause| CheckpointError::Io {
            path: path.display().to_string(),
            cause,
        };
        let text = serde_json::to_string(self).map_err(|e| CheckpointError::Invalid {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let tmp = path.with_extension("json.tmp");
        std::fs::write(&tmp, text).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }

    /// Read the checkpoint at `path` (`Ok(None)` if there is none) and check that it belongs to
    /// `scene` with `coordinates` node coordinates per step.
    pub fn load(
        path: &Path,
        scene: &str,
        coordinates: usize,
    ) -> Result<Option<Checkpoint>, CheckpointError> {
        let p = path.display().to_string();
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(cause) => return Err(CheckpointError::Io { path: p, cause }),
        };
        let c: Checkpoint = serde_json::from_str(&text).map_err(|e| CheckpointError::Invalid {
            path: p.clone(),
            reason: e.to_string(),
        })?;
        let mismatch = |reason: String| CheckpointError::Mismatch {
            path: p.clone(),
            reason,
        };
        if c.format != FORMAT {
            return Err(CheckpointError::Invalid {
                path: p.clone(),
                reason: format!("format {} (this build reads {FORMAT})", c.format),
            });
        }
        if c.scene != scene {
            return Err(mismatch(
                "its [turf] / [compression] sections differ from the scene's".into(),
            ));
        }
        if c.steps.is_empty() {
            return Err(CheckpointError::Invalid {
                path: p,
                reason: "it holds no step".into(),
            });
        }
        if let Some(s) = c.steps.iter().find(|s| s.x.len() != coordinates) {
            return Err(mismatch(format!(
                "a step has {} coordinates, the turf {coordinates}",
                s.x.len()
            )));
        }
        let nodes = coordinates / 3;
        let bad_anchor = |a: &Anchor| {
            let norm = a.offset.iter().map(|v| v * v).sum::<f64>().sqrt();
            a.node >= nodes || !(norm.is_finite() && norm > 0.0)
        };
        if let Some(a) = c
            .steps
            .iter()
            .flat_map(|s| &s.anchors)
            .find(|a| bad_anchor(a))
        {
            return Err(CheckpointError::Invalid {
                path: p,
                reason: format!(
                    "a held node {} (offset {:?} nm) is not a node of the {nodes} or has no \
                     finite, nonzero offset from the sphere's centre",
                    a.node, a.offset
                ),
            });
        }
        Ok(Some(c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discrete::solve::Cost;

    /// A checkpoint path in a folder that does not exist yet (`save` creates it).
    fn temp(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("turf_checkpoint_{name}_{}", std::process::id()));
        std::fs::remove_dir_all(&d).ok();
        d.join("discrete_checkpoint.json")
    }

    fn steps() -> Vec<SavedStep> {
        // values that no short decimal represents: the bits must survive exactly
        let x = vec![0.1 + 0.2, std::f64::consts::PI * 1e3, -1.0 / 3.0, 7e-310];
        vec![
            SavedStep {
                cost: Cost::default(),
                x: x.clone(),
                anchors: Vec::new(),
            },
            SavedStep {
                cost: Cost {
                    iterations: 12,
                    gradient_evaluations: 30,
                    hessian_evaluations: 12,
                    factorizations: 15,
                    seconds: 0.25,
                },
                x: x.iter().map(|v| v * (1.0 + f64::EPSILON)).collect(),
                // a node the sphere holds: its offset must survive as exactly as x
                anchors: vec![Anchor {
                    node: 0,
                    offset: [x[0], x[1], -x[2]],
                }],
            },
        ]
    }

    fn relaxation() -> SavedRelaxation {
        SavedRelaxation {
            iterations: 5,
            gradient_evaluations: 9,
            seconds: 0.5,
        }
    }

    #[test]
    fn a_saved_checkpoint_reads_back_bit_for_bit() {
        let path = temp("roundtrip");
        let c = Checkpoint::new("[turf]\nx = 1", relaxation(), 2125.9 + 1e-12, &steps());
        c.save(&path).unwrap();
        let back = Checkpoint::load(&path, "[turf]\nx = 1", 4)
            .unwrap()
            .unwrap();
        assert_eq!(back, c);
        assert_eq!(back.start_height().to_bits(), (2125.9 + 1e-12f64).to_bits());
        let (a, b) = (back.saved_steps(), steps());
        for (s, t) in a.iter().zip(&b) {
            assert_eq!(s.cost, t.cost);
            assert_eq!(s.anchors.len(), t.anchors.len());
            for (u, v) in s.anchors.iter().zip(&t.anchors) {
                assert!(u
                    .offset
                    .iter()
                    .zip(&v.offset)
                    .all(|(p, q)| p.to_bits() == q.to_bits()));
            }
            assert!(s
                .x
                .iter()
                .zip(&t.x)
                .all(|(u, v)| u.to_bits() == v.to_bits()));
        }
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn no_file_is_no_checkpoint_and_another_run_is_refused() {
        let path = temp("mismatch");
        std::fs::remove_file(&path).ok();
        assert!(Checkpoint::load(&path, "s", 4).unwrap().is_none());
        Checkpoint::new("s", relaxation(), 1.0, &steps())
            .save(&path)
            .unwrap();
        let other = Checkpoint::load(&path, "t", 4).unwrap_err();
        assert!(matches!(other, CheckpointError::Mismatch { .. }), "{other}");
        let size = Checkpoint::load(&path, "s", 6).unwrap_err();
        assert!(size.to_string().contains("4 coordinates"), "{size}");
        // a held node outside the turf is refused, not indexed
        let mut held = steps();
        held[1].anchors[0].node = 2;
        Checkpoint::new("s", relaxation(), 1.0, &held)
            .save(&path)
            .unwrap();
        let node = Checkpoint::load(&path, "s", 4).unwrap_err();
        assert!(node.to_string().contains("held node 2"), "{node}");
        std::fs::write(&path, "{\"format\": 1").unwrap();
        let bad = Checkpoint::load(&path, "s", 4).unwrap_err();
        assert!(matches!(bad, CheckpointError::Invalid { .. }), "{bad}");
        std::fs::remove_file(&path).ok();
    }
}
