//! Typed errors of NURBS construction, interpolation and search set-up.

/// Everything that can be wrong with NURBS input. Evaluation itself never fails.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NurbsError {
    /// Degree 0 (piecewise constant) is not supported; contours need at least degree 1.
    #[error("degree must be at least 1, got {degree}")]
    ZeroDegree {
        /// The degree given.
        degree: usize,
    },
    /// A knot is NaN or infinite.
    #[error("knot {index} is not finite ({value})")]
    NonFiniteKnot {
        /// Position in the knot vector.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// Knots must be non-decreasing.
    #[error("knot vector decreases at index {index}: {prev} > {next}")]
    KnotsNotNondecreasing {
        /// Index of the knot that is smaller than its predecessor.
        index: usize,
        /// The previous knot.
        prev: f64,
        /// The knot at `index`.
        next: f64,
    },
    /// The knot count must be `n_ctrl + degree + 1`.
    #[error("{got} knots given, {expected} needed for {n_ctrl} control points of degree {degree}")]
    KnotCountMismatch {
        /// Number of knots given.
        got: usize,
        /// Number of knots needed.
        expected: usize,
        /// Number of control points.
        n_ctrl: usize,
        /// Degree.
        degree: usize,
    },
    /// A knot repeats more often than the degree allows (interior: `degree`, ends: `degree + 1`).
    #[error("knot {value} has multiplicity {multiplicity}, at most {allowed} allowed there (degree {degree})")]
    KnotMultiplicity {
        /// The repeated knot value.
        value: f64,
        /// How often it occurs.
        multiplicity: usize,
        /// The allowed multiplicity at that place.
        allowed: usize,
        /// Degree.
        degree: usize,
    },
    /// The parameter domain `[U_p, U_n]` is empty.
    #[error("empty parameter domain [{lo}, {hi}]")]
    EmptyDomain {
        /// Start of the domain.
        lo: f64,
        /// End of the domain.
        hi: f64,
    },
    /// Fewer points or control points than the degree needs (`degree + 1`).
    #[error("{got} points given, at least {needed} needed for degree {degree}")]
    TooFewPoints {
        /// Number given.
        got: usize,
        /// Number needed.
        needed: usize,
        /// Degree.
        degree: usize,
    },
    /// Weights must be positive and finite.
    #[error("weight {index} is {weight}, weights must be positive and finite")]
    NonPositiveWeight {
        /// Control point index.
        index: usize,
        /// The weight given.
        weight: f64,
    },
    /// A coordinate is NaN or infinite.
    #[error("{what} {index} is not finite")]
    NonFiniteValue {
        /// Which input (control point, point, parameter).
        what: &'static str,
        /// Its index.
        index: usize,
    },
    /// Two arrays that must match in size do not.
    #[error("{what}: expected {expected} entries, got {got}")]
    SizeMismatch {
        /// Which input.
        what: &'static str,
        /// Size needed.
        expected: usize,
        /// Size given.
        got: usize,
    },
    /// Interpolation or grid parameters must increase strictly (closed: within one period).
    #[error(
        "parameters must increase strictly (closed: lie in [0, 1)); violated at index {index}"
    )]
    ParametersNotIncreasing {
        /// Index of the first offending parameter.
        index: usize,
    },
    /// Two consecutive interpolation points coincide, so chord-length parameters are undefined.
    #[error("interpolation points {index} and {next} coincide")]
    CoincidentPoints {
        /// First point.
        index: usize,
        /// The next point (closed: may wrap to 0).
        next: usize,
    },
    /// The interpolation matrix is singular (parameters and knots violate Schoenberg-Whitney).
    #[error("interpolation matrix singular at pivot {pivot}")]
    SingularInterpolation {
        /// Elimination step at which no usable pivot was found.
        pivot: usize,
    },
    /// A periodic curve/surface needs periodic knot spacing and wrapped control points.
    #[error("not periodic: {reason} (index {index})")]
    NotPeriodic {
        /// What failed.
        reason: &'static str,
        /// First offending index.
        index: usize,
    },
    /// A search grid needs at least two nodes (open) or one interval (closed) inside the domain.
    #[error("search grid: {reason}")]
    InvalidGrid {
        /// What failed.
        reason: &'static str,
    },
}
