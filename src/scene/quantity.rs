//! Physical quantities of a scene, typed by dimension.
//!
//! A scene key that holds a physical quantity accepts either a bare number, taken to be in
//! turf's internal units (nm, nN, s; so GPa, J/m², nN/nm, ...), or a string with units such as
//! `"700 MPa"` or `"1.8 um"`, converted once here by [`crate::units::parse_quantity`]. A string
//! of the wrong dimension is refused with a message naming the dimension the key expects. Every
//! newtype serialises as its value in internal units, so a resolved scene echoes plain numbers.

use crate::units::{parse_quantity, Dimension, UnitError};
use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::fmt;

/// A physical quantity stored in internal units.
pub trait Quantity: Copy {
    /// What kind of quantity this is (and so its internal unit).
    const DIMENSION: Dimension;
    /// The value in internal units.
    fn value(self) -> f64;
}

/// Read a number (internal units) or a quantity string of dimension `dim`.
fn deserialize_quantity<'de, D: Deserializer<'de>>(d: D, dim: Dimension) -> Result<f64, D::Error> {
    d.deserialize_any(QuantityVisitor { dim })
}

struct QuantityVisitor {
    dim: Dimension,
}

impl QuantityVisitor {
    fn finite<E: de::Error>(&self, v: f64) -> Result<f64, E> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(E::custom(format!(
                "{v} is not a finite number; expected {}",
                self.dim
            )))
        }
    }
}

impl<'de> Visitor<'de> for QuantityVisitor {
    type Value = f64;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(
            f,
            "{}: a number in {} or a string with units",
            self.dim,
            unit_name(self.dim)
        )
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
        self.finite(v)
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<f64, E> {
        parse_text(v, self.dim).map_err(E::custom)
    }
}

/// Why a quantity string could not be read; the message always names the dimension expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QuantityError {
    /// a quantity of another dimension (the unit error names the one expected)
    #[error(transparent)]
    WrongDimension(UnitError),
    /// not a quantity at all
    #[error("{error}; expected {expected}")]
    Unreadable {
        /// why it could not be read
        error: UnitError,
        /// the dimension the key expects
        expected: Dimension,
    },
    /// not a rate of the dimension per second
    #[error("\"{text}\" is not {dim} per second (e.g. \"10 uN/s\")")]
    NotPerSecond {
        /// the string
        text: String,
        /// the dimension whose rate was expected
        dim: Dimension,
    },
}

/// Parse a quantity string, with a message that always names the dimension expected.
pub fn parse_text(text: &str, dim: Dimension) -> Result<f64, QuantityError> {
    parse_quantity(text, dim).map_err(|e| match e {
        UnitError::WrongDimension { .. } => QuantityError::WrongDimension(e),
        error => QuantityError::Unreadable {
            error,
            expected: dim,
        },
    })
}

/// The internal unit of a dimension, or "a pure number" for dimensionless quantities.
pub fn unit_name(dim: Dimension) -> &'static str {
    match dim.internal_unit() {
        "" => "(no unit)",
        u => u,
    }
}

macro_rules! quantity {
    ($(#[$doc:meta])* $name:ident, $dim:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, Default, PartialEq, PartialOrd)]
        pub struct $name(pub f64);

        impl Quantity for $name {
            const DIMENSION: Dimension = $dim;
            fn value(self) -> f64 {
                self.0
            }
        }

        impl Serialize for $name {
            fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_f64(self.0)
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                deserialize_quantity(d, $dim).map($name)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "{} {}", self.0, unit_name($dim))
            }
        }
    };
}

quantity!(
    /// A length, nm.
    Length,
    Dimension::Length
);
quantity!(
    /// A force, nN.
    Force,
    Dimension::Force
);
quantity!(
    /// A pressure, stress or modulus, GPa.
    Pressure,
    Dimension::Pressure
);
quantity!(
    /// A surface energy or work of adhesion, J/m² (= nN/nm).
    SurfaceEnergy,
    Dimension::SurfaceEnergy
);
quantity!(
    /// An energy per unit length of tube, nN (= nJ/m).
    LineEnergy,
    Dimension::LineEnergy
);
quantity!(
    /// A time, s.
    Time,
    Dimension::Time
);
quantity!(
    /// A rate of displacement, nm/s.
    Rate,
    Dimension::Rate
);
quantity!(
    /// A spring stiffness, nN/nm (= N/m).
    Stiffness,
    Dimension::Stiffness
);
quantity!(
    /// A temperature, K.
    Temperature,
    Dimension::Temperature
);
quantity!(
    /// An areal number density, 1/nm².
    ArealDensity,
    Dimension::ArealDensity
);

/// A quantity whose dimension depends on another key (a schedule target is a depth under
/// displacement control and a load under load control): kept as written until validation
/// resolves it, after which it is always a number in internal units.
#[derive(Debug, Clone, PartialEq)]
pub enum Amount {
    /// a number (internal units)
    Number(f64),
    /// a string with units, not yet converted
    Text(String),
}

impl Amount {
    /// Convert to internal units of `dim`, replacing the text by the number.
    pub fn resolve(&mut self, dim: Dimension) -> Result<f64, QuantityError> {
        let v = match self {
            Amount::Number(v) => *v,
            Amount::Text(t) => parse_text(t, dim)?,
        };
        *self = Amount::Number(v);
        Ok(v)
    }

    /// Convert a rate of `dim` per second (a load rate in nN/s when `dim` is a force).
    ///
    /// `units` has no force-per-time dimension, so `"10 uN/s"` is read as the force
    /// `"10 s uN/s"` (every factor after the `/` divides), which is the rate times one second.
    pub fn resolve_per_second(&mut self, dim: Dimension) -> Result<f64, QuantityError> {
        let v = match self {
            Amount::Number(v) => *v,
            Amount::Text(t) => {
                let s = t.trim();
                let split = s
                    .find(|c: char| c.is_alphabetic() && c != 'e' && c != 'E')
                    .unwrap_or(s.len());
                let (num, unit) = s.split_at(split);
                let as_force = format!("{num} s {unit}");
                parse_quantity(&as_force, dim).map_err(|_| QuantityError::NotPerSecond {
                    text: t.clone(),
                    dim,
                })?
            }
        };
        *self = Amount::Number(v);
        Ok(v)
    }

    /// The number, once resolved.
    pub fn number(&self) -> Option<f64> {
        match self {
            Amount::Number(v) => Some(*v),
            Amount::Text(_) => None,
        }
    }
}

impl fmt::Display for Amount {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Amount::Number(v) => write!(f, "{v}"),
            Amount::Text(t) => write!(f, "\"{t}\""),
        }
    }
}

impl Serialize for Amount {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Amount::Number(v) => s.serialize_f64(*v),
            Amount::Text(t) => s.serialize_str(t),
        }
    }
}

impl<'de> Deserialize<'de> for Amount {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Amount;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number in internal units or a string with units")
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Amount, E> {
                Ok(Amount::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Amount, E> {
                Ok(Amount::Number(v as f64))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Amount, E> {
                if v.is_finite() {
                    Ok(Amount::Number(v))
                } else {
                    Err(E::custom(format!("{v} is not a finite number")))
                }
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Amount, E> {
                Ok(Amount::Text(v.to_string()))
            }
        }
        d.deserialize_any(V)
    }
}

/// A finite plain number (no unit); NaN and infinities are refused at load.
#[derive(Debug, Clone, Copy, Default, PartialEq, PartialOrd, Serialize)]
#[serde(transparent)]
pub struct Number(pub f64);

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        deserialize_quantity(d, Dimension::Dimensionless).map(Number)
    }
}

impl fmt::Display for Number {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    struct T {
        x: Pressure,
    }

    fn read(text: &str) -> Result<f64, String> {
        toml::from_str::<T>(text)
            .map(|t| t.x.0)
            .map_err(|e| e.message().to_string())
    }

    #[test]
    fn numbers_are_internal_units_and_strings_are_converted() {
        assert_eq!(read("x = 2").unwrap(), 2.0);
        assert_eq!(read("x = 0.7").unwrap(), 0.7);
        assert!((read("x = \"700 MPa\"").unwrap() - 0.7).abs() < 1e-15);
    }

    #[test]
    fn wrong_dimension_names_the_dimension_expected() {
        let e = read("x = \"3 nm\"").unwrap_err();
        assert!(e.contains("expected a pressure"), "{e}");
        let e = read("x = \"abc\"").unwrap_err();
        assert!(e.contains("expected a pressure"), "{e}");
        let e = read("x = true").unwrap_err();
        assert!(e.contains("pressure"), "{e}");
        let e = read("x = nan").unwrap_err();
        assert!(e.contains("not a finite number"), "{e}");
    }

    #[test]
    fn a_load_rate_is_read_per_second() {
        let mut a = Amount::Text("10 uN/s".into());
        let v = a.resolve_per_second(Dimension::Force).unwrap();
        assert!((v - 1e4).abs() < 1e-9, "{v}");
        let mut a = Amount::Text("60 mN/min".into());
        let v = a.resolve_per_second(Dimension::Force).unwrap();
        assert!((v - 1e6).abs() < 1e-6, "{v}");
        let mut bad = Amount::Text("10 uN".into());
        assert!(bad.resolve_per_second(Dimension::Force).is_err());
    }
}
