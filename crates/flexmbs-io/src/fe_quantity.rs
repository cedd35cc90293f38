//! Dimensioned numbers in FE body model files: a plain number is in the body's unit system
//! (`body.units`, SI or SI(mm)), a string `"20 mm"`, `"210 GPa"`, `"7850 kg/m^3"` is converted to
//! it. Serde has no deserialization context, so [`parse_fe_model`](crate::model::parse_fe_model)
//! sets the body's unit system for the duration of one parse ([`UnitsScope`]); the field
//! deserializers (`#[serde(deserialize_with = "...")]`) read it.

use crate::units::{Dimension, Quantity};
use flexmbs_fe::UnitSystem;
use serde::de::Error as _;
use serde::{Deserialize, Deserializer};
use std::cell::Cell;

thread_local! {
    static UNITS: Cell<UnitSystem> = const { Cell::new(UnitSystem::Si) };
}

/// Sets the unit system the FE quantity deserializers convert to, restoring the previous one
/// when dropped.
pub(crate) struct UnitsScope(UnitSystem);

impl UnitsScope {
    /// Converts to `units` until the scope ends.
    pub(crate) fn new(units: UnitSystem) -> Self {
        Self(UNITS.with(|u| u.replace(units)))
    }
}

impl Drop for UnitsScope {
    fn drop(&mut self) {
        UNITS.with(|u| u.set(self.0));
    }
}

/// One unit of `dim` in the body's unit system, in SI.
fn body_unit_in_si(dim: Dimension, units: UnitSystem) -> f64 {
    let l = units.length_to_si();
    match dim {
        Dimension::Length => l,
        Dimension::Area => l * l,
        Dimension::AreaMoment => l.powi(4),
        Dimension::Pressure => units.stress_to_si(),
        Dimension::Density => units.density_to_si(),
        _ => 1.0,
    }
}

/// The value of `q` in the body's unit system (a plain number is taken as it is).
fn in_body_units(q: &Quantity, dim: Dimension) -> Result<f64, String> {
    if q.unit.is_none() {
        return Ok(q.value);
    }
    let si = q.to_si(dim)?;
    Ok(si / body_unit_in_si(dim, UNITS.with(Cell::get)))
}

fn one<'de, D: Deserializer<'de>>(d: D, dim: Dimension) -> Result<f64, D::Error> {
    let q = Quantity::deserialize(d)?;
    in_body_units(&q, dim).map_err(D::Error::custom)
}

fn three<'de, D: Deserializer<'de>>(d: D, dim: Dimension) -> Result<[f64; 3], D::Error> {
    let q = <[Quantity; 3]>::deserialize(d)?;
    let mut out = [0.0; 3];
    for (o, q) in out.iter_mut().zip(&q) {
        *o = in_body_units(q, dim).map_err(D::Error::custom)?;
    }
    Ok(out)
}

/// A length.
pub(crate) fn length<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    one(d, Dimension::Length)
}

/// A point or vector of lengths `[x, y, z]`.
pub(crate) fn length3<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    three(d, Dimension::Length)
}

/// An optional length.
pub(crate) fn opt_length<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    match Option::<Quantity>::deserialize(d)? {
        Some(q) => in_body_units(&q, Dimension::Length)
            .map(Some)
            .map_err(D::Error::custom),
        None => Ok(None),
    }
}

/// An optional point `[x, y, z]`.
pub(crate) fn opt_length3<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
    match Option::<[Quantity; 3]>::deserialize(d)? {
        Some(q) => {
            let mut out = [0.0; 3];
            for (o, q) in out.iter_mut().zip(&q) {
                *o = in_body_units(q, Dimension::Length).map_err(D::Error::custom)?;
            }
            Ok(Some(out))
        }
        None => Ok(None),
    }
}

/// Polygon vertices `[[y, z], ...]`.
pub(crate) fn vertices<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
    let q = Vec::<[Quantity; 2]>::deserialize(d)?;
    q.iter()
        .map(|[y, z]| {
            Ok([
                in_body_units(y, Dimension::Length).map_err(D::Error::custom)?,
                in_body_units(z, Dimension::Length).map_err(D::Error::custom)?,
            ])
        })
        .collect()
}

/// A pressure (Young's modulus).
pub(crate) fn pressure<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    one(d, Dimension::Pressure)
}

/// A density.
pub(crate) fn density<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    one(d, Dimension::Density)
}

/// An area.
pub(crate) fn area<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    one(d, Dimension::Area)
}

/// A second moment of area or torsion constant.
pub(crate) fn area_moment<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    one(d, Dimension::AreaMoment)
}

/// Converts a length quantity for code that parses by hand (node selectors).
pub(crate) fn length_value(q: &Quantity) -> Result<f64, String> {
    in_body_units(q, Dimension::Length)
}
