//! The FFR body as a [`NeutralContourSource`]: frame `(R, A)`, field coordinates the modal
//! coordinates `q_f`, velocity coordinates `u = [Ṙ, w, q̇_f]` with `ω̄ = H w`, so
//! `J_T = [I, -A ū~ H, A Φ]`, `J_π = [0, A H, 0]`, `J_q = [0, 0, I]`.

use crate::contour_source::{ContourNodes, NeutralContourSource};
use crate::ffr::{FfrBody, FfrEval, FfrScratch};
use crate::rotation::skew;
use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

impl ContourNodes for FfrBody {
    fn num_nodes(&self) -> usize {
        FfrBody::num_nodes(self)
    }
    fn node_position(&self, i: usize) -> Vector3<f64> {
        self.u0[i]
    }
    fn num_fields(&self) -> usize {
        self.nf()
    }
    fn node_shape(&self, i: usize, k: usize) -> Vector3<f64> {
        let col = self.modes_t.column(k);
        Vector3::new(col[3 * i], col[3 * i + 1], col[3 * i + 2])
    }
    fn num_velocities(&self) -> usize {
        6 + self.nf()
    }
}

impl NeutralContourSource for FfrScratch {
    fn frame_rotation(&self) -> &Matrix3<f64> {
        &self.a
    }
    fn frame_angular_velocity(&self) -> &Vector3<f64> {
        &self.omega
    }
    fn field_coordinates(&self) -> &[f64] {
        self.qf.as_slice()
    }
    fn field_velocities(&self) -> &[f64] {
        self.qfd.as_slice()
    }
    fn num_velocities(&self) -> usize {
        6 + self.qf.len()
    }

    /// `J_T = [I, -A ū~ H, A Φ]`.
    fn point_jacobian(&self, u: &Vector3<f64>, phi: &[Vector3<f64>], mut jt: MatMut<'_, f64>) {
        let s = self;
        let b: Matrix3<f64> = -s.a * skew(u) * s.h;
        for i in 0..3 {
            for j in 0..3 {
                jt[(i, j)] = if i == j { 1.0 } else { 0.0 };
                jt[(i, 3 + j)] = b[(i, j)];
            }
        }
        for (k, p) in phi.iter().enumerate() {
            let col = s.a * p;
            for i in 0..3 {
                jt[(i, 6 + k)] = col[i];
            }
        }
    }

    /// The angular-velocity columns get `-A [Aᵀ d]~ H`.
    fn add_arm_jacobian(&self, d: &Vector3<f64>, mut jac: MatMut<'_, f64>) {
        let s = self;
        if *d == Vector3::zeros() {
            return;
        }
        let db = s.a.transpose() * d;
        let m = -s.a * skew(&db) * s.h;
        for i in 0..3 {
            for j in 0..3 {
                jac[(i, 3 + j)] += m[(i, j)];
            }
        }
    }

    fn rotation_jacobian(&self, mut jac: MatMut<'_, f64>) {
        let ah = self.a * self.h;
        for j in 0..jac.ncols() {
            for i in 0..3 {
                jac[(i, j)] = if (3..6).contains(&j) {
                    ah[(i, j - 3)]
                } else {
                    0.0
                };
            }
        }
    }

    fn add_rotation_row(&self, v: &Vector3<f64>, scale: f64, out: &mut [f64]) {
        let h = self.h.transpose() * v;
        for k in 0..3 {
            out[3 + k] += scale * h[k];
        }
    }

    fn add_field_row(&self, c: &dyn Fn(usize) -> f64, out: &mut [f64]) {
        for (k, o) in out[6..].iter_mut().enumerate() {
            *o += c(k);
        }
    }
}

/// The element's scratch content delegates to its evaluated state.
impl NeutralContourSource for FfrEval {
    fn frame_rotation(&self) -> &Matrix3<f64> {
        self.state.frame_rotation()
    }
    fn frame_angular_velocity(&self) -> &Vector3<f64> {
        self.state.frame_angular_velocity()
    }
    fn field_coordinates(&self) -> &[f64] {
        self.state.field_coordinates()
    }
    fn field_velocities(&self) -> &[f64] {
        self.state.field_velocities()
    }
    fn num_velocities(&self) -> usize {
        self.state.num_velocities()
    }
    fn point_jacobian(&self, u: &Vector3<f64>, phi: &[Vector3<f64>], jt: MatMut<'_, f64>) {
        self.state.point_jacobian(u, phi, jt)
    }
    fn add_arm_jacobian(&self, d: &Vector3<f64>, jac: MatMut<'_, f64>) {
        self.state.add_arm_jacobian(d, jac)
    }
    fn rotation_jacobian(&self, jac: MatMut<'_, f64>) {
        self.state.rotation_jacobian(jac)
    }
    fn add_rotation_row(&self, v: &Vector3<f64>, scale: f64, out: &mut [f64]) {
        self.state.add_rotation_row(v, scale, out)
    }
    fn add_field_row(&self, c: &dyn Fn(usize) -> f64, out: &mut [f64]) {
        self.state.add_field_row(c, out)
    }
}
