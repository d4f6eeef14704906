//! Why a scene was refused: every message names the file, the key (with its line where the
//! file has one), the value and what is allowed.

use std::fmt;
use std::path::PathBuf;

/// One problem found in a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// dotted key path, e.g. `adhesion.gamma` or `schedule.segment[1].rate`
    pub key: String,
    /// 1-based line in the scene file, when the key is written there
    pub line: Option<usize>,
    /// true when the key was given by `--set` on the command line
    pub is_from_command_line: bool,
    /// what is wrong: the value and what is allowed
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match (self.line, self.is_from_command_line) {
            (_, true) => write!(f, "{} (from --set): {}", self.key, self.message),
            (Some(l), false) => write!(f, "line {l}: {}: {}", self.key, self.message),
            (None, false) => write!(f, "{}: {}", self.key, self.message),
        }
    }
}

/// A scene that cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// the file could not be read
    #[error("cannot read scene {}", file.display())]
    Io {
        /// the scene file
        file: PathBuf,
        /// the cause (reported as the error's source)
        #[source]
        source: std::io::Error,
    },
    /// the file is not valid TOML
    #[error("{}:{line}:{column}: malformed TOML: {message}", file.display())]
    Syntax {
        /// the scene file
        file: PathBuf,
        /// 1-based line
        line: usize,
        /// 1-based column
        column: usize,
        /// the parser's message
        message: String,
    },
    /// a `--set KEY=VALUE` argument that cannot be applied
    #[error("--set {arg}: {message}")]
    Override {
        /// the argument as given
        arg: String,
        /// what is wrong and what is allowed
        message: String,
    },
    /// keys or values that do not make sense
    #[error("{}: {}", file.display(), list(problems))]
    Invalid {
        /// the scene file
        file: PathBuf,
        /// every problem found
        problems: Vec<Problem>,
    },
}

fn list(problems: &[Problem]) -> String {
    match problems {
        [one] => one.to_string(),
        many => {
            let mut s = format!("{} problems", many.len());
            for p in many {
                s.push_str("\n  ");
                s.push_str(&p.to_string());
            }
            s
        }
    }
}

impl SceneError {
    /// The problems of an `Invalid` scene (empty for the other kinds).
    pub fn problems(&self) -> &[Problem] {
        match self {
            SceneError::Invalid { problems, .. } => problems,
            _ => &[],
        }
    }
}
