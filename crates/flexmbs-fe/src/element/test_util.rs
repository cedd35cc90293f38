//! Test helpers: small structured meshes, rigid-body modes, a dense assembler, constrained static
//! solve and a dense generalized eigen solver (Cholesky reduction).

use super::{element_matrices, MassKind};
use crate::mesh::{Element, ElementKind, Mesh, Property};
use crate::Material;
use nalgebra::{DMatrix, DVector, SymmetricEigen};
use std::collections::HashMap;

/// A one-element mesh of `kind` with solid `material` and nodes `x`.
pub fn single_solid(kind: ElementKind, x: &[[f64; 3]], material: Material) -> Mesh {
    let mut m = Mesh::default();
    let nodes = x.iter().map(|p| m.add_node(*p)).collect();
    let property = m.add_property(Property::Solid { material });
    m.elements.push(Element {
        kind,
        nodes,
        property,
    });
    m
}

/// Reference node coordinates of a solid kind.
pub fn reference_nodes(kind: ElementKind) -> Vec<[f64; 3]> {
    match kind {
        ElementKind::Hex8 | ElementKind::Hex8I => super::hex8::HEX8_NODES.to_vec(),
        ElementKind::Hex20 | ElementKind::Hex20R => super::hex20::HEX20_NODES.to_vec(),
        ElementKind::Tet10 => super::tet10::TET10_NODES.to_vec(),
        ElementKind::Beam2 => vec![[0.0; 3], [1.0, 0.0, 0.0]],
    }
}

/// Rigid-body modes (ndof x 6): 3 translations, then rotations about x, y, z through the origin
/// (u = omega x X; rotation DOFs = omega when `dofs_per_node` = 6).
pub fn rigid_modes(x: &[[f64; 3]], dofs_per_node: usize) -> DMatrix<f64> {
    let mut r = DMatrix::zeros(x.len() * dofs_per_node, 6);
    for (a, p) in x.iter().enumerate() {
        let o = a * dofs_per_node;
        for c in 0..3 {
            r[(o + c, c)] = 1.0;
        }
        // omega = e_x: (0, -z, y); e_y: (z, 0, -x); e_z: (-y, x, 0)
        r[(o + 1, 3)] = -p[2];
        r[(o + 2, 3)] = p[1];
        r[(o, 4)] = p[2];
        r[(o + 2, 4)] = -p[0];
        r[(o, 5)] = -p[1];
        r[(o + 1, 5)] = p[0];
        if dofs_per_node == 6 {
            for c in 0..3 {
                r[(o + 3 + c, 3 + c)] = 1.0;
            }
        }
    }
    r
}

/// Sorted eigenvalues of a symmetric matrix.
pub fn sym_eigenvalues(a: &DMatrix<f64>) -> Vec<f64> {
    let mut v: Vec<f64> = SymmetricEigen::new(a.clone())
        .eigenvalues
        .iter()
        .copied()
        .collect();
    v.sort_by(|a, b| a.total_cmp(b));
    v
}

/// Maximum absolute entry.
pub fn max_abs(a: &DMatrix<f64>) -> f64 {
    a.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Dense assembly of all elements (all nodes with the same number of DOFs `dpn`).
pub fn assemble(mesh: &Mesh, mass: MassKind) -> (DMatrix<f64>, DMatrix<f64>) {
    let dpn = mesh.elements[0].kind.dofs_per_node();
    let n = mesh.num_nodes() * dpn;
    let mut k = DMatrix::zeros(n, n);
    let mut m = DMatrix::zeros(n, n);
    for (ei, el) in mesh.elements.iter().enumerate() {
        let em = element_matrices(mesh, ei, mass).unwrap();
        let dofs: Vec<usize> = el
            .nodes
            .iter()
            .flat_map(|&nd| (0..dpn).map(move |c| nd * dpn + c))
            .collect();
        for (i, &gi) in dofs.iter().enumerate() {
            for (j, &gj) in dofs.iter().enumerate() {
                k[(gi, gj)] += em.k[(i, j)];
                m[(gi, gj)] += em.m[(i, j)];
            }
        }
    }
    (k, m)
}

/// Solves K u = f with the DOFs in `fixed` prescribed to `u_fixed` (same length); returns full u.
pub fn solve_prescribed(
    k: &DMatrix<f64>,
    f: &DVector<f64>,
    fixed: &[usize],
    u_fixed: &[f64],
) -> DVector<f64> {
    let n = k.nrows();
    let mut is_fixed = vec![None; n];
    for (i, &d) in fixed.iter().enumerate() {
        is_fixed[d] = Some(u_fixed[i]);
    }
    let free: Vec<usize> = (0..n).filter(|&i| is_fixed[i].is_none()).collect();
    let mut u = DVector::zeros(n);
    for i in 0..n {
        if let Some(v) = is_fixed[i] {
            u[i] = v;
        }
    }
    let kff = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let rhs = DVector::from_fn(free.len(), |i, _| {
        f[free[i]] - (0..n).map(|j| k[(free[i], j)] * u[j]).sum::<f64>()
    });
    let uf = kff
        .cholesky()
        .expect("constrained K positive definite")
        .solve(&rhs);
    for (i, &d) in free.iter().enumerate() {
        u[d] = uf[i];
    }
    u
}

/// Smallest generalized eigenvalues omega^2 of K phi = omega^2 M phi on the free DOFs (Cholesky of M).
pub fn gen_eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>, fixed: &[usize]) -> Vec<f64> {
    let free: Vec<usize> = (0..k.nrows()).filter(|i| !fixed.contains(i)).collect();
    let kf = DMatrix::from_fn(free.len(), free.len(), |i, j| k[(free[i], free[j])]);
    let mf = DMatrix::from_fn(free.len(), free.len(), |i, j| m[(free[i], free[j])]);
    let l = mf.cholesky().expect("M positive definite").l();
    let linv = l.clone().try_inverse().unwrap();
    let a = &linv * kf * linv.transpose();
    sym_eigenvalues(&a)
}

/// Structured mesh of `kind` (Hex8, Hex8I, Hex20, Hex20R, or Tet10 by Kuhn subdivision of each
/// cell into 6 tetrahedra) on a box [0, len] with `n` cells per direction. Nodes are created on an
/// integer lattice of spacing 1/2 cell; `map` moves a node from its lattice position (arguments:
/// lattice index, lattice maximum, box position). Returns the mesh and each node's lattice index.
pub fn box_mesh(
    kind: ElementKind,
    n: [usize; 3],
    len: [f64; 3],
    material: Material,
    map: &dyn Fn([usize; 3], [usize; 3], [f64; 3]) -> [f64; 3],
) -> (Mesh, Vec<[usize; 3]>) {
    let mut mesh = Mesh::default();
    let property = mesh.add_property(Property::Solid { material });
    let mut ids: HashMap<[usize; 3], usize> = HashMap::new();
    let mut lattice = Vec::new();
    let lmax = [2 * n[0], 2 * n[1], 2 * n[2]];
    let mut node = |mesh: &mut Mesh, l: [usize; 3]| -> usize {
        *ids.entry(l).or_insert_with(|| {
            let p = [0, 1, 2].map(|c| len[c] * l[c] as f64 / lmax[c] as f64);
            lattice.push(l);
            mesh.add_node(map(l, lmax, p))
        })
    };
    for ez in 0..n[2] {
        for ey in 0..n[1] {
            for ex in 0..n[0] {
                let base = [2 * ex, 2 * ey, 2 * ez];
                let at = |r: [f64; 3]| [0, 1, 2].map(|c| (base[c] as f64 + 1.0 + r[c]) as usize);
                let conn: Vec<Vec<[usize; 3]>> = match kind {
                    ElementKind::Tet10 => {
                        kuhn_tets().iter().map(|t| tet10_lattice(t, base)).collect()
                    }
                    _ => vec![reference_nodes(kind).iter().map(|r| at(*r)).collect()],
                };
                for c in conn {
                    let nodes = c.iter().map(|l| node(&mut mesh, *l)).collect();
                    mesh.elements.push(Element {
                        kind,
                        nodes,
                        property,
                    });
                }
            }
        }
    }
    (mesh, lattice)
}

/// The 6 Kuhn tetrahedra of the unit cube as corner bit-vectors, positively oriented.
fn kuhn_tets() -> Vec<[[usize; 3]; 4]> {
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    perms
        .iter()
        .map(|p| {
            let mut v = [[0usize; 3]; 4];
            for s in 1..4 {
                v[s] = v[s - 1];
                v[s][p[s - 1]] = 1;
            }
            // orientation: det of (v1-v0, v2-v0, v3-v0) must be positive; swap v1,v2 otherwise
            let d = |a: [usize; 3]| nalgebra::Vector3::new(a[0] as f64, a[1] as f64, a[2] as f64);
            let det = nalgebra::Matrix3::from_columns(&[d(v[1]), d(v[2]), d(v[3])]).determinant();
            if det < 0.0 {
                v.swap(1, 2);
            }
            v
        })
        .collect()
}

/// Lattice indices of the 10 nodes of a Kuhn tetrahedron in the cell at `base`.
fn tet10_lattice(t: &[[usize; 3]; 4], base: [usize; 3]) -> Vec<[usize; 3]> {
    let corner = |v: [usize; 3]| [0, 1, 2].map(|c| base[c] + 2 * v[c]);
    let c: Vec<[usize; 3]> = t.iter().map(|v| corner(*v)).collect();
    let mid = |a: usize, b: usize| [0, 1, 2].map(|k| (c[a][k] + c[b][k]) / 2);
    vec![
        c[0],
        c[1],
        c[2],
        c[3],
        mid(0, 1),
        mid(1, 2),
        mid(2, 0),
        mid(0, 3),
        mid(1, 3),
        mid(2, 3),
    ]
}
