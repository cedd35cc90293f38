//! The mutable [`State`] of a simulation and the preallocated [`Workspace`].

use crate::algebra::{BlockMass, LinearSolver, SystemMatrix};
use crate::element::{ElementScratch, FrameKinematics, TangentScratch};
use crate::model::Model;
use faer::Mat;

/// Everything that evolves in time. Separate from the immutable [`Model`].
#[derive(Debug, Clone, PartialEq)]
pub struct State {
    /// Time.
    pub t: f64,
    /// Position coordinates (nq).
    pub q: Vec<f64>,
    /// Velocity coordinates (nu).
    pub u: Vec<f64>,
    /// Accelerations `u_dot` (nu) of the last step (consistent initial values from
    /// [`crate::integrator::consistent_accelerations`]).
    pub u_dot: Vec<f64>,
    /// Algorithmic accelerations `a` of the generalized-alpha scheme (nu).
    pub a: Vec<f64>,
    /// Lagrange multipliers (nc), one per constraint row.
    pub lambda: Vec<f64>,
    /// State of each contact of the model ([`crate::contact::ContactState`]; empty from
    /// [`State::zeros`], sized by [`crate::Model::initial_state`]).
    pub contacts: Vec<crate::contact::ContactState>,
}

impl State {
    /// Zero state of the given dimensions.
    pub fn zeros(nq: usize, nu: usize, nc: usize) -> Self {
        Self {
            t: 0.0,
            q: vec![0.0; nq],
            u: vec![0.0; nu],
            u_dot: vec![0.0; nu],
            a: vec![0.0; nu],
            lambda: vec![0.0; nc],
            contacts: Vec::new(),
        }
    }
}

/// Element-local results of one body, accumulated into the global ones when bodies share nodes
/// (their blocks overlap) or scatter-added when its coordinates are scattered; empty otherwise.
#[derive(Debug)]
pub struct ElementBuffers {
    /// Local forces / mass-vector product (nu of the element).
    pub h: Vec<f64>,
    /// Local mass matrix (nu x nu).
    pub mass: Mat<f64>,
    /// Local `dh/dq` (nu x nu).
    pub dh_dq: Mat<f64>,
    /// Local `dh/du` (nu x nu).
    pub dh_du: Mat<f64>,
}

impl ElementBuffers {
    /// Buffers for an element with `nu` velocity coordinates.
    pub fn new(nu: usize) -> Self {
        Self {
            h: vec![0.0; nu],
            mass: Mat::zeros(nu, nu),
            dh_dq: Mat::zeros(nu, nu),
            dh_du: Mat::zeros(nu, nu),
        }
    }
}

/// Buffers of the system-level evaluations ([`crate::system`]).
#[derive(Debug)]
pub struct SystemBuffers {
    /// Evaluated state of every body's element at the last evaluated state
    /// ([`crate::system::evaluate`]), in body order.
    pub eval: Vec<ElementScratch>,
    /// Per body, the element evaluated at perturbed states by the local load and
    /// constraint-force tangents (kinematics only), so that `eval` stays at the iterate.
    pub probe: Vec<ElementScratch>,
    /// Kinematics of every frame.
    pub frames: Vec<FrameKinematics>,
    /// One element's analytic load tangent (largest element nu, square;
    /// [`crate::Element::force_load_tangent`]).
    pub load_block: Mat<f64>,
    /// Tangent scratch per body.
    pub tangent_scratch: Vec<TangentScratch>,
    /// Element-local results per body, only for models whose bodies share nodes or whose
    /// coordinates are scattered.
    pub local: Vec<ElementBuffers>,
    /// Global mass matrix (nu x nu; 0 x 0 with the sparse backend, which keeps element blocks).
    pub mass: Mat<f64>,
    /// Global forces `h` incl. loads (nu).
    pub h: Vec<f64>,
    /// `dh/dq` along `q ⊕ dv` (nu x nu; 0 x 0 with the sparse backend).
    pub dh_dq: Mat<f64>,
    /// `dh/du` (nu x nu; 0 x 0 with the sparse backend).
    pub dh_du: Mat<f64>,
    /// Constraint values `g` (nc).
    pub g: Vec<f64>,
    /// Constraint Jacobian `G` (nc x nu), `g_dot = G u + g_t`.
    pub g_jac: Mat<f64>,
    /// Partial time derivative `g_t` (nc).
    pub g_t: Vec<f64>,
    /// Acceleration bias: `g_ddot = G u_dot + g_bias` (nc).
    pub g_bias: Vec<f64>,
    /// Perturbed positions for finite differences (nq).
    pub q_pert: Vec<f64>,
    /// Perturbed velocities for finite differences (nu).
    pub u_pert: Vec<f64>,
    /// Velocity-space perturbation (nu).
    pub dv_pert: Vec<f64>,
    /// Load forces at the plus perturbation (nu).
    pub h_plus: Vec<f64>,
    /// Load forces at the minus perturbation (nu).
    pub h_minus: Vec<f64>,
    /// Evaluation buffers of the guides ([`crate::contact::guide`]), in model order.
    pub guides: Vec<crate::contact::guide::GuideWork>,
}

/// Buffers of the integrators.
#[derive(Debug)]
pub struct StepBuffers {
    /// New positions (nq).
    pub q_new: Vec<f64>,
    /// New velocities (nu).
    pub u_new: Vec<f64>,
    /// New accelerations (nu).
    pub u_dot_new: Vec<f64>,
    /// New algorithmic accelerations (nu).
    pub a_new: Vec<f64>,
    /// Velocity-space position increment (nu).
    pub dv: Vec<f64>,
    /// New Lagrange multipliers (nc).
    pub lambda_new: Vec<f64>,
    /// Right-hand side / solution of the linear systems (nu + nc).
    pub rhs: Vec<f64>,
    /// DOPRI5 stage derivatives, 7 x (nq + nu).
    pub stages: [Vec<f64>; 7],
    /// DOPRI5 stage state and candidate solution (nq + nu each).
    pub y: [Vec<f64>; 2],
}

/// Scratch buffers of every evaluation and integrator, allocated once by [`Workspace::new`]
/// right after compiling the model; nothing in a time step allocates.
#[derive(Debug)]
pub struct Workspace {
    /// System evaluation buffers.
    pub sys: SystemBuffers,
    /// Integrator buffers.
    pub step: StepBuffers,
    /// Saddle matrix (nu + nc) of consistent accelerations, full Newton and statics.
    pub saddle: SystemMatrix,
    /// Factorized iteration matrix kept between steps by modified Newton (nu + nc).
    pub newton_matrix: SystemMatrix,
    /// Block-Cholesky factors of the mass matrix alone (explicit integration).
    pub mass_blocks: BlockMass,
    /// Step size `newton_matrix` was built for (NaN: no valid factorization).
    pub newton_matrix_h: f64,
    /// Solves done with the current `lu_newton` (modified Newton), counted across steps: the
    /// matrix is rebuilt after [`crate::integrator::MODIFIED_NEWTON_MAX_REUSE`].
    pub newton_matrix_solves: usize,
    /// Length per velocity coordinate for the adaptive error estimate
    /// ([`crate::Element::velocity_scales`]), filled at the start of an adaptive run (nu).
    pub error_scales: Vec<f64>,
    /// Evaluation buffers of the contacts' contours (flexible contours: deformed contour,
    /// search warm start, contact-point Jacobian).
    pub contact: crate::contact::ContactWork,
}

impl Workspace {
    /// Allocates all buffers for `model` with the automatic choice of the linear-solver
    /// backend ([`LinearSolver::Auto`]).
    pub fn new(model: &Model) -> Self {
        Self::with_linear_solver(model, LinearSolver::Auto)
    }

    /// Allocates all buffers for `model` with the given linear-solver backend. The sparse
    /// backend allocates no dense `nu x nu` matrix.
    pub fn with_linear_solver(model: &Model, choice: LinearSolver) -> Self {
        let (nq, nu, nc) = (model.nq, model.nu, model.nc);
        let saddle = SystemMatrix::new(model, choice);
        let nd = if saddle.is_sparse() { 0 } else { nu };
        let frames = model.frame_buffers();
        let tangent_scratch = model
            .bodies
            .iter()
            .map(|b| TangentScratch::new(b.element.as_ref()))
            .collect();
        let scratches = || {
            model
                .bodies
                .iter()
                .map(|b| {
                    let mut e = b.element.new_scratch();
                    if b.is_scattered() {
                        e.reserve_local(b.element.nq(), b.element.nu());
                    }
                    e
                })
                .collect()
        };
        let v = |n| vec![0.0; n];
        Self {
            sys: SystemBuffers {
                eval: scratches(),
                probe: scratches(),
                load_block: {
                    let n = model.bodies.iter().map(|b| b.element.nu()).max();
                    Mat::zeros(n.unwrap_or(0), n.unwrap_or(0))
                },
                frames,
                tangent_scratch,
                local: if model.general_layout() {
                    model
                        .bodies
                        .iter()
                        .map(|b| ElementBuffers::new(b.element.nu()))
                        .collect()
                } else {
                    Vec::new()
                },
                mass: Mat::zeros(nd, nd),
                h: v(nu),
                dh_dq: Mat::zeros(nd, nd),
                dh_du: Mat::zeros(nd, nd),
                g: v(nc),
                g_jac: Mat::zeros(nc, nu),
                g_t: v(nc),
                g_bias: v(nc),
                q_pert: v(nq),
                u_pert: v(nu),
                dv_pert: v(nu),
                h_plus: v(nu),
                h_minus: v(nu),
                guides: crate::contact::guide::new_works(model),
            },
            step: StepBuffers {
                q_new: v(nq),
                u_new: v(nu),
                u_dot_new: v(nu),
                a_new: v(nu),
                dv: v(nu),
                lambda_new: v(nc),
                rhs: v(nu + nc),
                stages: std::array::from_fn(|_| v(nq + nu)),
                y: [v(nq + nu), v(nq + nu)],
            },
            newton_matrix: SystemMatrix::new(model, choice),
            saddle,
            mass_blocks: BlockMass::new(model),
            newton_matrix_h: f64::NAN,
            newton_matrix_solves: 0,
            contact: crate::contact::ContactWork::new(model),
            error_scales: vec![1.0; nu],
        }
    }
}
