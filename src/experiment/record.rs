//! A force-controlled indentation record (time, applied force, displacement) read from text and
//! validated: the input of the fit of the quasi-rheological law (seed §2.3, eqs. 2.1–2.7).
//!
//! Two formats are accepted (docs/fit-indentation.md):
//!
//! - **CSV**: a header row naming the columns, then one row per sample; `#` starts a comment
//!   line. A column name is `QUANTITY_UNIT`: `time_UNIT` (`time_s`, `time_ms`),
//!   `load_UNIT` or `force_UNIT` (`load_uN`, `load_nN`, `load_mN`, `load_µN`),
//!   `depth_UNIT` or `displacement_UNIT` (`depth_nm`, `displacement_um`).
//! - **Nanoindenter text export** (Hysitron TriboScan: TriboScope, TI 9xx): any number of free
//!   header lines, then a tab-separated table whose header row names columns `NAME (UNIT)`:
//!   `Depth (nm)`, `Load (µN)` (or `Load (uN)`), `Time (s)`. Columns in volts (`Depth (V)`,
//!   `Load (V)`, the raw transducer signals) are skipped. Files in Latin-1 (the export's usual
//!   encoding of µ) are accepted as well as UTF-8.
//!
//! Units are converted once, here, by [`crate::units::parse_quantity`]; a unit of the wrong
//! dimension or an unknown one is refused. Columns with other names are ignored. Refused with
//! the file, line and column: a missing column, two columns of one quantity, a cell that is not
//! a finite number, a time that does not increase strictly, fewer than [`MIN_POINTS`] samples,
//! a load or a displacement that never changes.

use crate::units::{parse_quantity, Dimension};
use std::fmt;

/// The fewest samples accepted: four parameters are fitted (K₁, K₂, η and an offset), and
/// their standard errors need residual degrees of freedom; ten samples leave six (any real
/// record has far more).
pub const MIN_POINTS: usize = 10;

/// Which text format a record came in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Format {
    /// comma-separated with `QUANTITY_UNIT` column names
    Csv,
    /// tab-separated nanoindenter export with `Name (unit)` column names
    NanoindenterText,
}

/// A validated record, internal units.
#[derive(Debug, Clone, PartialEq)]
pub struct IndentationRecord {
    /// time, s, strictly increasing
    pub time: Vec<f64>,
    /// the force the instrument applies, nN
    pub load: Vec<f64>,
    /// the displacement the instrument measures, nm
    pub displacement: Vec<f64>,
    /// the format read
    pub format: Format,
    /// the header names of the (time, load, displacement) columns used
    pub columns: [String; 3],
}

/// Why a record was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct RecordError {
    /// the file (or a name for text not read from a file)
    pub source_name: String,
    /// the 1-based line, where one is at fault
    pub line: Option<usize>,
    /// the column, where one is at fault
    pub column: Option<String>,
    /// what is wrong and what is allowed
    pub reason: String,
}

impl fmt::Display for RecordError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.source_name)?;
        if let Some(l) = self.line {
            write!(f, ", line {l}")?;
        }
        if let Some(c) = &self.column {
            write!(f, ", column \"{c}\"")?;
        }
        write!(f, ": {}", self.reason)
    }
}

/// The three quantities a record needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Quantity {
    Time,
    Load,
    Displacement,
}

impl Quantity {
    fn from_name(name: &str) -> Option<Quantity> {
        match name.trim().to_lowercase().as_str() {
            "time" => Some(Quantity::Time),
            "load" | "force" => Some(Quantity::Load),
            "depth" | "displacement" => Some(Quantity::Displacement),
            _ => None,
        }
    }
    fn word(self) -> &'static str {
        match self {
            Quantity::Time => "time",
            Quantity::Load => "load",
            Quantity::Displacement => "displacement",
        }
    }
    fn dimension(self) -> Dimension {
        match self {
            Quantity::Time => Dimension::Time,
            Quantity::Load => Dimension::Force,
            Quantity::Displacement => Dimension::Length,
        }
    }
    fn examples(self, format: Format) -> &'static str {
        match (self, format) {
            (Quantity::Time, Format::Csv) => "time_s",
            (Quantity::Load, Format::Csv) => "load_uN, load_nN, load_mN or force_uN",
            (Quantity::Displacement, Format::Csv) => "depth_nm or displacement_nm",
            (Quantity::Time, Format::NanoindenterText) => "Time (s)",
            (Quantity::Load, Format::NanoindenterText) => "Load (µN)",
            (Quantity::Displacement, Format::NanoindenterText) => "Depth (nm)",
        }
    }
}

/// A column the record uses: its position, header name and factor to internal units.
struct Column {
    index: usize,
    name: String,
    factor: f64,
}

/// Decode a file's bytes: UTF-8, or else Latin-1 (each byte one code point), the encoding in
/// which nanoindenter software usually writes `µ`.
pub fn decode(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
    }
}

/// Split a header cell into (quantity name, unit) by the format's naming rule.
fn split_name(cell: &str, format: Format) -> Option<(&str, &str)> {
    let cell = cell.trim();
    match format {
        Format::Csv => cell.split_once('_'),
        Format::NanoindenterText => {
            let open = cell.find('(')?;
            let unit = cell[open + 1..].strip_suffix(')')?;
            Some((cell[..open].trim(), unit.trim()))
        }
    }
}

/// A nanoindenter table header: tab-separated, with a `Depth (..)`, `Load (..)` or `Time (..)`.
fn is_table_header(line: &str) -> bool {
    line.contains('\t')
        && line.split('\t').any(|c| {
            split_name(c, Format::NanoindenterText)
                .is_some_and(|(q, _)| Quantity::from_name(q).is_some())
        })
}

/// Parse a record from text; `source_name` names it in errors.
pub fn parse_record(text: &str, source_name: &str) -> Result<IndentationRecord, RecordError> {
    let src = Source(source_name);
    let lines: Vec<(usize, &str)> = crate::report::csv::strip_bom(text)
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end()))
        .collect();
    let (format, header_at) = detect_format(&lines, &src)?;
    let (header_line, header) = lines[header_at];
    let names = src.split(header_line, header, format)?;
    let [t, p, h] = columns(&names, header_line, format, &src)?;
    let cols = [&t, &p, &h];
    let ([time, load, displacement], row_lines) =
        read_rows(&lines[header_at + 1..], cols, format, &src)?;
    check_series([&time, &load, &displacement], &row_lines, cols, &src)?;
    Ok(IndentationRecord {
        time,
        load,
        displacement,
        format,
        columns: [t.name.clone(), p.name.clone(), h.name.clone()],
    })
}

/// The record's name, for its errors.
struct Source<'a>(&'a str);

impl Source<'_> {
    fn err(&self, line: Option<usize>, column: Option<&str>, reason: String) -> RecordError {
        RecordError {
            source_name: self.0.to_string(),
            line,
            column: column.map(str::to_string),
            reason,
        }
    }

    /// The fields of line `n` of a `format` file.
    fn split(&self, n: usize, line: &str, format: Format) -> Result<Vec<String>, RecordError> {
        let sep = match format {
            Format::Csv => ',',
            Format::NanoindenterText => '\t',
        };
        crate::report::csv::split_fields(line, sep)
            .map_err(|e| self.err(Some(n), None, e.to_string()))
    }
}

/// The format and the index in `lines` of its header row: a nanoindenter table header anywhere,
/// else a comma-separated first line that is not a comment.
fn detect_format(lines: &[(usize, &str)], src: &Source) -> Result<(Format, usize), RecordError> {
    let first = lines
        .iter()
        .find(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    let (format, header_at) = match lines.iter().position(|(_, l)| is_table_header(l)) {
        Some(i) => (Format::NanoindenterText, i),
        None => match first {
            Some((n, l)) if l.contains(',') => (Format::Csv, n - 1),
            _ => {
                return Err(src.err(
                    first.map(|(n, _)| *n),
                    None,
                    "no header row found: expected a CSV header such as \
                     \"time_s,load_uN,depth_nm\" or a tab-separated nanoindenter table header \
                     such as \"Depth (nm)<TAB>Load (µN)<TAB>Time (s)\""
                        .into(),
                ))
            }
        },
    };
    Ok((format, header_at))
}

/// The time, load and displacement columns of the header `names` (on line `header_line`),
/// with their unit factors.
fn columns(
    names: &[String],
    header_line: usize,
    format: Format,
    src: &Source,
) -> Result<[Column; 3], RecordError> {
    let mut found: [Option<Column>; 3] = [None, None, None];
    for (index, name) in names.iter().enumerate() {
        let Some((q, unit)) = split_name(name, format) else {
            continue;
        };
        let Some(quantity) = Quantity::from_name(q) else {
            continue;
        };
        if format == Format::NanoindenterText && unit == "V" {
            continue; // a raw transducer signal
        }
        let at = Some(header_line);
        if unit.is_empty() {
            return Err(src.err(
                at,
                Some(name),
                format!(
                    "the column carries no unit (e.g. {})",
                    quantity.examples(format)
                ),
            ));
        }
        let factor = parse_quantity(&format!("1 {unit}"), quantity.dimension())
            .map_err(|e| src.err(at, Some(name), format!("unit \"{unit}\" not accepted: {e}")))?;
        let slot = &mut found[quantity as usize];
        if let Some(prev) = slot {
            return Err(src.err(
                at,
                Some(name),
                format!(
                    "a second {} column besides \"{}\"",
                    quantity.word(),
                    prev.name
                ),
            ));
        }
        *slot = Some(Column {
            index,
            name: name.to_string(),
            factor,
        });
    }
    let [t, p, h] = found;
    let missing = |q: Quantity| {
        src.err(
            Some(header_line),
            None,
            format!(
                "no {} column (expected a column like {}; the header has: {})",
                q.word(),
                q.examples(format),
                names.join(", ")
            ),
        )
    };
    let t = t.ok_or_else(|| missing(Quantity::Time))?;
    let p = p.ok_or_else(|| missing(Quantity::Load))?;
    let h = h.ok_or_else(|| missing(Quantity::Displacement))?;
    Ok([t, p, h])
}

/// The values of the columns `cols` on the data rows (comments and blank lines skipped), in
/// internal units, with the line number of each sample.
fn read_rows(
    rows: &[(usize, &str)],
    cols: [&Column; 3],
    format: Format,
    src: &Source,
) -> Result<([Vec<f64>; 3], Vec<usize>), RecordError> {
    let width = cols.iter().map(|c| c.index).max().unwrap_or(0) + 1;
    let mut values: [Vec<f64>; 3] = [Vec::new(), Vec::new(), Vec::new()];
    let mut row_lines = Vec::new();
    for &(n, line) in rows {
        if line.trim().is_empty() || (format == Format::Csv && line.trim_start().starts_with('#')) {
            continue;
        }
        let cells = src.split(n, line, format)?;
        if cells.len() < width {
            return Err(src.err(
                Some(n),
                None,
                format!("{} values, the columns used need {width}", cells.len()),
            ));
        }
        for (k, c) in cols.iter().enumerate() {
            let cell = cells[c.index].as_str();
            let v: f64 = cell.parse().map_err(|_| {
                src.err(
                    Some(n),
                    Some(&c.name),
                    format!("\"{cell}\" is not a number"),
                )
            })?;
            if !v.is_finite() {
                return Err(src.err(
                    Some(n),
                    Some(&c.name),
                    format!("\"{cell}\" is not a finite number"),
                ));
            }
            values[k].push(v * c.factor);
        }
        row_lines.push(n);
    }
    Ok((values, row_lines))
}

/// Refuse series that cannot be fitted: too few samples, time not increasing strictly (the
/// samples' lines `row_lines`), a load or displacement that never changes.
fn check_series(
    [time, load, displacement]: [&[f64]; 3],
    row_lines: &[usize],
    [t, p, h]: [&Column; 3],
    src: &Source,
) -> Result<(), RecordError> {
    if time.len() < MIN_POINTS {
        return Err(src.err(
            None,
            None,
            format!(
                "{} samples; at least {MIN_POINTS} are needed to fit K1, K2, eta",
                time.len()
            ),
        ));
    }
    if let Some(i) = time.windows(2).position(|w| w[1] <= w[0]) {
        return Err(src.err(
            Some(row_lines[i + 1]),
            Some(&t.name),
            format!(
                "time must increase strictly: {} s follows {} s",
                time[i + 1],
                time[i]
            ),
        ));
    }
    if load.iter().all(|&x| x == load[0]) {
        return Err(src.err(
            None,
            Some(&p.name),
            "the load never changes: a record needs loading to determine the stiffnesses".into(),
        ));
    }
    if displacement.iter().all(|&x| x == displacement[0]) {
        return Err(src.err(
            None,
            Some(&h.name),
            "the displacement never changes: nothing to fit".into(),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(n: usize, sep: &str) -> String {
        (0..n)
            .map(|i| {
                format!(
                    "{}{sep}{}{sep}{}\n",
                    i as f64 * 0.5,
                    i as f64,
                    2.0 * i as f64
                )
            })
            .collect()
    }

    #[test]
    fn csv_units_are_converted_once() {
        let text = format!("# a comment\ntime_ms,load_uN,depth_um\n{}", rows(12, ","));
        let r = parse_record(&text, "r.csv").unwrap();
        assert_eq!(r.format, Format::Csv);
        assert_eq!(r.time[3], 1.5e-3);
        assert_eq!(r.load[3], 3.0e3);
        assert_eq!(r.displacement[3], 6.0e3);
    }

    #[test]
    fn hysitron_export_in_latin1_with_voltage_columns() {
        let text = format!(
            "Number of Points = 12\n\nDepth (nm)\tLoad (\u{b5}N)\tTime (s)\tDepth (V)\tLoad (V)\n{}",
            (0..12)
                .map(|i| format!("{}\t{}\t{}\t0.1\t0.2\n", 2 * i, i, i as f64 * 0.5))
                .collect::<String>()
        );
        let bytes: Vec<u8> = text.chars().map(|c| c as u32 as u8).collect();
        let decoded = decode(&bytes);
        let r = parse_record(&decoded, "r.txt").unwrap();
        assert_eq!(r.format, Format::NanoindenterText);
        assert_eq!(r.load[2], 2.0e3);
        assert_eq!(r.displacement[2], 4.0);
        assert_eq!(r.columns[1], "Load (\u{b5}N)");
    }

    #[test]
    fn refusals_name_line_and_column() {
        let e = parse_record(
            &format!("time_s,load_kg,depth_nm\n{}", rows(12, ",")),
            "a.csv",
        )
        .unwrap_err();
        assert_eq!((e.line, e.column.as_deref()), (Some(1), Some("load_kg")));
        let e = parse_record(&format!("time_s,load_uN\n{}", rows(12, ",")), "a.csv").unwrap_err();
        assert!(e.reason.starts_with("no displacement column"), "{e}");
        let mut text = format!("time_s,load_uN,depth_nm\n{}", rows(12, ","));
        text = text.replace("\n2,4,8\n", "\n2,nan,8\n");
        let e = parse_record(&text, "a.csv").unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref()),
            (Some(6), Some("load_uN")),
            "{e}"
        );
        let text = format!("time_s,load_uN,depth_nm\n{}", rows(12, ",")).replace("\n2,", "\n1,");
        let e = parse_record(&text, "a.csv").unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref()),
            (Some(6), Some("time_s")),
            "{e}"
        );
        let e = parse_record(
            &format!("time_s,load_uN,depth_nm\n{}", rows(5, ",")),
            "a.csv",
        )
        .unwrap_err();
        assert!(e.reason.contains("5 samples"), "{e}");
    }
}
