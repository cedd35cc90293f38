//! Error type of the FE front end.

use thiserror::Error;

/// Errors of meshing, element computation, assembly, eigen solution and reduction.
#[derive(Debug, Error)]
pub enum FeError {
    /// An element has a non-positive or inverted Jacobian at an integration point.
    #[error("element {element}: Jacobian determinant {det:e} <= 0 at integration point {point} (inverted or degenerate element)")]
    BadJacobian {
        /// Element index (0-based).
        element: usize,
        /// Integration point index.
        point: usize,
        /// Determinant found.
        det: f64,
    },
    /// Invalid input data (dimensions, parameters).
    #[error("invalid input: {0}")]
    Invalid(String),
    /// A named node set does not exist.
    #[error("node set '{0}' not found")]
    MissingNodeSet(String),
    /// A matrix that must be positive definite is not (e.g. an unconstrained K in a constrained analysis).
    #[error("{what} is not positive definite (factorization failed){hint}")]
    NotPositiveDefinite {
        /// Which matrix.
        what: String,
        /// Hint for the user.
        hint: String,
    },
    /// The eigen solver did not converge.
    #[error("eigen solver did not converge: {0}")]
    EigenNotConverged(String),
}
