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

    /// The entries `0..at` and `at..` as two parts that can be filled on two threads.
    fn split_at(&mut self, at: usize) -> (FillingPart<'_>, FillingPart<'_>) {
        let (v1, v2) = self.values.split_at_mut(at);
        let (h1, h2) = self.hit.split_at_mut(at);
        (
            FillingPart {
                values: v1,
                hit: h1,
                offset: 0,
            },
            FillingPart {
                values: v2,
                hit: h2,
                offset: at,
            },
        )
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

/// The entries `offset..offset + values.len()` of a [`Filling`].
struct FillingPart<'a> {
    values: &'a mut [f64],
    hit: &'a mut [bool],
    offset: usize,
}

impl FillingPart<'_> {
    fn add(&mut self, p: usize, v: f64) {
        if v != 0.0 {
            self.values[p - self.offset] += v;
            self.hit[p - self.offset] = true;
        }
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
    // the columns of the nodes from `split` on (about half the entries) are filled on a second
    // thread; every entry still receives its contributions in element order
    let split = (0..mesh.nodes.len())
        .find(|&node| pattern.col_ptr[dofs.first[node]] >= nnz / 2)
        .map_or(dofs.len, |node| dofs.first[node]);
    let at = pattern.col_ptr[split];
    for c0 in (0..ne).step_by(CHUNK) {
        let c1 = (c0 + CHUNK).min(ne);
        let ems = element_matrices_parallel(mesh, c0..c1, mass, workers)?;
        let ((k1, k2), (m1, m2)) = (k.split_at(at), m.split_at(at));
        let elements = &mesh.elements[c0..c1];
        let pattern = &pattern;
        std::thread::scope(|s| {
            let h = s.spawn(|| scatter_columns(pattern, dofs, elements, &ems, split.., (k2, m2)));
            let r = scatter_columns(pattern, dofs, elements, &ems, ..split, (k1, m1));
            h.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
                .and(r)
        })?;
        progress(c1, ne);
    }
    // K and M compacted on two threads
    let (k, m) = std::thread::scope(|s| {
        let h = s.spawn(|| m.finish(&pattern));
        let k = k.finish(&pattern);
        (k, h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
    });
    let (k, m) = (k?, m?);
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

/// Adds the element matrices `ems` of `elements` (in order) into the columns `cols` of `K` and
/// `M` (parts holding those columns' entries). Every DOF column of a node has the node's
/// neighbour rows (each neighbour's DOFs contiguous), so one search per node pair locates the
/// whole `npn x npn` block.
fn scatter_columns(
    pattern: &Pattern,
    dofs: &DofMap,
    elements: &[crate::mesh::Element],
    ems: &[ElementMatrices],
    cols: impl std::ops::RangeBounds<usize>,
    (mut k, mut m): (FillingPart<'_>, FillingPart<'_>),
) -> Result<(), FeError> {
    for (el, em) in elements.iter().zip(ems) {
        let npn = el.kind.dofs_per_node();
        for (jb, &nb) in el.nodes.iter().enumerate() {
            let cb = dofs.first[nb];
            if !cols.contains(&cb) {
                continue;
            }
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
    }
    Ok(())
}

fn pattern_error(row: usize, col: usize) -> FeError {
    FeError::Invalid(format!(
        "sparse assembly: entry ({row}, {col}) outside the node-adjacency pattern"
    ))
}
