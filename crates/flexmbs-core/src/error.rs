//! Error types of the engine: model building ([`ModelError`]) and time integration / statics
//! ([`SolverError`]).

use crate::element::ElementError;
use crate::ids::{BodyId, FrameId, JointId, LoadId};
use thiserror::Error;

/// An invalid model specification, detected by [`crate::ModelSpec::compile`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// A frame refers to a body that does not exist.
    #[error("frame `{frame}` refers to unknown body {body}")]
    UnknownBody {
        /// Frame name.
        frame: String,
        /// The missing body.
        body: BodyId,
    },
    /// A joint or load refers to a frame that does not exist.
    #[error("{item} refers to unknown frame {frame}")]
    UnknownFrame {
        /// Description of the referring item.
        item: String,
        /// The missing frame.
        frame: FrameId,
    },
    /// A joint or spring connects a frame to a frame of the same owner (or ground to ground).
    #[error("joint/spring `{item}` connects two frames of the same owner")]
    SameOwner {
        /// Name of the joint or spring.
        item: String,
    },
    /// Prescribed motion on a DOF the joint mask locks.
    #[error("joint {joint} prescribes motion on a locked DOF ({dof})")]
    PrescribedOnLockedDof {
        /// The joint.
        joint: JointId,
        /// Which DOF (`rz` or `tx`).
        dof: &'static str,
    },
    /// A numeric parameter outside its admissible range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Given value.
        value: f64,
        /// What is expected.
        reason: &'static str,
    },
    /// A piecewise-linear time table that is empty, of unequal lengths or not strictly increasing.
    #[error("invalid time table in load {load:?}: {reason}")]
    InvalidTimeTable {
        /// The load (None: a joint's prescribed motion).
        load: Option<LoadId>,
        /// What is wrong.
        reason: &'static str,
    },
    /// A local frame refers to an FE node the element does not have.
    #[error("frame `{frame}` refers to node {node} but the element has {num_nodes} nodes")]
    InvalidNode {
        /// Frame name.
        frame: String,
        /// Node index.
        node: usize,
        /// Number of nodes of the element.
        num_nodes: usize,
    },
    /// A body's parameters are not physical (e.g. mass <= 0, inertia not positive definite).
    #[error("body `{body}`: {reason}")]
    InvalidBody {
        /// Body name.
        body: String,
        /// What is wrong.
        reason: String,
    },
    /// A contact with an unsupported contour pair, bad contour or law parameters, or both
    /// contours on one owner.
    #[error("contact `{contact}`: {reason}")]
    InvalidContact {
        /// Contact name.
        contact: String,
        /// What is wrong.
        reason: String,
    },
    /// A force element ([`crate::force::ForceElement`]) with bad parameters or frames.
    #[error("force element `{element}`: {reason}")]
    InvalidForceElement {
        /// Its name.
        element: String,
        /// What is wrong.
        reason: String,
    },
    /// A state vector of the wrong length was given.
    #[error("{what} has length {got}, expected {expected}")]
    DimensionMismatch {
        /// Which vector.
        what: &'static str,
        /// Given length.
        got: usize,
        /// Expected length.
        expected: usize,
    },
    /// Initial elastic coordinates for a body without a `Vector` node, or of the wrong length.
    #[error("initial elastic coordinates of body `{body}`: {reason}")]
    InitialElastic {
        /// Body name.
        body: String,
        /// What is wrong.
        reason: String,
    },
}

/// A body whose element cannot be evaluated at a state ([`crate::system::evaluate`]); the
/// integrators turn it into [`SolverError::Element`] with the time and step.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("body `{body}`: {cause}")]
pub struct EvaluationError {
    /// Body name.
    pub body: String,
    /// Why its element cannot be evaluated.
    pub cause: ElementError,
}

impl EvaluationError {
    /// The solver error of a step from `t` of size `h` (load factor and increment for statics).
    pub fn at(self, t: f64, h: f64) -> SolverError {
        SolverError::Element {
            body: self.body,
            t,
            h,
            cause: Box::new(self.cause),
        }
    }
}

/// A failed time step or static solution.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolverError {
    /// Newton iterations did not converge.
    #[error(
        "Newton failed at t = {t} (step {h}): residual {residual:e} after {iterations} iterations"
    )]
    NewtonFailed {
        /// Time at the start of the step (or load factor for statics).
        t: f64,
        /// Step size (or load increment).
        h: f64,
        /// Last residual norm.
        residual: f64,
        /// Iterations done.
        iterations: usize,
    },
    /// A NaN or infinity appeared in the state, forces or residual.
    #[error("non-finite {what} at t = {t} (step {h}), residual {residual:e}")]
    NonFinite {
        /// What was non-finite.
        what: &'static str,
        /// Time at the start of the step.
        t: f64,
        /// Step size.
        h: f64,
        /// Last finite residual norm (NaN if none).
        residual: f64,
    },
    /// A body's element cannot be evaluated at a state of the step (singular Cardan angles, a
    /// degenerate quaternion, a failed internal solve).
    #[error("body `{body}` cannot be evaluated at t = {t} (step {h}): {cause}")]
    Element {
        /// Body name.
        body: String,
        /// Time at the start of the step (or load factor for statics).
        t: f64,
        /// Step size (or load increment).
        h: f64,
        /// The element's reason.
        cause: Box<ElementError>,
    },
    /// The iteration (or mass) matrix is singular.
    #[error("singular {what} matrix at t = {t} (step {h})")]
    Singular {
        /// Which matrix.
        what: &'static str,
        /// Time.
        t: f64,
        /// Step size.
        h: f64,
    },
    /// The adaptive step size fell below the minimum.
    #[error("step size {h:e} below minimum {h_min:e} at t = {t} (error estimate {error:e})")]
    StepTooSmall {
        /// Time.
        t: f64,
        /// Rejected step size.
        h: f64,
        /// Minimum step size.
        h_min: f64,
        /// Last error estimate (scaled, 1 = tolerance).
        error: f64,
    },
    /// The initial state violates a joint: its frames do not coincide in a locked direction, or
    /// the velocities do not respect it ([`crate::system::check_assembly`]).
    #[error("joint `{joint}` is not assembled in the initial state: {level} row {row} is off by {violation:.3e} (tolerance {tolerance:e})")]
    NotAssembled {
        /// Joint name.
        joint: String,
        /// Row name (`tx` ... `rz`, `motion`).
        row: &'static str,
        /// `position` (`g`, in m or rad) or `velocity` (`G u + g_t`, in m/s or rad/s).
        level: &'static str,
        /// The violation.
        violation: f64,
        /// The tolerance it exceeds.
        tolerance: f64,
    },
    /// A state vector does not fit the model.
    #[error("state vector {what} has length {got}, the model needs {expected}")]
    StateSize {
        /// Which vector.
        what: &'static str,
        /// Given length.
        got: usize,
        /// Expected length.
        expected: usize,
    },
    /// The integrator does not handle constraints (DOPRI5 with joints).
    #[error(
        "integrator `{integrator}` does not support constraints (model has {nc} constraint rows)"
    )]
    ConstraintsUnsupported {
        /// Integrator name.
        integrator: &'static str,
        /// Number of constraint rows.
        nc: usize,
    },
    /// The velocity-level contact problem of a time step (prox iteration) did not converge.
    #[error("contact problem not solved at t = {t} (step {h}): impulse change {residual:e} after {iterations} iterations")]
    ContactSolve {
        /// Time at the start of the step.
        t: f64,
        /// Step size.
        h: f64,
        /// Last change of the impulses (relative to their scale).
        residual: f64,
        /// Iterations done.
        iterations: usize,
    },
    /// An invalid integrator or solver setting.
    #[error("invalid setting `{name}` = {value}: {reason}")]
    InvalidSetting {
        /// Setting name.
        name: &'static str,
        /// Given value.
        value: f64,
        /// What is expected.
        reason: &'static str,
    },
}
