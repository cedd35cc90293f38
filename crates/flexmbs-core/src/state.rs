//! The mutable [`State`] of a simulation and the preallocated [`Workspace`].

use crate::element::{FrameKinematics, TangentScratch};
use crate::linsolve::DenseLu;
use crate::model::{FrameOwner, Model};
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
}

impl State {
    /// Zero state of the given dimensions.
    pub fn zeros(nq: usize, nu: usize, nc: usize) -> Self {
        Self { t: 0.0, q: vec![0.0; nq], u: vec![0.0; nu], u_dot: vec![0.0; nu], a: vec![0.0; nu], lambda: vec![0.0; nc] }
    }
}

/// Scratch buffers of every evaluation and integrator, allocated once by [`Workspace::new`];
/// nothing in a time step allocates.
#[derive(Debug)]
pub struct Workspace {
    /// Kinematics of every frame.
    pub frames: Vec<FrameKinematics>,
    /// Tangent scratch per body.
    pub tangent_scratch: Vec<TangentScratch>,
    /// Global mass matrix (nu x nu).
    pub mass: Mat<f64>,
    /// Global forces `h` incl. loads (nu).
    pub h: Vec<f64>,
    /// `dh/dq` along `q ⊕ dv` (nu x nu).
    pub dh_dq: Mat<f64>,
    /// `dh/du` (nu x nu).
    pub dh_du: Mat<f64>,
    /// Constraint values `g` (nc).
    pub g: Vec<f64>,
    /// Constraint Jacobian `G` (nc x nu), `g_dot = G u + g_t`.
    pub g_jac: Mat<f64>,
    /// Partial time derivative `g_t` (nc).
    pub g_t: Vec<f64>,
    /// Acceleration bias: `g_ddot = G u_dot + g_bias` (nc).
    pub g_bias: Vec<f64>,
    /// Iteration / augmented matrix solver (nu + nc).
    pub lu: DenseLu,
    /// Mass-matrix solver (nu) for explicit integration.
    pub lu_mass: DenseLu,
    /// Right-hand side / solution vector (nu + nc).
    pub rhs: Vec<f64>,
    /// Position scratch (nq), several.
    pub q_tmp: [Vec<f64>; 3],
    /// Velocity-space scratch (nu), several.
    pub u_tmp: [Vec<f64>; 4],
    /// Force scratch (nu), two.
    pub h_tmp: [Vec<f64>; 2],
    /// DOPRI5 stage derivatives, 7 x (nq + nu).
    pub stages: [Vec<f64>; 7],
    /// DOPRI5 stage state (nq + nu), two.
    pub y_tmp: [Vec<f64>; 2],
}

impl Workspace {
    /// Allocates all buffers for `model`.
    pub fn new(model: &Model) -> Self {
        let (nq, nu, nc) = (model.nq, model.nu, model.nc);
        let frames = model
            .frames
            .iter()
            .map(|f| match f.owner {
                FrameOwner::Ground => FrameKinematics::new(0),
                FrameOwner::Body(b) => FrameKinematics::new(model.bodies[b.0].element.nu()),
            })
            .collect();
        let tangent_scratch = model.bodies.iter().map(|b| TangentScratch::new(b.element.nq(), b.element.nu())).collect();
        let v = |n| vec![0.0; n];
        Self {
            frames,
            tangent_scratch,
            mass: Mat::zeros(nu, nu),
            h: v(nu),
            dh_dq: Mat::zeros(nu, nu),
            dh_du: Mat::zeros(nu, nu),
            g: v(nc),
            g_jac: Mat::zeros(nc, nu),
            g_t: v(nc),
            g_bias: v(nc),
            lu: DenseLu::new(nu + nc),
            lu_mass: DenseLu::new(nu),
            rhs: v(nu + nc),
            q_tmp: [v(nq), v(nq), v(nq)],
            u_tmp: [v(nu), v(nu), v(nu), v(nu)],
            h_tmp: [v(nu), v(nu)],
            stages: std::array::from_fn(|_| v(nq + nu)),
            y_tmp: [v(nq + nu), v(nq + nu)],
        }
    }
}
