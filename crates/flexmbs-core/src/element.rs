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
//! Velocity-space perturbations: a position change is always described by a velocity-space
//! increment `dv` (length `nu`) applied with [`Element::integrate_position`], `q ⊕ dv`. For
//! vector-space coordinates (Cardan angles, modal coordinates) `q ⊕ dv = q + T(q) dv`; for
//! quaternions it is the exponential map. Position tangents are taken along this map:
//! `dh_dq[:, j] = d/de h(q ⊕ e e_j)` at `e = 0` (an `nu x nu` matrix).

use faer::{Mat, MatMut};
use nalgebra::{Matrix3, Vector3};

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
#[derive(Debug, Clone)]
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
}

impl TangentScratch {
    /// Scratch for an element with `nq` position and `nu` velocity coordinates.
    pub fn new(nq: usize, nu: usize) -> Self {
        Self {
            q: vec![0.0; nq],
            u: vec![0.0; nu],
            dv: vec![0.0; nu],
            h_plus: vec![0.0; nu],
            h_minus: vec![0.0; nu],
        }
    }
}

/// The element contract (object safe: models store `Box<dyn Element>`).
///
/// Slices have the element's own lengths (`q`: nq, `u`, `h`: nu); matrices are `nu x nu`
/// views into the global matrices. Implementations must not allocate in any method called
/// during a time step (all methods except the pose setters).
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
    /// Mass matrix `M(q)` (nu x nu, symmetric positive definite), overwriting `m`.
    fn mass_matrix(&self, q: &[f64], m: MatMut<'_, f64>);
    /// `out = M(q) v` (`v`, `out`: nu), for residuals that need only the product. Default:
    /// [`Element::mass_matrix`] into the scratch matrix `m_scratch` (nu x nu, left holding `M`),
    /// then the product column by column; elements with a cheaper product (FFR bodies) override
    /// it and may leave `m_scratch` untouched.
    fn mass_times_vector(
        &self,
        q: &[f64],
        v: &[f64],
        mut m_scratch: MatMut<'_, f64>,
        out: &mut [f64],
    ) {
        self.mass_matrix(q, m_scratch.as_mut());
        out.fill(0.0);
        for (j, x) in v.iter().enumerate() {
            for (i, o) in out.iter_mut().enumerate() {
                *o += m_scratch[(i, j)] * x;
            }
        }
    }
    /// Generalized forces `h(t, q, u)`, overwriting `h`: minus quadratic velocity vector, minus
    /// elastic `K q` and damping `D u` forces, plus gravity `gravity` (global acceleration vector).
    fn forces(&self, t: f64, q: &[f64], u: &[f64], gravity: &Vector3<f64>, h: &mut [f64]);
    /// Kinematics of a local frame of this element (position, rotation, velocities,
    /// Jacobians, bias accelerations), overwriting `out` (its Jacobians are 3 x nu).
    fn frame_kinematics(&self, q: &[f64], u: &[f64], frame: &LocalFrame, out: &mut FrameKinematics);
    /// [`Element::frame_kinematics`] for callers that need only the frame (the load and
    /// constraint-force tangents evaluate frames at many perturbed states): same results, but an
    /// element whose full evaluation is expensive computes only what the frame needs and leaves its
    /// evaluated state for mass and forces untouched (FFR bodies: O(n_f) per frame instead of the
    /// O(n_f^2) deformed moments). Default: [`Element::frame_kinematics`].
    fn frame_kinematics_only(
        &self,
        q: &[f64],
        u: &[f64],
        frame: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        self.frame_kinematics(q, u, frame, out);
    }
    /// Tangents `dh_dq` (along `q ⊕ dv`) and `dh_du` (both nu x nu), overwriting them.
    /// Default: central finite differences ([`finite_difference_tangents`]).
    #[allow(clippy::too_many_arguments)]
    fn force_tangents(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        dh_dq: MatMut<'_, f64>,
        dh_du: MatMut<'_, f64>,
        scratch: &mut TangentScratch,
    ) {
        finite_difference_tangents(self, t, q, u, gravity, dh_dq, dh_du, scratch);
    }
    /// Kinetic energy `1/2 u^T M u`.
    fn kinetic_energy(&self, q: &[f64], u: &[f64]) -> f64;
    /// Potential of gravity `-int rho g . r dV` (zero at the global origin).
    fn gravity_potential(&self, q: &[f64], gravity: &Vector3<f64>) -> f64;
    /// Elastic strain energy `1/2 q_f^T K q_f`; default 0 (rigid).
    fn elastic_energy(&self, _q: &[f64]) -> f64 {
        0.0
    }
}

/// Central finite-difference tangents of [`Element::forces`]: column `j` of `dh_dq` is
/// `(h(q ⊕ e_j eps) - h(q ⊕ -e_j eps)) / (2 eps)`, likewise `dh_du` with `u ± eps e_j`,
/// `eps = 1e-6 max(1, |x_j|)`. Truncation error `O(eps^2)`, round-off `O(1e-16 |h| / eps)`.
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
        element.forces(t, &s.q, u, gravity, &mut s.h_plus);
        s.dv[j] = -eps;
        element.integrate_position(q, &s.dv, &mut s.q);
        element.forces(t, &s.q, u, gravity, &mut s.h_minus);
        s.dv[j] = 0.0;
        for i in 0..nu {
            dh_dq[(i, j)] = (s.h_plus[i] - s.h_minus[i]) / (2.0 * eps);
        }
    }
    s.u.copy_from_slice(u);
    for j in 0..nu {
        let eps = 1e-6 * u[j].abs().max(1.0);
        s.u[j] = u[j] + eps;
        element.forces(t, q, &s.u, gravity, &mut s.h_plus);
        s.u[j] = u[j] - eps;
        element.forces(t, q, &s.u, gravity, &mut s.h_minus);
        s.u[j] = u[j];
        for i in 0..nu {
            dh_du[(i, j)] = (s.h_plus[i] - s.h_minus[i]) / (2.0 * eps);
        }
    }
}

/// Skew-symmetric matrix `a~` with `a~ b = a x b`: the one implementation in
/// [`crate::rotation::skew`], re-exported here for existing callers.
pub use crate::rotation::skew;
