//! Orthonormalisation of the block Lanczos basis in the `M` inner product: classical
//! Gram-Schmidt against the basis (products with the stored `M V`), Cholesky-QR of a block in
//! two passes, random start and fill-in blocks.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};

use super::super::basis::{combine_in_place, concat_cols, concat_rows};
use super::super::ops::apply_mass;
use super::{BlockLanczos, OrthonormalBlock};
use crate::FeError;

impl BlockLanczos<'_> {
    /// Adds the requested random directions to the pending next block.
    pub(super) fn inject_into_pending(&mut self) -> Result<(), FeError> {
        if self.inject == 0 {
            return Ok(());
        }
        let used = self.used;
        let room = self.n - used;
        let Some((q, mq, b)) = self.next.take() else {
            return Ok(());
        };
        let extra = self.inject.min(room.saturating_sub(q.ncols()));
        self.inject = 0;
        if extra == 0 {
            self.next = Some((q, mq, b));
            return Ok(());
        }
        let (r, mr) = self.random_block_against(extra, used, Some((q.as_ref(), mq.as_ref())))?;
        let bl = b.ncols();
        let q = concat_cols(q.as_ref(), r.as_ref());
        let mq = concat_cols(mq.as_ref(), mr.as_ref());
        let b = concat_rows(b.as_ref(), Mat::zeros(extra, bl).as_ref());
        self.next = Some((q, mq, b));
        Ok(())
    }

    /// `W <- (I - V V^T M) W`, `passes` times (2: CGS2), the inner products `V^T M W = (M V)^T W` from the
    /// stored `M V`; returns the summed coefficients `V^T M W`.
    pub(super) fn project_out(&self, w: &mut Mat<f64>, used: usize, passes: usize) -> Mat<f64> {
        let bl = w.ncols();
        let mut c = Mat::zeros(used, bl);
        let vb = self.v.subcols(0, used);
        let mvb = self.mv.subcols(0, used);
        for _ in 0..passes {
            c += project_out_once(vb, mvb, w.as_mut());
        }
        c
    }

    /// M-orthonormalises `w` (already orthogonal to the first `used` basis vectors):
    /// `W = Q B` with `Q^T M Q = I`; returns `(Q, M Q, B)`. Numerically dependent directions are
    /// dropped (zero rows of `B`) and replaced by random directions so the block keeps its size.
    pub(super) fn m_orthonormalize(
        &mut self,
        w: Mat<f64>,
        used: usize,
        room: usize,
    ) -> Result<OrthonormalBlock, FeError> {
        let bl = w.ncols();
        let (q, mq, b) = self.gram_eigen_qr(w, used, 1e-20)?;
        let r = q.ncols();
        let want = bl.min(room);
        if r >= want {
            return Ok((q, mq, b));
        }
        let (fill, mfill) =
            self.random_block_against(want - r, used, Some((q.as_ref(), mq.as_ref())))?;
        let q = concat_cols(q.as_ref(), fill.as_ref());
        let mq = concat_cols(mq.as_ref(), mfill.as_ref());
        let b = concat_rows(b.as_ref(), Mat::zeros(want - r, bl).as_ref());
        Ok((q, mq, b))
    }

    /// Eigen-based Cholesky-QR in the M-inner product, done twice (with a
    /// reprojection against the basis in between): `(Q, M Q, B)`. Columns whose Gram eigenvalue
    /// is below `rel` times the largest column norm squared are dropped. `M Q` is the product of
    /// the second pass's `M W` with its coefficients (one product with `M` per pass).
    pub(super) fn gram_eigen_qr(
        &self,
        mut w: Mat<f64>,
        used: usize,
        rel: f64,
    ) -> Result<OrthonormalBlock, FeError> {
        let bl = w.ncols();
        let mut b_total = Mat::<f64>::identity(bl, bl);
        let mut ref_norm = None;
        // `M W` of both passes in one array; `W` and `M W` are combined in place (no fresh
        // n x block arrays per pass)
        let mut mw = Mat::zeros(self.n, bl);
        for pass in 0..2 {
            if pass == 1 {
                // Q's components along the basis are round-off: one pass removes them
                let _ = self.project_out(&mut w, used, 1);
            }
            let cols = w.ncols();
            apply_mass(self.m, w.as_ref(), mw.as_mut().subcols_mut(0, cols));
            let g = w.transpose() * mw.subcols(0, cols);
            let g = Mat::from_fn(g.nrows(), g.ncols(), |i, j| 0.5 * (g[(i, j)] + g[(j, i)]));
            let gmax = (0..g.nrows()).map(|i| g[(i, i)]).fold(0.0f64, f64::max);
            let thr = rel * *ref_norm.get_or_insert(gmax);
            if g.nrows() == 0 || gmax <= 0.0 || !gmax.is_finite() {
                return Ok((
                    Mat::zeros(self.n, 0),
                    Mat::zeros(self.n, 0),
                    Mat::zeros(0, bl),
                ));
            }
            let evd = g.self_adjoint_eigen(Side::Lower).map_err(|e| {
                FeError::EigenNotConverged(format!("Gram matrix eigen solver failed: {e:?}"))
            })?;
            let keep: Vec<usize> = (0..g.nrows()).rev().filter(|&i| evd.S()[i] > thr).collect();
            let u = evd.U();
            // Q = W U_k D_k^{-1/2}, B = D_k^{1/2} U_k^T
            let uk = Mat::from_fn(g.nrows(), keep.len(), |i, j| {
                u[(i, keep[j])] / evd.S()[keep[j]].sqrt()
            });
            let bk = Mat::from_fn(keep.len(), g.nrows(), |i, j| {
                u[(j, keep[i])] * evd.S()[keep[i]].sqrt()
            });
            combine_in_place(&mut w, 0, cols, uk.as_ref());
            w.truncate(self.n, keep.len());
            combine_in_place(&mut mw, 0, cols, uk.as_ref());
            b_total = &bk * &b_total;
        }
        mw.truncate(self.n, w.ncols());
        Ok((w, mw, b_total))
    }

    /// `count` random M-orthonormal vectors and their `M` products, orthogonal to the first
    /// `used` basis vectors and to `extra` (M-orthonormal columns and their `M` products), if
    /// given.
    pub(super) fn random_block_against(
        &mut self,
        count: usize,
        used: usize,
        extra: Option<(MatRef<'_, f64>, MatRef<'_, f64>)>,
    ) -> Result<(Mat<f64>, Mat<f64>), FeError> {
        for _attempt in 0..3 {
            let mut r = Mat::from_fn(self.n, count, |_, _| 0.0);
            for j in 0..count {
                for i in 0..self.n {
                    r[(i, j)] = self.rng.next_f64();
                }
            }
            for _ in 0..2 {
                if let Some((x, mx)) = extra {
                    let c = mx.transpose() * &r;
                    r -= x * &c;
                }
                let _ = self.project_out(&mut r, used, 2);
            }
            let (q, mq, _) = self.gram_eigen_qr(r, used, 1e-14)?;
            if q.ncols() == count {
                return Ok((q, mq));
            }
        }
        Err(FeError::EigenNotConverged(format!(
            "could not generate {count} new independent start vectors (basis {used} of {})",
            self.n
        )))
    }

    pub(super) fn random_block(&mut self, count: usize) -> Result<(Mat<f64>, Mat<f64>), FeError> {
        self.random_block_against(count, 0, None)
    }
}

/// Bases from this many rows are orthogonalised on two threads.
const PARALLEL_ROWS: usize = 20_000;

/// One classical Gram-Schmidt pass `W <- W - V C`, `C = (M V)^T W`; returns `C`. From
/// [`PARALLEL_ROWS`] on, the two halves of the rows run on two threads (fixed halves, partial
/// products summed in a fixed order: the result does not depend on the machine).
fn project_out_once(v: MatRef<'_, f64>, mv: MatRef<'_, f64>, mut w: MatMut<'_, f64>) -> Mat<f64> {
    let (n, used, bl) = (w.nrows(), v.ncols(), w.ncols());
    let mut c = Mat::zeros(used, bl);
    if n < PARALLEL_ROWS {
        matmul(
            c.as_mut(),
            Accum::Replace,
            mv.transpose(),
            w.as_ref(),
            1.0,
            Par::Seq,
        );
        matmul(w.as_mut(), Accum::Add, v, c.as_ref(), -1.0, Par::Seq);
        return c;
    }
    let h = n / 2;
    let mut c2 = Mat::zeros(used, bl);
    std::thread::scope(|s| {
        let (w1, w2) = (w.as_ref().subrows(0, h), w.as_ref().subrows(h, n - h));
        let (mv1, mv2) = (mv.subrows(0, h), mv.subrows(h, n - h));
        let c2 = &mut c2;
        let t = s.spawn(move || {
            matmul(
                c2.as_mut(),
                Accum::Replace,
                mv2.transpose(),
                w2,
                1.0,
                Par::Seq,
            )
        });
        matmul(
            c.as_mut(),
            Accum::Replace,
            mv1.transpose(),
            w1,
            1.0,
            Par::Seq,
        );
        t.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
    });
    c += &c2;
    let (w1, w2) = w.split_at_row_mut(h);
    let (v1, v2) = (v.subrows(0, h), v.subrows(h, n - h));
    let cr = c.as_ref();
    std::thread::scope(|s| {
        let t = s.spawn(move || matmul(w2, Accum::Add, v2, cr, -1.0, Par::Seq));
        matmul(w1, Accum::Add, v1, cr, -1.0, Par::Seq);
        t.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
    });
    c
}
