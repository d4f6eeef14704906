//! The checker that collects every problem of a scene (key, value, what is allowed) instead
//! of stopping at the first.

use super::quantity::{unit_name, Quantity};

/// Collects problems as (key path, message); lines are attached by the loader.
#[derive(Debug, Default)]
pub struct Checker {
    /// (key, message) in the order found
    pub problems: Vec<(String, String)>,
}

impl Checker {
    /// Record a problem with `key`.
    pub fn bad(&mut self, key: impl Into<String>, message: impl Into<String>) {
        self.problems.push((key.into(), message.into()));
    }

    /// A quantity that must be strictly positive.
    pub fn positive<Q: Quantity>(&mut self, key: &str, q: Q) {
        if q.value() <= 0.0 {
            self.bad(
                key,
                format!(
                    "{} {} is not allowed: must be positive",
                    q.value(),
                    unit_name(Q::DIMENSION)
                ),
            );
        }
    }

    /// An optional quantity that, if given, must be strictly positive.
    pub fn positive_opt<Q: Quantity>(&mut self, key: &str, q: Option<Q>) {
        if let Some(q) = q {
            self.positive(key, q);
        }
    }

    /// A plain number that must lie in `[lo, hi)` (or `(lo, hi)` when `open_low`).
    pub fn number_in(&mut self, key: &str, v: f64, lo: f64, hi: f64, open_low: bool) {
        let low_ok = if open_low { v > lo } else { v >= lo };
        if !(low_ok && v < hi) {
            let l = if open_low { "(" } else { "[" };
            self.bad(
                key,
                format!("{v} is not allowed: must lie in {l}{lo}, {hi})"),
            );
        }
    }

    /// A count that must be at least `min`.
    pub fn count_at_least(&mut self, key: &str, v: usize, min: usize) {
        if v < min {
            self.bad(key, format!("{v} is not allowed: must be at least {min}"));
        }
    }

    /// Record that `key` is not used in this configuration, and why.
    pub fn unused(&mut self, key: &str, why: &str) {
        self.bad(key, format!("is not used {why}; remove it"));
    }
}

/// A number to six significant figures, for messages; exponent form beyond 1e-4 … 1e7 in magnitude.
pub fn sig(x: f64) -> String {
    let v = format!("{:.5e}", x).parse::<f64>().unwrap_or(x);
    // very large or small magnitudes in exponent form: 1e-300 is "1e-300", not 300 digits
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}
