//! Block shift-invert Lanczos in the M-inner product with full (CGS2)
//! reorthogonalisation, thick restart and locking.
//!
//! Operator `OP = (K - sigma M)^{-1} M`, self-adjoint in `<x, y>_M = x^T M y`, with
//! eigenvalues `theta = 1 / (lambda - sigma)`; for `sigma` below the spectrum the
//! largest `theta` belong to the lowest `lambda`. The basis `V` (`V^T M V = I`) grows
//! block by block; the projected matrix `H = V^T M OP V` is formed explicitly from
//! the orthogonalisation coefficients (so it stays exact after restarts and random
//! injections), and the Krylov relation `OP V = V H + Q B E^T` (Q: next block)
//! gives the Ritz residual estimate `||OP y - theta y||_M = ||B E^T s||`.
//!
//! Locking: a Ritz pair whose estimate is below the tolerance is checked by its explicit residual
//! ([`super::ops::shift_invert_residuals`]); if that is below the tolerance too, the pair is
//! locked: its vector stays at the front of the basis (every new block is still orthogonalised
//! against it) but leaves the projected problem (its coupling to new blocks, of the size of its
//! residual, is dropped), so the basis capacity serves the pairs still converging and hundreds of
//! modes converge with a bounded basis.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};

use super::basis::{combine_in_place, empty_columns, SplitMix};
use super::cholesky::SparseCholesky;
use super::ops::{apply_mass, shift_invert_residuals};
use crate::{FeError, SparseMatrix};

mod orth;

/// Ritz pairs, ordered by increasing `lambda`.
#[derive(Debug)]
pub(crate) struct RitzPairs {
    /// Ritz values `lambda = sigma + 1 / theta` (infinity for `theta <= 0`), ascending.
    pub lambda: Vec<f64>,
    /// Ritz vectors (M-orthonormal) of the leading pairs (the wanted ones), `n x` at most
    /// `lambda.len()`.
    pub vectors: Mat<f64>,
    /// Relative residuals `||OP y - theta y||_M / theta`: explicit for locked pairs, the
    /// Krylov estimate for the others.
    pub estimate: Vec<f64>,
    /// Whether the pair is locked (its explicit residual is below the tolerance).
    pub locked: Vec<bool>,
    /// Current basis size.
    pub basis: usize,
}

/// An M-orthonormal block `Q`, its product `M Q` and the coefficients `B` (`W = Q B`).
type OrthonormalBlock = (Mat<f64>, Mat<f64>, Mat<f64>);

/// Ritz values (descending), coefficient vectors `S` and residual estimates.
type RitzDecomposition = (Vec<f64>, Mat<f64>, Vec<f64>);

/// The active part of the basis holds at most this many blocks ([`BlockLanczos::window`]).
const ACTIVE_WINDOW_BLOCKS: usize = 20;

/// How [`BlockLanczos::run`] ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Outcome {
    /// The wanted pairs are locked.
    Converged,
    /// Pairs whose estimates had converged failed the explicit residual test: the round-off
    /// floor of this shift is reached (a shift closer to them is needed).
    Stalled,
    /// The step budget ran out.
    Budget,
}

/// A Ritz pair of the merged list: locked (index into the locked pairs) or active (index into the
/// Ritz decomposition of the active part of the basis).
#[derive(Clone, Copy, Debug)]
enum Pair {
    Locked(usize),
    Active(usize),
}

/// State of a block shift-invert Lanczos run.
pub(crate) struct BlockLanczos<'a> {
    m: &'a SparseMatrix,
    n: usize,
    block: usize,
    cap: usize,
    /// Basis vectors in columns `0..used`.
    v: Mat<f64>,
    /// `M v` of the basis vectors (columns `0..used`): the M-inner products of the
    /// orthogonalisation read it instead of multiplying by `M` (two products per block step
    /// instead of seven).
    mv: Mat<f64>,
    /// Projected operator `V^T M OP V`.
    h: Mat<f64>,
    used: usize,
    /// Start column of the last block of `v` (not yet multiplied by OP).
    last: usize,
    /// Next block `Q`, its `M Q` and the coupling `B` (`Q B = (I - V V^T M) OP V_last`), if
    /// computed.
    next: Option<OrthonormalBlock>,
    /// Number of extra random vectors to add to the next block.
    inject: usize,
    rng: SplitMix,
    /// Number of locked pairs: their vectors are the columns `0..locked` of `v`.
    locked: usize,
    /// Eigenvalues of the locked pairs (from the explicit Rayleigh quotients of `OP`).
    locked_lambda: Vec<f64>,
    /// Explicit residuals of the locked pairs.
    locked_res: Vec<f64>,
    /// Ritz estimates must be below `tol * estimate_factor` before a pair is checked explicitly
    /// (lowered when estimates and explicit residuals disagree).
    estimate_factor: f64,
    /// Ritz values below this are not wanted (see [`Self::ritz_lambda`]).
    lambda_floor: f64,
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
            v: empty_columns(n, cap),
            mv: empty_columns(n, cap),
            h: Mat::zeros(cap, cap),
            used: 0,
            last: 0,
            next: None,
            inject: 0,
            rng: SplitMix(seed),
            locked: 0,
            locked_lambda: Vec::new(),
            locked_res: Vec::new(),
            estimate_factor: 1.0,
            lambda_floor: f64::INFINITY,
        };
        let (q, mq) = s.random_block(block)?;
        s.grow_to(block);
        s.v.as_mut().subcols_mut(0, block).copy_from(&q);
        s.mv.as_mut().subcols_mut(0, block).copy_from(&mq);
        s.used = block;
        Ok(s)
    }

    /// Raises the maximum basis size to at least `cap` (at most `n`), keeping the basis.
    pub fn ensure_capacity(&mut self, cap: usize) {
        let cap = cap.min(self.n);
        if cap <= self.cap {
            return;
        }
        self.v.reserve(self.n, cap);
        self.mv.reserve(self.n, cap);
        let mut h = Mat::zeros(cap, cap);
        h.as_mut()
            .submatrix_mut(0, 0, self.used, self.used)
            .copy_from(self.h.submatrix(0, 0, self.used, self.used));
        self.h = h;
        self.cap = cap;
    }

    /// Frees the stored `M V` (for the Sturm check's factorization, the peak of the modal
    /// analysis' memory); the next [`Self::run`] or [`Self::reshift`] recomputes it.
    pub fn release_mass_products(&mut self) {
        self.mv = empty_columns(self.n, 0);
    }

    /// Recomputes `M V` after [`Self::release_mass_products`].
    fn restore_mass_products(&mut self) {
        if self.mv.ncols() >= self.v.ncols() {
            return;
        }
        self.mv = empty_columns(self.n, self.cap);
        self.mv.resize_with(self.n, self.v.ncols(), |_, _| 0.0);
        apply_mass(self.m, self.v.as_ref(), self.mv.as_mut());
    }

    /// Makes the first `cols` columns of `V` and `M V` addressable (within the capacity; new
    /// columns zero). The bases grow with the basis instead of being allocated (and their memory
    /// touched) at the full capacity up front.
    fn grow_to(&mut self, cols: usize) {
        if cols > self.v.ncols() {
            self.v.resize_with(self.n, cols, |_, _| 0.0);
            self.mv.resize_with(self.n, cols, |_, _| 0.0);
        }
    }

    /// Requests `count` extra random directions in the next block (used when a
    /// Sturm count shows that eigenvalues are missing).
    pub fn inject_random(&mut self, count: usize) {
        self.inject += count;
    }

    /// Runs with the operator `OP = (K - sigma M)^-1 M` of the factor `op` until the `wanted`
    /// leading Ritz pairs are locked (explicit residual below `tol`), or `max_steps` expansions
    /// have been made. Returns the leading `report` Ritz pairs (at least `wanted` if available)
    /// and whether the wanted ones converged.
    ///
    /// After [`Outcome::Stalled`] or [`Outcome::Budget`] the Krylov space is restarted from the
    /// leading unconverged Ritz vectors (kept, with the locked pairs), ready for a new shift.
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &mut self,
        op: &SparseCholesky,
        sigma: f64,
        wanted: usize,
        report: usize,
        tol: f64,
        max_steps: usize,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<(RitzPairs, Outcome), FeError> {
        let mut steps = 0usize;
        self.restore_mass_products();
        if self.next.is_some() {
            // resume after a previous run: apply pending injections, then append
            let (theta, s, _) = self.rayleigh_ritz()?;
            self.inject_into_pending()?;
            self.advance(&theta, s.as_ref(), &[], wanted, false)?;
        }
        loop {
            self.expand(op)?;
            steps += 1;
            let (theta, s, est) = self.rayleigh_ritz()?;
            let order = self.merged_order(&theta, sigma);
            let want = wanted.min(order.len());
            let est_tol = tol * self.estimate_factor;
            let settled = |p: &Pair| match *p {
                Pair::Locked(_) => true,
                Pair::Active(j) => est[j] <= est_tol,
            };
            let lead = order.iter().take_while(|p| settled(p)).count();
            let locked_lead = order
                .iter()
                .take_while(|p| matches!(p, Pair::Locked(_)))
                .count();
            progress(self.used, lead);
            let p = report.max(want);
            if locked_lead >= want {
                let pairs = self.report(&order, (&theta, s.as_ref(), &est), sigma, &[], (p, want));
                return Ok((pairs, Outcome::Converged));
            }
            let pending = self.next.as_ref().map_or(0, |(q, _, _)| q.ncols());
            let full =
                self.used + pending > self.cap || self.used - self.locked + pending > self.window();
            let mut lock = Vec::new();
            let mut stalled = false;
            if lead >= want || full {
                let cand: Vec<usize> = order[..want]
                    .iter()
                    .filter_map(|p| match *p {
                        Pair::Active(j) if est[j] <= est_tol => Some(j),
                        _ => None,
                    })
                    .collect();
                lock = self.verify(op, sigma, s.as_ref(), &cand, tol);
                stalled = lock.len() < cand.len();
                let verified = |q: &Pair| match *q {
                    Pair::Locked(_) => true,
                    Pair::Active(j) => lock.iter().any(|l| l.0 == j),
                };
                if !stalled && order[..want].iter().all(verified) {
                    // every wanted pair has passed its explicit check: done, without the
                    // restart that would lock them (the next block stays pending: a run resumed
                    // after a Sturm check starts from this Krylov space and checks them again)
                    let pairs =
                        self.report(&order, (&theta, s.as_ref(), &est), sigma, &lock, (p, want));
                    return Ok((pairs, Outcome::Converged));
                }
            }
            if stalled || steps >= max_steps {
                let pairs =
                    self.report(&order, (&theta, s.as_ref(), &est), sigma, &lock, (p, want));
                self.next = None;
                self.thick_restart(&theta, s.as_ref(), &lock, want, true, 0)?;
                self.fresh_start()?;
                let outcome = if stalled {
                    Outcome::Stalled
                } else {
                    Outcome::Budget
                };
                return Ok((pairs, outcome));
            }
            self.advance(&theta, s.as_ref(), &lock, want, full)?;
        }
    }

    /// `steps` block expansions without restart or locking (at most until the basis is full);
    /// returns the Ritz values `lambda` (ascending, `theta > 0` only). The last block's product is
    /// pending, so [`Self::run`] at the same shift resumes from this Krylov space.
    pub fn probe(
        &mut self,
        op: &SparseCholesky,
        sigma: f64,
        steps: usize,
    ) -> Result<Vec<f64>, FeError> {
        for step in 0..steps {
            self.expand(op)?;
            let pending = self.next.as_ref().map_or(0, |(q, _, _)| q.ncols());
            if step + 1 == steps || self.used + pending > self.cap {
                break;
            }
            let (theta, s, _) = self.rayleigh_ritz()?;
            self.advance(&theta, s.as_ref(), &[], 0, false)?;
        }
        let (theta, _, _) = self.rayleigh_ritz()?;
        let mut lam: Vec<f64> = theta
            .iter()
            .filter(|&&t| t > 0.0)
            .map(|t| sigma + 1.0 / t)
            .collect();
        lam.sort_by(f64::total_cmp);
        Ok(lam)
    }

    /// Largest active (not locked) part of the basis before a thick restart: the projected
    /// eigenproblem of this size is solved at every step (cubic cost), so with hundreds of
    /// locked pairs the active part stays small.
    fn window(&self) -> usize {
        (ACTIVE_WINDOW_BLOCKS * self.block).max(40)
    }

    /// [`Self::window`], at least four pending blocks of `bq` columns (a block enlarged by random
    /// directions after a failed Sturm check must leave room for kept Ritz vectors).
    fn window_for(&self, bq: usize) -> usize {
        self.window().max(4 * bq)
    }

    /// Eigenvalues of the locked pairs.
    pub fn locked_lambda(&self) -> &[f64] {
        &self.locked_lambda
    }

    /// Lowers the threshold on the Ritz estimates below which pairs are checked explicitly
    /// (tenfold, down to 1e-4 of the tolerance); `false` if already at the floor.
    pub fn distrust_estimates(&mut self) -> bool {
        if self.estimate_factor <= 1e-4 {
            return false;
        }
        self.estimate_factor *= 0.1;
        true
    }

    /// Starts a new Krylov space (for a new operator): the locked vectors stay, the start block is
    /// the leading kept Ritz vectors after a thick restart (random directions if there are too
    /// few), `H` is cleared.
    fn fresh_start(&mut self) -> Result<(), FeError> {
        let kept = self.used - self.locked;
        let b = self.block.min(kept).min(self.n - self.locked);
        self.used = self.locked + b;
        let fill = self.block.min(self.n - self.locked) - b;
        if fill > 0 {
            let (r, mr) = self.random_block_against(fill, self.used, None)?;
            self.grow_to(self.used + fill);
            self.v.as_mut().subcols_mut(self.used, fill).copy_from(&r);
            self.mv.as_mut().subcols_mut(self.used, fill).copy_from(&mr);
            self.used += fill;
        }
        self.last = self.locked;
        self.next = None;
        self.h.fill(0.0);
        Ok(())
    }

    /// `lambda = sigma + 1 / theta` of a Ritz value `theta` of `OP`; infinity (not wanted) for
    /// `theta = 0` and for `theta < 0` unless `lambda` lies above the lowest unlocked eigenvalue
    /// of a slice ([`Self::reshift`]; below a shift under the spectrum, negative `theta` are
    /// round-off).
    fn ritz_lambda(&self, sigma: f64, theta: f64) -> f64 {
        let l = sigma + 1.0 / theta;
        if theta > 0.0 || (theta < 0.0 && l >= self.lambda_floor) {
            l
        } else {
            f64::INFINITY
        }
    }

    /// Prepares a new shift inside the spectrum (spectrum slicing), after a run that did not
    /// converge: the locked pairs with `lambda >= unlock_from` are unlocked and join the leading
    /// Ritz vectors in the start block of a new Krylov space (a locked vector is accurate to its
    /// residual times `(lambda_u - sigma) / (lambda_u - lambda)` in the direction of a pair `u` not
    /// yet converged: near neighbours, deflated, would keep that pair from converging; with the
    /// new shift they converge again, to the tolerance, in a few steps).
    pub fn reshift(&mut self, unlock_from: f64) {
        self.restore_mass_products();
        let (l, used) = (self.locked, self.used);
        let keep: Vec<usize> = (0..l)
            .filter(|&i| self.locked_lambda[i] < unlock_from)
            .collect();
        let free: Vec<usize> = (0..l)
            .filter(|&i| self.locked_lambda[i] >= unlock_from)
            .collect();
        let order: Vec<usize> = keep.iter().chain(&free).copied().chain(l..used).collect();
        for basis in [&mut self.v, &mut self.mv] {
            let v = Mat::from_fn(self.n, used, |i, j| basis[(i, order[j])]);
            basis.as_mut().subcols_mut(0, used).copy_from(&v);
        }
        self.locked_lambda = keep.iter().map(|&i| self.locked_lambda[i]).collect();
        self.locked_res = keep.iter().map(|&i| self.locked_res[i]).collect();
        self.locked = keep.len();
        self.last = self.locked;
        self.next = None;
        self.h.fill(0.0);
        self.lambda_floor = unlock_from;
        let width = used - self.locked;
        self.ensure_capacity(self.locked + 4 * width);
    }

    /// Locked and active pairs merged in the order of increasing `lambda` (active pairs with
    /// `theta <= 0`, i.e. below a shift inside the spectrum or numerically null, last).
    fn merged_order(&self, theta: &[f64], sigma: f64) -> Vec<Pair> {
        let mut order: Vec<(f64, Pair)> = (0..self.locked)
            .map(|i| (self.locked_lambda[i], Pair::Locked(i)))
            .chain(
                theta
                    .iter()
                    .enumerate()
                    .map(|(j, &t)| (self.ritz_lambda(sigma, t), Pair::Active(j))),
            )
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        order.into_iter().map(|(_, p)| p).collect()
    }

    /// Explicit residuals of the active Ritz pairs `cand`; returns those below `tol` as
    /// `(index, lambda, residual)`.
    fn verify(
        &self,
        op: &SparseCholesky,
        sigma: f64,
        s: MatRef<'_, f64>,
        cand: &[usize],
        tol: f64,
    ) -> Vec<(usize, f64, f64)> {
        // at most two blocks of candidates at a time, in equal parts: the check's vectors (three
        // n x part arrays) stay small beside the basis whatever the number of candidates, and
        // each solve serves as many columns as it can (a solve reads the whole factor)
        let parts = cand.len().div_ceil(2 * self.block.max(1)).max(1);
        let mut out = Vec::new();
        for part in cand.chunks(cand.len().div_ceil(parts).max(1)) {
            let mut y = self.ritz_vectors(s, part);
            let (lam, res) = shift_invert_residuals(op, self.m, sigma, &mut y);
            out.extend(
                part.iter()
                    .zip(lam.iter().zip(&res))
                    .filter(|(_, (_, &r))| r <= tol)
                    .map(|(&j, (&l, &r))| (j, l, r)),
            );
        }
        out
    }

    /// The leading `p` pairs of the merged list, with the vectors of the first `nv` (the others
    /// only bound the next eigenvalues); the active pairs in `lock` (index, explicit `lambda`,
    /// residual) are reported as locked.
    fn report(
        &self,
        order: &[Pair],
        (theta, s, est): (&[f64], MatRef<'_, f64>, &[f64]),
        sigma: f64,
        lock: &[(usize, f64, f64)],
        (p, nv): (usize, usize),
    ) -> RitzPairs {
        let p = p.min(order.len());
        let nv = nv.min(p);
        // runs of consecutive active pairs are combined straight into their columns (no second
        // n x p array beside the basis: the end of a run is the modal analysis' memory peak)
        let mut vectors = Mat::zeros(self.n, nv);
        let mut c = 0;
        while c < nv {
            let end = (c..nv)
                .find(|&e| matches!(order[e], Pair::Locked(_)))
                .unwrap_or(nv);
            if end == c {
                if let Pair::Locked(i) = order[c] {
                    vectors.col_mut(c).copy_from(self.v.col(i));
                }
                c += 1;
                continue;
            }
            let cols: Vec<usize> = order[c..end]
                .iter()
                .filter_map(|q| match *q {
                    Pair::Active(j) => Some(j),
                    Pair::Locked(_) => None,
                })
                .collect();
            self.active_combination_into(&self.v, s, &cols, vectors.subcols_mut(c, end - c));
            c = end;
        }
        let (mut th, mut estimate, mut locked) = (Vec::new(), Vec::new(), Vec::new());
        for q in &order[..p] {
            match *q {
                Pair::Locked(i) => {
                    th.push(self.locked_lambda[i]);
                    estimate.push(self.locked_res[i]);
                    locked.push(true);
                }
                Pair::Active(j) => match lock.iter().find(|l| l.0 == j) {
                    Some(&(_, l, r)) => {
                        th.push(l);
                        estimate.push(r);
                        locked.push(true);
                    }
                    None => {
                        th.push(self.ritz_lambda(sigma, theta[j]));
                        estimate.push(est[j]);
                        locked.push(false);
                    }
                },
            }
        }
        RitzPairs {
            lambda: th,
            vectors,
            estimate,
            locked,
            basis: self.used,
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
        let mut w = self.mv.subcols(ls, bl).to_owned();
        op.solve_in_place(w.as_mut());
        let c = self.project_out(&mut w, used, 2);
        // rows of locked pairs stay zero: their coupling is of the size of their residual
        for j in 0..bl {
            for i in self.locked..used {
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
        let next = if room == 0 {
            (
                Mat::zeros(self.n, 0),
                Mat::zeros(self.n, 0),
                Mat::zeros(0, bl),
            )
        } else {
            self.m_orthonormalize(w, used, room)?
        };
        self.next = Some(next);
        self.inject_into_pending()
    }

    /// Eigen-decomposition of the projected matrix of the active (not locked) part of the
    /// basis; Ritz values descending, eigenvector coefficients (rows: active basis columns
    /// `locked..used`) and residual estimates in the same order.
    fn rayleigh_ritz(&self) -> Result<RitzDecomposition, FeError> {
        let (l, u) = (self.locked, self.used);
        let a = u - l;
        let hs = self.h.submatrix(l, l, a, a).to_owned();
        let evd = hs.self_adjoint_eigen(Side::Lower).map_err(|e| {
            FeError::EigenNotConverged(format!("projected eigenproblem failed: {e:?}"))
        })?;
        let theta: Vec<f64> = (0..a).rev().map(|i| evd.S()[i]).collect();
        let s = Mat::from_fn(a, a, |i, j| evd.U()[(i, a - 1 - j)]);
        let (_, _, b) = self
            .next
            .as_ref()
            .expect("expand() precedes rayleigh_ritz()");
        let bl = u - self.last;
        let s_last = s.subrows(self.last - l, bl);
        let r = b * s_last; // rows: next block, cols: Ritz pairs
        let est = (0..a)
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

    /// The active Ritz vectors `V_active S[:, cols]`.
    fn ritz_vectors(&self, s: MatRef<'_, f64>, cols: &[usize]) -> Mat<f64> {
        self.active_combination(&self.v, s, cols)
    }

    /// `B_active S[:, cols]` for the basis `B` (`V` or `M V`).
    fn active_combination(&self, basis: &Mat<f64>, s: MatRef<'_, f64>, cols: &[usize]) -> Mat<f64> {
        let mut y = Mat::zeros(self.n, cols.len());
        self.active_combination_into(basis, s, cols, y.as_mut());
        y
    }

    /// [`Self::active_combination`] into `out` (`n x cols.len()`).
    fn active_combination_into(
        &self,
        basis: &Mat<f64>,
        s: MatRef<'_, f64>,
        cols: &[usize],
        out: MatMut<'_, f64>,
    ) {
        let sc = Mat::from_fn(s.nrows(), cols.len(), |i, j| s[(i, cols[j])]);
        matmul(
            out,
            Accum::Replace,
            basis.subcols(self.locked, self.used - self.locked),
            sc.as_ref(),
            1.0,
            Par::Seq,
        );
    }

    /// Appends the pending block `Q`. First, if pairs are to be locked (`lock`: active index,
    /// explicit `lambda`, residual) or the basis is full (`full`), performs a thick restart
    /// `V <- [V_locked, Y_lock, Y_keep, Q]`, `H <- diag(theta)` on the active part: all other
    /// Ritz vectors are kept when only locking, the leading `wanted + max(block, wanted / 2)`
    /// (within the capacity) when full.
    fn advance(
        &mut self,
        theta: &[f64],
        s: MatRef<'_, f64>,
        lock: &[(usize, f64, f64)],
        wanted: usize,
        full: bool,
    ) -> Result<(), FeError> {
        let (q, mq, _b) = self.next.take().expect("expand() precedes advance()");
        let bq = q.ncols();
        if bq == 0 {
            return Err(FeError::EigenNotConverged(format!(
                "Krylov space exhausted at basis size {} without convergence",
                self.used
            )));
        }
        if full || !lock.is_empty() {
            self.thick_restart(theta, s, lock, wanted, full, bq)?;
        }
        let bq = bq.min(self.cap - self.used);
        self.grow_to(self.used + bq);
        self.v
            .as_mut()
            .subcols_mut(self.used, bq)
            .copy_from(q.subcols(0, bq));
        self.mv
            .as_mut()
            .subcols_mut(self.used, bq)
            .copy_from(mq.subcols(0, bq));
        self.last = self.used;
        self.used += bq;
        Ok(())
    }

    /// The restart of [`Self::advance`] (before the pending block of `bq` columns is appended).
    fn thick_restart(
        &mut self,
        theta: &[f64],
        s: MatRef<'_, f64>,
        lock: &[(usize, f64, f64)],
        wanted: usize,
        full: bool,
        bq: usize,
    ) -> Result<(), FeError> {
        let locked_after = self.locked + lock.len();
        let rest: Vec<usize> = (0..theta.len())
            .filter(|j| !lock.iter().any(|l| l.0 == *j))
            .collect();
        let keep = if full {
            let open = wanted.saturating_sub(locked_after);
            (open + self.block.max(open / 2))
                .min(self.cap.saturating_sub(locked_after + 2 * bq))
                .min(self.window_for(bq).saturating_sub(2 * bq.max(self.block)))
                .min(rest.len())
        } else {
            rest.len().min(self.cap.saturating_sub(locked_after + bq))
        };
        if keep == 0 && locked_after < wanted {
            return Err(FeError::EigenNotConverged(format!(
                "maximum basis size {} too small for block size {bq} with {locked_after} locked pairs",
                self.cap
            )));
        }
        let cols: Vec<usize> = lock
            .iter()
            .map(|l| l.0)
            .chain(rest[..keep].iter().copied())
            .collect();
        let sc = Mat::from_fn(s.nrows(), cols.len(), |i, j| s[(i, cols[j])]);
        let (l, active) = (self.locked, self.used - self.locked);
        combine_in_place(&mut self.v, l, active, sc.as_ref());
        combine_in_place(&mut self.mv, l, active, sc.as_ref());
        self.h.fill(0.0);
        for &(_, t, r) in lock {
            self.locked_lambda.push(t);
            self.locked_res.push(r);
        }
        self.locked = locked_after;
        for (c, &j) in rest[..keep].iter().enumerate() {
            self.h[(locked_after + c, locked_after + c)] = theta[j];
        }
        self.used = locked_after + keep;
        Ok(())
    }
}
