//! The inertia (Sturm count) of a symmetric matrix from an `L D L^T` factorization without
//! pivoting (Sylvester's law of inertia).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::ldlt::factor::{LdltParams, LdltRegularization};
use faer::sparse::linalg::cholesky::{supernodal, SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Par, Side, Spec};

use super::cholesky::{factor_bytes, oom, symbolic_factor, zeros_or_refused};
use crate::{FeError, SparseMatrix};

/// Inertia of a symmetric matrix: numbers of negative, (numerically) zero and
/// positive pivots of `L D L^T` (Sylvester's law of inertia).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Inertia {
    /// Number of negative pivots = number of negative eigenvalues.
    pub negative: usize,
    /// Number of pivots with `|d| <= 1e-13 * max|a_ii|` (the count is then unreliable).
    pub near_zero: usize,
    /// Number of positive pivots.
    pub positive: usize,
}

impl Inertia {
    /// Counts the pivot `d`: near zero if `|d| <= tiny` or not finite.
    pub(super) fn count(&mut self, d: f64, tiny: f64) {
        if d.abs() <= tiny || !d.is_finite() {
            self.near_zero += 1;
        } else if d < 0.0 {
            self.negative += 1;
        } else {
            self.positive += 1;
        }
    }
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

pub(super) fn inertia_with_symbolic(
    symbolic: &SymbolicCholesky<usize>,
    a: faer::sparse::SparseColMatRef<'_, usize, f64>,
    values: &mut [f64],
) -> Result<Option<Inertia>, FeError> {
    if !ldlt_numeric(symbolic, a, values)? {
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
    let mut inertia = Inertia::default();
    for d in diag {
        inertia.count(d, tiny);
    }
    Ok(Some(inertia))
}

/// Numeric `L D L^T` (no pivoting) of `a` into `values` with the symbolic analysis `symbolic`;
/// `false` if a pivot vanished.
pub(super) fn ldlt_numeric<I: faer::Index>(
    symbolic: &SymbolicCholesky<I>,
    a: faer::sparse::SparseColMatRef<'_, I, f64>,
    values: &mut [f64],
) -> Result<bool, FeError> {
    let par = Par::Seq;
    let req =
        symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Spec::<LdltParams, f64>::default());
    let mut mem = MemBuffer::try_new(req).map_err(|_| oom())?;
    Ok(symbolic
        .factorize_numeric_ldlt(
            values,
            a,
            Side::Lower,
            LdltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Spec::<LdltParams, f64>::default(),
        )
        .is_ok())
}

/// Extracts the pivots `D` of an `L D L^T` factor stored by faer.
pub(super) fn ldlt_diagonal<I: faer::Index>(
    symbolic: &SymbolicCholesky<I>,
    values: &[f64],
) -> Vec<f64> {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            // column j of the simplicial factor starts with its diagonal entry (which holds d_j)
            let col_ptr = s.col_ptr();
            let row_idx = s.row_idx();
            (0..s.nrows())
                .map(|j| {
                    (col_ptr[j].zx()..col_ptr[j + 1].zx())
                        .find(|&p| row_idx[p].zx() == j)
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
