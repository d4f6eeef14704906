//! `[output]`: where results go and which optional files are written. `summary.json` and
//! the CSV curves are always written.

use super::check::Checker;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// `[output]`: output folder and optional files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// Output folder, relative to the working directory; not empty. Default
    /// `runs/<scene name>`; `turf run --out DIR` overrides both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dir: Option<PathBuf>,
    /// Write plots (`plots/*.svg`, `*.png`). Default true.
    #[serde(default = "yes")]
    pub plots: bool,
    /// Write VTK files for ParaView (`vtk/`) where a stage has a mesh or tubes. Default false.
    #[serde(default)]
    pub vtk: bool,
    /// Write material cards (`material.json`, `material.inp`) from the homogenize stage.
    /// Default true.
    #[serde(default = "yes")]
    pub cards: bool,
}

fn yes() -> bool {
    true
}

impl Default for Output {
    fn default() -> Self {
        Output {
            dir: None,
            plots: true,
            vtk: false,
            cards: true,
        }
    }
}

impl Output {
    pub(crate) fn check(&self, c: &mut Checker) {
        if self
            .dir
            .as_ref()
            .is_some_and(|d| d.as_os_str().to_string_lossy().trim().is_empty())
        {
            c.bad(
                "output.dir",
                "\"\" is not allowed: name a folder (e.g. \"runs/my_scene\"), or remove the key for runs/<scene name>",
            );
        }
    }
}
