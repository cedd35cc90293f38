//! A two-node spring-damper element for tests (`shared_nodes.rs`, `scattered_nodes.rs`).

use faer::MatMut;
use flexmbs_core::{Element, ElementScratch, FrameKinematics, LocalFrame, NodeKind};
use nalgebra::{Matrix3, Vector3};

/// A massless linear spring-damper between two `Vector(3)` nodes (the formula of
/// `Load::SpringDamper`); its frames are material points `x = (1 - xi) x1 + xi x2` with
/// `xi = LocalFrame::position.x`.
#[derive(Debug)]
pub struct Spring {
    pub stiffness: f64,
    pub damping: f64,
    pub free_length: f64,
}

impl Element for Spring {
    fn node_kinds(&self) -> &[NodeKind] {
        &[NodeKind::Vector(3), NodeKind::Vector(3)]
    }
    fn nq(&self) -> usize {
        6
    }
    fn nu(&self) -> usize {
        6
    }
    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        q.fill(0.0);
        u.fill(0.0);
    }
    fn set_pose(&self, _q: &mut [f64], _p: &Vector3<f64>, _r: &Matrix3<f64>) {}
    fn set_velocity(&self, _q: &[f64], _u: &mut [f64], _v: &Vector3<f64>, _w: &Vector3<f64>) {}
    fn q_dot(&self, _q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        q_dot.copy_from_slice(u);
    }
    fn mass_matrix(&self, _q: &[f64], _s: &mut ElementScratch, mut m: MatMut<'_, f64>) {
        m.fill(0.0);
    }
    #[allow(clippy::too_many_arguments)]
    fn forces(
        &self,
        _t: f64,
        q: &[f64],
        u: &[f64],
        _g: &Vector3<f64>,
        _s: &mut ElementScratch,
        h: &mut [f64],
    ) {
        let d = Vector3::new(q[3] - q[0], q[4] - q[1], q[5] - q[2]);
        let l = d.norm();
        let n = if l > 0.0 { d / l } else { Vector3::zeros() };
        let l_dot = n.dot(&Vector3::new(u[3] - u[0], u[4] - u[1], u[5] - u[2]));
        let f = self.stiffness * (l - self.free_length) + self.damping * l_dot;
        for i in 0..3 {
            h[i] = n[i] * f;
            h[3 + i] = -n[i] * f;
        }
    }
    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        _s: &mut ElementScratch,
        f: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        let xi = f.position.x;
        out.position = Vector3::from_fn(|i, _| (1.0 - xi) * q[i] + xi * q[3 + i]);
        out.rotation = f.rotation;
        out.velocity = Vector3::from_fn(|i, _| (1.0 - xi) * u[i] + xi * u[3 + i]);
        out.angular_velocity = Vector3::zeros();
        out.bias_acc = Vector3::zeros();
        out.bias_ang_acc = Vector3::zeros();
        out.jac_t.fill(0.0);
        out.jac_r.fill(0.0);
        for i in 0..3 {
            out.jac_t[(i, i)] = 1.0 - xi;
            out.jac_t[(i, 3 + i)] = xi;
        }
    }
    fn kinetic_energy(&self, _q: &[f64], _u: &[f64], _s: &mut ElementScratch) -> f64 {
        0.0
    }
    fn gravity_potential(&self, _q: &[f64], _g: &Vector3<f64>, _s: &mut ElementScratch) -> f64 {
        0.0
    }
    fn elastic_energy(&self, q: &[f64]) -> f64 {
        let l = Vector3::new(q[3] - q[0], q[4] - q[1], q[5] - q[2]).norm();
        0.5 * self.stiffness * (l - self.free_length).powi(2)
    }
}
