//! Point to 2D contour search (seed 000 §3.3, Algorithms 4-6).

use super::{
    cell, confine, grid_nodes, n_cells, ParamRange, ParametricSurface, SearchGrid, SearchSettings,
};
use crate::error::NurbsError;
use crate::surface::SurfaceDerivs;
use nalgebra::Vector3;

/// The normal projection of a point `C1` onto a 2D contour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceProjection {
    /// Contour coordinate `eta` of the contact point `C2`.
    pub eta: f64,
    /// Contour coordinate `xi` of the contact point `C2`.
    pub xi: f64,
    /// Contour point and partials at `(eta, xi)`.
    pub derivs: SurfaceDerivs,
    /// Distance vector `g = r_C1 - r_C2` (3.30).
    pub gap: Vector3<f64>,
    /// `|g|`.
    pub distance: f64,
    /// Unit normal (3.27) at `C2`.
    pub normal: Vector3<f64>,
    /// `n^T g` (positive on the side the normal points to).
    pub signed_distance: f64,
}

/// Hierarchical-territory search of the point of a 2D contour closest to a given point.
///
/// Coarse level (seed §3.3, Alg. 6 with Alg. 4): the tangent projections `g_eta = t_eta^T g`,
/// `g_xi = t_xi^T g` (3.31)-(3.32) are evaluated on the grid nodes; a cell is a potential region
/// where `g_eta` changes sign (or vanishes) along `eta` and `g_xi` along `xi` on its corners (the
/// overlap of both sign-change territories). Finer level (Alg. 5): Newton on
/// `t_eta^T g = t_xi^T g = 0` (3.6) from the cell centre, steps limited to one cell. Among the
/// converged local minima of the distance, the one with minimal distance is the contact point.
/// Warm start: Newton from the last solution; the coarse level runs only on the first call or
/// when that fails. Open directions: an iterate that leaves the contour twice in a row fails, so
/// a point whose projection lies outside the contour gives `None` (no contact), never a point
/// on the edge that is not a normal projection.
#[derive(Debug, Clone)]
pub struct SurfaceSearch {
    ranges: [ParamRange; 2],
    eta_nodes: Vec<f64>,
    xi_nodes: Vec<f64>,
    g_eta: Vec<f64>,
    g_xi: Vec<f64>,
    warm_step: [f64; 2],
    settings: SearchSettings,
    last: Option<[f64; 2]>,
    full_searches: usize,
}

impl SurfaceSearch {
    /// Search on `surface` with coarse grids `[eta, xi]` (allocates its buffers once).
    pub fn new<S: ParametricSurface + ?Sized>(
        surface: &S,
        grids: [SearchGrid; 2],
        settings: SearchSettings,
    ) -> Result<Self, NurbsError> {
        let ranges = surface.ranges();
        for r in &ranges {
            if !(r.lo.is_finite() && r.hi.is_finite() && r.lo < r.hi) {
                return Err(NurbsError::EmptyDomain { lo: r.lo, hi: r.hi });
            }
        }
        let eta_nodes = grid_nodes(&grids[0], ranges[0])?;
        let xi_nodes = grid_nodes(&grids[1], ranges[1])?;
        let n = eta_nodes.len() * xi_nodes.len();
        let warm_step = [
            ranges[0].length() / n_cells(&eta_nodes, ranges[0]) as f64,
            ranges[1].length() / n_cells(&xi_nodes, ranges[1]) as f64,
        ];
        Ok(Self {
            ranges,
            eta_nodes,
            xi_nodes,
            g_eta: vec![0.0; n],
            g_xi: vec![0.0; n],
            warm_step,
            settings,
            last: None,
            full_searches: 0,
        })
    }

    /// Forgets the last solution: the next search runs the coarse level.
    pub fn reset(&mut self) {
        self.last = None;
    }
    /// Contour coordinates of the last successful search (the warm start).
    pub fn last(&self) -> Option<[f64; 2]> {
        self.last
    }
    /// How many coarse-level (full) searches ran so far.
    pub fn full_search_count(&self) -> usize {
        self.full_searches
    }

    /// Contact point of `x` (Alg. 6): warm start from the last solution, full search on failure.
    /// `None`: no normal projection onto the contour (e.g. the point lies beyond an open edge).
    pub fn search<S: ParametricSurface + ?Sized>(
        &mut self,
        surface: &S,
        scratch: &mut S::Scratch,
        x: &Vector3<f64>,
    ) -> Option<SurfaceProjection> {
        if let Some(start) = self.last {
            if let Some(p) = self.newton(surface, scratch, x, start, self.warm_step) {
                self.last = Some([p.eta, p.xi]);
                return Some(p);
            }
        }
        self.full_search(surface, scratch, x)
    }

    /// Coarse level over the whole grid, then the finer level in every potential cell.
    pub fn full_search<S: ParametricSurface + ?Sized>(
        &mut self,
        surface: &S,
        scratch: &mut S::Scratch,
        x: &Vector3<f64>,
    ) -> Option<SurfaceProjection> {
        self.full_searches += 1;
        let nx = self.xi_nodes.len();
        let (mut nearest, mut nearest_distance) = ([0, 0], f64::INFINITY);
        for (m, &eta) in self.eta_nodes.iter().enumerate() {
            for (n, &xi) in self.xi_nodes.iter().enumerate() {
                let d = surface.surface_derivatives(eta, xi, scratch);
                let g = x - d.s;
                self.g_eta[m * nx + n] = d.s_u.dot(&g); // (3.31)
                self.g_xi[m * nx + n] = d.s_v.dot(&g); // (3.32)
                if g.norm() < nearest_distance {
                    (nearest, nearest_distance) = ([m, n], g.norm());
                }
            }
        }
        let mut best: Option<SurfaceProjection> = None;
        for ce in 0..n_cells(&self.eta_nodes, self.ranges[0]) {
            for cx in 0..n_cells(&self.xi_nodes, self.ranges[1]) {
                if !self.is_potential_cell(ce, cx) && !self.touches(ce, cx, nearest) {
                    continue;
                }
                let (e0, e1) = cell(&self.eta_nodes, self.ranges[0], ce);
                let (x0, x1) = cell(&self.xi_nodes, self.ranges[1], cx);
                let start = [0.5 * (e0 + e1), 0.5 * (x0 + x1)];
                let step = [e1 - e0, x1 - x0];
                if let Some(p) = self.newton(surface, scratch, x, start, step) {
                    if best.is_none_or(|b| p.distance < b.distance) {
                        best = Some(p);
                    }
                }
            }
        }
        self.last = best.map(|p| [p.eta, p.xi]);
        best
    }

    /// Cell `(ce, cx)` has the grid node `node` as a corner (the cells around the nearest node
    /// are always searched: a projection close to the node can hide from the corner signs when
    /// the zero line of a tangent projection enters and leaves the cell through one edge).
    fn touches(&self, ce: usize, cx: usize, node: [usize; 2]) -> bool {
        let (ne, nx) = (self.eta_nodes.len(), self.xi_nodes.len());
        (node[0] == ce || node[0] == (ce + 1) % ne) && (node[1] == cx || node[1] == (cx + 1) % nx)
    }

    /// Both tangent projections change sign (or vanish) on the corners of cell `(ce, cx)`.
    fn is_potential_cell(&self, ce: usize, cx: usize) -> bool {
        let (ne, nx) = (self.eta_nodes.len(), self.xi_nodes.len());
        let corners = [
            ce * nx + cx,
            ce * nx + (cx + 1) % nx,
            ((ce + 1) % ne) * nx + cx,
            ((ce + 1) % ne) * nx + (cx + 1) % nx,
        ];
        let changes = |g: &[f64]| {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for &c in &corners {
                lo = lo.min(g[c]);
                hi = hi.max(g[c]);
            }
            lo <= 0.0 && hi >= 0.0
        };
        changes(&self.g_eta) && changes(&self.g_xi)
    }

    /// Newton on `f = (t_eta^T g, t_xi^T g) = 0` (3.6) (descent steps where the distance is not
    /// convex, see [`newton_step`]); steps limited to `max_step`, open directions confined to
    /// the contour.
    fn newton<S: ParametricSurface + ?Sized>(
        &self,
        surface: &S,
        scratch: &mut S::Scratch,
        x: &Vector3<f64>,
        start: [f64; 2],
        max_step: [f64; 2],
    ) -> Option<SurfaceProjection> {
        let r = self.ranges;
        let mut u = start;
        let mut outside_in_a_row = 0;
        for _ in 0..self.settings.max_iterations {
            let d = surface.surface_derivatives(u[0], u[1], scratch);
            let (step, _) = newton_step(&d, x, self.settings.minima_only)?;
            let scale = (step[0].abs() / max_step[0])
                .max(step[1].abs() / max_step[1])
                .max(1.0);
            let (e, out_e) = confine(u[0] + step[0] / scale, r[0]);
            let (xi, out_x) = confine(u[1] + step[1] / scale, r[1]);
            let converged = scale == 1.0
                && step[0].abs() <= self.settings.step_tolerance * r[0].length()
                && step[1].abs() <= self.settings.step_tolerance * r[1].length();
            u = [e, xi];
            if out_e || out_x {
                outside_in_a_row += 1;
                if outside_in_a_row >= 2 {
                    return None;
                }
                continue;
            }
            outside_in_a_row = 0;
            if converged {
                return self.projection(surface, scratch, x, u);
            }
        }
        None
    }

    /// The projection at a converged `u`, if it is a minimum of the distance (when required).
    fn projection<S: ParametricSurface + ?Sized>(
        &self,
        surface: &S,
        scratch: &mut S::Scratch,
        x: &Vector3<f64>,
        u: [f64; 2],
    ) -> Option<SurfaceProjection> {
        let d = surface.surface_derivatives(u[0], u[1], scratch);
        let (_, is_minimum) = newton_step(&d, x, false).unwrap_or(([0.0; 2], false));
        if self.settings.minima_only && !is_minimum {
            return None;
        }
        let gap = x - d.s;
        let normal = d.normal();
        Some(SurfaceProjection {
            eta: u[0],
            xi: u[1],
            derivs: d,
            gap,
            distance: gap.norm(),
            normal,
            signed_distance: normal.dot(&gap),
        })
    }
}

/// Newton step `H^-1 f` of the projection equations `f = (t_eta^T g, t_xi^T g) = 0` (3.6), with
/// `H = -df/d(eta, xi)` the Hessian of `|g|^2 / 2`, and whether `H` is positive definite (a
/// minimum of the distance). With `descent`, an indefinite `H` is replaced by the first
/// fundamental form `[t_eta, t_xi]^T [t_eta, t_xi]` (Gauss-Newton): the step then still lowers
/// the distance instead of heading for a maximum or saddle point of it. `None` if singular.
fn newton_step(d: &SurfaceDerivs, x: &Vector3<f64>, descent: bool) -> Option<([f64; 2], bool)> {
    let g = x - d.s;
    let f = [d.s_u.dot(&g), d.s_v.dot(&g)];
    let (e, fm, gm) = (
        d.s_u.norm_squared(),
        d.s_u.dot(&d.s_v),
        d.s_v.norm_squared(),
    );
    let mut h = [e - d.s_uu.dot(&g), fm - d.s_uv.dot(&g), gm - d.s_vv.dot(&g)];
    let mut det = h[0] * h[2] - h[1] * h[1];
    let is_minimum = h[0] > 0.0 && det > 0.0;
    if descent && !is_minimum {
        h = [e, fm, gm];
        det = e * gm - fm * fm;
    }
    if !det.is_finite() || det.abs() <= 1e-14 * e * gm || e * gm == 0.0 {
        return None;
    }
    let step = [
        (h[2] * f[0] - h[1] * f[1]) / det,
        (h[0] * f[1] - h[1] * f[0]) / det,
    ];
    Some((step, is_minimum))
}
