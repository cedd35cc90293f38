//! The mode-shape matrix `Φ(eta, xi)` of a neutral contour at one contour point from **one**
//! evaluation of the B-spline basis (seed 000 §3.2.2): every mode's control net was interpolated
//! with the same basis, so `Φ_k(eta, xi) = Σ_rs N_r(eta) N_s(xi) C_k,rs` for all `k` is one
//! weighted sum over the `(p+1)(q+1)` active control points of the mode nets stored control
//! point by control point (`n_f` vectors contiguous), instead of one basis evaluation per mode.
//! The sums run in the order of [`flexmbs_nurbs::SurfaceInterpolator::field_derivatives`]
//! (`r`, then `s`, skipping zero `eta` functions), so the values are the same to the last bit.
//! The deformed net `C_0 + Σ_k q_f,k C_k` is one matrix-vector product (faer's SIMD kernel) with
//! the mode nets as the columns of a `3 n_ctrl x n_f` matrix: the same sum, rounded differently
//! (fused multiply-adds), at a fraction of the instructions of a loop over `Vector3`.

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
    /// `Φ_k'` (the derivative by `eta`) at the last point of a **curve** contour, from the same
    /// basis evaluation (a 1D guide's rates need it; unused, zero, for surfaces).
    pub(super) phi1: Vec<Vector3<f64>>,
    /// The deformed net as `3 n_ctrl` numbers.
    net_flat: Vec<f64>,
    /// The point `(eta, xi)` (bits) that `phi` belongs to (`Φ` depends on the point only, not
    /// on the state: the contact point's kinematics and its Jacobian share one evaluation).
    at: Option<[u64; 2]>,
}

impl ModeShapes {
    /// Buffers for degrees `[p, q]`, `nf` modes and `n_ctrl` control points (allocates;
    /// create once).
    pub(super) fn new(degrees: [usize; 2], nf: usize, n_ctrl: usize) -> Self {
        Self {
            basis: [BasisScratch::new(degrees[0]), BasisScratch::new(degrees[1])],
            phi: vec![Vector3::zeros(); nf],
            phi1: vec![Vector3::zeros(); nf],
            net_flat: vec![0.0; 3 * n_ctrl],
            at: None,
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

    /// `out = C_0 + Σ q_f,k C_k` (module documentation; `shapes` lends its flat buffer).
    /// O(n_ctrl n_f), no allocation.
    pub(super) fn deformed_into(
        &self,
        qf: &[f64],
        shapes: &mut ModeShapes,
        out: &mut [Vector3<f64>],
    ) {
        let (rows, nf) = (3 * self.net0.len(), self.modes.len());
        let flat = &mut shapes.net_flat[..rows];
        for (f, c) in flat.chunks_exact_mut(3).zip(&self.net0) {
            f.copy_from_slice(c.as_slice());
        }
        if nf > 0 {
            let lhs = faer::MatRef::from_column_major_slice(&self.flat, rows, nf);
            let rhs = faer::MatRef::from_column_major_slice(&qf[..nf], nf, 1);
            let dst = faer::MatMut::from_column_major_slice_mut(flat, rows, 1);
            faer::linalg::matmul::matmul(dst, faer::Accum::Add, lhs, rhs, 1.0, faer::Par::Seq);
        }
        for (c, f) in out.iter_mut().zip(flat.chunks_exact(3)) {
            *c = Vector3::new(f[0], f[1], f[2]);
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
        let at = Some([eta.to_bits(), xi.to_bits()]);
        if shapes.at == at {
            return Ok(());
        }
        shapes.at = None;
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
        shapes.at = at;
        Ok(())
    }

    /// `Φ(eta)` of a curve contour into `shapes.phi`, and `Φ'(eta)` into `shapes.phi1` (each
    /// in the order of [`CurveInterpolator::field_derivatives`]: bitwise its values).
    pub(super) fn curve_shapes(
        &self,
        interp: &CurveInterpolator,
        eta: f64,
        shapes: &mut ModeShapes,
    ) -> Result<(), NurbsError> {
        let at = Some([eta.to_bits(), u64::MAX]);
        if shapes.at == at {
            return Ok(());
        }
        shapes.at = None;
        let kv = interp.knot_vector();
        let be = &mut shapes.basis[0];
        check_degree(be, kv.degree())?;
        let (p, nf) = (kv.degree(), self.modes.len());
        let span = kv.basis_derivatives(eta, 2, false, be);
        shapes.phi.fill(Vector3::zeros());
        shapes.phi1.fill(Vector3::zeros());
        for j in 0..=p {
            let c = span - p + j;
            let (w, w1) = (be.der(0, j), be.der(1, j));
            let row = &self.by_ctrl[c * nf..(c + 1) * nf];
            for ((o, o1), m) in shapes.phi.iter_mut().zip(&mut shapes.phi1).zip(row) {
                *o += m * w;
                *o1 += m * w1;
            }
        }
        shapes.at = at;
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
        let flat = modes
            .iter()
            .flatten()
            .flat_map(|v| v.iter().copied())
            .collect();
        ModalNets {
            net0: net(0),
            modes,
            by_ctrl,
            flat,
            velocities: 6 + nf,
        }
    }

    /// `Φ` of one basis evaluation equals every mode's own field evaluation bit for bit (open
    /// and closed surfaces and curves, points inside spans and on knots), and the deformed net
    /// equals the mode-by-mode superposition to round-off (`4 n_f eps` of its terms' size).
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
            let mut shapes = ModeShapes::new([3, 3], nf, ip.n_ctrl().max(ne + 3));
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
                    let f = ic.field_derivatives(net, eta, &mut sc).unwrap();
                    assert_eq!(
                        f[0].map(f64::to_bits),
                        shapes.phi[k].map(f64::to_bits),
                        "mode {k}"
                    );
                    assert_eq!(
                        f[1].map(f64::to_bits),
                        shapes.phi1[k].map(f64::to_bits),
                        "slope of mode {k}"
                    );
                }
            }
            let qf = [0.3, -1.2, 0.05, 2.0, -0.7];
            let mut fast = n.net0.clone();
            n.deformed_into(&qf, &mut shapes, &mut fast);
            let mut slow = n.net0.clone();
            for (net, q) in n.modes.iter().zip(&qf) {
                for (c, m) in slow.iter_mut().zip(net) {
                    *c += m * *q;
                }
            }
            let size = |c: usize| {
                n.net0[c].amax()
                    + n.modes
                        .iter()
                        .zip(&qf)
                        .map(|(m, q)| m[c].amax() * q.abs())
                        .sum::<f64>()
            };
            for (c, (a, b)) in fast.iter().zip(&slow).enumerate() {
                let tol = 4.0 * nf as f64 * f64::EPSILON * size(c);
                assert!((a - b).amax() <= tol, "control point {c}: {a} vs {b}");
            }
        }
    }
}
