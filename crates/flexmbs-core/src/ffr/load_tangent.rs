//! Analytic tangent of a point force on an FFR body: `d(J_T^T f)/dq` along `q ⊕ dv`, O(n_f) per
//! load instead of the O(n_f^2) of central differences over all the body's coordinates.
//!
//! With `ū = u_0 + Φ_t q_f` the node (or point) in body axes, `H` the map `ω̄ = H w`, and `f̄ = Aᵀ f`
//! the force in body axes, the generalized force (seed 000 (2.76) with `J_T` of (2.70)) is
//!
//! ```text
//!     Q_R = A f̄,    Q_θ = Hᵀ (ū × f̄),    Q_f = Φ_tᵀ f̄.
//! ```
//!
//! A rotation increment `dv_θ` turns the floating frame by `δφ = H dv_θ` in body axes
//! (`δA = A δφ~`: the exponential map for quaternions, `Ȧ = A (Ḡ θ̇)~` for Cardan angles); a
//! modal increment moves the node by `Φ_t δq_f` and turns its frame by `J_l(θ_e) Φ_r δq_f`
//! (`θ_e = Φ_r q_f`, the exact node rotation `exp(θ_e~)`). Two kinds of force:
//! * **dead** (fixed in space): `f` constant, so `δf̄ = f̄~ δφ`;
//! * **follower** (fixed in the frame): `f̄ = C f_l` with `C = exp(θ_e~) R_l` (the frame's
//!   orientation in body axes), so `δf̄ = -f̄~ J_l Φ_r δq_f`, and `Q_R = A f̄` turns with `A`.
//!
//! For Cardan angles `H = Ḡ(θ)` depends on `θ`: the term `(∂Ḡ/∂θ_k)ᵀ (ū × f̄)` uses
//! [`crate::rotation::cardan_g_bar_dot`] with `θ̇ = e_k` (it is linear in `θ̇`).

use super::{FfrBody, FfrScratch, RotationParam};
use crate::element::LocalFrame;
use crate::rotation::{cardan_g_bar_dot, skew, so3_left_jacobian};
use faer::MatMut;
use nalgebra::{DMatrix, Matrix3, Vector3};

impl FfrBody {
    /// Overwrites `out` (n_u x n_u) with `d(J_T^T f)/dq` of a force at `frame` (a mesh-node frame
    /// or a point fixed in the floating frame) for the state evaluated in `s`: `force` is the
    /// global force (dead), or with `follower` the force in the frame's axes; `q` the body's
    /// coordinates (Cardan angles). See the module documentation. `None` for a mesh node the body
    /// does not have. No allocation.
    pub fn force_load_tangent(
        &self,
        q: &[f64],
        frame: &LocalFrame,
        force: &Vector3<f64>,
        follower: bool,
        s: &FfrScratch,
        mut out: MatMut<'_, f64>,
    ) -> Option<()> {
        let nf = self.nf();
        let node = match frame.mesh_node {
            Some(n) if n < self.num_nodes() => Some(n),
            Some(_) => return None,
            None => None,
        };
        let (mut u_bar, mut th_e) = (frame.position, Vector3::zeros());
        if let Some(n) = node {
            u_bar = self.u0[n];
            for (a, x) in s.qf.iter().enumerate() {
                u_bar += Vector3::from_column_slice(
                    &self.modes_t.column(a).as_slice()[3 * n..3 * n + 3],
                ) * *x;
                if let Some(mr) = &self.modes_r {
                    th_e +=
                        Vector3::from_column_slice(&mr.column(a).as_slice()[3 * n..3 * n + 3]) * *x;
                }
            }
        }
        let (a, h) = (s.a, s.h);
        // the force in body axes and the rotation of the frame's modal columns (J_l Φ_r)
        let (f_bar, jl) = if follower {
            let c = match (node, &self.modes_r) {
                (Some(_), Some(_)) => crate::rotation::rotation_vector_matrix(&th_e),
                _ => Matrix3::identity(),
            };
            (c * frame.rotation * force, so3_left_jacobian(&th_e))
        } else {
            (a.transpose() * force, Matrix3::zeros())
        };
        let has_rot_modes = follower && node.is_some() && self.modes_r.is_some();
        out.fill(0.0);
        let fx = skew(&f_bar);
        // rotation columns: dead Q_θ = Hᵀ ū~ f̄~ H; follower Q_R = -A f̄~ H; both the Cardan ∂H term
        let mut q_th = if follower {
            set_block(&mut out, 0, 3, &(-a * fx * h));
            Matrix3::zeros()
        } else {
            h.transpose() * skew(&u_bar) * fx * h
        };
        if self.rotation == RotationParam::Cardan {
            let th = Vector3::new(q[3], q[4], q[5]);
            let x = u_bar.cross(&f_bar);
            for k in 0..3 {
                let col = cardan_g_bar_dot(&th, &Vector3::ith(k, 1.0)).transpose() * x;
                for i in 0..3 {
                    q_th[(i, k)] += col[i];
                }
            }
        }
        set_block(&mut out, 3, 3, &q_th);
        // modal columns: d f̄ / d q_f = -f̄~ J_l Φ_r (follower at a node with rotational modes)
        let ht = h.transpose();
        let ux = skew(&u_bar);
        let node_rows = |m: &DMatrix<f64>, c: usize| match node {
            Some(n) => Vector3::from_column_slice(&m.column(c).as_slice()[3 * n..3 * n + 3]),
            None => Vector3::zeros(),
        };
        for c in 0..nf {
            let phi = node_rows(&self.modes_t, c);
            let df = match (&self.modes_r, has_rot_modes) {
                (Some(mr), true) => -fx * (jl * node_rows(mr, c)),
                _ => Vector3::zeros(),
            };
            if follower {
                let d_qr = a * df;
                for i in 0..3 {
                    out[(i, 6 + c)] = d_qr[i];
                }
            }
            let d_qth = ht * (phi.cross(&f_bar) + ux * df);
            for i in 0..3 {
                out[(3 + i, 6 + c)] = d_qth[i];
            }
            if has_rot_modes {
                // Q_f = Φ_tᵀ f̄: the dense (rank-3) modal block Φ_tᵀ δf̄
                for r in 0..nf {
                    out[(6 + r, 6 + c)] = node_rows(&self.modes_t, r).dot(&df);
                }
            }
        }
        // modal rows, rotation columns (dead force only): Φ_tᵀ f̄~ H
        if !follower {
            let fh = fx * h;
            for r in 0..nf {
                let row = node_rows(&self.modes_t, r).transpose() * fh;
                for j in 0..3 {
                    out[(6 + r, 3 + j)] = row[j];
                }
            }
        }
        Some(())
    }
}

/// `out[r0.., c0..] = b` (3 x 3).
fn set_block(out: &mut MatMut<'_, f64>, r0: usize, c0: usize, b: &Matrix3<f64>) {
    for i in 0..3 {
        for j in 0..3 {
            out[(r0 + i, c0 + j)] = b[(i, j)];
        }
    }
}
