//! The FFR body as an [`Element`] of the multibody engine: the adapter between the engine's
//! element contract and the FFR mathematics of [`FfrBody`] (seed 000 (2.73)).

use super::{FfrBody, FfrScratch, FfrTangentScratch, RotationParam};
use crate::element::{
    finite_difference_tangents, Element, ElementError, ElementScratch, FrameKinematics, LocalFrame,
    TangentScratch,
};
use crate::node::NodeKind;
use crate::rotation::{cardan_from_matrix, cardan_g_bar, quaternion_from_matrix, skew};
use faer::MatMut;
use nalgebra::{Matrix3, Vector3};

/// An FFR body in a multibody model: the body's constant data only. Its evaluated state at a
/// `(q, u)` is an [`FfrEval`] in the workspace ([`Element::update`]).
#[derive(Debug)]
pub struct FfrElement {
    body: FfrBody,
    analytic_tangent: bool,
    /// Floating-frame pose node and modal `Vector(n_f)` node.
    node_kinds: [NodeKind; 2],
}

/// The evaluated state of an [`FfrElement`] (its [`ElementScratch`]): rotation state, modal
/// coordinates and rates, and, after a full [`Element::update`], the deformed moments
/// (2.55)-(2.68); plus the work buffers of the analytic tangent.
#[derive(Debug, Clone)]
pub struct FfrEval {
    /// The evaluated state.
    pub state: FfrScratch,
    /// Work buffers of [`FfrBody::force_tangents`].
    pub tangent: FfrTangentScratch,
    /// Coefficients of the node-load stiffening ([`super::LoadStiffening`]): set by
    /// [`crate::system::add_load_stiffening_forces`] after an evaluation and kept until it sets
    /// them again (zero in a new scratch); empty without load stiffening.
    pub load_coefficients: Vec<f64>,
}

impl FfrElement {
    /// Wraps an FFR body.
    pub fn new(body: FfrBody) -> Self {
        let nf = body.nf();
        Self {
            analytic_tangent: true,
            node_kinds: [
                match body.rotation {
                    RotationParam::Cardan => NodeKind::PoseCardan,
                    RotationParam::Quaternion => NodeKind::Pose,
                },
                NodeKind::Vector(nf),
            ],
            body,
        }
    }

    /// Uses the central finite-difference tangent of the element contract instead of the
    /// analytic one ([`FfrBody::force_tangents`]); for cross-checks and benchmarks.
    pub fn with_finite_difference_tangent(mut self) -> Self {
        self.analytic_tangent = false;
        self
    }

    /// The wrapped body.
    pub fn body(&self) -> &FfrBody {
        &self.body
    }
}

impl FfrElement {
    /// `−K_load(c)` into the modal block of `dh_dq` at the coefficients in the scratch (none
    /// without load stiffening or before [`crate::system::add_load_stiffening_forces`]).
    fn add_load_stiffening_tangent(&self, s: &mut ElementScratch, dh_dq: MatMut<'_, f64>) {
        if let Some(l) = self.body.load_stiffening() {
            l.add_tangent(&eval(s).load_coefficients, self.body.nf(), dh_dq);
        }
    }
}

/// The evaluated FFR state in a scratch.
fn eval(s: &mut ElementScratch) -> &mut FfrEval {
    s.get_mut::<FfrEval>()
}

fn fill_nan(x: &mut [f64]) {
    x.fill(f64::NAN);
}

impl Element for FfrElement {
    fn node_kinds(&self) -> &[NodeKind] {
        &self.node_kinds
    }

    fn nq(&self) -> usize {
        self.body.nq()
    }

    fn nu(&self) -> usize {
        self.body.nu()
    }

    fn num_mesh_nodes(&self) -> usize {
        self.body.num_nodes()
    }

    /// Translations 1; rotations the body extent `max |u0|` (largest node distance from the
    /// body frame origin); mode `k` its largest nodal displacement
    /// `max_n max(|phi_t,nk|, extent |phi_r,nk|)` (a mode without nodal motion: the extent).
    fn velocity_scales(&self, out: &mut [f64]) {
        let b = &self.body;
        let extent = b.u0.iter().map(|x| x.norm()).fold(0.0, f64::max);
        let extent = if extent > 0.0 { extent } else { 1.0 };
        out[..3].fill(1.0);
        out[3..6].fill(extent);
        for (k, o) in out[6..].iter_mut().enumerate() {
            let node_max = |m: &nalgebra::DMatrix<f64>| {
                m.column(k)
                    .as_slice()
                    .chunks(3)
                    .map(|c| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
                    .fold(0.0, f64::max)
            };
            let t = node_max(&b.modes_t);
            let r = b.modes_r.as_ref().map_or(0.0, |m| extent * node_max(m));
            let scale = t.max(r);
            *o = if scale > 0.0 { scale } else { extent };
        }
    }

    fn reference_coordinates(&self, q: &mut [f64], u: &mut [f64]) {
        q.fill(0.0);
        u.fill(0.0);
        if self.body.rotation == RotationParam::Quaternion {
            q[3] = 1.0;
        }
    }

    fn set_pose(&self, q: &mut [f64], position: &Vector3<f64>, rotation: &Matrix3<f64>) {
        q[..3].copy_from_slice(position.as_slice());
        match self.body.rotation {
            RotationParam::Cardan => match cardan_from_matrix(rotation, 1e-9) {
                Ok(th) => q[3..6].copy_from_slice(th.as_slice()),
                Err(_) => q[3..6].fill(f64::NAN),
            },
            RotationParam::Quaternion => {
                q[3..7].copy_from_slice(quaternion_from_matrix(rotation).as_slice())
            }
        }
    }

    fn set_velocity(
        &self,
        q: &[f64],
        u: &mut [f64],
        velocity: &Vector3<f64>,
        omega: &Vector3<f64>,
    ) {
        u[..3].copy_from_slice(velocity.as_slice());
        let mut s = self.new_scratch();
        let zero = vec![0.0; self.nu()];
        let Ok(()) = self.update_kinematics(q, &zero, &mut s) else {
            u[3..6].fill(f64::NAN);
            return;
        };
        let omega_bar = eval(&mut s).state.a.transpose() * omega;
        match self.body.rotation {
            RotationParam::Cardan => {
                let th = Vector3::new(q[3], q[4], q[5]);
                match cardan_g_bar(&th).try_inverse() {
                    Some(gi) => u[3..6].copy_from_slice((gi * omega_bar).as_slice()),
                    None => u[3..6].fill(f64::NAN),
                }
            }
            RotationParam::Quaternion => u[3..6].copy_from_slice(omega_bar.as_slice()),
        }
    }

    fn q_dot(&self, q: &[f64], u: &[f64], q_dot: &mut [f64]) {
        self.body.coordinate_rates(q, u, q_dot);
    }

    /// `q ⊕ dv` node by node: the floating-frame pose through its node kind (the exponential map
    /// for quaternions, as for rigid bodies; addition for Cardan angles), `q_f + dv_f`.
    fn integrate_position(&self, q: &[f64], dv: &[f64], q_new: &mut [f64]) {
        let pose = self.node_kinds[0];
        let (nq, nu) = (pose.nq(), pose.nu());
        pose.integrate(&q[..nq], &dv[..nu], &mut q_new[..nq]);
        for ((x, q), d) in q_new[nq..].iter_mut().zip(&q[nq..]).zip(&dv[nu..]) {
            *x = q + d;
        }
    }

    fn normalize(&self, q: &mut [f64]) {
        if self.body.normalize(q).is_err() {
            fill_nan(q);
        }
    }

    fn new_scratch(&self) -> ElementScratch {
        let nf = self.body.nf();
        let nc = self
            .body
            .load_stiffening()
            .map_or(0, |l| l.num_coefficients());
        ElementScratch::with_contour_source(FfrEval {
            state: FfrScratch::new(nf),
            tangent: FfrTangentScratch::new(nf),
            load_coefficients: vec![0.0; nc],
        })
    }

    /// [`FfrBody::update`]: rotation state, `q_f`, `q_f_dot` and the deformed moments.
    fn update(&self, q: &[f64], u: &[f64], s: &mut ElementScratch) -> Result<(), ElementError> {
        Ok(self.body.update(q, u, &mut eval(s).state)?)
    }

    /// Rotation state, `q_f`, `q_f_dot` only (bitwise the values of a full update), without the
    /// O(n_f^2) moments: enough for frame kinematics.
    fn update_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        s: &mut ElementScratch,
    ) -> Result<(), ElementError> {
        Ok(update_kinematic_state(
            &self.body,
            q,
            u,
            &mut eval(s).state,
        )?)
    }

    fn mass_matrix(&self, _q: &[f64], s: &mut ElementScratch, m: MatMut<'_, f64>) {
        self.body.mass_matrix(&eval(s).state, m);
    }

    /// The modal block `m_ff` (2.69), plus the constant rotary-inertia term if set.
    fn constant_mass_tail(&self) -> usize {
        self.body.nf()
    }

    fn mass_times_vector(
        &self,
        q: &[f64],
        s: &mut ElementScratch,
        v: &[f64],
        mut m: MatMut<'_, f64>,
        out: &mut [f64],
    ) {
        // the product covers the translational terms; with node rotary inertia assemble M
        if self.body.rotary.is_some() {
            self.mass_matrix(q, s, m.as_mut());
            out.fill(0.0);
            for (j, x) in v.iter().enumerate() {
                for (i, o) in out.iter_mut().enumerate() {
                    *o += m[(i, j)] * x;
                }
            }
            return;
        }
        self.body.mass_times_vector(&eval(s).state, v, out);
    }

    fn forces(
        &self,
        _t: f64,
        _q: &[f64],
        _u: &[f64],
        gravity: &Vector3<f64>,
        s: &mut ElementScratch,
        h: &mut [f64],
    ) {
        let (b, st) = (&self.body, &eval(s).state);
        b.quadratic_velocity(st, h);
        b.add_internal_forces(st, h);
        b.add_gravity_force(st, gravity, h);
    }

    fn force_tangents(
        &self,
        t: f64,
        q: &[f64],
        u: &[f64],
        gravity: &Vector3<f64>,
        s: &mut ElementScratch,
        mut dh_dq: MatMut<'_, f64>,
        mut dh_du: MatMut<'_, f64>,
        fd: &mut TangentScratch,
    ) {
        if !self.analytic_tangent {
            finite_difference_tangents(self, t, q, u, gravity, dh_dq.as_mut(), dh_du, fd);
            self.add_load_stiffening_tangent(s, dh_dq);
            return;
        }
        let e = eval(s);
        let done = self.body.force_tangents(
            q,
            u,
            gravity,
            &mut e.state,
            &mut e.tangent,
            dh_dq.as_mut(),
            dh_du.as_mut(),
        );
        if done.is_err() {
            dh_dq.fill(f64::NAN);
            dh_du.fill(f64::NAN);
            return;
        }
        self.add_load_stiffening_tangent(s, dh_dq);
    }

    fn frame_kinematics(
        &self,
        q: &[f64],
        u: &[f64],
        s: &mut ElementScratch,
        frame: &LocalFrame,
        out: &mut FrameKinematics,
    ) {
        if frame_from_state(&self.body, q, u, &eval(s).state, frame, out).is_none() {
            out.position.fill(f64::NAN);
            out.velocity.fill(f64::NAN);
        }
    }

    /// Analytic, O(n_f) ([`FfrBody::force_load_tangent`]).
    fn force_load_tangent(
        &self,
        q: &[f64],
        _u: &[f64],
        s: &mut ElementScratch,
        frame: &LocalFrame,
        force: &Vector3<f64>,
        follower: bool,
        out: MatMut<'_, f64>,
    ) -> bool {
        let st = &eval(s).state;
        self.body
            .force_load_tangent(q, frame, force, follower, st, out)
            .is_some()
    }

    /// `1/2 q_fᵀ k_ff q_f` by faer's SIMD product into the evaluation's work buffer.
    fn elastic_energy_evaluated(&self, q: &[f64], s: &mut ElementScratch) -> f64 {
        let nf = self.body.nf();
        let qf = &q[q.len() - nf..];
        let buf = &mut eval(s).state.rhs.as_mut_slice()[..nf];
        super::body::mat_vec(&self.body.k_ff, qf, buf);
        0.5 * buf.iter().zip(qf).map(|(a, b)| a * b).sum::<f64>()
    }

    fn kinetic_energy(&self, _q: &[f64], u: &[f64], s: &mut ElementScratch) -> f64 {
        self.body.kinetic_energy(&mut eval(s).state, u)
    }

    fn gravity_potential(&self, q: &[f64], gravity: &Vector3<f64>, s: &mut ElementScratch) -> f64 {
        // V = -sum_j m_j g . r_j = -g . (I1 R + A S_t), S_t = sum_j m_j u_bar_j (deformed)
        let st = &eval(s).state;
        let r = Vector3::new(q[0], q[1], q[2]);
        -gravity.dot(&(self.body.invariants.i1 * r + st.a * st.s_t))
    }

    fn load_stiffened_ffr(&self) -> Option<&FfrBody> {
        self.body.load_stiffening().map(|_| &self.body)
    }

    fn elastic_energy(&self, q: &[f64]) -> f64 {
        let nf = self.body.nf();
        let qf = &q[q.len() - nf..];
        let mut e = 0.0;
        for a in 0..nf {
            for c in 0..nf {
                e += 0.5 * qf[a] * self.body.k_ff[(a, c)] * qf[c];
            }
        }
        e
    }
}

/// The part of [`FfrBody::update`] that frame kinematics read: `A`, `H`, `omega_bar`, `H_dot w`,
/// `q_f`, `q_f_dot` (bitwise the values of a full update), without the O(n_f^2) deformed moments.
fn update_kinematic_state(
    b: &FfrBody,
    q: &[f64],
    u: &[f64],
    s: &mut FfrScratch,
) -> Result<(), super::FfrError> {
    let nr = b.rotation.num_coordinates();
    for (what, expected, found) in [("q", b.nq(), q.len()), ("u", b.nu(), u.len())] {
        if expected != found {
            return Err(super::FfrError::DimensionMismatch {
                what,
                expected,
                found,
            });
        }
    }
    if b.rotation == RotationParam::Quaternion {
        let norm = nalgebra::Vector4::new(q[3], q[4], q[5], q[6]).norm();
        if !(norm.is_finite() && norm > 1e-12) {
            return Err(crate::rotation::RotationError::DegenerateQuaternion { norm }.into());
        }
    }
    b.set_rotation_state(&q[3..3 + nr], &Vector3::new(u[3], u[4], u[5]), s)?;
    s.qf.copy_from_slice(&q[3 + nr..]);
    s.qfd.copy_from_slice(&u[6..]);
    Ok(())
}

/// Kinematics of `frame` from an evaluated state `s` (a mesh-node frame or a point fixed in the
/// floating frame); `None` for an invalid mesh node.
fn frame_from_state(
    b: &FfrBody,
    q: &[f64],
    u: &[f64],
    s: &FfrScratch,
    frame: &LocalFrame,
    out: &mut FrameKinematics,
) -> Option<()> {
    match frame.mesh_node {
        Some(node) => {
            let k = b.node_kinematics(node, q, u, s).ok()?;
            b.node_jacobian_translation(node, s, out.jac_t.as_mut())
                .ok()?;
            b.node_jacobian_rotation(node, s, out.jac_r.as_mut()).ok()?;
            out.position = k.r;
            out.rotation = k.frame * frame.rotation;
            out.velocity = k.v;
            out.angular_velocity = k.omega;
            out.bias_acc = k.a_bias;
            out.bias_ang_acc = k.alpha_bias;
        }
        None => point_fixed_in_reference_frame(b, q, u, s, frame, out),
    }
    Some(())
}

/// Kinematics of a point `p` (and orientation) fixed in the floating frame: `r = R + A p`,
/// `J_T = [I, -A p~ H, 0]`, `J_R = [0, A H, 0]`, bias `A (w x (w x p) + z x p)` and `A z`
/// (seed 000 (2.70), (2.72) with `u_bar = p`, no deformation).
fn point_fixed_in_reference_frame(
    b: &FfrBody,
    q: &[f64],
    u: &[f64],
    s: &FfrScratch,
    frame: &LocalFrame,
    out: &mut FrameKinematics,
) {
    let p = frame.position;
    let w = s.omega;
    let z = s.hdot_w;
    out.position = Vector3::new(q[0], q[1], q[2]) + s.a * p;
    out.rotation = s.a * frame.rotation;
    out.velocity = Vector3::new(u[0], u[1], u[2]) + s.a * w.cross(&p);
    out.angular_velocity = s.a * w;
    out.bias_acc = s.a * (w.cross(&w.cross(&p)) + z.cross(&p));
    out.bias_ang_acc = s.a * z;
    let jt_rot = -s.a * skew(&p) * s.h;
    let jr_rot = s.a * s.h;
    let nu = b.nu();
    for i in 0..3 {
        for j in 0..nu {
            out.jac_t[(i, j)] = 0.0;
            out.jac_r[(i, j)] = 0.0;
        }
        out.jac_t[(i, i)] = 1.0;
        for j in 0..3 {
            out.jac_t[(i, 3 + j)] = jt_rot[(i, j)];
            out.jac_r[(i, 3 + j)] = jr_rot[(i, j)];
        }
    }
}
