//! Direct sparse assembly: the sparsity pattern from the element connectivity, then every
//! element matrix scatter-added into the compressed-column values (as FE codes assemble), so no
//! triplet list of all element entries is ever held: for a 60 000-DOF hex20 mesh the triplets
//! of K and M took 456 MB, the matrices themselves 190 MB.

use crate::assembly::DofMap;
use crate::element::{element_matrices, ElementMatrices, MassKind};
use crate::{FeError, Mesh, SparseMatrix};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};

/// A column-compressed pattern (sorted rows per column).
struct Pattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

/// Values being accumulated on a [`Pattern`]; `hit` marks the entries that received a nonzero
/// contribution, the only ones kept (the pattern of the sum of the element matrices' nonzero
/// entries).
struct Filling {
    values: Vec<f64>,
    hit: Vec<bool>,
}

impl Filling {
    fn new(nnz: usize) -> Result<Self, FeError> {
        let mut values = Vec::new();
        values.try_reserve_exact(nnz).map_err(|_| oom())?;
        values.resize(nnz, 0.0);
        Ok(Self {
            values,
            hit: vec![false; nnz],
        })
    }

    fn add(&mut self, p: usize, v: f64) {
        if v != 0.0 {
            self.values[p] += v;
            self.hit[p] = true;
        }
    }

    /// The matrix of the entries that received a nonzero contribution (pattern compacted).
    fn finish(self, pattern: &Pattern) -> Result<SparseMatrix, FeError> {
        let Self { mut values, hit } = self;
        let n = pattern.col_ptr.len() - 1;
        let kept = hit.iter().filter(|&&h| h).count();
        let mut rows = Vec::new();
        rows.try_reserve_exact(kept).map_err(|_| oom())?;
        let mut ptr = Vec::with_capacity(n + 1);
        ptr.push(0);
        let mut w = 0;
        for j in 0..n {
            for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                if hit[p] {
                    rows.push(pattern.row_idx[p]);
                    values[w] = values[p];
                    w += 1;
                }
            }
            ptr.push(w);
        }
        drop(hit);
        values.truncate(w);
        values.shrink_to_fit();
        let symbolic = SymbolicSparseColMat::new_checked(n, n, ptr, None, rows);
        Ok(SparseColMat::new(symbolic, values))
    }
}

fn oom() -> FeError {
    FeError::Invalid("out of memory in sparse assembly".into())
}

/// Column pointers of the node-adjacency pattern (every DOF of a node coupled with every DOF of
/// the nodes it shares an element with); `node_elements` lists each node's elements (CSR).
fn pattern_col_ptr(
    mesh: &Mesh,
    dofs: &DofMap,
    node_elements: &(Vec<usize>, Vec<usize>),
    mut visit: impl FnMut(usize, &[usize]),
) -> Vec<usize> {
    let n_nodes = mesh.nodes.len();
    let (ptr, list) = node_elements;
    let mut mark = vec![usize::MAX; n_nodes];
    let mut neighbours = Vec::new();
    let mut col_ptr = Vec::with_capacity(dofs.len + 1);
    col_ptr.push(0usize);
    for node in 0..n_nodes {
        neighbours.clear();
        for &e in &list[ptr[node]..ptr[node + 1]] {
            for &m in &mesh.elements[e].nodes {
                if mark[m] != node {
                    mark[m] = node;
                    neighbours.push(m);
                }
            }
        }
        neighbours.sort_unstable();
        let per_col: usize = neighbours.iter().map(|&m| dofs.count[m]).sum();
        for _ in 0..dofs.count[node] {
            col_ptr.push(col_ptr.last().copied().unwrap_or(0) + per_col);
        }
        visit(node, &neighbours);
    }
    col_ptr
}

/// Each node's elements, in compressed form `(ptr, list)`.
fn node_elements(mesh: &Mesh) -> (Vec<usize>, Vec<usize>) {
    let n = mesh.nodes.len();
    let mut ptr = vec![0usize; n + 1];
    for e in &mesh.elements {
        for &m in &e.nodes {
            ptr[m + 1] += 1;
        }
    }
    for i in 0..n {
        ptr[i + 1] += ptr[i];
    }
    let mut fill = ptr.clone();
    let mut list = vec![0usize; ptr[n]];
    for (ei, e) in mesh.elements.iter().enumerate() {
        for &m in &e.nodes {
            list[fill[m]] = ei;
            fill[m] += 1;
        }
    }
    (ptr, list)
}

/// Bytes the direct assembly of a pattern with `nnz` entries holds at its peak: the rows, the
/// values of K and M, the hit marks, and the compacted rows of K and M.
pub fn assembly_bytes(nnz: usize) -> u64 {
    (nnz as u64).saturating_mul(8 + 8 + 8 + 2 + 8 + 8)
}

/// Assembles K and M of all elements of `mesh` into the node-adjacency pattern, keeping the
/// entries with a nonzero element contribution (the pattern a triplet assembly gives). Values
/// are summed in element order (element matrices computed in parallel, [`CHUNK`] at a time).
pub(crate) fn assemble_direct(
    mesh: &Mesh,
    mass: MassKind,
    dofs: &DofMap,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(SparseMatrix, SparseMatrix), FeError> {
    let adjacency = node_elements(mesh);
    let col_ptr = pattern_col_ptr(mesh, dofs, &adjacency, |_, _| {});
    let nnz = col_ptr.last().copied().unwrap_or(0);
    crate::memory::check_allocation(
        &format!(
            "the assembly of K and M of {} elements ({nnz} matrix entries)",
            mesh.elements.len()
        ),
        assembly_bytes(nnz),
    )?;
    let mut row_idx = Vec::new();
    row_idx.try_reserve_exact(nnz).map_err(|_| oom())?;
    pattern_col_ptr(mesh, dofs, &adjacency, |node, neighbours| {
        for _ in 0..dofs.count[node] {
            for &m in neighbours {
                row_idx.extend(dofs.first[m]..dofs.first[m] + dofs.count[m]);
            }
        }
    });
    drop(adjacency);
    let pattern = Pattern { col_ptr, row_idx };
    let mut k = Filling::new(nnz)?;
    let mut m = Filling::new(nnz)?;
    let ne = mesh.elements.len();
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get().min(MAX_WORKERS));
    for c0 in (0..ne).step_by(CHUNK) {
        let c1 = (c0 + CHUNK).min(ne);
        let ems = element_matrices_parallel(mesh, c0..c1, mass, workers)?;
        for (ei, em) in (c0..c1).zip(&ems) {
            scatter_element(&pattern, dofs, &mesh.elements[ei], em, (&mut k, &mut m))?;
        }
        progress(c1, ne);
    }
    let k = k.finish(&pattern)?;
    let m = m.finish(&pattern)?;
    Ok((k, m))
}

/// Elements whose matrices are computed (in parallel) before they are added, in element order.
const CHUNK: usize = 128;
/// At most this many threads compute element matrices.
const MAX_WORKERS: usize = 8;

/// The matrices of the elements `range`, computed by up to `workers` threads on contiguous parts
/// (each element's matrices depend on that element only: the result does not depend on the
/// number of threads).
fn element_matrices_parallel(
    mesh: &Mesh,
    range: std::ops::Range<usize>,
    mass: MassKind,
    workers: usize,
) -> Result<Vec<ElementMatrices>, FeError> {
    let ids: Vec<usize> = range.collect();
    let one_part = |part: &[usize]| -> Result<Vec<ElementMatrices>, FeError> {
        part.iter()
            .map(|&e| element_matrices(mesh, e, mass))
            .collect()
    };
    if workers <= 1 || ids.len() < 2 * workers {
        return one_part(&ids);
    }
    let per = ids.len().div_ceil(workers);
    std::thread::scope(|s| {
        let handles: Vec<_> = ids
            .chunks(per)
            .map(|part| s.spawn(move || one_part(part)))
            .collect();
        let mut out = Vec::with_capacity(ids.len());
        for h in handles {
            let part = h
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            out.extend(part?);
        }
        Ok(out)
    })
}

/// Adds one element's matrices into `K` and `M`. Every DOF column of a node has the node's
/// neighbour rows (each neighbour's DOFs contiguous), so one search per node pair locates the
/// whole `npn x npn` block.
fn scatter_element(
    pattern: &Pattern,
    dofs: &DofMap,
    el: &crate::mesh::Element,
    em: &ElementMatrices,
    (k, m): (&mut Filling, &mut Filling),
) -> Result<(), FeError> {
    let npn = el.kind.dofs_per_node();
    for (jb, &nb) in el.nodes.iter().enumerate() {
        let cb = dofs.first[nb];
        let start = pattern.col_ptr[cb];
        let rows = &pattern.row_idx[start..pattern.col_ptr[cb + 1]];
        for (ja, &na) in el.nodes.iter().enumerate() {
            let ra = dofs.first[na];
            let off = rows.binary_search(&ra).map_err(|_| pattern_error(ra, cb))?;
            for db in 0..npn {
                let base = pattern.col_ptr[cb + db] + off;
                for da in 0..npn {
                    let (a, b) = (ja * npn + da, jb * npn + db);
                    k.add(base + da, em.k[(a, b)]);
                    m.add(base + da, em.m[(a, b)]);
                }
            }
        }
    }
    Ok(())
}

fn pattern_error(row: usize, col: usize) -> FeError {
    FeError::Invalid(format!(
        "sparse assembly: entry ({row}, {col}) outside the node-adjacency pattern"
    ))
}
