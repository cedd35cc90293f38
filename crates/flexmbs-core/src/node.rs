//! Coordinate maps: where the coordinates of a body (element) or a frame's Jacobian columns lie in
//! the global `q` / `u`.

use std::ops::Range;

/// Global indices of a sequence of element-local coordinates: one contiguous range (every body
/// created by [`crate::ModelSpec::add_body`], the zero-copy case), or an explicit list.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DofMap {
    /// Local coordinate `i` is global `range.start + i`.
    Contiguous(Range<usize>),
    /// Local coordinate `i` is global `indices[i]`.
    Scattered(Vec<usize>),
}

impl DofMap {
    /// Number of coordinates.
    pub fn len(&self) -> usize {
        match self {
            DofMap::Contiguous(r) => r.len(),
            DofMap::Scattered(v) => v.len(),
        }
    }

    /// No coordinates (a ground frame).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Global index of local coordinate `i`.
    ///
    /// # Panics
    /// If `i >= self.len()`.
    pub fn global(&self, i: usize) -> usize {
        match self {
            DofMap::Contiguous(r) => {
                assert!(i < r.len(), "local coordinate {i} of {}", r.len());
                r.start + i
            }
            DofMap::Scattered(v) => v[i],
        }
    }

    /// The contiguous range, if the map is one.
    pub fn as_range(&self) -> Option<Range<usize>> {
        match self {
            DofMap::Contiguous(r) => Some(r.clone()),
            DofMap::Scattered(_) => None,
        }
    }

    /// Global indices in local order.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        let (range, list) = match self {
            DofMap::Contiguous(r) => (r.clone(), &[][..]),
            DofMap::Scattered(v) => (0..0, v.as_slice()),
        };
        range.chain(list.iter().copied())
    }
}

use crate::rotation::{cardan_from_matrix, cardan_g, cardan_g_dot_theta_dot};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// The kind of a node: how its coordinates are parametrized and updated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    /// `n` additive coordinates (modal coordinates, point positions): `q ⊕ dv = q + dv`,
    /// `q_dot = u`.
    Vector(usize),
    /// Position (3) and unit quaternion `[w, x, y, z]` (4); `u = [R_dot; omega_bar]` with the
    /// body-frame angular velocity; `p ⊕ dv = p exp(dv_rot)` (exponential map).
    Pose,
    /// Position (3) and Cardan angles x-y-z (3, legacy: singular at `beta = ±90°`);
    /// `u = [R_dot; theta_dot]`, `q ⊕ dv = q + dv`.
    PoseCardan,
}

impl NodeKind {
    /// Number of position coordinates.
    pub fn nq(self) -> usize {
        match self {
            NodeKind::Vector(n) => n,
            NodeKind::Pose => 7,
            NodeKind::PoseCardan => 6,
        }
    }

    /// Number of velocity coordinates.
    pub fn nu(self) -> usize {
        match self {
            NodeKind::Vector(n) => n,
            NodeKind::Pose | NodeKind::PoseCardan => 6,
        }
    }

    /// Reference coordinates: at the origin, unrotated, at rest.
    pub fn reference(self, q: &mut [f64], u: &mut [f64]) {
        q.fill(0.0);
        u.fill(0.0);
        if self == NodeKind::Pose {
            q[3] = 1.0;
        }
    }

    /// Position update `q_new = q ⊕ dv`.
    pub fn integrate(self, q: &[f64], dv: &[f64], q_new: &mut [f64]) {
        match self {
            NodeKind::Vector(_) | NodeKind::PoseCardan => {
                for ((qn, qi), d) in q_new.iter_mut().zip(q).zip(dv) {
                    *qn = qi + d;
                }
            }
            NodeKind::Pose => {
                for i in 0..3 {
                    q_new[i] = q[i] + dv[i];
                }
                let p = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(
                    q[3], q[4], q[5], q[6],
                )) * UnitQuaternion::from_scaled_axis(Vector3::new(dv[3], dv[4], dv[5]));
                q_new[3..7].copy_from_slice(&[p.w, p.i, p.j, p.k]);
                self.normalize(q_new);
            }
        }
    }

    /// Kinematic relation `q_dot = T(q) u`.
    pub fn q_dot(self, q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        match self {
            NodeKind::Vector(_) | NodeKind::PoseCardan => q_dot.copy_from_slice(u),
            NodeKind::Pose => {
                q_dot[..3].copy_from_slice(&u[..3]);
                let p = nalgebra::Quaternion::new(q[3], q[4], q[5], q[6]);
                let d = p * nalgebra::Quaternion::new(0.0, u[3], u[4], u[5]) * 0.5;
                q_dot[3..7].copy_from_slice(&[d.w, d.i, d.j, d.k]);
            }
        }
    }

    /// Projects the coordinates onto their manifold (unit quaternion of a `Pose`).
    pub fn normalize(self, q: &mut [f64]) {
        if self == NodeKind::Pose {
            let n = (q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]).sqrt();
            for x in &mut q[3..7] {
                *x /= n;
            }
        }
    }

    /// Sets the pose of a `Pose` / `PoseCardan` node (global position and rotation matrix); for a
    /// `Vector(3)` node the position (the rotation is ignored); other vectors are unchanged.
    pub fn set_pose(self, q: &mut [f64], position: &Vector3<f64>, rotation: &Matrix3<f64>) {
        match self {
            NodeKind::Vector(3) => q.copy_from_slice(position.as_slice()),
            NodeKind::Vector(_) => {}
            NodeKind::PoseCardan => {
                q[..3].copy_from_slice(position.as_slice());
                // Tolerance 0: any finite rotation gets angles, also at or near the singularity
                // beta = +-90 deg, where alpha and gamma come from entries of order cos(beta)
                // (only alpha +- gamma is determined). The element refuses such a pose at its
                // first evaluation (`rotation::CARDAN_SINGULARITY_TOLERANCE`), naming the body.
                // Only a non-finite matrix errs: its angles are NaN.
                let theta = cardan_from_matrix(rotation, 0.0)
                    .unwrap_or_else(|_| Vector3::from_element(f64::NAN));
                q[3..6].copy_from_slice(theta.as_slice());
            }
            NodeKind::Pose => {
                q[..3].copy_from_slice(position.as_slice());
                let p = quaternion_of(rotation);
                q[3..7].copy_from_slice(&[p.w, p.i, p.j, p.k]);
            }
        }
    }

    /// Sets the velocity of the node origin and the angular velocity (global) of a pose node
    /// (after its pose); for a `Vector(3)` node the velocity; other vectors are unchanged.
    pub fn set_velocity(
        self,
        q: &[f64],
        u: &mut [f64],
        velocity: &Vector3<f64>,
        omega: &Vector3<f64>,
    ) {
        match self {
            NodeKind::Vector(3) => u.copy_from_slice(velocity.as_slice()),
            NodeKind::Vector(_) => {}
            NodeKind::PoseCardan => {
                u[..3].copy_from_slice(velocity.as_slice());
                let w = cardan_g(q[3], q[4])
                    .try_inverse()
                    .map(|gi| gi * omega)
                    .unwrap_or_else(|| Vector3::from_element(f64::NAN));
                u[3..6].copy_from_slice(w.as_slice());
            }
            NodeKind::Pose => {
                u[..3].copy_from_slice(velocity.as_slice());
                let a = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(
                    q[3], q[4], q[5], q[6],
                ))
                .to_rotation_matrix()
                .into_inner();
                u[3..6].copy_from_slice((a.transpose() * omega).as_slice());
            }
        }
    }
}

/// The unit quaternion of a rotation matrix: nalgebra's iterative `from_matrix` (kept: the
/// initial states of existing models stay bitwise the same), or, where that iteration stalls
/// (rotations by about 180°, whose gradient vanishes at its identity start: a beam along -x),
/// the closed form of `from_rotation_matrix`.
pub(crate) fn quaternion_of(rotation: &Matrix3<f64>) -> UnitQuaternion<f64> {
    let p = UnitQuaternion::from_matrix(rotation);
    if (p.to_rotation_matrix().into_inner() - rotation).amax() <= 1e-12 {
        return p;
    }
    UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(*rotation))
}

impl NodeKind {
    /// Can frames be fixed to a node of this kind ([`Self::frame_kinematics`])?
    pub fn carries_frames(self) -> bool {
        matches!(
            self,
            NodeKind::Pose | NodeKind::PoseCardan | NodeKind::Vector(3)
        )
    }

    /// Rotation matrix of a pose node (identity for a point).
    pub fn rotation(self, q: &[f64]) -> Matrix3<f64> {
        match self {
            NodeKind::PoseCardan => crate::rotation::cardan_matrix(&Vector3::new(q[3], q[4], q[5])),
            NodeKind::Pose => {
                UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(q[3], q[4], q[5], q[6]))
                    .to_rotation_matrix()
                    .into_inner()
            }
            NodeKind::Vector(_) => Matrix3::identity(),
        }
    }

    /// Kinematics of a frame fixed to the node at `local.position` (node axes) with
    /// `local.rotation`: `r = R + A p`, `J_T = [I, -(A p)~ J_rot]`, `J_R = [0, J_rot]` with
    /// `J_rot = G` (Cardan, global `G`) or `A` (quaternion); a `Vector(3)` node is a point
    /// (`J_T = I`, no rotation). Jacobians have the node's `nu` columns.
    pub fn frame_kinematics(
        self,
        q: &[f64],
        u: &[f64],
        local: &crate::LocalFrame,
        out: &mut crate::FrameKinematics,
    ) {
        out.jac_t.fill(0.0);
        out.jac_r.fill(0.0);
        if let NodeKind::Vector(_) = self {
            out.position = Vector3::new(q[0], q[1], q[2]);
            out.rotation = local.rotation;
            out.velocity = Vector3::new(u[0], u[1], u[2]);
            out.angular_velocity = Vector3::zeros();
            out.bias_acc = Vector3::zeros();
            out.bias_ang_acc = Vector3::zeros();
            for i in 0..3 {
                out.jac_t[(i, i)] = 1.0;
            }
            return;
        }
        let a = self.rotation(q);
        let r = Vector3::new(q[0], q[1], q[2]);
        let v = Vector3::new(u[0], u[1], u[2]);
        let s = a * local.position; // global offset node origin -> frame origin
        let w = Vector3::new(u[3], u[4], u[5]);
        // omega = J_rot w (global), with J_rot = G (Cardan) or A (quaternion)
        let (jrot, alpha_bias) = match self {
            NodeKind::PoseCardan => (cardan_g(q[3], q[4]), cardan_g_dot_theta_dot(q[3], q[4], &w)),
            _ => (a, Vector3::zeros()),
        };
        let omega = jrot * w;
        out.position = r + s;
        out.rotation = a * local.rotation;
        out.velocity = v + omega.cross(&s);
        out.angular_velocity = omega;
        let jt_rot = -crate::rotation::skew(&s) * jrot;
        for i in 0..3 {
            out.jac_t[(i, i)] = 1.0;
            for j in 0..3 {
                out.jac_t[(i, 3 + j)] = jt_rot[(i, j)];
                out.jac_r[(i, 3 + j)] = jrot[(i, j)];
            }
        }
        out.bias_acc = alpha_bias.cross(&s) + omega.cross(&omega.cross(&s));
        out.bias_ang_acc = alpha_bias;
    }
}

/// A node: the owner of a block of coordinates that one or several elements reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Name (for messages and output).
    pub name: String,
    /// Parametrization.
    pub kind: NodeKind,
    /// Its position coordinates in the global `q`.
    pub q: Range<usize>,
    /// Its velocity coordinates in the global `u`.
    pub u: Range<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation::cardan_matrix;

    /// The Cardan extraction `set_pose` inlined before it used [`cardan_from_matrix`] (the
    /// reference of the bitwise comparison).
    fn old_set_pose_cardan(r: &Matrix3<f64>) -> [f64; 3] {
        [
            (-r[(1, 2)]).atan2(r[(2, 2)]),
            r[(0, 2)].clamp(-1.0, 1.0).asin(),
            (-r[(0, 1)]).atan2(r[(0, 0)]),
        ]
    }

    /// `PoseCardan::set_pose` gives bitwise the angles of the old inlined formula: random
    /// rotations, the axes' quarter turns, and rotations at and near beta = +-90 deg (also
    /// matrices with round-off beyond |r_13| = 1, which the clamp maps to +-90 deg).
    #[test]
    fn pose_cardan_set_pose_is_bitwise_the_old_extraction() {
        let mut rotations = Vec::new();
        // Deterministic pseudo-random angles (LCG), beta over the whole range.
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..500 {
            let a = (2.0 * next() - 1.0) * std::f64::consts::PI;
            let b = (2.0 * next() - 1.0) * std::f64::consts::FRAC_PI_2;
            let g = (2.0 * next() - 1.0) * std::f64::consts::PI;
            rotations.push(cardan_matrix(&Vector3::new(a, b, g)));
            rotations.push(
                (UnitQuaternion::from_scaled_axis(Vector3::new(a, b, g) * 0.7))
                    .to_rotation_matrix()
                    .into_inner(),
            );
        }
        let h = std::f64::consts::FRAC_PI_2;
        for s in [-1.0, 1.0] {
            for d in [0.0, 1e-16, 1e-12, 1e-9, 1e-8, 1e-6, -1e-9] {
                for (a, g) in [(0.0, 0.0), (0.3, -1.1), (-2.0, 2.5)] {
                    rotations.push(cardan_matrix(&Vector3::new(a, s * (h - d), g)));
                }
            }
            let mut r = cardan_matrix(&Vector3::new(0.2, s * h, 0.4));
            r[(0, 2)] = s * (1.0 + 1e-15);
            rotations.push(r);
        }
        for k in 0..4 {
            let t = k as f64 * h;
            for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
                rotations.push(
                    UnitQuaternion::from_scaled_axis(axis * t)
                        .to_rotation_matrix()
                        .into_inner(),
                );
            }
        }
        let p = Vector3::new(0.1, -0.2, 0.3);
        for r in &rotations {
            let mut q = [0.0; 6];
            NodeKind::PoseCardan.set_pose(&mut q, &p, r);
            let old = old_set_pose_cardan(r);
            for i in 0..3 {
                assert_eq!(q[3 + i].to_bits(), old[i].to_bits(), "{r} angle {i}");
            }
            assert_eq!(&q[..3], p.as_slice());
        }
        assert!(rotations.len() > 1000);
    }

    /// A non-finite matrix gives NaN angles (before: NaN in the angles that read a NaN entry).
    #[test]
    fn pose_cardan_set_pose_of_a_nan_matrix_is_nan() {
        let mut r = Matrix3::identity();
        r[(0, 2)] = f64::NAN;
        let mut q = [0.0; 6];
        NodeKind::PoseCardan.set_pose(&mut q, &Vector3::zeros(), &r);
        assert!(q[3..].iter().all(|x| x.is_nan()));
    }
}
