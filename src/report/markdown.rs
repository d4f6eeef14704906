//! The per-run report `report.md`: a Markdown page, viewable offline beside the SVG plots it
//! embeds, built from the run's summary (the same data as `summary.json`; nothing is re-run).
//!
//! Sections: the scene (name, file, status), the plan (stages with the reason each runs, the
//! physics switched on and off), each stage run with its cost (wall time, evaluations), its
//! headline values, its files and its plots (`![](plots/x.svg)`), the stages planned but not
//! run and the error that stopped the run, the material card if a stage wrote `material.json`,
//! and the resolved parameters (derived numbers, key values, the resolved scene). A `[sweep]`
//! gets one stage section per swept value, pointing into its sub-folder.
//!
//! The summary is read as JSON so that this module does not depend on the pipeline's types
//! (dependencies flow pipeline → report); fields it does not find are left out, never invented.

use super::{write_atomic, ReportError};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The report's file name in the output folder.
pub const REPORT_FILE: &str = "report.md";

/// Render the report of `summary` (a serialised pipeline summary); `dir` is the output folder,
/// where a stage's `material.json` is read from.
pub fn render(summary: &Value, dir: &Path) -> String {
    let mut s = String::new();
    let name = summary["scene"]["scene"]["name"]
        .as_str()
        .filter(|n| !n.is_empty())
        .map_or_else(|| text(&summary["file"]), str::to_string);
    let _ = writeln!(s, "# Run report: {name}\n");
    let _ = writeln!(s, "- scene file: `{}`", text(&summary["file"]));
    let _ = writeln!(s, "- turf build: {}", text(&summary["turf_build"]));
    let complete = summary["complete"].as_bool() == Some(true);
    match summary["error"].as_str() {
        Some(e) => {
            let _ = writeln!(s, "- status: **stopped** — {e}");
        }
        None if complete => {
            let _ = writeln!(s, "- status: complete");
        }
        None => {
            let _ = writeln!(s, "- status: incomplete (the run was interrupted)");
        }
    }
    let _ = writeln!(
        s,
        "- units: every number in internal units (nm, nN, s; GPa, aJ, J/m^2)"
    );
    let stale: Vec<String> = summary["stale_files"]
        .as_array()
        .into_iter()
        .flatten()
        .map(text)
        .collect();
    if !stale.is_empty() {
        let _ = writeln!(
            s,
            "- **stale files** from an earlier run in this folder, not written by this one: {}",
            stale.join(", ")
        );
    }
    plan(&mut s, &summary["plan"]);
    match summary["sweep"].as_object() {
        Some(sw) => {
            let _ = writeln!(s, "\n## Sweep over `{}`", text(&sw["key"]));
            for p in sw["points"].as_array().into_iter().flatten() {
                let sub = text(&p["dir"]);
                let _ = writeln!(s, "\n### {} = {} (`{sub}/`)", text(&sw["key"]), p["value"]);
                stages(&mut s, &p["stages"], &sub, dir, "####");
            }
        }
        None => {
            let _ = writeln!(s, "\n## Stages");
            stages(&mut s, &summary["stages"], "", dir, "###");
        }
    }
    not_run(&mut s, summary);
    resolved(&mut s, summary);
    s
}

/// Render and write `report.md` into `dir`; returns its path.
pub fn write_run_report<T: serde::Serialize>(
    summary: &T,
    dir: &Path,
) -> Result<PathBuf, ReportError> {
    let path = dir.join(REPORT_FILE);
    let v = serde_json::to_value(summary).map_err(|e| ReportError::Invalid {
        path: path.display().to_string(),
        reason: e.to_string(),
    })?;
    write_atomic(&path, render(&v, dir).as_bytes())?;
    Ok(path)
}

/// A JSON string as text, anything else as its JSON form.
fn text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        Value::Null => String::new(),
        other => other.to_string(),
    }
}

/// Significant digits of the numbers in the report's tables (summary.json keeps them all).
const DIGITS: i32 = 7;

/// A number with [`DIGITS`] significant digits, in exponent form outside 1e-3..1e6.
fn number(v: &Value) -> String {
    match v.as_f64() {
        Some(0.0) => "0".into(),
        Some(x) if (1e-3..1e6).contains(&x.abs()) => {
            let decimals = (DIGITS - 1 - x.abs().log10().floor() as i32).max(0) as usize;
            let s = format!("{x:.decimals$}");
            match s.contains('.') {
                true => s.trim_end_matches('0').trim_end_matches('.').to_string(),
                false => s,
            }
        }
        Some(x) => format!("{:.*e}", DIGITS as usize - 1, x),
        None => text(v),
    }
}

fn plan(s: &mut String, plan: &Value) {
    let _ = writeln!(s, "\n## Plan\n\n| # | stage | why |\n|---|---|---|");
    for (i, st) in plan["stages"].as_array().into_iter().flatten().enumerate() {
        let _ = writeln!(
            s,
            "| {} | {} | {} |",
            i + 1,
            text(&st["stage"]),
            text(&st["why"])
        );
    }
    let physics = plan["physics"].as_array().into_iter().flatten();
    let mut first = true;
    for p in physics {
        if first {
            let _ = writeln!(s, "\nPhysics:\n");
            first = false;
        }
        let on = if p["on"].as_bool() == Some(true) {
            "on"
        } else {
            "off"
        };
        let _ = writeln!(
            s,
            "- [{on}] `{}` — {}",
            text(&p["name"]),
            text(&p["detail"])
        );
    }
}

fn stages(s: &mut String, records: &Value, sub: &str, dir: &Path, level: &str) {
    let prefix = |f: &str| {
        if sub.is_empty() {
            f.to_string()
        } else {
            format!("{sub}/{f}")
        }
    };
    let records = records.as_array().map(Vec::as_slice).unwrap_or_default();
    if records.is_empty() {
        let _ = writeln!(s, "\nNo stage finished.");
    }
    let mut cost = (0.0, 0u64);
    for (i, r) in records.iter().enumerate() {
        let (t, n) = (
            r["wall_time_s"].as_f64().unwrap_or(0.0),
            r["evaluations"].as_u64().unwrap_or(0),
        );
        cost = (cost.0 + t, cost.1 + n);
        let _ = writeln!(
            s,
            "\n{level} {}. {} — {t:.3} s, {n} evaluations\n",
            i + 1,
            text(&r["stage"])
        );
        for w in r["warnings"].as_array().into_iter().flatten() {
            let _ = writeln!(s, "- **warning:** {}", text(w));
        }
        if let Some(values) = r["values"].as_object().filter(|v| !v.is_empty()) {
            let _ = writeln!(s, "| value | |\n|---|---|");
            for (k, v) in values {
                let _ = writeln!(s, "| `{k}` | {} |", number(v));
            }
        }
        let files: Vec<String> = r["files"]
            .as_array()
            .into_iter()
            .flatten()
            .map(text)
            .collect();
        let (plots, others): (Vec<&String>, Vec<&String>) =
            files.iter().partition(|f| f.ends_with(".svg"));
        if !others.is_empty() {
            let links: Vec<String> = others
                .iter()
                .map(|f| format!("[{f}]({})", prefix(f)))
                .collect();
            let _ = writeln!(s, "\nFiles: {}", links.join(", "));
        }
        for p in plots {
            let _ = writeln!(s, "\n![{p}]({})", prefix(p));
        }
        if files.iter().any(|f| f == "material.json") {
            card(
                s,
                &dir.join(sub).join("material.json"),
                &prefix("material.json"),
            );
        }
    }
    if !records.is_empty() {
        let _ = writeln!(
            s,
            "\nTotal: {:.3} s, {} evaluations over {} stage{}.",
            cost.0,
            cost.1,
            records.len(),
            if records.len() == 1 { "" } else { "s" }
        );
    }
}

/// The material card a stage wrote, summarised from its file.
fn card(s: &mut String, path: &Path, link: &str) {
    let _ = writeln!(s, "\n**Material card** ([{link}]({link})):\n");
    let parsed = std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok());
    let Some(c) = parsed else {
        let _ = writeln!(s, "- (could not be read back from {})", path.display());
        return;
    };
    for key in ["hyperfoam", "prony", "tangent_law"] {
        if let Some(v) = c.get(key).filter(|v| !v.is_null()) {
            let _ = writeln!(s, "- {key}: `{v}`");
        }
    }
    let _ = writeln!(s, "- units: `{}`", c["units"]);
}

fn not_run(s: &mut String, summary: &Value) {
    let Some(error) = summary["error"].as_str() else {
        return;
    };
    let done: Vec<String> = match summary["sweep"].as_object() {
        Some(sw) => sw["points"]
            .as_array()
            .and_then(|p| p.last())
            .map(|p| p["stages"].clone())
            .unwrap_or_default(),
        None => summary["stages"].clone(),
    }
    .as_array()
    .into_iter()
    .flatten()
    .map(|r| text(&r["stage"]))
    .collect();
    let planned: Vec<String> = summary["plan"]["stages"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|p| text(&p["stage"]))
        .filter(|p| !done.contains(p))
        .collect();
    let _ = writeln!(s, "\n## The run stopped\n\n```\n{error}\n```");
    if !planned.is_empty() {
        let _ = writeln!(s, "\nPlanned but not finished: {}.", planned.join(", "));
    }
}

fn resolved(s: &mut String, summary: &Value) {
    let _ = writeln!(s, "\n## Resolved parameters");
    if let Some(d) = summary["derived"].as_object().filter(|d| !d.is_empty()) {
        let _ = writeln!(s, "\nDerived:\n\n| quantity | value |\n|---|---|");
        for (k, v) in d {
            let shown = if v.is_number() {
                number(v)
            } else {
                format!("`{v}`")
            };
            let _ = writeln!(s, "| `{k}` | {shown} |");
        }
    }
    let values = summary["plan"]["values"].as_array().into_iter().flatten();
    let mut first = true;
    for v in values {
        if first {
            let _ = writeln!(
                s,
                "\nKey values:\n\n| key | value | unit | note |\n|---|---|---|---|"
            );
            first = false;
        }
        let _ = writeln!(
            s,
            "| `{}` | {} | {} | {} |",
            text(&v["key"]),
            number(&v["value"]),
            text(&v["unit"]),
            text(&v["note"])
        );
    }
    let scene = serde_json::to_string_pretty(&summary["scene"]).unwrap_or_default();
    let _ = writeln!(
        s,
        "\nThe resolved scene (internal units):\n\n```json\n{scene}\n```"
    );
}
