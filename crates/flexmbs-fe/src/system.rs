//! A constrained FE system: the matrices over the independent DOFs of a mesh with its boundary
//! conditions, ready for modal analysis and reduction.

use crate::assembly::{assemble, entries, Assembled, DofMap};
use crate::constraint::{BoundaryConditions, ConstraintMap};
use crate::element::MassKind;
use crate::{FeError, Mesh, SparseMatrix};
use faer::Mat;

/// The constrained system `T^T K T v = ...` of a mesh.
#[derive(Debug, Clone)]
pub struct FeSystem {
    /// Constraint map (independent DOFs, interface nodes, expansion to nodal fields).
    pub map: ConstraintMap,
    /// Constrained stiffness `T^T K T`.
    pub k: SparseMatrix,
    /// Constrained mass `T^T M T`.
    pub m: SparseMatrix,
    /// Lumped node masses of all nodes (interface nodes 0) when the assembled mass matrix is diagonal in
    /// the translations with equal x, y, z masses per node (seed 000 Listing 4.3); `None` for consistent mass.
    pub node_masses: Option<Vec<f64>>,
}

impl FeSystem {
    /// Assembles `mesh` with the built-in elements and applies `bc`.
    pub fn assemble(
        mesh: &Mesh,
        bc: &BoundaryConditions,
        mass: MassKind,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, FeError> {
        let a = assemble(mesh, mass, &[], progress)?;
        Self::from_assembled(mesh, &a, bc)
    }

    /// Applies `bc` to matrices assembled elsewhere (e.g. imported from CalculiX) whose DOFs are
    /// numbered as [`DofMap::from_counts`]`(mesh.node_dofs())`.
    pub fn from_assembled(
        mesh: &Mesh,
        a: &Assembled,
        bc: &BoundaryConditions,
    ) -> Result<Self, FeError> {
        let map = ConstraintMap::new(mesh, bc)?;
        let expected = DofMap::from_counts(mesh.node_dofs());
        if a.dofs != expected {
            return Err(FeError::Invalid(
                "assembled matrices are not numbered like the mesh's DOFs".into(),
            ));
        }
        // K and M projected on two threads
        let (k, m) = std::thread::scope(|s| {
            let h = s.spawn(|| map.project(&a.m));
            let k = map.project(&a.k);
            (k, h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
        });
        let (k, m) = (k?, m?);
        let node_masses = lumped_node_masses(a, map.nodes.len());
        Ok(Self {
            map,
            k,
            m,
            node_masses,
        })
    }

    /// Number of independent DOFs.
    pub fn len(&self) -> usize {
        self.map.num_independent()
    }

    /// Whether the system has no DOFs.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Rigid-body vectors in independent DOFs: translations x, y, z and rotations about x, y, z
    /// through `center` (columns 0..6). Uses the constraint map, so interface nodes move as rigid nodes.
    pub fn rigid_body_vectors(&self, center: [f64; 3]) -> Mat<f64> {
        let n = self.len();
        let mut r = Mat::<f64>::zeros(n, 6);
        for (p, d) in self.map.independent.iter().enumerate() {
            let x = self.map.nodes[d.node];
            let rel = [x[0] - center[0], x[1] - center[1], x[2] - center[2]];
            if d.dir < 3 {
                r[(p, d.dir)] = 1.0;
                // rotation about axis a: (e_a x rel)_dir
                for a in 0..3 {
                    let e = unit(a);
                    let c = cross(e, rel);
                    r[(p, 3 + a)] = c[d.dir];
                }
            } else {
                r[(p, d.dir)] = 1.0;
            }
        }
        r
    }

    /// Mass and centre of mass of the free (unfixed) structure from the constrained mass matrix.
    pub fn mass_and_center(&self) -> (f64, [f64; 3]) {
        let r = self.rigid_body_vectors([0.0; 3]);
        let mr = sparse_times(&self.m, r.as_ref());
        let mass = (0..self.len()).map(|i| r[(i, 0)] * mr[(i, 0)]).sum::<f64>();
        // first moments: r_rot_a^T M r_trans_b gives (e_a x x) . m e_b -> static moments
        let s = |a: usize, b: usize| {
            (0..self.len())
                .map(|i| r[(i, 3 + a)] * mr[(i, b)])
                .sum::<f64>()
        };
        // (e_x x x)_y = -z, (e_y x x)_z = -x, (e_z x x)_x = -y  ->  S_z = -s(0,1), S_x = -s(1,2), S_y = -s(2,0)
        let c = if mass > 0.0 {
            [-s(1, 2) / mass, -s(2, 0) / mass, -s(0, 1) / mass]
        } else {
            [0.0; 3]
        };
        (mass, c)
    }
}

/// Node masses from a mass matrix that is diagonal in the translations with equal entries per node
/// (off-diagonal translational entries up to round-off, `1e-12` of the diagonal: a lumped beam
/// element rotated into global axes leaves entries of order `1e-17 m` there).
fn lumped_node_masses(a: &Assembled, n_nodes: usize) -> Option<Vec<f64>> {
    let mut masses = vec![0.0; n_nodes];
    let mut diag = vec![0.0; a.dofs.len];
    for (r, c, v) in entries(&a.m) {
        if r == c {
            diag[r] += v;
        }
    }
    for (r, c, v) in entries(&a.m) {
        let (_, dr) = a.dofs.node_of(r)?;
        let (_, dc) = a.dofs.node_of(c)?;
        let scale = (diag[r].abs() * diag[c].abs()).sqrt();
        if r != c && (dr < 3 || dc < 3) && v.abs() > 1e-12 * scale {
            return None;
        }
    }
    for (node, m) in masses.iter_mut().enumerate().take(a.dofs.count.len()) {
        if a.dofs.count[node] == 0 {
            continue;
        }
        let f = a.dofs.first[node];
        let (mx, my, mz) = (diag[f], diag[f + 1], diag[f + 2]);
        if (mx - my).abs() > 1e-12 * mx.abs() || (mx - mz).abs() > 1e-12 * mx.abs() {
            return None;
        }
        *m = mx;
    }
    Some(masses)
}

fn unit(a: usize) -> [f64; 3] {
    let mut e = [0.0; 3];
    e[a] = 1.0;
    e
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Sparse-dense product `A X`.
pub fn sparse_times(a: &SparseMatrix, x: faer::MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(a.nrows(), x.ncols());
    faer::sparse::linalg::matmul::sparse_dense_matmul(
        out.as_mut(),
        faer::Accum::Replace,
        a.as_ref(),
        x,
        1.0,
        faer::Par::Seq,
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::beam_line;
    use crate::mesh::{BeamSection, BeamTheory};
    use crate::{Material, UnitSystem};

    /// A lumped beam inclined in space (its element matrices rotated into global axes, which
    /// leaves round-off off the translational diagonal) still gives node masses: rho A L / 2 at
    /// the ends, rho A L at the inner nodes, to 1e-12.
    #[test]
    fn inclined_lumped_beam_has_node_masses() {
        let (rho, d, n) = (7800.0, 0.02, 4);
        let p1 = [0.3, 0.5, 0.7];
        let mat = Material {
            e: 210e9,
            nu: 0.3,
            rho,
        };
        let mesh = beam_line(
            [0.0; 3],
            p1,
            n,
            BeamSection::circle(d),
            BeamTheory::EulerBernoulli,
            [0.0, 0.0, 1.0],
            mat,
            UnitSystem::Si,
        )
        .unwrap();
        let bc = BoundaryConditions::default();
        let sys = FeSystem::assemble(&mesh, &bc, MassKind::Lumped, &mut |_, _| {}).unwrap();
        let masses = sys.node_masses.expect("node masses of a lumped beam");
        let le = p1.iter().map(|x| x * x).sum::<f64>().sqrt() / n as f64;
        let m_el = rho * std::f64::consts::PI * d * d / 4.0 * le;
        for (i, m) in masses.iter().enumerate() {
            let expected = if i == 0 || i == n { 0.5 * m_el } else { m_el };
            assert!(
                (m - expected).abs() < 1e-12 * m_el,
                "node {i}: {m} vs {expected}"
            );
        }
    }
}
