//! Rigid body element (reference point = centre of mass).
//!
//! Coordinates: `q = [R; theta]`, `R` the global centre-of-mass position and `theta` either
//! - Cardan angles x-y-z `(alpha, beta, gamma)`, `A = Rx(alpha) Ry(beta) Rz(gamma)` (seed 000
//!   eq. (2.22)), with `u = q_dot` (`T = I`, seed 000 eq. (2.26)); global angular velocity
//!   `omega = G theta_dot`, `G = [e_x, Rx e_y, Rx Ry e_z]` (= `A G_bar`, seed 000 eq. (2.31)); or
//! - a unit quaternion `p = (p0, p1, p2, p3)` (scalar first) with `u = [R_dot; omega_bar]`,
//!   `omega_bar` the angular velocity in body coordinates: `p_dot = 1/2 p * (0, omega_bar)`.
//!   Positions are updated by the exponential map `p ⊕ dv = p * exp(dv_rot / 2)`.

use crate::element::{
    skew, Element, ElementError, ElementScratch, FrameKinematics, LocalFrame, TangentScratch,
};
use crate::node::NodeKind;
use crate::rotation::{cardan_g, cardan_g_dot_theta_dot};
use faer::MatMut;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Parametrization of the rotation of a rigid body or of the floating frame of an FFR body
/// (one type for both, also re-exported as `ffr::RotationParam`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RotationParam {
    /// Cardan angles x-y-z (seed 000 (2.22)) with `u = q_dot` (2.26) (singular at
    /// `beta = ±90°`). Default.
    #[default]
    Cardan,
    /// Unit quaternion `[w, x, y, z]` with the body-frame angular velocity as velocity
    /// coordinates.
    Quaternion,
}

impl RotationParam {
    /// Number of rotation coordinates in `q` (3 or 4).
    pub fn num_coordinates(self) -> usize {
        match self {
            RotationParam::Cardan => 3,
            RotationParam::Quaternion => 4,
        }
    }
}

/// A rigid body: mass, inertia tensor about the centre of mass in body axes.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    /// Mass (> 0).
    pub mass: f64,
    /// Inertia tensor about the centre of mass in body coordinates (symmetric positive definite).
    pub inertia: Matrix3<f64>,
    /// Rotation parametrization.
    pub rotation: RotationParam,
}

impl RigidBody {
    /// Rigid body with Cardan angles.
    pub fn new(mass: f64, inertia: Matrix3<f64>) -> Self {
        Self {
            mass,
            inertia,
            rotation: RotationParam::Cardan,
        }
    }

    /// Same body with another rotation parametrization.
    pub fn with_rotation(mut self, rotation: RotationParam) -> Self {
        self.rotation = rotation;
        self
    }

    /// Rotation matrix `A` of the body from its coordinates.
    pub fn rotation_matrix(&self, q: &[f64]) -> Matrix3<f64> {
        match self.rotation {
            RotationParam::Cardan => cardan_matrix(q[3], q[4], q[5]),
            RotationParam::Quaternion => quaternion(q).to_rotation_matrix().into_inner(),
        }
    }

    /// Global angular velocity `omega`.
    pub fn angular_velocity(&self, q: &[f64], u: &[f64]) -> Vector3<f64> {
        let w = Vector3::new(u[3], u[4], u[5]);
        match self.rotation {
            RotationParam::Cardan => cardan_g(q[3], q[4]) * w,
            RotationParam::Quaternion => self.rotation_matrix(q) * w,
        }
    }

    /// Global angular momentum about the centre of mass `A I A^T omega`.
    pub fn angular_momentum(&self, q: &[f64], u: &[f64]) -> Vector3<f64> {
        let a = self.rotation_matrix(q);
        a * self.inertia * a.transpose() * self.angular_velocity(q, u)
    }

    /// Rotational part of `h` and of its tangents for the quaternion body:
    /// `h_rot = -omega_bar x (I omega_bar)`, `d h_rot / d omega_bar = -(w~ I - (I w)~)`.
    fn gyroscopic_tangent_quaternion(&self, u: &[f64]) -> Matrix3<f64> {
        let w = Vector3::new(u[3], u[4], u[5]);
        -(skew(&w) * self.inertia - skew(&(self.inertia * w)))
    }
}

/// `Rx(a) Ry(b) Rz(c)` (seed 000 eq. (2.22)); see [`crate::rotation::cardan_matrix`].
pub fn cardan_matrix(a: f64, b: f64, c: f64) -> Matrix3<f64> {
    crate::rotation::cardan_matrix(&Vector3::new(a, b, c))
}

fn quaternion(q: &[f64]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(q[3], q[4], q[5], q[6]))
}

impl Element for RigidBody {
    /// Translations 1; rotations the radius of gyration `sqrt(I_max / m)` about the centre of
    /// mass (largest diagonal entry of the inertia tensor).
    fn velocity_scales(&self, out: &mut [f64]) {
        let i_max = (0..3).map(|k| self.inertia[(k, k)]).fold(0.0, f64::max);
        out[..3].fill(1.0);
        out[3..6].fill((i_max / self.mass).sqrt());
    }

    /// Mass finite and > 0; inertia symmetric positive definite with principal moments obeying
    /// the triangle inequality (each at most the sum of the other two, as for any real body).
    fn validate(&self) -> Result<(), String> {
        let (m, i) = (self.mass, &self.inertia);
        if !(m.is_finite() && m > 0.0) {
            return Err(format!("mass must be finite and > 0, got {m}"));
        }
        if !i.iter().all(|x| x.is_finite()) || (i - i.transpose()).amax() > 1e-12 * i.amax() {
            return Err(format!("inertia must be finite and symmetric, got {i:?}"));
        }
        let p = i.symmetric_eigenvalues();
        let total = p.sum();
        if p.min() <= 0.0 {
            return Err(format!(
                "inertia must be positive definite, principal moments {:?}",
                p.as_slice()
            ));
        }
        for k in 0..3 {
            if p[k] > p[(k + 1) % 3] + p[(k + 2) % 3] + 1e-9 * total {
                return Err(format!(
                    "principal moments {:?} violate the triangle inequality: no real mass distribution has them",
                    p.as_slice()
                ));
            }
        }
        Ok(())
    }

    fn nq(&self) -> usize {
        match self.rotation {
            RotationParam::Cardan => 6,
            RotationParam::Quaternion => 7,
        }
    }
    fn nu(&self) -> usize {
        6
    }
    fn node_kinds(&self) -> &[NodeKind] {
        match self.rotation {
            RotationParam::Cardan => &[NodeKind::PoseCardan],
            RotationParam::Quaternion => &[NodeKind::Pose],
        }
    }
    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        self.node_kinds()[0].reference(q, u);
    }
    fn set_pose(&self, q: &mut [f64], position: &Vector3<f64>, rotation: &Matrix3<f64>) {
        self.node_kinds()[0].set_pose(q, position, rotation);
    }
    fn set_velocity(
        &self,
        q: &[f64],
        u: &mut [f64],
        velocity: &Vector3<f64>,
        omega: &Vector3<f64>,
    ) {
        self.node_kinds()[0].set_velocity(q, u, velocity, omega);
    }
    fn q_dot(&self, q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        self.node_kinds()[0].q_dot(q, u, q_dot);
    }
    fn integrate_position(&self, q: &[f64], dv: &[f64], q_new: &mut [f64]) {
        self.node_kinds()[0].integrate(q, dv, q_new);
    }
    fn normalize(&self, q: &mut [f64]) {
        self.node_kinds()[0].normalize(q);
    }
    /// Checks the rotation coordinates: Cardan angles away from `beta = ±90°` (where `G` is
    /// singular), a quaternion of non-zero norm. Everything else is evaluated in the queries.
    fn update(&self, q: &[f64], _u: &[f64], _s: &mut ElementScratch) -> Result<(), ElementError> {
        match self.rotation {
            RotationParam::Cardan => crate::rotation::check_cardan(
                &Vector3::new(q[3], q[4], q[5]),
                crate::rotation::CARDAN_SINGULARITY_TOLERANCE,
            )?,
            RotationParam::Quaternion => {
                let norm = nalgebra::Vector4::new(q[3], q[4], q[5], q[6]).norm();
                if !(norm.is_finite() && norm > 1e-12) {
                    return Err(
                        crate::rotation::RotationError::DegenerateQuaternion { norm }.into(),
                    );
                }
            }
        }
        Ok(())
    }
    fn mass_matrix(&self, q: &[f64], _s: &mut ElementScratch, mut m: MatMut<'_, f64>) {
        m.fill(0.0);
        for i in 0..3 {
            m[(i, i)] = self.mass;
        }
        let mrot = match self.rotation {
            RotationParam::Cardan => {
                let a = self.rotation_matrix(q);
                let g = cardan_g(q[3], q[4]);
                g.transpose() * a * self.inertia * a.transpose() * g
            }
            RotationParam::Quaternion => self.inertia,
        };
        for i in 0..3 {
            for j in 0..3 {
                m[(3 + i, 3 + j)] = mrot[(i, j)];
            }
        }
    }
    fn forces(
        &self,
        _t: f64,
        q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        _s: &mut ElementScratch,
        h: &mut [f64],
    ) {
        let f = gravity * self.mass;
        h[..3].copy_from_slice(f.as_slice());
        let w = Vector3::new(u[3], u[4], u[5]);
        let hr = match self.rotation {
            RotationParam::Cardan => {
                // h_theta = -G^T (I_g G_dot theta_dot + omega x I_g omega), I_g = A I A^T
                let a = self.rotation_matrix(q);
                let g = cardan_g(q[3], q[4]);
                let ig = a * self.inertia * a.transpose();
                let omega = g * w;
                -g.transpose()
                    * (ig * cardan_g_dot_theta_dot(q[3], q[4], &w) + omega.cross(&(ig * omega)))
            }
            RotationParam::Quaternion => -w.cross(&(self.inertia * w)),
        };
        h[3..6].copy_from_slice(hr.as_slice());
    }
    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        _s: &mut ElementScratch,
        frame: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        self.node_kinds()[0].frame_kinematics(q, u, frame, out);
    }
    fn force_tangents(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        _s: &mut ElementScratch,
        mut dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
        scratch: &mut TangentScratch,
    ) {
        match self.rotation {
            RotationParam::Cardan => crate::element::finite_difference_tangents(
                self, t, q, u, gravity, dh_dq, dh_du, scratch,
            ),
            RotationParam::Quaternion => {
                // h = [m g; -w x I w] does not depend on q; analytic gyroscopic tangent.
                dh_dq.fill(0.0);
                dh_du.fill(0.0);
                let k = self.gyroscopic_tangent_quaternion(u);
                for i in 0..3 {
                    for j in 0..3 {
                        dh_du[(3 + i, 3 + j)] = k[(i, j)];
                    }
                }
            }
        }
    }
    fn kinetic_energy(&self, q: &[f64], u: &[f64], _s: &mut ElementScratch) -> f64 {
        let v = Vector3::new(u[0], u[1], u[2]);
        let omega = self.angular_velocity(q, u);
        let a = self.rotation_matrix(q);
        0.5 * self.mass * v.norm_squared()
            + 0.5 * omega.dot(&(a * self.inertia * a.transpose() * omega))
    }
    fn gravity_potential(&self, q: &[f64], gravity: &Vector3<f64>, _s: &mut ElementScratch) -> f64 {
        -self.mass * gravity.dot(&Vector3::new(q[0], q[1], q[2]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::finite_difference_tangents;
    use faer::Mat;

    fn body(rot: RotationParam) -> RigidBody {
        let i = Matrix3::new(1.0, 0.1, -0.05, 0.1, 2.0, 0.2, -0.05, 0.2, 3.0);
        RigidBody::new(2.5, i).with_rotation(rot)
    }

    /// The analytic gyroscopic tangent of the quaternion body equals the default central
    /// finite-difference tangent to 1e-6 (both dh/du and dh/dq = 0).
    #[test]
    fn analytic_tangent_matches_finite_differences() {
        let b = body(RotationParam::Quaternion);
        let (mut q, mut u) = (vec![0.0; 7], vec![0.0; 6]);
        b.set_pose(
            &mut q,
            &Vector3::new(0.1, 0.2, 0.3),
            &cardan_matrix(0.3, -0.6, 1.2),
        );
        b.set_velocity(
            &q,
            &mut u,
            &Vector3::new(1.0, -2.0, 0.5),
            &Vector3::new(0.7, -1.3, 2.1),
        );
        let g = Vector3::new(0.0, -9.81, 0.0);
        let (mut kq, mut ku) = (Mat::<f64>::zeros(6, 6), Mat::<f64>::zeros(6, 6));
        let (mut fq, mut fu) = (Mat::<f64>::zeros(6, 6), Mat::<f64>::zeros(6, 6));
        let mut s = TangentScratch::new(&b);
        let mut e = b.evaluated(&q, &u).unwrap();
        b.force_tangents(0.0, &q, &u, &g, &mut e, kq.as_mut(), ku.as_mut(), &mut s);
        finite_difference_tangents(&b, 0.0, &q, &u, &g, fq.as_mut(), fu.as_mut(), &mut s);
        let mut worst: f64 = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                worst = worst
                    .max((kq[(i, j)] - fq[(i, j)]).abs())
                    .max((ku[(i, j)] - fu[(i, j)]).abs());
            }
        }
        assert!(worst < 1e-6, "max difference {worst}");
        assert!(ku[(3, 4)].abs() > 0.1, "tangent is not trivially zero");
    }

    /// Cardan and quaternion parametrizations of the same motion give the same frame velocity,
    /// angular velocity and kinetic energy (checks G, A and the Cardan mass matrix), to 1e-12.
    #[test]
    fn cardan_and_quaternion_agree() {
        let frame = LocalFrame::at(Vector3::new(0.3, -0.2, 0.4));
        let r = cardan_matrix(0.4, -0.7, 2.0);
        let (v, w) = (Vector3::new(0.5, 0.1, -0.3), Vector3::new(1.1, -0.4, 0.8));
        let mut out = Vec::new();
        for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
            let b = body(rot);
            let (mut q, mut u) = (vec![0.0; b.nq()], vec![0.0; 6]);
            b.set_pose(&mut q, &Vector3::new(1.0, 2.0, 3.0), &r);
            b.set_velocity(&q, &mut u, &v, &w);
            let mut k = FrameKinematics::new(6);
            let mut e = b.evaluated(&q, &u).unwrap();
            b.frame_kinematics(&q, &u, &mut e, &frame, &mut k);
            let mut m = Mat::<f64>::zeros(6, 6);
            b.mass_matrix(&q, &mut e, m.as_mut());
            let t_mass: f64 = (0..6)
                .map(|i| (0..6).map(|j| 0.5 * u[i] * m[(i, j)] * u[j]).sum::<f64>())
                .sum();
            assert!((t_mass - b.kinetic_energy(&q, &u, &mut e)).abs() < 1e-12);
            assert!((k.rotation - r).norm() < 1e-12);
            out.push((k.position, k.velocity, k.angular_velocity, t_mass));
        }
        assert!((out[0].0 - out[1].0).norm() < 1e-12);
        assert!((out[0].1 - out[1].1).norm() < 1e-12);
        assert!((out[0].2 - out[1].2).norm() < 1e-12);
        assert!((out[0].3 - out[1].3).abs() < 1e-12);
    }
}
