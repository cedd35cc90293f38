//! Global interpolation through points (seed 000 (3.18)-(3.23); NURBS Book A9.1 and its
//! periodic variant), factorized once and re-used for new point sets.

use crate::basis::{BasisScratch, KnotVector};
use crate::curve::NurbsCurve;
use crate::error::NurbsError;
use crate::lu::BandedLu;
use crate::params::{
    averaged_knots, curve_parameters, periodic_knots, surface_parameters, ParamMethod,
};
use crate::surface::NurbsSurface;
use nalgebra::{Vector3, Vector4};
use std::ops::{AddAssign, DivAssign, Mul, SubAssign};

/// A value that can be interpolated (the map points -> control points is linear): `f64`,
/// `Vector3<f64>` (positions, velocities, mode shape columns), `Vector4<f64>` (homogeneous).
pub trait Interpolant:
    Copy + AddAssign + SubAssign + DivAssign<f64> + Mul<f64, Output = Self>
{
}
impl<T: Copy + AddAssign + SubAssign + DivAssign<f64> + Mul<f64, Output = T>> Interpolant for T {}

/// Interpolation along one direction: parameters and knots fixed at set-up (from the undeformed
/// geometry, seed §3.2.2), the collocation matrix `N_ij = N_{j,p}(u_i)` (3.18) LU-factorized once;
/// [`CurveInterpolator::control_points_into`] then solves `P = N^-1 Q` (3.22) in place.
///
/// Open: `k` points, `k` control points, knots by averaging. Closed: `k` distinct points (the
/// first is not repeated), periodic knots, `k + p` control points with `P_{k+j} = P_j`, so the
/// curve is `C^(p-1)` across the seam.
#[derive(Debug, Clone)]
pub struct CurveInterpolator {
    knots: KnotVector,
    params: Vec<f64>,
    lu: BandedLu,
}

impl CurveInterpolator {
    /// Set-up from parameters (open: strictly increasing; closed: strictly increasing in
    /// `[0, 1)`, period 1), degree and closedness; needs at least `degree + 1` parameters.
    pub fn new(params: &[f64], degree: usize, closed: bool) -> Result<Self, NurbsError> {
        let k = params.len();
        if degree == 0 {
            return Err(NurbsError::ZeroDegree { degree });
        }
        if k < degree + 1 {
            return Err(NurbsError::TooFewPoints {
                got: k,
                needed: degree + 1,
                degree,
            });
        }
        check_parameters(params, closed)?;
        let knots = if closed {
            KnotVector::periodic(degree, periodic_knots(params, degree), k + degree)?
        } else {
            KnotVector::new(degree, averaged_knots(params, degree), k)?
        };
        let mut n = vec![0.0; k * k];
        let mut scratch = BasisScratch::new(degree);
        for (i, &u) in params.iter().enumerate() {
            let span = knots.basis_derivatives(u, 0, false, &mut scratch);
            for j in 0..=degree {
                n[i * k + (span - degree + j) % k] += scratch.der(0, j);
            }
        }
        let lu = BandedLu::factor(n, k)?;
        Ok(Self {
            knots,
            params: params.to_vec(),
            lu,
        })
    }

    /// Set-up from the points themselves (parameters by `method`, (3.19)-(3.21)).
    pub fn from_points(
        points: &[Vector3<f64>],
        method: ParamMethod,
        degree: usize,
        closed: bool,
    ) -> Result<Self, NurbsError> {
        Self::new(&curve_parameters(points, method, closed)?, degree, closed)
    }

    /// The knot vector of the interpolating curves.
    pub fn knot_vector(&self) -> &KnotVector {
        &self.knots
    }
    /// The interpolation parameters `u_i` (`C(u_i) = Q_i`).
    pub fn params(&self) -> &[f64] {
        &self.params
    }
    /// Number of points `k`.
    pub fn n_points(&self) -> usize {
        self.params.len()
    }
    /// Number of control points (open `k`, closed `k + p`).
    pub fn n_ctrl(&self) -> usize {
        self.knots.n_ctrl()
    }

    /// Control points of the curve through `values` (`k` entries) into `ctrl` (`n_ctrl`
    /// entries): `P = N^-1 Q` (3.22), closed ones wrapped. Allocation-free.
    pub fn control_points_into<T: Interpolant>(
        &self,
        values: &[T],
        ctrl: &mut [T],
    ) -> Result<(), NurbsError> {
        let k = self.n_points();
        size_check("points", k, values.len())?;
        size_check("control points", self.n_ctrl(), ctrl.len())?;
        ctrl[..k].copy_from_slice(values);
        self.solve_line(ctrl, 0, 1);
        Ok(())
    }

    /// The weights `w_i` of the data points in the interpolated curve's value at `u`:
    /// `C(u) = Σ_i w_i Q_i` for every data set `Q` (interpolation is linear in the data, so a
    /// load at `C(u)` acts on the data points with these shares; they sum to 1). `O(k^2)`,
    /// allocates: set-up time.
    pub fn data_weights(&self, u: f64) -> Result<Vec<f64>, NurbsError> {
        let (k, p) = (self.n_points(), self.knots.degree());
        let mut scratch = BasisScratch::new(p);
        let span = self.knots.basis_derivatives(u, 0, false, &mut scratch);
        let (mut data, mut ctrl) = (vec![0.0; k], vec![0.0; self.n_ctrl()]);
        let mut w = vec![0.0; k];
        for (i, wi) in w.iter_mut().enumerate() {
            data.fill(0.0);
            data[i] = 1.0;
            self.control_points_into(&data, &mut ctrl)?;
            *wi = (0..=p)
                .map(|j| scratch.der(0, j) * ctrl[span - p + j])
                .sum();
        }
        Ok(w)
    }

    #[cfg(test)]
    pub(crate) fn lu(&self) -> &BandedLu {
        &self.lu
    }

    /// Solves in place on `k` strided entries and writes the `p` wrapped ones (closed).
    pub(crate) fn solve_line<T: Interpolant>(&self, data: &mut [T], offset: usize, stride: usize) {
        self.lu.solve_strided(data, offset, stride);
        if self.knots.is_periodic() {
            let k = self.n_points();
            for j in 0..self.knots.degree() {
                data[offset + (k + j) * stride] = data[offset + j * stride];
            }
        }
    }

    /// A new (non-rational) curve through `points` (allocates; set-up time).
    pub fn interpolate(&self, points: &[Vector3<f64>]) -> Result<NurbsCurve, NurbsError> {
        let mut ctrl = vec![Vector4::zeros(); self.n_ctrl()];
        let homog: Vec<Vector4<f64>> = points.iter().map(|p| p.push(1.0)).collect();
        self.control_points_into(&homog, &mut ctrl)?;
        ctrl.iter_mut().for_each(|c| c.w = 1.0);
        NurbsCurve::from_knot_vector(self.knots.clone(), ctrl)
    }

    /// Re-interpolates `curve` (built by [`CurveInterpolator::interpolate`]) through new
    /// points in place, allocation-free (the deformed contour of a time step).
    pub fn update_curve(
        &self,
        points: &[Vector3<f64>],
        curve: &mut NurbsCurve,
    ) -> Result<(), NurbsError> {
        size_check("points", self.n_points(), points.len())?;
        size_check(
            "curve control points",
            self.n_ctrl(),
            curve.control_points_w().len(),
        )?;
        let ctrl = curve.control_points_w_mut();
        for (c, p) in ctrl.iter_mut().zip(points) {
            *c = p.push(1.0);
        }
        self.solve_line(ctrl, 0, 1);
        ctrl.iter_mut().for_each(|c| c.w = 1.0);
        Ok(())
    }
}

/// Surface interpolation of a grid `Q_ij` (row-major `i * n_xi + j`, `i` along `eta`): every
/// column along `eta`, then every row of the result along `xi` (seed §3.2.1 after (3.23)); both
/// directions factorized once, open or closed each.
#[derive(Debug, Clone)]
pub struct SurfaceInterpolator {
    eta: CurveInterpolator,
    xi: CurveInterpolator,
}

impl SurfaceInterpolator {
    /// Set-up from the parameters of both directions, degrees `[p, q]` and closedness.
    pub fn new(
        params_eta: &[f64],
        params_xi: &[f64],
        degrees: [usize; 2],
        closed: [bool; 2],
    ) -> Result<Self, NurbsError> {
        let eta = CurveInterpolator::new(params_eta, degrees[0], closed[0])?;
        let xi = CurveInterpolator::new(params_xi, degrees[1], closed[1])?;
        Ok(Self { eta, xi })
    }

    /// Set-up from the grid itself (line parameters averaged over the lines).
    pub fn from_grid(
        grid: &[Vector3<f64>],
        n_eta: usize,
        n_xi: usize,
        method: ParamMethod,
        degrees: [usize; 2],
        closed: [bool; 2],
    ) -> Result<Self, NurbsError> {
        let (pe, px) = surface_parameters(grid, n_eta, n_xi, method, closed)?;
        Self::new(&pe, &px, degrees, closed)
    }

    /// The interpolator along `eta`.
    pub fn eta(&self) -> &CurveInterpolator {
        &self.eta
    }
    /// The interpolator along `xi`.
    pub fn xi(&self) -> &CurveInterpolator {
        &self.xi
    }
    /// Number of control points `n_ctrl_eta * n_ctrl_xi`.
    pub fn n_ctrl(&self) -> usize {
        self.eta.n_ctrl() * self.xi.n_ctrl()
    }

    /// Control net (row-major, `n_ctrl_eta x n_ctrl_xi`) of the surface through the grid
    /// `values` (`n_eta x n_xi`). Allocation-free: both passes run in place in `ctrl`.
    pub fn control_points_into<T: Interpolant>(
        &self,
        values: &[T],
        ctrl: &mut [T],
    ) -> Result<(), NurbsError> {
        let (ne, nx) = (self.eta.n_points(), self.xi.n_points());
        size_check("grid points", ne * nx, values.len())?;
        size_check("control points", self.n_ctrl(), ctrl.len())?;
        let ncx = self.xi.n_ctrl();
        for i in 0..ne {
            ctrl[i * ncx..i * ncx + nx].copy_from_slice(&values[i * nx..(i + 1) * nx]);
        }
        self.solve_in_place(ctrl);
        Ok(())
    }

    /// The two passes on a net whose first `n_eta x n_xi` entries (stride `n_ctrl_xi`) hold Q.
    fn solve_in_place<T: Interpolant>(&self, ctrl: &mut [T]) {
        let ncx = self.xi.n_ctrl();
        for j in 0..self.xi.n_points() {
            self.eta.solve_line(ctrl, j, ncx);
        }
        for i in 0..self.eta.n_ctrl() {
            self.xi.solve_line(ctrl, i * ncx, 1);
        }
    }

    /// The weights of the grid points (row-major `n_eta x n_xi`) in the interpolated surface's
    /// value at `(eta, xi)`: `S(eta, xi) = Σ_ij w_ij Q_ij` for every grid `Q`. The two passes
    /// are separable, so `w_ij = w_i(eta) w_j(xi)` ([`CurveInterpolator::data_weights`]).
    /// Allocates: set-up time.
    pub fn data_weights(&self, eta: f64, xi: f64) -> Result<Vec<f64>, NurbsError> {
        let (we, wx) = (self.eta.data_weights(eta)?, self.xi.data_weights(xi)?);
        Ok(we
            .iter()
            .flat_map(|a| wx.iter().map(move |b| a * b))
            .collect())
    }

    /// A new (non-rational) surface through the grid (allocates; set-up time).
    pub fn interpolate(&self, grid: &[Vector3<f64>]) -> Result<NurbsSurface, NurbsError> {
        let n = self.n_ctrl();
        let mut ctrl = vec![Vector3::zeros(); n];
        self.control_points_into(grid, &mut ctrl)?;
        let eta = self.eta.knot_vector().clone();
        let xi = self.xi.knot_vector().clone();
        NurbsSurface::new(eta, xi, &ctrl, &vec![1.0; n])
    }

    /// Re-interpolates `surface` (built by [`SurfaceInterpolator::interpolate`]) through a new
    /// grid in place, allocation-free.
    pub fn update_surface(
        &self,
        grid: &[Vector3<f64>],
        surface: &mut NurbsSurface,
    ) -> Result<(), NurbsError> {
        let (ne, nx) = (self.eta.n_points(), self.xi.n_points());
        size_check("grid points", ne * nx, grid.len())?;
        size_check(
            "surface control points",
            self.n_ctrl(),
            surface.control_points_w().len(),
        )?;
        let ncx = self.xi.n_ctrl();
        let ctrl = surface.control_points_w_mut();
        for i in 0..ne {
            for j in 0..nx {
                ctrl[i * ncx + j] = grid[i * nx + j].push(1.0);
            }
        }
        self.solve_in_place(ctrl);
        ctrl.iter_mut().for_each(|c| c.w = 1.0);
        Ok(())
    }
}

fn size_check(what: &'static str, expected: usize, got: usize) -> Result<(), NurbsError> {
    if expected == got {
        Ok(())
    } else {
        Err(NurbsError::SizeMismatch {
            what,
            expected,
            got,
        })
    }
}

/// Parameters finite and strictly increasing; closed ones inside one period `[0, 1)`.
fn check_parameters(params: &[f64], closed: bool) -> Result<(), NurbsError> {
    for (i, u) in params.iter().enumerate() {
        if !u.is_finite() {
            return Err(NurbsError::NonFiniteValue {
                what: "parameter",
                index: i,
            });
        }
        if i > 0 && params[i - 1] >= *u {
            return Err(NurbsError::ParametersNotIncreasing { index: i });
        }
    }
    if closed && (params[0] < 0.0 || params[params.len() - 1] >= 1.0) {
        return Err(NurbsError::ParametersNotIncreasing { index: 0 });
    }
    Ok(())
}
