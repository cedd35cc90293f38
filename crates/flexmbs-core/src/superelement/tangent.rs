//! The analytic tangent `∂h/∂v` of the superelement forces (seed 001 (4.25), (4.32), (4.37),
//! (4.39)), extended by the variation of the rotation-vector measure (`Λ`) and gravity.
//!
//! With `h = −Pᵀ w_t`, `w_t = w − f_g`, `δq_loc = W P δv` (`W = Λ T`) and the frame variation
//! `δf = Z P δv`:
//!
//! ```text
//! −∂h/∂v = A₁(w_t) + Pᵀ L W P − Pᵀ M_G g~ Z_r P
//!   A₁: variation of Pᵀ (R_j and R_k in P)                     ~ K₃ (4.37)
//!   L = Wᵀ K_CB + Z_rᵀ F̂ + Tᵀ D   (exact)                      K₁ (4.25), K₂ (4.32), δΛ
//!     = (1 − Φ_rig,0 Φ_CB)ᵀ K_CB  (approximated)
//! ```
//!
//! `F̂` (3 x n) holds `w_k~` in the translation columns of interface `k` (the variation of
//! `[Φ_rig]ᵀ w`), `D` the blocks `∂(J_l⁻ᵀ(θ_k) ŝ_k)/∂θ_k`.

use super::eval::SuperelementEval;
use super::rotvec::inverse_left_jacobian_transpose_derivative;
use super::{Superelement, TransformMatrices};
use crate::rotation::skew;
use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

impl Superelement {
    /// `Z = B⁻¹ [Φ_CB] Λ` and `Z P` into `e.work.z`, `e.work.zp`: the variation of the floating
    /// frame (axes of the frame) per velocity-space variation of the coordinates (3.17).
    pub(super) fn frame_variation(&self, e: &mut SuperelementEval) {
        let n = self.n();
        for i in 0..6 {
            for j in 0..n {
                e.work.z[(i, j)] = (0..6).map(|r| e.b_inv[(i, r)] * e.phi_t[(r, j)]).sum();
            }
        }
        super::product_into(&mut e.work.zp, &e.work.z, &e.p, false);
    }

    /// `T`, `W = Λ T` and `W P` into `e.work`.
    fn local_variation(&self, e: &mut SuperelementEval) {
        let n = self.n();
        super::product_into(&mut e.work.t, &e.phi_rig, &e.work.z, false);
        e.work.t.neg_mut();
        for i in 0..n {
            e.work.t[(i, i)] += 1.0;
        }
        e.work.wm.copy_from(&e.work.t);
        for (k, l) in e.lam.iter().enumerate() {
            for j in 0..n {
                let v = l * Vector3::new(
                    e.work.t[(6 * k + 3, j)],
                    e.work.t[(6 * k + 4, j)],
                    e.work.t[(6 * k + 5, j)],
                );
                for r in 0..3 {
                    e.work.wm[(6 * k + 3 + r, j)] = v[r];
                }
            }
        }
        super::product_into(&mut e.work.wp, &e.work.wm, &e.p, false);
    }

    /// `L` of the module docs into `e.work.a`.
    fn force_variation(&self, e: &mut SuperelementEval) {
        match self.matrices {
            TransformMatrices::Approximated => {
                super::product_into(&mut e.work.a, &self.t0, &self.data.k_cb, true);
            }
            TransformMatrices::Exact => {
                super::product_into(&mut e.work.a, &e.work.wm, &self.data.k_cb, true);
                let n = self.n();
                for k in 0..self.n_interfaces() {
                    // Z_rᵀ F̂: columns of the translation of interface k
                    let wk = skew(&Vector3::new(e.w[6 * k], e.w[6 * k + 1], e.w[6 * k + 2]));
                    // Tᵀ D: columns of the rotation of interface k
                    let theta = e.q_loc.fixed_rows::<3>(6 * k + 3).into_owned();
                    let s_k = e.s_hat.fixed_rows::<3>(6 * k + 3).into_owned();
                    let d = inverse_left_jacobian_transpose_derivative(&theta, &s_k);
                    for i in 0..n {
                        let zr = Vector3::new(e.work.z[(3, i)], e.work.z[(4, i)], e.work.z[(5, i)]);
                        let tr = Vector3::new(
                            e.work.t[(6 * k + 3, i)],
                            e.work.t[(6 * k + 4, i)],
                            e.work.t[(6 * k + 5, i)],
                        );
                        let f = wk.transpose() * zr;
                        let g = d.transpose() * tr;
                        for c in 0..3 {
                            e.work.a[(i, 6 * k + c)] += f[c];
                            e.work.a[(i, 6 * k + 3 + c)] += g[c];
                        }
                    }
                }
            }
        }
    }

    /// `∂h/∂v` (module docs) into `dh_dq`.
    pub(super) fn force_tangent(
        &self,
        e: &mut SuperelementEval,
        gravity: &Vector3<f64>,
        mut dh_dq: MatMut<'_, f64>,
    ) {
        let n = self.n();
        let g_loc = e.rj.transpose() * gravity;
        e.f_g.gemv(1.0, &self.m_g, &g_loc, 0.0);
        self.frame_variation(e);
        self.local_variation(e);
        self.force_variation(e);
        // b = L W P − M_G g~ Z_r P  (local rows), then c = Pᵀ b
        super::product_into(&mut e.work.b, &e.work.a, &e.work.wp, false);
        let gs = skew(&g_loc);
        for j in 0..n {
            let zr = gs * Vector3::new(e.work.zp[(3, j)], e.work.zp[(4, j)], e.work.zp[(5, j)]);
            for i in 0..n {
                e.work.b[(i, j)] -=
                    self.m_g[(i, 0)] * zr[0] + self.m_g[(i, 1)] * zr[1] + self.m_g[(i, 2)] * zr[2];
            }
        }
        super::product_into(&mut e.work.c, &e.p, &e.work.b, true);
        self.add_rotation_variation(e);
        for j in 0..n {
            for i in 0..n {
                dh_dq[(i, j)] = -e.work.c[(i, j)];
            }
        }
    }

    /// Adds `A₁(w_t)`, the variation of `Pᵀ w_t` through `R_j` and `R_k`, to `e.work.c`.
    fn add_rotation_variation(&self, e: &mut SuperelementEval) {
        let n = self.n();
        let rj = e.rj;
        for k in 0..self.n_interfaces() {
            let wt = |i: usize| e.w[i] - e.f_g[i];
            let wtk = Vector3::new(wt(6 * k), wt(6 * k + 1), wt(6 * k + 2));
            let wrk = Vector3::new(wt(6 * k + 3), wt(6 * k + 4), wt(6 * k + 5));
            let a_t: Matrix3<f64> = -rj * skew(&wtk);
            let rkt_rj = e.node_r[k].transpose() * rj;
            let a_r: Matrix3<f64> = -rkt_rj * skew(&wrk);
            let own = skew(&(rkt_rj * wrk));
            let (ct, cr) = (self.vel_index[6 * k], self.vel_index[6 * k + 3]);
            for j in 0..n {
                let ephi = Vector3::new(e.work.zp[(3, j)], e.work.zp[(4, j)], e.work.zp[(5, j)]);
                let (vt, vr) = (a_t * ephi, a_r * ephi);
                for i in 0..3 {
                    e.work.c[(ct + i, j)] += vt[i];
                    e.work.c[(cr + i, j)] += vr[i];
                }
            }
            for i in 0..3 {
                for j in 0..3 {
                    e.work.c[(cr + i, cr + j)] += own[(i, j)];
                }
            }
        }
    }
}
