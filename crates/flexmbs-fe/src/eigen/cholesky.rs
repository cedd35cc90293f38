//! Sparse Cholesky factorization with a METIS nested-dissection ordering, and
//! the inertia (Sturm count) of a symmetric matrix from an `L D L^T` factorization.
//!
//! faer's supernodal Cholesky accepts a custom fill-reducing permutation through
//! [`faer::sparse::linalg::cholesky::factorize_symbolic_cholesky`]; the permutation
//! comes from `METIS_NodeND` on the graph of the sparsity pattern (crate-stack.md §2.2:
//! 35-45 % less fill and 2-4x faster factorizations than AMD for FE matrices).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::{LdltParams, LdltRegularization};
use faer::linalg::cholesky::llt::factor::{LltParams, LltRegularization};
use faer::perm::Perm;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal, CholeskySymbolicParams, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::{Conj, MatMut, Par, Side, Spec};

use crate::{FeError, SparseMatrix};

/// Serializes the calls into METIS (see [`metis_on_patterns`]).
static METIS_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Matrices below this dimension are ordered with faer's AMD instead of METIS.
const METIS_MIN_DIM: usize = 64;

/// Sparse `L L^T` factorization of a symmetric positive definite matrix
/// (faer supernodal/simplicial Cholesky, METIS `NodeND` ordering, AMD fallback).
#[derive(Debug)]
pub struct SparseCholesky {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    pattern_nnz: usize,
    /// `values` hold something else than the `L L^T` factor (an `L D L^T` of the Sturm check).
    stale: bool,
    /// `values` hold an `L D L^T` factor for solves ([`Self::factor_ldlt_in_place`]).
    ldlt: bool,
    /// Factors of `K - s M` ([`Self::factor_shifted_observed`]): the ordered lower pattern that
    /// the symbolic analysis (identity ordering) was made on; solves apply its ordering.
    shifted: Option<ShiftedPattern>,
}

/// The lower triangle of `P (K - s M) P^T` (`P` the fill-reducing ordering) on the union of the
/// patterns of `K` and `M`, rows sorted: the matrix the factorizations of the Lanczos driver
/// read, its pattern stored once. Given a matrix and an ordering, faer first copies the permuted
/// lower triangle into its workspace (values and 64-bit indices of every entry); given this
/// already ordered matrix and the identity ordering it reads it in place, and a new shift only
/// refills the values ([`Self::values`]). At the Sturm check the modal analysis thus holds one
/// lower triangle of values instead of two matrices (the shifted one and faer's permuted copy).
#[derive(Debug)]
struct ShiftedPattern {
    /// `fwd[new] = old`.
    fwd: Vec<usize>,
    /// `inv[old] = new`.
    inv: Vec<usize>,
    symbolic: faer::sparse::SymbolicSparseColMat<usize>,
}

impl ShiftedPattern {
    /// Calls `f(row, col, k, m)` for every entry of the ordered lower triangle (new indices,
    /// `row >= col`) in a fixed order, rows increasing, so that each column receives its rows
    /// sorted. Entry `(new i, new r)` takes the stored entry `(r, i)` of column `i` of `K` and
    /// `M` (symmetric matrices).
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

    fn new(k: &SparseMatrix, m: &SparseMatrix, fwd: Vec<usize>, inv: Vec<usize>) -> Self {
        let n = k.ncols();
        let mut col_ptr = vec![0usize; n + 1];
        Self::for_each(k, m, &fwd, &inv, |_, c, _, _| col_ptr[c + 1] += 1);
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let mut cursor = col_ptr[..n].to_vec();
        let mut rows = vec![0usize; col_ptr[n]];
        Self::for_each(k, m, &fwd, &inv, |r, c, _, _| {
            rows[cursor[c]] = r;
            cursor[c] += 1;
        });
        let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows);
        Self { fwd, inv, symbolic }
    }

    /// The values of the ordered lower triangle of `K - s M`, in the order of the pattern.
    fn values(&self, k: &SparseMatrix, m: &SparseMatrix, s: f64) -> Result<Vec<f64>, FeError> {
        let mut values = zeros_or_refused(self.nnz())?;
        let mut cursor = self.symbolic.col_ptr()[..self.fwd.len()].to_vec();
        Self::for_each(k, m, &self.fwd, &self.inv, |_, c, x, y| {
            values[cursor[c]] = x - s * y;
            cursor[c] += 1;
        });
        Ok(values)
    }

    fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// The transposed (upper triangle) pattern, rows sorted.
    fn upper(&self) -> faer::sparse::SymbolicSparseColMat<usize> {
        let n = self.fwd.len();
        let (col_ptr, rows) = (self.symbolic.col_ptr(), self.symbolic.row_idx());
        let mut up_ptr = vec![0usize; n + 1];
        for &r in rows {
            up_ptr[r + 1] += 1;
        }
        for j in 0..n {
            up_ptr[j + 1] += up_ptr[j];
        }
        let mut cursor = up_ptr[..n].to_vec();
        let mut up_rows = vec![0usize; rows.len()];
        for c in 0..n {
            for &r in &rows[col_ptr[c]..col_ptr[c + 1]] {
                up_rows[cursor[r]] = c;
                cursor[r] += 1;
            }
        }
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
        Self::factor_first_definite(k, m, &[sigma], on_estimate).map(|(chol, _)| chol)
    }

    /// [`Self::factor_shifted_observed`] for the first shift of `shifts` at which `K - s M` is
    /// positive definite, and its index: one ordering and symbolic analysis serve every attempt
    /// (a failed attempt costs one numeric factorization). The error of the last attempt if none
    /// is.
    pub(crate) fn factor_first_definite(
        k: &SparseMatrix,
        m: &SparseMatrix,
        shifts: &[f64],
        on_estimate: &mut dyn FnMut(usize, u64),
    ) -> Result<(Self, usize), FeError> {
        // the ordering reads the union of the patterns of K and M (the values do not matter)
        let perm = if k.nrows() >= METIS_MIN_DIM {
            metis_on_patterns(&[k, m])
        } else {
            None
        };
        let perm = match perm {
            Some(p) => p,
            None => amd_ordering(&super::shifted(k, m, 1.0)?)?,
        };
        let (fwd, inv) = perm.into_arrays();
        let (fwd, inv) = (fwd.into_vec(), inv.into_vec());
        let pattern = ShiftedPattern::new(k, m, fwd, inv);
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
            symbolic,
            values: factor,
            pattern_nnz: pattern.nnz(),
            stale: false,
            ldlt: false,
            shifted: Some(pattern),
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
                symbolic,
                values,
                pattern_nnz: a.compute_nnz(),
                stale: false,
                ldlt: false,
                shifted: None,
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
        let par = Par::Seq;
        let Some(pattern) = &self.shifted else {
            self.solve_ordered(rhs, par);
            return;
        };
        // the symbolic analysis has the identity ordering: the pattern's ordering is applied here,
        // in place (no copy of the right-hand sides)
        let mut rhs = rhs;
        permute_rows_in_place(rhs.as_mut(), &pattern.fwd);
        self.solve_columns_split(rhs.as_mut(), par);
        permute_rows_in_place(rhs.as_mut(), &pattern.inv);
    }

    /// [`Self::solve_ordered`] of the two halves of the columns, on two threads. The halves are
    /// the same on every machine (faer's kernels round differently for different numbers of
    /// columns, so the split is fixed, not taken from the machine's threads): the result does
    /// not depend on the machine. The solve reads the factor from memory once per half; two
    /// threads share that bandwidth better than one (60k-DOF bench: 5.6 -> 5.2 s).
    fn solve_columns_split(&self, rhs: MatMut<'_, f64>, par: Par) {
        let p = rhs.ncols();
        if p < 2 {
            self.solve_ordered(rhs, par);
            return;
        }
        let (left, right) = rhs.split_at_col_mut(p / 2);
        std::thread::scope(|s| {
            let h = s.spawn(|| self.solve_ordered(right, par));
            self.solve_ordered(left, par);
            h.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        });
    }

    /// The solve with faer's factor (and faer's ordering, if any).
    fn solve_ordered(&self, rhs: MatMut<'_, f64>, par: Par) {
        let req = self
            .symbolic
            .solve_in_place_scratch::<f64>(rhs.ncols(), par);
        let mut mem = MemBuffer::new(req);
        if self.ldlt {
            let ldlt = faer::sparse::linalg::cholesky::LdltRef::new(&self.symbolic, &self.values);
            ldlt.solve_in_place_with_conj(Conj::No, rhs, par, MemStack::new(&mut mem));
        } else {
            let llt = faer::sparse::linalg::cholesky::LltRef::new(&self.symbolic, &self.values);
            llt.solve_in_place_with_conj(Conj::No, rhs, par, MemStack::new(&mut mem));
        }
    }

    /// The storage holds the `L D L^T` of a Sturm check instead of this factor
    /// ([`Self::inertia_in_place`]); [`Self::refactor`] restores it.
    pub(crate) fn is_stale(&self) -> bool {
        self.stale
    }

    /// Dimension of the factored matrix.
    pub fn dim(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Number of stored entries of the factor `L`.
    pub fn nnz_l(&self) -> usize {
        self.symbolic.len_val()
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
fn factor_bytes(nnz_l: usize, scratch: usize) -> u64 {
    8 * nnz_l as u64 + scratch as u64
}

/// `n` zeros, or an error instead of an abort when the allocation fails.
fn zeros_or_refused(n: usize) -> Result<Vec<f64>, FeError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| oom())?;
    v.resize(n, 0.0);
    Ok(v)
}

fn oom() -> FeError {
    FeError::Invalid("out of memory in sparse factorization".into())
}

/// Symbolic Cholesky analysis with the METIS ordering (AMD for tiny or edgeless graphs,
/// or if METIS reports an error).
fn symbolic_factor(a: &SparseMatrix) -> Result<SymbolicCholesky<usize>, FeError> {
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

/// faer's AMD ordering of the pattern of `a` (full storage).
fn amd_ordering(a: &SparseMatrix) -> Result<Perm<usize>, FeError> {
    let sym = factorize_symbolic_cholesky(
        a.symbolic(),
        Side::Lower,
        SymmetricOrdering::Amd,
        CholeskySymbolicParams::default(),
    )
    .map_err(|e| FeError::Invalid(format!("symbolic Cholesky analysis failed: {e:?}")))?;
    let n = a.nrows();
    Ok(match sym.perm() {
        Some(p) => {
            let (fwd, inv) = p.arrays();
            Perm::new_checked(fwd.into(), inv.into(), n)
        }
        None => Perm::new_checked((0..n).collect(), (0..n).collect(), n),
    })
}

/// Fill-reducing permutation from `METIS_NodeND` on the adjacency graph of `a`
/// (diagonal excluded). Consecutive columns with identical patterns (the DOFs of
/// one FE node) are compressed into one weighted graph vertex first.
///
/// Returns `None` if the graph has no edges, is too large for METIS' 32-bit
/// indices, or METIS reports an error; the caller then falls back to AMD.
pub(crate) fn metis_nested_dissection(a: &SparseMatrix) -> Option<Perm<usize>> {
    metis_on_patterns(&[a])
}

/// [`metis_nested_dissection`] of the union of the patterns of `mats` (same dimension, e.g. `K`
/// and `M` for the ordering of `K - s M`), read from the matrices without forming the union.
/// Consecutive columns are one supervariable if their patterns are equal in every matrix.
pub(crate) fn metis_on_patterns(mats: &[&SparseMatrix]) -> Option<Perm<usize>> {
    let n = mats.first()?.nrows();
    if mats.iter().any(|a| a.nrows() != n || a.ncols() != n) {
        return None;
    }
    // 1. supervariables: runs of consecutive columns with identical row patterns.
    let mut group_of = vec![0usize; n];
    let mut group_start = vec![0usize];
    let (mut prev, mut cur) = (Vec::new(), Vec::new());
    union_rows(mats, 0, &mut prev);
    for (j, g) in group_of.iter_mut().enumerate().skip(1) {
        union_rows(mats, j, &mut cur);
        if cur != prev {
            group_start.push(j);
        }
        std::mem::swap(&mut prev, &mut cur);
        *g = group_start.len() - 1;
    }
    let ng = group_start.len();
    group_start.push(n);
    // 2. compressed graph (CSR, no self loops, no duplicates).
    let mut xadj: Vec<i32> = Vec::with_capacity(ng + 1);
    let mut adjncy: Vec<i32> = Vec::new();
    let mut mark = vec![usize::MAX; ng];
    xadj.push(0);
    for g in 0..ng {
        mark[g] = g;
        let first = adjncy.len();
        for a in mats {
            for &i in a.row_idx_of_col_raw(group_start[g]) {
                let h = group_of[i];
                if mark[h] != g {
                    mark[h] = g;
                    adjncy.push(i32::try_from(h).ok()?);
                }
            }
        }
        // ascending, as read from one pattern (METIS' result depends on the order)
        if mats.len() > 1 {
            adjncy[first..].sort_unstable();
        }
        xadj.push(i32::try_from(adjncy.len()).ok()?);
    }
    if adjncy.is_empty() {
        return None;
    }
    let mut vwgt: Vec<i32> = (0..ng)
        .map(|g| i32::try_from(group_start[g + 1] - group_start[g]).unwrap_or(i32::MAX))
        .collect();
    let mut nvtxs = i32::try_from(ng).ok()?;
    let mut options = [0i32; metis_sys::METIS_NOPTIONS as usize];
    let mut perm = vec![0i32; ng];
    let mut iperm = vec![0i32; ng];
    // SAFETY: METIS_SetDefaultOptions writes exactly METIS_NOPTIONS entries; METIS_NodeND
    // reads nvtxs+1 entries of xadj, xadj[nvtxs] entries of adjncy and nvtxs of vwgt,
    // and writes nvtxs entries of perm and iperm. All buffers have these sizes, the
    // graph is symmetric without self loops (built above from a symmetric pattern),
    // and none of the pointers is retained after the calls return.
    // METIS keeps its random generator in process-global state: calls from two threads at once
    // (parallel tests, a Python sweep) would race and make the ordering depend on timing
    let _metis = METIS_LOCK
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            vwgt.as_mut_ptr(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return None;
    }
    // METIS: row i of the permuted matrix is row perm[i] of the original (faer's `forward`).
    let mut fwd = Vec::with_capacity(n);
    for &g in &perm {
        let g = usize::try_from(g).ok()?;
        fwd.extend(group_start[g]..group_start[g + 1]);
    }
    let mut inv = vec![0usize; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    Some(Perm::new_checked(
        fwd.into_boxed_slice(),
        inv.into_boxed_slice(),
        n,
    ))
}

/// The sorted union of the row indices of column `j` of `mats` (sorted rows each) into `out`.
fn union_rows(mats: &[&SparseMatrix], j: usize, out: &mut Vec<usize>) {
    out.clear();
    for a in mats {
        out.extend_from_slice(a.row_idx_of_col_raw(j));
    }
    if mats.len() > 1 {
        out.sort_unstable();
        out.dedup();
    }
}

/// Inertia of a symmetric matrix: numbers of negative, (numerically) zero and
/// positive pivots of `L D L^T` (Sylvester's law of inertia).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Inertia {
    /// Number of negative pivots = number of negative eigenvalues.
    pub negative: usize,
    /// Number of pivots with `|d| <= 1e-13 * max|a_ii|` (the count is then unreliable).
    pub near_zero: usize,
    /// Number of positive pivots.
    pub positive: usize,
}

/// Inertia of the symmetric matrix `a` from a sparse `L D L^T` factorization without
/// pivoting (faer, METIS ordering). Returns `None` if a pivot is exactly zero.
///
/// For `a = K - b M` with `M` positive definite, `negative` is the number of
/// eigenvalues of `K x = lambda M x` below `b` (Sturm sequence property).
pub fn ldlt_inertia(a: &SparseMatrix) -> Result<Option<Inertia>, FeError> {
    let symbolic = symbolic_factor(a)?;
    let par = Par::Seq;
    let req =
        symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Spec::<LdltParams, f64>::default());
    crate::memory::check_allocation(
        &format!("the LDL^T factor of {} equations (Sturm check)", a.nrows()),
        factor_bytes(symbolic.len_val(), req.size_bytes()),
    )?;
    let mut values = zeros_or_refused(symbolic.len_val())?;
    inertia_with_symbolic(&symbolic, a.as_ref(), &mut values)
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
        if a.nrows() != self.dim() || a.compute_nnz() > self.pattern_nnz || self.shifted.is_some() {
            return ldlt_inertia(a);
        }
        self.stale = true;
        inertia_with_symbolic(&self.symbolic, a.as_ref(), &mut self.values)
    }

    /// [`Self::inertia_in_place`] of `K - b M` for a factor of [`Self::factor_shifted_observed`]
    /// (the values refilled into its ordered pattern); other factors build [`super::shifted_lower`].
    pub(crate) fn inertia_shifted_in_place(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        b: f64,
    ) -> Result<Option<Inertia>, FeError> {
        let Some(pattern) = &self.shifted else {
            return self.inertia_in_place(&super::shifted_lower(k, m, b)?);
        };
        let values = pattern.values(k, m, b)?;
        let a = faer::sparse::SparseColMatRef::new(pattern.symbolic.as_ref(), &values);
        self.stale = true;
        inertia_with_symbolic(&self.symbolic, a, &mut self.values)
    }

    /// [`Self::factor_ldlt_in_place`] of `K - s M` (see [`Self::inertia_shifted_in_place`]).
    pub(crate) fn factor_ldlt_shifted_in_place(
        &mut self,
        k: &SparseMatrix,
        m: &SparseMatrix,
        s: f64,
    ) -> Result<Option<Inertia>, FeError> {
        let Some(pattern) = &self.shifted else {
            return self.factor_ldlt_in_place(&super::shifted_lower(k, m, s)?);
        };
        let values = pattern.values(k, m, s)?;
        let a = faer::sparse::SparseColMatRef::new(pattern.symbolic.as_ref(), &values);
        self.stale = true;
        self.ldlt = false;
        let inertia = inertia_with_symbolic(&self.symbolic, a, &mut self.values)?;
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
        let Some(pattern) = &self.shifted else {
            return self.refactor(&super::shifted_lower(k, m, s)?);
        };
        let values = pattern.values(k, m, s)?;
        let a = faer::sparse::SparseColMatRef::new(pattern.symbolic.as_ref(), &values);
        refactor_llt(&self.symbolic, a, &mut self.values)?;
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
        if a.nrows() != self.dim() || a.compute_nnz() > self.pattern_nnz || self.shifted.is_some() {
            return Err(FeError::Invalid(
                "L D L^T pattern outside the factored pattern".into(),
            ));
        }
        self.stale = true;
        self.ldlt = false;
        let inertia = inertia_with_symbolic(&self.symbolic, a.as_ref(), &mut self.values)?;
        if inertia.is_some() {
            self.stale = false;
            self.ldlt = true;
        }
        Ok(inertia)
    }

    /// Numeric `L L^T` factorization of `a` (full storage or its lower triangle, pattern within
    /// the original one) into this factor's storage, reusing the symbolic analysis.
    pub(crate) fn refactor(&mut self, a: &SparseMatrix) -> Result<(), FeError> {
        if self.shifted.is_some() {
            return Err(FeError::Invalid(
                "refactor of a factor on an ordered pattern: use refactor_shifted".into(),
            ));
        }
        refactor_llt(&self.symbolic, a.as_ref(), &mut self.values)?;
        self.stale = false;
        self.ldlt = false;
        Ok(())
    }
}

/// Numeric `L L^T` of `a` into `values` with the symbolic analysis `symbolic`.
fn refactor_llt(
    symbolic: &SymbolicCholesky<usize>,
    a: faer::sparse::SparseColMatRef<'_, usize, f64>,
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

fn inertia_with_symbolic(
    symbolic: &SymbolicCholesky<usize>,
    a: faer::sparse::SparseColMatRef<'_, usize, f64>,
    values: &mut [f64],
) -> Result<Option<Inertia>, FeError> {
    let par = Par::Seq;
    let req =
        symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Spec::<LdltParams, f64>::default());
    let mut mem = MemBuffer::try_new(req).map_err(|_| oom())?;
    let res = symbolic.factorize_numeric_ldlt(
        values,
        a,
        Side::Lower,
        LdltRegularization::default(),
        par,
        MemStack::new(&mut mem),
        Spec::<LdltParams, f64>::default(),
    );
    if res.is_err() {
        return Ok(None);
    }
    let diag = ldlt_diagonal(symbolic, values);
    let scale = (0..a.ncols())
        .flat_map(|j| {
            a.row_idx_of_col_raw(j)
                .iter()
                .zip(a.val_of_col(j))
                .filter(move |(&i, _)| i == j)
                .map(|(_, v)| v.abs())
        })
        .fold(0.0f64, f64::max);
    let tiny = 1e-13 * scale;
    let mut inertia = Inertia {
        negative: 0,
        near_zero: 0,
        positive: 0,
    };
    for d in diag {
        if d.abs() <= tiny || !d.is_finite() {
            inertia.near_zero += 1;
        } else if d < 0.0 {
            inertia.negative += 1;
        } else {
            inertia.positive += 1;
        }
    }
    Ok(Some(inertia))
}

/// Extracts the pivots `D` of an `L D L^T` factor stored by faer.
fn ldlt_diagonal(symbolic: &SymbolicCholesky<usize>, values: &[f64]) -> Vec<f64> {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            // column j of the simplicial factor starts with its diagonal entry (which holds d_j)
            let col_ptr = s.col_ptr();
            let row_idx = s.row_idx();
            (0..s.nrows())
                .map(|j| {
                    (col_ptr[j]..col_ptr[j + 1])
                        .find(|&p| row_idx[p] == j)
                        .map_or(0.0, |p| values[p])
                })
                .collect()
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let ldlt = supernodal::SupernodalLdltRef::new(s, values);
            let mut d = Vec::with_capacity(s.nrows());
            for k in 0..s.n_supernodes() {
                let node = ldlt.supernode(k);
                let v = node.val();
                for c in 0..v.ncols() {
                    d.push(v[(c, c)]);
                }
            }
            d
        }
    }
}
