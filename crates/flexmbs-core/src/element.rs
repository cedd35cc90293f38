//! The element contract: one trait every body type implements (rigid body, FFR body,
//! superelement).
//!
//! An element owns `nq` position coordinates `q` and `nu` velocity coordinates `u` with the
//! kinematic relation `q_dot = T(q) u`. Its equations of motion are
//!
//! ```text
//!     M(q) u_dot = h(t, q, u) + sum_frames (J_T^T F + J_R^T M_ext) - G^T lambda
//! ```
//!
//! (seed 000 eq. (2.73) with `h = -Q_v - K q - D u + Q_gravity`). Everything outside the
//! element (joints, loads, springs) sees it only through the kinematics of its frames
//! ([`Element::frame_kinematics`]).
//!
//! The evaluation stage: [`Element::update`] evaluates the element once at `(q, u)` into its
//! [`ElementScratch`] (which lives in the [`crate::Workspace`], not in the element: the model stays
//! immutable), and the queries (mass matrix, forces, tangents, frame kinematics, energies) read
//! that evaluated state. A query is valid only for the `(q, u)` of the last `update` of the
//! scratch it is given (the arguments `q`, `u` must be those). A state the element cannot
//! evaluate (singular Cardan angles, a degenerate quaternion, a failed internal solve) is an
//! [`ElementError`].
//!
//! Velocity-space perturbations: a position change is always described by a velocity-space
//! increment `dv` (length `nu`) applied with [`Element::integrate_position`], `q ⊕ dv`. For
//! vector-space coordinates (Cardan angles, modal coordinates) `q ⊕ dv = q + T(q) dv`; for
//! quaternions it is the exponential map. Position tangents are taken along this map:
//! `dh_dq[:, j] = d/de h(q ⊕ e e_j)` at `e = 0` (an `nu x nu` matrix).

use crate::contour_source::NeutralContourSource;
use crate::rotation::RotationError;
use faer::{Mat, MatMut};
use nalgebra::{Matrix3, Vector3};
use std::any::Any;
use thiserror::Error;

/// Why an element cannot be evaluated at a state ([`Element::update`]).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ElementError {
    /// The rotation coordinates are singular: Cardan angles at `beta = ±90°` or a quaternion of
    /// (nearly) zero norm.
    #[error(transparent)]
    Rotation(#[from] RotationError),
    /// An iterative solve inside the element did not converge.
    #[error("{what} did not converge: residual {residual:e} after {iterations} iterations")]
    InternalSolve {
        /// What was solved.
        what: &'static str,
        /// Last residual.
        residual: f64,
        /// Iterations done.
        iterations: usize,
    },
    /// A coordinate vector or buffer of the wrong length.
    #[error("{what} has length {found}, expected {expected}")]
    Dimension {
        /// Which vector.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Given length.
        found: usize,
    },
    /// Any other reason, in words.
    #[error("{reason}")]
    Other {
        /// What went wrong.
        reason: String,
    },
}

/// The evaluated state of one element and its work buffers: what [`Element::update`] writes and
/// the queries read. Created once per element by [`Element::new_scratch`] (the
/// [`crate::Workspace`] holds one per body, plus probes for perturbed evaluations); its content
/// is private to the element type. For a body whose coordinates are scattered in the global
/// vectors it also holds the gathered element-local coordinates ([`crate::gather`]).
pub struct ElementScratch(
    Box<dyn Any + Send + Sync>,
    crate::gather::LocalCoordinates,
    Option<SourceCast>,
);

/// Recovers the [`NeutralContourSource`] view of a scratch's content.
type SourceCast = fn(&(dyn Any + Send + Sync)) -> Option<&dyn NeutralContourSource>;

fn cast_source<T: NeutralContourSource + Any>(
    a: &(dyn Any + Send + Sync),
) -> Option<&dyn NeutralContourSource> {
    a.downcast_ref::<T>()
        .map(|t| t as &dyn NeutralContourSource)
}

impl ElementScratch {
    /// Wraps an element's own state type.
    pub fn new<T: Any + Send + Sync>(state: T) -> Self {
        Self(Box::new(state), Default::default(), None)
    }

    /// Wraps an element's own state type that supplies neutral contours
    /// ([`crate::contour_source`]): [`Self::contour_source`] returns it.
    pub fn with_contour_source<T: NeutralContourSource + Any>(state: T) -> Self {
        Self(Box::new(state), Default::default(), Some(cast_source::<T>))
    }

    /// The state as a source of neutral contours, if the element type supplies one.
    pub fn contour_source(&self) -> Option<&dyn NeutralContourSource> {
        self.2.and_then(|cast| cast(self.0.as_ref()))
    }

    /// The gather buffers of a scattered body.
    pub(crate) fn local_mut(&mut self) -> &mut crate::gather::LocalCoordinates {
        &mut self.1
    }

    /// A scratch for an element that keeps no evaluated state.
    pub fn empty() -> Self {
        Self::new(())
    }

    /// The element's state. Panics if the scratch was created by an element of another type:
    /// a scratch belongs to the element that created it (the workspace keeps them in body order).
    pub fn get_mut<T: Any>(&mut self) -> &mut T {
        self.0
            .downcast_mut::<T>()
            .expect("element scratch created by another element type")
    }

    /// Read access to the element's state (see [`ElementScratch::get_mut`]).
    pub fn get<T: Any>(&self) -> &T {
        self.0
            .downcast_ref::<T>()
            .expect("element scratch created by another element type")
    }

    /// Read access if the scratch holds a `T` (`None`: another element type's scratch), for
    /// checks at compile time (e.g. a contour that needs an FFR body).
    pub fn try_get<T: Any>(&self) -> Option<&T> {
        self.0.downcast_ref::<T>()
    }
}

impl std::fmt::Debug for ElementScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("ElementScratch")
    }
}

/// A frame fixed on an element, described in the element's reference frame.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalFrame {
    /// Origin in the element reference frame (undeformed position for flexible elements).
    pub position: Vector3<f64>,
    /// Orientation relative to the element reference frame (columns = frame axes).
    pub rotation: Matrix3<f64>,
    /// FE mesh node the frame follows (flexible elements); `None` for a point fixed in the
    /// reference frame (rigid bodies).
    pub mesh_node: Option<usize>,
}

impl LocalFrame {
    /// Frame at `position` with the element's orientation.
    pub fn at(position: Vector3<f64>) -> Self {
        Self {
            position,
            rotation: Matrix3::identity(),
            mesh_node: None,
        }
    }
}

/// Kinematics of one frame in global coordinates, filled by [`Element::frame_kinematics`].
///
/// The Jacobians have `nu` columns of the owning element: `v = J_T u`, `omega = J_R u`, and the
/// accelerations are `a = J_T u_dot + bias_acc`, `alpha = J_R u_dot + bias_ang_acc`.
#[derive(Debug, Clone)]
pub struct FrameKinematics {
    /// Global position of the frame origin.
    pub position: Vector3<f64>,
    /// Global orientation (columns = frame axes in global coordinates).
    pub rotation: Matrix3<f64>,
    /// Global velocity of the origin.
    pub velocity: Vector3<f64>,
    /// Global angular velocity.
    pub angular_velocity: Vector3<f64>,
    /// Translational Jacobian `J_T` (3 x nu).
    pub jac_t: Mat<f64>,
    /// Rotational Jacobian `J_R` (3 x nu).
    pub jac_r: Mat<f64>,
    /// `J_T_dot u` (acceleration of the origin at `u_dot = 0`).
    pub bias_acc: Vector3<f64>,
    /// `J_R_dot u` (angular acceleration at `u_dot = 0`).
    pub bias_ang_acc: Vector3<f64>,
}

impl FrameKinematics {
    /// Zeroed kinematics for an owner with `nu` velocity coordinates (0 for ground).
    pub fn new(nu: usize) -> Self {
        Self {
            position: Vector3::zeros(),
            rotation: Matrix3::identity(),
            velocity: Vector3::zeros(),
            angular_velocity: Vector3::zeros(),
            jac_t: Mat::zeros(3, nu),
            jac_r: Mat::zeros(3, nu),
            bias_acc: Vector3::zeros(),
            bias_ang_acc: Vector3::zeros(),
        }
    }
}

/// Scratch vectors for [`finite_difference_tangents`], sized for one element
/// (allocated once in the [`crate::Workspace`]).
#[derive(Debug)]
pub struct TangentScratch {
    /// Perturbed positions (nq).
    pub q: Vec<f64>,
    /// Perturbed velocities (nu).
    pub u: Vec<f64>,
    /// Velocity-space perturbation (nu).
    pub dv: Vec<f64>,
    /// Forces at the plus perturbation (nu).
    pub h_plus: Vec<f64>,
    /// Forces at the minus perturbation (nu).
    pub h_minus: Vec<f64>,
    /// The element evaluated at the perturbed states (the evaluated state of the unperturbed one
    /// is left alone).
    pub probe: ElementScratch,
}

impl TangentScratch {
    /// Scratch for `element`.
    pub fn new<E: Element + ?Sized>(element: &E) -> Self {
        let (nq, nu) = (element.nq(), element.nu());
        Self {
            q: vec![0.0; nq],
            u: vec![0.0; nu],
            dv: vec![0.0; nu],
            h_plus: vec![0.0; nu],
            h_minus: vec![0.0; nu],
            probe: element.new_scratch(),
        }
    }
}

/// The element contract (object safe: models store `Box<dyn Element>`).
///
/// Slices have the element's own lengths (`q`: nq, `u`, `h`: nu); matrices are `nu x nu`
/// views into the global matrices. Implementations must not allocate in any method called
/// during a time step (all methods except the pose setters, [`Element::new_scratch`] and
/// [`Element::evaluated`]).
pub trait Element: std::fmt::Debug + Send + Sync {
    /// The kinds of the nodes the element's coordinates live on, in order: its local `q` (`u`)
    /// is the concatenation of their position (velocity) coordinates, so the kinds' `nq` (`nu`)
    /// sum to [`Element::nq`] ([`Element::nu`]). A rigid body is one pose node, an FFR body a pose
    /// node and a `Vector(n_f)` node.
    fn node_kinds(&self) -> &[crate::NodeKind];
    /// Number of position coordinates `nq`.
    fn nq(&self) -> usize;
    /// Number of velocity coordinates `nu`.
    fn nu(&self) -> usize;
    /// Checks the element's parameters when the model is compiled; `Err(reason)` makes
    /// [`crate::ModelSpec::compile`] fail with [`crate::ModelError::InvalidBody`]. Default: valid.
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }
    /// Number of FE mesh nodes frames may refer to ([`LocalFrame::mesh_node`]); 0 for rigid
    /// bodies.
    fn num_mesh_nodes(&self) -> usize {
        0
    }
    /// Per velocity coordinate, the length (m per unit) that turns its position error into a
    /// displacement: 1 for translations, a body length for rotations, the largest nodal
    /// displacement of the mode for a modal coordinate. Weights the local error of adaptive
    /// steps ([`crate::integrator::AdaptiveSettings`]). Default 1 for every coordinate.
    fn velocity_scales(&self, out: &mut [f64]) {
        out.fill(1.0);
    }
    /// Reference coordinates: element at the origin, unrotated, undeformed, at rest.
    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]);
    /// Sets the pose of the element reference frame (position and rotation matrix, global).
    fn set_pose(&self, q: &mut [f64], position: &Vector3<f64>, rotation: &Matrix3<f64>);
    /// Sets the velocity of the reference frame origin and the angular velocity (global).
    fn set_velocity(&self, q: &[f64], u: &mut [f64], velocity: &Vector3<f64>, omega: &Vector3<f64>);
    /// Kinematic relation `q_dot = T(q) u`.
    fn q_dot(&self, q: &[f64], u: &[f64], q_dot: &mut [f64]);
    /// Position update `q_new = q ⊕ dv` for a velocity-space increment `dv` (see module docs).
    /// Default: `q + T(q) dv`, then [`Element::normalize`].
    fn integrate_position(&self, q: &[f64], dv: &[f64], q_new: &mut [f64]) {
        self.q_dot(q, dv, q_new);
        for (qn, qi) in q_new.iter_mut().zip(q) {
            *qn += qi;
        }
        self.normalize(q_new);
    }
    /// Projects the coordinates back onto their manifold (unit quaternion); default: nothing.
    fn normalize(&self, _q: &mut [f64]) {}
    /// A scratch for this element's evaluated state ([`ElementScratch`]); called when the
    /// workspace is built (may allocate). Default: an empty scratch (elements that evaluate
    /// everything from `q`, `u` in the queries).
    fn new_scratch(&self) -> ElementScratch {
        ElementScratch::empty()
    }
    /// The evaluation stage: evaluates the element at `(q, u)` into `scratch`, once per state;
    /// the queries below read it. Err: the state cannot be evaluated (the integrators report it
    /// with the body, the time and the cause). Default: nothing to evaluate.
    fn update(
        &self,
        _q: &[f64],
        _u: &[f64],
        _scratch: &mut ElementScratch,
    ) -> Result<(), ElementError> {
        Ok(())
    }
    /// [`Element::update`] for callers that query only [`Element::frame_kinematics`] (the load and
    /// constraint-force tangents evaluate frames at many perturbed states): an element whose full
    /// evaluation is expensive evaluates only what frames need (FFR bodies: O(n_f) instead of the
    /// O(n_f^2) deformed moments). Default: [`Element::update`].
    fn update_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        scratch: &mut ElementScratch,
    ) -> Result<(), ElementError> {
        self.update(q, u, scratch)
    }
    /// Mass matrix `M(q)` (nu x nu, symmetric positive definite), overwriting `m`.
    fn mass_matrix(&self, q: &[f64], scratch: &mut ElementScratch, m: MatMut<'_, f64>);
    /// Size `n_c` of a trailing block of the mass matrix (its last `n_c` velocity coordinates)
    /// that never depends on the state: an FFR body's modal mass `m_ff` (2.69). The block-Cholesky
    /// mass ([`crate::algebra::BlockMass`]) then factors it once and per state only the Schur
    /// complement of the leading block. Default 0 (none).
    fn constant_mass_tail(&self) -> usize {
        0
    }
    /// `out = M(q) v` (`v`, `out`: nu), for residuals that need only the product. Default:
    /// [`Element::mass_matrix`] into the scratch matrix `m_scratch` (nu x nu, left holding `M`),
    /// then the product column by column; elements with a cheaper product (FFR bodies) override
    /// it and may leave `m_scratch` untouched.
    fn mass_times_vector(
        &self,
        q: &[f64],
        scratch: &mut ElementScratch,
        v: &[f64],
        mut m_scratch: MatMut<'_, f64>,
        out: &mut [f64],
    ) {
        self.mass_matrix(q, scratch, m_scratch.as_mut());
        out.fill(0.0);
        for (j, x) in v.iter().enumerate() {
            for (i, o) in out.iter_mut().enumerate() {
                *o += m_scratch[(i, j)] * x;
            }
        }
    }
    /// Generalized forces `h(t, q, u)`, overwriting `h`: minus quadratic velocity vector, minus
    /// elastic `K q` and damping `D u` forces, plus gravity `gravity` (global acceleration vector).
    #[allow(clippy::too_many_arguments)]
    fn forces(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        scratch: &mut ElementScratch,
        h: &mut [f64],
    );
    /// Kinematics of a local frame of this element (position, rotation, velocities,
    /// Jacobians, bias accelerations), overwriting `out` (its Jacobians are 3 x nu). Needs
    /// [`Element::update`] or [`Element::update_kinematics`] at `(q, u)`.
    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        scratch: &mut ElementScratch,
        frame: &LocalFrame,
        out: &mut FrameKinematics,
    );
    /// Tangents `dh_dq` (along `q ⊕ dv`) and `dh_du` (both nu x nu), overwriting them.
    /// Default: central finite differences ([`finite_difference_tangents`]; the perturbed
    /// states are evaluated in `fd.probe`, `scratch` stays at `(q, u)`).
    #[allow(clippy::too_many_arguments)]
    fn force_tangents(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        _scratch: &mut ElementScratch,
        dh_dq: MatMut<'_, f64>,
        dh_du: MatMut<'_, f64>,
        fd: &mut TangentScratch,
    ) {
        finite_difference_tangents(self, t, q, u, gravity, dh_dq, dh_du, fd);
    }
    /// The load tangent `d(J_T^T f)/dq` (along `q ⊕ dv`; nu x nu, overwriting `out`) of a force at
    /// `frame` for the state evaluated in `scratch`: `force` global (a dead load) or, with
    /// `follower`, in the axes of the frame (turning with it). `false`: not provided, the caller
    /// differentiates numerically (the default).
    #[allow(clippy::too_many_arguments)]
    fn force_load_tangent(
        &self,
        _q: &[f64],
        _u: &[f64],
        _scratch: &mut ElementScratch,
        _frame: &LocalFrame,
        _force: &Vector3<f64>,
        _follower: bool,
        _out: MatMut<'_, f64>,
    ) -> bool {
        false
    }
    /// Kinetic energy `1/2 u^T M u`.
    fn kinetic_energy(&self, q: &[f64], u: &[f64], scratch: &mut ElementScratch) -> f64;
    /// Potential of gravity `-int rho g . r dV` (zero at the global origin).
    fn gravity_potential(
        &self,
        q: &[f64],
        gravity: &Vector3<f64>,
        scratch: &mut ElementScratch,
    ) -> f64;
    /// Elastic strain energy `1/2 q_f^T K q_f`; default 0 (rigid).
    fn elastic_energy(&self, _q: &[f64]) -> f64 {
        0.0
    }
    /// The size of the largest gross force terms whose difference the forces are (N): the
    /// round-off of `h` is about `eps` times this, and Newton's round-off floor is judged against it
    /// ([`crate::integrator::NewtonSettings`]). Elements whose forces come from differences of
    /// absolute coordinates (superelements: stiffness times positions) return it; default 0 (the
    /// forces themselves are the scale).
    fn force_scale(&self, _q: &[f64]) -> f64 {
        0.0
    }
    /// [`Element::elastic_energy`] from the state evaluated in `scratch` (at `q`), as the energy
    /// output calls it: elements whose strain energy needs the evaluation stage (superelements:
    /// the recovered floating frame) override it. Default: [`Element::elastic_energy`].
    fn elastic_energy_evaluated(&self, q: &[f64], _scratch: &mut ElementScratch) -> f64 {
        self.elastic_energy(q)
    }
    /// The FFR body of an element with geometric stiffening by node loads
    /// ([`crate::ffr::LoadStiffening`]), whose force the system stage adds
    /// ([`crate::system::add_load_stiffening_forces`]); default `None`.
    fn load_stiffened_ffr(&self) -> Option<&crate::ffr::FfrBody> {
        None
    }
    /// A fresh scratch evaluated at `(q, u)`: for set-up code and tests outside a time step
    /// (allocates). Time steps use the workspace's scratches.
    fn evaluated(&self, q: &[f64], u: &[f64]) -> Result<ElementScratch, ElementError> {
        let mut s = self.new_scratch();
        self.update(q, u, &mut s)?;
        Ok(s)
    }
}

/// Central finite-difference tangents of [`Element::forces`]: column `j` of `dh_dq` is
/// `(h(q ⊕ e_j eps) - h(q ⊕ -e_j eps)) / (2 eps)`, likewise `dh_du` with `u ± eps e_j`,
/// `eps = 1e-6 max(1, |x_j|)`. Truncation error `O(eps^2)`, round-off `O(1e-16 |h| / eps)`.
/// Every perturbed state is evaluated ([`Element::update`]) in `s.probe`; one the element
/// cannot evaluate gives NaN entries (reported by the integrators as a non-finite matrix).
#[allow(clippy::too_many_arguments)]
pub fn finite_difference_tangents<E: Element + ?Sized>(
    element: &E,
    t: f64,
    q: &[f64],
    u: &[f64],
    gravity: &Vector3<f64>,
    mut dh_dq: MatMut<'_, f64>,
    mut dh_du: MatMut<'_, f64>,
    s: &mut TangentScratch,
) {
    let nu = element.nu();
    s.dv.fill(0.0);
    for j in 0..nu {
        let eps = 1e-6;
        s.dv[j] = eps;
        element.integrate_position(q, &s.dv, &mut s.q);
        probe_forces(element, t, &s.q, u, gravity, &mut s.probe, &mut s.h_plus);
        s.dv[j] = -eps;
        element.integrate_position(q, &s.dv, &mut s.q);
        probe_forces(element, t, &s.q, u, gravity, &mut s.probe, &mut s.h_minus);
        s.dv[j] = 0.0;
        for i in 0..nu {
            dh_dq[(i, j)] = (s.h_plus[i] - s.h_minus[i]) / (2.0 * eps);
        }
    }
    s.u.copy_from_slice(u);
    for j in 0..nu {
        let eps = 1e-6 * u[j].abs().max(1.0);
        s.u[j] = u[j] + eps;
        probe_forces(element, t, q, &s.u, gravity, &mut s.probe, &mut s.h_plus);
        s.u[j] = u[j] - eps;
        probe_forces(element, t, q, &s.u, gravity, &mut s.probe, &mut s.h_minus);
        s.u[j] = u[j];
        for i in 0..nu {
            dh_du[(i, j)] = (s.h_plus[i] - s.h_minus[i]) / (2.0 * eps);
        }
    }
}

/// `h(t, q, u)` of `element` evaluated in `probe`; NaN if the state cannot be evaluated.
fn probe_forces<E: Element + ?Sized>(
    element: &E,
    t: f64,
    q: &[f64],
    u: &[f64],
    gravity: &Vector3<f64>,
    probe: &mut ElementScratch,
    h: &mut [f64],
) {
    match element.update(q, u, probe) {
        Ok(()) => element.forces(t, q, u, gravity, probe, h),
        Err(_) => h.fill(f64::NAN),
    }
}

/// Skew-symmetric matrix `a~` with `a~ b = a x b`: the one implementation in
/// [`crate::rotation::skew`], re-exported here for existing callers.
pub use crate::rotation::skew;
