//! CSV tables of curves: one header row whose names carry their units (`depth_nm`, `load_nN`),
//! then one row per point. Written atomically; NaN or infinite values are refused.
//!
//! Reading (the curve and record readers of `homogenize` and `experiment`): [`strip_bom`]
//! drops a UTF-8 byte-order mark, [`split_fields`] splits a line honouring double-quoted
//! fields, as spreadsheets write them.

use super::{write_atomic, ReportError};
use std::path::Path;

/// A table of equally long named columns.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Table {
    columns: Vec<(String, Vec<f64>)>,
}

impl Table {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a column; its name should carry the unit (`load_nN`).
    pub fn column(mut self, name: &str, values: Vec<f64>) -> Self {
        self.columns.push((name.to_string(), values));
        self
    }

    /// The values of a column by name.
    pub fn get(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
    }

    /// Render as CSV text, checking lengths and finiteness.
    pub fn to_csv(&self, path_for_errors: &Path) -> Result<String, ReportError> {
        let path = path_for_errors.display().to_string();
        let rows = self.columns.first().map_or(0, |c| c.1.len());
        if let Some((name, v)) = self.columns.iter().find(|(_, v)| v.len() != rows) {
            return Err(ReportError::Invalid {
                path,
                reason: format!("column {name} has {} rows, expected {rows}", v.len()),
            });
        }
        if let Some((name, _)) = self
            .columns
            .iter()
            .find(|(_, v)| v.iter().any(|x| !x.is_finite()))
        {
            return Err(ReportError::NonFinite {
                path,
                what: format!("column {name}"),
            });
        }
        let mut out = self
            .columns
            .iter()
            .map(|c| c.0.as_str())
            .collect::<Vec<_>>()
            .join(",");
        out.push('\n');
        for i in 0..rows {
            let row: Vec<String> = self
                .columns
                .iter()
                .map(|c| format!("{:e}", c.1[i]))
                .collect();
            out.push_str(&row.join(","));
            out.push('\n');
        }
        Ok(out)
    }

    /// Write atomically to `path`.
    pub fn write(&self, path: &Path) -> Result<(), ReportError> {
        let text = self.to_csv(path)?;
        write_atomic(path, text.as_bytes())
    }
}

/// `text` without a leading UTF-8 byte-order mark (spreadsheets on Windows write one).
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// A line whose double-quoted field is not closed.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("a double-quoted field is not closed")]
pub struct UnclosedQuote;

/// Split one line at `sep` into trimmed fields; a field may be enclosed in double quotes
/// (`"1.5"`, `"load, uN"`), inside which `sep` is literal and `""` is one quote. An
/// unterminated quote is an error.
pub fn split_fields(line: &str, sep: char) -> Result<Vec<String>, UnclosedQuote> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') if field.trim().is_empty() => {
                field.clear();
                quoted = true;
            }
            (false, c) if c == sep => fields.push(std::mem::take(&mut field).trim().to_string()),
            (false, c) => field.push(c),
        }
    }
    if quoted {
        return Err(UnclosedQuote);
    }
    fields.push(field.trim().to_string());
    Ok(fields)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_split_with_quotes_and_a_bom_is_dropped() {
        let f = |l: &str| split_fields(l, ',').unwrap();
        assert_eq!(f("a, b ,c"), ["a", "b", "c"]);
        assert_eq!(f("\"strain\", \"stress_MPa\""), ["strain", "stress_MPa"]);
        assert_eq!(f("\"1,5\",\"say \"\"hi\"\"\""), ["1,5", "say \"hi\""]);
        assert_eq!(f("x,,"), ["x", "", ""]);
        assert_eq!(split_fields("a\t\"b\"", '\t').unwrap(), ["a", "b"]);
        assert!(split_fields("\"open,1", ',').is_err());
        assert_eq!(strip_bom("\u{feff}strain,stress_MPa"), "strain,stress_MPa");
        assert_eq!(strip_bom("strain"), "strain");
    }

    #[test]
    fn table_round_trips_values_exactly_and_refuses_nan() {
        let t = Table::new()
            .column("depth_nm", vec![0.0, 0.1, 1.0 / 3.0])
            .column("load_nN", vec![1e-300, -2.5, 7.0]);
        let text = t.to_csv(Path::new("x.csv")).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some("depth_nm,load_nN"));
        let third: Vec<f64> = lines
            .nth(2)
            .unwrap()
            .split(',')
            .map(|s| s.parse().unwrap())
            .collect();
        assert_eq!(third, vec![1.0 / 3.0, 7.0]);
        let bad = Table::new().column("a", vec![f64::NAN]);
        assert!(matches!(
            bad.to_csv(Path::new("x.csv")),
            Err(ReportError::NonFinite { .. })
        ));
        let ragged = Table::new().column("a", vec![1.0]).column("b", vec![]);
        assert!(matches!(
            ragged.to_csv(Path::new("x.csv")),
            Err(ReportError::Invalid { .. })
        ));
    }
}
