//! `--set KEY=VALUE`: overrides applied to the TOML document before it is read into the typed
//! scene, so that they are validated exactly like values written in the file.
//!
//! KEY is a dotted path (`adhesion.gamma`); array elements are addressed as
//! `schedule.segment[1].rate` or `schedule.segment.1.rate`. VALUE is read as a TOML value
//! (`0.2`, `true`, `[0.35, 0.1]`, `"0.2 J/m^2"`) and, if it is not one, as a string — so
//! `--set adhesion.gamma="0.2 J/m^2"` works after the shell has removed the quotes.

use super::error::SceneError;
use toml::{Table, Value};

/// One step of a key path.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// a table key
    Key(String),
    /// an array index
    Index(usize),
}

/// A parsed `--set` argument.
#[derive(Debug, Clone)]
pub struct Override {
    /// the argument as given
    pub arg: String,
    /// the path, canonically written (`schedule.segment[1].rate`)
    pub key: String,
    /// the path's steps
    pub steps: Vec<Step>,
    /// the value
    pub value: Value,
}

/// Parse a key path into steps; `None` if it is malformed.
pub fn parse_path(key: &str) -> Option<Vec<Step>> {
    let mut steps = Vec::new();
    for part in key.split('.') {
        let (name, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if name.is_empty() && (steps.is_empty() || rest.is_empty()) {
            return None;
        }
        if !name.is_empty() {
            if name.chars().all(|c| c.is_ascii_digit()) && !steps.is_empty() {
                steps.push(Step::Index(name.parse().ok()?));
            } else if name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
            {
                steps.push(Step::Key(name.to_string()));
            } else {
                return None;
            }
        }
        while !rest.is_empty() {
            let close = rest.find(']')?;
            steps.push(Step::Index(rest.get(1..close)?.parse().ok()?));
            rest = &rest[close + 1..];
            if !rest.is_empty() && !rest.starts_with('[') {
                return None;
            }
        }
    }
    (!steps.is_empty()).then_some(steps)
}

/// Write steps as a canonical key path.
pub fn path_string(steps: &[Step]) -> String {
    let mut s = String::new();
    for st in steps {
        match st {
            Step::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                s.push_str(k);
            }
            Step::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// Read the value of `--set`: a TOML value if it is one, else the text as a string.
pub fn parse_value(text: &str) -> Value {
    let probe = format!("v = {text}");
    match probe.parse::<Table>() {
        Ok(mut t) if t.len() == 1 => t.remove("v").unwrap_or_else(|| Value::String(text.into())),
        _ => Value::String(text.trim().to_string()),
    }
}

impl Override {
    /// Parse `KEY=VALUE`.
    pub fn parse(arg: &str) -> Result<Override, SceneError> {
        let bad = |message: &str| SceneError::Override {
            arg: arg.to_string(),
            message: message.to_string(),
        };
        let (key, value) = arg
            .split_once('=')
            .ok_or_else(|| bad("expected KEY=VALUE, e.g. --set adhesion.gamma=\"0.2 J/m^2\""))?;
        let steps = parse_path(key.trim()).ok_or_else(|| {
            bad("the key must be a dotted path such as adhesion.gamma or schedule.segment[1].rate")
        })?;
        Ok(Override {
            arg: arg.to_string(),
            key: path_string(&steps),
            steps,
            value: parse_value(value),
        })
    }

    /// Set the value in `doc`, creating tables on the way; arrays must already hold the index.
    pub fn apply(&self, doc: &mut Table) -> Result<(), SceneError> {
        set(doc, &self.steps, self.value.clone()).map_err(|e| SceneError::Override {
            arg: self.arg.clone(),
            message: e.to_string(),
        })
    }
}

/// Why a value could not be set at a key path.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PathError {
    /// the index is past the end of the array
    #[error("{at} has {len} element(s); index {index} is out of range")]
    OutOfRange {
        /// the array's path
        at: String,
        /// its length
        len: usize,
        /// the index asked for
        index: usize,
    },
    /// the value on the path is neither a table (for a key) nor an array (for an index)
    #[error("{} is {kind}, so it has no element {step}", if .at.is_empty() { "the scene" } else { .at.as_str() })]
    NoElement {
        /// the value's path ("" for the scene itself)
        at: String,
        /// the value's TOML type
        kind: &'static str,
        /// the step that cannot be taken, as written in a path
        step: String,
    },
}

/// Set `value` at `steps` in `doc`.
pub fn set(doc: &mut Table, steps: &[Step], value: Value) -> Result<(), PathError> {
    let mut here = Value::Table(std::mem::take(doc));
    let result = set_in(&mut here, steps, value, String::new());
    if let Value::Table(t) = here {
        *doc = t;
    }
    result
}

fn set_in(here: &mut Value, steps: &[Step], value: Value, at: String) -> Result<(), PathError> {
    let Some((first, rest)) = steps.split_first() else {
        *here = value;
        return Ok(());
    };
    match (first, here) {
        (Step::Key(k), Value::Table(t)) => {
            let child = t
                .entry(k.clone())
                .or_insert_with(|| Value::Table(Table::new()));
            let p = if at.is_empty() {
                k.clone()
            } else {
                format!("{at}.{k}")
            };
            set_in(child, rest, value, p)
        }
        (Step::Index(i), Value::Array(a)) => {
            let n = a.len();
            let Some(child) = a.get_mut(*i) else {
                return Err(PathError::OutOfRange {
                    at,
                    len: n,
                    index: *i,
                });
            };
            set_in(child, rest, value, format!("{at}[{i}]"))
        }
        (_, other) => Err(PathError::NoElement {
            kind: other.type_str(),
            step: path_string(std::slice::from_ref(first)),
            at,
        }),
    }
}

/// The value at `steps`, if present.
pub fn get<'a>(doc: &'a Table, steps: &[Step]) -> Option<&'a Value> {
    let (Step::Key(first), rest) = steps.split_first()? else {
        return None;
    };
    let mut here = doc.get(first)?;
    for s in rest {
        here = match (s, here) {
            (Step::Key(k), Value::Table(t)) => t.get(k)?,
            (Step::Index(i), Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(here)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_accept_both_index_spellings() {
        let a = parse_path("schedule.segment[1].rate").unwrap();
        let b = parse_path("schedule.segment.1.rate").unwrap();
        assert_eq!(a, b);
        assert_eq!(path_string(&a), "schedule.segment[1].rate");
        assert!(parse_path("").is_none());
        assert!(parse_path("a..b").is_none());
        assert!(parse_path("a.b c").is_none());
    }

    #[test]
    fn values_are_toml_or_else_strings() {
        assert_eq!(parse_value("0.2"), Value::Float(0.2));
        assert_eq!(parse_value("true"), Value::Boolean(true));
        assert_eq!(parse_value("0.2 J/m^2"), Value::String("0.2 J/m^2".into()));
        assert_eq!(parse_value("\"5 nm\""), Value::String("5 nm".into()));
        assert!(matches!(parse_value("[1, 2]"), Value::Array(_)));
    }

    #[test]
    fn set_creates_tables_and_refuses_missing_indices() {
        let mut doc: Table = "[[schedule.segment]]\nkind = \"load\"\n".parse().unwrap();
        set(
            &mut doc,
            &parse_path("adhesion.gamma").unwrap(),
            Value::Float(0.1),
        )
        .unwrap();
        assert_eq!(
            get(&doc, &parse_path("adhesion.gamma").unwrap()),
            Some(&Value::Float(0.1))
        );
        set(
            &mut doc,
            &parse_path("schedule.segment[0].to").unwrap(),
            Value::Float(5.0),
        )
        .unwrap();
        let e = set(
            &mut doc,
            &parse_path("schedule.segment[3].to").unwrap(),
            Value::Float(5.0),
        );
        assert!(e.unwrap_err().to_string().contains("out of range"));
        let e = set(
            &mut doc,
            &parse_path("adhesion.gamma.x").unwrap(),
            Value::Float(5.0),
        );
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("adhesion.gamma is float"));
    }
}
