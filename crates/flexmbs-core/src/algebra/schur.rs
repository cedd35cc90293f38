//! Cholesky factorization of a mass block whose trailing `n_c x n_c` block is constant (an FFR
//! body's modal mass `m_ff` (2.69), seed 000; [`crate::Element::constant_mass_tail`]), through
//! the Schur complement of that block. With the coordinates split into the varying leading ones
//! `v` (the floating frame's `R`, `theta`) and the constant trailing ones `c` (the modal ones),
//!
//! ```text
//!     M = [M_vv  M_vc]  =  [L_s  Xᵀ ] [L_sᵀ  0  ]     L_c L_cᵀ = M_cc            (once)
//!         [M_cv  M_cc]     [0    L_c] [X     L_cᵀ],   X = L_c⁻¹ M_cv             (n_v solves)
//!                                                      L_s L_sᵀ = M_vv - Xᵀ X   (n_v x n_v)
//! ```
//!
//! (the Cholesky factorization of `M` with the constant block ordered first), so a new state
//! costs `n_v` forward substitutions with the constant `L_c` (`O(n_v n_c^2)`) and an
//! `n_v x n_v` Cholesky instead of the `O(n^3 / 3)` of a full factorization: at 100 modes
//! 6 x 100^2 / 2 against 106^3 / 3 multiply-adds. A solve costs what a full Cholesky solve costs.
//! The constant block is compared bitwise with the factored one at every update and refactored
//! if it changed (the element's declaration is checked, not trusted).

use crate::linsolve::cholesky_factor;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// The factors `L_c`, `X`, `L_s` of a block with a constant trailing block (module
/// documentation). No allocation after [`SchurMass::new`].
#[derive(Debug)]
pub(super) struct SchurMass {
    /// Leading (varying) coordinates `n_v`.
    nv: usize,
    /// The constant block `M_cc` that `l_c` belongs to (NaN: none yet).
    m_cc: Mat<f64>,
    /// Lower Cholesky factor of `M_cc`.
    l_c: Mat<f64>,
    /// `X = L_c⁻¹ M_cv` (`n_c x n_v`).
    x: Mat<f64>,
    /// Lower Cholesky factor of the Schur complement `M_vv - Xᵀ X`.
    l_s: Mat<f64>,
    /// Factorizations of the constant block so far.
    constant_factorizations: usize,
}

#[cfg(test)]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
/// Column `j` of a column-major matrix as a slice.
fn col(m: &Mat<f64>, j: usize) -> &[f64] {
    m.col_as_slice(j)
}

#[cfg(test)]
/// `L y = b` in place (`l` lower triangular, column-oriented).
fn forward_substitute(l: &Mat<f64>, b: &mut [f64]) {
    for j in 0..b.len() {
        let c = col(l, j);
        let xj = b[j] / c[j];
        b[j] = xj;
        if xj != 0.0 {
            for (bi, lij) in b[j + 1..].iter_mut().zip(&c[j + 1..]) {
                *bi -= lij * xj;
            }
        }
    }
}

/// `Lᵀ x = b` in place (`l` lower triangular, row of `Lᵀ` = column of `L`).
#[cfg(test)]
fn back_substitute(l: &Mat<f64>, b: &mut [f64]) {
    for j in (0..b.len()).rev() {
        let c = col(l, j);
        let s = b[j] - dot(&b[j + 1..], &c[j + 1..]);
        b[j] = s / c[j];
    }
}

impl SchurMass {
    /// Buffers for an `n x n` block whose last `nc` coordinates have a constant mass block.
    pub(super) fn new(n: usize, nc: usize) -> Self {
        let nv = n - nc;
        Self {
            nv,
            m_cc: Mat::from_fn(nc, nc, |_, _| f64::NAN),
            l_c: Mat::zeros(nc, nc),
            x: Mat::zeros(nc, nv),
            l_s: Mat::zeros(nv, nv),
            constant_factorizations: 0,
        }
    }

    /// Factorizations of the constant block so far (1 when it stayed constant).
    pub(super) fn constant_factorizations(&self) -> usize {
        self.constant_factorizations
    }

    /// Factors the symmetric block `m` (both triangles filled). `Err(())` if it is not
    /// numerically positive definite.
    pub(super) fn factor(&mut self, m: MatRef<'_, f64>) -> Result<(), ()> {
        let (nv, nc) = (self.nv, self.m_cc.nrows());
        let m_cc = m.submatrix(nv, nv, nc, nc);
        // column by column through slices (an indexed comparison costs 10^4 bounds-checked
        // element accesses per update at 100 modes)
        let same = (0..nc).all(|j| {
            let b = self.m_cc.col_as_slice(j);
            match m_cc.col(j).try_as_col_major() {
                Some(a) => a
                    .as_slice()
                    .iter()
                    .zip(b)
                    .all(|(x, y)| x.to_bits() == y.to_bits()),
                None => (0..nc).all(|i| m_cc[(i, j)].to_bits() == b[i].to_bits()),
            }
        });
        if !same {
            self.m_cc.copy_from(m_cc);
            self.l_c.copy_from(m_cc);
            self.constant_factorizations += 1;
            if cholesky_factor(self.l_c.as_mut(), 0.0).is_err() {
                self.m_cc.fill(f64::NAN);
                return Err(());
            }
        }
        // X = L_c^-1 M_cv (all columns at once), the Schur complement M_vv - X^T X, its factor
        self.x.copy_from(m.submatrix(nv, 0, nc, nv));
        solve_lower_triangular_in_place(self.l_c.as_ref(), self.x.as_mut(), Par::Seq);
        self.l_s.copy_from(m.submatrix(0, 0, nv, nv));
        let x = self.x.as_ref();
        matmul(
            self.l_s.as_mut(),
            Accum::Add,
            x.transpose(),
            x,
            -1.0,
            Par::Seq,
        );
        cholesky_factor(self.l_s.as_mut(), 0.0).map_err(|_| ())
    }

    /// Solves `M z = b` in place with the last factors, one column by scalar loops (the
    /// reference of the tests; `b`: the block's `n` entries, varying ones first): `y_c = L_c⁻¹ b_c`, `y_v = L_s⁻¹ (b_v - Xᵀ y_c)`, `z_v = L_s⁻ᵀ y_v`,
    /// `z_c = L_c⁻ᵀ (y_c - X z_v)`.
    #[cfg(test)]
    pub(super) fn solve_in_place(&self, b: &mut [f64]) {
        let (bv, bc) = b.split_at_mut(self.nv);
        forward_substitute(&self.l_c, bc);
        for (i, v) in bv.iter_mut().enumerate() {
            *v -= dot(col(&self.x, i), bc);
        }
        forward_substitute(&self.l_s, bv);
        back_substitute(&self.l_s, bv);
        for (j, &zj) in bv.iter().enumerate() {
            if zj != 0.0 {
                for (c, xij) in bc.iter_mut().zip(col(&self.x, j)) {
                    *c -= xij * zj;
                }
            }
        }
        back_substitute(&self.l_c, bc);
    }

    /// As [`Self::solve_in_place`] for the `k` columns of `b` (`n x k`) at once, with faer's
    /// SIMD triangular solves and products (the same operations, rounded differently).
    pub(super) fn solve_columns_in_place(&self, b: MatMut<'_, f64>) {
        let (mut bv, mut bc) = b.split_at_row_mut(self.nv);
        solve_lower_triangular_in_place(self.l_c.as_ref(), bc.as_mut(), Par::Seq);
        let x = self.x.as_ref();
        matmul(
            bv.as_mut(),
            Accum::Add,
            x.transpose(),
            bc.as_ref(),
            -1.0,
            Par::Seq,
        );
        solve_lower_triangular_in_place(self.l_s.as_ref(), bv.as_mut(), Par::Seq);
        solve_upper_triangular_in_place(self.l_s.transpose(), bv.as_mut(), Par::Seq);
        matmul(bc.as_mut(), Accum::Add, x, bv.as_ref(), -1.0, Par::Seq);
        solve_upper_triangular_in_place(self.l_c.transpose(), bc, Par::Seq);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linsolve::DenseLu;

    /// A symmetric positive definite `n x n` matrix `B Bᵀ + n 1` with entries from `seed`.
    fn spd(n: usize, seed: usize) -> Mat<f64> {
        let b = |i: usize, j: usize| (((i * 7 + j * 3 + seed) % 11) as f64 - 5.0) * 0.3;
        Mat::from_fn(n, n, |i, j| {
            (0..n).map(|k| b(i, k) * b(j, k)).sum::<f64>() + if i == j { n as f64 } else { 0.0 }
        })
    }

    /// The Schur solve equals a dense LU solve of the same matrix to round-off (both backward
    /// stable; the matrices are well conditioned), for a constant and a changed trailing block.
    #[test]
    fn schur_solve_equals_dense_lu() {
        let (n, nc) = (9, 6);
        let mut schur = SchurMass::new(n, nc);
        let a = spd(n, 1);
        // the same constant block, the varying block changed (by a positive definite term)
        let mut b = a.clone();
        for i in 0..n - nc {
            b[(i, i)] += 1.0 + i as f64;
        }
        let c = spd(n, 3);
        let rhs: Vec<f64> = (0..n).map(|i| (0.7 * i as f64).cos()).collect();
        for (m, factorizations) in [(&a, 1), (&b, 1), (&c, 2)] {
            schur.factor(m.as_ref()).unwrap();
            assert_eq!(schur.constant_factorizations(), factorizations);
            let mut x = rhs.clone();
            schur.solve_in_place(&mut x);
            // two columns at once: the same solution (to round-off) in each
            let mut two: Vec<f64> = rhs.iter().chain(&rhs).copied().collect();
            schur.solve_columns_in_place(MatMut::from_column_major_slice_mut(&mut two, n, 2));
            for (i, xi) in x.iter().enumerate() {
                for c in 0..2 {
                    assert!((two[c * n + i] - xi).abs() <= 1e-13 * xi.abs().max(1.0));
                }
            }
            let mut lu = DenseLu::new(n);
            lu.a.copy_from(m);
            assert!(lu.factor());
            let mut y = rhs.clone();
            lu.solve_in_place(&mut y);
            for i in 0..n {
                assert!(
                    (x[i] - y[i]).abs() <= 1e-13 * y[i].abs().max(1.0),
                    "{i}: {x:?} {y:?}"
                );
            }
        }
    }

    /// An indefinite Schur complement or constant block is an error, not NaN.
    #[test]
    fn schur_rejects_indefinite_blocks() {
        let (n, nc) = (4, 2);
        let mut m = Mat::from_fn(n, n, |i, j| if i == j { 1.0 } else { 0.0 });
        m[(0, 2)] = 2.0;
        m[(2, 0)] = 2.0;
        assert!(SchurMass::new(n, nc).factor(m.as_ref()).is_err());
        let mut m = Mat::from_fn(n, n, |i, j| if i == j { 1.0 } else { 0.0 });
        m[(3, 3)] = -1.0;
        assert!(SchurMass::new(n, nc).factor(m.as_ref()).is_err());
    }
}
