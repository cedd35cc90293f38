//! Eigen solvers for the generalized symmetric problem `K phi = lambda M phi`
//! (`lambda = omega^2`), seed 000 ch. 2.3 / seed 001 ch. 3 (modal reduction).
//!
//! * [`dense_generalized`]: all pairs by Cholesky reduction (small models).
//! * [`lowest_modes`]: the lowest pairs of large sparse models by block shift-invert
//!   Lanczos on a METIS-ordered sparse Cholesky of `K - sigma M`, with locking of converged
//!   pairs and spectrum slicing (new shifts inside the spectrum, `L D L^T`, when a shift's
//!   round-off floor is reached), followed by a Sturm-sequence check (inertia of `K - b M` from
//!   `L D L^T`) so that missed copies of repeated eigenvalues are detected instead of going
//!   unnoticed (crate-stack.md §2.3, lesson 1).
//!
//! `K` may be singular (free-free bodies: 6 rigid-body modes, or mechanisms); the
//! automatic shift is negative, half the lowest nonzero eigenvalue below zero, so
//! `K - sigma M` stays positive definite.

mod basis;
mod cholesky;
mod dense;
mod driver;
mod inertia;
mod lanczos;
mod ops;
mod ordering;
mod shift;
mod split;
#[cfg(test)]
mod tests;

use faer::Mat;

pub use cholesky::SparseCholesky;
pub use dense::{dense_generalized, dense_shift_invert};
pub use inertia::{ldlt_inertia, Inertia};

use crate::{FeError, SparseMatrix};
use driver::lanczos_solution;
use ops::{apply_mass, apply_stiffness};
use ordering::{shifted_ordering, FillOrdering};

/// `A X` for a symmetric `A` in full storage (symmetric to round-off, as `K` and `M`): a pass
/// over `A` serves eight columns of `X`, the rows split between two threads (the result does not
/// depend on the machine). For many columns this is several times faster than a
/// compressed-column product.
pub fn symmetric_product(a: &SparseMatrix, x: faer::MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::zeros(a.nrows(), x.ncols());
    apply_stiffness(a, x, out.as_mut());
    out
}

/// Which algorithm [`lowest_modes`] uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EigenMethod {
    /// Dense below [`EigenOptions::dense_limit`] unknowns, Lanczos above.
    #[default]
    Auto,
    /// Dense Cholesky reduction + symmetric eigen decomposition (O(n^2) memory).
    Dense,
    /// Block shift-invert Lanczos on a sparse factorization.
    Lanczos,
}

/// Options of [`lowest_modes`].
#[derive(Clone, Debug)]
pub struct EigenOptions {
    /// Number of lowest eigenpairs wanted.
    pub n_modes: usize,
    /// Spectral shift `sigma`; must lie below the lowest eigenvalue (so that
    /// `K - sigma M` is positive definite). `None`: automatic, taken from the spectrum:
    /// `-lambda_e / 2` with `lambda_e` the lowest nonzero eigenvalue, estimated by short Lanczos
    /// runs started at `-1e-5 tr(K)/tr(M)`; safe for free-free models. Either shift is moved
    /// into the spectrum (slicing) if the wanted pairs cannot converge at it.
    pub shift: Option<f64>,
    /// Tolerance on the relative residual of every returned pair (see
    /// [`EigenSolution::residuals`]).
    pub tol: f64,
    /// Algorithm choice.
    pub method: EigenMethod,
    /// [`EigenMethod::Auto`] uses the dense solver up to this many unknowns.
    pub dense_limit: usize,
    /// Lanczos block size (number of vectors per step). Blocks catch multiplicities
    /// up to the block size directly; larger ones are caught by the Sturm check.
    pub block_size: usize,
    /// Maximum Lanczos basis size before a thick restart; 0 = automatic
    /// (`max(4 n_modes, 2 n_modes + 10 block_size)`, at most `n`).
    pub max_basis: usize,
    /// Verify the number of eigenvalues below a cut by the inertia of `K - b M`.
    pub sturm_check: bool,
    /// The model is supported (boundary conditions remove its rigid-body motion), so `K` is
    /// expected positive definite: with the automatic shift the solver first tries `sigma = 0`
    /// (`K` itself, factored once, a shift below the spectrum at the distance of the lowest
    /// eigenvalue) and takes the spectrum-probing shift only if `K` does not factor as positive
    /// definite (a mechanism). `false` (default): the spectrum-probing shift at once.
    pub supported: bool,
}

impl Default for EigenOptions {
    fn default() -> Self {
        Self {
            n_modes: 10,
            shift: None,
            tol: 1e-9,
            method: EigenMethod::Auto,
            dense_limit: 1500,
            block_size: 8,
            max_basis: 0,
            sturm_check: true,
            supported: false,
        }
    }
}

/// Progress events reported by [`lowest_modes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EigenEvent {
    /// A sparse factorization of `K - sigma M` is starting.
    Factorizing {
        /// Dimension.
        n: usize,
        /// Stored entries of `K` (the pattern of `K - sigma M` for FE matrices).
        nnz: usize,
    },
    /// The symbolic analysis is done: the size of the factor, before the numeric work.
    FactorEstimate {
        /// Stored entries of the factor `L`.
        nnz_l: usize,
        /// Bytes of `L` and the factorization's workspace (in the Lanczos path also the values
        /// of the shifted matrix the factorizations read).
        bytes: u64,
    },
    /// The factorization finished.
    Factorized {
        /// Stored entries of the factor `L`.
        nnz_l: usize,
    },
    /// One Lanczos block step finished.
    Iteration {
        /// Current basis size.
        basis: usize,
        /// Leading Ritz pairs converged (by the residual estimate).
        converged: usize,
        /// Number of pairs that must converge.
        wanted: usize,
    },
    /// A Sturm-sequence check was made.
    SturmCheck {
        /// Number of eigenvalues found below the cut.
        expected: usize,
        /// Number of negative pivots of `K - b M` (true count below the cut).
        found: usize,
    },
}

/// Result of [`lowest_modes`].
#[derive(Clone, Debug)]
pub struct EigenSolution {
    /// Eigenvalues `omega^2`, ascending.
    pub omega2: Vec<f64>,
    /// Eigenvectors as columns (`n x n_modes`), M-normalised: `X^T M X = I`.
    pub vectors: Mat<f64>,
    /// Relative residuals of the pairs.
    ///
    /// Lanczos path: the explicit residual of the shift-inverted operator `OP = (K - sigma M)^-1 M`,
    /// `||OP x - theta x||_M / (|theta| ||x||_M)` with `theta = 1 / (lambda - sigma)` and `sigma`
    /// the shift at which the pair converged; it bounds the eigenvalue error,
    /// `|lambda - lambda_exact| <= r |lambda - sigma|` (first order), i.e. relative to the pair's
    /// own scale (`|lambda - sigma| <= 1.5 |lambda|` for the automatic shift, `|lambda|` for a
    /// supported model started at `sigma = 0`; `|sigma|`, half the
    /// lowest nonzero eigenvalue, for zero-energy modes). The plain residual
    /// `||K x - lambda M x|| / (|lambda| ||M x||)` is not used: evaluating `K x` in floating point
    /// alone errs by `eps |K| |x|`, up to 2e-5 of `|lambda M x|` for the lowest mode of a slender
    /// beam (docs/decisions.md).
    ///
    /// Dense path: `||K x - lambda M x||_2 / ((|lambda| + |sigma|) ||M x||_2)` with the automatic
    /// shift value `-1e-5 tr(K)/tr(M)` used only as a scale.
    pub residuals: Vec<f64>,
    /// Sturm check `(eigenvalues returned below the cut, true count below the cut)`,
    /// `None` for the dense path (all eigenvalues known) or if disabled.
    pub sturm: Option<(usize, usize)>,
    /// The shift the Lanczos iteration started at (0 for a supported model whose `K` factors,
    /// see [`EigenOptions::supported`]); the dense path: the automatic shift value.
    pub start_shift: f64,
}

/// `K - sigma M` on the union of both sparsity patterns.
///
/// Errors: [`FeError::Invalid`] if the dimensions differ or the row indices are not sorted.
pub fn shifted(k: &SparseMatrix, m: &SparseMatrix, sigma: f64) -> Result<SparseMatrix, FeError> {
    if k.nrows() != m.nrows() || k.ncols() != m.ncols() {
        return Err(FeError::Invalid(format!(
            "K is {}x{} but M is {}x{}",
            k.nrows(),
            k.ncols(),
            m.nrows(),
            m.ncols()
        )));
    }
    for (name, a) in [("K", k), ("M", m)] {
        if !rows_sorted(a) {
            return Err(FeError::Invalid(format!("{name} has unsorted row indices")));
        }
    }
    faer::sparse::ops::binary_op(k.as_ref(), m.as_ref(), |a, b| {
        a.copied().unwrap_or(0.0) - sigma * b.copied().unwrap_or(0.0)
    })
    .map_err(|e| FeError::Invalid(format!("K - sigma M: {e:?}")))
}

/// The lower triangle (diagonal included) of `K - sigma M`, with the values of [`shifted`]: half
/// the memory, all a factorization with [`faer::Side::Lower`] reads. (The Lanczos driver's
/// factorizations read an ordered lower triangle kept with the factor instead, see
/// [`SparseCholesky::factor_shifted_observed`].)
pub fn shifted_lower(
    k: &SparseMatrix,
    m: &SparseMatrix,
    sigma: f64,
) -> Result<SparseMatrix, FeError> {
    if k.nrows() != m.nrows() || k.ncols() != m.ncols() || k.nrows() != k.ncols() {
        return Err(FeError::Invalid(format!(
            "K is {}x{} but M is {}x{}",
            k.nrows(),
            k.ncols(),
            m.nrows(),
            m.ncols()
        )));
    }
    let n = k.ncols();
    let (mut col_ptr, mut rows, mut values) = (Vec::with_capacity(n + 1), Vec::new(), Vec::new());
    col_ptr.push(0);
    for j in 0..n {
        let (kr, kv) = (k.row_idx_of_col_raw(j), k.val_of_col(j));
        let (mr, mv) = (m.row_idx_of_col_raw(j), m.val_of_col(j));
        let (mut a, mut b) = (
            kr.partition_point(|&i| i < j),
            mr.partition_point(|&i| i < j),
        );
        while a < kr.len() || b < mr.len() {
            let (ri, rm) = (kr.get(a).copied(), mr.get(b).copied());
            let row = ri.unwrap_or(usize::MAX).min(rm.unwrap_or(usize::MAX));
            let x = if ri == Some(row) {
                a += 1;
                Some(kv[a - 1])
            } else {
                None
            };
            let y = if rm == Some(row) {
                b += 1;
                Some(mv[b - 1])
            } else {
                None
            };
            rows.push(row);
            values.push(x.unwrap_or(0.0) - sigma * y.unwrap_or(0.0));
        }
        col_ptr.push(rows.len());
    }
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows);
    Ok(faer::sparse::SparseColMat::new(symbolic, values))
}

fn rows_sorted(a: &SparseMatrix) -> bool {
    (0..a.ncols()).all(|j| a.row_idx_of_col_raw(j).windows(2).all(|w| w[0] < w[1]))
}

/// Checks that `K` and `M` are square, of equal size, finite, symmetric (relative
/// tolerance 1e-10) with sorted indices, and that `M` has a positive diagonal.
fn validate(k: &SparseMatrix, m: &SparseMatrix) -> Result<(), FeError> {
    if k.nrows() != k.ncols() || m.nrows() != m.ncols() || k.nrows() != m.nrows() {
        return Err(FeError::Invalid(format!(
            "K is {}x{} and M is {}x{}: both must be square and of equal size",
            k.nrows(),
            k.ncols(),
            m.nrows(),
            m.ncols()
        )));
    }
    // K and M checked on two threads
    let (rk, rm) = std::thread::scope(|s| {
        let h = s.spawn(|| check_symmetric("M", m));
        let rk = check_symmetric("K", k);
        (
            rk,
            h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)),
        )
    });
    rk?;
    rm?;
    let d = diagonal(m);
    if let Some((i, v)) = d.iter().enumerate().find(|(_, v)| **v <= 0.0) {
        return Err(FeError::NotPositiveDefinite {
            what: "mass matrix M".into(),
            hint: format!(": diagonal entry {i} is {v:e} (must be > 0)"),
        });
    }
    Ok(())
}

/// Sorted rows, finite values and symmetry (relative tolerance 1e-10) of the matrix `name`.
fn check_symmetric(name: &str, a: &SparseMatrix) -> Result<(), FeError> {
    if !rows_sorted(a) {
        return Err(FeError::Invalid(format!(
            "{name} has unsorted or duplicate row indices"
        )));
    }
    let amax = a.val().iter().fold(0.0f64, |s, v| s.max(v.abs()));
    if !amax.is_finite() {
        return Err(FeError::Invalid(format!("{name} has non-finite entries")));
    }
    let asym = max_asymmetry(a);
    if asym > 1e-10 * amax {
        return Err(FeError::Invalid(format!(
            "{name} is not symmetric: max |a_ij - a_ji| = {asym:e} (max |a_ij| = {amax:e})"
        )));
    }
    Ok(())
}

/// `max |a_ij - a_ji|` over the stored entries (a missing mirror entry counts as zero), without
/// a transposed copy of `a`: the mirror of entry `(i, j)` is row `j` of column `i`, and for a
/// fixed column `i` the rows asked for grow with `j`, so one cursor per column finds every mirror
/// in a single pass (rows sorted, [`rows_sorted`]).
fn max_asymmetry(a: &SparseMatrix) -> f64 {
    let mut cursor = vec![0usize; a.ncols()];
    let mut asym = 0.0f64;
    for j in 0..a.ncols() {
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            let rows = a.row_idx_of_col_raw(i);
            let c = &mut cursor[i];
            while *c < rows.len() && rows[*c] < j {
                *c += 1;
            }
            let mirror = if rows.get(*c) == Some(&j) {
                a.val_of_col(i)[*c]
            } else {
                0.0
            };
            asym = asym.max((v - mirror).abs());
        }
    }
    asym
}

fn diagonal(a: &SparseMatrix) -> Vec<f64> {
    (0..a.ncols())
        .map(|j| {
            a.row_idx_of_col_raw(j)
                .iter()
                .zip(a.val_of_col(j))
                .filter(|(&i, _)| i == j)
                .map(|(_, v)| *v)
                .sum()
        })
        .collect()
}

/// Starting shift `-1e-5 tr(K) / tr(M)` (tr(K)/tr(M) is a mean Rayleigh quotient
/// of the unit vectors, a scale of the spectrum).
fn automatic_shift(k: &SparseMatrix, m: &SparseMatrix) -> f64 {
    let tk: f64 = diagonal(k).iter().map(|v| v.abs()).sum();
    let tm: f64 = diagonal(m).iter().sum();
    let s = if tk > 0.0 && tm > 0.0 { tk / tm } else { 1.0 };
    -1e-5 * s
}

/// Rayleigh quotients, M-normalisation and relative residuals of the columns of `x`.
fn rayleigh_and_residuals(
    k: &SparseMatrix,
    m: &SparseMatrix,
    x: &mut Mat<f64>,
    sigma: f64,
) -> (Vec<f64>, Vec<f64>) {
    let (n, p) = (x.nrows(), x.ncols());
    let mut kx = Mat::zeros(n, p);
    let mut mx = Mat::zeros(n, p);
    apply_stiffness(k, x.as_ref(), kx.as_mut());
    apply_mass(m, x.as_ref(), mx.as_mut());
    let mut lam = Vec::with_capacity(p);
    let mut res = Vec::with_capacity(p);
    for j in 0..p {
        let xmx = x.col(j).transpose() * mx.col(j);
        let xkx = x.col(j).transpose() * kx.col(j);
        let l = xkx / xmx;
        let s = 1.0 / xmx.sqrt();
        let r = (0..n)
            .map(|i| (kx[(i, j)] - l * mx[(i, j)]).powi(2))
            .sum::<f64>()
            .sqrt();
        res.push(r / ((l.abs() + sigma.abs()) * mx.col(j).norm_l2()));
        lam.push(l);
        for i in 0..n {
            x[(i, j)] *= s;
        }
    }
    (lam, res)
}

/// Sorts eigenpairs ascending by eigenvalue.
fn sort_pairs(lam: Vec<f64>, res: Vec<f64>, x: &Mat<f64>) -> (Vec<f64>, Vec<f64>, Mat<f64>) {
    let mut idx: Vec<usize> = (0..lam.len()).collect();
    idx.sort_by(|&a, &b| lam[a].total_cmp(&lam[b]));
    let xs = Mat::from_fn(x.nrows(), idx.len(), |i, j| x[(i, idx[j])]);
    (
        idx.iter().map(|&i| lam[i]).collect(),
        idx.iter().map(|&i| res[i]).collect(),
        xs,
    )
}

/// The `opts.n_modes` lowest eigenpairs of `K phi = lambda M phi` (`K` symmetric,
/// possibly singular; `M` symmetric positive definite, lumped or consistent).
///
/// Errors: [`FeError::Invalid`] for bad input (dimensions, asymmetry, non-finite
/// values, `n_modes > n`), [`FeError::NotPositiveDefinite`] if `M` (or `K - sigma M`
/// for a user shift) is not positive definite, [`FeError::EigenNotConverged`] if the
/// iteration or the Sturm check fails.
pub fn lowest_modes(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<EigenSolution, FeError> {
    lowest_modes_started(k, m, opts, None, progress)
}

/// [`lowest_modes`] of a model whose `K` is positive definite, started from `k_factor`, the
/// factorization of `K` itself (shift 0, by [`SparseCholesky::factor_shifted_observed`] of
/// `K` and `M`): a caller that has solved with `K` already (the static constraint modes of
/// Craig-Bampton, seed 001 ch. 3) saves the eigen solver's first factorization. The sparse
/// solver starts at shift 0 with it and later refactors it in place; the dense path and a
/// user shift (`opts.shift`) do not use it.
///
/// Errors: as [`lowest_modes`]; [`FeError::Invalid`] if `k_factor` has another dimension than
/// `K`.
pub fn lowest_modes_from_k_factor(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
    k_factor: SparseCholesky,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<EigenSolution, FeError> {
    if k_factor.dim() != k.nrows() {
        return Err(FeError::Invalid(format!(
            "the factorization of K has dimension {}, K {}",
            k_factor.dim(),
            k.nrows()
        )));
    }
    lowest_modes_started(k, m, opts, Some(k_factor), progress)
}

/// [`lowest_modes`], with the factorization of `K` to start the sparse solver from if given.
fn lowest_modes_started(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
    k_factor: Option<SparseCholesky>,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<EigenSolution, FeError> {
    let n = k.nrows();
    let nm = opts.n_modes;
    let dense = match opts.method {
        EigenMethod::Dense => true,
        EigenMethod::Lanczos => false,
        EigenMethod::Auto => n <= opts.dense_limit,
    };
    // the factor serves the sparse solver's default start only
    let k_factor = k_factor.filter(|_| !dense && nm > 0 && opts.shift.is_none());
    let ordering = checked_with_ordering(k, m, !dense && nm > 0 && k_factor.is_none())?;
    if nm > n {
        return Err(FeError::Invalid(format!(
            "{nm} modes requested but the model has only {n} unknowns"
        )));
    }
    if !(opts.tol > 0.0 && opts.tol < 1.0) {
        return Err(FeError::Invalid(format!(
            "eigen tolerance {} must lie in (0, 1)",
            opts.tol
        )));
    }
    if nm == 0 {
        return Ok(EigenSolution {
            omega2: vec![],
            vectors: Mat::zeros(n, 0),
            residuals: vec![],
            sturm: None,
            start_shift: 0.0,
        });
    }
    if dense {
        crate::memory::check_dense_eigen(n)?;
        let sigma = opts.shift.unwrap_or_else(|| automatic_shift(k, m));
        let (lam, x) = dense_shift_invert(k.to_dense().as_ref(), m.to_dense().as_ref(), sigma)?;
        if lam.len() < nm {
            return Err(FeError::Invalid(format!(
                "{nm} modes requested but the mass matrix has rank {}",
                lam.len()
            )));
        }
        let mut x = x.subcols(0, nm).to_owned();
        let (_, res) = rayleigh_and_residuals(k, m, &mut x, sigma);
        return Ok(EigenSolution {
            omega2: lam[..nm].to_vec(),
            vectors: x,
            residuals: res,
            sturm: None,
            start_shift: sigma,
        });
    }
    lanczos_solution(k, m, opts, ordering, k_factor, progress)
}

/// [`validate`]; with `order`, the fill-reducing ordering of `K - s M` (patterns only) is
/// computed on a second thread meanwhile (dimensions checked first). An invalid input is
/// reported as by [`validate`] whatever happened to the ordering.
fn checked_with_ordering(
    k: &SparseMatrix,
    m: &SparseMatrix,
    order: bool,
) -> Result<Option<FillOrdering>, FeError> {
    let square = k.nrows() == k.ncols() && m.nrows() == m.ncols() && k.nrows() == m.nrows();
    if !(order && square) {
        validate(k, m)?;
        return Ok(None);
    }
    let (valid, ordering) = std::thread::scope(|s| {
        let h = s.spawn(|| shifted_ordering(k, m));
        (validate(k, m), h.join())
    });
    valid?;
    match ordering {
        Ok(o) => o.map(Some),
        Err(panic) => std::panic::resume_unwind(panic),
    }
}
