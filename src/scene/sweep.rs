//! `[sweep]`: one numeric key varied over a list of values; every stage runs once per value.

use serde::{Deserialize, Serialize};

/// `[sweep]`: the key and its values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sweep {
    /// Dotted path of an existing numeric key, e.g. `"adhesion.gamma"` or
    /// `"schedule.segment[1].rate"`. Required.
    pub key: String,
    /// Values, each a number or a quantity string valid for that key. At least one.
    pub values: Vec<toml::Value>,
}
