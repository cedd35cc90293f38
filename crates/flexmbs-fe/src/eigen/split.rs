//! Two-domain factorization of `A = K - s M` for two threads.
//!
//! METIS' top-level bisection ([`super::ordering::metis_two_domains`]) splits the unknowns into
//! two domains that no entry couples and their separator `S`:
//!
//! ```text
//!     | A_11   0    A_1S |
//! A = |  0    A_22  A_2S |
//!     | A_S1  A_S2  A_SS |
//! ```
//!
//! Each *half* `H_i = [[A_ii, A_iS], [A_Si, A_SS]]` is a principal submatrix of `A` (positive
//! definite if `A` is) and is factored on its own thread by faer's supernodal factorization (which
//! is sequential over the elimination tree): `H_i = L_i D_i L_i^T` with the trailing block
//! `R_i = L_Si D_Si L_Si^T = A_SS - A_Si A_ii^-1 A_iS`. The Schur complement of both domains,
//! `C = A_SS - A_S1 A_11^-1 A_1S - A_S2 A_22^-1 A_2S = R_1 + R_2 - A_SS`, is small and dense
//! (`L L^T`, or Bunch-Kaufman `L B L^T` for an indefinite `A`). Inertia (Sylvester, block
//! elimination): `In(A) = In(D_1 on domain 1) + In(D_2 on domain 2) + In(C)`. Solves (`D = I`
//! for `L L^T`; `L_i = [[L_ii, 0], [L_Si', L_Si]]`): one forward substitution of `H_i` on
//! `[b_i; 0]` gives `y_i = L_ii^-1 b_i` and `z_i` with `L_Si z_i = -L_Si' y_i` (the domain's
//! update of the separator); `x_S = C^-1 (b_S + L_S1 z_1 + L_S2 z_2)`; one backward substitution
//! of `H_i` on `[D_ii^-1 y_i; L_Si^T x_S]` gives `x_i` (and `x_S` again).
//!
//! The halves run on two fixed threads whatever the machine, so results do not depend on it.
//! Each thread reads only its half of the factor in a solve (the solves are memory-bound).

use faer::linalg::cholesky::ldlt::factor::LdltParams;
use faer::linalg::solvers::{Lblt, Llt, Solve};

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
    solve_unit_upper_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef as LltRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SymbolicSupernodalCholesky, CholeskySymbolicParams,
    SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::SparseColMatRef;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side, Spec};

use super::cholesky::{factor_bytes, refactor_llt, zeros_or_refused, ShiftedPattern};
use super::inertia::{ldlt_diagonal, ldlt_numeric, Inertia};
use super::ordering::TwoDomains;
use crate::{FeError, SparseMatrix};

/// Models from this dimension on are factored in two domains (when METIS' separator is small,
/// [`accept`]).
pub(super) const SPLIT_MIN_DIM: usize = 20_000;

/// Whether the two domains pay: each domain holds at least an eighth of the unknowns and the
/// separator (dense, `O(ns^3)` work and `O(ns^2)` memory) at most a tenth and 6000 DOFs.
pub(super) fn accept(d: &TwoDomains) -> bool {
    let n = d.first + d.second + d.separator;
    8 * d.first.min(d.second) >= n && 10 * d.separator <= n && d.separator <= 6000
}

/// One domain with the separator: the ordered lower triangle of `H_i`, its symbolic analysis
/// and factor.
#[derive(Debug)]
struct Half {
    /// Rows of `H_i`: the domain's DOFs (original indices), then the separator's (32-bit
    /// indices).
    pattern: ShiftedPattern<u32>,
    symbolic: SymbolicCholesky<u32>,
    values: Vec<f64>,
    /// DOFs of the domain (the leading block).
    inner: usize,
    /// Pivots `D_ii` of the domain (`L D L^T` only).
    pivots: Vec<f64>,
    /// Trailing block `L_Si` (dense lower, unit diagonal for `L D L^T`).
    l_sep: Mat<f64>,
    /// The solves' work vector, kept between solves.
    work: std::sync::Mutex<Vec<f64>>,
    /// Longest off-diagonal pattern of a supernode (rows of the solves' update buffer).
    update_rows: usize,
}

/// The dense factor of the separator's Schur complement `C`.
#[derive(Debug)]
enum Schur {
    Llt(Llt<f64>),
    Lblt(Lblt<f64>),
}

/// Factor of `K - s M` in two domains and their separator (see the module documentation).
#[derive(Debug)]
pub(super) struct SplitFactor {
    halves: [Half; 2],
    /// Separator DOFs (original indices), in the order of the halves' trailing blocks.
    sep: Vec<usize>,
    schur: Option<Schur>,
}

impl Half {
    /// Pattern and symbolic analysis (supernodal, identity ordering) of the half with the
    /// domain `dofs` and the separator `sep` (original indices, in this order).
    fn new(
        k: &SparseMatrix,
        m: &SparseMatrix,
        dofs: &[usize],
        sep: &[usize],
    ) -> Result<Self, FeError> {
        let fwd: Vec<usize> = dofs.iter().chain(sep).copied().collect();
        let mut inv = vec![usize::MAX; k.nrows()];
        for (h, &o) in fwd.iter().enumerate() {
            inv[o] = h;
        }
        let pattern = ShiftedPattern::<u32>::new(k, m, fwd, inv)
            .ok_or_else(|| FeError::Invalid("a domain is too large for 32-bit indices".into()))?;
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(
            pattern.upper().as_ref(),
            Side::Upper,
            SymmetricOrdering::Identity,
            params,
        )
        .map_err(|e| FeError::Invalid(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        let update_rows = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(sn) => (0..sn.n_supernodes())
                .map(|s| sn.supernode(s).pattern().len())
                .max()
                .unwrap_or(0),
            SymbolicCholeskyRaw::Simplicial(_) => unreachable!("halves are forced supernodal"),
        };
        Ok(Self {
            pattern,
            symbolic,
            values: Vec::new(),
            inner: dofs.len(),
            pivots: Vec::new(),
            l_sep: Mat::new(),
            work: std::sync::Mutex::new(Vec::new()),
            update_rows,
        })
    }

    fn supernodal(&self) -> &SymbolicSupernodalCholesky<u32> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => s,
            SymbolicCholeskyRaw::Simplicial(_) => unreachable!("halves are forced supernodal"),
        }
    }

    /// Bytes of the factor and its workspace.
    fn bytes(&self) -> u64 {
        let req = self
            .symbolic
            .factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Spec::<LdltParams, f64>::default());
        factor_bytes(self.symbolic.len_val(), req.size_bytes()) + 8 * self.pattern.nnz() as u64
    }

    /// Factors `H_i` of `K - s M` (`L L^T`, or `L D L^T` without pivoting if `ldlt`) and keeps
    /// `L_Si` (and `D_ii`). Returns `R_i = L_Si D_Si L_Si^T`, `A_SS` (dense; if `with_a_ss`: both
    /// halves hold it, one copy serves) and the largest `|a_jj|` of the half; `Ok(None)`: a pivot
    /// vanished (`L D L^T`) or was not positive (`L L^T`).
    fn factor(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
        (ldlt, with_a_ss): (bool, bool),
    ) -> Result<Option<HalfSchur>, FeError> {
        if self.values.len() != self.symbolic.len_val() {
            self.values = zeros_or_refused(self.symbolic.len_val())?;
        }
        let lower = self.pattern.values(k, m, s)?;
        let a = SparseColMatRef::new(self.pattern.symbolic.as_ref(), &lower);
        let (a_ss, scale) = separator_block(a, self.inner, with_a_ss);
        let ok = if ldlt {
            ldlt_numeric(&self.symbolic, a, &mut self.values)?
        } else {
            refactor_llt(&self.symbolic, a, &mut self.values).is_ok()
        };
        drop(lower);
        if !ok {
            return Ok(None);
        }
        let (l_sep, d_sep) = trailing_block(self.supernodal(), &self.values, self.inner, ldlt);
        self.pivots = if ldlt {
            ldlt_diagonal(&self.symbolic, &self.values)[..self.inner].to_vec()
        } else {
            Vec::new()
        };
        let mut ld = l_sep.clone();
        for (j, d) in d_sep.iter().enumerate() {
            ld.col_mut(j).iter_mut().for_each(|v| *v *= d);
        }
        let r = &ld * l_sep.transpose();
        self.l_sep = l_sep;
        Ok(Some(HalfSchur { r, a_ss, scale }))
    }

    /// `[b_i; 0]` from the rows of `rhs`, forward substitution with `L_i`, `D_ii^-1` on the
    /// domain's part: returns the work vector and `L_Si z_i` (the separator's update).
    /// `work` holds the work vector (kept between solves: no fresh pages per solve).
    fn forward<'w>(
        &self,
        rhs: MatRef<'_, f64>,
        ldlt: bool,
        work: &'w mut Vec<f64>,
    ) -> (MatMut<'w, f64>, Mat<f64>) {
        let (nh, p) = (self.pattern.fwd.len(), rhs.ncols());
        work.clear();
        work.resize(nh * p, 0.0);
        let mut x = MatMut::from_column_major_slice_mut(&mut work[..], nh, p);
        for c in 0..p {
            for (h, &o) in self.pattern.fwd[..self.inner].iter().enumerate() {
                x[(h, c)] = rhs[(o, c)];
            }
        }
        lower_solve(
            self.supernodal(),
            &self.values,
            self.update_rows,
            ldlt,
            x.as_mut(),
        );
        for (h, d) in self.pivots.iter().enumerate() {
            for c in 0..p {
                x[(h, c)] /= d;
            }
        }
        let t = &self.l_sep * x.rb().subrows(self.inner, nh - self.inner);
        (x, t)
    }

    /// Backward substitution with `L_i^T` on `[D_ii^-1 y_i; L_Si^T x_S]` (`x` from
    /// [`Self::forward`]): the domain's part of `x` becomes the solution on the domain.
    fn backward(&self, mut x: MatMut<'_, f64>, x_sep: MatRef<'_, f64>, ldlt: bool) {
        let nh = x.nrows();
        let w = self.l_sep.transpose() * x_sep;
        x.rb_mut()
            .subrows_mut(self.inner, nh - self.inner)
            .copy_from(&w);
        upper_solve(self.supernodal(), &self.values, self.update_rows, ldlt, x);
    }
}

/// What a factored half contributes to the separator's Schur complement.
struct HalfSchur {
    /// `R_i = L_Si D_Si L_Si^T = A_SS - A_Si A_ii^-1 A_iS`.
    r: Mat<f64>,
    /// `A_SS`, dense (from one half only).
    a_ss: Option<Mat<f64>>,
    /// Largest `|a_jj|` of the half.
    scale: f64,
}

impl SplitFactor {
    /// The halves' patterns and symbolic analyses for the ordering `fwd` (`fwd[new] = old`,
    /// domains then separator, sizes `d`), built on two threads; `on_estimate(nnz_l, bytes)`
    /// before any numeric work (memory guard as for one factor).
    pub(super) fn new(
        k: &SparseMatrix,
        m: &SparseMatrix,
        fwd: &[usize],
        d: TwoDomains,
        on_estimate: &mut dyn FnMut(usize, u64),
    ) -> Result<Self, FeError> {
        let (dom1, rest) = fwd.split_at(d.first);
        let (dom2, sep) = rest.split_at(d.second);
        let (h1, h2) = std::thread::scope(|sc| {
            let h = sc.spawn(|| Half::new(k, m, dom2, sep));
            let h1 = Half::new(k, m, dom1, sep);
            (
                h1,
                h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
            )
        });
        let halves = [h1?, h2?];
        let nnz_l = halves.iter().map(|h| h.symbolic.len_val()).sum();
        let dense = 8 * 5 * (d.separator * d.separator) as u64;
        let bytes = halves.iter().map(Half::bytes).sum::<u64>() + dense;
        on_estimate(nnz_l, bytes);
        crate::memory::check_allocation(
            &format!(
                "the sparse Cholesky factor of {} equations (two domains)",
                fwd.len()
            ),
            bytes,
        )?;
        Ok(Self {
            halves,
            sep: sep.to_vec(),
            schur: None,
        })
    }

    /// Dimension of the factored matrix.
    pub(super) fn dim(&self) -> usize {
        self.halves.iter().map(|h| h.inner).sum::<usize>() + self.sep.len()
    }

    /// Entries of the halves' factors.
    pub(super) fn nnz_l(&self) -> usize {
        self.halves.iter().map(|h| h.symbolic.len_val()).sum()
    }

    /// `L L^T` of `K - s M`; [`FeError::NotPositiveDefinite`] if it is not positive definite.
    pub(super) fn factor_llt(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
    ) -> Result<(), FeError> {
        let not_pd = || FeError::NotPositiveDefinite {
            what: format!("sparse matrix of dimension {}", k.nrows()),
            hint: " (two-domain factorization)".into(),
        };
        self.schur = None;
        let (c, _) = self.factor_halves(k, m, s, false)?.ok_or_else(not_pd)?;
        let llt = c.llt(Side::Lower).map_err(|_| not_pd())?;
        self.schur = Some(Schur::Llt(llt));
        Ok(())
    }

    /// `L D L^T` of `K - s M` (halves without pivoting, the Schur complement with Bunch-Kaufman
    /// pivoting) and its inertia; `None` if a pivot of a half vanished (count unreliable).
    pub(super) fn factor_ldlt(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
    ) -> Result<Option<Inertia>, FeError> {
        self.schur = None;
        let Some((c, scale)) = self.factor_halves(k, m, s, true)? else {
            return Ok(None);
        };
        // the pivot threshold of one factorization of the whole matrix
        let tiny = 1e-13 * scale;
        let mut inertia = Inertia::default();
        for d in self.halves.iter().flat_map(|h| h.pivots.iter()) {
            inertia.count(*d, tiny);
        }
        let lblt = c.lblt(Side::Lower);
        block_inertia(&lblt, tiny, &mut inertia);
        self.schur = Some(Schur::Lblt(lblt));
        Ok(Some(inertia))
    }

    /// Both halves on two threads; the Schur complement `C = R_1 + R_2 - A_SS` and the largest
    /// `|a_jj|`, or `None` if a half failed.
    fn factor_halves(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
        ldlt: bool,
    ) -> Result<Option<(Mat<f64>, f64)>, FeError> {
        let [h1, h2] = &mut self.halves;
        let (r1, r2) = std::thread::scope(|sc| {
            let h = sc.spawn(|| h2.factor(k, m, s, (ldlt, false)));
            let r1 = h1.factor(k, m, s, (ldlt, true));
            (
                r1,
                h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
            )
        });
        let (Some(r1), Some(r2)) = (r1?, r2?) else {
            return Ok(None);
        };
        let a_ss = r1.a_ss.expect("the first half extracts A_SS");
        let c = &r1.r + &r2.r - &a_ss;
        Ok(Some((c, r1.scale.max(r2.scale))))
    }

    /// Solves `A X = B` in place (`rhs` holds `B` in the original DOF order).
    ///
    /// # Panics
    /// If no factorization succeeded since the last failed one (a programming error).
    pub(super) fn solve_in_place(&self, mut rhs: MatMut<'_, f64>) {
        let schur = self
            .schur
            .as_ref()
            .expect("solve with a failed two-domain factorization");
        let ldlt = matches!(schur, Schur::Lblt(_));
        let [h1, h2] = &self.halves;
        let mut w1 = h1.work.lock().unwrap_or_else(|p| p.into_inner());
        let mut w2 = h2.work.lock().unwrap_or_else(|p| p.into_inner());
        let (w1, w2) = (&mut *w1, &mut *w2);
        let b = rhs.as_ref();
        let ((mut x1, t1), (mut x2, t2)) = std::thread::scope(|sc| {
            let h = sc.spawn(|| h2.forward(b, ldlt, w2));
            let f1 = h1.forward(b, ldlt, w1);
            (
                f1,
                h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
            )
        });
        let p = rhs.ncols();
        let mut xs = t1 + t2;
        for c in 0..p {
            for (j, &o) in self.sep.iter().enumerate() {
                xs[(j, c)] += rhs[(o, c)];
            }
        }
        match schur {
            Schur::Llt(f) => f.solve_in_place(xs.as_mut()),
            Schur::Lblt(f) => f.solve_in_place(xs.as_mut()),
        }
        std::thread::scope(|sc| {
            let h = sc.spawn(|| h2.backward(x2.rb_mut(), xs.as_ref(), ldlt));
            h1.backward(x1.rb_mut(), xs.as_ref(), ldlt);
            h.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
        });
        for (half, x) in [(h1, x1.as_ref()), (h2, x2.as_ref())] {
            for c in 0..p {
                for (h, &o) in half.pattern.fwd[..half.inner].iter().enumerate() {
                    rhs[(o, c)] = x[(h, c)];
                }
            }
        }
        for c in 0..p {
            for (j, &o) in self.sep.iter().enumerate() {
                rhs[(o, c)] = xs[(j, c)];
            }
        }
    }
}

/// The trailing block `A_SS` (rows and columns from `inner` on, dense symmetric) of the lower
/// triangle `a` if `keep`, and the largest `|a_jj|` of `a`.
fn separator_block(
    a: SparseColMatRef<'_, u32, f64>,
    inner: usize,
    keep: bool,
) -> (Option<Mat<f64>>, f64) {
    let ns = a.ncols() - inner;
    let mut a_ss = keep.then(|| Mat::zeros(ns, ns));
    let mut scale = 0.0f64;
    for j in 0..a.ncols() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            let i = i as usize;
            if i == j {
                scale = scale.max(v.abs());
            }
            if let (true, Some(a_ss)) = (j >= inner, a_ss.as_mut()) {
                a_ss[(i - inner, j - inner)] = v;
                a_ss[(j - inner, i - inner)] = v;
            }
        }
    }
    (a_ss, scale)
}

/// The trailing block (rows and columns from `inner` on) of a supernodal factor: `L_S` (dense
/// lower; unit diagonal for `L D L^T`) and its pivots (`D_S`; ones for `L L^T`).
fn trailing_block(
    sn: &SymbolicSupernodalCholesky<u32>,
    values: &[f64],
    inner: usize,
    ldlt: bool,
) -> (Mat<f64>, Vec<f64>) {
    let ns = sn.nrows() - inner;
    let mut l = Mat::zeros(ns, ns);
    let mut d = vec![1.0; ns];
    let factor = LltRef::new(sn, values);
    for s in 0..sn.n_supernodes() {
        let node = factor.supernode(s);
        let (start, v) = (node.start(), node.val());
        let size = v.ncols();
        if start + size <= inner {
            continue;
        }
        for cl in 0..size {
            let c = start + cl;
            if c < inner {
                continue;
            }
            for rl in cl..size {
                l[(start + rl - inner, c - inner)] = v[(rl, cl)];
            }
            for (idx, &r) in node.pattern().iter().enumerate() {
                l[(r as usize - inner, c - inner)] = v[(size + idx, cl)];
            }
            if ldlt {
                d[c - inner] = v[(cl, cl)];
                l[(c - inner, c - inner)] = 1.0;
            }
        }
    }
    (l, d)
}

/// `L x = b` in place over the supernodes (unit diagonal if `unit`: faer's `L D L^T` storage
/// holds `D` there); `update_rows`: the longest off-diagonal pattern of a supernode.
fn lower_solve(
    sn: &SymbolicSupernodalCholesky<u32>,
    values: &[f64],
    update_rows: usize,
    unit: bool,
    mut x: MatMut<'_, f64>,
) {
    let p = x.ncols();
    let mut tmp = Mat::<f64>::zeros(update_rows, p);
    let factor = LltRef::new(sn, values);
    for s in 0..sn.n_supernodes() {
        let node = factor.supernode(s);
        let (start, v, pattern) = (node.start(), node.val(), node.pattern());
        let size = v.ncols();
        let (top, bot) = v.split_at_row(size);
        let mut xt = x.rb_mut().subrows_mut(start, size);
        if unit {
            solve_unit_lower_triangular_in_place(top, xt.rb_mut(), Par::Seq);
        } else {
            solve_lower_triangular_in_place(top, xt.rb_mut(), Par::Seq);
        }
        let mut t = tmp.subrows_mut(0, pattern.len());
        matmul(t.rb_mut(), Accum::Replace, bot, xt.rb(), 1.0, Par::Seq);
        for c in 0..p {
            for (idx, &i) in pattern.iter().enumerate() {
                x[(i as usize, c)] -= t[(idx, c)];
            }
        }
    }
}

/// `L^T x = b` in place over the supernodes, in reverse (unit diagonal if `unit`; `update_rows`
/// as for [`lower_solve`]).
fn upper_solve(
    sn: &SymbolicSupernodalCholesky<u32>,
    values: &[f64],
    update_rows: usize,
    unit: bool,
    mut x: MatMut<'_, f64>,
) {
    let p = x.ncols();
    let mut tmp = Mat::<f64>::zeros(update_rows, p);
    let factor = LltRef::new(sn, values);
    for s in (0..sn.n_supernodes()).rev() {
        let node = factor.supernode(s);
        let (start, v, pattern) = (node.start(), node.val(), node.pattern());
        let size = v.ncols();
        let (top, bot) = v.split_at_row(size);
        let mut t = tmp.subrows_mut(0, pattern.len());
        for c in 0..p {
            for (idx, &i) in pattern.iter().enumerate() {
                t[(idx, c)] = x[(i as usize, c)];
            }
        }
        let mut xt = x.rb_mut().subrows_mut(start, size);
        matmul(
            xt.rb_mut(),
            Accum::Add,
            bot.transpose(),
            t.rb(),
            -1.0,
            Par::Seq,
        );
        if unit {
            solve_unit_upper_triangular_in_place(top.transpose(), xt.rb_mut(), Par::Seq);
        } else {
            solve_upper_triangular_in_place(top.transpose(), xt.rb_mut(), Par::Seq);
        }
    }
}

/// Adds the inertia of the block diagonal `B` of a Bunch-Kaufman `L B L^T` (1 x 1 pivots and
/// 2 x 2 blocks, the latter by their two eigenvalues) to `inertia`.
fn block_inertia(f: &Lblt<f64>, tiny: f64, inertia: &mut Inertia) {
    let (d, e) = (f.B_diag(), f.B_subdiag());
    let n = d.dim();
    let mut i = 0;
    while i < n {
        if i + 1 < n && e[i] != 0.0 {
            let (a, b, c) = (d[i], e[i], d[i + 1]);
            let mid = 0.5 * (a + c);
            let rad = (0.5 * (a - c)).hypot(b);
            inertia.count(mid - rad, tiny);
            inertia.count(mid + rad, tiny);
            i += 2;
        } else {
            inertia.count(d[i], tiny);
            i += 1;
        }
    }
}
