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
//!
//! ```
//! use flexmbs_nurbs::*;
//! use nalgebra::Vector3;
//! // the top surface of a beam: 20 x 4 nodes, eta along the beam, xi across
//! let node = |i: usize, j: usize, sag: f64| {
//!     let x = i as f64 / 19.0;
//!     Vector3::new(x, 0.1 * j as f64 / 3.0, -sag * x * x)
//! };
//! let grid: Vec<_> = (0..20).flat_map(|i| (0..4).map(move |j| node(i, j, 0.0))).collect();
//! // set-up: parameters and knots from the undeformed nodes, both factorizations
//! let ip = SurfaceInterpolator::from_grid(&grid, 20, 4, ParamMethod::ChordLength, [3, 3], [false, false])?;
//! let mut contour = ip.interpolate(&grid)?;
//! let mut scratch = contour.scratch();
//! let grids = [SearchGrid::EqualSpacing(19), SearchGrid::EqualSpacing(3)];
//! let mut search = SurfaceSearch::new(&contour, grids, SearchSettings::default())?;
//! // a step: re-interpolate the deformed nodes in place, then find the contact point
//! let deformed: Vec<_> = (0..20).flat_map(|i| (0..4).map(move |j| node(i, j, 0.01))).collect();
//! ip.update_surface(&deformed, &mut contour)?;
//! let p = search.search(&contour, &mut scratch, &Vector3::new(0.5, 0.05, 0.1)).unwrap();
//! assert!((p.derivs.s.x - 0.5).abs() < 1e-2 && p.signed_distance > 0.1);
//! // beyond the end of the beam there is no normal projection: no contact
//! assert!(search.search(&contour, &mut scratch, &Vector3::new(1.2, 0.05, 0.1)).is_none());
//! # Ok::<(), NurbsError>(())
//! ```
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
