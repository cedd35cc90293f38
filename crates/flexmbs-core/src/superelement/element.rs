//! [`Element`] for [`Superelement`]: coordinates node by node, mass `Pᵀ M_CB P` (4.9), forces
//! (4.12) plus gravity, frames at interface points, the analytic tangent (`tangent.rs`).

use super::eval::SuperelementEval;
use super::Superelement;
use crate::element::{
    Element, ElementError, ElementScratch, FrameKinematics, LocalFrame, TangentScratch,
};
use crate::NodeKind;
use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

impl Superelement {
    /// Applies `f(kind, q range, u range)` to every node of the element.
    fn for_nodes(
        &self,
        mut f: impl FnMut(NodeKind, std::ops::Range<usize>, std::ops::Range<usize>),
    ) {
        let (mut qo, mut uo) = (0, 0);
        for &k in &self.kinds {
            f(k, qo..qo + k.nq(), uo..uo + k.nu());
            qo += k.nq();
            uo += k.nu();
        }
    }

    /// Local velocities `P u` into `e.work.vel`.
    fn local_velocity(&self, e: &mut SuperelementEval, u: &[f64]) {
        for i in 0..self.n() {
            e.work.vel[i] = (0..self.n()).map(|j| e.p[(i, j)] * u[j]).sum();
        }
    }
}

impl Superelement {
    /// Adds the fictitious forces `−C v` of `T = ½ vᵀ Pᵀ M_CB P v` to `h` (Lagrange equations
    /// with the body-frame angular velocities of the nodes as quasi-velocities):
    /// `h_C = Pᵀ M_CB Ω̃ w − Pᵀ Ω̃ μ + (Z_r P)ᵀ Σ_b μ_b × w_b + [ω̄_k × (Pᵀ μ)_k]` with
    /// `w = P v`, `μ = M_CB w`, `Ω = Z_r w` the floating frame's angular velocity (frame axes),
    /// `Ω̃` its cross product on every 3-block of the interface coordinates.
    fn add_fictitious_forces(&self, e: &mut SuperelementEval, u: &[f64], h: &mut [f64]) {
        let (n, ni) = (self.n(), self.n_interfaces());
        self.frame_variation(e);
        self.local_velocity(e, u);
        e.work.mom.gemv(1.0, &self.data.m_cb, &e.work.vel, 0.0);
        let omega = Vector3::new(
            (0..n).map(|i| e.work.zp[(3, i)] * u[i]).sum(),
            (0..n).map(|i| e.work.zp[(4, i)] * u[i]).sum(),
            (0..n).map(|i| e.work.zp[(5, i)] * u[i]).sum(),
        );
        // tmp = Ω̃ w, then local force c = M_CB Ω̃ w − Ω̃ μ; g_φ = Σ μ_b × w_b
        e.work.tmp.fill(0.0);
        let mut g_phi = Vector3::zeros();
        for b in 0..2 * ni {
            let wb = e.work.vel.fixed_rows::<3>(3 * b).into_owned();
            let mb = e.work.mom.fixed_rows::<3>(3 * b).into_owned();
            e.work
                .tmp
                .fixed_rows_mut::<3>(3 * b)
                .copy_from(&omega.cross(&wb));
            g_phi += mb.cross(&wb);
        }
        e.work
            .a
            .column_mut(0)
            .gemv(1.0, &self.data.m_cb, &e.work.tmp, 0.0);
        for b in 0..2 * ni {
            let mb = e.work.mom.fixed_rows::<3>(3 * b).into_owned();
            let c = omega.cross(&mb);
            for i in 0..3 {
                e.work.a[(3 * b + i, 0)] -= c[i];
            }
        }
        for (j, hj) in h.iter_mut().enumerate() {
            *hj += (0..n).map(|i| e.p[(i, j)] * e.work.a[(i, 0)]).sum::<f64>()
                + (0..3)
                    .map(|r| e.work.zp[(3 + r, j)] * g_phi[r])
                    .sum::<f64>();
        }
        for k in 0..ni {
            let c = self.vel_index[6 * k + 3];
            let wbar = Vector3::new(u[c], u[c + 1], u[c + 2]);
            let ptm =
                e.node_r[k].transpose() * e.rj * e.work.mom.fixed_rows::<3>(6 * k + 3).into_owned();
            let add = wbar.cross(&ptm);
            for i in 0..3 {
                h[c + i] += add[i];
            }
        }
    }
}

impl Element for Superelement {
    /// `|K_CB|_∞ max_k |x_k|`: the elastic forces are `K_CB` times local coordinates that are
    /// differences of absolute interface positions, so their round-off is about `eps` times this
    /// (3.5e-9 N for a 0.1 m tube segment at x = 0.55 m).
    fn force_scale(&self, q: &[f64]) -> f64 {
        let k = &self.data.k_cb;
        let k_inf = (0..k.nrows())
            .map(|i| k.row(i).iter().map(|x| x.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let x_max = self
            .q_offset
            .iter()
            .map(|&o| Vector3::new(q[o], q[o + 1], q[o + 2]).norm())
            .fold(0.0, f64::max);
        k_inf * x_max
    }

    fn node_kinds(&self) -> &[NodeKind] {
        &self.kinds
    }

    fn nq(&self) -> usize {
        self.kinds.iter().map(|k| k.nq()).sum()
    }

    fn nu(&self) -> usize {
        self.n()
    }

    fn num_mesh_nodes(&self) -> usize {
        self.n_interfaces()
    }

    fn velocity_scales(&self, out: &mut [f64]) {
        out.fill(1.0);
        for k in 0..self.n_interfaces() {
            for i in 3..6 {
                out[self.vel_index[6 * k + i]] = self.length;
            }
        }
    }

    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        u.fill(0.0);
        q.fill(0.0);
        self.set_pose(q, &Vector3::zeros(), &Matrix3::identity());
    }

    /// Places the undeformed body with its floating frame at `position`, `rotation` (internal
    /// modes unchanged).
    fn set_pose(&self, q: &mut [f64], position: &Vector3<f64>, rotation: &Matrix3<f64>) {
        for k in 0..self.n_interfaces() {
            let (x0, r0) = self.interface_reference(k);
            let o = self.q_offset[k];
            NodeKind::Pose.set_pose(
                &mut q[o..o + 7],
                &(position + rotation * x0),
                &(rotation * r0),
            );
        }
    }

    /// Rigid velocity field of the body about the floating-frame origin implied by the first
    /// interface (`x_0 − R_0 R_00ᵀ x_00`).
    fn set_velocity(
        &self,
        q: &[f64],
        u: &mut [f64],
        velocity: &Vector3<f64>,
        omega: &Vector3<f64>,
    ) {
        let (x00, r00) = self.interface_reference(0);
        let o = self.q_offset[0];
        let rj = NodeKind::Pose.rotation(&q[o..o + 7]) * r00.transpose();
        let xj = Vector3::new(q[o], q[o + 1], q[o + 2]) - rj * x00;
        for k in 0..self.n_interfaces() {
            let o = self.q_offset[k];
            let x = Vector3::new(q[o], q[o + 1], q[o + 2]);
            let uo = self.vel_index[6 * k];
            NodeKind::Pose.set_velocity(
                &q[o..o + 7],
                &mut u[uo..uo + 6],
                &(velocity + omega.cross(&(x - xj))),
                omega,
            );
        }
    }

    fn q_dot(&self, q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        self.for_nodes(|k, rq, ru| k.q_dot(&q[rq.clone()], &u[ru], &mut q_dot[rq]));
    }

    fn integrate_position(&self, q: &[f64], dv: &[f64], q_new: &mut [f64]) {
        self.for_nodes(|k, rq, ru| k.integrate(&q[rq.clone()], &dv[ru], &mut q_new[rq]));
    }

    fn normalize(&self, q: &mut [f64]) {
        self.for_nodes(|k, rq, _| k.normalize(&mut q[rq]));
    }

    fn new_scratch(&self) -> ElementScratch {
        ElementScratch::with_contour_source(SuperelementEval::new(self))
    }

    /// The evaluation, and the floating frame's velocity and `q̇_loc` for neutral contours.
    fn update(
        &self,
        q: &[f64],
        u: &[f64],
        scratch: &mut ElementScratch,
    ) -> Result<(), ElementError> {
        let e = scratch.get_mut::<SuperelementEval>();
        self.evaluate(q, e)?;
        self.contour_kinematics(e, u);
        Ok(())
    }

    /// `M = Pᵀ M_CB P` (4.9).
    fn mass_matrix(&self, _q: &[f64], scratch: &mut ElementScratch, mut m: MatMut<'_, f64>) {
        let e = scratch.get_mut::<SuperelementEval>();
        super::product_into(&mut e.work.a, &self.data.m_cb, &e.p, false);
        super::product_into(&mut e.work.b, &e.p, &e.work.a, true);
        for i in 0..self.n() {
            for j in 0..self.n() {
                m[(i, j)] = e.work.b[(i, j)];
            }
        }
    }

    /// `h = −Pᵀ (w − M_CB G R_jᵀ g)`: the elastic forces (4.12) and gravity, plus the fictitious
    /// forces of [`super::FictitiousForces::FromMcb`] if selected.
    fn forces(
        &self,
        _t: f64,
        _q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        scratch: &mut ElementScratch,
        h: &mut [f64],
    ) {
        let e = scratch.get_mut::<SuperelementEval>();
        let g_loc = e.rj.transpose() * gravity;
        e.f_g.gemv(1.0, &self.m_g, &g_loc, 0.0);
        for (j, hj) in h.iter_mut().enumerate() {
            *hj = -(0..self.n())
                .map(|i| e.p[(i, j)] * (e.w[i] - e.f_g[i]))
                .sum::<f64>();
        }
        if self.fictitious == super::FictitiousForces::FromMcb {
            self.add_fictitious_forces(e, u, h);
        }
    }

    /// A frame on interface `k` (`mesh_node: Some(k)`) moves with that interface node; a frame
    /// without a mesh node is fixed to the floating frame (position and velocity exact, bias
    /// accelerations omitted: attach joints to interface nodes).
    fn frame_kinematics(
        &self,
        _q: &[f64],
        u: &[f64],
        scratch: &mut ElementScratch,
        frame: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        let e = scratch.get_mut::<SuperelementEval>();
        out.jac_t.fill(0.0);
        out.jac_r.fill(0.0);
        out.bias_acc = Vector3::zeros();
        out.bias_ang_acc = Vector3::zeros();
        if let Some(k) = frame.mesh_node {
            let a = e.node_r[k];
            let c = self.vel_index[6 * k];
            for i in 0..3 {
                out.jac_t[(i, c + i)] = 1.0;
                for j in 0..3 {
                    out.jac_r[(i, c + 3 + j)] = a[(i, j)];
                }
            }
            out.position = e.node_x[k];
            out.rotation = a * frame.rotation;
        } else {
            // δx_j = R_j Z_t P δv, δπ_j = R_j Z_r P δv
            self.frame_variation(e);
            let s = e.rj * frame.position;
            let s_skew = crate::rotation::skew(&s);
            for j in 0..self.n() {
                let zt =
                    e.rj * Vector3::new(e.work.zp[(0, j)], e.work.zp[(1, j)], e.work.zp[(2, j)]);
                let zr =
                    e.rj * Vector3::new(e.work.zp[(3, j)], e.work.zp[(4, j)], e.work.zp[(5, j)]);
                let jt = zt - s_skew * zr;
                for i in 0..3 {
                    out.jac_t[(i, j)] = jt[i];
                    out.jac_r[(i, j)] = zr[i];
                }
            }
            out.position = e.x_j + s;
            out.rotation = e.rj * frame.rotation;
        }
        let (mut v, mut w) = (Vector3::zeros(), Vector3::zeros());
        for (j, uj) in u.iter().enumerate() {
            for i in 0..3 {
                v[i] += out.jac_t[(i, j)] * uj;
                w[i] += out.jac_r[(i, j)] * uj;
            }
        }
        out.velocity = v;
        out.angular_velocity = w;
    }

    #[allow(clippy::too_many_arguments)]
    fn force_tangents(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        scratch: &mut ElementScratch,
        dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
        fd: &mut TangentScratch,
    ) {
        if self.fictitious == super::FictitiousForces::FromMcb {
            crate::element::finite_difference_tangents(self, t, q, u, gravity, dh_dq, dh_du, fd);
            return;
        }
        let e = scratch.get_mut::<SuperelementEval>();
        self.force_tangent(e, gravity, dh_dq);
        for j in 0..self.n() {
            for i in 0..self.n() {
                dh_du[(i, j)] = 0.0;
            }
        }
    }

    fn kinetic_energy(&self, _q: &[f64], u: &[f64], scratch: &mut ElementScratch) -> f64 {
        let e = scratch.get_mut::<SuperelementEval>();
        self.local_velocity(e, u);
        let v = &e.work.vel;
        let n = self.n();
        let mut t = 0.0;
        for i in 0..n {
            t += v[i] * (0..n).map(|j| self.data.m_cb[(i, j)] * v[j]).sum::<f64>();
        }
        0.5 * t
    }

    /// `−g · (m x_j + R_j (m c_0 + M_Gᵀ q_loc))`: the centre of mass moved by the deformation
    /// to first order.
    fn gravity_potential(
        &self,
        _q: &[f64],
        gravity: &Vector3<f64>,
        scratch: &mut ElementScratch,
    ) -> f64 {
        let e = scratch.get_mut::<SuperelementEval>();
        let mut shift = Vector3::zeros();
        for c in 0..3 {
            shift[c] = (0..self.n()).map(|i| self.m_g[(i, c)] * e.q_loc[i]).sum();
        }
        let first_moment =
            self.mass * e.x_j + e.rj * (self.mass * self.data.centre_of_mass + shift);
        -gravity.dot(&first_moment)
    }

    /// `½ q_locᵀ K_CB q_loc` of the evaluated state.
    fn elastic_energy_evaluated(&self, _q: &[f64], scratch: &mut ElementScratch) -> f64 {
        let e = scratch.get_mut::<SuperelementEval>();
        0.5 * e.q_loc.dot(&e.s)
    }

    /// `½ q_locᵀ K_CB q_loc` (recovers the floating frame in a fresh evaluation: allocates; the
    /// energy output uses [`Element::elastic_energy_evaluated`]).
    fn elastic_energy(&self, q: &[f64]) -> f64 {
        let mut e = SuperelementEval::new(self);
        match self.evaluate(q, &mut e) {
            Ok(()) => 0.5 * e.q_loc.dot(&e.s),
            Err(_) => f64::NAN,
        }
    }
}
