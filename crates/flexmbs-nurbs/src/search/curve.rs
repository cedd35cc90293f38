//! Point to 1D contour search (seed 000 §3.3 reduced to one contour coordinate).

use super::{
    cell, confine, grid_nodes, n_cells, ParamRange, ParametricCurve, SearchGrid, SearchSettings,
};
use crate::curve::CurveDerivs;
use crate::error::NurbsError;
use nalgebra::Vector3;

/// The normal projection of a point onto a 1D contour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveProjection {
    /// Contour coordinate `eta` of the contact point.
    pub eta: f64,
    /// Contour point and derivatives at `eta`.
    pub derivs: CurveDerivs,
    /// Distance vector `g = r_C1 - r_C2` (3.30).
    pub gap: Vector3<f64>,
    /// `|g|`.
    pub distance: f64,
}

/// Search of the point of a 1D contour closest to a given point: coarse grid of sign changes of
/// `t^T g` (3.31), Newton on `t^T g = 0` in each potential interval, minimal distance among the
/// local minima; warm start from the last solution, coarse level only when that fails. As
/// [`crate::SurfaceSearch`], `None` when the projection lies beyond an open end.
#[derive(Debug, Clone)]
pub struct CurveSearch {
    range: ParamRange,
    nodes: Vec<f64>,
    g: Vec<f64>,
    warm_step: f64,
    settings: SearchSettings,
    last: Option<f64>,
    full_searches: usize,
}

impl CurveSearch {
    /// Search on `curve` with a coarse grid (allocates its buffers once).
    pub fn new<C: ParametricCurve + ?Sized>(
        curve: &C,
        grid: SearchGrid,
        settings: SearchSettings,
    ) -> Result<Self, NurbsError> {
        let range = curve.range();
        if !(range.lo.is_finite() && range.hi.is_finite() && range.lo < range.hi) {
            return Err(NurbsError::EmptyDomain {
                lo: range.lo,
                hi: range.hi,
            });
        }
        let nodes = grid_nodes(&grid, range)?;
        let warm_step = range.length() / n_cells(&nodes, range) as f64;
        let g = vec![0.0; nodes.len()];
        Ok(Self {
            range,
            nodes,
            g,
            warm_step,
            settings,
            last: None,
            full_searches: 0,
        })
    }

    /// Forgets the last solution.
    pub fn reset(&mut self) {
        self.last = None;
    }
    /// Contour coordinate of the last successful search.
    pub fn last(&self) -> Option<f64> {
        self.last
    }
    /// How many coarse-level searches ran so far.
    pub fn full_search_count(&self) -> usize {
        self.full_searches
    }

    /// Contact point of `x`: warm start, full search on failure; `None`: no normal projection.
    pub fn search<C: ParametricCurve + ?Sized>(
        &mut self,
        curve: &C,
        scratch: &mut C::Scratch,
        x: &Vector3<f64>,
    ) -> Option<CurveProjection> {
        if let Some(start) = self.last {
            if let Some(p) = self.newton(curve, scratch, x, start, self.warm_step) {
                self.last = Some(p.eta);
                return Some(p);
            }
        }
        self.full_search(curve, scratch, x)
    }

    /// Coarse level over all grid intervals, then Newton in every interval with a sign change.
    pub fn full_search<C: ParametricCurve + ?Sized>(
        &mut self,
        curve: &C,
        scratch: &mut C::Scratch,
        x: &Vector3<f64>,
    ) -> Option<CurveProjection> {
        self.full_searches += 1;
        let (mut nearest, mut nearest_distance) = (0, f64::INFINITY);
        for (i, (gi, &u)) in self.g.iter_mut().zip(&self.nodes).enumerate() {
            let d = curve.curve_derivatives(u, scratch);
            *gi = d.d1.dot(&(x - d.c));
            if (x - d.c).norm() < nearest_distance {
                (nearest, nearest_distance) = (i, (x - d.c).norm());
            }
        }
        let n = self.nodes.len();
        let mut best: Option<CurveProjection> = None;
        for c in 0..n_cells(&self.nodes, self.range) {
            let (fa, fb) = (self.g[c], self.g[(c + 1) % n]);
            // the intervals next to the nearest node are always searched (as in the 2D search)
            if fa * fb > 0.0 && nearest != c && nearest != (c + 1) % n {
                continue;
            }
            let (a, b) = cell(&self.nodes, self.range, c);
            if let Some(p) = self.newton(curve, scratch, x, 0.5 * (a + b), b - a) {
                if best.is_none_or(|q| p.distance < q.distance) {
                    best = Some(p);
                }
            }
        }
        self.last = best.map(|p| p.eta);
        best
    }

    /// Newton on `f = t^T g = 0`, `f' = C''^T g - |C'|^2` (a descent step `f / |C'|^2` where
    /// the distance is not convex); steps limited to `max_step`.
    fn newton<C: ParametricCurve + ?Sized>(
        &self,
        curve: &C,
        scratch: &mut C::Scratch,
        x: &Vector3<f64>,
        start: f64,
        max_step: f64,
    ) -> Option<CurveProjection> {
        let mut u = start;
        let mut outside_in_a_row = 0;
        for _ in 0..self.settings.max_iterations {
            let d = curve.curve_derivatives(u, scratch);
            let g = x - d.c;
            let f = d.d1.dot(&g);
            // Hessian of |g|^2 / 2; where it is not positive, a Gauss-Newton (descent) step
            let hessian = d.d1.norm_squared() - d.d2.dot(&g);
            let h = if self.settings.minima_only && hessian <= 0.0 {
                d.d1.norm_squared()
            } else {
                hessian
            };
            if !h.is_finite()
                || h.abs() <= 1e-14 * d.d1.norm_squared()
                || d.d1.norm_squared() == 0.0
            {
                return None;
            }
            let step = f / h;
            let limited = step.clamp(-max_step, max_step);
            let (next, outside) = confine(u + limited, self.range);
            let converged =
                limited == step && step.abs() <= self.settings.step_tolerance * self.range.length();
            u = next;
            if outside {
                outside_in_a_row += 1;
                if outside_in_a_row >= 2 {
                    return None;
                }
                continue;
            }
            outside_in_a_row = 0;
            if converged {
                let d = curve.curve_derivatives(u, scratch);
                let gap = x - d.c;
                let is_minimum = d.d2.dot(&gap) - d.d1.norm_squared() < 0.0;
                if self.settings.minima_only && !is_minimum {
                    return None;
                }
                return Some(CurveProjection {
                    eta: u,
                    derivs: d,
                    gap,
                    distance: gap.norm(),
                });
            }
        }
        None
    }
}
