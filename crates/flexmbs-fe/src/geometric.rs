//! Geometric (stress) stiffness of a reduced body under the inertial loads of its floating frame:
//! the unit-load method of Wallrapp / Schwertassek (as in SIMPACK's `SID` data).
//!
//! A body whose frame rotates with body-frame angular velocity `ω` carries the d'Alembert
//! (centrifugal) load `f = -M a(x)`, `a(x) = ω × (ω × x) = (ω ωᵀ - |ω|² I) x`, which is a linear
//! combination of six **load patterns** with coefficients `ω_a ω_b` (`a <= b`):
//! `a_aa(x) = e_a x_a - x` and, for `a < b`, `a_ab(x) = e_a x_b + e_b x_a`. For each pattern `i`:
//!
//! 1. solve the static problem `K u_i = f_i` on the body's supports (its fixed nodes, plus optional
//!    extra support nodes);
//! 2. recover the element stresses of `u_i` and assemble the stress stiffness
//!    `K_σ,i = Σ_e ∫ Gᵀ Σ G dV` (solids: `Σ = σ ⊗ I_3` from the Gauss-point stresses; beams: the
//!    axial-force geometric stiffness, [`beam_geometric_stiffness_local`]);
//! 3. project on the modes: `K_G,i = Φᵀ K_σ,i Φ` (`n_f × n_f`).
//!
//! The stiffened modal stiffness of the spinning body is `k_ff + Σ_i ω_a ω_b K_G,i`; because the
//! load of a linear body is linear in the pattern coefficients, so are the stresses and `K_σ`.
//! Translational-acceleration (`a = e_d`) and angular-acceleration (`a = e_d × x`) patterns are
//! available too ([`InertialLoad`]).
//!
//! Inertial loads use the element mass matrices (`f_e = -M_e A_e` with the nodal acceleration
//! field `A_e`: translations `a(x_j)`, rotations 0). This is exact for lumped masses (the FFR body's
//! own inertia `Σ m_j Φ_jᵀ a_j`) and for consistent solid masses (a linear field lies in the FE
//! space); for consistent beam masses the rotational DOFs of the field are neglected (converges
//! with the mesh).

use crate::assembly::{sparse_from_triplets, DofMap};
use crate::eigen::SparseCholesky;
use crate::element::gauss::{hex_rule, tet_rule_4, QuadPoint};
use crate::element::solid::{b_matrix, eval_point, ShapeFn};
use crate::element::{beam, element_matrices, hex20, hex8, tet10, MassKind};
use crate::mesh::{ElementKind, Property};
use crate::reduction::ReducedBody;
use crate::system::FeSystem;
use crate::{FeError, Mesh, NodeIdx, SparseMatrix};
use faer::sparse::Triplet;
use faer::Mat;
use nalgebra::{DMatrix, Matrix3, Vector3, Vector6};
use thiserror::Error;

/// An inertial load pattern of the body frame, defined by its acceleration field `a(x)` (body
/// coordinates `x` relative to the frame origin); the load is `f = -M a`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InertialLoad {
    /// Coefficient of `ω_a ω_b` (`a <= b`) in the centrifugal acceleration `ω × (ω × x)`:
    /// `e_a x_a - x` for `a == b`, `e_a x_b + e_b x_a` for `a < b`.
    Centrifugal(usize, usize),
    /// Unit translational acceleration of the frame along axis `d`: `a = e_d`.
    Translation(usize),
    /// Unit angular acceleration about axis `d`: `a = e_d × x`.
    AngularAcceleration(usize),
}

impl InertialLoad {
    /// The six centrifugal patterns `(0,0), (0,1), (0,2), (1,1), (1,2), (2,2)`.
    pub fn centrifugal() -> Vec<InertialLoad> {
        let mut v = Vec::with_capacity(6);
        for a in 0..3 {
            for b in a..3 {
                v.push(InertialLoad::Centrifugal(a, b));
            }
        }
        v
    }

    /// Acceleration field of the pattern at body-frame position `x`.
    pub fn acceleration(&self, x: [f64; 3]) -> Result<[f64; 3], GeometricError> {
        let bad = || GeometricError::BadPattern { pattern: *self };
        let mut a = [0.0; 3];
        match *self {
            InertialLoad::Centrifugal(p, q) => {
                if p > q || q > 2 {
                    return Err(bad());
                }
                if p == q {
                    a = [-x[0], -x[1], -x[2]];
                    a[p] += x[p];
                } else {
                    a[p] += x[q];
                    a[q] += x[p];
                }
            }
            InertialLoad::Translation(d) => {
                if d > 2 {
                    return Err(bad());
                }
                a[d] = 1.0;
            }
            InertialLoad::AngularAcceleration(d) => {
                if d > 2 {
                    return Err(bad());
                }
                let mut e = Vector3::zeros();
                e[d] = 1.0;
                let c = e.cross(&Vector3::from(x));
                a = [c[0], c[1], c[2]];
            }
        }
        Ok(a)
    }
}

/// Projected geometric stiffness matrices of a reduced body, one per load pattern, in the units of
/// the body (stiffness per unit pattern coefficient, e.g. per (rad/s)² for centrifugal patterns).
#[derive(Debug, Clone, PartialEq)]
pub struct GeometricStiffness {
    /// The load patterns.
    pub load_patterns: Vec<InertialLoad>,
    /// `K_G,i = Φᵀ K_σ,i Φ`, `n_f × n_f` each, same order as `load_patterns`.
    pub matrices: Vec<Mat<f64>>,
}

impl GeometricStiffness {
    /// Number of modes `n_f` (0 without patterns).
    pub fn num_modes(&self) -> usize {
        self.matrices.first().map_or(0, |m| m.nrows())
    }

    /// `Σ_ab ω_a ω_b K_G,ab` over the centrifugal patterns (other patterns ignored).
    pub fn centrifugal_matrix(&self, omega: [f64; 3]) -> Mat<f64> {
        let n = self.num_modes();
        let mut k = Mat::<f64>::zeros(n, n);
        for (p, m) in self.load_patterns.iter().zip(&self.matrices) {
            if let InertialLoad::Centrifugal(a, b) = *p {
                let c = omega[a] * omega[b];
                k += Mat::from_fn(n, n, |i, j| c * m[(i, j)]);
            }
        }
        k
    }
}

/// Errors of the geometric-stiffness computation.
#[derive(Debug, Error)]
pub enum GeometricError {
    /// Error of the FE front end (element, assembly, factorization).
    #[error(transparent)]
    Fe(#[from] FeError),
    /// The static problem has no supports (free-free body): `K` is singular.
    #[error("the static unit-load problem of '{body}' is singular: the body has no fixed nodes; pass support nodes (inertia relief is not implemented)")]
    NoSupports {
        /// Body name.
        body: String,
    },
    /// The static problem has supports but `K` is still singular: a mechanism.
    #[error("the static unit-load problem of '{body}' is singular although {held} nodes are held: the supports do not stop every rigid-body motion (a single solid node is a pin), or the mesh has a zero-energy mechanism (hourglass modes of reduced-integration elements with one element across a section: use hex20 or more divisions; disconnected parts)")]
    Mechanism {
        /// Body name.
        body: String,
        /// Number of fixed and support nodes.
        held: usize,
    },
    /// A load pattern with an axis index out of range (or `a > b` for centrifugal patterns).
    #[error("invalid inertial load pattern {pattern:?} (axes 0..3, centrifugal a <= b)")]
    BadPattern {
        /// The pattern.
        pattern: InertialLoad,
    },
    /// Node data of the reduced body do not match the system.
    #[error("reduced body has {found} mode rows, the system has 3 x {nodes} nodes")]
    NodeMismatch {
        /// Number of nodes of the constraint map.
        nodes: usize,
        /// Rows of the reduced body's translational modes.
        found: usize,
    },
    /// A node load at a node index out of range.
    #[error("node load at node {node} out of range (mesh has {nodes} nodes)")]
    NodeOutOfRange {
        /// The node.
        node: NodeIdx,
        /// Number of mesh nodes.
        nodes: usize,
    },
    /// A node load with an axis out of range, or a moment at a node without rotational DOFs.
    #[error("invalid node load {load:?} (axes 0..3; moments only at nodes with rotations)")]
    BadNodeLoad {
        /// The load.
        load: crate::geometric_loads::NodeLoad,
    },
    /// Inertia relief of a free-free body needs a statically determinate support: a node with six
    /// independent DOFs.
    #[error("the unit-load problems of the free-free body '{body}' need a node with six DOFs (a beam node or a rigid interface node) as the determinate support of inertia relief; solid meshes need a rigid interface")]
    NoReliefSupport {
        /// Body name.
        body: String,
    },
    /// A support node index is out of range.
    #[error("support node {node} out of range (mesh has {nodes} nodes)")]
    SupportOutOfRange {
        /// The node.
        node: NodeIdx,
        /// Number of mesh nodes.
        nodes: usize,
    },
}

/// Geometric stiffness (12 × 12, local frame, DOFs `u, v, w, θx, θy, θz` per node) of a two-node
/// beam of length `l` under axial force `n` (tension positive), from the cubic Hermite
/// interpolation (Przemieniecki 1968; McGuire, Gallagher, Ziemian (9.19)): per bending plane
/// `N/L [6/5, L/10, -6/5, L/10; L/10, 2L²/15, -L/10, -L²/30; ...]`, torsion `N (I_p/A)/L [1, -1]`
/// and the axial term `N/L [1, -1]` of the Green strain (as `Gᵀ Σ G` of a solid). Used for
/// Euler-Bernoulli and Timoshenko beams alike (shear effect on `K_σ` neglected).
pub fn beam_geometric_stiffness_local(n: f64, l: f64, ip_over_a: f64) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(12, 12);
    let c = n / l;
    let plane = [
        [1.2, 0.1 * l, -1.2, 0.1 * l],
        [0.1 * l, 2.0 * l * l / 15.0, -0.1 * l, -l * l / 30.0],
        [-1.2, -0.1 * l, 1.2, -0.1 * l],
        [0.1 * l, -l * l / 30.0, -0.1 * l, 2.0 * l * l / 15.0],
    ];
    let planes: [([usize; 4], [f64; 4]); 2] = [
        ([1, 5, 7, 11], [1.0, 1.0, 1.0, 1.0]),
        ([2, 4, 8, 10], [1.0, -1.0, 1.0, -1.0]),
    ];
    for (idx, sg) in planes {
        for i in 0..4 {
            for j in 0..4 {
                k[(idx[i], idx[j])] += c * sg[i] * sg[j] * plane[i][j];
            }
        }
    }
    for (i, j, f) in [(0, 6, 1.0), (3, 9, ip_over_a)] {
        k[(i, i)] += c * f;
        k[(j, j)] += c * f;
        k[(i, j)] -= c * f;
        k[(j, i)] -= c * f;
    }
    k
}

/// Shape function, stress-recovery and `K_σ` integration rule of a solid element kind (the
/// stiffness rule; `Hex8I` uses the compatible trilinear field, its incompatible modes are not
/// recovered).
fn solid_rule(kind: ElementKind) -> Option<(ShapeFn, Vec<QuadPoint>)> {
    Some(match kind {
        ElementKind::Hex8 | ElementKind::Hex8I => (hex8::hex8_shape as ShapeFn, hex_rule(2)),
        ElementKind::Hex20 => (hex20::hex20_shape as ShapeFn, hex_rule(3)),
        ElementKind::Hex20R => (hex20::hex20_shape as ShapeFn, hex_rule(2)),
        ElementKind::Tet10 => (tet10::tet10_shape as ShapeFn, tet_rule_4()),
        ElementKind::Beam2 => return None,
    })
}

/// Stress stiffness `K_σ` (global coordinates, element DOF order) of element `element` for its
/// nodal displacements `u_e` (node-major, 3 or 6 DOFs per node): solids
/// `Σ_p det J w (dN_a · σ_p dN_b) I_3` with Gauss-point stresses `σ_p = D B_p u_e` (Voigt, shear
/// engineering strains); beams [`beam_geometric_stiffness_local`] with `N = EA Δu_x / L`.
pub fn element_stress_stiffness(
    mesh: &Mesh,
    element: usize,
    u_e: &[f64],
) -> Result<DMatrix<f64>, FeError> {
    let el = mesh
        .elements
        .get(element)
        .ok_or_else(|| FeError::Invalid(format!("element index {element} out of range")))?;
    let x: Vec<[f64; 3]> = el
        .nodes
        .iter()
        .map(|&n| {
            mesh.nodes
                .get(n)
                .copied()
                .ok_or_else(|| FeError::Invalid(format!("element {element}: node {n} missing")))
        })
        .collect::<Result<_, _>>()?;
    let nd = el.kind.dofs_per_node() * x.len();
    if u_e.len() != nd || x.len() != el.kind.num_nodes() {
        return Err(FeError::Invalid(format!(
            "element {element}: {} displacements for {nd} DOFs",
            u_e.len()
        )));
    }
    let prop = mesh.properties.get(el.property).ok_or_else(|| {
        FeError::Invalid(format!(
            "element {element}: missing property {}",
            el.property
        ))
    })?;
    match (el.kind, prop) {
        (
            ElementKind::Beam2,
            Property::Beam {
                material,
                section,
                orientation,
                ..
            },
        ) => {
            let (r, l) = beam::beam_frame(x[0], x[1], *orientation, element)?;
            let du = Vector3::new(u_e[6] - u_e[0], u_e[7] - u_e[1], u_e[8] - u_e[2]);
            let n = material.e * section.area * r.row(0).transpose().dot(&du) / l;
            let kl = beam_geometric_stiffness_local(n, l, (section.iy + section.iz) / section.area);
            let mut t = DMatrix::zeros(12, 12);
            for b in 0..4 {
                t.view_mut((3 * b, 3 * b), (3, 3)).copy_from(&r);
            }
            Ok(t.transpose() * kl * &t)
        }
        (kind, Property::Solid { material }) => {
            let (shape, rule) = solid_rule(kind).ok_or_else(|| {
                FeError::Invalid(format!("element {element}: not a solid element"))
            })?;
            let d = material.elasticity_matrix();
            let ue = nalgebra::DVector::from_column_slice(u_e);
            let nn = x.len();
            let mut k = DMatrix::zeros(nd, nd);
            for (ip, p) in rule.iter().enumerate() {
                let e = eval_point(shape, &x, p.xi, element, ip)?;
                let eps = b_matrix(&e.dndx) * &ue;
                let sig: Vector6<f64> = d * Vector6::from_column_slice(eps.as_slice());
                let s = Matrix3::new(
                    sig[0], sig[3], sig[5], sig[3], sig[1], sig[4], sig[5], sig[4], sig[2],
                );
                let f = e.det * p.w;
                for a in 0..nn {
                    let sa = s * e.dndx[a];
                    for b in 0..nn {
                        let v = f * sa.dot(&e.dndx[b]);
                        for c in 0..3 {
                            k[(3 * a + c, 3 * b + c)] += v;
                        }
                    }
                }
            }
            Ok(k)
        }
        (kind, _) => Err(FeError::Invalid(format!(
            "element {element} ({kind:?}) has a property of the wrong kind"
        ))),
    }
}

/// Element DOF vector of element `el` from nodal translation/rotation fields (`3 N × k`, column `c`).
fn element_vector(
    mesh: &Mesh,
    el: usize,
    t: &Mat<f64>,
    r: &Mat<f64>,
    c: usize,
    out: &mut Vec<f64>,
) {
    let e = &mesh.elements[el];
    let npn = e.kind.dofs_per_node();
    out.clear();
    for &n in &e.nodes {
        for d in 0..npn {
            out.push(if d < 3 {
                t[(3 * n + d, c)]
            } else {
                r[(3 * n + d - 3, c)]
            });
        }
    }
}

/// Inertial load vectors `f_i = -M a_i` of `patterns` over the independent DOFs of `sys`
/// (columns), from the element masses of kind `mass` (see the module docs).
pub fn inertial_loads(
    mesh: &Mesh,
    sys: &FeSystem,
    mass: MassKind,
    patterns: &[InertialLoad],
) -> Result<Mat<f64>, GeometricError> {
    let dofs = DofMap::from_counts(mesh.node_dofs());
    let np = patterns.len();
    let mut full = Mat::<f64>::zeros(dofs.len, np);
    let mut acc = Vec::new();
    for (ei, el) in mesh.elements.iter().enumerate() {
        let me = element_matrices(mesh, ei, mass)?.m;
        let npn = el.kind.dofs_per_node();
        for (c, p) in patterns.iter().enumerate() {
            acc.clear();
            for &n in &el.nodes {
                let a = p.acceleration(mesh.nodes[n])?;
                acc.extend_from_slice(&a);
                acc.extend(std::iter::repeat_n(0.0, npn - 3));
            }
            for (i, &n) in el.nodes.iter().enumerate() {
                for d in 0..npn {
                    let row = i * npn + d;
                    let f: f64 = (0..acc.len()).map(|j| me[(row, j)] * acc[j]).sum();
                    full[(dofs.first[n] + d, c)] -= f;
                }
            }
        }
    }
    // f_ind = T^T f_full
    let mut out = Mat::<f64>::zeros(sys.len(), np);
    for (i, row) in sys.map.rows.iter().enumerate().take(dofs.len) {
        for &(p, tp) in row {
            for c in 0..np {
                out[(p, c)] += tp * full[(i, c)];
            }
        }
    }
    Ok(out)
}

/// Solves `K v = f` (columns of `f`, independent DOFs of `sys`) with the independent DOFs of the
/// `supports` nodes held at zero in addition to the system's fixed nodes.
pub fn static_solve(
    sys: &FeSystem,
    f: &Mat<f64>,
    supports: &[NodeIdx],
    body: &str,
) -> Result<Mat<f64>, GeometricError> {
    let n = sys.len();
    let mut held = vec![false; n];
    for &s in supports {
        if s >= sys.map.nodes.len() {
            return Err(GeometricError::SupportOutOfRange {
                node: s,
                nodes: sys.map.nodes.len(),
            });
        }
        for p in sys.map.independent_of_node(s) {
            held[p] = true;
        }
    }
    let free: Vec<usize> = (0..n).filter(|&p| !held[p]).collect();
    let mut pos = vec![usize::MAX; n];
    for (i, &p) in free.iter().enumerate() {
        pos[p] = i;
    }
    let mut trip = Vec::new();
    for (i, j, v) in crate::assembly::entries(&sys.k) {
        if pos[i] != usize::MAX && pos[j] != usize::MAX {
            trip.push(Triplet::new(pos[i], pos[j], v));
        }
    }
    let kf: SparseMatrix = sparse_from_triplets(free.len(), &trip)?;
    let chol = match SparseCholesky::factor(&kf) {
        Ok(c) => c,
        Err(FeError::NotPositiveDefinite { .. }) => {
            let mut nodes: Vec<NodeIdx> = sys.map.fixed_nodes.clone();
            nodes.extend_from_slice(supports);
            nodes.sort_unstable();
            nodes.dedup();
            let held = nodes.len();
            return Err(if held == 0 {
                GeometricError::NoSupports { body: body.into() }
            } else {
                GeometricError::Mechanism {
                    body: body.into(),
                    held,
                }
            });
        }
        Err(e) => return Err(e.into()),
    };
    let mut rhs = Mat::<f64>::from_fn(free.len(), f.ncols(), |i, c| f[(free[i], c)]);
    chol.solve_in_place(rhs.as_mut());
    let mut v = Mat::<f64>::zeros(n, f.ncols());
    for (i, &p) in free.iter().enumerate() {
        for c in 0..f.ncols() {
            v[(p, c)] = rhs[(i, c)];
        }
    }
    Ok(v)
}

/// Stress stiffness `T^T K_σ(v) T` over the independent DOFs of `sys` for the independent-DOF
/// displacement vector `v` (e.g. the result of [`static_solve`]).
pub fn stress_stiffness_matrix(
    mesh: &Mesh,
    sys: &FeSystem,
    v: &[f64],
) -> Result<SparseMatrix, FeError> {
    if v.len() != sys.len() {
        return Err(FeError::Invalid(format!(
            "displacement vector has {} entries, the system {}",
            v.len(),
            sys.len()
        )));
    }
    let (t, r) = sys
        .map
        .expand(faer::MatRef::from_column_major_slice(v, v.len(), 1));
    let dofs = DofMap::from_counts(mesh.node_dofs());
    let mut trip = Vec::new();
    let mut ue = Vec::new();
    let mut eqs = Vec::new();
    for (ei, el) in mesh.elements.iter().enumerate() {
        element_vector(mesh, ei, &t, &r, 0, &mut ue);
        let ks = element_stress_stiffness(mesh, ei, &ue)?;
        let npn = el.kind.dofs_per_node();
        eqs.clear();
        for &n in &el.nodes {
            eqs.extend((0..npn).map(|d| dofs.first[n] + d));
        }
        for (a, &ga) in eqs.iter().enumerate() {
            for (b, &gb) in eqs.iter().enumerate() {
                if ks[(a, b)] != 0.0 {
                    trip.push(Triplet::new(ga, gb, ks[(a, b)]));
                }
            }
        }
    }
    let full = sparse_from_triplets(dofs.len, &trip)?;
    sys.map.project(&full)
}

/// Geometric stiffness of the reduced body `body` (reduced from `mesh` and `sys`) for the inertial
/// load `patterns` (unit-load method, see the module docs): static solutions on the fixed nodes of
/// `sys` plus `supports`, element stresses, `K_G,i = Φᵀ K_σ,i Φ` with the modes of `body`
/// (translations and rotations of its nodal fields). Inertial loads use element masses of kind
/// `mass` (use the kind `sys` was assembled with). Cost: one sparse factorization and one pass
/// over the elements per pattern.
pub fn geometric_stiffness(
    mesh: &Mesh,
    sys: &FeSystem,
    body: &ReducedBody,
    mass: MassKind,
    patterns: &[InertialLoad],
    supports: &[NodeIdx],
) -> Result<GeometricStiffness, GeometricError> {
    let nn = sys.map.nodes.len();
    if body.modes_t.nrows() != 3 * nn {
        return Err(GeometricError::NodeMismatch {
            nodes: nn,
            found: body.modes_t.nrows(),
        });
    }
    let f = inertial_loads(mesh, sys, mass, patterns)?;
    let v = static_solve(sys, &f, supports, &body.name)?;
    let k_g = project_stress_stiffness(mesh, sys, body, &v)?;
    Ok(GeometricStiffness {
        load_patterns: patterns.to_vec(),
        matrices: k_g,
    })
}

/// Projected stress stiffness `K_G,i = Φᵀ K_σ(v_i) Φ` (symmetrized, `n_f × n_f`) of each column
/// `v_i` of `v` (independent-DOF displacements of `sys`, e.g. static unit-load solutions), with
/// the modes of `body` (translations and rotations of its nodal fields).
pub fn project_stress_stiffness(
    mesh: &Mesh,
    sys: &FeSystem,
    body: &ReducedBody,
    v: &Mat<f64>,
) -> Result<Vec<Mat<f64>>, GeometricError> {
    let nn = sys.map.nodes.len();
    if body.modes_t.nrows() != 3 * nn {
        return Err(GeometricError::NodeMismatch {
            nodes: nn,
            found: body.modes_t.nrows(),
        });
    }
    let nf = body.num_modes();
    let (t, r) = sys.map.expand(v.as_ref());
    let zero_r = Mat::<f64>::zeros(3 * nn, nf);
    let modes_r = body.modes_r.as_ref().unwrap_or(&zero_r);
    let mut k_g = vec![Mat::<f64>::zeros(nf, nf); v.ncols()];
    let mut ue = Vec::new();
    let mut phi_e: Vec<Vec<f64>> = vec![Vec::new(); nf];
    for ei in 0..mesh.elements.len() {
        for (k, col) in phi_e.iter_mut().enumerate() {
            element_vector(mesh, ei, &body.modes_t, modes_r, k, col);
        }
        for (c, kg) in k_g.iter_mut().enumerate() {
            element_vector(mesh, ei, &t, &r, c, &mut ue);
            let ks = element_stress_stiffness(mesh, ei, &ue)?;
            let nd = ue.len();
            for a in 0..nf {
                let ksa: Vec<f64> = (0..nd)
                    .map(|j| (0..nd).map(|i| phi_e[a][i] * ks[(i, j)]).sum())
                    .collect();
                for b in 0..nf {
                    kg[(a, b)] += (0..nd).map(|j| ksa[j] * phi_e[b][j]).sum::<f64>();
                }
            }
        }
    }
    for kg in &mut k_g {
        let s = Mat::from_fn(nf, nf, |i, j| 0.5 * (kg[(i, j)] + kg[(j, i)]));
        *kg = s;
    }
    Ok(k_g)
}
