//! Fill-reducing orderings of sparse symmetric matrices: METIS nested dissection on the graph
//! of the sparsity pattern (supervariables compressed first), faer's AMD as the fallback, and
//! the two-domain variant whose top separator the split factorization uses
//! ([`super::split`]).

use faer::perm::Perm;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::Side;

use crate::{FeError, SparseMatrix};

/// A fill-reducing ordering of `K - s M` ([`shifted_ordering`]).
#[derive(Debug)]
pub(crate) enum FillOrdering {
    /// METIS' top bisection, accepted for the two-domain factorization ([`super::split`]).
    TwoDomains(Perm<usize>, TwoDomains),
    /// One ordering of the whole matrix (METIS; AMD for small or edgeless graphs).
    Whole(Perm<usize>),
}

/// The ordering of `K - s M` for any shift, from the patterns of `K` and `M` (values not read):
/// METIS' two domains from [`super::split::SPLIT_MIN_DIM`] unknowns if they pay
/// ([`super::split::accept`]; otherwise METIS' ordering of the whole), METIS from
/// [`METIS_MIN_DIM`], AMD below or if METIS fails.
pub(crate) fn shifted_ordering(
    k: &SparseMatrix,
    m: &SparseMatrix,
) -> Result<FillOrdering, FeError> {
    let perm = if k.nrows() >= super::split::SPLIT_MIN_DIM {
        match metis_two_domains(&[k, m]) {
            Some((p, d)) if super::split::accept(&d) => return Ok(FillOrdering::TwoDomains(p, d)),
            Some((p, _)) => Some(p),
            None => metis_on_patterns(&[k, m]),
        }
    } else if k.nrows() >= METIS_MIN_DIM {
        metis_on_patterns(&[k, m])
    } else {
        None
    };
    Ok(FillOrdering::Whole(match perm {
        Some(p) => p,
        None => amd_ordering(&super::shifted(k, m, 1.0)?)?,
    }))
}

/// Serializes the calls into METIS (see [`metis_on_patterns`]).
static METIS_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Matrices below this dimension are ordered with faer's AMD instead of METIS.
pub(super) const METIS_MIN_DIM: usize = 64;

/// faer's AMD ordering of the pattern of `a` (full storage).
pub(super) fn amd_ordering(a: &SparseMatrix) -> Result<Perm<usize>, FeError> {
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
    let g = CompressedGraph::new(mats)?;
    let perm = g.order(None)?;
    g.expand(&perm)
}

/// Sizes of the two domains and of their separator in [`metis_two_domains`] (DOFs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TwoDomains {
    /// DOFs of the first domain (ordered first).
    pub first: usize,
    /// DOFs of the second domain (ordered next).
    pub second: usize,
    /// DOFs of the separator (ordered last).
    pub separator: usize,
}

/// [`metis_on_patterns`] that also reports METIS' top-level bisection (`METIS_NodeNDP` with two
/// parts): the ordering lists the first domain, the second domain, then the vertex separator,
/// each domain in its own nested-dissection order. No entry of the matrices couples the two
/// domains (checked here on the patterns: `None` if one did, or if METIS fails).
pub(crate) fn metis_two_domains(mats: &[&SparseMatrix]) -> Option<(Perm<usize>, TwoDomains)> {
    let g = CompressedGraph::new(mats)?;
    let mut sizes = [0i32; 3];
    let perm = g.order(Some(&mut sizes))?;
    let perm = g.expand(&perm)?;
    let first = usize::try_from(sizes[0]).ok()?;
    let second = usize::try_from(sizes[1]).ok()?;
    let separator = usize::try_from(sizes[2]).ok()?;
    let n = g.group_start[g.group_start.len() - 1];
    if first + second + separator != n {
        return None;
    }
    let (_, inv) = perm.as_ref().arrays();
    let domain = |old: usize| match inv[old] {
        i if i < first => 0u8,
        i if i < first + second => 1,
        _ => 2,
    };
    for a in mats {
        for j in 0..n {
            let dj = domain(j);
            if dj < 2 && a.row_idx_of_col_raw(j).iter().any(|&i| domain(i) == 1 - dj) {
                return None;
            }
        }
    }
    Some((
        perm,
        TwoDomains {
            first,
            second,
            separator,
        },
    ))
}

/// The graph of a symmetric pattern with runs of consecutive columns of equal patterns (the
/// DOFs of one FE node) compressed into one vertex weighted by the run's length (METIS' CSR
/// arrays, no self loops, no duplicates).
struct CompressedGraph {
    xadj: Vec<i32>,
    adjncy: Vec<i32>,
    vwgt: Vec<i32>,
    /// First column of each vertex, then `n`.
    group_start: Vec<usize>,
}

impl CompressedGraph {
    /// `None` if the graph has no edges or is too large for METIS' 32-bit indices.
    fn new(mats: &[&SparseMatrix]) -> Option<Self> {
        let n = mats.first()?.nrows();
        if mats.iter().any(|a| a.nrows() != n || a.ncols() != n) {
            return None;
        }
        // a pattern within another one adds nothing to the union (consistent M: equal to K's;
        // lumped M: K's diagonal)
        let mut kept: Vec<&SparseMatrix> = Vec::with_capacity(mats.len());
        for (i, &a) in mats.iter().enumerate() {
            let covered = |b: &SparseMatrix| pattern_within(a, b);
            if !kept.iter().any(|&b| covered(b))
                && !mats[i + 1..]
                    .iter()
                    .any(|&b| covered(b) && !pattern_within(b, a))
            {
                kept.push(a);
            }
        }
        let mats = &kept[..];
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
        let vwgt: Vec<i32> = (0..ng)
            .map(|g| i32::try_from(group_start[g + 1] - group_start[g]).unwrap_or(i32::MAX))
            .collect();
        Some(Self {
            xadj,
            adjncy,
            vwgt,
            group_start,
        })
    }

    /// METIS' nested-dissection ordering of the vertices (`perm[new] = old`): `METIS_NodeND`, or
    /// `METIS_NodeNDP` with two parts when `sizes` is given (it receives the weights of the first
    /// part, the second part and the top separator). `None` if METIS reports an error.
    fn order(&self, sizes: Option<&mut [i32; 3]>) -> Option<Vec<i32>> {
        let ng = self.vwgt.len();
        let (mut xadj, mut adjncy, mut vwgt) =
            (self.xadj.clone(), self.adjncy.clone(), self.vwgt.clone());
        let mut nvtxs = i32::try_from(ng).ok()?;
        let mut options = [0i32; metis_sys::METIS_NOPTIONS as usize];
        let mut perm = vec![0i32; ng];
        let mut iperm = vec![0i32; ng];
        // METIS keeps its random generator in process-global state: calls from two threads at
        // once (parallel tests, a Python sweep) would race and make the ordering depend on timing
        let _metis = METIS_LOCK
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        // SAFETY: METIS_SetDefaultOptions writes exactly METIS_NOPTIONS entries; METIS_NodeND and
        // METIS_NodeNDP read nvtxs+1 entries of xadj, xadj[nvtxs] entries of adjncy and nvtxs of
        // vwgt, and write nvtxs entries of perm and iperm (NodeNDP with npes = 2 also writes
        // 2 npes - 1 = 3 entries of sizes). All buffers have these sizes, the graph is symmetric
        // without self loops (built from a symmetric pattern), and none of the pointers is
        // retained after the calls return.
        let status = unsafe {
            metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
            match sizes {
                None => metis_sys::METIS_NodeND(
                    &mut nvtxs,
                    xadj.as_mut_ptr(),
                    adjncy.as_mut_ptr(),
                    vwgt.as_mut_ptr(),
                    options.as_mut_ptr(),
                    perm.as_mut_ptr(),
                    iperm.as_mut_ptr(),
                ),
                Some(sizes) => metis_sys::METIS_NodeNDP(
                    nvtxs,
                    xadj.as_mut_ptr(),
                    adjncy.as_mut_ptr(),
                    vwgt.as_mut_ptr(),
                    2,
                    options.as_mut_ptr(),
                    perm.as_mut_ptr(),
                    iperm.as_mut_ptr(),
                    sizes.as_mut_ptr(),
                ),
            }
        };
        (status == metis_sys::rstatus_et_METIS_OK).then_some(perm)
    }

    /// The ordering of the columns from an ordering of the vertices (each vertex's columns in
    /// their original order).
    fn expand(&self, perm: &[i32]) -> Option<Perm<usize>> {
        let n = self.group_start[self.group_start.len() - 1];
        // METIS: row i of the permuted matrix is row perm[i] of the original (faer's `forward`).
        let mut fwd = Vec::with_capacity(n);
        for &g in perm {
            let g = usize::try_from(g).ok()?;
            fwd.extend(self.group_start[g]..self.group_start[g + 1]);
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
}

/// Whether every stored entry of `a` is stored in `b` (same dimension, sorted rows).
pub(super) fn pattern_within(a: &SparseMatrix, b: &SparseMatrix) -> bool {
    let (sa, sb) = (a.symbolic(), b.symbolic());
    if sa.col_ptr() == sb.col_ptr() && sa.row_idx() == sb.row_idx() {
        return true;
    }
    (0..a.ncols()).all(|j| {
        let rb = b.row_idx_of_col_raw(j);
        let mut p = 0;
        a.row_idx_of_col_raw(j).iter().all(|&i| {
            while p < rb.len() && rb[p] < i {
                p += 1;
            }
            p < rb.len() && rb[p] == i
        })
    })
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
