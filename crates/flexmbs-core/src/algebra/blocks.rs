//! Local dense blocks of the sparse backend and their slot maps: element blocks (mass and
//! force tangents on the element's columns) and coupling blocks (load tangents and the
//! geometric stiffness of constraint forces, by central differences over the coordinates of
//! the owners of the load's or joint's frames only).

use crate::element::{FrameKinematics, TangentScratch};
use crate::joint::{joint_rows, ConstraintRow, Joint, MAX_JOINT_ROWS};
use crate::load::FrameWrench;
use crate::model::{Body, FrameOwner, Model};
use crate::state::SystemBuffers;
use crate::{FrameId, Load};
use faer::Mat;
use nalgebra::Vector3;

/// An element's local `nu_e x nu_e` blocks and their slots (column-major).
pub(super) struct ElementBlock {
    offset: usize,
    slots: Vec<usize>,
    mass: Mat<f64>,
    dh_dq: Mat<f64>,
    dh_du: Mat<f64>,
}

impl ElementBlock {
    /// Blocks of `body` written to `slots`.
    pub(super) fn new(body: &Body, slots: Vec<usize>) -> Self {
        let n = body.element.nu();
        Self {
            offset: body.u_offset,
            slots,
            mass: Mat::zeros(n, n),
            dh_dq: Mat::zeros(n, n),
            dh_du: Mat::zeros(n, n),
        }
    }

    /// Element mass matrix at `q`.
    pub(super) fn compute_mass(&mut self, body: &Body, q: &[f64]) {
        let oq = body.q_offset;
        body.element
            .mass_matrix(&q[oq..oq + body.element.nq()], self.mass.as_mut());
    }

    /// Element force tangents at `(t, q, u)` with gravity `g`.
    pub(super) fn compute_tangents(
        &mut self,
        body: &Body,
        t: f64,
        q: &[f64],
        u: &[f64],
        g: &Vector3<f64>,
        scratch: &mut TangentScratch,
    ) {
        let (oq, n) = (body.q_offset, body.element.nu());
        self.dh_dq.fill(0.0);
        self.dh_du.fill(0.0);
        body.element.force_tangents(
            t,
            &q[oq..oq + body.element.nq()],
            &u[self.offset..self.offset + n],
            g,
            self.dh_dq.as_mut(),
            self.dh_du.as_mut(),
            scratch,
        );
    }

    /// `values[slot(i, j)] += f(M_ij, dh/dq_ij, dh/du_ij)` over the block.
    pub(super) fn scatter(&self, values: &mut [f64], f: impl Fn(f64, f64, f64) -> f64) {
        let n = self.mass.nrows();
        for j in 0..n {
            let (m, kq, ku) = (
                self.mass.col_as_slice(j),
                self.dh_dq.col_as_slice(j),
                self.dh_du.col_as_slice(j),
            );
            let slots = &self.slots[j * n..(j + 1) * n];
            for i in 0..n {
                values[slots[i]] += f(m[i], kq[i], ku[i]);
            }
        }
    }

    /// `out[cols] = M_e v[cols]` (the mass block is the element's scratch).
    pub(super) fn mass_times_vector(&mut self, body: &Body, q: &[f64], v: &[f64], out: &mut [f64]) {
        let (oq, o, n) = (body.q_offset, self.offset, body.element.nu());
        body.element.mass_times_vector(
            &q[oq..oq + body.element.nq()],
            &v[o..o + n],
            self.mass.as_mut(),
            &mut out[o..o + n],
        );
    }
}

/// A coupling block over the columns of the owners of some frames (a load's or a joint's).
pub(super) struct CouplingBlock {
    /// Owner bodies and the position of their first column in the block.
    owners: Vec<(usize, usize)>,
    /// The frames, with the index of their owner in `owners` (`None`: ground).
    frames: Vec<(FrameId, Option<usize>)>,
    slots: Vec<usize>,
    dh_dq: Mat<f64>,
    dh_du: Mat<f64>,
    plus: Vec<f64>,
    minus: Vec<f64>,
}

impl CouplingBlock {
    /// Block over `cols` (sorted owners' columns) for `frames`, written to `slots`.
    pub(super) fn new(
        model: &Model,
        cols: &[usize],
        frames: &[FrameId],
        slots: Vec<usize>,
    ) -> Self {
        let mut owners: Vec<(usize, usize)> = Vec::new();
        let mut fr = Vec::new();
        for &f in frames {
            let owner = match model.frames[f.0].owner {
                // node-owned frames never reach the sparse backend (`sparse_supported`)
                FrameOwner::Ground | FrameOwner::Node(_) => None,
                FrameOwner::Body(b) => {
                    let pos = cols
                        .binary_search(&model.bodies[b.0].u_offset)
                        .expect("owner columns in block");
                    let k = match owners.iter().position(|o| o.0 == b.0) {
                        Some(k) => k,
                        None => {
                            owners.push((b.0, pos));
                            owners.len() - 1
                        }
                    };
                    Some(k)
                }
            };
            fr.push((f, owner));
        }
        let n = cols.len();
        Self {
            owners,
            frames: fr,
            slots,
            dh_dq: Mat::zeros(n, n),
            dh_du: Mat::zeros(n, n),
            plus: vec![0.0; n],
            minus: vec![0.0; n],
        }
    }

    /// `values[slot(i, j)] += f(dh/dq_ij, dh/du_ij)` over the block.
    pub(super) fn scatter(&self, values: &mut [f64], f: impl Fn(f64, f64) -> f64) {
        let n = self.plus.len();
        for j in 0..n {
            let (kq, ku) = (self.dh_dq.col_as_slice(j), self.dh_du.col_as_slice(j));
            let slots = &self.slots[j * n..(j + 1) * n];
            for i in 0..n {
                values[slots[i]] += f(kq[i], ku[i]);
            }
        }
    }

    /// Kinematics of the block's frames owned by `owner` at `(q, u)` of that body.
    fn update_frames(
        &self,
        model: &Model,
        owner: usize,
        qb: &[f64],
        ub: &[f64],
        out: &mut [FrameKinematics],
    ) {
        let body = &model.bodies[self.owners[owner].0];
        for &(f, o) in &self.frames {
            if o == Some(owner) {
                body.element
                    .frame_kinematics(qb, ub, &model.frames[f.0].local, &mut out[f.0]);
            }
        }
    }

    /// Central differences of `eval` (block-local generalized forces at the current frames)
    /// along `q ⊕ dv` and `u` of every owner coordinate: columns of `dh_dq`, `dh_du`
    /// (the same steps as [`crate::system::assemble_tangents`]). Frames end at `(q, u)`.
    fn differentiate(
        &mut self,
        model: &Model,
        q: &[f64],
        u: &[f64],
        sys: &mut SystemBuffers,
        eval: impl Fn(&[FrameKinematics], &[(usize, usize)], &mut [f64]),
    ) {
        for k in 0..self.owners.len() {
            let (b, pos) = self.owners[k];
            let body = &model.bodies[b];
            let (nq, nu, oq, o) = (
                body.element.nq(),
                body.element.nu(),
                body.q_offset,
                body.u_offset,
            );
            let (qb, ub) = (&q[oq..oq + nq], &u[o..o + nu]);
            let dv = &mut sys.dv_pert[o..o + nu];
            let up = &mut sys.u_pert[o..o + nu];
            dv.fill(0.0);
            up.copy_from_slice(ub);
            for j in 0..nu {
                let eps = 1e-6;
                for sign in [1.0, -1.0] {
                    dv[j] = sign * eps;
                    body.element
                        .integrate_position(qb, dv, &mut sys.q_pert[oq..oq + nq]);
                    self.update_frames(model, k, &sys.q_pert[oq..oq + nq], ub, &mut sys.frames);
                    let out = if sign > 0.0 {
                        &mut self.plus
                    } else {
                        &mut self.minus
                    };
                    eval(&sys.frames, &self.owners, out);
                }
                dv[j] = 0.0;
                difference_column(&mut self.dh_dq, pos + j, &self.plus, &self.minus, eps);
                let eps = 1e-6 * ub[j].abs().max(1.0);
                for sign in [1.0, -1.0] {
                    up[j] = ub[j] + sign * eps;
                    self.update_frames(model, k, qb, up, &mut sys.frames);
                    let out = if sign > 0.0 {
                        &mut self.plus
                    } else {
                        &mut self.minus
                    };
                    eval(&sys.frames, &self.owners, out);
                }
                up[j] = ub[j];
                difference_column(&mut self.dh_du, pos + j, &self.plus, &self.minus, eps);
            }
            self.update_frames(model, k, qb, ub, &mut sys.frames);
        }
    }

    /// Tangents of the generalized forces of `load` (load factor `mu`) on the owners' columns.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn load_tangents(
        &mut self,
        model: &Model,
        load: &Load,
        t: f64,
        mu: f64,
        q: &[f64],
        u: &[f64],
        sys: &mut SystemBuffers,
    ) {
        self.differentiate(model, q, u, sys, |frames, owners, out| {
            out.fill(0.0);
            let mut w: [FrameWrench; 2] = [(FrameId(0), Vector3::zeros(), Vector3::zeros()); 2];
            let n = load.wrenches(t, mu, frames, &mut w);
            for (frame, f, m) in &w[..n] {
                let Some(pos) = owner_position(model, owners, *frame) else {
                    continue;
                };
                let k = &frames[frame.0];
                for j in 0..k.jac_t.ncols() {
                    let mut s = 0.0;
                    for i in 0..3 {
                        s += k.jac_t[(i, j)] * f[i] + k.jac_r[(i, j)] * m[i];
                    }
                    out[pos + j] += s;
                }
            }
        });
    }

    /// `d(G_j^T lambda_j)/dq` of one joint (rows `lambda`) on its owners' columns, into `dh_dq`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn constraint_force_tangent(
        &mut self,
        model: &Model,
        joint: &Joint,
        t: f64,
        lambda: &[f64],
        q: &[f64],
        u: &[f64],
        sys: &mut SystemBuffers,
    ) {
        self.differentiate(model, q, u, sys, |frames, owners, out| {
            out.fill(0.0);
            let mut rows = [ConstraintRow::ZERO; MAX_JOINT_ROWS];
            let n = joint.num_rows();
            let (ka, kb) = (&frames[joint.frame_a.0], &frames[joint.frame_b.0]);
            joint_rows(joint, t, ka, kb, &mut rows[..n]);
            for (side, frame) in [joint.frame_a, joint.frame_b].into_iter().enumerate() {
                let Some(pos) = owner_position(model, owners, frame) else {
                    continue;
                };
                let k = &frames[frame.0];
                for j in 0..k.jac_t.ncols() {
                    let mut s = 0.0;
                    for (row, l) in rows[..n].iter().zip(lambda) {
                        let (ct, cr) = if side == 0 {
                            (&row.t_a, &row.r_a)
                        } else {
                            (&row.t_b, &row.r_b)
                        };
                        for d in 0..3 {
                            s += (ct[d] * k.jac_t[(d, j)] + cr[d] * k.jac_r[(d, j)]) * l;
                        }
                    }
                    out[pos + j] += s;
                }
            }
        });
    }
}

/// Block position of the first column of `frame`'s owner (`None`: ground).
fn owner_position(model: &Model, owners: &[(usize, usize)], frame: FrameId) -> Option<usize> {
    match model.frames[frame.0].owner {
        FrameOwner::Ground | FrameOwner::Node(_) => None,
        FrameOwner::Body(b) => owners.iter().find(|o| o.0 == b.0).map(|o| o.1),
    }
}

fn difference_column(m: &mut Mat<f64>, col: usize, hp: &[f64], hm: &[f64], eps: f64) {
    for (i, (p, n)) in hp.iter().zip(hm).enumerate() {
        m[(i, col)] = (p - n) / (2.0 * eps);
    }
}
