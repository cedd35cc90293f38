//! Sparse Cholesky factorization with a METIS nested-dissection ordering: one factor of the
//! whole matrix, or for large `K - s M` two domains on two threads ([`super::split`]); the
//! Sturm counts of the Lanczos driver in the factor's storage ([`super::inertia`]).
//!
//! faer's supernodal Cholesky accepts a custom fill-reducing permutation through
//! [`faer::sparse::linalg::cholesky::factorize_symbolic_cholesky`]; the permutation
//! comes from `METIS_NodeND` on the graph of the sparsity pattern (crate-stack.md §2.2:
//! 35-45 % less fill and 2-4x faster factorizations than AMD for FE matrices).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltParams, LltRegularization};
use faer::perm::Perm;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering,
};
use faer::{Conj, MatMut, Par, Side, Spec};

use crate::{FeError, SparseMatrix};

use super::inertia::{inertia_with_symbolic, ldlt_inertia, Inertia};
use super::ordering::{
    metis_nested_dissection, shifted_ordering, FillOrdering, TwoDomains, METIS_MIN_DIM,
};
use super::split::SplitFactor;

/// Sparse `L L^T` factorization of a symmetric positive definite matrix
/// (faer supernodal/simplicial Cholesky, METIS `NodeND` ordering, AMD fallback).
#[derive(Debug)]
pub struct SparseCholesky {
    factor: Factor,
    pattern_nnz: usize,
    /// The storage holds something else than the `L L^T` factor (an `L D L^T` of the Sturm
    /// check).
    stale: bool,
    /// The storage holds an `L D L^T` factor for solves ([`Self::factor_ldlt_in_place`]).
    ldlt: bool,
}

/// The storage of a [`SparseCholesky`].
#[derive(Debug)]
enum Factor {
    /// One faer factor of the whole matrix.
    One(Box<OneFactor>),
    /// Two domains and their separator, on two threads ([`super::split`]; large factors of
    /// `K - s M`).
    Split(Box<SplitFactor>),
}

/// faer's factor of the whole matrix.
#[derive(Debug)]
struct OneFactor {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    /// Factors of `K - s M` ([`SparseCholesky::factor_shifted_observed`]): the ordered lower
    /// pattern that the symbolic analysis (identity ordering) was made on; solves apply its
    /// ordering.
    shifted: Option<ShiftedPattern>,
}

/// The lower triangle of `P (K - s M) P^T` (`P` the fill-reducing ordering) on the union of the
/// patterns of `K` and `M`, rows sorted: the matrix the factorizations of the Lanczos driver
/// read, its pattern stored once. Given a matrix and an ordering, faer first copies the permuted
/// lower triangle into its workspace (values and 64-bit indices of every entry); given this
/// already ordered matrix and the identity ordering it reads it in place, and a new shift only
/// refills the values ([`Self::values`]). At the Sturm check the modal analysis thus holds one
/// lower triangle of values instead of two matrices (the shifted one and faer's permuted copy).
/// A pattern may also cover a subset of the unknowns (the halves of [`super::split`]): `fwd`
/// lists the subset, `inv` is `usize::MAX` outside it. `I`: the index type of the pattern (and of
/// the factorization reading it; the halves use `u32`, half the memory of `usize`).
#[derive(Debug)]
pub(super) struct ShiftedPattern<I: faer::Index = usize> {
    /// `fwd[new] = old`.
    pub(super) fwd: Vec<usize>,
    /// `inv[old] = new`.
    inv: Vec<usize>,
    pub(super) symbolic: faer::sparse::SymbolicSparseColMat<I>,
}

impl<I: faer::Index> ShiftedPattern<I> {
    /// Calls `f(row, col, k, m)` for every entry of the ordered lower triangle (new indices,
    /// `row >= col`) in a fixed order, rows increasing, so that each column receives its rows
    /// sorted. Entry `(new i, new r)` takes the stored entry `(r, i)` of column `i` of `K` and
    /// `M` (symmetric matrices). Rows outside the subset (`inv = usize::MAX`) are skipped.
    fn for_each(
        k: &SparseMatrix,
        m: &SparseMatrix,
        fwd: &[usize],
        inv: &[usize],
        mut f: impl FnMut(usize, usize, f64, f64),
    ) {
        for (pi, &i) in fwd.iter().enumerate() {
            let (kr, kv) = (k.row_idx_of_col_raw(i), k.val_of_col(i));
            let (mr, mv) = (m.row_idx_of_col_raw(i), m.val_of_col(i));
            let (mut a, mut b) = (0, 0);
            while a < kr.len() || b < mr.len() {
                let (ri, rm) = (kr.get(a).copied(), mr.get(b).copied());
                let row = ri.unwrap_or(usize::MAX).min(rm.unwrap_or(usize::MAX));
                let x = if ri == Some(row) {
                    a += 1;
                    kv[a - 1]
                } else {
                    0.0
                };
                let y = if rm == Some(row) {
                    b += 1;
                    mv[b - 1]
                } else {
                    0.0
                };
                let pr = inv[row];
                if pr <= pi {
                    f(pi, pr, x, y);
                }
            }
        }
    }

    /// The pattern of the subset `fwd` (`inv` its inverse, `usize::MAX` outside). `None` if the
    /// entries or the dimension do not fit the index type `I`.
    pub(super) fn new(
        k: &SparseMatrix,
        m: &SparseMatrix,
        fwd: Vec<usize>,
        inv: Vec<usize>,
    ) -> Option<Self> {
        let n = fwd.len();
        let mut count = vec![0usize; n + 1];
        Self::for_each(k, m, &fwd, &inv, |_, c, _, _| count[c + 1] += 1);
        for j in 0..n {
            count[j + 1] += count[j];
        }
        if count[n] > I::MAX.zx() || n > I::MAX.zx() {
            return None;
        }
        let mut cursor = count[..n].to_vec();
        let mut rows = vec![I::truncate(0); count[n]];
        Self::for_each(k, m, &fwd, &inv, |r, c, _, _| {
            rows[cursor[c]] = I::truncate(r);
            cursor[c] += 1;
        });
        let col_ptr = count.into_iter().map(I::truncate).collect();
        let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows);
        Some(Self { fwd, inv, symbolic })
    }

    /// The values of the ordered lower triangle of `K - s M`, in the order of the pattern.
    pub(super) fn values(
        &self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
    ) -> Result<Vec<f64>, FeError> {
        let mut values = zeros_or_refused(self.nnz())?;
        let mut cursor: Vec<usize> = self.symbolic.col_ptr()[..self.fwd.len()]
            .iter()
            .map(|p| p.zx())
            .collect();
        Self::for_each(k, m, &self.fwd, &self.inv, |_, c, x, y| {
            values[cursor[c]] = x - s * y;
            cursor[c] += 1;
        });
        Ok(values)
    }

    pub(super) fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// The transposed (upper triangle) pattern, rows sorted.
    pub(super) fn upper(&self) -> faer::sparse::SymbolicSparseColMat<I> {
        let n = self.fwd.len();
        let (col_ptr, rows) = (self.symbolic.col_ptr(), self.symbolic.row_idx());
        let mut up_ptr = vec![0usize; n + 1];
        for r in rows {
            up_ptr[r.zx() + 1] += 1;
        }
        for j in 0..n {
            up_ptr[j + 1] += up_ptr[j];
        }
        let mut cursor = up_ptr[..n].to_vec();
        let mut up_rows = vec![I::truncate(0); rows.len()];
        for c in 0..n {
            for r in &rows[col_ptr[c].zx()..col_ptr[c + 1].zx()] {
                up_rows[cursor[r.zx()]] = I::truncate(c);
                cursor[r.zx()] += 1;
            }
        }
        let up_ptr = up_ptr.into_iter().map(I::truncate).collect();
        faer::sparse::SymbolicSparseColMat::new_checked(n, n, up_ptr, None, up_rows)
    }
}

impl SparseCholesky {
    /// Factors the symmetric positive definite matrix `a` (full storage, both triangles).
    ///
    /// Returns [`FeError::NotPositiveDefinite`] if a pivot is not positive and
    /// [`FeError::Invalid`] if `a` is not square.
    pub fn factor(a: &SparseMatrix) -> Result<Self, FeError> {
        Self::factor_observed(a, &mut |_, _| {})
    }

    /// [`SparseCholesky::factor`] that reports the size of the factor from the symbolic
    /// analysis before the numeric work: `on_estimate(nnz_l, bytes)` (entries of `L`; bytes of
    /// `L` and the factorization's workspace). An estimate above the memory available is
    /// refused with [`FeError::MemoryRefused`] ([`crate::memory`]) before any allocation.
    pub fn factor_observed(
        a: &SparseMatrix,
        on_estimate: &mut dyn FnMut(usize, u64),
    ) -> Result<Self, FeError> {
        let symbolic = symbolic_factor(a)?;
        let par = Par::Seq;
        let req =
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Spec::<LltParams, f64>::default());
        let bytes = factor_bytes(symbolic.len_val(), req.size_bytes());
        on_estimate(symbolic.len_val(), bytes);
        crate::memory::check_allocation(
            &format!("the sparse Cholesky factor of {} equations", a.nrows()),
            bytes,
        )?;
        Self::factor_with_symbolic(symbolic, a)
    }

    /// [`SparseCholesky::factor_observed`] of `K - sigma M` (`K`, `M` symmetric with sorted rows)
    /// without holding the full shifted matrix during the numeric work: the ordering (METIS)
    /// reads the full matrix, which is then dropped; the symbolic analysis and every numeric
    /// factorization read the ordered lower triangle ([`ShiftedPattern`], identity ordering: the
    /// factor of faer's ordering of the full matrix, without faer's permuted copy). The estimate
    /// (`on_estimate`, memory guard) counts `L`, faer's workspace and the values of the shifted
    /// matrix.
    pub fn factor_shifted_observed(
        k: &SparseMatrix,
        m: &SparseMatrix,
        sigma: f64,
        on_estimate: &mut dyn FnMut(usize, u64),
    ) -> Result<Self, FeError> {
        Self::factor_first_definite(k, m, &[sigma], None, on_estimate).map(|(chol, _)| chol)
    }

    /// [`Self::factor_shifted_observed`] for the first shift of `shifts` at which `K - s M` is
    /// positive definite, and its index: one ordering and symbolic analysis serve every attempt
    /// (a failed attempt costs one numeric factorization). The error of the last attempt if none
    /// is.
    /// The ordering is `ordering` if given (from [`shifted_ordering`]), computed otherwise.
    pub(crate) fn factor_first_definite(
        k: &SparseMatrix,
        m: &SparseMatrix,
        shifts: &[f64],
        ordering: Option<FillOrdering>,
        on_estimate: &mut dyn FnMut(usize, u64),
    ) -> Result<(Self, usize), FeError> {
        let ordering = match ordering {
            Some(o) => o,
            None => shifted_ordering(k, m)?,
        };
        let perm = match ordering {
            FillOrdering::TwoDomains(p, d) => {
                return Self::split_first_definite(k, m, p, d, shifts, on_estimate)
            }
            FillOrdering::Whole(p) => p,
        };
        let (fwd, inv) = perm.into_arrays();
        let (fwd, inv) = (fwd.into_vec(), inv.into_vec());
        let pattern = ShiftedPattern::<usize>::new(k, m, fwd, inv)
            .ok_or_else(|| FeError::Invalid("matrix too large for its indices".into()))?;
        // with the identity ordering faer's symbolic analysis reads the upper triangle whatever
        // the side: the transposed pattern, only for the analysis
        let symbolic = factorize_symbolic_cholesky(
            pattern.upper().as_ref(),
            Side::Upper,
            SymmetricOrdering::Identity,
            CholeskySymbolicParams::default(),
        )
        .map_err(|e| FeError::Invalid(format!("symbolic Cholesky analysis failed: {e:?}")))?;
        let req = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Spec::<LltParams, f64>::default());
        let bytes = factor_bytes(symbolic.len_val(), req.size_bytes()) + 8 * pattern.nnz() as u64;
        on_estimate(symbolic.len_val(), bytes);
        crate::memory::check_allocation(
            &format!("the sparse Cholesky factor of {} equations", k.nrows()),
            bytes,
        )?;
        let mut factor = zeros_or_refused(symbolic.len_val())?;
        let mut result = Err(FeError::Invalid("no shift to factor K - s M at".into()));
        for (i, &s) in shifts.iter().enumerate() {
            let values = pattern.values(k, m, s)?;
            let lower = faer::sparse::SparseColMatRef::new(pattern.symbolic.as_ref(), &values);
            result = refactor_llt(&symbolic, lower, &mut factor).map(|()| i);
            if result.is_ok() {
                break;
            }
        }
        let used = result?;
        let chol = Self {
            pattern_nnz: pattern.nnz(),
            factor: Factor::One(Box::new(OneFactor {
                symbolic,
                values: factor,
                shifted: Some(pattern),
            })),
            stale: false,
            ldlt: false,
        };
        Ok((chol, used))
    }

    /// [`Self::factor_first_definite`] in two domains ([`super::split`]) with the ordering
    /// `perm` of [`metis_two_domains`].
    fn split_first_definite(
        k: &SparseMatrix,
        m: &SparseMatrix,
        perm: Perm<usize>,
        domains: TwoDomains,
        shifts: &[f64],
        on_estimate: &mut dyn FnMut(usize, u64),
    ) -> Result<(Self, usize), FeError> {
        let (fwd, _) = perm.as_ref().arrays();
        let mut factor = SplitFactor::new(k, m, fwd, domains, on_estimate)?;
        let mut result = Err(FeError::Invalid("no shift to factor K - s M at".into()));
        for (i, &s) in shifts.iter().enumerate() {
            result = factor.factor_llt(k, m, s).map(|()| i);
            if result.is_ok() {
                break;
            }
        }
        let used = result?;
        let chol = Self {
            factor: Factor::Split(Box::new(factor)),
            pattern_nnz: usize::MAX,
            stale: false,
            ldlt: false,
        };
        Ok((chol, used))
    }

    /// Numeric factorization of `a` reusing a symbolic analysis of the same pattern.
    fn factor_with_symbolic(
        symbolic: SymbolicCholesky<usize>,
        a: &SparseMatrix,
    ) -> Result<Self, FeError> {
        Self::factor_with_symbolic_ref(symbolic, a.as_ref())
    }

    fn factor_with_symbolic_ref(
        symbolic: SymbolicCholesky<usize>,
        a: faer::sparse::SparseColMatRef<'_, usize, f64>,
    ) -> Result<Self, FeError> {
        let mut values = zeros_or_refused(symbolic.len_val())?;
        let par = Par::Seq;
        let req =
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Spec::<LltParams, f64>::default());
        let mut mem = MemBuffer::try_new(req).map_err(|_| oom())?;
        let res = symbolic.factorize_numeric_llt(
            &mut values,
            a,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Spec::<LltParams, f64>::default(),
        );
        match res {
            Ok(_) => Ok(Self {
                factor: Factor::One(Box::new(OneFactor {
                    symbolic,
                    values,
                    shifted: None,
                })),
                pattern_nnz: a.compute_nnz(),
                stale: false,
                ldlt: false,
            }),
            Err(e) => Err(FeError::NotPositiveDefinite {
                what: format!("sparse matrix of dimension {}", a.nrows()),
                hint: format!(" ({e:?})"),
            }),
        }
    }

    /// Solves `A X = B` in place for all columns of `rhs` (`rhs` holds `B` on entry, `X` on exit).
    ///
    /// # Panics
    /// Panics if `rhs.nrows() != self.dim()` or the storage holds a Sturm check's `L D L^T`
    /// (programming errors, not input errors).
    pub fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        assert!(
            !self.stale,
            "solve with a factor overwritten by a Sturm check"
        );
        let f = match &self.factor {
            Factor::One(f) => f,
            Factor::Split(f) => return f.solve_in_place(rhs),
        };
        let par = Par::Seq;
        let Some(pattern) = &f.shifted else {
            f.solve_ordered(self.ldlt, rhs, par);
            return;
        };
        // the symbolic analysis has the identity ordering: the pattern's ordering is applied here,
        // in place (no copy of the right-hand sides)
        let mut rhs = rhs;
        permute_rows_in_place(rhs.as_mut(), &pattern.fwd);
        f.solve_columns_split(self.ldlt, rhs.as_mut(), par);
        permute_rows_in_place(rhs.as_mut(), &pattern.inv);
    }

    /// The storage holds the `L D L^T` of a Sturm check instead of this factor
    /// ([`Self::inertia_in_place`]); [`Self::refactor`] restores it.
    pub(crate) fn is_stale(&self) -> bool {
        self.stale
    }

    /// Whether the factor is held in two domains ([`super::split`]).
    #[cfg(test)]
    pub(crate) fn is_split(&self) -> bool {
        matches!(self.factor, Factor::Split(_))
    }

    /// Dimension of the factored matrix.
    pub fn dim(&self) -> usize {
        match &self.factor {
            Factor::One(f) => f.symbolic.nrows(),
            Factor::Split(f) => f.dim(),
        }
    }

    /// Number of stored entries of the factor `L`.
    pub fn nnz_l(&self) -> usize {
        match &self.factor {
            Factor::One(f) => f.symbolic.len_val(),
            Factor::Split(f) => f.nnz_l(),
        }
    }
}

impl OneFactor {
    /// [`Self::solve_ordered`] of the two halves of the columns, on two threads. The halves are
    /// the same on every machine (faer's kernels round differently for different numbers of
    /// columns, so the split is fixed, not taken from the machine's threads): the result does
    /// not depend on the machine. The solve reads the factor from memory once per half; two
    /// threads share that bandwidth better than one (60k-DOF bench: 5.6 -> 5.2 s).
    fn solve_columns_split(&self, ldlt: bool, rhs: MatMut<'_, f64>, par: Par) {
        let p = rhs.ncols();
        if p < 2 {
            self.solve_ordered(ldlt, rhs, par);
            return;
        }
        let (left, right) = rhs.split_at_col_mut(p / 2);
        std::thread::scope(|s| {
            let h = s.spawn(|| self.solve_ordered(ldlt, right, par));
            self.solve_ordered(ldlt, left, par);
            h.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        });
    }

    /// The solve with faer's factor (and faer's ordering, if any).
    fn solve_ordered(&self, ldlt: bool, rhs: MatMut<'_, f64>, par: Par) {
        let req = self
            .symbolic
            .solve_in_place_scratch::<f64>(rhs.ncols(), par);
        let mut mem = MemBuffer::new(req);
        if ldlt {
            let ldlt = faer::sparse::linalg::cholesky::LdltRef::new(&self.symbolic, &self.values);
            ldlt.solve_in_place_with_conj(Conj::No, rhs, par, MemStack::new(&mut mem));
        } else {
            let llt = faer::sparse::linalg::cholesky::LltRef::new(&self.symbolic, &self.values);
            llt.solve_in_place_with_conj(Conj::No, rhs, par, MemStack::new(&mut mem));
        }
    }
}

/// Row `i` of `a` becomes its row `from[i]` (`from` a permutation), in place: each cycle of the
/// permutation is followed once with one row held aside.
fn permute_rows_in_place(mut a: MatMut<'_, f64>, from: &[usize]) {
    let (n, p) = (a.nrows(), a.ncols());
    debug_assert_eq!(from.len(), n);
    let mut done = vec![false; n];
    let mut held = vec![0.0f64; p];
    for start in 0..n {
        if done[start] {
            continue;
        }
        for (c, h) in held.iter_mut().enumerate() {
            *h = a[(start, c)];
        }
        let mut i = start;
        loop {
            done[i] = true;
            let j = from[i];
            if j == start {
                for (c, &h) in held.iter().enumerate() {
                    a[(i, c)] = h;
                }
                break;
            }
            for c in 0..p {
                a[(i, c)] = a[(j, c)];
            }
            i = j;
        }
    }
}

/// Bytes of a factor with `nnz_l` stored entries and a workspace of `scratch` bytes.
pub(super) fn factor_bytes(nnz_l: usize, scratch: usize) -> u64 {
    8 * nnz_l as u64 + scratch as u64
}

/// `n` zeros, or an error instead of an abort when the allocation fails.
pub(super) fn zeros_or_refused(n: usize) -> Result<Vec<f64>, FeError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| oom())?;
    v.resize(n, 0.0);
    Ok(v)
}

pub(super) fn oom() -> FeError {
    FeError::Invalid("out of memory in sparse factorization".into())
}

/// Symbolic Cholesky analysis with the METIS ordering (AMD for tiny or edgeless graphs,
/// or if METIS reports an error).
pub(super) fn symbolic_factor(a: &SparseMatrix) -> Result<SymbolicCholesky<usize>, FeError> {
    if a.nrows() != a.ncols() {
        return Err(FeError::Invalid(format!(
            "matrix to factor is not square ({} x {})",
            a.nrows(),
            a.ncols()
        )));
    }
    let perm = if a.nrows() >= METIS_MIN_DIM {
        metis_nested_dissection(a)
    } else {
        None
    };
    let params = CholeskySymbolicParams::default();
    let sym = match &perm {
        Some(p) => factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Lower,
            SymmetricOrdering::Custom(p.as_ref()),
            params,
        ),
        None => {
            factorize_symbolic_cholesky(a.symbolic(), Side::Lower, SymmetricOrdering::Amd, params)
        }
    };
    sym.map_err(|e| FeError::Invalid(format!("symbolic Cholesky analysis failed: {e:?}")))
}

impl SparseCholesky {
    /// Inertia of `a` (full storage or its lower triangle; for a factor of
    /// [`Self::factor_shifted_observed`] a separate factorization), whose pattern must lie within the
    /// pattern of the matrix this factorization was computed from (e.g. `K - b M` vs.
    /// `K - sigma M`, [`super::shifted_lower`]), computed in this factor's own storage: the
    /// symbolic analysis (ordering) and the memory of `L` are reused, so the Sturm check needs
    /// no second factor. The `L L^T` factor is gone afterwards: [`Self::refactor`] before the
    /// next solve.
    pub(crate) fn inertia_in_place(
        &mut self,
        a: &SparseMatrix,
    ) -> Result<Option<Inertia>, FeError> {
        // a factor on an ordered pattern reads matrices in its own ordering only
        let fits = a.nrows() == self.dim() && a.compute_nnz() <= self.pattern_nnz;
        match &mut self.factor {
            Factor::One(f) if fits && f.shifted.is_none() => {
                self.stale = true;
                inertia_with_symbolic(&f.symbolic, a.as_ref(), &mut f.values)
            }
            _ => ldlt_inertia(a),
        }
    }

    /// [`Self::inertia_in_place`] of `K - b M` for a factor of [`Self::factor_shifted_observed`]
    /// (the values refilled into its ordered pattern; two domains: their own `L D L^T`); other
    /// factors build [`super::shifted_lower`].
    pub(crate) fn inertia_shifted_in_place(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        b: f64,
    ) -> Result<Option<Inertia>, FeError> {
        let f = match &mut self.factor {
            Factor::Split(f) => {
                self.stale = true;
                return f.factor_ldlt(k, m, b);
            }
            Factor::One(f) => f,
        };
        let Some(pattern) = &f.shifted else {
            return self.inertia_in_place(&super::shifted_lower(k, m, b)?);
        };
        let lower = pattern.values(k, m, b)?;
        let a = faer::sparse::SparseColMatRef::new(pattern.symbolic.as_ref(), &lower);
        self.stale = true;
        inertia_with_symbolic(&f.symbolic, a, &mut f.values)
    }

    /// [`Self::factor_ldlt_in_place`] of `K - s M` (see [`Self::inertia_shifted_in_place`]).
    pub(crate) fn factor_ldlt_shifted_in_place(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
    ) -> Result<Option<Inertia>, FeError> {
        if matches!(&self.factor, Factor::One(f) if f.shifted.is_none()) {
            return self.factor_ldlt_in_place(&super::shifted_lower(k, m, s)?);
        }
        self.ldlt = false;
        let inertia = self.inertia_shifted_in_place(k, m, s)?;
        if inertia.is_some() {
            self.stale = false;
            self.ldlt = true;
        }
        Ok(inertia)
    }

    /// [`Self::refactor`] with `K - s M` (see [`Self::inertia_shifted_in_place`]).
    pub(crate) fn refactor_shifted(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
    ) -> Result<(), FeError> {
        match &mut self.factor {
            Factor::Split(f) => f.factor_llt(k, m, s)?,
            Factor::One(f) => {
                let Some(pattern) = &f.shifted else {
                    return self.refactor(&super::shifted_lower(k, m, s)?);
                };
                let lower = pattern.values(k, m, s)?;
                let a = faer::sparse::SparseColMatRef::new(pattern.symbolic.as_ref(), &lower);
                refactor_llt(&f.symbolic, a, &mut f.values)?;
            }
        }
        self.stale = false;
        self.ldlt = false;
        Ok(())
    }

    /// `L D L^T` factorization (no pivoting) of the symmetric, possibly indefinite `a` (pattern
    /// within the original one) into this factor's storage, for solves with a shift inside the
    /// spectrum (spectrum slicing); returns its inertia (`None`: a zero pivot, the storage is then
    /// stale). [`Self::refactor`] returns to `L L^T`.
    pub(crate) fn factor_ldlt_in_place(
        &mut self,
        a: &SparseMatrix,
    ) -> Result<Option<Inertia>, FeError> {
        let fits = a.nrows() == self.dim() && a.compute_nnz() <= self.pattern_nnz;
        let f = match &mut self.factor {
            Factor::One(f) if fits && f.shifted.is_none() => f,
            _ => {
                return Err(FeError::Invalid(
                    "L D L^T pattern outside the factored pattern".into(),
                ))
            }
        };
        self.stale = true;
        self.ldlt = false;
        let inertia = inertia_with_symbolic(&f.symbolic, a.as_ref(), &mut f.values)?;
        if inertia.is_some() {
            self.stale = false;
            self.ldlt = true;
        }
        Ok(inertia)
    }

    /// Numeric `L L^T` factorization of `a` (full storage or its lower triangle, pattern within
    /// the original one) into this factor's storage, reusing the symbolic analysis.
    pub(crate) fn refactor(&mut self, a: &SparseMatrix) -> Result<(), FeError> {
        let f = match &mut self.factor {
            Factor::One(f) if f.shifted.is_none() => f,
            _ => {
                return Err(FeError::Invalid(
                    "refactor of a factor on an ordered pattern: use refactor_shifted".into(),
                ))
            }
        };
        refactor_llt(&f.symbolic, a.as_ref(), &mut f.values)?;
        self.stale = false;
        self.ldlt = false;
        Ok(())
    }
}

/// Numeric `L L^T` of `a` into `values` with the symbolic analysis `symbolic`.
pub(super) fn refactor_llt<I: faer::Index>(
    symbolic: &SymbolicCholesky<I>,
    a: faer::sparse::SparseColMatRef<'_, I, f64>,
    values: &mut [f64],
) -> Result<(), FeError> {
    let par = Par::Seq;
    let req = symbolic.factorize_numeric_llt_scratch::<f64>(par, Spec::<LltParams, f64>::default());
    let mut mem = MemBuffer::try_new(req).map_err(|_| oom())?;
    symbolic
        .factorize_numeric_llt(
            values,
            a,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Spec::<LltParams, f64>::default(),
        )
        .map_err(|e| FeError::NotPositiveDefinite {
            what: format!("sparse matrix of dimension {}", a.nrows()),
            hint: format!(" ({e:?})"),
        })?;
    Ok(())
}
