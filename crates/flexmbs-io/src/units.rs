//! Physical quantities in model files: a plain number (SI) or a string `"value unit"`
//! (`"30 mm"`, `"1500 rpm"`, `"90 deg"`), converted with a small unit table per dimension.

use serde::de::{self, Deserializer, Visitor};
use serde::Deserialize;
use std::f64::consts::PI;
use std::fmt;

/// A number as written in the model file, with its unit if one was given.
#[derive(Debug, Clone, PartialEq)]
pub struct Quantity {
    /// The number as written.
    pub value: f64,
    /// The unit as written (`None`: the value is in SI).
    pub unit: Option<String>,
}

impl Quantity {
    /// A plain SI number.
    pub fn si(value: f64) -> Self {
        Self { value, unit: None }
    }

    /// The value in SI units for a quantity of dimension `dim`; `Err` carries the message
    /// (wrong or unknown unit, listing the accepted units).
    pub fn to_si(&self, dim: Dimension) -> Result<f64, String> {
        let Some(unit) = &self.unit else {
            return Ok(self.value);
        };
        let norm = normalize_unit(unit);
        if let Some((_, f)) = dim.units().iter().find(|(u, _)| normalize_unit(u) == norm) {
            return Ok(self.value * f);
        }
        let other = Dimension::ALL
            .iter()
            .find(|d| d.units().iter().any(|(u, _)| normalize_unit(u) == norm));
        let what = match other {
            Some(d) => format!("unit `{unit}` is a {} unit", d.name()),
            None => format!("unknown unit `{unit}`"),
        };
        Err(format!(
            "{what}; expected a {} (accepted units: {})",
            dim.name(),
            dim.unit_list()
        ))
    }
}

/// `N*m`, `N m`, `N·m` and `Nm` compare equal; `^` is optional before exponents.
fn normalize_unit(u: &str) -> String {
    u.chars()
        .filter(|c| !matches!(c, ' ' | '*' | '·' | '^'))
        .collect()
}

/// Physical dimensions of model-file values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// Pure number.
    Dimensionless,
    /// Length (m).
    Length,
    /// Mass (kg).
    Mass,
    /// Time (s).
    Time,
    /// Angle (rad).
    Angle,
    /// Velocity (m/s).
    Velocity,
    /// Angular velocity (rad/s).
    AngularVelocity,
    /// Acceleration (m/s^2).
    Acceleration,
    /// Force (N).
    Force,
    /// Torque (N m).
    Torque,
    /// Moment of inertia (kg m^2).
    Inertia,
    /// Translational stiffness (N/m).
    Stiffness,
    /// Translational damping (N s/m).
    Damping,
    /// Frequency (Hz).
    Frequency,
    /// Rotational stiffness (N m/rad).
    RotationalStiffness,
    /// Rotational damping (N m s/rad).
    RotationalDamping,
    /// Pressure, stress, Young's modulus (Pa).
    Pressure,
    /// Density (kg/m^3).
    Density,
    /// Area (m^2).
    Area,
    /// Second moment of area, torsion constant (m^4).
    AreaMoment,
}

impl Dimension {
    /// Every dimension (for "this unit is a ... unit" messages).
    pub const ALL: [Dimension; 20] = [
        Dimension::Dimensionless,
        Dimension::Length,
        Dimension::Mass,
        Dimension::Time,
        Dimension::Angle,
        Dimension::Velocity,
        Dimension::AngularVelocity,
        Dimension::Acceleration,
        Dimension::Force,
        Dimension::Torque,
        Dimension::Inertia,
        Dimension::Stiffness,
        Dimension::Damping,
        Dimension::Frequency,
        Dimension::RotationalStiffness,
        Dimension::RotationalDamping,
        Dimension::Pressure,
        Dimension::Density,
        Dimension::Area,
        Dimension::AreaMoment,
    ];

    /// Name used in messages.
    pub fn name(self) -> &'static str {
        match self {
            Dimension::Dimensionless => "dimensionless number",
            Dimension::Length => "length",
            Dimension::Mass => "mass",
            Dimension::Time => "time",
            Dimension::Angle => "angle",
            Dimension::Velocity => "velocity",
            Dimension::AngularVelocity => "angular velocity",
            Dimension::Acceleration => "acceleration",
            Dimension::Force => "force",
            Dimension::Torque => "torque",
            Dimension::Inertia => "moment of inertia",
            Dimension::Stiffness => "stiffness",
            Dimension::Damping => "damping coefficient",
            Dimension::Frequency => "frequency",
            Dimension::RotationalStiffness => "rotational stiffness",
            Dimension::RotationalDamping => "rotational damping coefficient",
            Dimension::Pressure => "pressure (stress, modulus)",
            Dimension::Density => "density",
            Dimension::Area => "area",
            Dimension::AreaMoment => "second moment of area",
        }
    }

    /// Accepted units and their factor to SI (the first one is the SI unit).
    pub fn units(self) -> &'static [(&'static str, f64)] {
        match self {
            Dimension::Dimensionless => &[("1", 1.0), ("%", 0.01)],
            Dimension::Length => &[
                ("m", 1.0),
                ("mm", 1e-3),
                ("cm", 1e-2),
                ("um", 1e-6),
                ("km", 1e3),
            ],
            Dimension::Mass => &[("kg", 1.0), ("g", 1e-3), ("t", 1e3)],
            Dimension::Time => &[("s", 1.0), ("ms", 1e-3), ("us", 1e-6), ("min", 60.0)],
            Dimension::Angle => &[("rad", 1.0), ("deg", PI / 180.0), ("rev", 2.0 * PI)],
            Dimension::Velocity => &[("m/s", 1.0), ("mm/s", 1e-3), ("km/h", 1.0 / 3.6)],
            Dimension::AngularVelocity => &[
                ("rad/s", 1.0),
                ("deg/s", PI / 180.0),
                ("rpm", PI / 30.0),
                ("rev/s", 2.0 * PI),
            ],
            Dimension::Acceleration => &[("m/s^2", 1.0), ("mm/s^2", 1e-3), ("g0", 9.80665)],
            Dimension::Force => &[("N", 1.0), ("mN", 1e-3), ("kN", 1e3), ("MN", 1e6)],
            Dimension::Torque => &[("N*m", 1.0), ("N*mm", 1e-3), ("kN*m", 1e3)],
            Dimension::Inertia => &[("kg*m^2", 1.0), ("kg*mm^2", 1e-6), ("g*mm^2", 1e-9)],
            Dimension::Stiffness => &[("N/m", 1.0), ("N/mm", 1e3), ("kN/m", 1e3), ("kN/mm", 1e6)],
            Dimension::Damping => &[("N*s/m", 1.0), ("N*s/mm", 1e3), ("kN*s/m", 1e3)],
            Dimension::Frequency => &[("Hz", 1.0), ("kHz", 1e3), ("1/s", 1.0)],
            Dimension::RotationalStiffness => &[
                ("N*m/rad", 1.0),
                ("N*mm/rad", 1e-3),
                ("kN*m/rad", 1e3),
                ("N*m/deg", 180.0 / PI),
            ],
            Dimension::RotationalDamping => &[
                ("N*m*s/rad", 1.0),
                ("N*mm*s/rad", 1e-3),
                ("kN*m*s/rad", 1e3),
            ],
            Dimension::Pressure => &[
                ("Pa", 1.0),
                ("kPa", 1e3),
                ("MPa", 1e6),
                ("GPa", 1e9),
                ("N/mm^2", 1e6),
                ("N/m^2", 1.0),
            ],
            Dimension::Density => &[
                ("kg/m^3", 1.0),
                ("g/cm^3", 1e3),
                ("kg/dm^3", 1e3),
                ("t/mm^3", 1e12),
                ("t/m^3", 1e3),
            ],
            Dimension::Area => &[("m^2", 1.0), ("cm^2", 1e-4), ("mm^2", 1e-6)],
            Dimension::AreaMoment => &[("m^4", 1.0), ("cm^4", 1e-8), ("mm^4", 1e-12)],
        }
    }

    /// Comma-separated list of the accepted units.
    pub fn unit_list(self) -> String {
        self.units()
            .iter()
            .map(|(u, _)| *u)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl<'de> Deserialize<'de> for Quantity {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(QuantityVisitor)
    }
}

struct QuantityVisitor;

impl Visitor<'_> for QuantityVisitor {
    type Value = Quantity;
    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a number (SI) or a string \"value unit\" such as \"30 mm\"")
    }
    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Quantity, E> {
        Ok(Quantity::si(v as f64))
    }
    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Quantity, E> {
        Ok(Quantity::si(v as f64))
    }
    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Quantity, E> {
        Ok(Quantity::si(v))
    }
    fn visit_str<E: de::Error>(self, s: &str) -> Result<Quantity, E> {
        parse_quantity(s).map_err(E::custom)
    }
}

/// Parses `"value unit"` (`"value"` alone is SI).
pub fn parse_quantity(s: &str) -> Result<Quantity, String> {
    let s = s.trim();
    let split = s
        .find(|c: char| c.is_whitespace() || (c.is_alphabetic() && c != 'e' && c != 'E'))
        .unwrap_or(s.len());
    // a number may contain `e` (exponent): retry the split after the exponent if needed
    let (num, unit) = s.split_at(split);
    let value: f64 = num.trim().parse().map_err(|_| {
        format!("cannot read `{s}` as a quantity: expected \"value unit\" such as \"30 mm\"")
    })?;
    let unit = unit.trim();
    Ok(Quantity {
        value,
        unit: (!unit.is_empty()).then(|| unit.to_string()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_converts() {
        let q = parse_quantity("30 mm").unwrap();
        assert_eq!(q.to_si(Dimension::Length).unwrap(), 0.03);
        let q = parse_quantity("1500 rpm").unwrap();
        assert!((q.to_si(Dimension::AngularVelocity).unwrap() - 50.0 * PI).abs() < 1e-12);
        let q = parse_quantity("2.5e-3 s").unwrap();
        assert_eq!(q.to_si(Dimension::Time).unwrap(), 2.5e-3);
        let q = parse_quantity("2kN").unwrap();
        assert_eq!(q.to_si(Dimension::Force).unwrap(), 2000.0);
        let q = parse_quantity("3 N m").unwrap();
        assert_eq!(q.to_si(Dimension::Torque).unwrap(), 3.0);
        let e = parse_quantity("3 mm").unwrap().to_si(Dimension::Mass);
        assert!(e.unwrap_err().contains("length unit"));
        assert!(parse_quantity("abc").is_err());
    }
}
