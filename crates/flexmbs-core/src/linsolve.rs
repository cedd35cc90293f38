//! Small dense factorizations: a preallocated LU (faer, partial pivoting) for the dense saddle
//! matrices and an in-place Cholesky for symmetric positive definite blocks (element mass
//! matrices, [`crate::algebra::BlockMass`]).
//!
//! All memory (matrix, permutations, faer scratch stack) is allocated in [`DenseLu::new`];
//! [`DenseLu::factor`], [`DenseLu::solve_in_place`] and the Cholesky functions do not allocate.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::factor;
use faer::{Mat, MatMut, Par};

/// Dense square matrix with an in-place LU factorization.
pub struct DenseLu {
    /// The matrix to factor (overwritten by its LU factors in [`DenseLu::factor`]).
    pub a: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    stack: MemBuffer,
    /// Solution buffer of [`DenseLu::solve_in_place`].
    x: Vec<f64>,
    /// Largest absolute entry of each column of the matrix before [`DenseLu::factor`].
    column_max: Vec<f64>,
}

impl std::fmt::Debug for DenseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DenseLu").field("dim", &self.dim()).finish()
    }
}

impl DenseLu {
    /// Allocates an `n x n` system.
    pub fn new(n: usize) -> Self {
        let req = factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default());
        Self {
            a: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            x: vec![0.0; n],
            stack: MemBuffer::new(req),
            column_max: vec![0.0; n],
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.a.nrows()
    }

    /// Factors `a` in place. Returns `false` if an entry is not finite, or a pivot `u_jj` is not
    /// above `1e-14` times the largest entry of column `j` of `A` (the matrix is then
    /// numerically singular).
    ///
    /// The test is relative to each column (partial pivoting permutes rows only, so column `j`
    /// of `U` comes from column `j` of `A`): it does not change when a column is scaled. A test
    /// against the largest entry of the whole matrix would refuse regular saddle-point systems
    /// of stiff structures, whose multiplier pivots are about `|G|^2 / k` (compliance) while the
    /// largest entry is the stiffness `k` (a superelement frame clamped at two points: pivots
    /// 1e-15 of the largest entry).
    pub fn factor(&mut self) -> bool {
        let n = self.dim();
        if n == 0 {
            return true;
        }
        for j in 0..n {
            let mut cmax = 0.0_f64;
            for &v in self.a.col_as_slice(j) {
                if !v.is_finite() {
                    return false;
                }
                cmax = cmax.max(v.abs());
            }
            self.column_max[j] = cmax;
        }
        factor::lu_in_place(
            self.a.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.stack),
            Default::default(),
        );
        (0..n).all(|j| {
            let p = self.a[(j, j)];
            p.is_finite() && p.abs() > 1e-14 * self.column_max[j]
        })
    }

    /// Solves `A x = b` with the factors of the last [`DenseLu::factor`]; `b` is overwritten by `x`.
    ///
    /// `P A = L U` (faer's convention: `perm[i]` is the row of `A` that became row `i`):
    /// `x = U^-1 L^-1 P b` by column-oriented forward and back substitution on the packed
    /// factors. Hand-written instead of faer's `solve_in_place`, whose dispatch dominated the
    /// cost for the small saddle systems of a time step (n ~ 20-40); the flop count is the same.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let n = self.dim();
        if n == 0 {
            return;
        }
        debug_assert_eq!(b.len(), n, "right-hand side length");
        // y = P b into the solution buffer
        let x = &mut self.x;
        for (xi, &p) in x.iter_mut().zip(&self.perm) {
            *xi = b[p];
        }
        // L y = P b (unit lower triangular), column by column
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                let col = &self.a.col_as_slice(j)[j + 1..n];
                for (xi, l) in x[j + 1..n].iter_mut().zip(col) {
                    *xi -= l * xj;
                }
            }
        }
        // U x = y, column by column from the last
        for j in (0..n).rev() {
            let col = &self.a.col_as_slice(j)[..=j];
            let xj = x[j] / col[j];
            x[j] = xj;
            if xj != 0.0 {
                for (xi, u) in x[..j].iter_mut().zip(&col[..j]) {
                    *xi -= u * xj;
                }
            }
        }
        b.copy_from_slice(x);
    }
}

/// Cholesky factorization `A = L L^T` in place: the lower triangle of `a` becomes `L` (the
/// strict upper triangle is not read and not written). Returns `false` if a pivot is not
/// positive or not finite (the matrix is not numerically positive definite).
pub fn cholesky_in_place(a: &mut Mat<f64>) -> bool {
    cholesky_factor(a.as_mut(), 0.0).is_ok()
}

/// The one dense Cholesky factorization of the engine (element mass blocks, the free FFR body's
/// accelerations): the lower triangle of the square view `a` becomes `L` with `A = L L^T`.
/// `Err((pivot, value))` if a pivot is not finite or not above `min_pivot_rel` times the largest
/// diagonal entry of `A` (0: just positive). No allocation.
pub fn cholesky_factor(mut a: MatMut<'_, f64>, min_pivot_rel: f64) -> Result<(), (usize, f64)> {
    let n = a.nrows();
    let floor = min_pivot_rel * (0..n).map(|i| a[(i, i)].abs()).fold(0.0, f64::max);
    for j in 0..n {
        // column j: a_jj - sum_k l_jk^2, then the entries below
        for k in 0..j {
            let ljk = a[(j, k)];
            if ljk != 0.0 {
                for i in j..n {
                    let lik = a[(i, k)];
                    a[(i, j)] -= lik * ljk;
                }
            }
        }
        let d = a[(j, j)];
        if !(d > floor && d > 0.0 && d.is_finite()) {
            return Err((j, d));
        }
        let d = d.sqrt();
        a[(j, j)] = d;
        for i in j + 1..n {
            a[(i, j)] /= d;
        }
    }
    Ok(())
}

/// Solves `L L^T x = b` with the factor of [`cholesky_in_place`]; `b` is overwritten by `x`.
pub fn cholesky_solve_in_place(l: &Mat<f64>, b: &mut [f64]) {
    cholesky_solve(l.as_ref(), b);
}

/// Solves `L L^T x = b` with the factor of [`cholesky_factor`] in the view `l` (columns
/// contiguous); `b` is overwritten by `x`.
pub fn cholesky_solve(l: faer::MatRef<'_, f64>, b: &mut [f64]) {
    let n = l.nrows();
    debug_assert_eq!(b.len(), n, "right-hand side length");
    let col_of = |j: usize| {
        l.col(j)
            .try_as_col_major()
            .expect("column-major factor")
            .as_slice()
    };
    for j in 0..n {
        let col = col_of(j);
        let xj = b[j] / col[j];
        b[j] = xj;
        if xj != 0.0 {
            for (bi, lij) in b[j + 1..].iter_mut().zip(&col[j + 1..]) {
                *bi -= lij * xj;
            }
        }
    }
    for j in (0..n).rev() {
        let col = col_of(j);
        let mut s = b[j];
        for (bi, lij) in b[j + 1..].iter().zip(&col[j + 1..]) {
            s -= lij * bi;
        }
        b[j] = s / col[j];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_small_system_against_hand_solution() {
        // [0 1; 4 -6] x = [1; -2] has x = [1, 1]; the zero (0,0) entry forces a row swap.
        let mut lu = DenseLu::new(2);
        lu.a[(0, 1)] = 1.0;
        lu.a[(1, 0)] = 4.0;
        lu.a[(1, 1)] = -6.0;
        assert!(lu.factor());
        let mut b = [1.0, -2.0];
        lu.solve_in_place(&mut b);
        assert!(
            (b[0] - 1.0).abs() < 1e-15 && (b[1] - 1.0).abs() < 1e-15,
            "{b:?}"
        );
    }

    /// Pivoting 9 x 9 system against the dense residual `|A x - b|`.
    #[test]
    fn solves_pivoting_system_to_round_off() {
        let n = 9;
        let f = |i: usize, j: usize| {
            let v = ((i * 7 + j * 13) % 11) as f64 - 5.0 + if i == j { 0.5 } else { 0.0 };
            if i + j == 3 {
                0.0
            } else {
                v
            }
        };
        let mut lu = DenseLu::new(n);
        for j in 0..n {
            for i in 0..n {
                lu.a[(i, j)] = f(i, j);
            }
        }
        assert!(lu.factor());
        let b: Vec<f64> = (0..n).map(|i| (i as f64 - 3.0) * 0.7).collect();
        let mut x = b.clone();
        lu.solve_in_place(&mut x);
        for (i, bi) in b.iter().enumerate() {
            let r: f64 = (0..n).map(|j| f(i, j) * x[j]).sum::<f64>() - bi;
            assert!(r.abs() < 1e-12, "row {i}: residual {r}");
        }
    }

    #[test]
    fn detects_singular_matrix() {
        let mut lu = DenseLu::new(2);
        lu.a[(0, 0)] = 1.0;
        lu.a[(0, 1)] = 2.0;
        lu.a[(1, 0)] = 2.0;
        lu.a[(1, 1)] = 4.0;
        assert!(!lu.factor());
    }

    /// The saddle matrix `[[k K0, G^T], [G, 0]]` of a stiff structure (k = 1e9) held by two
    /// independent constraints: its multiplier pivots are about `1/k`, 1e-18 of the largest entry,
    /// yet the matrix is regular and the solution has a small residual. With a redundant
    /// constraint (a repeated row of `G`) it is refused.
    #[test]
    fn stiff_saddle_matrix_is_regular_and_redundant_constraints_are_not() {
        let k = 1e9;
        let k0 = |i: usize, j: usize| match i.abs_diff(j) {
            0 => 2.0,
            1 => -1.0,
            _ => 0.0,
        };
        let saddle = |g: [[f64; 4]; 2]| {
            let mut lu = DenseLu::new(6);
            for i in 0..4 {
                for j in 0..4 {
                    lu.a[(i, j)] = k * k0(i, j);
                }
            }
            for (r, row) in g.iter().enumerate() {
                for (j, &v) in row.iter().enumerate() {
                    lu.a[(4 + r, j)] = v;
                    lu.a[(j, 4 + r)] = v;
                }
            }
            lu
        };
        let g = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]];
        let mut lu = saddle(g);
        let a = lu.a.clone();
        assert!(lu.factor(), "regular stiff saddle matrix refused");
        let b = [1.0, -2.0, 3.0, 0.5, 1e-3, -2e-3];
        let mut x = b;
        lu.solve_in_place(&mut x);
        for (i, bi) in b.iter().enumerate() {
            let r: f64 = (0..6).map(|j| a[(i, j)] * x[j]).sum::<f64>() - bi;
            let scale: f64 = (0..6).map(|j| (a[(i, j)] * x[j]).abs()).sum::<f64>();
            assert!(
                r.abs() <= 1e-12 * scale.max(bi.abs()),
                "row {i}: residual {r:e}"
            );
        }
        let mut redundant = saddle([g[0], g[0]]);
        assert!(!redundant.factor(), "redundant constraints accepted");
    }

    /// SPD 7 x 7 system: Cholesky solution against the LU solution and the residual.
    #[test]
    fn cholesky_matches_lu_on_spd_matrix() {
        let n = 7;
        let b_mat = |i: usize, j: usize| ((i * 5 + j * 3) % 7) as f64 - 3.0;
        let a = Mat::from_fn(n, n, |i, j| {
            (0..n).map(|k| b_mat(i, k) * b_mat(j, k)).sum::<f64>() + if i == j { 1.0 } else { 0.0 }
        });
        let rhs: Vec<f64> = (0..n).map(|i| 1.0 - 0.3 * i as f64).collect();
        let mut l = a.clone();
        assert!(cholesky_in_place(&mut l));
        let mut x = rhs.clone();
        cholesky_solve_in_place(&l, &mut x);
        let mut lu = DenseLu::new(n);
        lu.a.copy_from(&a);
        assert!(lu.factor());
        let mut y = rhs.clone();
        lu.solve_in_place(&mut y);
        for i in 0..n {
            assert!(
                (x[i] - y[i]).abs() <= 1e-12 * y[i].abs().max(1.0),
                "{i}: {} vs {}",
                x[i],
                y[i]
            );
            let r: f64 = (0..n).map(|j| a[(i, j)] * x[j]).sum::<f64>() - rhs[i];
            assert!(r.abs() < 1e-11, "row {i}: residual {r}");
        }
    }

    #[test]
    fn cholesky_rejects_indefinite_matrix() {
        let mut a = Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { 2.0 });
        assert!(!cholesky_in_place(&mut a));
    }
}
