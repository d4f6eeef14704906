//! Internal units and the parser for quantity strings such as `"700 MPa"` or `"1.8 µm"`.
//!
//! Inside turf every number is in the system **nm, nN, s** (and K for temperature). Derived
//! units follow: stress in GPa (nN/nm²), energy in aJ (nN·nm), surface energy in J/m² (nN/nm),
//! line energy in nN (= nJ/m), stiffness in nN/nm (= N/m), bending stiffness in nN·nm²,
//! velocity in nm/s. The mass unit that makes F = m·a consistent is nN·s²/nm = 1 kg.
//!
//! A quantity string is a number followed (with or without a space) by a unit expression built
//! from prefixed SI atoms, `*`, `·` or a space for products, `/` for quotients and `^n` (or ²,
//! ³) for powers: `"0.46 J/m^2"`, `"1 uN/nm"`, `"2.21e-20 N*m^2"`. `u`, `µ` (micro sign) and `μ`
//! (Greek mu) all mean micro. Conversion happens once, at scene load (see `scene`).

use std::fmt;

/// Boltzmann constant in internal units, aJ/K (1.380649e-23 J/K).
pub const BOLTZMANN_AJ_PER_K: f64 = 1.380_649e-5;

/// Physical dimension as exponents of (length, mass, time, temperature) in SI base units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dim {
    /// exponent of length
    pub l: i8,
    /// exponent of mass
    pub m: i8,
    /// exponent of time
    pub t: i8,
    /// exponent of temperature
    pub k: i8,
}

impl Dim {
    const fn new(l: i8, m: i8, t: i8, k: i8) -> Self {
        Dim { l, m, t, k }
    }
    fn mul(self, o: Dim, sign: i8) -> Dim {
        Dim::new(
            self.l + sign * o.l,
            self.m + sign * o.m,
            self.t + sign * o.t,
            self.k + sign * o.k,
        )
    }
    fn pow(self, p: i8) -> Dim {
        Dim::new(self.l * p, self.m * p, self.t * p, self.k * p)
    }
}

/// The kinds of quantity a scene can hold, each with its internal unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// length, nm
    Length,
    /// force, nN
    Force,
    /// pressure or stress, GPa
    Pressure,
    /// surface energy or work of adhesion, J/m² (= nN/nm)
    SurfaceEnergy,
    /// energy per unit length of tube, nN (= nJ/m)
    LineEnergy,
    /// energy, aJ (= nN·nm)
    Energy,
    /// time, s
    Time,
    /// velocity (a rate of displacement), nm/s
    Rate,
    /// strain rate, 1/s
    StrainRate,
    /// spring stiffness, nN/nm (= N/m)
    Stiffness,
    /// dashpot coefficient, nN·s/nm
    Damping,
    /// bending stiffness Y·I, nN·nm²
    BendingStiffness,
    /// areal number density, 1/nm²
    ArealDensity,
    /// temperature, K
    Temperature,
    /// a pure number
    Dimensionless,
}

impl Dimension {
    /// SI dimension exponents of this kind of quantity.
    pub fn dim(self) -> Dim {
        use Dimension::*;
        match self {
            Length => Dim::new(1, 0, 0, 0),
            Force => Dim::new(1, 1, -2, 0),
            Pressure => Dim::new(-1, 1, -2, 0),
            SurfaceEnergy | Stiffness => Dim::new(0, 1, -2, 0),
            LineEnergy => Dim::new(1, 1, -2, 0),
            Energy => Dim::new(2, 1, -2, 0),
            Time => Dim::new(0, 0, 1, 0),
            Rate => Dim::new(1, 0, -1, 0),
            StrainRate => Dim::new(0, 0, -1, 0),
            Damping => Dim::new(0, 1, -1, 0),
            BendingStiffness => Dim::new(3, 1, -2, 0),
            ArealDensity => Dim::new(-2, 0, 0, 0),
            Temperature => Dim::new(0, 0, 0, 1),
            Dimensionless => Dim::new(0, 0, 0, 0),
        }
    }

    /// Human name with an example, for error messages.
    pub fn describe(self) -> &'static str {
        use Dimension::*;
        match self {
            Length => "a length (e.g. \"1.8 um\", \"20 nm\")",
            Force => "a force (e.g. \"10 uN\", \"5 nN\")",
            Pressure => "a pressure or modulus (e.g. \"700 MPa\", \"0.4 TPa\")",
            SurfaceEnergy => "a surface energy (e.g. \"0.46 J/m^2\")",
            LineEnergy => "a line energy (e.g. \"1 nJ/m\", \"1 nN\")",
            Energy => "an energy (e.g. \"1 aJ\", \"1 eV\")",
            Time => "a time (e.g. \"3 s\", \"10 ms\")",
            Rate => "a rate (e.g. \"10 nm/s\")",
            StrainRate => "a strain rate (e.g. \"0.01 1/s\")",
            Stiffness => "a stiffness (e.g. \"1 uN/nm\", \"100 N/m\")",
            Damping => "a dashpot coefficient (e.g. \"1 uN*s/nm\")",
            BendingStiffness => "a bending stiffness (e.g. \"2.21e-20 N*m^2\")",
            ArealDensity => "an areal density (e.g. \"1e10 1/cm^2\", \"0.01 1/um^2\")",
            Temperature => "a temperature (e.g. \"300 K\")",
            Dimensionless => "a pure number",
        }
    }

    /// Internal unit symbol, used in output column names and messages.
    pub fn internal_unit(self) -> &'static str {
        use Dimension::*;
        match self {
            Length => "nm",
            Force => "nN",
            Pressure => "GPa",
            SurfaceEnergy => "J/m^2",
            LineEnergy => "nN",
            Energy => "aJ",
            Time => "s",
            Rate => "nm/s",
            StrainRate => "1/s",
            Stiffness => "nN/nm",
            Damping => "nN*s/nm",
            BendingStiffness => "nN*nm^2",
            ArealDensity => "1/nm^2",
            Temperature => "K",
            Dimensionless => "",
        }
    }

    fn from_dim(d: Dim) -> Option<Dimension> {
        use Dimension::*;
        [
            Length,
            Force,
            Pressure,
            SurfaceEnergy,
            Energy,
            Time,
            Rate,
            StrainRate,
            Damping,
            BendingStiffness,
            ArealDensity,
            Temperature,
            Dimensionless,
        ]
        .into_iter()
        .find(|x| x.dim() == d)
    }
}

impl fmt::Display for Dimension {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.describe())
    }
}

/// Why a quantity string could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UnitError {
    /// no number at the start of the string
    #[error("\"{0}\" does not start with a number")]
    NoNumber(String),
    /// a unit atom that turf does not know
    #[error("unknown unit \"{atom}\" in \"{text}\" (known: m, g, s, N, Pa, J, eV, K, min, h, Å with SI prefixes T G M k c m u µ n p f a)")]
    UnknownUnit {
        /// the atom
        atom: String,
        /// the whole string
        text: String,
    },
    /// the unit is valid but of another dimension
    #[error("\"{text}\" is {found}, expected {expected}")]
    WrongDimension {
        /// the whole string
        text: String,
        /// what the key needs
        expected: Dimension,
        /// what the string is
        found: String,
    },
    /// the number is NaN or infinite
    #[error("\"{0}\" is not a finite number")]
    NotFinite(String),
}

/// Parse a quantity string and convert it to internal units, checking its dimension.
///
/// A bare number (no unit) is taken to be in internal units already.
pub fn parse_quantity(text: &str, expected: Dimension) -> Result<f64, UnitError> {
    let s = text.trim();
    let split = number_prefix_len(s);
    if split == 0 {
        return Err(UnitError::NoNumber(text.to_string()));
    }
    let value: f64 = s[..split]
        .parse()
        .map_err(|_| UnitError::NoNumber(text.to_string()))?;
    if !value.is_finite() {
        return Err(UnitError::NotFinite(text.to_string()));
    }
    let unit = s[split..].trim();
    if unit.is_empty() {
        return Ok(value);
    }
    let (factor_si, dim) = parse_unit_expr(unit, text)?;
    if dim != expected.dim() {
        let found = Dimension::from_dim(dim)
            .map(|d| d.describe().to_string())
            .unwrap_or_else(|| {
                format!(
                    "of dimension L^{} M^{} T^{} K^{}",
                    dim.l, dim.m, dim.t, dim.k
                )
            });
        return Err(UnitError::WrongDimension {
            text: text.to_string(),
            expected,
            found,
        });
    }
    // Internal units: L = 1e-9 m, M = 1 kg, T = 1 s, K = 1 K. Powers of ten are kept as
    // integers until here, so "20 uN" is exactly 20000 nN.
    let out = value * factor_si.0 * 10f64.powi(factor_si.1 + 9 * dim.l as i32);
    if !out.is_finite() {
        return Err(UnitError::NotFinite(text.to_string()));
    }
    Ok(out)
}

/// Length of the number (sign, digits, point, exponent) at the start of `s`.
fn number_prefix_len(s: &str) -> usize {
    let b = s.as_bytes();
    let mut i = 0;
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        i += 1;
    }
    let start_digits = i;
    while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
        i += 1;
    }
    if i == start_digits {
        return 0;
    }
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        let mut j = i + 1;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            j += 1;
        }
        let exp_start = j;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        if j > exp_start {
            i = j;
        }
    }
    i
}

/// An SI factor as mantissa × 10^exponent (prefixes stay exact integers of the exponent).
type Factor = (f64, i32);

/// Parse a unit expression into (SI factor, dimension). Factors are separated by `*`, `·` or
/// spaces; every factor after a `/` divides (so `uN*s/nm` and `N/m/s` read as expected).
fn parse_unit_expr(unit: &str, text: &str) -> Result<(Factor, Dim), UnitError> {
    let mut factor: Factor = (1.0, 0);
    let mut dim = Dim::new(0, 0, 0, 0);
    let mut sign: i8 = 1;
    for (i, part) in unit.split('/').enumerate() {
        if i > 0 {
            sign = -1;
        }
        let factors = part.split(['*', '·', ' ']).filter(|t| !t.is_empty());
        let mut any = false;
        for token in factors {
            let (f, d) = parse_factor(token, text)?;
            factor = (
                factor.0 * f.0.powi(sign as i32),
                factor.1 + sign as i32 * f.1,
            );
            dim = dim.mul(d, sign);
            any = true;
        }
        if !any {
            return Err(UnitError::UnknownUnit {
                atom: part.to_string(),
                text: text.to_string(),
            });
        }
    }
    Ok((factor, dim))
}

/// One factor such as `nm^2`, `m²`, `1`, `uN`.
fn parse_factor(token: &str, text: &str) -> Result<(Factor, Dim), UnitError> {
    let (atom, power) = split_power(token);
    let unknown = || UnitError::UnknownUnit {
        atom: token.to_string(),
        text: text.to_string(),
    };
    let power = power.ok_or_else(unknown)?;
    if atom == "1" {
        return Ok(((1.0, 0), Dim::new(0, 0, 0, 0)));
    }
    let (f, d) = atom_si(atom).ok_or_else(unknown)?;
    Ok(((f.0.powi(power as i32), f.1 * power as i32), d.pow(power)))
}

fn split_power(token: &str) -> (&str, Option<i8>) {
    for (sup, p) in [('²', 2), ('³', 3), ('⁴', 4)] {
        if let Some(a) = token.strip_suffix(sup) {
            return (a, Some(p));
        }
    }
    match token.split_once('^') {
        Some((a, p)) => (a, p.trim().parse::<i8>().ok()),
        None => (token, Some(1)),
    }
}

/// SI factor and dimension of a (possibly prefixed) unit atom.
fn atom_si(atom: &str) -> Option<(Factor, Dim)> {
    if let Some(base) = base_unit(atom) {
        return Some(base);
    }
    let mut chars = atom.chars();
    let p = chars.next()?;
    let rest = chars.as_str();
    let scale = match p {
        'T' => 12,
        'G' => 9,
        'M' => 6,
        'k' => 3,
        'c' => -2,
        'm' => -3,
        'u' | 'µ' | 'μ' => -6,
        'n' => -9,
        'p' => -12,
        'f' => -15,
        'a' => -18,
        _ => return None,
    };
    if !prefixable(rest) {
        return None;
    }
    let (f, d) = base_unit(rest)?;
    Some(((f.0, f.1 + scale), d))
}

fn prefixable(base: &str) -> bool {
    matches!(base, "m" | "g" | "s" | "N" | "Pa" | "J" | "eV")
}

fn base_unit(atom: &str) -> Option<(Factor, Dim)> {
    let length = Dim::new(1, 0, 0, 0);
    Some(match atom {
        "m" => ((1.0, 0), length),
        "Å" | "angstrom" => ((1.0, -10), length),
        "g" => ((1.0, -3), Dim::new(0, 1, 0, 0)),
        "s" => ((1.0, 0), Dim::new(0, 0, 1, 0)),
        "min" => ((60.0, 0), Dim::new(0, 0, 1, 0)),
        "h" => ((3600.0, 0), Dim::new(0, 0, 1, 0)),
        "N" => ((1.0, 0), Dimension::Force.dim()),
        "Pa" => ((1.0, 0), Dimension::Pressure.dim()),
        "J" => ((1.0, 0), Dimension::Energy.dim()),
        "eV" => ((1.602_176_634, -19), Dimension::Energy.dim()),
        "K" => ((1.0, 0), Dimension::Temperature.dim()),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use Dimension::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs().max(1e-300)
    }

    #[test]
    fn the_issue_examples_convert_to_internal_units() {
        let cases = [
            ("7 um", Length, 7000.0),
            ("7um", Length, 7000.0),
            ("1.8 µm", Length, 1800.0),
            ("1.8 μm", Length, 1800.0),
            ("0.4 TPa", Pressure, 400.0),
            ("700 MPa", Pressure, 0.7),
            ("0.46 J/m^2", SurfaceEnergy, 0.46),
            ("0.46 J/m²", SurfaceEnergy, 0.46),
            ("10 nm/s", Rate, 10.0),
            ("1 uN/nm", Stiffness, 1000.0),
            ("20 uN", Force, 20_000.0),
            ("210 mN/nm", Stiffness, 2.1e8),
            ("100 N/m", Stiffness, 100.0),
            ("300 K", Temperature, 300.0),
            ("1 nJ/m", LineEnergy, 1.0),
            ("1 nN", LineEnergy, 1.0),
            ("2.21e-20 N*m^2", BendingStiffness, 2.21e7),
            ("3 s", Time, 3.0),
            ("10 ms", Time, 0.01),
            ("2 min", Time, 120.0),
            ("1 aJ", Energy, 1.0),
            ("3.4 Å", Length, 0.34),
            ("1e10 1/cm^2", ArealDensity, 1e-4),
            ("0.34", Length, 0.34),
            ("1 uN*s/nm", Damping, 1000.0),
            ("1 kg*m/s^2", Force, 1e9),
            ("4.1e-21 J", Energy, 4.1e-3),
        ];
        for (text, dim, want) in cases {
            let got = parse_quantity(text, dim).unwrap_or_else(|e| panic!("{text}: {e}"));
            assert!(close(got, want), "{text}: got {got}, want {want}");
        }
    }

    #[test]
    fn kt_at_room_temperature_is_about_4_zj() {
        assert!(close(BOLTZMANN_AJ_PER_K * 300.0, 4.141_947e-3));
    }

    #[test]
    fn wrong_dimension_names_what_was_expected_and_found() {
        let e = parse_quantity("700 MPa", Length).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("expected a length"), "{msg}");
        assert!(msg.contains("a pressure"), "{msg}");
    }

    #[test]
    fn garbage_is_refused() {
        assert!(matches!(
            parse_quantity("MPa", Pressure),
            Err(UnitError::NoNumber(_))
        ));
        assert!(matches!(
            parse_quantity("3 furlongs", Length),
            Err(UnitError::UnknownUnit { .. })
        ));
        assert!(matches!(
            parse_quantity("3 mmin", Time),
            Err(UnitError::UnknownUnit { .. })
        ));
        assert!(parse_quantity("1e400 nm", Length).is_err());
        assert!(parse_quantity("", Length).is_err());
        assert!(parse_quantity("3 m^x", Length).is_err());
    }
}
