//! Mechanisms of an FE model: motions without strain energy that are not the rigid-body motions
//! a body is allowed to have. Two checks:
//! - [`mesh_parts`]: the connected parts of a mesh (elements joined through shared nodes, the
//!   nodes of a rigid interface joined, all fixed nodes joined through the ground). A flexible
//!   body of several parts has the rigid-body modes of each part.
//! - [`count_zero_energy`]: eigenvalues at round-off level relative to the scale of the spectrum
//!   ([`spectrum_scale`]). A body has 6 of them (free-free) or none (supported); more are hourglass modes
//!   of reduced-integration elements, disconnected parts or supports that do not stop every
//!   rigid-body motion.

use crate::constraint::BoundaryConditions;
use crate::{Mesh, NodeIdx, SparseMatrix};

/// Eigenvalues `omega^2` below this fraction of [`spectrum_scale`] count as zero energy.
/// Measured (`tests/mechanism.rs`): round-off puts zero eigenvalues at 5e-17 of the scale for the
/// hourglass modes of a 10 x 1 x 1 hex20r cantilever (dense and Lanczos), 4e-17 for the rigid
/// modes of two hex8 boxes and 2.3e-14 for those of a slender beam mesh (1 m steel wire of 1 mm
/// in 200 elements), whose first clamped bending mode lies at 9.7e-12 (the lowest elastic modes
/// of the solid cantilevers: 3e-9 and above). A finer or more slender beam mesh than that wire
/// is past what the eigen solvers resolve (in 1000 elements Lanczos does not converge).
pub const ZERO_ENERGY_TOLERANCE: f64 = 1e-12;

/// Scale of the spectrum of `K phi = omega^2 M phi`: the largest `|K_ii| / M_ii` over the DOFs
/// with mass (the Rayleigh quotient of the stiffest unit vector, of the order of the largest
/// eigenvalue, which sets the round-off of the small ones); 1 if there is none.
pub fn spectrum_scale(k: &SparseMatrix, m: &SparseMatrix) -> f64 {
    let s = diagonal(k)
        .zip(diagonal(m))
        .filter(|(_, mi)| *mi > 0.0)
        .map(|(ki, mi)| ki.abs() / mi)
        .fold(0.0, f64::max);
    if s > 0.0 {
        s
    } else {
        1.0
    }
}

/// The diagonal entries of a sparse matrix (duplicates summed).
fn diagonal(a: &SparseMatrix) -> impl Iterator<Item = f64> + '_ {
    (0..a.ncols()).map(move |j| {
        a.row_idx_of_col_raw(j)
            .iter()
            .zip(a.val_of_col(j))
            .filter(|(&i, _)| i == j)
            .map(|(_, v)| *v)
            .sum::<f64>()
    })
}

/// Number of eigenvalues `omega2` below [`ZERO_ENERGY_TOLERANCE`] times `scale`.
pub fn count_zero_energy(omega2: &[f64], scale: f64) -> usize {
    omega2
        .iter()
        .filter(|&&w| w < ZERO_ENERGY_TOLERANCE * scale)
        .count()
}

/// Union-find with path halving.
struct Parts {
    parent: Vec<usize>,
}

impl Parts {
    fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }
    fn root(&mut self, mut a: usize) -> usize {
        while self.parent[a] != a {
            self.parent[a] = self.parent[self.parent[a]];
            a = self.parent[a];
        }
        a
    }
    fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb);
        }
    }
    /// Joins all `nodes` into one part.
    fn join_all(&mut self, nodes: &[NodeIdx]) {
        if let Some((&first, rest)) = nodes.split_first() {
            for &n in rest {
                self.join(first, n);
            }
        }
    }
}

/// The connected parts of the structure: node lists (ascending, each part ordered by its lowest
/// node) of the components of the graph whose edges are the elements (all nodes of an element
/// joined), the rigid interfaces of `bc` (their nodes joined) and the fixed nodes of `bc` (all
/// joined: they move with the ground, or the floating frame of a supported body). Nodes used by
/// no element, interface or support belong to no part. Node indices out of range are ignored
/// (they are reported by the assembly).
pub fn mesh_parts(mesh: &Mesh, bc: &BoundaryConditions) -> Vec<Vec<NodeIdx>> {
    let n = mesh.num_nodes();
    let mut parts = Parts::new(n);
    let mut used = vec![false; n];
    let in_range =
        |nodes: &[NodeIdx]| -> Vec<NodeIdx> { nodes.iter().copied().filter(|&i| i < n).collect() };
    let groups = mesh
        .elements
        .iter()
        .map(|e| in_range(&e.nodes))
        .chain(bc.rigid.iter().map(|r| in_range(&r.nodes)))
        .chain(std::iter::once(in_range(&bc.fixed)));
    for g in groups {
        for &i in &g {
            used[i] = true;
        }
        parts.join_all(&g);
    }
    let mut by_root: std::collections::BTreeMap<usize, Vec<NodeIdx>> = Default::default();
    for i in (0..n).filter(|&i| used[i]) {
        by_root.entry(parts.root(i)).or_default().push(i);
    }
    by_root.into_values().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::box_mesh;
    use crate::{ElementKind, Material};

    fn steel() -> Material {
        Material {
            e: 210e9,
            nu: 0.3,
            rho: 7850.0,
        }
    }

    /// Two boxes side by side (shared face) are one part; moved apart they are two, with the
    /// node counts of each box; fixing a node of each box joins them through the ground; a rigid
    /// interface over one node of each box joins them too.
    #[test]
    fn parts_follow_elements_interfaces_and_supports() {
        let a = box_mesh(
            [0.1, 0.02, 0.02],
            [2, 1, 1],
            ElementKind::Hex8,
            steel(),
            crate::UnitSystem::Si,
        )
        .unwrap();
        let na = a.num_nodes();
        assert_eq!(na, 12);
        let mut two = a.clone();
        let offset = two.num_nodes();
        for x in &a.nodes {
            two.add_node([x[0] + 1.0, x[1], x[2]]);
        }
        for e in &a.elements {
            let mut e = e.clone();
            e.nodes.iter_mut().for_each(|i| *i += offset);
            two.elements.push(e);
        }
        let none = BoundaryConditions::default();
        assert_eq!(mesh_parts(&a, &none).len(), 1);
        let p = mesh_parts(&two, &none);
        assert_eq!(p.len(), 2);
        assert_eq!(p[0], (0..na).collect::<Vec<_>>());
        assert_eq!(p[1], (na..2 * na).collect::<Vec<_>>());
        let fixed = BoundaryConditions {
            fixed: vec![0, na],
            rigid: vec![],
        };
        assert_eq!(mesh_parts(&two, &fixed).len(), 1);
        let rigid = BoundaryConditions {
            fixed: vec![],
            rigid: vec![crate::constraint::RigidInterface {
                name: "tie".into(),
                nodes: vec![3, na + 3],
                point: None,
            }],
        };
        assert_eq!(mesh_parts(&two, &rigid).len(), 1);
    }

    #[test]
    fn zero_energy_count_is_relative_to_the_scale() {
        let w = [-1e-6, 1e-5, 2e-4, 1.0, 50.0];
        assert_eq!(count_zero_energy(&w, 1e10), 3);
        assert_eq!(count_zero_energy(&w, 1e8), 2);
    }
}
