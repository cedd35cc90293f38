//! The products with `M` and `K` of the Lanczos driver (one function each, so that their storage
//! can change in one place) and the per-pair convergence measure: the explicit residual of the
//! shift-inverted operator.

use faer::reborrow::ReborrowMut;
use faer::{Mat, MatMut, MatRef};

use super::cholesky::SparseCholesky;
use crate::SparseMatrix;

/// `out = M x` (every product with the mass matrix in the Lanczos solver goes through here).
pub(super) fn apply_mass(m: &SparseMatrix, x: MatRef<'_, f64>, out: MatMut<'_, f64>) {
    symmetric_block_product(m, x, out);
}

/// `out = K x` (every product with the stiffness matrix in the eigen solver goes through here).
pub(super) fn apply_stiffness(k: &SparseMatrix, x: MatRef<'_, f64>, out: MatMut<'_, f64>) {
    symmetric_block_product(k, x, out);
}

/// Columns of `x` per pass of [`symmetric_block_product`] (one Lanczos block).
const PASS_COLS: usize = 8;

/// Rows from which the products run on two threads (each row is computed the same way on either
/// thread: the result does not depend on it).
const PARALLEL_ROWS: usize = 4096;

/// `out = A x` for a symmetric `A` in full storage, read as `A^T x`: row `j` of the product is the
/// dot product of column `j` of `A` with the rows of `x`, so each pass over the matrix serves
/// [`PASS_COLS`] columns of `x` (stored row by row) and writes every output entry once. faer's
/// compressed-column product scatters one column of `x` per pass over the matrix, eight passes for
/// a Lanczos block: this is the same arithmetic with an eighth of the memory traffic. `A` is
/// symmetric to the validation tolerance (1e-10 relative, [`super::lowest_modes`]); the factorization
/// reads its lower triangle only, so neither product is more exact than the other. The two halves
/// of the rows run on two threads; every entry is one dot product in a fixed order, so the result
/// does not depend on the machine's threads.
fn symmetric_block_product(a: &SparseMatrix, x: MatRef<'_, f64>, out: MatMut<'_, f64>) {
    let (n, p) = (x.nrows(), x.ncols());
    assert!(a.nrows() == n && a.ncols() == n && out.nrows() == n && out.ncols() == p);
    // the columns of a pass, row by row: kept per thread between products (a fresh n x 8
    // block per product would cost its pages' faults every time)
    XT.with_borrow_mut(|xt| {
        xt.clear();
        xt.resize(n * PASS_COLS, 0.0);
        block_product_passes(a, x, out, xt);
    });
}

thread_local! {
    /// The work rows of [`symmetric_block_product`].
    static XT: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The passes of [`symmetric_block_product`] with the work rows `xt` (`n * PASS_COLS`).
fn block_product_passes(
    a: &SparseMatrix,
    x: MatRef<'_, f64>,
    out: MatMut<'_, f64>,
    xt: &mut [f64],
) {
    let (n, p) = (x.nrows(), x.ncols());
    let mut out = out;
    for c0 in (0..p).step_by(PASS_COLS) {
        let w = PASS_COLS.min(p - c0);
        for c in 0..w {
            let xc = x.col(c0 + c);
            for i in 0..n {
                xt[i * PASS_COLS + c] = xc[i];
            }
        }
        let block = out.rb_mut().subcols_mut(c0, w);
        if n < PARALLEL_ROWS {
            product_rows(a, xt, 0, block);
            continue;
        }
        let (top, bottom) = block.split_at_row_mut(n / 2);
        let xt = &*xt;
        std::thread::scope(|s| {
            let h = s.spawn(move || product_rows(a, xt, n / 2, bottom));
            product_rows(a, xt, 0, top);
            h.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
        });
    }
}

/// Rows `first..first + out.nrows()` of [`symmetric_block_product`] (`xt`: the pass's columns of
/// `x`, row by row).
fn product_rows(a: &SparseMatrix, xt: &[f64], first: usize, mut out: MatMut<'_, f64>) {
    let w = out.ncols();
    for r in 0..out.nrows() {
        let j = first + r;
        let mut acc = [0.0f64; PASS_COLS];
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            let xi: &[f64; PASS_COLS] = xt[i * PASS_COLS..(i + 1) * PASS_COLS]
                .try_into()
                .expect("row of PASS_COLS entries");
            for c in 0..PASS_COLS {
                acc[c] += v * xi[c];
            }
        }
        for c in 0..w {
            out[(r, c)] = acc[c];
        }
    }
}

/// Eigenvalues and explicit residuals of approximate eigenvectors `x` (columns) from the
/// shift-inverted operator `OP = (K - sigma M)^{-1} M` (`op` factors `K - sigma M`).
///
/// For each column: `w = OP x`, `theta = x^T M w / x^T M x` (Rayleigh quotient of `OP` in the
/// `M` inner product), `lambda = sigma + 1 / theta` and the relative residual
/// `||w - theta x||_M / (|theta| ||x||_M)`. `OP` is self-adjoint in the `M` inner product, so a
/// residual `r` bounds the distance to an exact eigenvalue: `|lambda - lambda_exact| <= r |lambda -
/// sigma|` to first order. With `sigma` a fraction of the lowest eigenvalue below it (the automatic
/// shift) `|lambda - sigma|` is at most about `2 |lambda|`: the error on the pair's own scale; for
/// zero-energy modes (`lambda = 0`) the scale is `|sigma|`, half the lowest nonzero eigenvalue.
///
/// The columns of `x` are M-normalised in place. Returns `(lambda, residual)`.
pub(super) fn shift_invert_residuals(
    op: &SparseCholesky,
    m: &SparseMatrix,
    sigma: f64,
    x: &mut Mat<f64>,
) -> (Vec<f64>, Vec<f64>) {
    let (n, p) = (x.nrows(), x.ncols());
    // two n x p buffers besides x (the peak memory of the modal analysis is near): `mx` holds
    // M x, later M s
    let mut mx = Mat::zeros(n, p);
    apply_mass(m, x.as_ref(), mx.as_mut());
    let mut w = mx.clone();
    op.solve_in_place(w.as_mut());
    let mut lam = Vec::with_capacity(p);
    let mut theta = Vec::with_capacity(p);
    let mut xnorm = Vec::with_capacity(p);
    for j in 0..p {
        let xmx = x.col(j).transpose() * mx.col(j);
        // x^T M w = (M x)^T w (M symmetric)
        let t = (mx.col(j).transpose() * w.col(j)) / xmx;
        theta.push(t);
        xnorm.push(xmx.max(0.0).sqrt());
        lam.push(sigma + 1.0 / t);
        for i in 0..n {
            w[(i, j)] -= t * x[(i, j)];
        }
    }
    // w now holds the residual vectors s = OP x - theta x
    let mut ms = mx;
    apply_mass(m, w.as_ref(), ms.as_mut());
    let mut res = Vec::with_capacity(p);
    for j in 0..p {
        let sms = (w.col(j).transpose() * ms.col(j)).max(0.0).sqrt();
        let r = sms / (theta[j].abs() * xnorm[j]);
        res.push(if r.is_finite() { r } else { f64::INFINITY });
        let s = 1.0 / xnorm[j];
        for i in 0..n {
            x[(i, j)] *= s;
        }
    }
    (lam, res)
}
