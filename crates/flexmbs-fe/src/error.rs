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
    /// More zero-energy modes than the rigid-body modes the supports allow: a mechanism
    /// ([`crate::mechanism`]).
    #[error("{found} of the {computed} lowest modes have zero energy (omega^2 below {tolerance:e} of the largest K_ii/M_ii) where a {kind} body has {expected}: the model is a mechanism, these are not elastic modes. Causes: hourglass modes of reduced-integration elements (hex20r with a single element across a section: use at least 2 divisions across or hex20), parts not connected to each other, or supports that do not stop every rigid-body motion (one fixed solid node is a pin)")]
    Mechanism {
        /// Zero-energy modes found.
        found: usize,
        /// Modes computed.
        computed: usize,
        /// Rigid-body modes expected (6 free-free, 0 supported).
        expected: usize,
        /// `free-free` or `supported`.
        kind: &'static str,
        /// [`crate::mechanism::ZERO_ENERGY_TOLERANCE`].
        tolerance: f64,
    },
    /// An allocation was estimated to exceed the memory available ([`crate::memory`]).
    #[error("{what} would need about {est}, more than the {avail} available ({from}): use a coarser mesh or fewer modes, or set {env} to override (e.g. {env}=64G)", est = crate::memory::format_bytes(*estimate), avail = crate::memory::format_bytes(*available), from = limit_source, env = crate::memory::MEMORY_LIMIT_ENV)]
    MemoryRefused {
        /// What would have been allocated.
        what: String,
        /// Estimated bytes.
        estimate: u64,
        /// Bytes available.
        available: u64,
        /// Where the available figure comes from.
        limit_source: &'static str,
    },
    /// The eigen solver did not converge.
    #[error("eigen solver did not converge: {0}")]
    EigenNotConverged(String),
}
