//! LU factorization with partial pivoting of the interpolation matrix `N` of (3.18), factorized
//! once and solved in place on strided data of any [`Interpolant`].
//!
//! `N` is banded (open: bandwidth `p`) or cyclic banded (closed: plus `p` wrapped columns), so
//! elimination skips zero multipliers and the factors are kept in compressed rows: a solve costs
//! `O(k p)` (open) rather than `O(k^2)`.

use crate::error::NurbsError;
use crate::interp::Interpolant;

/// `P A = L U` with the row swaps recorded LAPACK-style and `L` (unit, strictly lower) and `U`
/// (upper, diagonal first in each row) stored as compressed rows of their nonzero entries.
#[derive(Debug, Clone)]
pub(crate) struct BandedLu {
    n: usize,
    piv: Vec<usize>,
    l_start: Vec<usize>,
    l_cols: Vec<usize>,
    l_vals: Vec<f64>,
    u_start: Vec<usize>,
    u_cols: Vec<usize>,
    u_vals: Vec<f64>,
}

impl BandedLu {
    /// Factorizes the row-major `n x n` matrix `a`. Entries are basis function values in
    /// [0, 1]; a pivot below `1e-13` counts as singular (Schoenberg-Whitney violated).
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
        Ok(Self::compress(&a, n, piv))
    }

    /// Keeps only the nonzero entries of the factors (exact zeros stay exact in elimination).
    fn compress(a: &[f64], n: usize, piv: Vec<usize>) -> Self {
        let (mut l_start, mut l_cols, mut l_vals) = (vec![0], Vec::new(), Vec::new());
        let (mut u_start, mut u_cols, mut u_vals) = (vec![0], Vec::new(), Vec::new());
        for i in 0..n {
            for j in 0..i {
                if a[i * n + j] != 0.0 {
                    l_cols.push(j);
                    l_vals.push(a[i * n + j]);
                }
            }
            l_start.push(l_cols.len());
            for j in i..n {
                if j == i || a[i * n + j] != 0.0 {
                    u_cols.push(j);
                    u_vals.push(a[i * n + j]);
                }
            }
            u_start.push(u_cols.len());
        }
        Self {
            n,
            piv,
            l_start,
            l_cols,
            l_vals,
            u_start,
            u_cols,
            u_vals,
        }
    }

    /// Solves `A x = b` in place, `b_i = data[offset + i * stride]`; allocation-free.
    pub(crate) fn solve_strided<T: Interpolant>(
        &self,
        data: &mut [T],
        offset: usize,
        stride: usize,
    ) {
        let at = |i: usize| offset + i * stride;
        for k in 0..self.n {
            if self.piv[k] != k {
                data.swap(at(k), at(self.piv[k]));
            }
        }
        for i in 1..self.n {
            let mut acc = data[at(i)];
            for e in self.l_start[i]..self.l_start[i + 1] {
                acc -= data[at(self.l_cols[e])] * self.l_vals[e];
            }
            data[at(i)] = acc;
        }
        for i in (0..self.n).rev() {
            let (first, end) = (self.u_start[i], self.u_start[i + 1]);
            let mut acc = data[at(i)];
            for e in first + 1..end {
                acc -= data[at(self.u_cols[e])] * self.u_vals[e];
            }
            acc /= self.u_vals[first];
            data[at(i)] = acc;
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::CurveInterpolator;

    /// The factors stay sparse: open O(k p), closed O(k p) plus the `p` wrapped columns/rows.
    #[test]
    fn factors_of_interpolation_matrices_stay_sparse() {
        let k = 200;
        for (closed, p) in [(false, 3), (true, 3), (false, 5), (true, 4)] {
            let params: Vec<f64> = (0..k)
                .map(|i| (i as f64 + 0.3 * (i as f64).sin()) / k as f64)
                .collect();
            let ip = CurveInterpolator::new(&params, p, closed).unwrap();
            let lu = ip.lu();
            let nnz = lu.l_vals.len() + lu.u_vals.len();
            let bound = if closed {
                k * (4 * p + 3)
            } else {
                k * (3 * p + 2)
            };
            assert!(
                nnz <= bound,
                "closed={closed} p={p}: {nnz} nonzeros > {bound}"
            );
        }
    }
}
