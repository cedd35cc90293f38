//! The point-mass body: a particle of mass `m` on one `Vector(3)` node, its global position
//! (`q = x`, `u = ẋ`, `M = m 1`, `h = m g`). It has no rotations: its frames translate with it and
//! keep their global axes (`J_R = 0`), so joints that lock rotations and torques must not act on
//! it (the model compiler refuses them).

use crate::element::{Element, ElementScratch, FrameKinematics, LocalFrame, TangentScratch};
use crate::NodeKind;
use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

/// A particle of mass `mass` (kg).
#[derive(Debug, Clone, PartialEq)]
pub struct PointMass {
    mass: f64,
}

impl PointMass {
    /// A particle of mass `mass` (> 0, checked by [`Element::validate`]).
    pub fn new(mass: f64) -> Self {
        Self { mass }
    }

    /// Its mass.
    pub fn mass(&self) -> f64 {
        self.mass
    }
}

const KINDS: [NodeKind; 1] = [NodeKind::Vector(3)];

fn vec3(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

impl Element for PointMass {
    fn node_kinds(&self) -> &[NodeKind] {
        &KINDS
    }
    fn nq(&self) -> usize {
        3
    }
    fn nu(&self) -> usize {
        3
    }
    fn validate(&self) -> Result<(), String> {
        if self.mass > 0.0 && self.mass.is_finite() {
            Ok(())
        } else {
            Err(format!(
                "point mass must be > 0 and finite, got {}",
                self.mass
            ))
        }
    }
    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        q.fill(0.0);
        u.fill(0.0);
    }
    /// Places the particle at `position`; a particle has no orientation (`rotation` is ignored).
    fn set_pose(&self, q: &mut [f64], position: &Vector3<f64>, _rotation: &Matrix3<f64>) {
        q.copy_from_slice(position.as_slice());
    }
    /// Sets the velocity; a particle has no angular velocity (`omega` is ignored).
    fn set_velocity(&self, _q: &[f64], u: &mut [f64], v: &Vector3<f64>, _omega: &Vector3<f64>) {
        u.copy_from_slice(v.as_slice());
    }
    fn q_dot(&self, _q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        q_dot.copy_from_slice(u);
    }
    fn mass_matrix(&self, _q: &[f64], _s: &mut ElementScratch, mut m: MatMut<'_, f64>) {
        m.fill(0.0);
        for i in 0..3 {
            m[(i, i)] = self.mass;
        }
    }
    fn forces(
        &self,
        _t: f64,
        _q: &[f64],
        _u: &[f64],
        gravity: &Vector3<f64>,
        _s: &mut ElementScratch,
        h: &mut [f64],
    ) {
        h.copy_from_slice((gravity * self.mass).as_slice());
    }
    /// Frame origin `x + p` with the frame's offset `p` in global axes, axes fixed in space.
    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        _s: &mut ElementScratch,
        f: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        out.position = vec3(q) + f.position;
        out.rotation = f.rotation;
        out.velocity = vec3(u);
        out.angular_velocity = Vector3::zeros();
        out.bias_acc = Vector3::zeros();
        out.bias_ang_acc = Vector3::zeros();
        out.jac_t.fill(0.0);
        out.jac_r.fill(0.0);
        for i in 0..3 {
            out.jac_t[(i, i)] = 1.0;
        }
    }
    /// Gravity is the only force: no tangent.
    fn force_tangents(
        &self,
        _t: f64,
        _q: &[f64],
        _u: &[f64],
        _g: &Vector3<f64>,
        _s: &mut ElementScratch,
        mut dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
        _fd: &mut TangentScratch,
    ) {
        dh_dq.fill(0.0);
        dh_du.fill(0.0);
    }
    /// `J_T = 1` is constant and the frame axes do not turn: a force has no load tangent.
    fn force_load_tangent(
        &self,
        _q: &[f64],
        _u: &[f64],
        _s: &mut ElementScratch,
        _frame: &LocalFrame,
        _force: &Vector3<f64>,
        _follower: bool,
        mut out: MatMut<'_, f64>,
    ) -> bool {
        out.fill(0.0);
        true
    }
    fn kinetic_energy(&self, _q: &[f64], u: &[f64], _s: &mut ElementScratch) -> f64 {
        0.5 * self.mass * vec3(u).norm_squared()
    }
    fn gravity_potential(&self, q: &[f64], g: &Vector3<f64>, _s: &mut ElementScratch) -> f64 {
        -self.mass * g.dot(&vec3(q))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::finite_difference_tangents;

    /// The analytic tangents (zero) and frame Jacobians equal finite differences.
    #[test]
    fn tangents_and_frame_jacobian_match_finite_differences() {
        let p = PointMass::new(2.5);
        let (q, u) = ([0.3, -1.0, 2.0], [0.1, 0.2, -0.4]);
        let g = Vector3::new(0.0, 0.0, -9.81);
        let mut fd = TangentScratch::new(&p);
        let (mut kq, mut ku) = (faer::Mat::zeros(3, 3), faer::Mat::zeros(3, 3));
        finite_difference_tangents(&p, 0.0, &q, &u, &g, kq.as_mut(), ku.as_mut(), &mut fd);
        assert_eq!(kq.norm_max() + ku.norm_max(), 0.0);
        let frame = LocalFrame::at(Vector3::new(0.0, 0.5, 0.0));
        let mut s = ElementScratch::empty();
        let mut k = FrameKinematics::new(3);
        p.frame_kinematics(&q, &u, &mut s, &frame, &mut k);
        assert_eq!(k.position, Vector3::new(0.3, -0.5, 2.0));
        let mut k2 = FrameKinematics::new(3);
        let dq = [0.0, 1e-6, 0.0];
        let q2: Vec<f64> = q.iter().zip(dq).map(|(a, b)| a + b).collect();
        p.frame_kinematics(&q2, &u, &mut s, &frame, &mut k2);
        let fd_col = (k2.position - k.position) / 1e-6;
        assert!(
            (fd_col - Vector3::new(k.jac_t[(0, 1)], k.jac_t[(1, 1)], k.jac_t[(2, 1)])).norm()
                < 1e-9
        );
        assert!((p.kinetic_energy(&q, &u, &mut s) - 0.5 * 2.5 * 0.21).abs() < 1e-15);
        assert!(PointMass::new(0.0).validate().is_err());
        assert!(PointMass::new(f64::NAN).validate().is_err());
    }
}
