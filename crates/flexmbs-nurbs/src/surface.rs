//! Tensor-product NURBS surfaces (seed 000 (3.23); NURBS Book A3.6, A4.4).

use crate::basis::{BasisScratch, KnotVector};
use crate::curve::{check_wrapped, homogeneous};
use crate::error::NurbsError;
use crate::MAX_DERIVATIVE;
use nalgebra::{Vector3, Vector4};

/// A NURBS surface `S(eta, xi) = H{ sum_i sum_j N_{i,p}(eta) N_{j,q}(xi) P_ij^w }` (3.23).
///
/// Control points are stored row-major: `P_ij` at `i * n_xi + j`, `i` along `eta`, `j` along `xi`.
#[derive(Debug, Clone, PartialEq)]
pub struct NurbsSurface {
    eta: KnotVector,
    xi: KnotVector,
    ctrl_w: Vec<Vector4<f64>>,
}

/// Scratch of surface evaluation; create once per surface with [`NurbsSurface::scratch`].
#[derive(Debug, Clone)]
pub struct SurfaceScratch {
    pub(crate) eta: BasisScratch,
    pub(crate) xi: BasisScratch,
    temp: Vec<Vector4<f64>>,
}

impl SurfaceScratch {
    /// Scratch for degrees `[p, q]`.
    pub(crate) fn new(p: usize, q: usize) -> Self {
        Self {
            eta: BasisScratch::new(p),
            xi: BasisScratch::new(q),
            temp: vec![Vector4::zeros(); (MAX_DERIVATIVE + 1) * (q + 1)],
        }
    }
}

/// Point and partial derivatives up to order two of a surface at one parameter pair.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfaceDerivs {
    /// `S`.
    pub s: Vector3<f64>,
    /// `S_eta` (tangent `t_eta` (3.25)).
    pub s_u: Vector3<f64>,
    /// `S_xi` (tangent `t_xi` (3.26)).
    pub s_v: Vector3<f64>,
    /// `S_eta,eta`.
    pub s_uu: Vector3<f64>,
    /// `S_eta,xi`.
    pub s_uv: Vector3<f64>,
    /// `S_xi,xi`.
    pub s_vv: Vector3<f64>,
}

impl SurfaceDerivs {
    /// Unit normal `n = t_eta x t_xi / |t_eta x t_xi|` (3.27); zero where the tangents are parallel.
    pub fn normal(&self) -> Vector3<f64> {
        let n = self.s_u.cross(&self.s_v);
        let len = n.norm();
        if len > 0.0 {
            n / len
        } else {
            Vector3::zeros()
        }
    }
}

impl NurbsSurface {
    /// Surface from two knot vectors (open or periodic, see [`KnotVector`]) and row-major
    /// Cartesian control points with weights (> 0); sizes must match the knot vectors.
    pub fn new(
        eta: KnotVector,
        xi: KnotVector,
        points: &[Vector3<f64>],
        weights: &[f64],
    ) -> Result<Self, NurbsError> {
        let n = eta.n_ctrl() * xi.n_ctrl();
        if points.len() != n {
            return Err(NurbsError::SizeMismatch {
                what: "control points",
                expected: n,
                got: points.len(),
            });
        }
        if weights.len() != n {
            return Err(NurbsError::SizeMismatch {
                what: "weights",
                expected: n,
                got: weights.len(),
            });
        }
        let ctrl_w = points
            .iter()
            .zip(weights)
            .enumerate()
            .map(|(i, (p, &w))| homogeneous(i, p, w))
            .collect::<Result<Vec<_>, _>>()?;
        let (ne, nx) = (eta.n_ctrl(), xi.n_ctrl());
        if eta.is_periodic() {
            for j in 0..nx {
                check_wrapped(&ctrl_w, ne, eta.degree(), |i| i * nx + j)?;
            }
        }
        if xi.is_periodic() {
            for i in 0..ne {
                check_wrapped(&ctrl_w, nx, xi.degree(), |j| i * nx + j)?;
            }
        }
        Ok(Self { eta, xi, ctrl_w })
    }

    /// Knot vector along `eta`.
    pub fn eta_knots(&self) -> &KnotVector {
        &self.eta
    }
    /// Knot vector along `xi`.
    pub fn xi_knots(&self) -> &KnotVector {
        &self.xi
    }
    /// Homogeneous control points, row-major (`i * n_xi + j`).
    pub fn control_points_w(&self) -> &[Vector4<f64>] {
        &self.ctrl_w
    }
    /// Mutable homogeneous control points (for in-place re-interpolation).
    pub(crate) fn control_points_w_mut(&mut self) -> &mut [Vector4<f64>] {
        &mut self.ctrl_w
    }
    /// Scratch for evaluation (allocates; create once). Evaluation with the scratch of a
    /// surface of other degrees panics.
    pub fn scratch(&self) -> SurfaceScratch {
        SurfaceScratch::new(self.eta.degree(), self.xi.degree())
    }

    /// Replaces the Cartesian control points (row-major), keeping the weights; allocation-free.
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

    /// Point `S(eta, xi)` (3.23); parameters clamped (open) or wrapped (periodic).
    pub fn point(&self, eta: f64, xi: f64, scratch: &mut SurfaceScratch) -> Vector3<f64> {
        self.derivs_nd(eta, xi, 0, [false; 2], scratch).s
    }

    /// Point and all partial derivatives up to order two (NURBS Book A3.6 on the homogeneous
    /// net, then the rational derivatives A4.4).
    pub fn derivatives(&self, eta: f64, xi: f64, scratch: &mut SurfaceScratch) -> SurfaceDerivs {
        self.derivs_nd(eta, xi, 2, [false; 2], scratch)
    }

    /// As [`NurbsSurface::derivatives`], one-sided from the left in the directions flagged in
    /// `left` (`[eta, xi]`): limits at knots and, for periodic directions, across the seam.
    pub fn derivatives_left(
        &self,
        eta: f64,
        xi: f64,
        left: [bool; 2],
        scratch: &mut SurfaceScratch,
    ) -> SurfaceDerivs {
        self.derivs_nd(eta, xi, 2, left, scratch)
    }

    fn derivs_nd(
        &self,
        eta: f64,
        xi: f64,
        nd: usize,
        left: [bool; 2],
        s: &mut SurfaceScratch,
    ) -> SurfaceDerivs {
        let (p, q, nx) = (self.eta.degree(), self.xi.degree(), self.xi.n_ctrl());
        let su = self.eta.basis_derivatives(eta, nd, left[0], &mut s.eta);
        let sv = self.xi.basis_derivatives(xi, nd, left[1], &mut s.xi);
        // temp[k][s] = sum_r N^(k)_r(eta) P^w_(r, s) over the (p+1) x (q+1) active net, one pass
        let q1 = q + 1;
        let temp = &mut s.temp[..(nd + 1) * q1];
        temp.iter_mut().for_each(|t| *t = Vector4::zeros());
        for r in 0..=p {
            let start = (su - p + r) * nx + sv - q;
            let row = &self.ctrl_w[start..start + q1];
            for k in 0..=nd {
                let n = s.eta.der(k, r);
                for (t, c) in temp[k * q1..(k + 1) * q1].iter_mut().zip(row) {
                    *t += c * n;
                }
            }
        }
        // a[k][l]: homogeneous partial derivative d^(k+l) S^w / d eta^k d xi^l
        let mut a = [[Vector4::zeros(); 3]; 3];
        for (k, ak) in a.iter_mut().enumerate().take(nd + 1) {
            for (l, akl) in ak.iter_mut().enumerate().take(nd - k + 1) {
                let tk = &temp[k * q1..(k + 1) * q1];
                *akl = tk
                    .iter()
                    .enumerate()
                    .fold(Vector4::zeros(), |v, (j, t)| v + t * s.xi.der(l, j));
            }
        }
        rational_surface_derivatives(&a)
    }
}

/// Cartesian partials of `S = A / w` from homogeneous partials (NURBS Book (4.20), A4.4).
fn rational_surface_derivatives(a: &[[Vector4<f64>; 3]; 3]) -> SurfaceDerivs {
    let w = a[0][0].w;
    let (w10, w01, w20, w11, w02) = (a[1][0].w, a[0][1].w, a[2][0].w, a[1][1].w, a[0][2].w);
    let s = a[0][0].xyz() / w;
    let s_u = (a[1][0].xyz() - s * w10) / w;
    let s_v = (a[0][1].xyz() - s * w01) / w;
    let s_uu = (a[2][0].xyz() - s_u * (2.0 * w10) - s * w20) / w;
    let s_vv = (a[0][2].xyz() - s_v * (2.0 * w01) - s * w02) / w;
    let s_uv = (a[1][1].xyz() - s * w11 - s_v * w10 - s_u * w01) / w;
    SurfaceDerivs {
        s,
        s_u,
        s_v,
        s_uu,
        s_uv,
        s_vv,
    }
}
