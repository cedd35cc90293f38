//! Storage helpers of the block Lanczos basis: columns reserved without touching their memory,
//! in-place restarts, block concatenation and the deterministic start-vector generator.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};

/// Deterministic splitmix64 generator for start blocks (no external RNG dependency).
pub(super) struct SplitMix(pub(super) u64);

impl SplitMix {
    pub(super) fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// Rows of a basis combined per pass of [`combine_in_place`].
const COMBINE_ROWS: usize = 2048;

/// `B[:, l..l+k] <- B[:, l..l+a] S` (`S`: `a x k`, `k <= a`) in place, a band of rows at a
/// time: each row of the result depends on the same row of `B` only, so a thick restart needs a
/// buffer of [`COMBINE_ROWS`] rows instead of a copy of the basis.
pub(super) fn combine_in_place(basis: &mut Mat<f64>, l: usize, a: usize, sc: MatRef<'_, f64>) {
    let (n, k) = (basis.nrows(), sc.ncols());
    debug_assert!(sc.nrows() == a && k <= a && l + a <= basis.ncols());
    let mut band = Mat::<f64>::zeros(COMBINE_ROWS.min(n), k);
    for r0 in (0..n).step_by(COMBINE_ROWS) {
        let rows = COMBINE_ROWS.min(n - r0);
        matmul(
            band.as_mut().subrows_mut(0, rows),
            Accum::Replace,
            basis.as_ref().submatrix(r0, l, rows, a),
            sc,
            1.0,
            Par::Seq,
        );
        basis
            .as_mut()
            .submatrix_mut(r0, l, rows, k)
            .copy_from(band.subrows(0, rows));
    }
}

/// An `n x 0` matrix with room for `cap` columns (memory reserved, not touched).
pub(super) fn empty_columns(n: usize, cap: usize) -> Mat<f64> {
    let mut v = Mat::with_capacity(n, cap);
    v.resize_with(n, 0, |_, _| 0.0);
    v
}

pub(super) fn concat_cols(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let ca = a.ncols();
    Mat::from_fn(a.nrows(), ca + b.ncols(), |i, j| {
        if j < ca {
            a[(i, j)]
        } else {
            b[(i, j - ca)]
        }
    })
}

pub(super) fn concat_rows(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let ra = a.nrows();
    Mat::from_fn(ra + b.nrows(), a.ncols(), |i, j| {
        if i < ra {
            a[(i, j)]
        } else {
            b[(i - ra, j)]
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The in-place restart equals the product `B[:, l..l+a] S` formed apart, across several row
    /// bands (n = 5000 > 2 bands), and leaves the columns before `l` alone.
    #[test]
    fn combine_in_place_equals_the_product() {
        let (n, l, a, k) = (5000, 3, 7, 5);
        let b = Mat::from_fn(n, l + a, |i, j| ((i * 31 + j * 17) % 23) as f64 - 11.0);
        let s = Mat::from_fn(a, k, |i, j| 0.1 * (i as f64) - 0.3 * (j as f64) + 0.05);
        let expected = b.subcols(l, a) * &s;
        let mut c = b.clone();
        combine_in_place(&mut c, l, a, s.as_ref());
        assert!((c.subcols(l, k) - &expected).norm_max() < 1e-12 * expected.norm_max());
        assert_eq!(c.subcols(0, l), b.subcols(0, l));
    }
}
