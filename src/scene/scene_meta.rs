//! `[scene]`: the scene's name, description and random seed.

use super::check::Checker;
use serde::{Deserialize, Serialize};

/// `[scene]`: what the scene is called and the seed of every random choice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneMeta {
    /// Name of the scene; it names the output folder `runs/<name>/`. Letters, digits, `-`,
    /// `_` and `.`. Default: the file name without `.toml`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// One-line description, echoed in `summary.json`. Default: empty.
    #[serde(default)]
    pub description: String,
    /// Seed of every random choice (turf generation, ...): a run gives the same numbers with the
    /// same seed. Default 1.
    #[serde(default = "default_seed")]
    pub seed: u64,
}

fn default_seed() -> u64 {
    1
}

impl Default for SceneMeta {
    fn default() -> Self {
        SceneMeta {
            name: None,
            description: String::new(),
            seed: default_seed(),
        }
    }
}

impl SceneMeta {
    pub(crate) fn check(&self, c: &mut Checker) {
        if let Some(name) = &self.name {
            let ok = !name.is_empty()
                && !name.starts_with('.')
                && name
                    .chars()
                    .all(|ch| ch.is_ascii_alphanumeric() || "-_.".contains(ch));
            if !ok {
                c.bad(
                    "scene.name",
                    format!("\"{name}\" is not allowed: it names a folder, so use letters, digits, '-', '_' and '.' (not first)"),
                );
            }
        }
    }
}
