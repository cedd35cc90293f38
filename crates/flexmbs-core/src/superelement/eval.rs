//! The evaluation stage of a superelement: floating-frame recovery by Newton-Raphson (3.7), local
//! interface coordinates, `[Φ_rig]` (3.14), `B = [Φ_CB] Λ [Φ_rig]` (3.17) and the projected
//! internal forces (4.12).

use super::rotvec::{inverse_left_jacobian, log_quaternion, node_quaternion};
use super::{Superelement, TransformMatrices};
use crate::element::ElementError;
use crate::rotation::skew;
use nalgebra::{DMatrix, DVector, Matrix3, Matrix6, UnitQuaternion, Vector3, Vector6};

/// Newton iterations of the floating-frame recovery before it is declared failed.
const MAX_FRAME_ITERATIONS: usize = 30;
/// Convergence of the frame recovery: `|Δx_j| / length + |Δφ_j|` below this, or below
/// [`FRAME_ROUNDOFF`] and no longer falling (the round-off floor of the local coordinates).
const FRAME_TOLERANCE: f64 = 1e-14;
/// Steps below this that stop falling quadratically are at the round-off floor.
const FRAME_ROUNDOFF: f64 = 1e-10;

/// The evaluated state of a [`Superelement`] (its [`crate::ElementScratch`]).
#[derive(Debug, Clone)]
pub struct SuperelementEval {
    /// Floating-frame origin `x_j` (global).
    pub x_j: Vector3<f64>,
    /// Floating-frame orientation `R_j`.
    pub r_j: UnitQuaternion<f64>,
    /// `R_j` as a matrix.
    pub rj: Matrix3<f64>,
    /// Newton iterations of the last frame recovery.
    pub iterations: usize,
    /// Local coordinates `q_loc = [u_1, θ_1, ..., η]`.
    pub q_loc: DVector<f64>,
    pub(super) node_x: Vec<Vector3<f64>>,
    pub(super) node_r: Vec<Matrix3<f64>>,
    pub(super) node_p: Vec<UnitQuaternion<f64>>,
    /// Deformed interface positions `r_k = x_k0 + u_k` in the floating frame.
    pub(super) r: Vec<Vector3<f64>>,
    /// `J_l⁻¹(θ_k)`.
    pub(super) lam: Vec<Matrix3<f64>>,
    /// Deformed `[Φ_rig]` (n x 6).
    pub(super) phi_rig: DMatrix<f64>,
    /// `[Φ_CB] Λ` (6 x n).
    pub(super) phi_t: DMatrix<f64>,
    /// `B⁻¹ = ([Φ_CB] Λ [Φ_rig])⁻¹`.
    pub(super) b_inv: Matrix6<f64>,
    /// `K_CB q_loc`.
    pub(super) s: DVector<f64>,
    /// `ŝ = s − Φ_CBᵀ z` (exact matrices).
    pub(super) s_hat: DVector<f64>,
    /// Elastic force in local coordinates, `h_el = −Pᵀ w`.
    pub(super) w: DVector<f64>,
    /// Gravity force in local coordinates, `M_CB G R_jᵀ g` (written by `forces`).
    pub(super) f_g: DVector<f64>,
    /// `P` (n x n, rows local, columns velocity).
    pub(super) p: DMatrix<f64>,
    pub(super) work: TangentWork,
    /// Angular velocity `ω̄` of the floating frame in its axes (`contour.rs`).
    pub(super) omega_bar: Vector3<f64>,
    /// `q̇_loc` (`contour.rs`).
    pub(super) qd_loc: DVector<f64>,
    /// Velocity index of local coordinate `i` (the element's).
    pub(super) vel_index: Vec<usize>,
}

/// Work matrices of the analytic tangent.
#[derive(Debug, Clone)]
pub(super) struct TangentWork {
    /// `Z = B⁻¹ [Φ_CB] Λ` (6 x n): `δf = Z δq̂` (3.17).
    pub z: DMatrix<f64>,
    /// `Z P` (6 x n, velocity columns).
    pub zp: DMatrix<f64>,
    /// `T = 1 − [Φ_rig] Z` (3.18).
    pub t: DMatrix<f64>,
    /// `W = Λ T`: `δq_loc = W P δv`.
    pub wm: DMatrix<f64>,
    /// `W P`.
    pub wp: DMatrix<f64>,
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    pub c: DMatrix<f64>,
    /// Local velocities `w = P u`.
    pub vel: DVector<f64>,
    /// Local momenta `μ = M_CB w`.
    pub mom: DVector<f64>,
    /// A local work vector.
    pub tmp: DVector<f64>,
}

impl SuperelementEval {
    pub(super) fn new(se: &Superelement) -> Self {
        let (n, ni) = (se.n(), se.n_interfaces());
        let sq = || DMatrix::zeros(n, n);
        Self {
            x_j: Vector3::zeros(),
            r_j: UnitQuaternion::identity(),
            rj: Matrix3::identity(),
            iterations: 0,
            q_loc: DVector::zeros(n),
            node_x: vec![Vector3::zeros(); ni],
            node_r: vec![Matrix3::identity(); ni],
            node_p: vec![UnitQuaternion::identity(); ni],
            r: vec![Vector3::zeros(); ni],
            lam: vec![Matrix3::identity(); ni],
            phi_rig: DMatrix::zeros(n, 6),
            phi_t: DMatrix::zeros(6, n),
            b_inv: Matrix6::identity(),
            s: DVector::zeros(n),
            s_hat: DVector::zeros(n),
            w: DVector::zeros(n),
            f_g: DVector::zeros(n),
            p: sq(),
            work: TangentWork {
                z: DMatrix::zeros(6, n),
                zp: DMatrix::zeros(6, n),
                t: sq(),
                wm: sq(),
                wp: sq(),
                a: sq(),
                b: sq(),
                c: sq(),
                vel: DVector::zeros(n),
                mom: DVector::zeros(n),
                tmp: DVector::zeros(n),
            },
            omega_bar: Vector3::zeros(),
            qd_loc: DVector::zeros(n),
            vel_index: se.vel_index.clone(),
        }
    }

    /// `Λᵀ v` in place (rotation blocks `J_l⁻ᵀ(θ_k)`).
    pub(super) fn lam_t_apply(&self, v: &mut DVector<f64>) {
        for (k, l) in self.lam.iter().enumerate() {
            let r = l.transpose() * v.fixed_rows::<3>(6 * k + 3);
            v.fixed_rows_mut::<3>(6 * k + 3).copy_from(&r);
        }
    }
}

impl Superelement {
    /// Reads the interface node poses and the internal modes from `q`.
    fn read_nodes(&self, q: &[f64], e: &mut SuperelementEval) {
        for k in 0..self.n_interfaces() {
            let o = self.q_offset[k];
            e.node_x[k] = Vector3::new(q[o], q[o + 1], q[o + 2]);
            e.node_p[k] = node_quaternion(&q[o + 3..o + 7]);
            e.node_r[k] = e.node_p[k].to_rotation_matrix().into_inner();
        }
    }

    /// Closed-form first guess of the floating frame: the rotation midway (geodesic) between the
    /// rotations the first and the last interface imply for a rigid body (`R_k R_k0ᵀ`), the
    /// origin the mean of the origins the interfaces imply with it (`x_k − R_j x_k0`).
    fn frame_guess(&self, e: &mut SuperelementEval) {
        let ni = self.n_interfaces();
        let implied = |k: usize| e.node_p[k] * self.r0_inv[k];
        let (a, b) = (implied(0), implied(ni - 1));
        let half = 0.5 * log_quaternion(&(a.inverse() * b));
        e.r_j = a * UnitQuaternion::from_scaled_axis(half);
        e.rj = e.r_j.to_rotation_matrix().into_inner();
        let mut x = Vector3::zeros();
        for k in 0..ni {
            x += e.node_x[k] - e.rj * self.interface_reference(k).0;
        }
        e.x_j = x / ni as f64;
    }

    /// Local coordinates, `Λ`, `[Φ_rig]`, `[Φ_CB] Λ` and `B⁻¹` at the current frame of `e`.
    fn local_coordinates(&self, q: &[f64], e: &mut SuperelementEval) -> Result<(), ElementError> {
        let rjt = e.rj.transpose();
        let rj_inv = e.r_j.inverse();
        e.phi_rig.fill(0.0);
        for k in 0..self.n_interfaces() {
            let (x0, _) = self.interface_reference(k);
            let r = rjt * (e.node_x[k] - e.x_j);
            let u = r - x0;
            let rel = rj_inv * e.node_p[k] * self.r0_inv[k];
            let theta = log_quaternion(&rel);
            e.q_loc.fixed_rows_mut::<3>(6 * k).copy_from(&u);
            e.q_loc.fixed_rows_mut::<3>(6 * k + 3).copy_from(&theta);
            e.r[k] = r;
            e.lam[k] = inverse_left_jacobian(&theta);
            let s = -skew(&r);
            for i in 0..3 {
                e.phi_rig[(6 * k + i, i)] = 1.0;
                e.phi_rig[(6 * k + 3 + i, 3 + i)] = 1.0;
                for j in 0..3 {
                    e.phi_rig[(6 * k + i, 3 + j)] = s[(i, j)];
                }
            }
        }
        let m = self.data.internal_modes;
        let n = self.n();
        for i in 0..m {
            e.q_loc[6 * self.n_interfaces() + i] = q[self.q_eta + i];
        }
        // [Φ_CB] Λ
        e.phi_t.copy_from(&self.data.phi_cb);
        for (k, l) in e.lam.iter().enumerate() {
            for row in 0..6 {
                let v = Vector3::new(
                    self.data.phi_cb[(row, 6 * k + 3)],
                    self.data.phi_cb[(row, 6 * k + 4)],
                    self.data.phi_cb[(row, 6 * k + 5)],
                );
                let lv = l.transpose() * v;
                for c in 0..3 {
                    e.phi_t[(row, 6 * k + 3 + c)] = lv[c];
                }
            }
        }
        let mut b = Matrix6::zeros();
        for i in 0..6 {
            for j in 0..6 {
                b[(i, j)] = (0..n).map(|c| e.phi_t[(i, c)] * e.phi_rig[(c, j)]).sum();
            }
        }
        e.b_inv = super::invert6(&b).ok_or(ElementError::InternalSolve {
            what: "superelement floating frame ([Phi_CB][Phi_rig] singular)",
            residual: f64::INFINITY,
            iterations: e.iterations,
        })?;
        Ok(())
    }

    /// Recovers the floating frame from `[Φ_CB] q_loc = 0` (3.7) by Newton-Raphson from the
    /// closed-form guess; leaves `e` evaluated at the converged frame.
    pub(super) fn recover_frame(
        &self,
        q: &[f64],
        e: &mut SuperelementEval,
    ) -> Result<(), ElementError> {
        self.read_nodes(q, e);
        self.frame_guess(e);
        e.iterations = 0;
        let mut last_step = f64::INFINITY;
        loop {
            self.local_coordinates(q, e)?;
            let mut c = Vector6::zeros();
            for i in 0..6 {
                c[i] = (0..self.n())
                    .map(|j| self.data.phi_cb[(i, j)] * e.q_loc[j])
                    .sum();
            }
            // d(Φ_CB q_loc)/d(δa, δφ) = −Φ_CB Λ Φ_rig = −B
            let d = e.b_inv * c;
            let step = d.fixed_rows::<3>(0).norm() / self.length + d.fixed_rows::<3>(3).norm();
            if !step.is_finite() || e.iterations >= MAX_FRAME_ITERATIONS {
                return Err(ElementError::InternalSolve {
                    what: "superelement floating-frame recovery",
                    residual: c.norm(),
                    iterations: e.iterations,
                });
            }
            if step < FRAME_TOLERANCE || (step < FRAME_ROUNDOFF && step > 0.1 * last_step) {
                return Ok(());
            }
            last_step = step;
            e.x_j += e.rj * d.fixed_rows::<3>(0);
            e.r_j *= UnitQuaternion::from_scaled_axis(d.fixed_rows::<3>(3).into_owned());
            e.rj = e.r_j.to_rotation_matrix().into_inner();
            e.iterations += 1;
        }
    }

    /// `P`: node velocities → local velocities (`R_jᵀ ẋ_k`, `R_jᵀ R_k ω̄_k`, `η̇`).
    fn fill_p(&self, e: &mut SuperelementEval) {
        e.p.fill(0.0);
        let rjt = e.rj.transpose();
        for k in 0..self.n_interfaces() {
            let rot = rjt * e.node_r[k];
            for i in 0..3 {
                for j in 0..3 {
                    e.p[(6 * k + i, self.vel_index[6 * k + j])] = rjt[(i, j)];
                    e.p[(6 * k + 3 + i, self.vel_index[6 * k + 3 + j])] = rot[(i, j)];
                }
            }
        }
        for i in 6 * self.n_interfaces()..self.n() {
            e.p[(i, self.vel_index[i])] = 1.0;
        }
    }

    /// The whole evaluation: frame, local coordinates, `P`, `s = K_CB q_loc` and the projected
    /// elastic force `w` (`h_el = −Pᵀ w`): exact `w = Λᵀ (s − Φ_CBᵀ B⁻ᵀ Φ_rigᵀ Λᵀ s)` (the
    /// gradient of `½ q_locᵀ K_CB q_loc`), approximated `w = (1 − Φ_rig,0 Φ_CB)ᵀ s` (3.25).
    pub(super) fn evaluate(&self, q: &[f64], e: &mut SuperelementEval) -> Result<(), ElementError> {
        self.recover_frame(q, e)?;
        self.fill_p(e);
        e.s.gemv(1.0, &self.data.k_cb, &e.q_loc, 0.0);
        match self.matrices {
            TransformMatrices::Exact => {
                // y = Λᵀ s, then w = Λᵀ ŝ (the buffer is moved out of `e` while `e.lam` is
                // read: no allocation, a zero-length vector holds its place)
                e.w.copy_from(&e.s);
                let mut y = std::mem::replace(&mut e.w, DVector::zeros(0));
                e.lam_t_apply(&mut y);
                let mut g6 = Vector6::zeros();
                for j in 0..6 {
                    g6[j] = (0..self.n()).map(|i| e.phi_rig[(i, j)] * y[i]).sum();
                }
                let z = e.b_inv.transpose() * g6;
                e.s_hat.copy_from(&e.s);
                for i in 0..self.n() {
                    e.s_hat[i] -= (0..6).map(|r| self.data.phi_cb[(r, i)] * z[r]).sum::<f64>();
                }
                y.copy_from(&e.s_hat);
                e.lam_t_apply(&mut y);
                e.w = y;
            }
            TransformMatrices::Approximated => {
                e.w.gemv_tr(1.0, &self.t0, &e.s, 0.0);
                e.s_hat.copy_from(&e.s);
            }
        }
        Ok(())
    }
}
