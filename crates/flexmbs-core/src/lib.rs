//! The flexmbs multibody engine.
//!
//! Architecture (see `docs/engine.md`): an editable [`ModelSpec`] compiles into an immutable
//! [`Model`]; the evolving [`State`] and the preallocated [`Workspace`] are separate. Every
//! body type implements the one [`Element`] contract; joints, loads and springs attach to
//! [`model::Frame`]s. Integrators: generalized-alpha for index-3 constrained systems
//! ([`integrator::GenAlpha`]), explicit DOPRI5 ([`integrator::Dopri5`]) and static equilibrium
//! ([`integrator::Statics`]).
#![warn(missing_docs)]

pub mod element;
pub mod error;
pub mod ffr;
pub mod ids;
pub mod integrator;
pub mod joint;
pub mod linsolve;
pub mod load;
pub mod model;
pub mod rigid;
pub mod rotation;
pub mod state;
pub mod system;
pub mod time_function;

pub use element::{Element, FrameKinematics, LocalFrame, TangentScratch};
pub use error::{ModelError, SolverError};
pub use ids::{BodyId, FrameId, JointId, LoadId};
pub use joint::{Joint, PrescribedMotion};
pub use load::{Load, LoadCoordinates};
pub use model::{Model, ModelSpec};
pub use rigid::{RigidBody, RotationParam};
pub use state::{State, Workspace};
pub use time_function::TimeFunction;
