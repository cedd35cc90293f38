//! Craig-Bampton data of a superelement from an FE body file (a multibody `type = "superelement"`,
//! seed 001 ch. 3-4 and §8.4): the FE model's Craig-Bampton reduction to its named interfaces
//! (each a mesh node with rotations, or a node set tied rigidly to a 6-DOF interface node), the
//! floating-frame condition `[Φ_CB]` (3.7) at the undeformed centre of mass or at the first
//! interface, and the conversion to SI.
//!
//! **The frame condition at the centre of mass.** `[Φ_CB]` gives the rigid motion of the floating
//! frame for each Craig-Bampton coordinate. When an FE node with rotations sits at the centre of
//! mass `c` (a beam mesh with an even number of elements), it is that node's six mode values, as
//! for `superelement_beam`. Otherwise (a solid) the frame follows the **mass-weighted
//! least-squares rigid motion** of the body: for a displacement field `V q` over the independent
//! FE DOFs, the rigid motion `a = (t, θ)` about `c` minimising `(V q − R a)ᵀ M (V q − R a)` is
//!
//! ```text
//!   a = (Rᵀ M R)⁻¹ Rᵀ M V q,   so   [Φ_CB] = (Rᵀ M R)⁻¹ Rᵀ M V
//! ```
//!
//! with `R` (n x 6) the FE rigid-body modes about `c` and `M` the FE mass matrix that also gives
//! `M_CB = Vᵀ M V`. It is the linearized Buckens (mean-axes) condition `Rᵀ M u_el = 0` for the
//! elastic part `u_el = V q − R a`, and exact for rigid motions: `V Φ_rig,0 = R` gives
//! `[Φ_CB][Φ_rig,0] = 1`. About the centre of mass `Rᵀ M R = diag(m 1, J_c)`.

use flexmbs_core::superelement::{Interface, SuperelementData};
use flexmbs_fe::assembly::entries;
use flexmbs_fe::reduction::{ReducedBody, ReductionKind};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::NodeIdx;
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};
use thiserror::Error;

/// Where the floating frame of an FE superelement sits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FeFrame {
    /// At the undeformed centre of mass (a node with rotations there, else the mass-weighted
    /// least-squares rigid motion; module docs).
    #[default]
    CentreOfMass,
    /// At the first interface point (the "traditional" variant).
    FirstInterface,
}

/// How the frame condition `[Φ_CB]` was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameCondition {
    /// The six mode values of the FE node (with rotations) at the frame origin.
    Node(NodeIdx),
    /// The mass-weighted least-squares rigid motion (linearized mean axes).
    MeanAxes,
}

/// Why an FE model cannot be a superelement.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FeSuperelementError {
    /// Not a Craig-Bampton or Guyan reduction.
    #[error("the FE body file reduces with `{method}`: a superelement needs `method = \"craig-bampton\"` (or \"guyan\") in [body.reduction], with its interfaces in `interface`")]
    NotCraigBampton {
        /// The reduction found.
        method: String,
    },
    /// No interface.
    #[error("the FE body file names no interface (`interface = [...]` in [body.reduction]): a superelement needs at least one interface point")]
    NoInterface,
    /// An interface with other than six independent DOFs.
    #[error("interface {index} (`{name}`, FE node {node_id}) has {dofs} independent DOFs, a superelement interface needs 6: a node set of a solid mesh must be tied to one 6-DOF node (`[[body.boundary.rigid]]` with that name), or name a beam node")]
    InterfaceDofs {
        /// 0-based interface index.
        index: usize,
        /// Its name.
        name: String,
        /// FE node id.
        node_id: u64,
        /// DOFs found.
        dofs: usize,
    },
    /// The FE model has fixed nodes.
    #[error("the FE body file fixes {count} nodes ([body.boundary] fixed): a superelement must be free (its rigid motion comes from its interfaces); clamp an interface point with `fixed` in the multibody model instead")]
    FixedNodes {
        /// Number of fixed nodes.
        count: usize,
    },
    /// `Rᵀ M R` not invertible or a non-positive mass.
    #[error("the FE mass matrix gives no invertible rigid-body inertia (mass {mass:e}): the frame condition at the centre of mass is undefined")]
    SingularInertia {
        /// Total mass found.
        mass: f64,
    },
}

/// The superelement data and where its floating frame sits.
#[derive(Debug, Clone)]
pub struct FeSuperelementData {
    /// The Craig-Bampton data in SI, in the floating frame.
    pub data: SuperelementData,
    /// Floating-frame origin in FE coordinates (SI, relative to the FE origin).
    pub origin: Vector3<f64>,
    /// How `[Φ_CB]` was obtained.
    pub condition: FrameCondition,
}

/// The Craig-Bampton data of `reduced` (a Craig-Bampton reduction of `sys` to the interfaces
/// named `names`, in that order) with the floating frame at `frame`.
pub fn superelement_from_reduced(
    sys: &FeSystem,
    reduced: &ReducedBody,
    names: &[String],
    frame: FeFrame,
) -> Result<FeSuperelementData, FeSuperelementError> {
    let internal = match reduced.kind {
        ReductionKind::CraigBampton { internal_modes } => internal_modes,
        ref k => {
            return Err(FeSuperelementError::NotCraigBampton {
                method: format!("{k:?}").to_lowercase(),
            })
        }
    };
    if reduced.interface_nodes.is_empty() {
        return Err(FeSuperelementError::NoInterface);
    }
    if !sys.map.fixed_nodes.is_empty() {
        return Err(FeSuperelementError::FixedNodes {
            count: sys.map.fixed_nodes.len(),
        });
    }
    check_interface_dofs(sys, reduced, names)?;
    let v = basis_on_independent_dofs(sys, reduced);
    let c = centre_of_mass(sys)?;
    let (origin, phi_cb, condition) = match frame {
        FeFrame::FirstInterface => {
            let node = reduced.interface_nodes[0];
            (
                node_position(sys, node),
                node_rows(sys, &v, node),
                FrameCondition::Node(node),
            )
        }
        FeFrame::CentreOfMass => match node_at(sys, &c) {
            Some(node) => (c, node_rows(sys, &v, node), FrameCondition::Node(node)),
            None => (c, mean_axes_rows(sys, &v, &c)?, FrameCondition::MeanAxes),
        },
    };
    let to_dmatrix = |m: &faer::Mat<f64>| DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)]);
    let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
    let interfaces = reduced
        .interface_nodes
        .iter()
        .map(|&n| Interface {
            position: node_position(sys, n) - origin,
            rotation: Matrix3::identity(),
        })
        .collect();
    let data = SuperelementData {
        interfaces,
        internal_modes: internal,
        m_cb: sym(to_dmatrix(&reduced.m_red)),
        k_cb: sym(to_dmatrix(&reduced.k_red)),
        phi_cb,
        centre_of_mass: c - origin,
    };
    Ok(to_si(
        FeSuperelementData {
            data,
            origin,
            condition,
        },
        reduced.units,
    ))
}

/// Every interface node has exactly the six independent DOFs `ux .. rz` in that order (the
/// column order of the Craig-Bampton basis is then `[u_1, θ_1, ..., u_N, θ_N, η]`).
fn check_interface_dofs(
    sys: &FeSystem,
    reduced: &ReducedBody,
    names: &[String],
) -> Result<(), FeSuperelementError> {
    for (index, &node) in reduced.interface_nodes.iter().enumerate() {
        let d = sys.map.independent_of_node(node);
        let ordered = d
            .iter()
            .enumerate()
            .all(|(k, &p)| sys.map.independent[p].dir == k);
        if d.len() != 6 || !ordered {
            return Err(FeSuperelementError::InterfaceDofs {
                index,
                name: names.get(index).cloned().unwrap_or_default(),
                node_id: reduced.node_ids.get(node).copied().unwrap_or(0),
                dofs: d.len(),
            });
        }
    }
    Ok(())
}

/// Undeformed position of FE node `node` (mesh or interface node), body units.
fn node_position(sys: &FeSystem, node: NodeIdx) -> Vector3<f64> {
    Vector3::from(sys.map.nodes[node])
}

/// The Craig-Bampton basis `V` over the independent DOFs (n x n_cb), from the nodal fields of
/// `reduced` (an independent DOF is its node's own DOF).
fn basis_on_independent_dofs(sys: &FeSystem, reduced: &ReducedBody) -> DMatrix<f64> {
    let n = sys.map.independent.len();
    let nf = reduced.num_modes();
    DMatrix::from_fn(n, nf, |p, c| {
        let d = sys.map.independent[p];
        match (d.dir < 3, &reduced.modes_r) {
            (true, _) => reduced.modes_t[(3 * d.node + d.dir, c)],
            (false, Some(r)) => r[(3 * d.node + d.dir - 3, c)],
            (false, None) => 0.0,
        }
    })
}

/// The rigid-body modes `R` (n x 6) over the independent DOFs about the point `c`: translation
/// `t + θ × (x − c)` and rotation `θ` of each node.
fn rigid_modes_about(sys: &FeSystem, c: &Vector3<f64>) -> DMatrix<f64> {
    let n = sys.map.independent.len();
    let mut r = DMatrix::zeros(n, 6);
    for (p, d) in sys.map.independent.iter().enumerate() {
        let x = node_position(sys, d.node) - c;
        if d.dir < 3 {
            r[(p, d.dir)] = 1.0;
            for k in 0..3 {
                // (e_k × x)_dir
                let mut e = Vector3::zeros();
                e[k] = 1.0;
                r[(p, 3 + k)] = e.cross(&x)[d.dir];
            }
        } else {
            r[(p, d.dir)] = 1.0;
        }
    }
    r
}

/// `M a` for the sparse FE mass `M` and a dense `a`.
fn mass_times(sys: &FeSystem, a: &DMatrix<f64>) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(a.nrows(), a.ncols());
    for (i, j, v) in entries(&sys.m) {
        for c in 0..a.ncols() {
            out[(i, c)] += v * a[(j, c)];
        }
    }
    out
}

/// Undeformed centre of mass from the FE mass: with `B = T_tᵀ M R_rot` about the origin,
/// `B = −m skew(c)`.
fn centre_of_mass(sys: &FeSystem) -> Result<Vector3<f64>, FeSuperelementError> {
    let r = rigid_modes_about(sys, &Vector3::zeros());
    let a = r.transpose() * mass_times(sys, &r);
    let m = (a[(0, 0)] + a[(1, 1)] + a[(2, 2)]) / 3.0;
    if !(m > 0.0 && m.is_finite()) {
        return Err(FeSuperelementError::SingularInertia { mass: m });
    }
    Ok(Vector3::new(-a[(2, 4)], -a[(0, 5)], -a[(1, 3)]) / m)
}

/// An FE node with rotations within 1e-9 of the body size of `c`, if any.
fn node_at(sys: &FeSystem, c: &Vector3<f64>) -> Option<NodeIdx> {
    let size = sys
        .map
        .nodes
        .iter()
        .map(|x| (Vector3::from(*x) - c).norm())
        .fold(0.0, f64::max);
    (0..sys.map.nodes.len()).find(|&n| {
        (node_position(sys, n) - c).norm() <= 1e-9 * size.max(f64::MIN_POSITIVE)
            && sys.map.independent_of_node(n).len() == 6
    })
}

/// The six rows of `V` at `node` (its ux .. rz).
fn node_rows(sys: &FeSystem, v: &DMatrix<f64>, node: NodeIdx) -> DMatrix<f64> {
    let d = sys.map.independent_of_node(node);
    DMatrix::from_fn(6, v.ncols(), |i, c| v[(d[i], c)])
}

/// `[Φ_CB] = (Rᵀ M R)⁻¹ Rᵀ M V` about the centre of mass (module docs).
fn mean_axes_rows(
    sys: &FeSystem,
    v: &DMatrix<f64>,
    c: &Vector3<f64>,
) -> Result<DMatrix<f64>, FeSuperelementError> {
    let r = rigid_modes_about(sys, c);
    let mr = mass_times(sys, &r);
    let a = r.transpose() * &mr;
    let mass = (a[(0, 0)] + a[(1, 1)] + a[(2, 2)]) / 3.0;
    let a6 = Matrix6::from_fn(|i, j| a[(i, j)]);
    let inv = a6
        .try_inverse()
        .ok_or(FeSuperelementError::SingularInertia { mass })?;
    let inv = DMatrix::from_fn(6, 6, |i, j| inv[(i, j)]);
    Ok(inv * mr.transpose() * v)
}

/// Converts body units to SI: with the SI coordinates `q_si = D⁻¹ q` (translations times the
/// length factor `l`, rotations and internal-mode amplitudes unchanged) the energies scale by
/// `e = m_unit l²`: `M_si = e D M D`, `K_si = e D K D`, `[Φ_CB]_si = diag(l 1, 1) [Φ_CB] D`.
fn to_si(mut s: FeSuperelementData, units: flexmbs_fe::UnitSystem) -> FeSuperelementData {
    let l = units.length_to_si();
    if l == 1.0 && units.mass_to_si() == 1.0 {
        return s;
    }
    let e = units.mass_to_si() * l * l;
    let d = &mut s.data;
    let n = d.len();
    let dcol = |j: usize| {
        if j < 6 * d.interfaces.len() && j % 6 < 3 {
            1.0 / l
        } else {
            1.0
        }
    };
    let scale: Vec<f64> = (0..n).map(dcol).collect();
    for (i, si) in scale.iter().enumerate() {
        for (j, sj) in scale.iter().enumerate() {
            d.m_cb[(i, j)] *= e * si * sj;
            d.k_cb[(i, j)] *= e * si * sj;
        }
    }
    for i in 0..6 {
        let row = if i < 3 { l } else { 1.0 };
        for (j, sj) in scale.iter().enumerate() {
            d.phi_cb[(i, j)] *= row * sj;
        }
    }
    for itf in &mut d.interfaces {
        itf.position *= l;
    }
    d.centre_of_mass *= l;
    s.origin *= l;
    s
}
