//! Boundary conditions of an FE model: fixed node sets and rigid interfaces (RBE2-like),
//! applied by a sparse transformation `u = T v` from independent DOFs `v` to all DOFs `u`.
//!
//! A rigid interface ties every DOF of a node set to one 6-DOF interface node at point `x_m`:
//! `u_s = u_m + theta_m x (x_s - x_m)` and, for slave nodes with rotations, `theta_s = theta_m`.
//! Constrained matrices are `T^T K T` and `T^T M T`.

use crate::assembly::{entries, sparse_from_triplets, DofMap};
use crate::{FeError, Mesh, NodeIdx, SparseMatrix};
use faer::sparse::Triplet;
use faer::Mat;

/// A rigid interface: `nodes` move rigidly with a new 6-DOF node at `point`
/// (the centroid of the set when `None`).
#[derive(Debug, Clone, PartialEq)]
pub struct RigidInterface {
    /// Name (used for the interface node set).
    pub name: String,
    /// Slave nodes.
    pub nodes: Vec<NodeIdx>,
    /// Location of the interface node; centroid of `nodes` if `None`.
    pub point: Option<[f64; 3]>,
}

/// Boundary conditions: fixed nodes (all their DOFs zero) and rigid interfaces.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BoundaryConditions {
    /// Nodes whose DOFs are all fixed.
    pub fixed: Vec<NodeIdx>,
    /// Rigid interfaces.
    pub rigid: Vec<RigidInterface>,
}

/// A DOF of the independent set: which node and direction it moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IndependentDof {
    /// Node.
    pub node: NodeIdx,
    /// Direction 0..6 (ux, uy, uz, rx, ry, rz).
    pub dir: usize,
}

/// The transformation from independent to all DOFs, and bookkeeping to expand vectors into nodal fields.
#[derive(Debug, Clone)]
pub struct ConstraintMap {
    /// Node positions including the added interface nodes (appended after the mesh nodes).
    pub nodes: Vec<[f64; 3]>,
    /// Global DOF numbering of all nodes (mesh nodes and interface nodes).
    pub dofs: DofMap,
    /// For every global DOF the list of (independent DOF, coefficient); empty for fixed DOFs.
    pub rows: Vec<Vec<(usize, f64)>>,
    /// The independent DOFs.
    pub independent: Vec<IndependentDof>,
    /// Index of the interface node of each rigid interface.
    pub interface_nodes: Vec<NodeIdx>,
    /// Nodes with all DOFs fixed.
    pub fixed_nodes: Vec<NodeIdx>,
    /// Number of DOFs of the mesh nodes (the assembled matrices' dimension); interface DOFs follow.
    pub mesh_dofs: usize,
}

impl ConstraintMap {
    /// Builds the map for `mesh` with boundary conditions `bc`. Mesh nodes get the DOF counts of
    /// [`Mesh::node_dofs`]; interface nodes are appended with 6.
    pub fn new(mesh: &Mesh, bc: &BoundaryConditions) -> Result<Self, FeError> {
        let n_mesh = mesh.num_nodes();
        let mut nodes = mesh.nodes.clone();
        let mut counts = mesh.node_dofs();
        let mut master_of: Vec<Option<usize>> = vec![None; n_mesh];
        let mut interface_nodes = Vec::new();
        for (r, ri) in bc.rigid.iter().enumerate() {
            if ri.nodes.is_empty() {
                return Err(FeError::Invalid(format!(
                    "rigid interface '{}' has no nodes",
                    ri.name
                )));
            }
            let p = ri.point.unwrap_or_else(|| centroid(&mesh.nodes, &ri.nodes));
            for &s in &ri.nodes {
                if s >= n_mesh {
                    return Err(FeError::Invalid(format!(
                        "rigid interface '{}': node index {s} out of range",
                        ri.name
                    )));
                }
                if let Some(other) = master_of[s] {
                    return Err(FeError::Invalid(format!(
                        "node {} belongs to two rigid interfaces ('{}' and '{}')",
                        mesh.node_ids[s], bc.rigid[other].name, ri.name
                    )));
                }
                master_of[s] = Some(r);
            }
            nodes.push(p);
            counts.push(6);
            interface_nodes.push(nodes.len() - 1);
        }
        let mut fixed = vec![false; nodes.len()];
        for &f in &bc.fixed {
            if f >= n_mesh {
                return Err(FeError::Invalid(format!(
                    "fixed node index {f} out of range"
                )));
            }
            fixed[f] = true;
        }
        let mesh_dofs: usize = counts[..n_mesh].iter().sum();
        let dofs = DofMap::from_counts(counts);
        // independent DOFs: free DOFs of unconstrained mesh nodes and all DOFs of interface nodes
        // whose slaves are not fixed (a fixed slave fixes its interface node).
        let mut iface_fixed = vec![false; interface_nodes.len()];
        for (s, m) in master_of.iter().enumerate() {
            if let (Some(r), true) = (m, fixed[s]) {
                iface_fixed[*r] = true;
            }
        }
        let mut independent = Vec::new();
        let mut index_of = vec![usize::MAX; dofs.len];
        for node in 0..nodes.len() {
            let is_slave = node < n_mesh && master_of[node].is_some();
            let is_fixed = if node < n_mesh {
                fixed[node]
            } else {
                iface_fixed[node - n_mesh]
            };
            if is_slave || is_fixed {
                continue;
            }
            for dir in 0..dofs.count[node] {
                index_of[dofs.first[node] + dir] = independent.len();
                independent.push(IndependentDof { node, dir });
            }
        }
        let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); dofs.len];
        for node in 0..nodes.len() {
            for dir in 0..dofs.count[node] {
                let eq = dofs.first[node] + dir;
                if index_of[eq] != usize::MAX {
                    rows[eq].push((index_of[eq], 1.0));
                    continue;
                }
                let Some(r) = (node < n_mesh).then(|| master_of[node]).flatten() else {
                    continue;
                };
                let m = interface_nodes[r];
                if iface_fixed[r] {
                    continue;
                }
                let mi = |d: usize| index_of[dofs.first[m] + d];
                if dir < 3 {
                    // u_s = u_m + theta x d, d = x_s - x_m; (theta x d)_dir
                    let d = sub(nodes[node], nodes[m]);
                    rows[eq].push((mi(dir), 1.0));
                    let (a, b) = ((dir + 1) % 3, (dir + 2) % 3);
                    // (theta x d)_dir = theta_a d_b - theta_b d_a
                    if d[b] != 0.0 {
                        rows[eq].push((mi(3 + a), d[b]));
                    }
                    if d[a] != 0.0 {
                        rows[eq].push((mi(3 + b), -d[a]));
                    }
                } else {
                    rows[eq].push((mi(dir), 1.0));
                }
            }
        }
        let fixed_nodes = (0..n_mesh).filter(|&n| fixed[n]).collect();
        Ok(Self {
            nodes,
            dofs,
            rows,
            independent,
            interface_nodes,
            fixed_nodes,
            mesh_dofs,
        })
    }

    /// Number of independent DOFs.
    pub fn num_independent(&self) -> usize {
        self.independent.len()
    }

    /// `T^T A T` for a matrix `A` over all DOFs.
    pub fn project(&self, a: &SparseMatrix) -> Result<SparseMatrix, FeError> {
        if a.nrows() != self.mesh_dofs || a.ncols() != self.mesh_dofs {
            return Err(FeError::Invalid(format!(
                "matrix is {} x {} but the mesh has {} DOFs",
                a.nrows(),
                a.ncols(),
                self.mesh_dofs
            )));
        }
        if let Some(index) = self.selection() {
            return Ok(select_submatrix(a, &index, self.num_independent()));
        }
        self.project_triplets(a)
    }

    /// `T^T A T` through triplets (any `T`).
    fn project_triplets(&self, a: &SparseMatrix) -> Result<SparseMatrix, FeError> {
        let mut t = Vec::with_capacity(a.compute_nnz());
        for (i, j, v) in entries(a) {
            for &(p, tp) in &self.rows[i] {
                for &(q, tq) in &self.rows[j] {
                    t.push(Triplet::new(p, q, tp * tq * v));
                }
            }
        }
        sparse_from_triplets(self.num_independent(), &t)
    }

    /// If `T` only selects DOFs (every DOF fixed or mapped with coefficient 1 to its own
    /// independent DOF, in increasing order: supports without rigid interfaces), each DOF's
    /// independent index (`usize::MAX` when fixed).
    fn selection(&self) -> Option<Vec<usize>> {
        let mut index = Vec::with_capacity(self.rows.len());
        let mut next = 0;
        for row in &self.rows {
            match row.as_slice() {
                [] => index.push(usize::MAX),
                [(p, c)] if *c == 1.0 && *p == next => {
                    index.push(next);
                    next += 1;
                }
                _ => return None,
            }
        }
        Some(index)
    }

    /// Expands independent-DOF vectors (columns of `v`) to nodal fields: translations (3 N x k) and
    /// rotations (3 N x k, zero for nodes without rotations). N counts mesh and interface nodes.
    pub fn expand(&self, v: faer::MatRef<'_, f64>) -> (Mat<f64>, Mat<f64>) {
        let n = self.nodes.len();
        let k = v.ncols();
        let mut t = Mat::<f64>::zeros(3 * n, k);
        let mut r = Mat::<f64>::zeros(3 * n, k);
        for node in 0..n {
            for dir in 0..self.dofs.count[node] {
                let eq = self.dofs.first[node] + dir;
                for c in 0..k {
                    let val: f64 = self.rows[eq].iter().map(|&(p, tp)| tp * v[(p, c)]).sum();
                    if dir < 3 {
                        t[(3 * node + dir, c)] = val;
                    } else {
                        r[(3 * node + dir - 3, c)] = val;
                    }
                }
            }
        }
        (t, r)
    }

    /// The load vector over the independent DOFs (`T^T f`) of the force `force` distributed on
    /// the translations of the nodes by the weights (node, weight), e.g. the shape-function
    /// values of a point ([`crate::point_load::point_weights`]).
    pub fn weighted_nodal_load(&self, weights: &[(NodeIdx, f64)], force: [f64; 3]) -> Vec<f64> {
        let mut f = vec![0.0; self.num_independent()];
        for &(node, w) in weights {
            if node >= self.dofs.count.len() {
                continue;
            }
            for (dir, fd) in force.iter().enumerate().take(self.dofs.count[node].min(3)) {
                let eq = self.dofs.first[node] + dir;
                for &(p, c) in &self.rows[eq] {
                    f[p] += c * w * fd;
                }
            }
        }
        f
    }

    /// Independent DOF indices of a node (empty if fixed or slave).
    pub fn independent_of_node(&self, node: NodeIdx) -> Vec<usize> {
        let mut out = Vec::new();
        if node < self.dofs.count.len() {
            for dir in 0..self.dofs.count[node] {
                let eq = self.dofs.first[node] + dir;
                if let [(p, c)] = self.rows[eq][..] {
                    if c == 1.0 && self.independent[p].node == node {
                        out.push(p);
                    }
                }
            }
        }
        out
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Arithmetic mean of node positions.
pub fn centroid(nodes: &[[f64; 3]], set: &[NodeIdx]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &n in set {
        for d in 0..3 {
            c[d] += nodes[n][d];
        }
    }
    let k = set.len().max(1) as f64;
    [c[0] / k, c[1] / k, c[2] / k]
}

/// `T^T A T` for a selecting `T` ([`ConstraintMap::selection`]): the submatrix of the kept rows
/// and columns, built directly (same pattern, explicit zeros included, and values as the
/// triplet product `1 * 1 * v`).
fn select_submatrix(a: &SparseMatrix, index: &[usize], n: usize) -> SparseMatrix {
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let val = a.val();
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let (mut rows, mut values) = (Vec::new(), Vec::new());
    for (j, &q) in index.iter().enumerate().take(a.ncols()) {
        if q == usize::MAX {
            continue;
        }
        for p in cp[j]..cp[j + 1] {
            let i = index[ri[p]];
            if i != usize::MAX {
                rows.push(i);
                values.push(val[p]);
            }
        }
        col_ptr.push(rows.len());
    }
    // independent DOFs without mesh columns (interface nodes) have empty columns
    col_ptr.resize(n + 1, rows.len());
    let symbolic = faer::sparse::SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows);
    faer::sparse::SparseColMat::new(symbolic, values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::assemble;
    use crate::element::MassKind;
    use crate::mesh::generate::box_mesh;
    use crate::{ElementKind, Material, UnitSystem};

    #[test]
    fn selection_projection_equals_triplet_projection() {
        let mesh = box_mesh(
            [0.4, 0.1, 0.1],
            [4, 2, 2],
            ElementKind::Hex20,
            Material::steel(),
            UnitSystem::Si,
        )
        .unwrap();
        let a = assemble(&mesh, MassKind::Consistent, &[], &mut |_, _| {}).unwrap();
        let fixed: Vec<usize> = (0..mesh.num_nodes())
            .filter(|&n| mesh.nodes[n][0] < 1e-9)
            .collect();
        let bc = BoundaryConditions {
            fixed,
            rigid: Vec::new(),
        };
        let map = ConstraintMap::new(&mesh, &bc).unwrap();
        assert!(map.selection().is_some());
        for m in [&a.k, &a.m] {
            let fast = map.project(m).unwrap();
            let reference = map.project_triplets(m).unwrap();
            assert_eq!(fast.symbolic().col_ptr(), reference.symbolic().col_ptr());
            assert_eq!(fast.symbolic().row_idx(), reference.symbolic().row_idx());
            assert_eq!(fast.val(), reference.val());
        }
    }
}
