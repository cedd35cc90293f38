//! The flexmbs multibody engine.
//!
//! Architecture (see `docs/engine.md`): an editable [`ModelSpec`] compiles into an immutable
//! [`Model`]; the evolving [`State`] and the preallocated [`Workspace`] are separate. Every
//! body type implements the one [`Element`] contract; joints, loads and springs attach to
//! [`model::Frame`]s. Integrators: generalized-alpha for index-3 constrained systems
//! ([`integrator::GenAlpha`]), explicit DOPRI5 ([`integrator::Dopri5`]) and static equilibrium
//! ([`integrator::Statics`]).
//!
//! # Quick start: a physical pendulum
//! A 1 kg rod, centre of mass 0.5 m below a revolute joint (axis z), released at 0.1 rad; its
//! small-amplitude period is `2 pi sqrt(I_hinge / (m g l))`. For a flexible body use
//! [`ffr::FfrElement`] built from a reduced FE body (`crates/flexmbs-core/examples/
//! flexible_pendulum.rs`).
//! ```
//! use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
//! use flexmbs_core::{Joint, ModelSpec, RigidBody};
//! use nalgebra::{Matrix3, Rotation3, Vector3};
//!
//! let (m, l, i_c) = (1.0, 0.5, 1.0 / 12.0);
//! let mut spec = ModelSpec::new();
//! spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
//! let rod = spec.add_body("rod", RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(i_c, 1e-4, i_c))));
//! let hinge = spec.add_ground_frame("hinge", Vector3::zeros(), Matrix3::identity());
//! let top = spec.add_frame("top", rod, Vector3::new(0.0, l, 0.0), Matrix3::identity());
//! spec.add_joint(Joint::revolute("pin", hinge, top));
//! let model = spec.compile()?;
//!
//! // initial state: rotated by 0.1 rad about the hinge, at rest (assembled: the frames coincide)
//! let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), 0.1);
//! let mut state = model.initial_state();
//! model.set_body_pose(&mut state, rod, rot * Vector3::new(0.0, -l, 0.0), rot.into_inner());
//! let mut ws = flexmbs_core::Workspace::new(&model);
//! let ga = GenAlpha::new(GenAlphaSettings::default())?;
//! ga.initialize(&model, &mut state, &mut ws)?;
//! let mut crossings = Vec::new(); // upward zero crossings of the centre of mass x
//! let (mut t_last, mut x_last) = (0.0, 1.0);
//! ga.integrate(&model, &mut state, &mut ws, 1e-3, 3.0, |s, _| {
//!     let x = model.body_q(rod, &s.q)[0]; // q = [R, Cardan angles]
//!     if x_last < 0.0 && x >= 0.0 {
//!         crossings.push(t_last + (s.t - t_last) * x_last / (x_last - x));
//!     }
//!     (t_last, x_last) = (s.t, x);
//! })?;
//! let period = crossings[1] - crossings[0];
//! // small-angle period with the finite-amplitude correction 1 + theta0^2 / 16
//! let exact = 2.0 * std::f64::consts::PI * ((i_c + m * l * l) / (m * 9.81 * l)).sqrt()
//!     * (1.0 + 0.1_f64.powi(2) / 16.0);
//! assert!((period - exact).abs() < 1e-4 * exact, "{period} vs {exact}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod algebra;
pub mod contact;
pub mod contour_source;
pub mod element;
pub mod error;
pub mod ffr;
pub mod force;
mod gather;
pub mod ids;
pub mod integrator;
pub mod joint;
pub mod linsolve;
pub mod load;
pub mod model;
pub mod node;
pub mod point_mass;
pub mod power;
pub mod rigid;
pub mod rotation;
mod spec_initial;
pub mod state;
pub mod superelement;
pub mod system;
pub mod time_function;
pub mod user_function;

pub use element::{
    Element, ElementError, ElementScratch, FrameKinematics, LocalFrame, TangentScratch,
};
pub use error::{EvaluationError, ModelError, SolverError};
pub use ids::{BodyId, FrameId, JointId, LoadId, NodeId};
pub use joint::{Joint, PrescribedMotion};
pub use load::{Load, LoadCoordinates};
pub use model::{BodyDofs, Model, ModelSpec};
pub use node::{DofMap, NodeKind};
pub use rigid::{RigidBody, RotationParam};
pub use state::{State, Workspace};
pub use time_function::{Discontinuity, MotionLaw, TimeFunction};
