//! Floating frame of reference (FFR) body: inertia shape integrals, mass matrix, quadratic velocity vector, Jacobians (seed 000 ch. 2.4).
//!
//! A self-contained, allocation-free-at-runtime library of FFR mathematics:
//! - [`FfrInvariants`]: the constant inertia shape integrals (lumped or consistent mass);
//! - [`FfrBody`]: mass matrix `M(q)`, quadratic velocity vector `Q_v(q, u)`, stiffness,
//!   damping, node kinematics and Jacobians, generalized forces, accelerations;
//! - [`FfrScratch`]: the per-body work buffers, created once.
//!
//! Coordinates: `q = [R (3), rotation (3 Cardan angles or 4 quaternion components), q_f (n_f)]`,
//! velocities `u = [R_dot (3), w (3), q_f_dot (n_f)]` with `w = theta_dot` (Cardan, seed 000
//! (2.26)) or `w = omega_bar` (quaternion, body-frame angular velocity). See
//! `docs/notation-ffr.md` for the derivation and the corrected quadratic velocity vector (2.79).

mod body;
mod consistent;
pub mod contour;
mod element;
mod invariants;
mod kinematics;
mod load_stiffening;
mod load_tangent;
mod mass_product;
mod moments;
mod rotary;
mod si;
mod stiffening;
mod tangent;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_consistent;
#[cfg(test)]
mod tests_dynamics;
#[cfg(test)]
mod tests_load_stiffening;
#[cfg(test)]
mod tests_stiffening;
#[cfg(test)]
mod tests_tangent;

pub use body::{FfrBody, FfrScratch, RigidProperties, RotationParam};
pub use consistent::{consistent_mass_to_si, gram_to_si, restrict_gram};
pub use element::{FfrElement, FfrEval};
pub use invariants::{FfrInvariants, ISOTROPY_TOLERANCE};
pub use kinematics::NodeKinematics;
pub use load_stiffening::{InterfaceStiffness, LoadStiffening};
pub use rotary::{diagonal_inertia, RotaryInertia};
pub use si::reduced_body_to_si;
pub use stiffening::GeometricStiffening;
pub use tangent::{FfrTangentScratch, ROTATION_FD_STEP};

use crate::rotation::RotationError;
use thiserror::Error;

/// Errors of the FFR body computations.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FfrError {
    /// An input array has the wrong size.
    #[error("dimension mismatch in {what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// What was checked.
        what: &'static str,
        /// Expected size.
        expected: usize,
        /// Actual size.
        found: usize,
    },
    /// A node mass is negative or not finite, or the total mass is not positive
    /// (`node == usize::MAX`).
    #[error("invalid mass {mass} at node {node} (usize::MAX = total mass)")]
    InvalidMass {
        /// Node index.
        node: usize,
        /// The mass.
        mass: f64,
    },
    /// The reduced body carries no lumped node masses.
    #[error(
        "reduced body '{name}' has no lumped node masses (its FE mass is consistent): its \
         inertia must come from the consistent mass"
    )]
    MissingNodeMasses {
        /// Body name.
        name: String,
    },
    /// A non-finite number in the input.
    #[error("non-finite value in {what}")]
    NonFinite {
        /// Where.
        what: &'static str,
    },
    /// The consistent mass matrix has node blocks that are not `m_ij I_3`.
    #[error(
        "consistent mass matrix is not block-isotropic at ({row}, {col}): deviation {deviation:e}"
    )]
    NonIsotropicMass {
        /// Row (3 x node + direction).
        row: usize,
        /// Column.
        col: usize,
        /// Absolute deviation from isotropy.
        deviation: f64,
    },
    /// A node index is out of range.
    #[error("node {node} out of range (body has {nodes} nodes)")]
    NodeOutOfRange {
        /// Requested node.
        node: usize,
        /// Number of nodes.
        nodes: usize,
    },
    /// The mass matrix is not positive definite (Cholesky pivot).
    #[error("mass matrix not positive definite: pivot {pivot} = {value:e}")]
    NotPositiveDefinite {
        /// Pivot index.
        pivot: usize,
        /// Pivot value.
        value: f64,
    },
    /// Modal damping ratios need diagonal reduced mass and stiffness matrices.
    #[error("modal damping needs diagonal m_ff and k_ff: off-diagonal ({row}, {col}) relative size {relative:e}")]
    NotDiagonal {
        /// Row.
        row: usize,
        /// Column.
        col: usize,
        /// |off-diagonal| / sqrt(diag_i diag_j).
        relative: f64,
    },
    /// A geometric-stiffness load pattern the engine cannot use here (centrifugal patterns in
    /// [`GeometricStiffening`]; node loads, and accelerations of a supported body, in
    /// [`LoadStiffening`]).
    #[error("unsupported geometric stiffness load pattern {pattern} here (centrifugal patterns: geometric stiffening; node loads and accelerations of a supported body: load stiffening)")]
    UnsupportedLoadPattern {
        /// The pattern (debug form).
        pattern: String,
    },
    /// Rotation parametrization error (Cardan singularity, zero quaternion).
    #[error(transparent)]
    Rotation(#[from] RotationError),
}

impl From<FfrError> for crate::element::ElementError {
    fn from(e: FfrError) -> Self {
        match e {
            FfrError::Rotation(r) => Self::Rotation(r),
            FfrError::DimensionMismatch {
                what,
                expected,
                found,
            } => Self::Dimension {
                what,
                expected,
                found,
            },
            other => Self::Other {
                reason: other.to_string(),
            },
        }
    }
}
