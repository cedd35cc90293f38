//! Geometric stiffness of a reduced body under forces and moments at its nodes, and the
//! unit-load method for free-free bodies with **inertia relief**.
//!
//! [`crate::geometric`] computes `K_G,i = Φᵀ K_σ,i Φ` for inertial load patterns of the floating
//! frame, each solved statically on the body's supports (fixed nodes). An FFR body in a mechanism
//! is also loaded at the nodes where joints and loads attach (joint reactions, applied forces),
//! and it is often free-free (no fixed node: the rod of a slider-crank). This module adds
//!
//! - **node load patterns** ([`NodeLoad`]): a unit force or moment at a node along a body axis
//!   (the FE load vector `Tᵀ e_dof` over the independent DOFs, so a node of a rigid interface
//!   loads its interface node);
//! - **inertia relief** for a body without fixed nodes: each unit load `f` is balanced by the
//!   d'Alembert load of the rigid-body acceleration it would cause,
//!   `f̃ = f − M Φ_r (Φ_rᵀ M Φ_r)⁺ Φ_rᵀ f` (`Φ_r`: the six rigid-body fields,
//!   [`FeSystem::rigid_body_vectors`]), so `Φ_rᵀ f̃ = 0`; the self-equilibrated `f̃` is then
//!   solved statically with one node of six independent DOFs held (a beam node or a rigid
//!   interface node: a statically determinate support, whose reactions vanish for an equilibrated
//!   load), and the stress state is that of the free body. Translational- and
//!   angular-acceleration patterns are rigid-body inertial loads and relieve to zero; centrifugal
//!   patterns keep their non-rigid part.
//!
//! Because the loads on a free body in motion are balanced by its rigid-body inertia (up to the
//! elastic coupling terms), the relieved patterns combined with the current node forces and the
//! angular velocity give the stress state of the real load: `Σ_p c_p f̃_p = P (F_ext − M a_rigid) =
//! F_ext − M a_rigid` (`P` the relief projector, which leaves an equilibrated load unchanged and
//! removes the rigid-body accelerations' loads).

use crate::element::MassKind;
use crate::geometric::{
    inertial_loads, project_stress_stiffness, static_solve, GeometricError, GeometricStiffness,
    InertialLoad,
};
use crate::reduction::ReducedBody;
use crate::system::{sparse_times, FeSystem};
use crate::{Mesh, NodeIdx};
use faer::Mat;
use nalgebra::{Matrix6, SymmetricEigen};

/// A unit load at a mesh node along body axis `axis` (0, 1, 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeLoad {
    /// Unit force.
    Force {
        /// Node index.
        node: NodeIdx,
        /// Axis.
        axis: usize,
    },
    /// Unit moment (nodes with rotational DOFs only).
    Moment {
        /// Node index.
        node: NodeIdx,
        /// Axis.
        axis: usize,
    },
}

/// A unit load pattern of the unit-load method: an inertial load of the floating frame or a node
/// load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitLoad {
    /// Inertial load (`f = −M a(x)`).
    Inertial(InertialLoad),
    /// Force or moment at a node.
    Node(NodeLoad),
}

/// Projected geometric stiffness matrices of a reduced body, one per unit load pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadGeometricStiffness {
    /// The patterns.
    pub patterns: Vec<UnitLoad>,
    /// `K_G,i = Φᵀ K_σ,i Φ` (`n_f × n_f`, body units per unit pattern coefficient), same order.
    pub matrices: Vec<Mat<f64>>,
    /// Whether the static problems used inertia relief (body without fixed nodes).
    pub inertia_relief: bool,
}

impl LoadGeometricStiffness {
    /// The centrifugal patterns (for the engine's centrifugal stiffening, e.g.
    /// `FfrBody::with_geometric_stiffening`; relieved for a free-free body).
    pub fn centrifugal(&self) -> GeometricStiffness {
        let (mut load_patterns, mut matrices) = (Vec::new(), Vec::new());
        for (p, m) in self.patterns.iter().zip(&self.matrices) {
            if let UnitLoad::Inertial(c @ InertialLoad::Centrifugal(..)) = *p {
                load_patterns.push(c);
                matrices.push(m.clone());
            }
        }
        GeometricStiffness {
            load_patterns,
            matrices,
        }
    }

    /// All patterns except the centrifugal ones (node loads, accelerations).
    pub fn without_centrifugal(&self) -> LoadGeometricStiffness {
        let keep = |p: &UnitLoad| !matches!(p, UnitLoad::Inertial(InertialLoad::Centrifugal(..)));
        let (patterns, matrices) = self
            .patterns
            .iter()
            .zip(&self.matrices)
            .filter(|(p, _)| keep(p))
            .map(|(p, m)| (*p, m.clone()))
            .unzip();
        LoadGeometricStiffness {
            patterns,
            matrices,
            inertia_relief: self.inertia_relief,
        }
    }
}

/// Load vectors (columns, independent DOFs of `sys`) of `patterns`; inertial patterns from the
/// element masses of kind `mass` ([`inertial_loads`]).
pub fn unit_load_vectors(
    mesh: &Mesh,
    sys: &FeSystem,
    mass: MassKind,
    patterns: &[UnitLoad],
) -> Result<Mat<f64>, GeometricError> {
    let n = sys.len();
    let mut f = Mat::<f64>::zeros(n, patterns.len());
    let nodes = sys.map.dofs.count.len();
    for (c, p) in patterns.iter().enumerate() {
        match *p {
            UnitLoad::Inertial(ip) => {
                let col = inertial_loads(mesh, sys, mass, &[ip])?;
                for i in 0..n {
                    f[(i, c)] = col[(i, 0)];
                }
            }
            UnitLoad::Node(nl) => {
                let (node, axis, dof) = match nl {
                    NodeLoad::Force { node, axis } => (node, axis, axis),
                    NodeLoad::Moment { node, axis } => (node, axis, 3 + axis),
                };
                if node >= nodes {
                    return Err(GeometricError::NodeOutOfRange { node, nodes });
                }
                if axis > 2 || dof >= sys.map.dofs.count[node] {
                    return Err(GeometricError::BadNodeLoad { load: nl });
                }
                let eq = sys.map.dofs.first[node] + dof;
                for &(p, tp) in &sys.map.rows[eq] {
                    f[(p, c)] += tp;
                }
            }
        }
    }
    Ok(f)
}

/// Inertia relief in place: `f ← f − M Φ_r (Φ_rᵀ M Φ_r)⁺ Φ_rᵀ f` for every column (see the
/// module docs). The pseudo-inverse drops rigid fields without inertia (eigenvalues below
/// `1e-12` of the largest, e.g. the torsion of a beam without rotary inertia); a load along such
/// a field stays unbalanced and is reacted by the support.
pub fn inertia_relief(sys: &FeSystem, f: &mut Mat<f64>) {
    let (_, c) = sys.mass_and_center();
    let phi = sys.rigid_body_vectors(c);
    let mphi = sparse_times(&sys.m, phi.as_ref());
    let n = sys.len();
    let a = Matrix6::from_fn(|i, j| (0..n).map(|k| phi[(k, i)] * mphi[(k, j)]).sum::<f64>());
    let a = 0.5 * (a + a.transpose());
    let eig = SymmetricEigen::new(a);
    let top = eig.eigenvalues.amax();
    let mut pinv = Matrix6::zeros();
    for k in 0..6 {
        let l = eig.eigenvalues[k];
        if l > 1e-12 * top {
            let v = eig.eigenvectors.column(k);
            pinv += v * v.transpose() / l;
        }
    }
    for col in 0..f.ncols() {
        let r = nalgebra::Vector6::from_fn(|i, _| (0..n).map(|k| phi[(k, i)] * f[(k, col)]).sum());
        let acc = pinv * r;
        for k in 0..n {
            let mut s = 0.0;
            for i in 0..6 {
                s += mphi[(k, i)] * acc[i];
            }
            f[(k, col)] -= s;
        }
    }
}

/// A statically determinate support for the relieved problems: the first node with six
/// independent DOFs (a beam node, a rigid interface node), `None` if there is none.
pub fn relief_support(sys: &FeSystem) -> Option<NodeIdx> {
    (0..sys.map.dofs.count.len()).find(|&n| sys.map.independent_of_node(n).len() == 6)
}

/// The unit-load method for `patterns` on `body` (reduced from `mesh` and `sys`): static solutions
/// on the fixed nodes of `sys`, or, for a body without fixed nodes, with inertia relief on a
/// determinate support ([`relief_support`]); element stress stiffness; projection on the modes.
/// `mass` is the element mass kind of `sys`. Errors: a free-free body without a node of six
/// independent DOFs (solid meshes without a rigid interface: [`GeometricError::NoReliefSupport`]),
/// a node load at a node or DOF that does not exist.
pub fn load_geometric_stiffness(
    mesh: &Mesh,
    sys: &FeSystem,
    body: &ReducedBody,
    mass: MassKind,
    patterns: &[UnitLoad],
) -> Result<LoadGeometricStiffness, GeometricError> {
    let mut f = unit_load_vectors(mesh, sys, mass, patterns)?;
    let relief = sys.map.fixed_nodes.is_empty();
    let supports = if relief {
        inertia_relief(sys, &mut f);
        vec![
            relief_support(sys).ok_or_else(|| GeometricError::NoReliefSupport {
                body: body.name.clone(),
            })?,
        ]
    } else {
        Vec::new()
    };
    let v = static_solve(sys, &f, &supports, &body.name)?;
    let matrices = project_stress_stiffness(mesh, sys, body, &v)?;
    Ok(LoadGeometricStiffness {
        patterns: patterns.to_vec(),
        matrices,
        inertia_relief: relief,
    })
}
