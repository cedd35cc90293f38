//! NURBS geometry and geometric contact search for flexmbs contours.
//!
//! Seed 000 §3.2.1 (NURBS curves (3.9)-(3.18), global interpolation (3.19)-(3.22), surfaces by
//! row-then-column interpolation (3.23)) and §3.3 (hierarchical-territory contact search,
//! Algorithms 4-6), following the algorithms of *The NURBS Book* (Piegl & Tiller, 2nd ed.):
//! A2.1 `FindSpan`, A2.2 `BasisFuns`, the derivatives (2.7) of A2.3 `DersBasisFuns`, A3.6/A4.2/A4.4 (rational curve and
//! surface derivatives), A9.1 (global interpolation) and its periodic variant.
//!
//! No dynamics here. Everything that runs per time step is allocation-free: evaluation takes
//! `&self` plus a scratch struct created once per curve/surface ([`CurveScratch`],
//! [`SurfaceScratch`]); interpolation matrices are factorized once at set-up
//! ([`CurveInterpolator`], [`SurfaceInterpolator`]) and re-used to map new point sets (deformed
//! node positions, velocities, mode shapes) to control points in place.
#![warn(missing_docs)]

pub mod basis;
pub mod curve;
pub mod error;
mod field;
pub mod interp;
mod lu;
pub mod params;
pub mod search;
pub mod surface;

pub use basis::{BasisScratch, KnotVector};
pub use curve::{CurveDerivs, CurveScratch, NurbsCurve};
pub use error::NurbsError;
pub use interp::{CurveInterpolator, Interpolant, SurfaceInterpolator};
pub use params::ParamMethod;
pub use search::{
    CurveProjection, CurveSearch, ParamRange, ParametricCurve, ParametricSurface, SearchGrid,
    SearchSettings, SurfaceProjection, SurfaceSearch,
};
pub use surface::{NurbsSurface, SurfaceDerivs, SurfaceScratch};

/// Highest derivative order the evaluators compute (point, first and second derivatives).
pub const MAX_DERIVATIVE: usize = 2;
