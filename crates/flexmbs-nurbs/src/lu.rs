//! Dense LU factorization with partial pivoting, solved in place on strided data of any
//! [`Interpolant`] (the interpolation matrix `N` of (3.18) is factorized once, then reused).

use crate::error::NurbsError;
use crate::interp::Interpolant;

/// `P A = L U`, row swaps recorded LAPACK-style (`piv[i]`: row swapped with `i` at step `i`).
#[derive(Debug, Clone)]
pub(crate) struct DenseLu {
    n: usize,
    lu: Vec<f64>,
    piv: Vec<usize>,
}

impl DenseLu {
    /// Factorizes the row-major `n x n` matrix `a`. Entries are basis function values in
    /// [0, 1]; a pivot below `1e-13` times the largest entry of its column counts as singular.
    pub(crate) fn factor(mut a: Vec<f64>, n: usize) -> Result<Self, NurbsError> {
        debug_assert_eq!(a.len(), n * n);
        let mut piv = vec![0; n];
        for k in 0..n {
            let (mut best, mut row) = (0.0f64, k);
            for i in k..n {
                let v = a[i * n + k].abs();
                if v > best {
                    best = v;
                    row = i;
                }
            }
            if best.is_nan() || best <= 1e-13 {
                return Err(NurbsError::SingularInterpolation { pivot: k });
            }
            piv[k] = row;
            if row != k {
                for j in 0..n {
                    a.swap(k * n + j, row * n + j);
                }
            }
            let d = a[k * n + k];
            for i in k + 1..n {
                let l = a[i * n + k] / d;
                a[i * n + k] = l;
                if l != 0.0 {
                    for j in k + 1..n {
                        a[i * n + j] -= l * a[k * n + j];
                    }
                }
            }
        }
        Ok(Self { n, lu: a, piv })
    }

    /// Solves `A x = b` in place, `b_i = data[offset + i * stride]`; allocation-free.
    pub(crate) fn solve_strided<T: Interpolant>(
        &self,
        data: &mut [T],
        offset: usize,
        stride: usize,
    ) {
        let (n, lu) = (self.n, &self.lu);
        let at = |i: usize| offset + i * stride;
        for k in 0..n {
            if self.piv[k] != k {
                data.swap(at(k), at(self.piv[k]));
            }
        }
        for i in 1..n {
            let mut acc = data[at(i)];
            for j in 0..i {
                let l = lu[i * n + j];
                if l != 0.0 {
                    acc -= data[at(j)] * l;
                }
            }
            data[at(i)] = acc;
        }
        for i in (0..n).rev() {
            let mut acc = data[at(i)];
            for j in i + 1..n {
                let u = lu[i * n + j];
                if u != 0.0 {
                    acc -= data[at(j)] * u;
                }
            }
            acc /= lu[i * n + i];
            data[at(i)] = acc;
        }
    }
}
