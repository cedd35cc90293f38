//! Block shift-invert Lanczos in the M-inner product with full (CGS2)
//! reorthogonalisation and thick restart.
//!
//! Operator `OP = (K - sigma M)^{-1} M`, self-adjoint in `<x, y>_M = x^T M y`, with
//! eigenvalues `theta = 1 / (lambda - sigma)`; for `sigma` below the spectrum the
//! largest `theta` belong to the lowest `lambda`. The basis `V` (`V^T M V = I`) grows
//! block by block; the projected matrix `H = V^T M OP V` is formed explicitly from
//! the orthogonalisation coefficients (so it stays exact after restarts and random
//! injections), and the Krylov relation `OP V = V H + Q B E^T` (Q: next block)
//! gives the Ritz residual estimate `||OP y - theta y||_M = ||B E^T s||`.

use faer::linalg::matmul::matmul;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::{Accum, Mat, MatRef, Par, Side};

use super::cholesky::SparseCholesky;
use crate::{FeError, SparseMatrix};

/// Ritz pairs of `OP`, ordered by decreasing `theta` (i.e. increasing `lambda`).
#[derive(Debug)]
pub(crate) struct RitzPairs {
    /// Ritz values of `OP`, descending.
    pub theta: Vec<f64>,
    /// Ritz vectors (M-orthonormal), `n x theta.len()`.
    pub vectors: Mat<f64>,
    /// Relative residual estimates `||OP y - theta y||_M / theta`.
    pub estimate: Vec<f64>,
    /// Current basis size.
    pub basis: usize,
}

/// Ritz values (descending), coefficient vectors `S` and residual estimates.
type RitzDecomposition = (Vec<f64>, Mat<f64>, Vec<f64>);

/// Deterministic splitmix64 generator for start blocks (no external RNG dependency).
struct SplitMix(u64);

impl SplitMix {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// State of a block shift-invert Lanczos run.
pub(crate) struct BlockLanczos<'a> {
    m: &'a SparseMatrix,
    n: usize,
    block: usize,
    cap: usize,
    /// Basis vectors in columns `0..used`.
    v: Mat<f64>,
    /// Projected operator `V^T M OP V`.
    h: Mat<f64>,
    used: usize,
    /// Start column of the last block of `v` (not yet multiplied by OP).
    last: usize,
    /// Next block `Q` and coupling `B` (`Q B = (I - V V^T M) OP V_last`), if computed.
    next: Option<(Mat<f64>, Mat<f64>)>,
    /// Number of extra random vectors to add to the next block.
    inject: usize,
    rng: SplitMix,
}

impl<'a> BlockLanczos<'a> {
    /// Sets up the iteration with a random M-orthonormal start block.
    /// `cap` is the maximum basis size (clamped to `[min(n, 3 block), n]`).
    pub fn new(m: &'a SparseMatrix, block: usize, cap: usize, seed: u64) -> Result<Self, FeError> {
        let n = m.nrows();
        let block = block.clamp(1, n.max(1));
        let cap = cap.max(3 * block).min(n);
        let mut s = Self {
            m,
            n,
            block,
            cap,
            v: Mat::zeros(n, cap),
            h: Mat::zeros(cap, cap),
            used: 0,
            last: 0,
            next: None,
            inject: 0,
            rng: SplitMix(seed),
        };
        let q = s.random_block(block)?;
        s.v.as_mut().subcols_mut(0, block).copy_from(&q);
        s.used = block;
        Ok(s)
    }

    /// Raises the maximum basis size to at least `cap` (at most `n`), keeping the basis.
    pub fn ensure_capacity(&mut self, cap: usize) {
        let cap = cap.min(self.n);
        if cap <= self.cap {
            return;
        }
        let mut v = Mat::zeros(self.n, cap);
        v.as_mut()
            .subcols_mut(0, self.used)
            .copy_from(self.v.subcols(0, self.used));
        let mut h = Mat::zeros(cap, cap);
        h.as_mut()
            .submatrix_mut(0, 0, self.used, self.used)
            .copy_from(self.h.submatrix(0, 0, self.used, self.used));
        self.v = v;
        self.h = h;
        self.cap = cap;
    }

    /// Requests `count` extra random directions in the next block (used when a
    /// Sturm count shows that eigenvalues are missing).
    pub fn inject_random(&mut self, count: usize) {
        self.inject += count;
    }

    /// Runs with the operator `OP = (K - sigma M)^-1` of the factor `op` until the `wanted`
    /// leading Ritz pairs have estimates below `tol`, or `max_steps` expansions have been made. Returns the leading `report` Ritz pairs
    /// (at least `wanted` if available) and whether the wanted ones converged.
    pub fn run(
        &mut self,
        op: &SparseCholesky,
        wanted: usize,
        report: usize,
        tol: f64,
        max_steps: usize,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<(RitzPairs, bool), FeError> {
        let mut steps = 0usize;
        if self.next.is_some() {
            // resume after a previous run: apply pending injections, then append
            let (theta, s, _) = self.rayleigh_ritz()?;
            self.inject_into_pending()?;
            self.append_next(&theta, s.as_ref(), wanted)?;
        }
        loop {
            self.expand(op)?;
            steps += 1;
            let (theta, s, est) = self.rayleigh_ritz()?;
            let conv = est.iter().take_while(|&&e| e <= tol).count();
            progress(self.used, conv);
            let done = conv >= wanted.min(theta.len());
            if done || steps >= max_steps {
                let p = report.max(wanted).min(theta.len());
                let vectors = self.ritz_vectors(s.as_ref(), p);
                let pairs = RitzPairs {
                    theta: theta[..p].to_vec(),
                    vectors,
                    estimate: est[..p].to_vec(),
                    basis: self.used,
                };
                return Ok((pairs, done));
            }
            self.append_next(&theta, s.as_ref(), wanted)?;
        }
    }

    /// Multiplies the last block by OP, orthogonalises it against the whole basis
    /// (two classical Gram-Schmidt passes) and stores the coefficients in `H`.
    fn expand(&mut self, op: &SparseCholesky) -> Result<(), FeError> {
        if self.next.is_some() {
            return Ok(());
        }
        let (ls, used) = (self.last, self.used);
        let bl = used - ls;
        let mut w = Mat::zeros(self.n, bl);
        sparse_dense_matmul(
            w.as_mut(),
            Accum::Replace,
            self.m.as_ref(),
            self.v.subcols(ls, bl),
            1.0,
            Par::Seq,
        );
        op.solve_in_place(w.as_mut());
        let c = self.project_out(&mut w, used);
        for j in 0..bl {
            for i in 0..used {
                self.h[(i, ls + j)] = c[(i, j)];
                self.h[(ls + j, i)] = c[(i, j)];
            }
        }
        for j in 0..bl {
            for i in 0..j {
                let a = 0.5 * (c[(ls + i, j)] + c[(ls + j, i)]);
                self.h[(ls + i, ls + j)] = a;
                self.h[(ls + j, ls + i)] = a;
            }
        }
        let room = self.n - used;
        let (q, b) = if room == 0 {
            (Mat::zeros(self.n, 0), Mat::zeros(0, bl))
        } else {
            self.m_orthonormalize(w, used, room)?
        };
        self.next = Some((q, b));
        self.inject_into_pending()
    }

    /// Adds the requested random directions to the pending next block.
    fn inject_into_pending(&mut self) -> Result<(), FeError> {
        if self.inject == 0 {
            return Ok(());
        }
        let used = self.used;
        let room = self.n - used;
        let Some((q, b)) = self.next.take() else {
            return Ok(());
        };
        let extra = self.inject.min(room.saturating_sub(q.ncols()));
        self.inject = 0;
        if extra == 0 {
            self.next = Some((q, b));
            return Ok(());
        }
        let r = self.random_block_against(extra, used, Some(q.as_ref()))?;
        let bl = b.ncols();
        let q = concat_cols(q.as_ref(), r.as_ref());
        let b = concat_rows(b.as_ref(), Mat::zeros(extra, bl).as_ref());
        self.next = Some((q, b));
        Ok(())
    }

    /// `W <- (I - V V^T M) W` twice (CGS2); returns the summed coefficients `V^T M W`.
    fn project_out(&self, w: &mut Mat<f64>, used: usize) -> Mat<f64> {
        let bl = w.ncols();
        let mut c = Mat::zeros(used, bl);
        let mut mw = Mat::zeros(self.n, bl);
        let mut ci = Mat::zeros(used, bl);
        let vb = self.v.subcols(0, used);
        for _ in 0..2 {
            sparse_dense_matmul(
                mw.as_mut(),
                Accum::Replace,
                self.m.as_ref(),
                w.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(
                ci.as_mut(),
                Accum::Replace,
                vb.transpose(),
                mw.as_ref(),
                1.0,
                Par::Seq,
            );
            matmul(w.as_mut(), Accum::Add, vb, ci.as_ref(), -1.0, Par::Seq);
            c += &ci;
        }
        c
    }

    /// M-orthonormalises `w` (already orthogonal to the first `used` basis vectors):
    /// `W = Q B` with `Q^T M Q = I`. Numerically dependent directions are dropped
    /// (zero rows of `B`) and replaced by random directions so the block keeps its size.
    fn m_orthonormalize(
        &mut self,
        w: Mat<f64>,
        used: usize,
        room: usize,
    ) -> Result<(Mat<f64>, Mat<f64>), FeError> {
        let bl = w.ncols();
        let (q, b) = self.gram_eigen_qr(w, used, 1e-20)?;
        let r = q.ncols();
        let want = bl.min(room);
        if r >= want {
            return Ok((q, b));
        }
        let fill = self.random_block_against(want - r, used, Some(q.as_ref()))?;
        let q = concat_cols(q.as_ref(), fill.as_ref());
        let b = concat_rows(b.as_ref(), Mat::zeros(want - r, bl).as_ref());
        Ok((q, b))
    }

    /// Eigen-based Cholesky-QR in the M-inner product, done twice (with a
    /// reprojection against the basis in between). Columns whose Gram eigenvalue
    /// is below `rel` times the largest column norm squared are dropped.
    fn gram_eigen_qr(
        &self,
        mut w: Mat<f64>,
        used: usize,
        rel: f64,
    ) -> Result<(Mat<f64>, Mat<f64>), FeError> {
        let bl = w.ncols();
        let mut b_total = Mat::<f64>::identity(bl, bl);
        let mut ref_norm = None;
        for pass in 0..2 {
            if pass == 1 {
                let _ = self.project_out(&mut w, used);
            }
            let mut mw = Mat::zeros(self.n, w.ncols());
            sparse_dense_matmul(
                mw.as_mut(),
                Accum::Replace,
                self.m.as_ref(),
                w.as_ref(),
                1.0,
                Par::Seq,
            );
            let g = w.transpose() * &mw;
            let g = Mat::from_fn(g.nrows(), g.ncols(), |i, j| 0.5 * (g[(i, j)] + g[(j, i)]));
            let gmax = (0..g.nrows()).map(|i| g[(i, i)]).fold(0.0f64, f64::max);
            let thr = rel * *ref_norm.get_or_insert(gmax);
            if g.nrows() == 0 || gmax <= 0.0 || !gmax.is_finite() {
                return Ok((Mat::zeros(self.n, 0), Mat::zeros(0, bl)));
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
            w = &w * &uk;
            b_total = &bk * &b_total;
        }
        Ok((w, b_total))
    }

    /// `count` random M-orthonormal vectors, orthogonal to the first `used` basis
    /// vectors and to `extra` (M-orthonormal columns), if given.
    fn random_block_against(
        &mut self,
        count: usize,
        used: usize,
        extra: Option<MatRef<'_, f64>>,
    ) -> Result<Mat<f64>, FeError> {
        for _attempt in 0..3 {
            let mut r = Mat::from_fn(self.n, count, |_, _| 0.0);
            for j in 0..count {
                for i in 0..self.n {
                    r[(i, j)] = self.rng.next_f64();
                }
            }
            for _ in 0..2 {
                if let Some(x) = extra {
                    let mut mr = Mat::zeros(self.n, count);
                    sparse_dense_matmul(
                        mr.as_mut(),
                        Accum::Replace,
                        self.m.as_ref(),
                        r.as_ref(),
                        1.0,
                        Par::Seq,
                    );
                    let c = x.transpose() * &mr;
                    r -= x * &c;
                }
                let _ = self.project_out(&mut r, used);
            }
            let (q, _) = self.gram_eigen_qr(r, used, 1e-14)?;
            if q.ncols() == count {
                return Ok(q);
            }
        }
        Err(FeError::EigenNotConverged(format!(
            "could not generate {count} new independent start vectors (basis {used} of {})",
            self.n
        )))
    }

    fn random_block(&mut self, count: usize) -> Result<Mat<f64>, FeError> {
        self.random_block_against(count, 0, None)
    }

    /// Eigen-decomposition of the projected matrix; Ritz values descending,
    /// eigenvector coefficients and residual estimates in the same order.
    fn rayleigh_ritz(&self) -> Result<RitzDecomposition, FeError> {
        let u = self.used;
        let hs = self.h.submatrix(0, 0, u, u).to_owned();
        let evd = hs.self_adjoint_eigen(Side::Lower).map_err(|e| {
            FeError::EigenNotConverged(format!("projected eigenproblem failed: {e:?}"))
        })?;
        let theta: Vec<f64> = (0..u).rev().map(|i| evd.S()[i]).collect();
        let s = Mat::from_fn(u, u, |i, j| evd.U()[(i, u - 1 - j)]);
        let (_, b) = self
            .next
            .as_ref()
            .expect("expand() precedes rayleigh_ritz()");
        let bl = u - self.last;
        let s_last = s.subrows(self.last, bl);
        let r = b * s_last; // rows: next block, cols: Ritz pairs
        let est = (0..u)
            .map(|j| {
                let nr = r.col(j).norm_l2();
                if theta[j].abs() > 0.0 {
                    nr / theta[j].abs()
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        Ok((theta, s, est))
    }

    fn ritz_vectors(&self, s: MatRef<'_, f64>, p: usize) -> Mat<f64> {
        let mut y = Mat::zeros(self.n, p);
        matmul(
            y.as_mut(),
            Accum::Replace,
            self.v.subcols(0, self.used),
            s.subcols(0, p),
            1.0,
            Par::Seq,
        );
        y
    }

    /// Appends the pending block `Q`; if the basis is full, first performs a thick
    /// restart keeping the leading Ritz vectors (`V <- [V S_k, Q]`, `H <- diag(theta_k)`).
    fn append_next(
        &mut self,
        theta: &[f64],
        s: MatRef<'_, f64>,
        wanted: usize,
    ) -> Result<(), FeError> {
        let (q, _b) = self.next.take().expect("expand() precedes append_next()");
        let bq = q.ncols();
        if bq == 0 {
            return Err(FeError::EigenNotConverged(format!(
                "Krylov space exhausted at basis size {} without convergence",
                self.used
            )));
        }
        if self.used + bq > self.cap {
            let keep = (wanted + self.block.max(wanted / 2))
                .min(self.cap.saturating_sub(2 * bq))
                .min(self.used);
            if keep == 0 {
                return Err(FeError::EigenNotConverged(format!(
                    "maximum basis size {} too small for block size {bq}",
                    self.cap
                )));
            }
            let y = self.ritz_vectors(s, keep);
            self.v.as_mut().subcols_mut(0, keep).copy_from(&y);
            self.h.fill(0.0);
            for (i, &t) in theta.iter().enumerate().take(keep) {
                self.h[(i, i)] = t;
            }
            self.used = keep;
        }
        let bq = bq.min(self.cap - self.used);
        self.v
            .as_mut()
            .subcols_mut(self.used, bq)
            .copy_from(q.subcols(0, bq));
        self.last = self.used;
        self.used += bq;
        Ok(())
    }
}

fn concat_cols(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let ca = a.ncols();
    Mat::from_fn(a.nrows(), ca + b.ncols(), |i, j| {
        if j < ca {
            a[(i, j)]
        } else {
            b[(i, j - ca)]
        }
    })
}

fn concat_rows(a: MatRef<'_, f64>, b: MatRef<'_, f64>) -> Mat<f64> {
    let ra = a.nrows();
    Mat::from_fn(ra + b.nrows(), a.ncols(), |i, j| {
        if i < ra {
            a[(i, j)]
        } else {
            b[(i - ra, j)]
        }
    })
}
