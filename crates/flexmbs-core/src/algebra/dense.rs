//! Dense backend: the saddle matrix as a full `(nu + nc)^2` array, assembled from the dense
//! system buffers (`sys.mass`, `sys.dh_dq`, `sys.dh_du`, `sys.g_jac`) and factored by
//! [`DenseLu`]. Bitwise the historical path (same operations in the same order).

use super::SaddleKind;
use crate::linsolve::DenseLu;
use crate::model::Model;
use crate::state::SystemBuffers;
use crate::system;
use faer::Mat;

/// Dense saddle matrix and its LU.
#[derive(Debug)]
pub(super) struct DenseSystem {
    /// Matrix and factors.
    pub(super) lu: DenseLu,
}

impl DenseSystem {
    /// Allocates an `n x n` system.
    pub(super) fn new(n: usize) -> Self {
        Self {
            lu: DenseLu::new(n),
        }
    }

    /// Builds the matrix `kind` (see [`super::SystemMatrix::build`]).
    pub(super) fn build(
        &mut self,
        kind: SaddleKind,
        model: &Model,
        q: &[f64],
        u: &[f64],
        lambda: &[f64],
        sys: &mut SystemBuffers,
    ) {
        let a = &mut self.lu.a;
        let nu = model.nu;
        match kind {
            SaddleKind::AugmentedMass => {
                system::assemble_mass(model, q, &mut sys.eval, sys.mass.as_mut(), &mut sys.local);
                for j in 0..nu {
                    for i in 0..nu {
                        a[(i, j)] = sys.mass[(i, j)];
                    }
                }
            }
            SaddleKind::Iteration { t, c_u, c_q } => {
                system::assemble_mass(model, q, &mut sys.eval, sys.mass.as_mut(), &mut sys.local);
                system::assemble_tangents(model, t, q, u, 1.0, sys);
                for j in 0..nu {
                    for i in 0..nu {
                        a[(i, j)] =
                            sys.mass[(i, j)] - c_u * sys.dh_du[(i, j)] - c_q * sys.dh_dq[(i, j)];
                    }
                }
            }
            SaddleKind::LeastSquares => {
                for j in 0..nu {
                    for i in 0..nu {
                        a[(i, j)] = if i == j { 1.0 } else { 0.0 };
                    }
                }
            }
            SaddleKind::StaticTangent { t, mu } => {
                system::assemble_tangents(model, t, q, u, mu, sys);
                system::subtract_constraint_force_tangent(model, t, q, u, lambda, sys);
                for j in 0..nu {
                    for i in 0..nu {
                        a[(i, j)] = -sys.dh_dq[(i, j)];
                    }
                }
            }
        }
        fill_constraint_blocks(a, nu, &sys.g_jac);
    }
}

/// Writes `G` and `G^T` into the border of the saddle matrix `out` and zeroes its `nc x nc`
/// corner (`G`: nc x nu).
fn fill_constraint_blocks(out: &mut Mat<f64>, nu: usize, g: &Mat<f64>) {
    let nc = g.nrows();
    for j in 0..nu {
        for r in 0..nc {
            out[(nu + r, j)] = g[(r, j)];
            out[(j, nu + r)] = g[(r, j)];
        }
    }
    for j in 0..nc {
        for i in 0..nc {
            out[(nu + i, nu + j)] = 0.0;
        }
    }
}

/// [`crate::system::TangentSink`] adding `c_q` times the `d/dq` entries and `c_u` times the
/// `d/du` entries into a dense matrix (the iteration matrix of [`DenseSystem`]).
pub(super) struct MatrixSink<'a> {
    a: &'a mut Mat<f64>,
    c_q: f64,
    c_u: f64,
}

impl<'a> MatrixSink<'a> {
    /// A sink into `a` with the coefficients `c_q`, `c_u`.
    pub(super) fn new(a: &'a mut Mat<f64>, c_q: f64, c_u: f64) -> Self {
        Self { a, c_q, c_u }
    }
}

impl crate::system::TangentSink for MatrixSink<'_> {
    fn add(&mut self, _: &mut SystemBuffers, row: usize, col: usize, velocity: bool, value: f64) {
        let c = if velocity { self.c_u } else { self.c_q };
        self.a[(row, col)] += c * value;
    }
}
