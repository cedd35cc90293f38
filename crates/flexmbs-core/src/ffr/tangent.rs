//! Analytic tangents `dh/dq`, `dh/du` of the FFR body forces
//! `h = Q_v - K q - D u + Q_g` ([`FfrBody::quadratic_velocity`], [`FfrBody::add_internal_forces`],
//! [`FfrBody::add_gravity_force`]).
//!
//! Structure (`q = [R, rotation, q_f]`, `u = [R_dot, w, q_f_dot]`, position columns along the
//! velocity-space map `q ⊕ dv` of the element contract):
//! - `R`, `R_dot` columns: zero (`h` does not depend on them);
//! - `q_f`, `q_f_dot` columns: exact closed forms from the invariants. With `P_kl` the deformed
//!   moments of [`FfrScratch::p`] (linear in `q_f`, `dP_kl/dq_f,c = S_kl[c, :]`),
//!   `y_kl = S_kl q_f_dot`, `D_k = S_23 - S_32, ...` (2.68):
//!   - `dI_θθ/dq_f,c = tr(U_c) I - U_c`, `U_c[k][l] = P_kl[c] + P_lk[c]` (from (2.59), (2.64));
//!   - `dN_kl/dq_f,c = y_kl[c]`, `dN_kl/dq_f_dot,c = P_kl[c]`;
//!   - `dQ_f/dq_f = -(Σ_kl ω_k ω_l S_kl - |ω|² m_ff - Σ_k z_k D_k) - K`;
//!   - `dQ_f/dq_f_dot = 2 Σ_k ω_k D_k - D`;
//! - rotation and `w` columns (3 each): central differences of a "light" force evaluation in
//!   which only `A`, `H`, `ω`, `z = H_dot w` change (the `q_f`-dependent moments are reused),
//!   O(n_f) per evaluation. `h` is quadratic in `w`, so its `w` differences are exact up to
//!   round-off (step `max(1, |w|)`); the rotation columns use the step 1e-6 (truncation O(1e-12)).
//!
//! - node rotary inertia ([`super::RotaryInertia`], `ffr/rotary.rs`): its terms depend on the
//!   rotation, `w` and `q_f_dot` only; they are part of the light evaluation (rotation and `w`
//!   columns), and its `q_f_dot` columns are `-H^T ω~ C` (w rows).
//!
//! The whole tangent costs about `25 n_f^2` multiply-adds, versus `2 n_u` full force
//! evaluations (`~ 20 n_f^3`) of the finite-difference default. No allocation.

use super::body::CARDAN_SINGULARITY_TOLERANCE;
use super::{FfrBody, FfrError, FfrScratch, RotationParam};
use crate::rotation::{
    cardan_g_bar, cardan_g_bar_dot, cardan_matrix, check_cardan, quaternion_e_transpose,
    quaternion_matrix,
};
use faer::MatMut;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector4};

/// Step of the central differences in the rotation coordinates.
pub const ROTATION_FD_STEP: f64 = 1e-6;

/// Work buffers of [`FfrBody::force_tangents`] (created once per body).
#[derive(Debug, Clone)]
pub struct FfrTangentScratch {
    /// `y_kl = S_kl q_f_dot`, row `3 k + l` (9 x n_f).
    y: DMatrix<f64>,
    /// `S_stack q_f_dot` (9 n_f, block `3 k + l` = `S_kl^T q_f_dot = y_lk`).
    y_flat: DVector<f64>,
    /// `D_k q_f_dot` (3 x n_f).
    dq: DMatrix<f64>,
    /// `K q_f + D q_f_dot` (n_f).
    kd: DVector<f64>,
    /// One column of the `q_f` block (n_f).
    col: DVector<f64>,
    /// Forces at the plus / minus perturbation (n_u).
    h_plus: Vec<f64>,
    h_minus: Vec<f64>,
}

impl FfrTangentScratch {
    /// Buffers for a body with `nf` modes.
    pub fn new(nf: usize) -> Self {
        Self {
            y: DMatrix::zeros(9, nf),
            y_flat: DVector::zeros(9 * nf),
            dq: DMatrix::zeros(3, nf),
            kd: DVector::zeros(nf),
            col: DVector::zeros(nf),
            h_plus: vec![0.0; 6 + nf],
            h_minus: vec![0.0; 6 + nf],
        }
    }
}

/// Rotation part of the evaluated state, saved and restored around the perturbations.
#[derive(Clone, Copy)]
struct RotationState {
    a: Matrix3<f64>,
    h: Matrix3<f64>,
    hdot_w: Vector3<f64>,
    omega: Vector3<f64>,
}

impl RotationState {
    fn of(s: &FfrScratch) -> Self {
        Self {
            a: s.a,
            h: s.h,
            hdot_w: s.hdot_w,
            omega: s.omega,
        }
    }
    fn store(&self, s: &mut FfrScratch) {
        s.a = self.a;
        s.h = self.h;
        s.hdot_w = self.hdot_w;
        s.omega = self.omega;
    }
}

impl FfrBody {
    /// Sets `A`, `H`, `H_dot w`, `ω` of `s` for the rotation coordinates `rot` (3 Cardan angles
    /// or 4 quaternion components, any non-zero norm) and the velocity coordinates `w`.
    pub(super) fn set_rotation_state(
        &self,
        rot: &[f64],
        w: &Vector3<f64>,
        s: &mut FfrScratch,
    ) -> Result<(), FfrError> {
        match self.rotation {
            RotationParam::Cardan => {
                let th = Vector3::new(rot[0], rot[1], rot[2]);
                check_cardan(&th, CARDAN_SINGULARITY_TOLERANCE)?;
                s.a = cardan_matrix(&th);
                s.h = cardan_g_bar(&th);
                s.hdot_w = cardan_g_bar_dot(&th, w) * w;
            }
            RotationParam::Quaternion => {
                s.a = quaternion_matrix(&Vector4::new(rot[0], rot[1], rot[2], rot[3]));
                s.h = Matrix3::identity();
                s.hdot_w = Vector3::zeros();
            }
        }
        s.omega = s.h * w;
        Ok(())
    }

    /// The forces `h` for the rotation state of `s` with the `q_f`-dependent moments of `s` and
    /// the velocity products of `ts` (`y`, `dq`, `kd`) precomputed. O(n_f).
    fn forces_light(
        &self,
        s: &FfrScratch,
        dq: &DMatrix<f64>,
        kd: &DVector<f64>,
        g: &Vector3<f64>,
        out: &mut [f64],
    ) {
        let inv = &self.invariants;
        let gb = s.a.transpose() * g;
        let (qr, c) = self.quadratic_velocity_frame_terms(s);
        let qr = qr + inv.i1 * g;
        let qw = s.h.transpose() * (s.s_t.cross(&gb) - c);
        for i in 0..3 {
            out[i] = qr[i];
            out[3 + i] = qw[i];
        }
        for a in 0..self.nf() {
            let mut acc = self.quadratic_velocity_modal_sum(s, a, |k| dq[(k, a)]);
            for k in 0..3 {
                acc -= inv.s_bar[(k, a)] * gb[k];
            }
            out[6 + a] = -acc - kd[a];
        }
        if let Some(r) = &self.rotary {
            r.add_quadratic_velocity(s, out);
        }
    }

    /// Tangents of the forces `h = Q_v - K q - D u + Q_g` (gravity `g`) at the state evaluated by
    /// [`Self::update`] into `s`: `dh_dq` along `q ⊕ dv` (columns per velocity coordinate) and
    /// `dh_du`, both `n_u x n_u`, overwritten. See the module documentation for the formulas.
    /// `s` is left as evaluated. No allocation.
    #[allow(clippy::too_many_arguments)]
    pub fn force_tangents(
        &self,
        q: &[f64],
        u: &[f64],
        g: &Vector3<f64>,
        s: &mut FfrScratch,
        ts: &mut FfrTangentScratch,
        mut dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
    ) -> Result<(), FfrError> {
        let nf = self.nf();
        let nu = self.nu();
        if ts.kd.len() != nf {
            return Err(FfrError::DimensionMismatch {
                what: "tangent scratch modes",
                expected: nf,
                found: ts.kd.len(),
            });
        }
        // velocity products: y_kl = S_kl q_f_dot, D_k q_f_dot, K q_f + D q_f_dot
        // y_flat[9 a + 3 k + l] = (S_kl^T q_f_dot)[a]
        self.moments
            .apply(s.qfd.as_slice(), ts.y_flat.as_mut_slice());
        for a in 0..nf {
            for k in 0..3 {
                for l in 0..3 {
                    ts.y[(3 * k + l, a)] = ts.y_flat[9 * a + 3 * l + k];
                }
            }
        }
        for a in 0..nf {
            // D_1 qfd = y_23 - y_32, D_2 qfd = y_31 - y_13, D_3 qfd = y_12 - y_21
            ts.dq[(0, a)] = ts.y[(5, a)] - ts.y[(7, a)];
            ts.dq[(1, a)] = ts.y[(6, a)] - ts.y[(2, a)];
            ts.dq[(2, a)] = ts.y[(1, a)] - ts.y[(3, a)];
            let mut acc = 0.0;
            for b in 0..nf {
                acc += self.k_ff[(a, b)] * s.qf[b] + self.d_ff[(a, b)] * s.qfd[b];
            }
            ts.kd[a] = acc;
        }
        dh_dq.fill(0.0);
        dh_du.fill(0.0);
        self.rotation_and_w_columns(q, u, g, s, ts, dh_dq.as_mut(), dh_du.as_mut())?;
        self.modal_columns(g, s, ts, dh_dq.as_mut(), dh_du.as_mut());
        self.add_geometric_stiffening_tangent(q, u, s, dh_dq.as_mut(), dh_du.as_mut());
        debug_assert_eq!(dh_dq.nrows(), nu);
        Ok(())
    }

    /// Rotation columns of `dh_dq` and `w` columns of `dh_du` by central differences of
    /// [`Self::forces_light`].
    #[allow(clippy::too_many_arguments)]
    fn rotation_and_w_columns(
        &self,
        q: &[f64],
        u: &[f64],
        g: &Vector3<f64>,
        s: &mut FfrScratch,
        ts: &mut FfrTangentScratch,
        mut dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
    ) -> Result<(), FfrError> {
        let nu = self.nu();
        let saved = RotationState::of(s);
        let w0 = Vector3::new(u[3], u[4], u[5]);
        let nr = self.rotation.num_coordinates();
        let mut rot = [0.0; 4];
        rot[..nr].copy_from_slice(&q[3..3 + nr]);
        let mut result = Ok(());
        for j in 0..3 {
            // position: rotation ⊕ ±eps e_j (theta + dv, or p + 1/2 E(p) dv for quaternions)
            let eps = ROTATION_FD_STEP;
            for sign in [1.0, -1.0] {
                let mut r = rot;
                match self.rotation {
                    RotationParam::Cardan => r[j] += sign * eps,
                    RotationParam::Quaternion => {
                        let p = Vector4::new(rot[0], rot[1], rot[2], rot[3]);
                        let mut dv = Vector3::zeros();
                        dv[j] = sign * eps;
                        let pd = 0.5 * quaternion_e_transpose(&p).transpose() * dv;
                        for i in 0..4 {
                            r[i] += pd[i];
                        }
                    }
                }
                if let Err(e) = self.set_rotation_state(&r[..nr], &w0, s) {
                    result = Err(e);
                }
                let out = if sign > 0.0 {
                    &mut ts.h_plus
                } else {
                    &mut ts.h_minus
                };
                self.forces_light(s, &ts.dq, &ts.kd, g, out);
            }
            for i in 0..nu {
                dh_dq[(i, 3 + j)] = (ts.h_plus[i] - ts.h_minus[i]) / (2.0 * eps);
            }
            // velocity: w ± eps e_j, exact for the quadratic dependence
            let eps = w0.amax().max(1.0);
            for sign in [1.0, -1.0] {
                let mut w = w0;
                w[j] += sign * eps;
                if let Err(e) = self.set_rotation_state(&rot[..nr], &w, s) {
                    result = Err(e);
                }
                let out = if sign > 0.0 {
                    &mut ts.h_plus
                } else {
                    &mut ts.h_minus
                };
                self.forces_light(s, &ts.dq, &ts.kd, g, out);
            }
            for i in 0..nu {
                dh_du[(i, 3 + j)] = (ts.h_plus[i] - ts.h_minus[i]) / (2.0 * eps);
            }
        }
        saved.store(s);
        result
    }

    /// `q_f` columns of `dh_dq` and `q_f_dot` columns of `dh_du` in closed form.
    fn modal_columns(
        &self,
        g: &Vector3<f64>,
        s: &FfrScratch,
        ts: &mut FfrTangentScratch,
        mut dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
    ) {
        let nf = self.nf();
        let inv = &self.invariants;
        let (w, z) = (s.omega, s.hdot_w);
        let w2 = w.norm_squared();
        let gb = s.a.transpose() * g;
        let ht = s.h.transpose();
        for c in 0..nf {
            let sc = Vector3::new(inv.s_bar[(0, c)], inv.s_bar[(1, c)], inv.s_bar[(2, c)]);
            // R rows: dS_t/dq_f,c = S_bar[:, c]
            let r_q = -(s.a * (w.cross(&w.cross(&sc)) + z.cross(&sc)));
            let r_u = -(s.a * (2.0 * w.cross(&sc)));
            // w rows
            let mut uc = Matrix3::zeros();
            let mut yc = Matrix3::zeros();
            let mut pc = Matrix3::zeros();
            for k in 0..3 {
                for l in 0..3 {
                    uc[(k, l)] = s.p[(3 * k + l, c)] + s.p[(3 * l + k, c)];
                    yc[(k, l)] = ts.y[(3 * k + l, c)];
                    pc[(k, l)] = s.p[(3 * k + l, c)];
                }
            }
            let ditt = Matrix3::identity() * uc.trace() - uc;
            let cq = w.cross(&(ditt * w)) + 2.0 * (yc.trace() * w - yc.transpose() * w) + ditt * z;
            let w_q = ht * (sc.cross(&gb) - cq);
            let mut w_u = -(ht * (2.0 * (pc.trace() * w - pc.transpose() * w)));
            if let Some(r) = &self.rotary {
                // node rotary inertia: d/dq_f_dot,c of -H^T [ω x (I_s ω + C q_f_dot)]
                let cc = Vector3::new(r.c[(0, c)], r.c[(1, c)], r.c[(2, c)]);
                w_u -= ht * w.cross(&cc);
            }
            for i in 0..3 {
                dh_dq[(i, 6 + c)] = r_q[i];
                dh_du[(i, 6 + c)] = r_u[i];
                dh_dq[(3 + i, 6 + c)] = w_q[i];
                dh_du[(3 + i, 6 + c)] = w_u[i];
            }
            // f rows, column c: -(Σ_kl ω_k ω_l S_kl - |ω|² m_ff - Σ_k z_k D_k)[:, c] - K[:, c]
            let col = ts.col.as_mut_slice();
            for (a, v) in col.iter_mut().enumerate() {
                *v = w2 * inv.m_ff[(a, c)] - self.k_ff[(a, c)];
            }
            for k in 0..3 {
                for l in 0..3 {
                    let f = -w[k] * w[l];
                    let skl = &inv.s_kl[3 * k + l].as_slice()[c * nf..(c + 1) * nf];
                    for (v, x) in col.iter_mut().zip(skl) {
                        *v += f * x;
                    }
                }
            }
            for (k, d) in self.s_skew.iter().enumerate() {
                let dcol = &d.as_slice()[c * nf..(c + 1) * nf];
                for (v, x) in col.iter_mut().zip(dcol) {
                    *v += z[k] * x;
                }
            }
            for a in 0..nf {
                dh_dq[(6 + a, 6 + c)] = col[a];
            }
            // f rows of dh_du: 2 Σ_k ω_k D_k - D
            for a in 0..nf {
                let mut v = -self.d_ff[(a, c)];
                for (k, d) in self.s_skew.iter().enumerate() {
                    v += 2.0 * w[k] * d[(a, c)];
                }
                dh_du[(6 + a, 6 + c)] = v;
            }
        }
    }
}
