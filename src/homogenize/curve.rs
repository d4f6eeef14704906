//! Input curves of the homogenisation: a nominal compressive stress–strain curve (with an
//! optional lateral-strain column) and a stress-relaxation curve, read from CSV and validated.
//!
//! Conventions (as the tangent law (5.1) and DESIGN.md): the nominal axial strain ε = 1 − λ is
//! positive in compression, the nominal stress (force over undeformed area) positive in
//! compression; the nominal lateral strain εₗ = λₗ − 1 is positive when the sample widens.
//!
//! CSV format: a header row naming the columns, then one row per point; `#` starts a comment
//! line. Stress-strain columns: `strain` (or `strain_nominal`), one stress column whose name
//! carries its unit — `stress_GPa`, `stress_MPa`, `stress_kPa` or `stress_Pa` — and optionally
//! `lateral_strain`. Relaxation columns: `time_s` and either `g` (the normalised relaxation
//! modulus) or a stress column as above. Any other column is refused.

use std::fmt;

/// The smallest number of points accepted (a 3-parameter fit needs a few more than 3).
pub const MIN_POINTS: usize = 6;

/// Largest negative stress accepted, as a fraction of the peak (noise about zero).
pub const NEGATIVE_NOISE: f64 = 0.05;

/// A compressive nominal stress–strain curve, internal units.
#[derive(Debug, Clone, PartialEq)]
pub struct StressStrainCurve {
    /// nominal compressive strain ε = 1 − λ, strictly increasing, 0 ≤ ε < 1
    pub strain: Vec<f64>,
    /// nominal compressive stress, GPa
    pub stress: Vec<f64>,
    /// nominal lateral strain λₗ − 1 (positive when widening), if measured
    pub lateral_strain: Option<Vec<f64>>,
}

/// A stress-relaxation curve at a held strain.
#[derive(Debug, Clone, PartialEq)]
pub struct RelaxationCurve {
    /// time since the strain was applied, s, strictly increasing, ≥ 0
    pub time: Vec<f64>,
    /// the relaxing quantity: normalised modulus g(t) or a stress in GPa
    pub value: Vec<f64>,
    /// whether `value` is already normalised (a `g` column) or a stress to be normalised by
    /// the fit
    pub normalised: bool,
}

/// Why a curve was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct CurveError {
    /// where (file name, or "curve")
    pub source_name: String,
    /// what is wrong and what is allowed
    pub reason: String,
}

impl fmt::Display for CurveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.source_name, self.reason)
    }
}

fn err(source_name: &str, reason: String) -> CurveError {
    CurveError {
        source_name: source_name.to_string(),
        reason,
    }
}

/// Stress unit factors to GPa, by column-name suffix.
const STRESS_COLUMNS: [(&str, f64); 4] = [
    ("stress_gpa", 1.0),
    ("stress_mpa", 1e-3),
    ("stress_kpa", 1e-6),
    ("stress_pa", 1e-9),
];

/// Parsed CSV: header names (lower-cased) and rows of numbers with their line numbers.
struct Csv {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
}

fn parse_csv(text: &str, src: &str) -> Result<Csv, CurveError> {
    let split = |line: usize, row: &str| {
        crate::report::csv::split_fields(row, ',')
            .map_err(|e| err(src, format!("line {line}: {e}")))
    };
    let mut lines = crate::report::csv::strip_bom(text)
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (header_line, header) = lines.next().ok_or_else(|| {
        err(
            src,
            "empty file: expected a header row and data rows".into(),
        )
    })?;
    let names: Vec<String> = split(header_line, header)?
        .iter()
        .map(|s| s.to_ascii_lowercase())
        .collect();
    if names.iter().any(|n| n.parse::<f64>().is_ok()) {
        return Err(err(
            src,
            format!("the first row \"{header}\" holds numbers: a header row naming the columns is required"),
        ));
    }
    let mut columns = vec![Vec::new(); names.len()];
    for (line, row) in lines {
        let cells = split(line, row)?;
        if cells.len() != names.len() {
            return Err(err(
                src,
                format!(
                    "line {line}: {} values, the header has {} columns",
                    cells.len(),
                    names.len()
                ),
            ));
        }
        for (c, cell) in cells.iter().enumerate() {
            let v: f64 = cell.parse().map_err(|_| {
                err(
                    src,
                    format!(
                        "line {line}, column {}: \"{cell}\" is not a number",
                        names[c]
                    ),
                )
            })?;
            if !v.is_finite() {
                return Err(err(
                    src,
                    format!(
                        "line {line}, column {}: \"{cell}\" is not a finite number",
                        names[c]
                    ),
                ));
            }
            columns[c].push(v);
        }
    }
    Ok(Csv { names, columns })
}

impl Csv {
    fn take(&self, name: &str) -> Option<Vec<f64>> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.columns[i].clone())
    }
    fn refuse_unknown(&self, known: &[&str], src: &str) -> Result<(), CurveError> {
        match self.names.iter().find(|n| !known.contains(&n.as_str())) {
            Some(n) => Err(err(
                src,
                format!("unknown column \"{n}\" (allowed: {})", known.join(", ")),
            )),
            None => Ok(()),
        }
    }
    /// The single stress column, converted to GPa.
    fn stress(&self, src: &str) -> Result<Option<Vec<f64>>, CurveError> {
        let found: Vec<_> = STRESS_COLUMNS
            .iter()
            .filter_map(|(n, f)| {
                self.take(n)
                    .map(|v| v.into_iter().map(|x| x * f).collect::<Vec<f64>>())
            })
            .collect();
        match found.len() {
            0 => Ok(None),
            1 => Ok(found.into_iter().next()),
            _ => Err(err(src, "more than one stress column".into())),
        }
    }
}

fn strictly_increasing(v: &[f64], what: &str, src: &str) -> Result<(), CurveError> {
    match v.windows(2).position(|w| w[1] <= w[0]) {
        Some(i) => Err(err(
            src,
            format!(
                "{what} must increase strictly: data row {} ({}) is followed by {}",
                i + 1,
                v[i],
                v[i + 1]
            ),
        )),
        None => Ok(()),
    }
}

impl StressStrainCurve {
    /// Build from arrays and validate (see [`StressStrainCurve::validate`]).
    pub fn new(
        strain: Vec<f64>,
        stress: Vec<f64>,
        lateral_strain: Option<Vec<f64>>,
        src: &str,
    ) -> Result<Self, CurveError> {
        let c = StressStrainCurve {
            strain,
            stress,
            lateral_strain,
        };
        c.validate(src)?;
        Ok(c)
    }

    /// Read a CSV text (see the module doc for the columns).
    pub fn from_csv(text: &str, src: &str) -> Result<Self, CurveError> {
        let csv = parse_csv(text, src)?;
        let mut known = vec!["strain", "strain_nominal", "lateral_strain"];
        known.extend(STRESS_COLUMNS.iter().map(|(n, _)| *n));
        csv.refuse_unknown(&known, src)?;
        let strain = csv.take("strain").or_else(|| csv.take("strain_nominal")).ok_or_else(|| {
            err(src, format!("no strain column: expected \"strain\" (nominal, compression positive); found {:?}", csv.names))
        })?;
        let stress = csv.stress(src)?.ok_or_else(|| {
            err(src, format!("no stress column: expected one of stress_GPa, stress_MPa, stress_kPa, stress_Pa; found {:?}", csv.names))
        })?;
        Self::new(strain, stress, csv.take("lateral_strain"), src)
    }

    /// Check: at least [`MIN_POINTS`] points, equal lengths, finite values, strain strictly
    /// increasing within [0, 1), compressive stress (positive peak; points below zero by at most
    /// [`NEGATIVE_NOISE`] of the peak, as noise), lateral strain > −1.
    pub fn validate(&self, src: &str) -> Result<(), CurveError> {
        let n = self.strain.len();
        if self.stress.len() != n || self.lateral_strain.as_ref().is_some_and(|l| l.len() != n) {
            return Err(err(src, "columns of different lengths".into()));
        }
        if n < MIN_POINTS {
            return Err(err(
                src,
                format!("{n} points; at least {MIN_POINTS} are needed for a fit"),
            ));
        }
        let all = self
            .strain
            .iter()
            .chain(&self.stress)
            .chain(self.lateral_strain.iter().flatten());
        if all.clone().any(|x| !x.is_finite()) {
            return Err(err(src, "a value is NaN or infinite".into()));
        }
        strictly_increasing(&self.strain, "strain", src)?;
        if self.strain[0] < 0.0 || self.strain[n - 1] >= 1.0 {
            return Err(err(
                src,
                format!(
                    "strain must lie in [0, 1) (nominal compressive strain, compression positive); got {} to {}",
                    self.strain[0],
                    self.strain[n - 1]
                ),
            ));
        }
        // Noise may dip a point near the origin below zero; a curve that is mostly or strongly
        // negative has the opposite sign convention.
        let peak = self
            .stress
            .iter()
            .cloned()
            .fold(f64::NEG_INFINITY, f64::max);
        if peak == 0.0 && self.stress.iter().all(|&s| s == 0.0) {
            return Err(err(
                src,
                "every stress is zero: the curve carries no load to fit".into(),
            ));
        }
        if let Some(i) = self
            .stress
            .iter()
            .position(|&s| peak <= 0.0 || s < -NEGATIVE_NOISE * peak)
        {
            return Err(err(
                src,
                format!(
                    "stress {} at strain {} is negative: give the compressive stress as positive",
                    self.stress[i], self.strain[i]
                ),
            ));
        }
        if self.lateral_strain.iter().flatten().any(|&l| l <= -1.0) {
            return Err(err(
                src,
                "lateral strain must exceed -1 (a positive lateral stretch)".into(),
            ));
        }
        Ok(())
    }
}

impl RelaxationCurve {
    /// Read a CSV text with `time_s` and `g` or a stress column.
    pub fn from_csv(text: &str, src: &str) -> Result<Self, CurveError> {
        let csv = parse_csv(text, src)?;
        let mut known = vec!["time_s", "g"];
        known.extend(STRESS_COLUMNS.iter().map(|(n, _)| *n));
        csv.refuse_unknown(&known, src)?;
        let time = csv.take("time_s").ok_or_else(|| {
            err(
                src,
                format!("no time column \"time_s\"; found {:?}", csv.names),
            )
        })?;
        let (value, normalised) = match (csv.take("g"), csv.stress(src)?) {
            (Some(g), None) => (g, true),
            (None, Some(s)) => (s, false),
            _ => {
                return Err(err(
                    src,
                    "expected exactly one of a \"g\" column or a stress column (stress_GPa, stress_MPa, ...)".into(),
                ))
            }
        };
        let c = RelaxationCurve {
            time,
            value,
            normalised,
        };
        c.validate(src)?;
        Ok(c)
    }

    /// Check: at least [`MIN_POINTS`] points, finite, time strictly increasing from ≥ 0,
    /// positive values.
    pub fn validate(&self, src: &str) -> Result<(), CurveError> {
        let n = self.time.len();
        if self.value.len() != n {
            return Err(err(src, "columns of different lengths".into()));
        }
        if n < MIN_POINTS {
            return Err(err(
                src,
                format!("{n} points; at least {MIN_POINTS} are needed for a fit"),
            ));
        }
        if self.time.iter().chain(&self.value).any(|x| !x.is_finite()) {
            return Err(err(src, "a value is NaN or infinite".into()));
        }
        strictly_increasing(&self.time, "time", src)?;
        if self.time[0] < 0.0 {
            return Err(err(src, "time must be non-negative".into()));
        }
        if self.value.iter().any(|&v| v <= 0.0) {
            return Err(err(src, "relaxing values must be positive".into()));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str =
        "# a curve\nstrain,stress_MPa\n0,0\n0.01,6\n0.02,11\n0.05,20\n0.1,30\n0.2,40\n";

    #[test]
    fn a_good_curve_is_read_in_gpa() {
        let c = StressStrainCurve::from_csv(GOOD, "t.csv").unwrap();
        assert_eq!(c.strain.len(), 6);
        assert!((c.stress[5] - 0.040).abs() < 1e-15);
        assert!(c.lateral_strain.is_none());
    }

    fn refused(text: &str, needle: &str) {
        let e = StressStrainCurve::from_csv(text, "t.csv")
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle) && e.starts_with("t.csv"), "{e}");
    }

    #[test]
    fn bad_curves_are_refused_with_a_clear_reason() {
        refused("strain,stress_MPa\n0,0\n0.1,1\n", "at least 6");
        refused(
            "strain,stress_MPa\n0,0\n0.01,6\n0.03,11\n0.02,12\n0.1,30\n0.2,40\n",
            "increase strictly",
        );
        refused(
            "strain,stress_MPa\n0,0\n0.01,NaN\n0.02,11\n0.05,20\n0.1,30\n0.2,40\n",
            "not a finite number",
        );
        refused(
            "strain,force_N\n0,0\n0.01,6\n0.02,11\n0.05,20\n0.1,30\n0.2,40\n",
            "unknown column \"force_n\"",
        );
        refused(
            "eps,stress_MPa\n0,0\n0.01,6\n0.02,11\n0.05,20\n0.1,30\n0.2,40\n",
            "unknown column",
        );
        refused(
            "strain\n0\n0.01\n0.02\n0.05\n0.1\n0.2\n",
            "no stress column",
        );
        refused("0,0\n0.01,6\n0.02,11\n0.05,20\n0.1,30\n0.2,40\n", "header");
        refused("strain,stress_MPa\n0,0\n0.01,6,3\n", "line 3");
        refused(
            "strain,stress_MPa\n0,0\n-0.01,-6\n-0.02,-11\n-0.05,-20\n-0.1,-30\n-0.2,-40\n",
            "increase strictly",
        );
        refused(
            "strain,stress_MPa\n0,0\n0.01,-6\n0.02,-11\n0.05,-20\n0.1,-30\n0.2,-40\n",
            "negative",
        );
        refused(
            "strain,stress_MPa\n0,0\n0.01,6\n0.02,11\n0.05,20\n0.1,30\n1.2,40\n",
            "[0, 1)",
        );
        refused(
            "strain,stress_MPa\n0,0\n0.01,0\n0.02,0\n0.05,0\n0.1,0\n0.2,0\n",
            "every stress is zero",
        );
    }

    #[test]
    fn relaxation_curves() {
        let t = "time_s,g\n0,1\n1,0.9\n2,0.8\n4,0.7\n8,0.65\n16,0.6\n";
        let c = RelaxationCurve::from_csv(t, "r.csv").unwrap();
        assert!(c.normalised);
        let bad = "time_s,g,stress_MPa\n0,1,1\n1,0.9,1\n2,0.8,1\n4,0.7,1\n8,0.65,1\n16,0.6,1\n";
        assert!(RelaxationCurve::from_csv(bad, "r.csv").is_err());
    }
}
