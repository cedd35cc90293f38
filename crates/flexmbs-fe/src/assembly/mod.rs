//! Sparse assembly of the global stiffness and mass matrices.
//!
//! Each node carries 3 (solid) or 6 (beam or rigid-interface node) degrees of freedom, numbered
//! node by node; [`DofMap`] gives the global equation of a node's direction.

mod direct;

pub use direct::assembly_bytes;

use crate::element::MassKind;
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

/// Assembles K and M of all elements of `mesh` (direct stiffness method, scatter-added into the
/// node-adjacency pattern: [`direct`]). `extra_dofs` gives nodes that need 6 DOFs although no
/// element uses them (rigid-interface nodes). `progress(done, total)` is called every few
/// elements.
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
    let (k, m) = direct::assemble_direct(mesh, mass, &dofs, progress)?;
    Ok(Assembled { k, m, dofs })
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
    use crate::element::element_matrices;

    /// The triplet assembly the direct one replaced (every nonzero element entry a triplet,
    /// duplicates summed by faer), as the reference of the direct assembly's pattern and values.
    fn assemble_triplets(mesh: &Mesh, mass: MassKind) -> (SparseMatrix, SparseMatrix) {
        let dofs = DofMap::from_counts(mesh.node_dofs());
        let (mut kt, mut mt) = (Vec::new(), Vec::new());
        for (ei, el) in mesh.elements.iter().enumerate() {
            let em = element_matrices(mesh, ei, mass).unwrap();
            let npn = el.kind.dofs_per_node();
            let eqs: Vec<usize> = el
                .nodes
                .iter()
                .flat_map(|&n| (0..npn).map(move |d| (n, d)))
                .map(|(n, d)| dofs.first[n] + d)
                .collect();
            for (a, &ga) in eqs.iter().enumerate() {
                for (b, &gb) in eqs.iter().enumerate() {
                    if em.k[(a, b)] != 0.0 {
                        kt.push(Triplet::new(ga, gb, em.k[(a, b)]));
                    }
                    if em.m[(a, b)] != 0.0 {
                        mt.push(Triplet::new(ga, gb, em.m[(a, b)]));
                    }
                }
            }
        }
        (
            sparse_from_triplets(dofs.len, &kt).unwrap(),
            sparse_from_triplets(dofs.len, &mt).unwrap(),
        )
    }

    /// Same pattern as the triplet assembly and the same values up to the order of summation
    /// (at most 8 contributions per entry: a few ulp of the largest contribution).
    fn assert_same_as_triplets(mesh: &Mesh, mass: MassKind) {
        let a = assemble(mesh, mass, &[], &mut |_, _| {}).unwrap();
        let (k, m) = assemble_triplets(mesh, mass);
        for (direct, reference) in [(&a.k, &k), (&a.m, &m)] {
            assert_eq!(direct.symbolic().col_ptr(), reference.symbolic().col_ptr());
            assert_eq!(direct.symbolic().row_idx(), reference.symbolic().row_idx());
            let scale = reference.val().iter().fold(0.0f64, |s, v| s.max(v.abs()));
            for (x, y) in direct.val().iter().zip(reference.val()) {
                assert!((x - y).abs() <= 1e-14 * scale, "{x} vs {y}");
            }
        }
    }

    #[test]
    fn direct_assembly_equals_triplet_assembly() {
        use crate::mesh::generate::{beam_line, box_mesh};
        use crate::mesh::{BeamSection, BeamTheory};
        use crate::{ElementKind, Material, UnitSystem};
        let mut meshes = Vec::new();
        for kind in [
            ElementKind::Hex8,
            ElementKind::Hex8I,
            ElementKind::Hex20,
            ElementKind::Hex20R,
        ] {
            meshes.push(
                box_mesh(
                    [0.3, 0.1, 0.05],
                    [4, 2, 3],
                    kind,
                    Material::steel(),
                    UnitSystem::Si,
                )
                .unwrap(),
            );
        }
        let section = BeamSection::rectangle(0.02, 0.01);
        meshes.push(
            beam_line(
                [0.0; 3],
                [1.0, 0.2, 0.0],
                7,
                section,
                BeamTheory::EulerBernoulli,
                [0.0, 0.0, 1.0],
                Material::steel(),
                UnitSystem::Si,
            )
            .unwrap(),
        );
        for mesh in &meshes {
            for mass in [MassKind::Consistent, MassKind::Lumped] {
                assert_same_as_triplets(mesh, mass);
            }
        }
    }

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
