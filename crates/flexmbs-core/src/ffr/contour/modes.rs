//! The mode-shape matrix `Φ(eta, xi)` of a neutral contour at one contour point from **one**
//! evaluation of the B-spline basis (seed 000 §3.2.2): every mode's control net was interpolated
//! with the same basis, so `Φ_k(eta, xi) = Σ_rs N_r(eta) N_s(xi) C_k,rs` for all `k` is one
//! weighted sum over the `(p+1)(q+1)` active control points of the mode nets stored control
//! point by control point (`n_f` vectors contiguous), instead of one basis evaluation per mode.
//! The sums run in the order of [`flexmbs_nurbs::SurfaceInterpolator::field_derivatives`]
//! (`r`, then `s`, skipping zero `eta` functions), so the values are the same to the last bit.
//! The same layout makes the deformed net `C_0 + Σ_k q_f,k C_k` one contiguous pass.

use super::ModalNets;
use flexmbs_nurbs::{BasisScratch, CurveInterpolator, NurbsError, SurfaceInterpolator};
use nalgebra::Vector3;

/// Basis scratch and the evaluated `Φ` of a contour point (one per contour state).
#[derive(Debug, Clone)]
pub(super) struct ModeShapes {
    /// Basis functions in `eta` and `xi` (a curve uses the first).
    basis: [BasisScratch; 2],
    /// `Φ_k` at the last point, `k = 0 .. n_f` (body axes).
    pub(super) phi: Vec<Vector3<f64>>,
}

impl ModeShapes {
    /// Buffers for degrees `[p, q]` and `nf` modes (allocates; create once).
    pub(super) fn new(degrees: [usize; 2], nf: usize) -> Self {
        Self {
            basis: [BasisScratch::new(degrees[0]), BasisScratch::new(degrees[1])],
            phi: vec![Vector3::zeros(); nf],
        }
    }
}

impl ModalNets {
    /// The mode nets control point by control point: `out[c n_f + k] = C_k,c`.
    pub(super) fn by_control_point(
        modes: &[Vec<Vector3<f64>>],
        n_ctrl: usize,
    ) -> Vec<Vector3<f64>> {
        let nf = modes.len();
        (0..n_ctrl * nf).map(|i| modes[i % nf][i / nf]).collect()
    }

    /// `out = C_0 + Σ q_f,k C_k` (additions in the order of `k`). O(n_ctrl n_f), no allocation.
    pub(super) fn deformed_into(&self, qf: &[f64], out: &mut [Vector3<f64>]) {
        let nf = self.modes.len();
        for ((c, c0), row) in out
            .iter_mut()
            .zip(&self.net0)
            .zip(self.by_ctrl.chunks_exact(nf))
        {
            let mut v = *c0;
            for (m, q) in row.iter().zip(qf) {
                v += m * *q;
            }
            *c = v;
        }
    }

    /// `Φ(eta, xi)` of a surface contour into `shapes.phi` (module documentation).
    pub(super) fn surface_shapes(
        &self,
        interp: &SurfaceInterpolator,
        eta: f64,
        xi: f64,
        shapes: &mut ModeShapes,
    ) -> Result<(), NurbsError> {
        let (ke, kx) = (interp.eta().knot_vector(), interp.xi().knot_vector());
        let [be, bx] = &mut shapes.basis;
        check_degree(be, ke.degree())?;
        check_degree(bx, kx.degree())?;
        let (p, q, nx, nf) = (ke.degree(), kx.degree(), kx.n_ctrl(), self.modes.len());
        let su = ke.basis_derivatives(eta, 2, false, be);
        let sv = kx.basis_derivatives(xi, 2, false, bx);
        shapes.phi.fill(Vector3::zeros());
        for r in 0..=p {
            let nu = be.der(0, r);
            if nu == 0.0 {
                continue;
            }
            for s in 0..=q {
                let c = (su - p + r) * nx + sv - q + s;
                let w = nu * bx.der(0, s);
                let row = &self.by_ctrl[c * nf..(c + 1) * nf];
                for (o, m) in shapes.phi.iter_mut().zip(row) {
                    *o += m * w;
                }
            }
        }
        Ok(())
    }

    /// `Φ(eta)` of a curve contour into `shapes.phi`.
    pub(super) fn curve_shapes(
        &self,
        interp: &CurveInterpolator,
        eta: f64,
        shapes: &mut ModeShapes,
    ) -> Result<(), NurbsError> {
        let kv = interp.knot_vector();
        let be = &mut shapes.basis[0];
        check_degree(be, kv.degree())?;
        let (p, nf) = (kv.degree(), self.modes.len());
        let span = kv.basis_derivatives(eta, 2, false, be);
        shapes.phi.fill(Vector3::zeros());
        for j in 0..=p {
            let c = span - p + j;
            let w = be.der(0, j);
            for (o, m) in shapes
                .phi
                .iter_mut()
                .zip(&self.by_ctrl[c * nf..(c + 1) * nf])
            {
                *o += m * w;
            }
        }
        Ok(())
    }
}

fn check_degree(scratch: &BasisScratch, degree: usize) -> Result<(), NurbsError> {
    if scratch.degree() == degree {
        Ok(())
    } else {
        Err(NurbsError::SizeMismatch {
            what: "scratch degree",
            expected: degree,
            got: scratch.degree(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbs_nurbs::ParamMethod;

    /// Pseudo-random control nets of `nf` modes with `n_ctrl` points.
    fn nets(n_ctrl: usize, nf: usize) -> ModalNets {
        let v = |i: usize| ((i * 37 % 101) as f64 / 50.0 - 1.0) * (1.0 + (i % 7) as f64);
        let net = |k: usize| {
            (0..n_ctrl)
                .map(|c| Vector3::new(v(3 * c + k), v(3 * c + k + 1) - 0.3, v(7 * c + 2 * k)))
                .collect::<Vec<_>>()
        };
        let modes: Vec<_> = (1..=nf).map(net).collect();
        let by_ctrl = ModalNets::by_control_point(&modes, n_ctrl);
        ModalNets {
            net0: net(0),
            modes,
            by_ctrl,
        }
    }

    /// `Φ` of one basis evaluation equals every mode's own field evaluation bit for bit (open
    /// and closed surfaces and curves, points inside spans and on knots), and the deformed net
    /// equals the mode-by-mode superposition bit for bit.
    #[test]
    fn shapes_equal_per_mode_fields_bitwise() {
        let nf = 5;
        for closed in [[false, false], [true, false]] {
            let (ne, nx) = (7, 5);
            let grid: Vec<Vector3<f64>> = (0..ne * nx)
                .map(|n| {
                    let (i, j) = ((n / nx) as f64, (n % nx) as f64);
                    let a = std::f64::consts::TAU * i / ne as f64;
                    Vector3::new(a.cos(), a.sin(), 0.3 * j + 0.01 * i * j)
                })
                .collect();
            let ip = SurfaceInterpolator::from_grid(
                &grid,
                ne,
                nx,
                ParamMethod::ChordLength,
                [3, 3],
                closed,
            )
            .unwrap();
            let n = nets(ip.n_ctrl(), nf);
            let mut shapes = ModeShapes::new([3, 3], nf);
            let mut sc = ip.scratch();
            let (e, x) = (ip.eta().params().to_vec(), ip.xi().params().to_vec());
            for (eta, xi) in [
                (0.37 * e[ne - 1], 0.61 * x[nx - 1]),
                (e[2], x[1]),
                (e[0], x[nx - 1]),
            ] {
                n.surface_shapes(&ip, eta, xi, &mut shapes).unwrap();
                for (k, net) in n.modes.iter().enumerate() {
                    let f = ip.field_derivatives(net, eta, xi, &mut sc).unwrap()[0];
                    assert_eq!(
                        f.map(f64::to_bits),
                        shapes.phi[k].map(f64::to_bits),
                        "mode {k}"
                    );
                }
            }
            let curve: Vec<Vector3<f64>> = grid[..ne * nx].iter().step_by(nx).copied().collect();
            let ic = CurveInterpolator::from_points(&curve, ParamMethod::ChordLength, 3, closed[0])
                .unwrap();
            let n = nets(ic.n_ctrl(), nf);
            let mut sc = ic.scratch();
            for &eta in &[0.0, ic.params()[3], 0.77 * ic.params()[ne - 1]] {
                n.curve_shapes(&ic, eta, &mut shapes).unwrap();
                for (k, net) in n.modes.iter().enumerate() {
                    let f = ic.field_derivatives(net, eta, &mut sc).unwrap()[0];
                    assert_eq!(
                        f.map(f64::to_bits),
                        shapes.phi[k].map(f64::to_bits),
                        "mode {k}"
                    );
                }
            }
            let qf = [0.3, -1.2, 0.05, 2.0, -0.7];
            let mut fast = n.net0.clone();
            n.deformed_into(&qf, &mut fast);
            let mut slow = n.net0.clone();
            for (net, q) in n.modes.iter().zip(&qf) {
                for (c, m) in slow.iter_mut().zip(net) {
                    *c += m * *q;
                }
            }
            let bits =
                |v: &[Vector3<f64>]| v.iter().map(|p| p.map(f64::to_bits)).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&slow));
        }
    }
}
