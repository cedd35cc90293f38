//! Rational B-spline (NURBS) curves (seed 000 (3.9)-(3.18); NURBS Book A3.2, A4.2).

use crate::basis::{BasisScratch, KnotVector};
use crate::error::NurbsError;
use nalgebra::{Vector3, Vector4};

/// A NURBS curve `C(u) = H{ sum_i N_{i,p}(u) P_i^w }` (3.16)-(3.17) with homogeneous control
/// points `P^w = (w x, w y, w z, w)` (3.15).
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsCurve {
    knots: KnotVector,
    ctrl_w: Vec<Vector4<f64>>,
}

/// Scratch of curve evaluation; create once per curve with [`NurbsCurve::scratch`].
#[derive(Debug, Clone)]
pub struct CurveScratch {
    pub(crate) basis: BasisScratch,
}

/// Point and first two derivatives of a curve at one parameter.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CurveDerivs {
    /// `C(u)`.
    pub c: Vector3<f64>,
    /// `C'(u)`.
    pub d1: Vector3<f64>,
    /// `C''(u)`.
    pub d2: Vector3<f64>,
}

/// Homogeneous control point `(w P, w)` with validation of the weight and coordinates.
pub(crate) fn homogeneous(
    index: usize,
    p: &Vector3<f64>,
    w: f64,
) -> Result<Vector4<f64>, NurbsError> {
    if !(w.is_finite() && w > 0.0) {
        return Err(NurbsError::NonPositiveWeight { index, weight: w });
    }
    if !p.iter().all(|x| x.is_finite()) {
        return Err(NurbsError::NonFiniteValue {
            what: "control point",
            index,
        });
    }
    Ok(Vector4::new(w * p.x, w * p.y, w * p.z, w))
}

/// Checks that the last `p` of `n` (strided) control points repeat the first `p` (periodic).
pub(crate) fn check_wrapped(
    ctrl: &[Vector4<f64>],
    n: usize,
    p: usize,
    at: impl Fn(usize) -> usize,
) -> Result<(), NurbsError> {
    let k = n - p;
    for j in 0..p {
        let (a, b) = (ctrl[at(j)], ctrl[at(k + j)]);
        if (a - b).norm() > 1e-12 * (1.0 + a.norm()) {
            return Err(NurbsError::NotPeriodic {
                reason: "control points not wrapped",
                index: k + j,
            });
        }
    }
    Ok(())
}

impl NurbsCurve {
    /// Curve of degree `degree` from Cartesian control points, weights (> 0) and an open knot
    /// vector of `points.len() + degree + 1` non-decreasing knots.
    pub fn new(
        degree: usize,
        knots: Vec<f64>,
        points: &[Vector3<f64>],
        weights: &[f64],
    ) -> Result<Self, NurbsError> {
        let ctrl_w = homogeneous_points(points, weights)?;
        let knots = KnotVector::new(degree, knots, points.len())?;
        Ok(Self { knots, ctrl_w })
    }

    /// Closed (periodic) curve: the knots must repeat with the period and the last `degree`
    /// control points must equal the first `degree` (as [`crate::CurveInterpolator`] builds it).
    pub fn new_periodic(
        degree: usize,
        knots: Vec<f64>,
        points: &[Vector3<f64>],
        weights: &[f64],
    ) -> Result<Self, NurbsError> {
        let ctrl_w = homogeneous_points(points, weights)?;
        let knots = KnotVector::periodic(degree, knots, points.len())?;
        check_wrapped(&ctrl_w, points.len(), degree, |i| i)?;
        Ok(Self { knots, ctrl_w })
    }

    /// Curve from an already validated knot vector and homogeneous control points.
    pub fn from_knot_vector(
        knots: KnotVector,
        ctrl_w: Vec<Vector4<f64>>,
    ) -> Result<Self, NurbsError> {
        if ctrl_w.len() != knots.n_ctrl() {
            let (expected, got) = (knots.n_ctrl(), ctrl_w.len());
            return Err(NurbsError::SizeMismatch {
                what: "control points",
                expected,
                got,
            });
        }
        for (i, c) in ctrl_w.iter().enumerate() {
            homogeneous(i, &(c.xyz() / c.w), c.w)?;
        }
        if knots.is_periodic() {
            check_wrapped(&ctrl_w, knots.n_ctrl(), knots.degree(), |i| i)?;
        }
        Ok(Self { knots, ctrl_w })
    }

    /// Degree `p`.
    pub fn degree(&self) -> usize {
        self.knots.degree()
    }
    /// The knot vector.
    pub fn knot_vector(&self) -> &KnotVector {
        &self.knots
    }
    /// Homogeneous control points `(w x, w y, w z, w)`.
    pub fn control_points_w(&self) -> &[Vector4<f64>] {
        &self.ctrl_w
    }
    /// Parameter domain `[U_p, U_n]`.
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }
    /// Whether the curve is closed (periodic).
    pub fn is_periodic(&self) -> bool {
        self.knots.is_periodic()
    }
    /// Scratch for evaluation (allocates; create once).
    pub fn scratch(&self) -> CurveScratch {
        CurveScratch {
            basis: BasisScratch::new(self.degree()),
        }
    }

    /// Replaces the Cartesian control points, keeping the weights (allocation-free; for
    /// periodic curves the caller passes the wrapped set).
    pub fn set_control_points(&mut self, points: &[Vector3<f64>]) -> Result<(), NurbsError> {
        if points.len() != self.ctrl_w.len() {
            let (expected, got) = (self.ctrl_w.len(), points.len());
            return Err(NurbsError::SizeMismatch {
                what: "control points",
                expected,
                got,
            });
        }
        for (c, p) in self.ctrl_w.iter_mut().zip(points) {
            let w = c.w;
            *c = Vector4::new(w * p.x, w * p.y, w * p.z, w);
        }
        Ok(())
    }

    /// Mutable homogeneous control points (for in-place re-interpolation).
    pub(crate) fn control_points_w_mut(&mut self) -> &mut [Vector4<f64>] {
        &mut self.ctrl_w
    }

    /// Point `C(u)` (3.17); `u` is clamped (open) or wrapped (periodic) into the domain.
    pub fn point(&self, u: f64, scratch: &mut CurveScratch) -> Vector3<f64> {
        self.derivs_nd(u, 0, false, scratch).c
    }

    /// Point, first and second derivative at `u` (rational derivatives, NURBS Book A4.2).
    pub fn derivatives(&self, u: f64, scratch: &mut CurveScratch) -> CurveDerivs {
        self.derivs_nd(u, 2, false, scratch)
    }

    /// As [`NurbsCurve::derivatives`], but one-sided from the left at a knot (for a periodic
    /// curve at the domain start: the end of the previous period). Checks continuity at knots.
    pub fn derivatives_left(&self, u: f64, scratch: &mut CurveScratch) -> CurveDerivs {
        self.derivs_nd(u, 2, true, scratch)
    }

    fn derivs_nd(&self, u: f64, nd: usize, left: bool, s: &mut CurveScratch) -> CurveDerivs {
        let p = self.degree();
        let span = self.knots.basis_derivatives(u, nd, left, &mut s.basis);
        let mut a = [Vector4::zeros(); 3];
        for (k, ak) in a.iter_mut().enumerate().take(nd + 1) {
            for j in 0..=p {
                *ak += self.ctrl_w[span - p + j] * s.basis.der(k, j);
            }
        }
        rational_curve_derivatives(&a)
    }
}

/// Cartesian derivatives of `C = A / w` from the homogeneous derivatives `A^(k) = (A, w)^(k)`
/// (NURBS Book (4.8), A4.2): `C' = (A' - w' C)/w`, `C'' = (A'' - 2 w' C' - w'' C)/w`.
pub(crate) fn rational_curve_derivatives(a: &[Vector4<f64>; 3]) -> CurveDerivs {
    let w = a[0].w;
    let c = a[0].xyz() / w;
    let d1 = (a[1].xyz() - c * a[1].w) / w;
    let d2 = (a[2].xyz() - d1 * (2.0 * a[1].w) - c * a[2].w) / w;
    CurveDerivs { c, d1, d2 }
}

fn homogeneous_points(
    points: &[Vector3<f64>],
    weights: &[f64],
) -> Result<Vec<Vector4<f64>>, NurbsError> {
    if weights.len() != points.len() {
        let (expected, got) = (points.len(), weights.len());
        return Err(NurbsError::SizeMismatch {
            what: "weights",
            expected,
            got,
        });
    }
    points
        .iter()
        .zip(weights)
        .enumerate()
        .map(|(i, (p, &w))| homogeneous(i, p, w))
        .collect()
}
