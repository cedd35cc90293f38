//! Preallocated dense LU solver (faer, partial pivoting) used for the iteration matrix.
//!
//! All memory (matrix, permutations, faer scratch stack) is allocated in [`DenseLu::new`];
//! [`DenseLu::factor`] and [`DenseLu::solve_in_place`] do not allocate.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::{Mat, MatMut, Par};

/// Dense square matrix with an in-place LU factorization.
pub struct DenseLu {
    /// The matrix to factor (overwritten by its LU factors in [`DenseLu::factor`]).
    pub a: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    stack: MemBuffer,
}

impl std::fmt::Debug for DenseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DenseLu").field("dim", &self.dim()).finish()
    }
}

impl DenseLu {
    /// Allocates an `n x n` system.
    pub fn new(n: usize) -> Self {
        let req = StackReq::any_of(&[
            factor::lu_in_place_scratch::<usize, f64>(n, n, Par::Seq, Default::default()),
            solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        Self {
            a: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            stack: MemBuffer::new(req),
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.a.nrows()
    }

    /// Factors `a` in place. Returns `false` if a pivot is zero, tiny relative to the largest
    /// entry (`1e-14`), or non-finite (the matrix is then numerically singular).
    pub fn factor(&mut self) -> bool {
        let n = self.dim();
        if n == 0 {
            return true;
        }
        let mut amax = 0.0_f64;
        for j in 0..n {
            for i in 0..n {
                let v = self.a[(i, j)];
                if !v.is_finite() {
                    return false;
                }
                amax = amax.max(v.abs());
            }
        }
        factor::lu_in_place(
            self.a.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.stack),
            Default::default(),
        );
        (0..n).all(|i| {
            let p = self.a[(i, i)];
            p.is_finite() && p.abs() > 1e-14 * amax
        })
    }

    /// Solves `A x = b` with the factors of the last [`DenseLu::factor`]; `b` is overwritten by `x`.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let n = self.dim();
        if n == 0 {
            return;
        }
        let perm = faer::perm::PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        solve::solve_in_place(
            self.a.as_ref(),
            self.a.as_ref(),
            perm,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.stack),
        );
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

    #[test]
    fn detects_singular_matrix() {
        let mut lu = DenseLu::new(2);
        lu.a[(0, 0)] = 1.0;
        lu.a[(0, 1)] = 2.0;
        lu.a[(1, 0)] = 2.0;
        lu.a[(1, 1)] = 4.0;
        assert!(!lu.factor());
    }
}
