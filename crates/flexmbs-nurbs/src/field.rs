//! Evaluation of interpolated fields on a contour: any values (positions, velocities, mode shape
//! columns, scalars) whose control net came from an interpolator, evaluated with the B-spline
//! basis of that interpolator (weights 1). Seed 000 §3.2.2: the mode shapes are interpolated once
//! at set-up, and the Jacobian of a contour point is the same combination of their nets.

use crate::basis::BasisScratch;
use crate::curve::CurveScratch;
use crate::error::NurbsError;
use crate::interp::{CurveInterpolator, Interpolant, SurfaceInterpolator};
use crate::surface::SurfaceScratch;

fn net_size_check(expected: usize, got: usize) -> Result<(), NurbsError> {
    if expected == got {
        Ok(())
    } else {
        Err(NurbsError::SizeMismatch {
            what: "control net",
            expected,
            got,
        })
    }
}

fn scratch_check(scratch: &BasisScratch, degree: usize) -> Result<(), NurbsError> {
    net_size_check(degree, scratch.degree()).map_err(|_| NurbsError::SizeMismatch {
        what: "scratch degree",
        expected: degree,
        got: scratch.degree(),
    })
}

impl CurveInterpolator {
    /// Scratch for [`CurveInterpolator::field_derivatives`] (allocates; create once).
    pub fn scratch(&self) -> CurveScratch {
        CurveScratch {
            basis: BasisScratch::new(self.knot_vector().degree()),
        }
    }

    /// Value and first two derivatives `[f, f', f'']` at `u` of the field with control values
    /// `net` (from [`CurveInterpolator::control_points_into`]): `f(u) = sum_i N_{i,p}(u) net_i`.
    /// Allocation-free.
    pub fn field_derivatives<T: Interpolant>(
        &self,
        net: &[T],
        u: f64,
        scratch: &mut CurveScratch,
    ) -> Result<[T; 3], NurbsError> {
        let kv = self.knot_vector();
        net_size_check(kv.n_ctrl(), net.len())?;
        scratch_check(&scratch.basis, kv.degree())?;
        let p = kv.degree();
        let span = kv.basis_derivatives(u, 2, false, &mut scratch.basis);
        let mut out = [net[0] * 0.0; 3];
        for (k, o) in out.iter_mut().enumerate() {
            for j in 0..=p {
                *o += net[span - p + j] * scratch.basis.der(k, j);
            }
        }
        Ok(out)
    }
}

impl SurfaceInterpolator {
    /// Scratch for [`SurfaceInterpolator::field_derivatives`] (allocates; create once).
    pub fn scratch(&self) -> SurfaceScratch {
        let (p, q) = (
            self.eta().knot_vector().degree(),
            self.xi().knot_vector().degree(),
        );
        SurfaceScratch::new(p, q)
    }

    /// Value and partials `[f, f_eta, f_xi, f_eta,eta, f_eta,xi, f_xi,xi]` at `(eta, xi)` of the
    /// field with the control net `net` (row-major, from
    /// [`SurfaceInterpolator::control_points_into`]). Allocation-free.
    pub fn field_derivatives<T: Interpolant>(
        &self,
        net: &[T],
        eta: f64,
        xi: f64,
        scratch: &mut SurfaceScratch,
    ) -> Result<[T; 6], NurbsError> {
        let (ke, kx) = (self.eta().knot_vector(), self.xi().knot_vector());
        net_size_check(self.n_ctrl(), net.len())?;
        scratch_check(&scratch.eta, ke.degree())?;
        scratch_check(&scratch.xi, kx.degree())?;
        let (p, q, nx) = (ke.degree(), kx.degree(), kx.n_ctrl());
        let su = ke.basis_derivatives(eta, 2, false, &mut scratch.eta);
        let sv = kx.basis_derivatives(xi, 2, false, &mut scratch.xi);
        let mut out = [net[0] * 0.0; 6];
        // (k, l) derivative orders in the order of the output
        for (o, (k, l)) in out
            .iter_mut()
            .zip([(0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)])
        {
            for r in 0..=p {
                let nu = scratch.eta.der(k, r);
                if nu == 0.0 {
                    continue;
                }
                for s in 0..=q {
                    *o += net[(su - p + r) * nx + sv - q + s] * (nu * scratch.xi.der(l, s));
                }
            }
        }
        Ok(out)
    }
}
