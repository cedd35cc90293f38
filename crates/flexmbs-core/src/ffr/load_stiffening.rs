//! Geometric stiffening of an FFR body by the loads at its nodes (joint reactions, applied loads)
//! and, for a supported body, by the frame accelerations: the unit-load method extended beyond
//! the centrifugal patterns of [`super::GeometricStiffening`].
//!
//! The stressed modal stiffness is `k_ff + K_geo(ω̄) + K_load(c)` with
//! `K_load(c) = Σ_p c_p K_G,p` over
//! - per interface node `k`: the body-axis components of the force `F̄_k` and moment `M̄_k` the
//!   model applies at the node's frames (`c = Aᵀ F`, `Aᵀ M`; joint reactions `−Σ λ_r t_r`,
//!   `−Σ λ_r r_r` of the rows through the frame, plus the wrenches of loads and force elements);
//! - for a body with supports (fixed nodes in the FE model): the d'Alembert load of the frame's
//!   translational acceleration minus gravity, `ā − ḡ = Aᵀ (R̈ − g)`, and of its angular
//!   acceleration `ω̄̇ = H ẇ + Ḣ w` ([`flexmbs_fe::geometric::InertialLoad::Translation`],
//!   `AngularAcceleration`). A free-free body uses inertia relief instead
//!   ([`flexmbs_fe::geometric_loads`]): its node-load patterns are balanced by the rigid-body
//!   inertia they cause, and its acceleration patterns vanish.
//!
//! The generalized elastic force gains `−K_load(c) q_f`. The coefficients depend on the joint
//! multipliers and accelerations, which the element contract does not see: the system stage
//! [`crate::system::add_load_stiffening_forces`] computes them at each Newton iterate into the
//! body's scratch ([`super::FfrEval::load_coefficients`]) and adds the force; the element's
//! tangent then adds `∂/∂q_f = −K_load(c)` at those coefficients. The dependence of `c` on
//! `λ`, `u̇` and on the floating-frame rotation (`Aᵀ`) is left out of the iteration matrix.

use super::{FfrBody, FfrError};
use faer::MatMut;
use flexmbs_fe::geometric::InertialLoad;
use flexmbs_fe::geometric_loads::{LoadGeometricStiffness, NodeLoad, UnitLoad};
use nalgebra::{DMatrix, DVector};

/// The projected geometric stiffness of one interface node: force patterns along the body axes,
/// then moment patterns (zero matrices for a node without rotations), SI, per N and per N m.
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceStiffness {
    /// Mesh node index.
    pub node: usize,
    /// `K_G` of a unit force along x, y, z and a unit moment about x, y, z (`n_f × n_f`).
    pub matrices: [DMatrix<f64>; 6],
}

/// Node-load (and, for supported bodies, acceleration) geometric stiffness of an FFR body.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadStiffening {
    /// Interface nodes in order; coefficient block `6 k .. 6 k + 6` belongs to `interfaces[k]`.
    pub interfaces: Vec<InterfaceStiffness>,
    /// `K_G` of the frame translational acceleration along x, y, z and angular acceleration about
    /// x, y, z (per m/s² and rad/s²), `None` for a free-free body (inertia relief: they vanish).
    pub acceleration: Option<[DMatrix<f64>; 6]>,
    /// Whether the unit loads were relieved by the body's inertia (free-free body).
    pub inertia_relief: bool,
}

fn checked(m: &faer::Mat<f64>, nf: usize) -> Result<DMatrix<f64>, FfrError> {
    for (what, found) in [
        ("rows of a load geometric stiffness matrix", m.nrows()),
        ("columns of a load geometric stiffness matrix", m.ncols()),
    ] {
        if found != nf {
            return Err(FfrError::DimensionMismatch {
                what,
                expected: nf,
                found,
            });
        }
    }
    let d = DMatrix::from_fn(nf, nf, |i, j| m[(i, j)]);
    if d.iter().any(|x| !x.is_finite()) {
        return Err(FfrError::NonFinite {
            what: "load geometric stiffness matrix",
        });
    }
    Ok(d)
}

impl LoadStiffening {
    /// From the unit-load matrices of [`flexmbs_fe::geometric_loads::load_geometric_stiffness`]
    /// (SI, `n_f` modes): node force/moment patterns grouped by node (in order of first
    /// appearance; a pattern not given is a zero matrix), and, only for a supported body, the six
    /// acceleration patterns (all six required). Centrifugal patterns belong to
    /// [`FfrBody::with_geometric_stiffening`] and are rejected here.
    pub fn from_fe(g: &LoadGeometricStiffness, nf: usize) -> Result<Self, FfrError> {
        if g.patterns.len() != g.matrices.len() {
            return Err(FfrError::DimensionMismatch {
                what: "load geometric stiffness matrices per pattern",
                expected: g.patterns.len(),
                found: g.matrices.len(),
            });
        }
        let zero = || std::array::from_fn(|_| DMatrix::zeros(nf, nf));
        let mut interfaces: Vec<InterfaceStiffness> = Vec::new();
        let mut acc: [Option<DMatrix<f64>>; 6] = Default::default();
        for (p, m) in g.patterns.iter().zip(&g.matrices) {
            let m = checked(m, nf)?;
            let (node, slot) = match *p {
                UnitLoad::Node(NodeLoad::Force { node, axis }) if axis < 3 => (node, axis),
                UnitLoad::Node(NodeLoad::Moment { node, axis }) if axis < 3 => (node, 3 + axis),
                UnitLoad::Inertial(InertialLoad::Translation(d)) if d < 3 && !g.inertia_relief => {
                    acc[d] = Some(m);
                    continue;
                }
                UnitLoad::Inertial(InertialLoad::AngularAcceleration(d))
                    if d < 3 && !g.inertia_relief =>
                {
                    acc[3 + d] = Some(m);
                    continue;
                }
                other => {
                    return Err(FfrError::UnsupportedLoadPattern {
                        pattern: format!("{other:?}"),
                    })
                }
            };
            let k = match interfaces.iter().position(|i| i.node == node) {
                Some(k) => k,
                None => {
                    interfaces.push(InterfaceStiffness {
                        node,
                        matrices: zero(),
                    });
                    interfaces.len() - 1
                }
            };
            interfaces[k].matrices[slot] = m;
        }
        let given = acc.iter().filter(|m| m.is_some()).count();
        let acceleration = match given {
            0 => None,
            6 => Some(acc.map(|m| m.unwrap_or_else(|| DMatrix::zeros(nf, nf)))),
            _ => {
                return Err(FfrError::DimensionMismatch {
                    what: "acceleration load patterns (all six or none)",
                    expected: 6,
                    found: given,
                })
            }
        };
        Ok(Self {
            interfaces,
            acceleration,
            inertia_relief: g.inertia_relief,
        })
    }

    /// Number of load coefficients: 6 per interface node, plus 6 accelerations.
    pub fn num_coefficients(&self) -> usize {
        6 * self.interfaces.len() + 6
    }

    /// Interface index of mesh node `node`, if it has load patterns.
    pub fn interface_of(&self, node: usize) -> Option<usize> {
        self.interfaces.iter().position(|i| i.node == node)
    }

    /// The pattern matrices in coefficient order (interfaces, then accelerations if any).
    fn matrices(&self) -> impl Iterator<Item = &DMatrix<f64>> {
        self.interfaces
            .iter()
            .flat_map(|i| i.matrices.iter())
            .chain(self.acceleration.iter().flatten())
    }

    /// `K_load(c) = Σ_p c_p K_G,p` (allocates).
    pub fn matrix(&self, c: &[f64]) -> DMatrix<f64> {
        let nf = self.interfaces.first().map_or_else(
            || self.acceleration.as_ref().map_or(0, |a| a[0].nrows()),
            |i| i.matrices[0].nrows(),
        );
        let mut k = DMatrix::zeros(nf, nf);
        for (m, ci) in self.matrices().zip(c) {
            k += *ci * m;
        }
        k
    }

    /// Adds `−K_load(c) q_f` to `out[6..]`. O(n_p n_f²), no allocation.
    pub fn add_force(&self, c: &[f64], qf: &DVector<f64>, out: &mut [f64]) {
        let nf = qf.len();
        for (m, &ci) in self.matrices().zip(c) {
            if ci == 0.0 {
                continue;
            }
            for i in 0..nf {
                let mut acc = 0.0;
                for j in 0..nf {
                    acc += m[(i, j)] * qf[j];
                }
                out[6 + i] -= ci * acc;
            }
        }
    }

    /// Power `q̇_fᵀ (−K_load(c) q_f)` of the force. No allocation.
    pub fn power(&self, c: &[f64], qf: &DVector<f64>, qfd: &[f64]) -> f64 {
        let nf = qf.len();
        let mut p = 0.0;
        for (m, &ci) in self.matrices().zip(c) {
            if ci == 0.0 {
                continue;
            }
            for i in 0..nf {
                let mut acc = 0.0;
                for j in 0..nf {
                    acc += m[(i, j)] * qf[j];
                }
                p -= ci * qfd[i] * acc;
            }
        }
        p
    }

    /// Adds `∂(−K_load(c) q_f)/∂q_f = −K_load(c)` to the modal block of `dh_dq`.
    pub fn add_tangent(&self, c: &[f64], nf: usize, mut dh_dq: MatMut<'_, f64>) {
        for (m, &ci) in self.matrices().zip(c) {
            if ci == 0.0 {
                continue;
            }
            for j in 0..nf {
                for i in 0..nf {
                    dh_dq[(6 + i, 6 + j)] -= ci * m[(i, j)];
                }
            }
        }
    }
}

impl FfrBody {
    /// The body with geometric stiffening by node loads (and accelerations, supported bodies)
    /// switched on (off by default); see [`LoadStiffening`]. Combine with
    /// [`FfrBody::with_geometric_stiffening`] for the centrifugal part (for a free-free body the
    /// relieved centrifugal patterns).
    pub fn with_load_stiffening(mut self, s: LoadStiffening) -> Result<Self, FfrError> {
        let nf = self.nf();
        if let Some(m) = s.matrices().find(|m| m.nrows() != nf || m.ncols() != nf) {
            return Err(FfrError::DimensionMismatch {
                what: "load geometric stiffness matrix",
                expected: nf,
                found: m.nrows(),
            });
        }
        for i in &s.interfaces {
            if i.node >= self.num_nodes() {
                return Err(FfrError::NodeOutOfRange {
                    node: i.node,
                    nodes: self.num_nodes(),
                });
            }
        }
        self.load_stiffening = Some(s);
        Ok(self)
    }

    /// The node-load stiffening data, if switched on.
    pub fn load_stiffening(&self) -> Option<&LoadStiffening> {
        self.load_stiffening.as_ref()
    }
}
