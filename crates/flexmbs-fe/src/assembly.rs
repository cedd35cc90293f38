//! Sparse assembly of the global stiffness and mass matrices.
//!
//! Each node carries 3 (solid) or 6 (beam or rigid-interface node) degrees of freedom, numbered
//! node by node; [`DofMap`] gives the global equation of a node's direction.

use crate::element::{element_matrices, MassKind};
use crate::{FeError, Mesh, NodeIdx, SparseMatrix};
use faer::sparse::Triplet;

/// Global numbering of the degrees of freedom: node `i` owns equations `first[i] .. first[i] + count[i]`,
/// directions ux, uy, uz, rx, ry, rz in that order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DofMap {
    /// First equation of each node.
    pub first: Vec<usize>,
    /// Number of DOFs of each node (0, 3 or 6).
    pub count: Vec<usize>,
    /// Total number of equations.
    pub len: usize,
}

impl DofMap {
    /// Numbers the DOFs of nodes with the given per-node counts.
    pub fn from_counts(count: Vec<usize>) -> Self {
        let mut first = Vec::with_capacity(count.len());
        let mut len = 0;
        for &c in &count {
            first.push(len);
            len += c;
        }
        Self { first, count, len }
    }

    /// Equation of direction `dir` (0..6) of `node`, if the node has it.
    pub fn dof(&self, node: NodeIdx, dir: usize) -> Option<usize> {
        (dir < *self.count.get(node)?).then(|| self.first[node] + dir)
    }

    /// The node and direction of equation `eq` (binary search, O(log n)).
    pub fn node_of(&self, eq: usize) -> Option<(NodeIdx, usize)> {
        if eq >= self.len {
            return None;
        }
        let node = self.first.partition_point(|&f| f <= eq) - 1;
        // skip nodes with zero DOFs that share the same `first`
        let node = (node..self.count.len()).find(|&n| self.count[n] > 0 && self.first[n] <= eq)?;
        Some((node, eq - self.first[node]))
    }
}

/// Assembled global matrices of a mesh (unconstrained).
#[derive(Debug, Clone)]
pub struct Assembled {
    /// Stiffness matrix K (full symmetric storage).
    pub k: SparseMatrix,
    /// Mass matrix M (consistent, or diagonal when lumped).
    pub m: SparseMatrix,
    /// DOF numbering.
    pub dofs: DofMap,
}

/// Assembles K and M of all elements of `mesh` (direct stiffness method). `extra_dofs` gives nodes that
/// need 6 DOFs although no element uses them (rigid-interface nodes). `progress(done, total)` is
/// called every few elements.
pub fn assemble(
    mesh: &Mesh,
    mass: MassKind,
    extra_dofs: &[NodeIdx],
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Assembled, FeError> {
    mesh.validate()?;
    let mut counts = mesh.node_dofs();
    for &n in extra_dofs {
        counts[n] = 6;
    }
    let dofs = DofMap::from_counts(counts);
    let est: usize = mesh
        .elements
        .iter()
        .map(|e| (e.nodes.len() * e.kind.dofs_per_node()).pow(2))
        .sum();
    let m_est = if mass == MassKind::Lumped {
        dofs.len
    } else {
        est
    };
    crate::memory::check_allocation(
        &format!(
            "the stiffness and mass triplets of {} elements",
            mesh.elements.len()
        ),
        triplet_bytes(est.saturating_add(m_est)),
    )?;
    let mut kt = Vec::with_capacity(est);
    let mut mt = Vec::with_capacity(m_est);
    let mut eqs = Vec::with_capacity(120);
    let ne = mesh.elements.len();
    for (ei, el) in mesh.elements.iter().enumerate() {
        let em = element_matrices(mesh, ei, mass)?;
        let npn = el.kind.dofs_per_node();
        eqs.clear();
        for &n in &el.nodes {
            eqs.extend((0..npn).map(|d| dofs.first[n] + d));
        }
        for (a, &ga) in eqs.iter().enumerate() {
            for (b, &gb) in eqs.iter().enumerate() {
                let kv = em.k[(a, b)];
                if kv != 0.0 {
                    kt.push(Triplet::new(ga, gb, kv));
                }
                let mv = em.m[(a, b)];
                if mv != 0.0 {
                    mt.push(Triplet::new(ga, gb, mv));
                }
            }
        }
        if ei % 256 == 0 || ei + 1 == ne {
            progress(ei + 1, ne);
        }
    }
    let k = sparse_from_triplets(dofs.len, &kt)?;
    let m = sparse_from_triplets(dofs.len, &mt)?;
    Ok(Assembled { k, m, dofs })
}

/// Bytes of `count` assembly triplets (row, column, value).
pub fn triplet_bytes(count: usize) -> u64 {
    (count as u64).saturating_mul(std::mem::size_of::<Triplet<usize, usize, f64>>() as u64)
}

/// Builds an n x n sparse matrix from triplets, summing duplicates.
pub fn sparse_from_triplets(
    n: usize,
    t: &[Triplet<usize, usize, f64>],
) -> Result<SparseMatrix, FeError> {
    SparseMatrix::try_new_from_triplets(n, n, t)
        .map_err(|e| FeError::Invalid(format!("sparse matrix assembly failed: {e:?}")))
}

/// Iterates over the stored entries `(row, col, value)` of a sparse matrix.
pub fn entries(a: &SparseMatrix) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let v = a.val();
    (0..a.ncols()).flat_map(move |j| (cp[j]..cp[j + 1]).map(move |p| (ri[p], j, v[p])))
}

/// The diagonal of a sparse matrix.
pub fn diagonal(a: &SparseMatrix) -> Vec<f64> {
    let mut d = vec![0.0; a.nrows().min(a.ncols())];
    for (i, j, v) in entries(a) {
        if i == j {
            d[i] += v;
        }
    }
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dof_map_round_trip() {
        let m = DofMap::from_counts(vec![3, 0, 6, 3]);
        assert_eq!(m.len, 12);
        assert_eq!(m.dof(2, 5), Some(8));
        assert_eq!(m.dof(1, 0), None);
        assert_eq!(m.dof(0, 3), None);
        for eq in 0..m.len {
            let (n, d) = m.node_of(eq).unwrap();
            assert_eq!(m.dof(n, d), Some(eq));
        }
        assert_eq!(m.node_of(12), None);
    }
}
