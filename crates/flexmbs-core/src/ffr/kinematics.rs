//! Node kinematics of an FFR body: position (2.24), velocity (2.32), Jacobians of translation
//! (2.70) and rotation (2.72) and the acceleration bias terms `J_dot u` needed by constraints;
//! generalized forces of point forces and torques (2.76).
//!
//! **Node frames with rotational modes** (beam nodes) extend (2.71), (2.72) exactly. The elastic
//! rotation vector of node `p` is `theta = Phi_r^p q_f`; the node frame is the orthonormal
//!
//! `F = A exp(skew(theta))`
//!
//! (not the linearized `A (I + skew(theta))`). With `exp(skew(theta))_dot exp(skew(theta))^T =
//! skew(J_l(theta) theta_dot)` (the SO(3) left Jacobian [`so3_left_jacobian`]) and
//! `A^T A_dot = skew(omega_bar)`:
//!
//! `skew(omega) = F_dot F^T = A skew(omega_bar + J_l(theta) theta_dot) A^T`, so
//! `omega = A (omega_bar + J_l Phi_r q_f_dot)` and, with `omega_bar = H w`,
//!
//! `J_R = [0, A H, A J_l(theta) Phi_r]` ((2.72) with the elastic term exact at any `q_f`).
//!
//! Differentiating `omega = A (H w + J_l theta_dot)` once more (`A_dot = A skew(omega_bar)`):
//! `omega_dot = J_R u_dot + A [omega_bar x (J_l theta_dot) + H_dot w + J_l_dot theta_dot]`,
//! the last bracket (times `A`) being the bias `J_R_dot u` ([`so3_left_jacobian_dot`]).
//! At `q_f = 0` all of this reduces to the linear formulas (`J_l(0) = I`, `J_l_dot(0) theta_dot
//! = skew(theta_dot)/2 theta_dot = 0`).
//!
//! All functions need [`FfrBody::update`] first and cost O(n_f) per node.

use super::{FfrBody, FfrError, FfrScratch};
use crate::rotation::{rotation_vector_matrix, skew, so3_left_jacobian, so3_left_jacobian_dot};
use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

/// Kinematic state of one node (global components unless noted).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodeKinematics {
    /// Deformed local position `ū = u0 + Φ q_f` (2.23), body frame.
    pub u_bar: Vector3<f64>,
    /// Position `r = R + A ū` (2.24).
    pub r: Vector3<f64>,
    /// Velocity `r_dot = R_dot + A (ω̄ × ū + Φ q_f_dot)` (2.32).
    pub v: Vector3<f64>,
    /// Translational bias acceleration `J_dot_T u = A [ω̄×(ω̄×ū) + 2 ω̄×(Φ q_f_dot) + (H_dot w)×ū]`.
    pub a_bias: Vector3<f64>,
    /// Orientation of the node frame `A exp(skew(θ))`, `θ = Φ_r q_f` (orthonormal; `A` without
    /// rotational modes).
    pub frame: Matrix3<f64>,
    /// Angular velocity `A (ω̄ + J_l(θ) Φ_r q_f_dot)` ((2.71) with rotational modes).
    pub omega: Vector3<f64>,
    /// Rotational bias acceleration `J_dot_R u = A [ω̄ × (J_l θ_dot) + H_dot w + J_l_dot θ_dot]`.
    pub alpha_bias: Vector3<f64>,
}

impl FfrBody {
    fn check_node(&self, node: usize) -> Result<(), FfrError> {
        if node < self.num_nodes() {
            Ok(())
        } else {
            Err(FfrError::NodeOutOfRange {
                node,
                nodes: self.num_nodes(),
            })
        }
    }

    /// True if node `node` does not move relative to the floating frame: its translational
    /// (and, if the body has them, rotational) mode rows are all exactly zero, as for the fixed
    /// nodes of a clamped reduction.
    pub fn node_is_fixed(&self, node: usize) -> bool {
        let zero = |m: &nalgebra::DMatrix<f64>| {
            (3 * node..3 * node + 3).all(|r| m.row(r).iter().all(|x| *x == 0.0))
        };
        node < self.num_nodes() && zero(&self.modes_t) && self.modes_r.as_ref().is_none_or(zero)
    }

    /// True if the floating frame moves with material of the body, so that a frame fixed in it
    /// (`r = R + A p`, no mode rows) is a rigid extension of that material: the body has no
    /// modes, or its modes are clamped, i.e. they fix a node with rotations (beam node: zero
    /// translational and rotational rows) or three non-collinear nodes (solid nodes).
    ///
    /// Otherwise (free-free modes, Craig-Bampton bodies) the floating frame is, to first order, a
    /// mean-axis frame of the body, not a material point: a joint at a frame fixed in it
    /// constrains an abstract frame and misses the local compliance of the body there.
    pub fn floating_frame_is_material(&self) -> bool {
        if self.nf() == 0 {
            return true;
        }
        let fixed: Vec<Vector3<f64>> = (0..self.num_nodes())
            .filter(|&j| self.node_is_fixed(j))
            .map(|j| self.u0[j])
            .collect();
        if self.modes_r.is_some() && !fixed.is_empty() {
            return true;
        }
        spans_a_plane(&fixed)
    }

    /// Elastic displacement `u_f = Φ^p q_f` of node `node` in body-frame axes (seed 000 (2.8)),
    /// for post-processing; `q_f` has length n_f (e.g. the last n_f entries of the body's `q`).
    pub fn node_deformation(&self, node: usize, q_f: &[f64]) -> Result<Vector3<f64>, FfrError> {
        self.check_node(node)?;
        if q_f.len() != self.nf() {
            return Err(FfrError::DimensionMismatch {
                what: "q_f",
                expected: self.nf(),
                found: q_f.len(),
            });
        }
        let mut v = Vector3::zeros();
        for k in 0..3 {
            for (a, x) in q_f.iter().enumerate() {
                v[k] += self.modes_t[(3 * node + k, a)] * x;
            }
        }
        Ok(v)
    }

    /// `Φ^p x` for the 3 rows of node `p` of `modes` (O(3 n_f)).
    fn mode_rows_times(
        modes: &nalgebra::DMatrix<f64>,
        node: usize,
        x: &nalgebra::DVector<f64>,
    ) -> Vector3<f64> {
        let mut v = Vector3::zeros();
        for k in 0..3 {
            for a in 0..x.len() {
                v[k] += modes[(3 * node + k, a)] * x[a];
            }
        }
        v
    }

    /// Global position, frame, velocities and bias accelerations of node `node` for the state of
    /// `s` (needs [`FfrBody::update`]), with `R` and `R_dot` from `q` and `u`.
    pub fn node_kinematics(
        &self,
        node: usize,
        q: &[f64],
        u: &[f64],
        s: &FfrScratch,
    ) -> Result<NodeKinematics, FfrError> {
        self.check_node(node)?;
        let phi_q = Self::mode_rows_times(&self.modes_t, node, &s.qf);
        let phi_qd = Self::mode_rows_times(&self.modes_t, node, &s.qfd);
        let u_bar = self.u0[node] + phi_q;
        let w = s.omega;
        let z = s.hdot_w;
        let r = Vector3::new(q[0], q[1], q[2]) + s.a * u_bar;
        let v = Vector3::new(u[0], u[1], u[2]) + s.a * (w.cross(&u_bar) + phi_qd);
        let a_bias = s.a * (w.cross(&w.cross(&u_bar)) + 2.0 * w.cross(&phi_qd) + z.cross(&u_bar));
        let (frame, omega, alpha_bias) = match &self.modes_r {
            Some(mr) => {
                let th = Self::mode_rows_times(mr, node, &s.qf);
                let thd = Self::mode_rows_times(mr, node, &s.qfd);
                let jl_thd = so3_left_jacobian(&th) * thd;
                let jl_dot_thd = so3_left_jacobian_dot(&th, &thd) * thd;
                (
                    s.a * rotation_vector_matrix(&th),
                    s.a * (w + jl_thd),
                    s.a * (w.cross(&jl_thd) + z + jl_dot_thd),
                )
            }
            None => (s.a, s.a * w, s.a * z),
        };
        Ok(NodeKinematics {
            u_bar,
            r,
            v,
            a_bias,
            frame,
            omega,
            alpha_bias,
        })
    }

    /// Jacobian of translation of node `node`, `J_T = [I, -A ũ H, A Φ]` (2.70), into `jt`
    /// (3 x n_u).
    pub fn node_jacobian_translation(
        &self,
        node: usize,
        s: &FfrScratch,
        mut jt: MatMut<'_, f64>,
    ) -> Result<(), FfrError> {
        self.check_node(node)?;
        let u_bar = self.u0[node] + Self::mode_rows_times(&self.modes_t, node, &s.qf);
        let b = -s.a * skew(&u_bar) * s.h;
        for i in 0..3 {
            for j in 0..3 {
                jt[(i, j)] = if i == j { 1.0 } else { 0.0 };
                jt[(i, 3 + j)] = b[(i, j)];
            }
            for a in 0..self.nf() {
                let mut acc = 0.0;
                for k in 0..3 {
                    acc += s.a[(i, k)] * self.modes_t[(3 * node + k, a)];
                }
                jt[(i, 6 + a)] = acc;
            }
        }
        Ok(())
    }

    /// `A J_l(θ)` of node `node` (`θ = Φ_r q_f`), the factor of `Φ_r` in `J_R`; `None` without
    /// rotational modes.
    fn elastic_rotation_factor(&self, node: usize, s: &FfrScratch) -> Option<Matrix3<f64>> {
        let mr = self.modes_r.as_ref()?;
        let th = Self::mode_rows_times(mr, node, &s.qf);
        Some(s.a * so3_left_jacobian(&th))
    }

    /// Jacobian of rotation of node `node`, `J_R = [0, A H, A J_l(θ) Φ_r]` ((2.72) extended
    /// exactly by the rotational modes, see the module doc; zero without them), into `jr`
    /// (3 x n_u).
    pub fn node_jacobian_rotation(
        &self,
        node: usize,
        s: &FfrScratch,
        mut jr: MatMut<'_, f64>,
    ) -> Result<(), FfrError> {
        self.check_node(node)?;
        let ah = s.a * s.h;
        let factor = self.elastic_rotation_factor(node, s);
        for i in 0..3 {
            for j in 0..3 {
                jr[(i, j)] = 0.0;
                jr[(i, 3 + j)] = ah[(i, j)];
            }
            for a in 0..self.nf() {
                let mut acc = 0.0;
                if let (Some(mr), Some(f)) = (&self.modes_r, &factor) {
                    for k in 0..3 {
                        acc += f[(i, k)] * mr[(3 * node + k, a)];
                    }
                }
                jr[(i, 6 + a)] = acc;
            }
        }
        Ok(())
    }

    /// Adds the generalized force `J_T^T F` (2.76) of a global force `f` at node `node` to `out`.
    pub fn add_node_force(
        &self,
        node: usize,
        f: &Vector3<f64>,
        s: &FfrScratch,
        out: &mut [f64],
    ) -> Result<(), FfrError> {
        self.check_node(node)?;
        let u_bar = self.u0[node] + Self::mode_rows_times(&self.modes_t, node, &s.qf);
        let fb = s.a.transpose() * f;
        // (-A ũ H)^T F = H^T ũ A^T F = H^T (ū × F_bar)
        let tw = s.h.transpose() * u_bar.cross(&fb);
        for i in 0..3 {
            out[i] += f[i];
            out[3 + i] += tw[i];
        }
        for a in 0..self.nf() {
            let mut acc = 0.0;
            for k in 0..3 {
                acc += self.modes_t[(3 * node + k, a)] * fb[k];
            }
            out[6 + a] += acc;
        }
        Ok(())
    }

    /// Adds the generalized force `J_R^T τ` (2.76) of a global torque `tau` at node `node` to `out`.
    pub fn add_node_torque(
        &self,
        node: usize,
        tau: &Vector3<f64>,
        s: &FfrScratch,
        out: &mut [f64],
    ) -> Result<(), FfrError> {
        self.check_node(node)?;
        let tb = s.a.transpose() * tau;
        let tw = s.h.transpose() * tb;
        for i in 0..3 {
            out[3 + i] += tw[i];
        }
        if let (Some(mr), Some(f)) = (&self.modes_r, self.elastic_rotation_factor(node, s)) {
            // (A J_l Φ_r)^T τ = Φ_r^T (J_l^T A^T τ)
            let te = f.transpose() * tau;
            for a in 0..self.nf() {
                let mut acc = 0.0;
                for k in 0..3 {
                    acc += mr[(3 * node + k, a)] * te[k];
                }
                out[6 + a] += acc;
            }
        }
        Ok(())
    }
}

/// True if the points are not all collinear (three of them span a plane), to a relative
/// tolerance of 1e-9 of their extent.
fn spans_a_plane(points: &[Vector3<f64>]) -> bool {
    let Some(p0) = points.first() else {
        return false;
    };
    let Some(p1) = points
        .iter()
        .max_by(|a, b| (*a - p0).norm().total_cmp(&(*b - p0).norm()))
    else {
        return false;
    };
    let axis = p1 - p0;
    let extent = axis.norm();
    if extent == 0.0 {
        return false;
    }
    let n = axis / extent;
    points
        .iter()
        .any(|p| (p - p0).cross(&n).norm() > 1e-9 * extent)
}
