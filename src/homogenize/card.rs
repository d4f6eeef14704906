//! Material cards: turf's own `material.json` and the Abaqus/CalculiX keyword card
//! `material.inp`, written and read back (the continuum stage takes either).
//!
//! `material.json` holds the constants with their units in the key names (`mu_GPa`, `tau_s`),
//! the tangent law when there is one, and the provenance (the data and the fit that produced
//! the constants).
//!
//! `material.inp` is a deck fragment (`*MATERIAL`, `*HYPERFOAM, N=…`, `*VISCOELASTIC,
//! TIME=PRONY`) to `*INCLUDE` in an Abaqus or CalculiX deck. The `*HYPERFOAM` data lines list
//! μ₁, α₁, …, μ_N, α_N, then ν₁ … ν_N (νᵢ = βᵢ/(1 + 2βᵢ)), eight values per line; the card
//! states its unit system in a comment and in a machine-read `** turf-units:` line. Two
//! CalculiX 2.20 facts shape it: `N=1` fails there with a singular matrix, so a one-term
//! material is written as `N=2` with a zero second term (the same energy); and `*VISCOELASTIC`
//! is not a CalculiX keyword — CalculiX warns and runs the elastic card, only Abaqus and turf
//! apply the relaxation. Reading drops zero-μ padding terms.

use super::hyperfoam::{beta_from_nu, Hyperfoam};
use super::prony::Prony;
use super::tangent_law::TangentLaw;
use crate::units::{parse_quantity, Dimension};

/// Format tag of `material.json`.
pub const JSON_FORMAT: &str = "turf-material-card";
/// Version of the `material.json` layout.
pub const JSON_VERSION: u32 = 1;
/// Material name used in the `.inp` card.
pub const INP_MATERIAL_NAME: &str = "TURF";

/// Where the constants came from.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Provenance {
    /// the input: "tangent law E0=…" or the curve file
    pub data: String,
    /// how the constants were obtained (fit settings and quality), free-form JSON
    pub fit: serde_json::Value,
    /// the turf version that wrote the card
    pub turf_version: String,
}

/// A material card: the hyperfoam, optionally its relaxation, and its provenance.
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialCard {
    /// the elastic constants
    pub hyperfoam: Hyperfoam,
    /// the relaxation, if any
    pub prony: Option<Prony>,
    /// the tangent law the card was fitted to (or fitted alongside), if any
    pub tangent_law: Option<TangentLaw>,
    /// where it came from
    pub provenance: Provenance,
}

/// Why a card could not be read.
#[derive(Debug, Clone, thiserror::Error)]
#[error("{source_name}: {reason}")]
pub struct CardError {
    /// the file (or "card")
    pub source_name: String,
    /// what is wrong
    pub reason: String,
}

fn err(src: &str, reason: impl Into<String>) -> CardError {
    CardError {
        source_name: src.to_string(),
        reason: reason.into(),
    }
}

#[derive(serde::Serialize, serde::Deserialize)]
struct JsonUnits {
    stress: String,
    time: String,
    system: String,
}

#[derive(serde::Serialize, serde::Deserialize)]
struct JsonHyperfoam {
    #[serde(rename = "mu_GPa")]
    mu: Vec<f64>,
    alpha: Vec<f64>,
    beta: Vec<f64>,
}

#[derive(serde::Serialize, serde::Deserialize)]
struct JsonCard {
    format: String,
    version: u32,
    units: JsonUnits,
    hyperfoam: JsonHyperfoam,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    prony: Option<Prony>,
    #[serde(skip_serializing_if = "Option::is_none", default)]
    tangent_law: Option<TangentLaw>,
    provenance: Provenance,
}

/// CalculiX reads 132 characters of a line and Abaqus puts eight values on a `*HYPERFOAM`
/// line: ten significant digits (relative rounding 5e-10) keep eight values within the limit.
fn num(x: f64) -> String {
    format!("{x:.9e}")
}

/// Longest comment text per line, well inside CalculiX's 132 characters.
const COMMENT_WIDTH: usize = 100;

/// `** ` comment lines holding `text`, wrapped at [`COMMENT_WIDTH`] characters.
fn comment(label: &str, text: &str) -> String {
    let chars: Vec<char> = format!("{label}{}", text.replace('\n', " "))
        .chars()
        .collect();
    chars
        .chunks(COMMENT_WIDTH)
        .map(|c| format!("** {}\n", c.iter().collect::<String>()))
        .collect()
}

impl MaterialCard {
    /// The `material.json` value.
    pub fn to_json(&self) -> serde_json::Value {
        let card = JsonCard {
            format: JSON_FORMAT.into(),
            version: JSON_VERSION,
            units: JsonUnits {
                stress: "GPa".into(),
                time: "s".into(),
                system: "nm, nN, s".into(),
            },
            hyperfoam: JsonHyperfoam {
                mu: self.hyperfoam.mu(),
                alpha: self.hyperfoam.alpha(),
                beta: self.hyperfoam.beta(),
            },
            prony: self.prony.clone(),
            tangent_law: self.tangent_law,
            provenance: self.provenance.clone(),
        };
        serde_json::to_value(card).expect("a card always serialises")
    }

    /// Read `material.json` text.
    pub fn from_json(text: &str, src: &str) -> Result<Self, CardError> {
        let c: JsonCard = serde_json::from_str(text)
            .map_err(|e| err(src, format!("not a turf material card: {e}")))?;
        if c.format != JSON_FORMAT || c.version != JSON_VERSION {
            return Err(err(
                src,
                format!(
                    "format {} v{}; expected {JSON_FORMAT} v{JSON_VERSION}",
                    c.format, c.version
                ),
            ));
        }
        if c.units.stress != "GPa" || c.units.time != "s" {
            return Err(err(
                src,
                format!(
                    "units stress={} time={}; turf cards are in GPa and s",
                    c.units.stress, c.units.time
                ),
            ));
        }
        let hyperfoam = Hyperfoam::new(&c.hyperfoam.mu, &c.hyperfoam.alpha, &c.hyperfoam.beta)
            .map_err(|e| err(src, e.to_string()))?;
        let prony = c
            .prony
            .map(|p| Prony::new(p.g, p.k, p.tau))
            .transpose()
            .map_err(|e| err(src, e.to_string()))?;
        let tangent_law = c
            .tangent_law
            .map(|t| TangentLaw::new(t.e0, t.e_inf, t.eps0))
            .transpose()
            .map_err(|e| err(src, e.to_string()))?;
        Ok(MaterialCard {
            hyperfoam,
            prony,
            tangent_law,
            provenance: c.provenance,
        })
    }

    /// The `material.inp` text.
    pub fn to_inp(&self) -> String {
        let mut s = String::new();
        let h = &self.hyperfoam;
        s.push_str("** turf material card: hyperfoam (Hill/Storakers, the Abaqus *HYPERFOAM form)");
        s.push_str(if self.prony.is_some() {
            " with Prony relaxation\n"
        } else {
            "\n"
        });
        s.push_str(
            "** Unit system: length nm, force nN, time s => stress (mu_i) in GPa. Build the rest\n",
        );
        s.push_str(
            "** of the deck in the same units (or scale mu_i: 1 GPa = 1000 MPa = 1e9 Pa).\n",
        );
        s.push_str("** turf-units: stress=GPa time=s\n");
        s.push_str(&comment("data: ", &self.provenance.data));
        s.push_str(&comment("fit: ", &self.provenance.fit.to_string()));
        s.push_str(&format!(
            "** written by turf {}\n",
            self.provenance.turf_version
        ));
        let mut terms = h.terms.clone();
        if terms.len() == 1 {
            s.push_str("** CalculiX 2.20 fails on *HYPERFOAM, N=1 (singular matrix): this one-term material is\n");
            s.push_str(
                "** written as N=2 with a zero second term (mu2 = 0), which is the same energy.\n",
            );
            let mut pad = terms[0];
            pad.mu = 0.0;
            terms.push(pad);
        }
        if self.prony.is_some() {
            s.push_str("** CalculiX ignores *VISCOELASTIC (not a CalculiX keyword: it warns and runs the\n");
            s.push_str("** elastic card). Abaqus and turf apply the relaxation below.\n");
        }
        s.push_str(&format!(
            "*MATERIAL, NAME={INP_MATERIAL_NAME}\n*HYPERFOAM, N={}\n",
            terms.len()
        ));
        let mut values: Vec<String> = Vec::new();
        for t in &terms {
            values.push(num(t.mu));
            values.push(num(t.alpha));
        }
        values.extend(terms.iter().map(|t| num(t.nu())));
        for chunk in values.chunks(8) {
            s.push_str(&chunk.join(", "));
            s.push('\n');
        }
        if let Some(p) = &self.prony {
            s.push_str("*VISCOELASTIC, TIME=PRONY\n");
            for i in 0..p.g.len() {
                s.push_str(&format!(
                    "{}, {}, {}\n",
                    num(p.g[i]),
                    num(p.k[i]),
                    num(p.tau[i])
                ));
            }
        }
        s
    }

    /// Read a `material.inp` card: the first `*HYPERFOAM` (N ≤ 3) and an optional
    /// `*VISCOELASTIC, TIME=PRONY`, in the units of its `** turf-units:` line (required: a card
    /// without a stated unit system cannot be read safely).
    pub fn from_inp(text: &str, src: &str) -> Result<Self, CardError> {
        let mut units = InpUnits::default();
        // (keyword line, data lines)
        let mut blocks: Vec<(String, Vec<String>)> = Vec::new();
        for raw in text.lines() {
            let line = raw.trim();
            if let Some(c) = line.strip_prefix("**") {
                if let Some(u) = c.trim().strip_prefix("turf-units:") {
                    units.read(u, src)?;
                }
                continue;
            }
            if line.is_empty() {
                continue;
            }
            if line.starts_with('*') {
                blocks.push((line.to_ascii_uppercase().replace(' ', ""), Vec::new()));
            } else if let Some(b) = blocks.last_mut() {
                b.1.push(line.to_string());
            }
        }
        let stress_factor = units.stress.ok_or_else(|| {
            err(
                src,
                "no \"** turf-units: stress=GPa time=s\" line: the card's unit system is unknown",
            )
        })?;
        let time_factor = units.time.unwrap_or(1.0);
        Ok(MaterialCard {
            hyperfoam: inp_hyperfoam(&blocks, stress_factor, src)?,
            prony: inp_prony(&blocks, time_factor, src)?,
            tangent_law: None,
            provenance: Provenance {
                data: format!("read from {src}"),
                fit: serde_json::json!({}),
                turf_version: env!("CARGO_PKG_VERSION").into(),
            },
        })
    }

    /// Read a card from text, by the file's extension (`.json` or `.inp`).
    pub fn parse(text: &str, src: &str) -> Result<Self, CardError> {
        if src.to_ascii_lowercase().ends_with(".inp") {
            Self::from_inp(text, src)
        } else if src.to_ascii_lowercase().ends_with(".json") {
            Self::from_json(text, src)
        } else {
            Err(err(src, "a material card must be a .json or .inp file"))
        }
    }
}

/// The `** turf-units:` comment of an `.inp` card: the factors from its stress and time units
/// to GPa and s.
#[derive(Default)]
struct InpUnits {
    stress: Option<f64>,
    time: Option<f64>,
}

impl InpUnits {
    /// Read the `key=unit` pairs `u` of a `turf-units:` line.
    fn read(&mut self, u: &str, src: &str) -> Result<(), CardError> {
        for kv in u.split_whitespace() {
            let (k, v) = kv
                .split_once('=')
                .ok_or_else(|| err(src, format!("turf-units: \"{kv}\" is not key=unit")))?;
            let dim = match k {
                "stress" => Dimension::Pressure,
                "time" => Dimension::Time,
                _ => {
                    return Err(err(
                        src,
                        format!("turf-units: unknown key \"{k}\" (stress, time)"),
                    ))
                }
            };
            // the internal units themselves convert exactly (no rounding of 1e9/1e9)
            let f = if v == "GPa" || v == "s" {
                1.0
            } else {
                parse_quantity(&format!("1 {v}"), dim)
                    .map_err(|e| err(src, format!("turf-units: {e}")))?
            };
            if k == "stress" {
                self.stress = Some(f);
            } else {
                self.time = Some(f);
            }
        }
        Ok(())
    }
}

/// The comma-separated finite numbers on `lines` of an `.inp` card.
fn inp_numbers(lines: &[String], src: &str) -> Result<Vec<f64>, CardError> {
    lines
        .iter()
        .flat_map(|l| l.split(',').map(str::trim).filter(|s| !s.is_empty()))
        .map(|s| {
            s.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| err(src, format!("\"{s}\" is not a finite number")))
        })
        .collect()
}

/// The `*HYPERFOAM` block (N ≤ 3; padding terms with μ = 0 dropped), μ in GPa.
fn inp_hyperfoam(
    blocks: &[(String, Vec<String>)],
    stress_factor: f64,
    src: &str,
) -> Result<Hyperfoam, CardError> {
    let (key, data) = blocks
        .iter()
        .find(|(k, _)| k.starts_with("*HYPERFOAM"))
        .ok_or_else(|| err(src, "no *HYPERFOAM keyword"))?;
    let n = match key.split(',').find_map(|p| p.strip_prefix("N=")) {
        None => 1,
        Some(v) => v
            .parse::<usize>()
            .map_err(|_| err(src, format!("{key}: bad N")))?,
    };
    if !(1..=3).contains(&n) {
        return Err(err(src, format!("{key}: N = {n}; 1 to 3 supported")));
    }
    let v = inp_numbers(data, src)?;
    // 3N constants, optionally one temperature
    if v.len() < 3 * n || v.len() > 3 * n + 1 {
        return Err(err(
            src,
            format!("*HYPERFOAM, N={n} needs {} values (mu, alpha pairs then nu), found {} (temperature-dependent cards are not supported)", 3 * n, v.len()),
        ));
    }
    let (mut mu, mut alpha, mut beta) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        if v[2 * i] == 0.0 {
            continue; // padding term
        }
        mu.push(v[2 * i] * stress_factor);
        alpha.push(v[2 * i + 1]);
        let nu = v[2 * n + i];
        if !(nu > -1.0 && nu < 0.5) {
            return Err(err(src, format!("nu{} = {nu} outside (-1, 0.5)", i + 1)));
        }
        beta.push(beta_from_nu(nu));
    }
    Hyperfoam::new(&mu, &alpha, &beta).map_err(|e| err(src, e.to_string()))
}

/// The `*VISCOELASTIC, TIME=PRONY` block, if any, τ in s.
fn inp_prony(
    blocks: &[(String, Vec<String>)],
    time_factor: f64,
    src: &str,
) -> Result<Option<Prony>, CardError> {
    let Some((k, lines)) = blocks.iter().find(|(k, _)| k.starts_with("*VISCOELASTIC")) else {
        return Ok(None);
    };
    if !k.contains("TIME=PRONY") {
        return Err(err(src, format!("{k}: only TIME=PRONY is supported")));
    }
    let (mut g, mut kk, mut tau) = (Vec::new(), Vec::new(), Vec::new());
    for l in lines {
        let row = inp_numbers(std::slice::from_ref(l), src)?;
        if row.len() != 3 {
            return Err(err(
                src,
                format!("*VISCOELASTIC line \"{l}\": expected g, k, tau"),
            ));
        }
        g.push(row[0]);
        kk.push(row[1]);
        tau.push(row[2] * time_factor);
    }
    Prony::new(g, kk, tau)
        .map(Some)
        .map_err(|e| err(src, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn card(n: usize, with_prony: bool) -> MaterialCard {
        let (mu, al, be) = ([0.3, 0.05, 0.01], [12.0, 2.0, 0.7], [0.25, 0.25, 0.25]);
        MaterialCard {
            hyperfoam: Hyperfoam::new(&mu[..n], &al[..n], &be[..n]).unwrap(),
            prony: with_prony.then(|| Prony::from_relaxation(0.4, 3.0).unwrap()),
            tangent_law: Some(TangentLaw::seed(0.05)),
            provenance: Provenance {
                data: "test".into(),
                fit: serde_json::json!({"terms": n}),
                turf_version: "0".into(),
            },
        }
    }

    /// the .inp carries ten significant digits (and ν = β/(1+2β) and back a few ulps more)
    const ROUND_TRIP_TOL: f64 = 1e-9;

    fn same(a: &MaterialCard, b: &MaterialCard) {
        assert_eq!(a.hyperfoam.terms.len(), b.hyperfoam.terms.len());
        let close = |x: f64, y: f64| (x - y).abs() <= ROUND_TRIP_TOL * x.abs().max(y.abs());
        for (x, y) in a.hyperfoam.terms.iter().zip(&b.hyperfoam.terms) {
            assert!(close(x.mu, y.mu) && close(x.alpha, y.alpha));
            assert!((x.beta - y.beta).abs() < ROUND_TRIP_TOL);
        }
        assert_eq!(a.prony.is_some(), b.prony.is_some());
        if let (Some(p), Some(q)) = (&a.prony, &b.prony) {
            let all = |p: &Prony| {
                p.g.iter()
                    .chain(&p.k)
                    .chain(&p.tau)
                    .copied()
                    .collect::<Vec<_>>()
            };
            assert!(all(p).iter().zip(all(q)).all(|(x, y)| close(*x, y)));
        }
    }

    #[test]
    fn json_and_inp_round_trip_for_one_to_three_terms() {
        for n in 1..=3 {
            for pr in [false, true] {
                let c = card(n, pr);
                let j = MaterialCard::from_json(&c.to_json().to_string(), "m.json").unwrap();
                same(&c, &j);
                assert_eq!(j.tangent_law, c.tangent_law);
                let inp = c.to_inp();
                let i = MaterialCard::parse(&inp, "m.inp").unwrap();
                same(&c, &i);
                if n == 1 {
                    assert!(inp.contains("*HYPERFOAM, N=2"), "{inp}");
                }
                assert_eq!(inp.contains("*VISCOELASTIC, TIME=PRONY"), pr);
                assert!(inp.contains("ignores *VISCOELASTIC") == pr);
                assert!(inp.lines().all(|l| l.len() <= 132), "{inp}");
            }
        }
    }

    #[test]
    fn units_are_honoured_and_required() {
        let c = card(1, true);
        let mpa = c.to_inp().replace("stress=GPa", "stress=MPa");
        let r = MaterialCard::from_inp(&mpa, "m.inp").unwrap();
        assert!((r.hyperfoam.terms[0].mu - 0.3e-3).abs() < 1e-18);
        let none = c.to_inp().replace("** turf-units: stress=GPa time=s\n", "");
        assert!(MaterialCard::from_inp(&none, "m.inp")
            .unwrap_err()
            .to_string()
            .contains("unit system"));
    }

    #[test]
    fn malformed_cards_are_refused() {
        let c = card(2, false).to_inp();
        assert!(
            MaterialCard::from_inp(&c.replace("*HYPERFOAM", "*HYPERELASTIC"), "m.inp").is_err()
        );
        let short = c
            .replace(", 0.", ", ")
            .lines()
            .filter(|l| !l.contains("e-1,"))
            .collect::<Vec<_>>()
            .join("\n");
        assert!(MaterialCard::from_inp(&short, "m.inp").is_err());
        assert!(MaterialCard::from_json("{}", "m.json").is_err());
        assert!(MaterialCard::parse("", "m.txt").is_err());
    }
}
