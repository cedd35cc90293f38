//! The CalculiX matrix export of `*FREQUENCY, SOLVER=MATRIXSTORAGE`: `job.sti` (stiffness K),
//! `job.mas` (consistent mass M) and `job.dof` (equation -> node and direction).
//!
//! `.sti`/`.mas`: one entry per line, `row col value`, 1-based equation numbers, upper triangle
//! including the diagonal (`row <= col`), every diagonal present. The full symmetric matrix is
//! `U + U^T - diag(U)`. `.dof`: line `k` is equation `k`, written `node.direction`; it is split at
//! the dot into two integers (never read as a float: `651.10` is not `651.1`). Directions 1-3
//! are translations; 4-6 (rotations, e.g. of ccx knots) are accepted as well.

use crate::error::{excerpt, parse_finite, read_text, IoError};
use faer::sparse::Triplet;
use faer::Mat;
use flexmbs_fe::{Mesh, SparseMatrix};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Stiffness, mass and DOF map of one CalculiX matrix export.
#[derive(Debug, Clone)]
pub struct CcxMatrices {
    /// Stiffness matrix K, full symmetric storage.
    pub k: SparseMatrix,
    /// Consistent mass matrix M, full symmetric storage.
    pub m: SparseMatrix,
    /// For each equation: (node label, direction 1..=6).
    pub dofs: Vec<(u64, u8)>,
}

/// Parses a `.sti` or `.mas` file (upper triangle, 1-based) into the full symmetric matrix.
/// Errors: malformed line, `row > col`, non-finite value, repeated position, missing diagonal.
pub fn parse_ccx_matrix(text: &str, file: &Path) -> Result<SparseMatrix, IoError> {
    // (col, row, value, line), all 0-based indices.
    let mut ent: Vec<(usize, usize, f64, usize)> = Vec::new();
    for (i, l) in text.lines().enumerate() {
        let ln = i + 1;
        let t: Vec<&str> = l.split_whitespace().collect();
        if t.is_empty() {
            continue;
        }
        if t.len() != 3 {
            return Err(IoError::parse(
                file,
                ln,
                "3 fields (row col value)",
                format!("{}: {}", t.len(), excerpt(l)),
            ));
        }
        let idx = |s: &str, what: &str| -> Result<usize, IoError> {
            match s.parse::<usize>() {
                Ok(v) if v >= 1 => Ok(v - 1),
                _ => Err(IoError::parse(
                    file,
                    ln,
                    format!("a 1-based {what} index"),
                    excerpt(s),
                )),
            }
        };
        let (r, c) = (idx(t[0], "row")?, idx(t[1], "column")?);
        if r > c {
            return Err(IoError::invalid(
                file,
                ln,
                format!("entry ({}, {}) below the diagonal: the export holds the upper triangle (row <= col)", r + 1, c + 1),
            ));
        }
        ent.push((c, r, parse_finite(t[2], file, ln, "matrix value")?, ln));
    }
    if ent.is_empty() {
        return Err(IoError::inconsistent(
            file,
            "no matrix entries (empty file)",
        ));
    }
    ent.sort_by_key(|e| (e.0, e.1));
    for w in ent.windows(2) {
        if (w[0].0, w[0].1) == (w[1].0, w[1].1) {
            let (first, second) = (w[0].3.min(w[1].3), w[0].3.max(w[1].3));
            return Err(IoError::invalid(
                file,
                second,
                format!(
                    "entry ({}, {}) repeated (first on line {first})",
                    w[0].1 + 1,
                    w[0].0 + 1
                ),
            ));
        }
    }
    let n = ent.iter().map(|e| e.0).max().unwrap_or(0) + 1;
    let ndiag = ent.iter().filter(|e| e.0 == e.1).count();
    if ndiag != n {
        // Entries are unique and sorted by column: the k-th diagonal found must be (k, k).
        // (No allocation of size n: n comes from the file and may be huge.)
        let miss = ent
            .iter()
            .filter(|e| e.0 == e.1)
            .enumerate()
            .find(|(k, e)| e.0 != *k)
            .map_or(ndiag, |(k, _)| k);
        return Err(IoError::inconsistent(
            file,
            format!(
                "diagonal entry ({0}, {0}) missing: {ndiag} of {n} diagonal entries present",
                miss + 1
            ),
        ));
    }
    let mut trip = Vec::with_capacity(2 * ent.len());
    for &(c, r, v, _) in &ent {
        trip.push(Triplet::new(r, c, v));
        if r != c {
            trip.push(Triplet::new(c, r, v));
        }
    }
    SparseMatrix::try_new_from_triplets(n, n, &trip)
        .map_err(|e| IoError::inconsistent(file, format!("cannot build sparse matrix: {e:?}")))
}

/// Parses a `.dof` file: line `k` is `node.direction` of equation `k`.
pub fn parse_ccx_dofs(text: &str, file: &Path) -> Result<Vec<(u64, u8)>, IoError> {
    let mut out = Vec::new();
    let mut seen: HashMap<(u64, u8), usize> = HashMap::new();
    for (i, l) in text.lines().enumerate() {
        let ln = i + 1;
        let t = l.trim();
        if t.is_empty() {
            continue;
        }
        let bad = || {
            IoError::parse(
                file,
                ln,
                "node.direction (two integers, direction 1..6)",
                excerpt(t),
            )
        };
        let (a, b) = t.split_once('.').ok_or_else(bad)?;
        let node: u64 = a.parse().map_err(|_| bad())?;
        let dir: u8 = b.parse().map_err(|_| bad())?;
        if !(1..=6).contains(&dir) {
            return Err(bad());
        }
        if let Some(first) = seen.insert((node, dir), ln) {
            return Err(IoError::invalid(
                file,
                ln,
                format!("DOF {node}.{dir} repeated (first on line {first})"),
            ));
        }
        out.push((node, dir));
    }
    if out.is_empty() {
        return Err(IoError::inconsistent(file, "no DOFs (empty file)"));
    }
    Ok(out)
}

/// `job` + `.ext` without touching dots inside the job name.
fn with_ext(job: &Path, ext: &str) -> PathBuf {
    let mut s = job.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Reads `job.sti`, `job.mas`, `job.dof` (`job` is the path without extension).
pub fn read_ccx_matrices(job: &Path) -> Result<CcxMatrices, IoError> {
    let (ps, pm, pd) = (
        with_ext(job, "sti"),
        with_ext(job, "mas"),
        with_ext(job, "dof"),
    );
    let k = parse_ccx_matrix(&read_text(&ps)?, &ps)?;
    let m = parse_ccx_matrix(&read_text(&pm)?, &pm)?;
    let dofs = parse_ccx_dofs(&read_text(&pd)?, &pd)?;
    CcxMatrices::new(k, m, dofs, job)
}

impl CcxMatrices {
    /// Combines parsed parts, checking that K, M and the DOF list have the same dimension.
    /// `job` only serves the error message.
    pub fn new(
        k: SparseMatrix,
        m: SparseMatrix,
        dofs: Vec<(u64, u8)>,
        job: &Path,
    ) -> Result<Self, IoError> {
        if k.nrows() != m.nrows() || k.nrows() != dofs.len() {
            return Err(IoError::inconsistent(
                job,
                format!(
                    "dimensions disagree: .sti has {} equations, .mas {}, .dof {}",
                    k.nrows(),
                    m.nrows(),
                    dofs.len()
                ),
            ));
        }
        Ok(Self { k, m, dofs })
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.dofs.len()
    }

    /// Whether there are no equations (never true for a parsed export).
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// The matrices restricted to the DOFs for which `keep(node, direction)` is true, in their
    /// original order (e.g. `|n, _| !clamped.contains(&n)` clamps a node set). Values are copied,
    /// not recomputed.
    pub fn remove_dofs(&self, keep: impl Fn(u64, u8) -> bool) -> CcxMatrices {
        let mut new_of = vec![usize::MAX; self.dofs.len()];
        let mut dofs = Vec::new();
        for (i, &(n, d)) in self.dofs.iter().enumerate() {
            if keep(n, d) {
                new_of[i] = dofs.len();
                dofs.push((n, d));
            }
        }
        let restrict = |a: &SparseMatrix| -> SparseMatrix {
            let (cp, ri, v) = (a.col_ptr(), a.row_idx(), a.val());
            let mut trip = Vec::new();
            for j in 0..a.ncols() {
                if new_of[j] == usize::MAX {
                    continue;
                }
                for p in cp[j]..cp[j + 1] {
                    if new_of[ri[p]] != usize::MAX {
                        trip.push(Triplet::new(new_of[ri[p]], new_of[j], v[p]));
                    }
                }
            }
            SparseMatrix::try_new_from_triplets(dofs.len(), dofs.len(), &trip)
                .expect("indices of a restricted valid matrix are in range")
        };
        CcxMatrices {
            k: restrict(&self.k),
            m: restrict(&self.m),
            dofs: dofs.clone(),
        }
    }

    /// Rigid-body matrix R (`n x 6`): columns are unit translations x, y, z and unit rotations
    /// about x, y, z through `origin` (`u = theta x (X - origin)`), from the node coordinates of
    /// `mesh` (matched by label). DOFs of nodes absent from the mesh (element-internal nodes of
    /// C3D8I) get zero rows: incompatible modes carry no rigid motion. Rotational directions 4-6
    /// get the rotation columns.
    pub fn rigid_body_matrix(&self, mesh: &Mesh, origin: [f64; 3]) -> Mat<f64> {
        let pos: HashMap<u64, [f64; 3]> = mesh
            .node_ids
            .iter()
            .copied()
            .zip(mesh.nodes.iter().copied())
            .collect();
        let mut r = Mat::<f64>::zeros(self.dofs.len(), 6);
        for (i, &(n, d)) in self.dofs.iter().enumerate() {
            let Some(x) = pos.get(&n) else { continue };
            let d = (d - 1) as usize;
            if d >= 3 {
                r[(i, d)] = 1.0;
                continue;
            }
            r[(i, d)] = 1.0;
            let p = [x[0] - origin[0], x[1] - origin[1], x[2] - origin[2]];
            for a in 0..3 {
                // Component d of e_a x p.
                let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                r[(i, 3 + a)] = if d == b {
                    -p[c]
                } else if d == c {
                    p[b]
                } else {
                    0.0
                };
            }
        }
        r
    }
}

/// Sparse-times-dense product `A B` for a CSC matrix.
pub fn sparse_times_dense(a: &SparseMatrix, b: &Mat<f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(a.nrows(), b.ncols());
    let (cp, ri, v) = (a.col_ptr(), a.row_idx(), a.val());
    for j in 0..a.ncols() {
        for p in cp[j]..cp[j + 1] {
            for m in 0..b.ncols() {
                out[(ri[p], m)] += v[p] * b[(j, m)];
            }
        }
    }
    out
}
