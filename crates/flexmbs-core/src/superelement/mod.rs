//! The superelement body in absolute interface coordinates (seed 001 ch. 3-4): a flexible body
//! whose coordinates are the absolute poses of its interface points (`Pose` nodes, shared with
//! neighbouring bodies without Lagrange multipliers) plus optionally the amplitudes of internal
//! Craig-Bampton modes (a `Vector(m)` node).
//!
//! The floating frame is not a coordinate: it is recovered at every evaluation by Newton-Raphson
//! from the condition of zero elastic deformation at its location, `[Φ_CB] q_loc = 0` (3.7), so the
//! element is a pure function of its coordinates. Local interface coordinates of interface `k`:
//! `u_k = R_jᵀ (x_k − x_j) − x_k0` and `θ_k = log(R_jᵀ R_k R_k0ᵀ)` (a rotation vector in the
//! floating-frame axes). Equations (`docs/engine.md`, "Superelements"):
//!
//! ```text
//!   M = Pᵀ M_CB P                                 (4.9); P = diag(R_jᵀ, R_jᵀ R_k, ..., I)
//!   h = −Pᵀ Tᵀ K_CB q_loc + Pᵀ M_CB G R_jᵀ g         (4.10), (4.12)
//!   K_t = −∂h/∂v                                  (4.25), (4.32), (4.37), (4.39)
//! ```
//!
//! with `T` the exact `Λ (1 − Φ_rig Z)` (deformed `[Φ_rig]` (3.14), `Z` (3.17) with `Φ_CB Λ`,
//! `Λ` the inverse left Jacobians of the rotation vectors: the exact variation of the implemented
//! measure) or the approximated `1 − Φ_rig,0 Φ_CB` (3.25).

mod beam_segment;
mod contour;
mod element;
mod eval;
pub mod rotvec;
mod tangent;
#[cfg(test)]
mod tests;

pub use beam_segment::{
    beam_segment, beam_segment_basis, beam_segment_with_interfaces, even_elements, BeamSegmentSpec,
    FrameLocation,
};
pub use contour::{beam_segment_contour_nodes, fe_contour_nodes};
pub use eval::SuperelementEval;

use crate::NodeKind;
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};
use thiserror::Error;

/// Which transformation matrices `[Φ_rig]`, `[Z]`, `[T]` the forces use (seed 001 §3.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TransformMatrices {
    /// Deformed `[Φ_rig]` (3.14), `[Z]` (3.17), `[T]` (3.18), with the exact variation of the
    /// rotation vectors: the internal forces are the gradient of `½ q_locᵀ K_CB q_loc`.
    #[default]
    Exact,
    /// Undeformed `[Φ_rig,0]` (3.20): `[Z] ≈ [Φ_CB]` (3.23), `[T] ≈ 1 − [Φ_rig,0][Φ_CB]` (3.25).
    Approximated,
}

/// How the velocity-dependent (fictitious) forces `Ĉ v` of (4.11) are treated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FictitiousForces {
    /// Neglected, as in the benchmarks of seed 001 ch. 5 (the mass matrix `Pᵀ M_CB P` acts on
    /// the accelerations alone).
    #[default]
    Neglected,
    /// The velocity terms of the Lagrange equations of the kinetic energy
    /// `T = ½ vᵀ Pᵀ M_CB P v` that the mass matrix (4.9) implies (`docs/engine.md`): with these
    /// the body conserves `T + V`; their tangent is taken by finite differences.
    FromMcb,
}

/// Bad superelement data.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SuperelementError {
    /// A matrix of the wrong size.
    #[error("{what} is {rows} x {cols}, expected {expected_rows} x {expected_cols}")]
    Dimension {
        /// Which matrix.
        what: &'static str,
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
        /// Expected rows.
        expected_rows: usize,
        /// Expected columns.
        expected_cols: usize,
    },
    /// No interface point.
    #[error("a superelement needs at least one interface point")]
    NoInterface,
    /// `[Φ_CB][Φ_rig,0]` is not invertible: the modes at the floating-frame location do not fix
    /// the rigid-body motion (it should be the identity, seed 001 §3.3).
    #[error("[Phi_CB][Phi_rig,0] is singular or far from the identity (deviation {deviation:e}): the Craig-Bampton mode values at the floating frame do not describe a rigid-body motion")]
    SingularFrameCondition {
        /// `max |[Φ_CB][Φ_rig,0] − 1|`.
        deviation: f64,
    },
    /// A non-finite or non-symmetric matrix.
    #[error("{what} is not finite and symmetric")]
    NotSymmetric {
        /// Which matrix.
        what: &'static str,
    },
}

/// One interface point of a superelement: its undeformed pose in the floating frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Interface {
    /// Undeformed position `x_k0` relative to the floating frame (its axes).
    pub position: Vector3<f64>,
    /// Undeformed orientation `R_k0` relative to the floating frame (columns = node axes).
    pub rotation: Matrix3<f64>,
}

/// Craig-Bampton data of a superelement, all in the undeformed floating frame: coordinates
/// ordered `[u_1, θ_1, ..., u_N, θ_N, η]` (6 per interface point, then `m` internal modes).
#[derive(Debug, Clone, PartialEq)]
pub struct SuperelementData {
    /// Interface points (N).
    pub interfaces: Vec<Interface>,
    /// Number of internal (fixed-interface) Craig-Bampton modes `m`.
    pub internal_modes: usize,
    /// Reduced mass `M_CB` (n x n, n = 6N + m).
    pub m_cb: DMatrix<f64>,
    /// Reduced stiffness `K_CB` (n x n).
    pub k_cb: DMatrix<f64>,
    /// `[Φ_CB]` (6 x n): displacement and rotation of the floating-frame location per mode
    /// (3.7).
    pub phi_cb: DMatrix<f64>,
    /// Centre of mass of the undeformed body in the floating frame (zero when the floating frame
    /// is at the centre of mass); used for the gravity potential.
    pub centre_of_mass: Vector3<f64>,
}

impl SuperelementData {
    /// Number of local coordinates `n = 6N + m`.
    pub fn len(&self) -> usize {
        6 * self.interfaces.len() + self.internal_modes
    }

    /// No coordinates.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `[Φ_rig,0]` (3.20): the rigid-body modes of the undeformed body (n x 6).
    pub fn rigid_modes(&self) -> DMatrix<f64> {
        let mut p = DMatrix::zeros(self.len(), 6);
        for (k, itf) in self.interfaces.iter().enumerate() {
            let s = -crate::rotation::skew(&itf.position);
            for i in 0..3 {
                p[(6 * k + i, i)] = 1.0;
                p[(6 * k + 3 + i, 3 + i)] = 1.0;
                for j in 0..3 {
                    p[(6 * k + i, 3 + j)] = s[(i, j)];
                }
            }
        }
        p
    }

    fn check(&self) -> Result<(), SuperelementError> {
        if self.interfaces.is_empty() {
            return Err(SuperelementError::NoInterface);
        }
        let n = self.len();
        for (what, m, r, c) in [
            ("M_CB", &self.m_cb, n, n),
            ("K_CB", &self.k_cb, n, n),
            ("Phi_CB", &self.phi_cb, 6, n),
        ] {
            if m.nrows() != r || m.ncols() != c {
                return Err(SuperelementError::Dimension {
                    what,
                    rows: m.nrows(),
                    cols: m.ncols(),
                    expected_rows: r,
                    expected_cols: c,
                });
            }
        }
        for (what, m) in [("M_CB", &self.m_cb), ("K_CB", &self.k_cb)] {
            let scale = m.amax();
            if !m.iter().all(|x| x.is_finite()) || (m - m.transpose()).amax() > 1e-9 * scale {
                return Err(SuperelementError::NotSymmetric { what });
            }
        }
        let b = &self.phi_cb * self.rigid_modes();
        let deviation = (&b - DMatrix::<f64>::identity(6, 6)).amax();
        if !deviation.is_finite() || deviation > 1e-6 {
            return Err(SuperelementError::SingularFrameCondition { deviation });
        }
        Ok(())
    }
}

/// A superelement body (see the module docs). Nodes: the N interface `Pose` nodes with the
/// `Vector(m)` node of internal modes (if `m > 0`) inserted after the first interface node, so
/// that a chain of two-interface bodies has consecutive nodes (`a, η, b`).
#[derive(Debug, Clone)]
pub struct Superelement {
    data: SuperelementData,
    matrices: TransformMatrices,
    fictitious: FictitiousForces,
    kinds: Vec<NodeKind>,
    /// Velocity index of local coordinate `i` (local order: interfaces, then η).
    vel_index: Vec<usize>,
    /// Position offset of each interface node's coordinates in the element's `q`.
    q_offset: Vec<usize>,
    /// Position offset of the internal modes in `q`.
    q_eta: usize,
    /// `M_CB G` (n x 3): the inertia forces of a unit rigid translation (gravity).
    m_g: DMatrix<f64>,
    /// Total mass `Gᵀ M_CB G` (trace / 3).
    mass: f64,
    /// `1 − [Φ_rig,0][Φ_CB]` (3.25), n x n.
    t0: DMatrix<f64>,
    /// A length for the frame-recovery tolerance (largest interface distance, at least 1e-3).
    length: f64,
    /// `R_k0⁻¹` as unit quaternions.
    r0_inv: Vec<nalgebra::UnitQuaternion<f64>>,
}

impl Superelement {
    /// A superelement from Craig-Bampton data, with exact matrices and neglected fictitious
    /// forces.
    pub fn new(data: SuperelementData) -> Result<Self, SuperelementError> {
        data.check()?;
        let n_itf = data.interfaces.len();
        let m = data.internal_modes;
        let mut kinds = vec![NodeKind::Pose; n_itf];
        let eta_slot = if m > 0 { Some(1.min(n_itf)) } else { None };
        if let Some(s) = eta_slot {
            kinds.insert(s, NodeKind::Vector(m));
        }
        let (mut q_offset, mut u_offset) = (Vec::new(), Vec::new());
        let (mut q_eta, mut u_eta) = (0, 0);
        let (mut qo, mut uo) = (0, 0);
        for (i, k) in kinds.iter().enumerate() {
            if Some(i) == eta_slot {
                (q_eta, u_eta) = (qo, uo);
            } else {
                q_offset.push(qo);
                u_offset.push(uo);
            }
            qo += k.nq();
            uo += k.nu();
        }
        let mut vel_index = Vec::with_capacity(data.len());
        for &uo in &u_offset {
            vel_index.extend(uo..uo + 6);
        }
        vel_index.extend(u_eta..u_eta + m);
        let phi_rig0 = data.rigid_modes();
        let m_g = &data.m_cb * phi_rig0.columns(0, 3);
        let mass = (phi_rig0.columns(0, 3).transpose() * &m_g).trace() / 3.0;
        let t0 = DMatrix::identity(data.len(), data.len()) - &phi_rig0 * &data.phi_cb;
        let length = data
            .interfaces
            .iter()
            .map(|i| i.position.norm())
            .fold(1e-3, f64::max);
        let r0_inv = data
            .interfaces
            .iter()
            .map(|i| crate::node::quaternion_of(&i.rotation).inverse())
            .collect();
        Ok(Self {
            r0_inv,
            data,
            matrices: TransformMatrices::default(),
            fictitious: FictitiousForces::default(),
            kinds,
            vel_index,
            q_offset,
            q_eta,
            m_g,
            mass,
            t0,
            length,
        })
    }

    /// Selects exact or approximated transformation matrices.
    pub fn with_matrices(mut self, matrices: TransformMatrices) -> Self {
        self.matrices = matrices;
        self
    }

    /// Selects the treatment of the fictitious forces.
    pub fn with_fictitious_forces(mut self, fictitious: FictitiousForces) -> Self {
        self.fictitious = fictitious;
        self
    }

    /// The Craig-Bampton data.
    pub fn data(&self) -> &SuperelementData {
        &self.data
    }

    /// Total mass of the body.
    pub fn mass(&self) -> f64 {
        self.mass
    }

    /// Number of local coordinates `n`.
    fn n(&self) -> usize {
        self.data.len()
    }

    /// Number of interface points.
    fn n_interfaces(&self) -> usize {
        self.data.interfaces.len()
    }

    /// Undeformed pose `(x_k0, R_k0)` of interface `k` in the floating frame.
    fn interface_reference(&self, k: usize) -> (&Vector3<f64>, &Matrix3<f64>) {
        let itf = &self.data.interfaces[k];
        (&itf.position, &itf.rotation)
    }
}

/// `B⁻¹` of a 6 x 6 matrix, `None` if singular.
fn invert6(b: &Matrix6<f64>) -> Option<Matrix6<f64>> {
    b.try_inverse()
}

/// `c = a b` (`transpose_a`: `c = aᵀ b`) by plain loops: nalgebra's `gemm` allocates packing
/// buffers, and these products run inside time steps (sizes of a few dozen).
fn product_into(c: &mut DMatrix<f64>, a: &DMatrix<f64>, b: &DMatrix<f64>, transpose_a: bool) {
    let (rows, inner) = if transpose_a {
        (a.ncols(), a.nrows())
    } else {
        (a.nrows(), a.ncols())
    };
    debug_assert_eq!((c.nrows(), c.ncols(), inner), (rows, b.ncols(), b.nrows()));
    for j in 0..b.ncols() {
        for i in 0..rows {
            let mut s = 0.0;
            for k in 0..inner {
                let aik = if transpose_a { a[(k, i)] } else { a[(i, k)] };
                s += aik * b[(k, j)];
            }
            c[(i, j)] = s;
        }
    }
}
