//! Geometric contact search: the point on a contour closest to a given point (normal
//! projection), seed 000 §3.3 (hierarchical-territory algorithm, Algorithms 4-6).
//!
//! The search is written against two small traits, [`ParametricCurve`] and
//! [`ParametricSurface`] (position and derivatives at parameters), implemented by the NURBS
//! types and by any analytic contour.

mod curve;
mod surface;

pub use curve::{CurveProjection, CurveSearch};
pub use surface::{SurfaceProjection, SurfaceSearch};

use crate::curve::{CurveDerivs, CurveScratch, NurbsCurve};
use crate::error::NurbsError;
use crate::surface::{NurbsSurface, SurfaceDerivs, SurfaceScratch};

/// Parameter range of one contour direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParamRange {
    /// Start.
    pub lo: f64,
    /// End.
    pub hi: f64,
    /// Closed: the contour is periodic with period `hi - lo` (seam at `lo == hi`).
    pub closed: bool,
}

impl ParamRange {
    /// Period/length `hi - lo`.
    pub fn length(&self) -> f64 {
        self.hi - self.lo
    }
    /// Wraps (closed) a parameter into `[lo, hi)`; open parameters are returned unchanged.
    pub fn wrap(&self, u: f64) -> f64 {
        if self.closed {
            let w = self.lo + (u - self.lo).rem_euclid(self.length());
            if w >= self.hi {
                self.lo
            } else {
                w
            }
        } else {
            u
        }
    }
}

/// A curve contour: position and derivatives at a parameter (1D contour, seed §3.2.2).
pub trait ParametricCurve {
    /// Evaluation scratch (`()` for analytic curves).
    type Scratch;
    /// The parameter range.
    fn range(&self) -> ParamRange;
    /// `C, C', C''` at `u` (inside the range).
    fn curve_derivatives(&self, u: f64, scratch: &mut Self::Scratch) -> CurveDerivs;
}

/// A surface contour: position and partials up to order two at `(eta, xi)` (2D contour).
pub trait ParametricSurface {
    /// Evaluation scratch (`()` for analytic surfaces).
    type Scratch;
    /// Parameter ranges `[eta, xi]`.
    fn ranges(&self) -> [ParamRange; 2];
    /// `S` and its partials at `(eta, xi)` (inside the ranges).
    fn surface_derivatives(&self, eta: f64, xi: f64, scratch: &mut Self::Scratch) -> SurfaceDerivs;
}

impl ParametricCurve for NurbsCurve {
    type Scratch = CurveScratch;
    fn range(&self) -> ParamRange {
        let (lo, hi) = self.domain();
        ParamRange {
            lo,
            hi,
            closed: self.is_periodic(),
        }
    }
    fn curve_derivatives(&self, u: f64, scratch: &mut CurveScratch) -> CurveDerivs {
        self.derivatives(u, scratch)
    }
}

impl ParametricSurface for NurbsSurface {
    type Scratch = SurfaceScratch;
    fn ranges(&self) -> [ParamRange; 2] {
        let (e, x) = (self.eta_knots(), self.xi_knots());
        let ((el, eh), (xl, xh)) = (e.domain(), x.domain());
        [
            ParamRange {
                lo: el,
                hi: eh,
                closed: e.is_periodic(),
            },
            ParamRange {
                lo: xl,
                hi: xh,
                closed: x.is_periodic(),
            },
        ]
    }
    fn surface_derivatives(
        &self,
        eta: f64,
        xi: f64,
        scratch: &mut SurfaceScratch,
    ) -> SurfaceDerivs {
        self.derivatives(eta, xi, scratch)
    }
}

/// Coarse grid of one direction (seed §4.5: `setEqualSpacing` / `setNodes`).
#[derive(Debug, Clone, PartialEq)]
pub enum SearchGrid {
    /// This many equal intervals over the range.
    EqualSpacing(usize),
    /// Given strictly increasing parameter values inside the range (e.g. the nodes' parameters).
    Nodes(Vec<f64>),
}

/// Tolerances of the Newton refinement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchSettings {
    /// Maximum Newton iterations per start.
    pub max_iterations: usize,
    /// Convergence: Newton step below this fraction of the parameter range.
    pub step_tolerance: f64,
    /// Accept only local minima of the distance (reject maxima and saddle points of it).
    pub minima_only: bool,
}

impl Default for SearchSettings {
    fn default() -> Self {
        Self {
            max_iterations: 30,
            step_tolerance: 1e-12,
            minima_only: true,
        }
    }
}

/// Grid node parameters of one direction; a closed direction gets no node at `hi` (the
/// interval from the last node to `lo + period` closes the loop).
pub(crate) fn grid_nodes(grid: &SearchGrid, range: ParamRange) -> Result<Vec<f64>, NurbsError> {
    let nodes = match grid {
        SearchGrid::EqualSpacing(n) => {
            if *n == 0 {
                return Err(NurbsError::InvalidGrid {
                    reason: "zero intervals",
                });
            }
            let count = if range.closed { *n } else { n + 1 };
            let h = range.length() / *n as f64;
            (0..count).map(|i| range.lo + h * i as f64).collect()
        }
        SearchGrid::Nodes(v) => v.clone(),
    };
    let min_nodes = if range.closed { 1 } else { 2 };
    if nodes.len() < min_nodes {
        return Err(NurbsError::InvalidGrid {
            reason: "too few nodes",
        });
    }
    for (i, &u) in nodes.iter().enumerate() {
        if !u.is_finite() || u < range.lo || u > range.hi || (range.closed && u >= range.hi) {
            return Err(NurbsError::InvalidGrid {
                reason: "node outside the parameter range",
            });
        }
        if i > 0 && nodes[i - 1] >= u {
            return Err(NurbsError::InvalidGrid {
                reason: "nodes not strictly increasing",
            });
        }
    }
    Ok(nodes)
}

/// Number of grid intervals (closed: one more, across the seam).
pub(crate) fn n_cells(nodes: &[f64], range: ParamRange) -> usize {
    if range.closed {
        nodes.len()
    } else {
        nodes.len() - 1
    }
}

/// Interval `c` as `(start, end)`; the closing interval of a closed direction ends at
/// `nodes[0] + period`.
pub(crate) fn cell(nodes: &[f64], range: ParamRange, c: usize) -> (f64, f64) {
    let end = if c + 1 < nodes.len() {
        nodes[c + 1]
    } else {
        nodes[0] + range.length()
    };
    (nodes[c], end)
}

/// Moves a Newton iterate back into an open range; returns the new value and whether it had
/// to be moved by more than a rounding margin (the iterate left the contour).
pub(crate) fn confine(u: f64, range: ParamRange) -> (f64, bool) {
    if range.closed {
        return (range.wrap(u), false);
    }
    let margin = 1e-12 * range.length();
    let c = u.clamp(range.lo, range.hi);
    (c, (u - c).abs() > margin)
}
