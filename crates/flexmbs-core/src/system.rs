//! System-level assembly: frame kinematics, mass matrix, forces, tangents, constraints and
//! energies of a [`Model`] at given `(t, q, u)`, written into preallocated buffers.

use crate::element::{ElementScratch, FrameKinematics};
use crate::error::{EvaluationError, SolverError};
use crate::gather::{with_local, with_local_q};
use crate::ids::FrameId;
use crate::joint::{joint_rows, ConstraintRow, MAX_JOINT_ROWS};
use crate::load::{FrameWrench, Load};
use crate::model::{FrameOwner, Model};
use crate::state::{ElementBuffers, State, SystemBuffers, Workspace};
use faer::MatMut;

mod contact_tangent;
mod load_stiffening;
mod local_tangent;
pub(crate) use contact_tangent::add_contact_tangent;
pub use contact_tangent::add_contact_tangents;
pub use load_stiffening::{add_load_stiffening_forces, load_coefficients, load_stiffening_power};
pub use local_tangent::{add_load_tangents, subtract_constraint_force_tangent};
pub(crate) use local_tangent::{
    add_one_load_tangent, subtract_one_constraint_force_tangent, TangentSink,
};
use nalgebra::Vector3;

/// Energies of a state (seed 000 eq. (2.43) for the kinetic part).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energy {
    /// Kinetic energy.
    pub kinetic: f64,
    /// Potential energy of gravity.
    pub gravity: f64,
    /// Elastic energy of the elements.
    pub elastic: f64,
    /// Energy stored in springs.
    pub springs: f64,
}

impl Energy {
    /// Sum of all parts.
    pub fn total(&self) -> f64 {
        self.kinetic + self.gravity + self.elastic + self.springs
    }
}

/// The evaluation stage of one state: every body's element evaluated at `(q, u)` into
/// `sys.eval` ([`crate::Element::update`]), then the kinematics of every frame into
/// `sys.frames`. The assembly functions below read both, so call this first at each state.
/// Err: the first body whose element cannot be evaluated, and why.
pub fn evaluate(
    model: &Model,
    q: &[f64],
    u: &[f64],
    sys: &mut SystemBuffers,
) -> Result<(), EvaluationError> {
    evaluate_elements(model, q, u, &mut sys.eval)?;
    update_frames(model, q, u, &mut sys.eval, &mut sys.frames);
    Ok(())
}

/// Every body's element evaluated at `(q, u)` into `eval` (one scratch per body, body order).
pub fn evaluate_elements(
    model: &Model,
    q: &[f64],
    u: &[f64],
    eval: &mut [ElementScratch],
) -> Result<(), EvaluationError> {
    for (b, e) in model.bodies.iter().zip(eval.iter_mut()) {
        with_local(b, q, u, e, |qb, ub, e| b.element.update(qb, ub, e)).map_err(|cause| {
            EvaluationError {
                body: b.name.clone(),
                cause,
            }
        })?;
    }
    Ok(())
}

/// [`evaluate_elements`] through the kinematics-only path ([`crate::Element::update_kinematics`]):
/// enough for [`update_frames`] and [`update_selected_frames`], not for mass, forces or energies.
pub fn evaluate_kinematics(
    model: &Model,
    q: &[f64],
    u: &[f64],
    eval: &mut [ElementScratch],
) -> Result<(), EvaluationError> {
    for (b, e) in model.bodies.iter().zip(eval.iter_mut()) {
        with_local(b, q, u, e, |qb, ub, e| {
            b.element.update_kinematics(qb, ub, e)
        })
        .map_err(|cause| EvaluationError {
            body: b.name.clone(),
            cause,
        })?;
    }
    Ok(())
}

/// The largest [`crate::Element::force_scale`] of the bodies at `q` (0 if none has one).
/// Allocates for a body with scattered coordinates; inside a step use [`force_scale_in`].
pub fn force_scale(model: &Model, q: &[f64]) -> f64 {
    let mut buf = Vec::new();
    model
        .bodies
        .iter()
        .map(|b| {
            let qb = crate::gather::gathered(&b.dofs().q, q, &mut buf);
            b.element.force_scale(qb)
        })
        .fold(0.0, f64::max)
}

/// [`force_scale`] with the gather buffers of the bodies' scratches `eval` (no allocation).
pub fn force_scale_in(model: &Model, q: &[f64], eval: &mut [ElementScratch]) -> f64 {
    model
        .bodies
        .iter()
        .zip(eval.iter_mut())
        .map(|(b, e)| with_local_q(b, q, e, |qb, _| b.element.force_scale(qb)))
        .fold(0.0, f64::max)
}

/// Kinematics of every frame at `(q, u)`; `eval` must hold the elements evaluated there.
pub fn update_frames(
    model: &Model,
    q: &[f64],
    u: &[f64],
    eval: &mut [ElementScratch],
    frames: &mut [FrameKinematics],
) {
    for (i, k) in frames.iter_mut().enumerate().take(model.frames.len()) {
        frame_kinematics_into(model, FrameId(i), q, u, eval, k);
    }
}

/// Kinematics of frame `id` at `(q, u)` into `k`, by its owner: ground (constant), a body's
/// element (evaluated in `eval`), or a node.
fn frame_kinematics_into(
    model: &Model,
    id: FrameId,
    q: &[f64],
    u: &[f64],
    eval: &mut [ElementScratch],
    k: &mut FrameKinematics,
) {
    let f = &model.frames[id.index()];
    match f.owner {
        FrameOwner::Ground => {
            k.position = f.local.position;
            k.rotation = f.local.rotation;
        }
        FrameOwner::Body(b) => {
            let (body, e) = (&model.bodies[b.0], &mut eval[b.0]);
            with_local(body, q, u, e, |qb, ub, e| {
                body.element.frame_kinematics(qb, ub, e, &f.local, k)
            });
        }
        FrameOwner::Node(n) => {
            let n = &model.nodes[n.0];
            let (qn, un) = (&q[n.q.clone()], &u[n.u.clone()]);
            n.kind.frame_kinematics(qn, un, &f.local, k);
        }
    }
}

/// Kinematics of the frames `ids` only at `(q, u)` (the other entries of `frames` are left as
/// they are), as [`update_frames`] computes them; `eval` must hold the elements evaluated at
/// `(q, u)`. No allocation.
pub fn update_selected_frames(
    model: &Model,
    q: &[f64],
    u: &[f64],
    eval: &mut [ElementScratch],
    ids: &[FrameId],
    frames: &mut [FrameKinematics],
) {
    for id in ids {
        frame_kinematics_into(model, *id, q, u, eval, &mut frames[id.index()]);
    }
}

/// Global mass matrix `M(q)` from the evaluated elements `eval`. Every element overwrites its
/// diagonal block ([`crate::Element::mass_matrix`]); only the entries outside these blocks are
/// zeroed. With shared nodes the blocks overlap: each is computed into `local` and added.
pub fn assemble_mass(
    model: &Model,
    q: &[f64],
    eval: &mut [ElementScratch],
    mut mass: MatMut<'_, f64>,
    local: &mut [ElementBuffers],
) {
    if model.general_layout() {
        mass.fill(0.0);
        for ((b, l), e) in model
            .bodies
            .iter()
            .zip(local.iter_mut())
            .zip(eval.iter_mut())
        {
            with_local_q(b, q, e, |qb, e| {
                b.element.mass_matrix(qb, e, l.mass.as_mut())
            });
            b.dofs().u.scatter_add_block(mass.as_mut(), &l.mass);
        }
        return;
    }
    zero_outside_diagonal_blocks(model, mass.as_mut());
    for (b, e) in model.bodies.iter().zip(eval.iter_mut()) {
        let (nq, nu) = (b.element.nq(), b.element.nu());
        b.element.mass_matrix(
            &q[b.q_offset..b.q_offset + nq],
            e,
            mass.as_mut().submatrix_mut(b.u_offset, b.u_offset, nu, nu),
        );
    }
}

/// Zeroes the entries of a `nu x nu` matrix that lie outside the bodies' diagonal blocks
/// (the coupling blocks between bodies, zero in `M`). Nothing to do for a single body.
fn zero_outside_diagonal_blocks(model: &Model, mut m: MatMut<'_, f64>) {
    for b in &model.bodies {
        let (o, nu) = (b.u_offset, b.element.nu());
        for j in o..o + nu {
            let mut col = m.as_mut().col_mut(j);
            for i in (0..o).chain(o + nu..col.nrows()) {
                col[i] = 0.0;
            }
        }
    }
}

/// `out = M(q) v` for the global (block-diagonal) mass matrix, body by body with
/// [`crate::Element::mass_times_vector`] from the evaluated elements `eval`; `mass` (nu x nu) is
/// scratch for elements without their own product: afterwards it is not a valid assembled `M`
/// (use [`assemble_mass`] for that).
#[allow(clippy::too_many_arguments)]
pub fn mass_times_vector(
    model: &Model,
    q: &[f64],
    v: &[f64],
    eval: &mut [ElementScratch],
    mut mass: MatMut<'_, f64>,
    out: &mut [f64],
    local: &mut [ElementBuffers],
) {
    if model.general_layout() {
        out.fill(0.0);
        for ((b, l), e) in model
            .bodies
            .iter()
            .zip(local.iter_mut())
            .zip(eval.iter_mut())
        {
            with_local(b, q, v, e, |qb, vb, e| {
                b.element
                    .mass_times_vector(qb, e, vb, l.mass.as_mut(), &mut l.h)
            });
            b.dofs().u.scatter_add(&l.h, out);
        }
        return;
    }
    for (b, e) in model.bodies.iter().zip(eval.iter_mut()) {
        let (nq, nu, o) = (b.element.nq(), b.element.nu(), b.u_offset);
        b.element.mass_times_vector(
            &q[b.q_offset..b.q_offset + nq],
            e,
            &v[o..o + nu],
            mass.as_mut().submatrix_mut(o, o, nu, nu),
            &mut out[o..o + nu],
        );
    }
}

/// Global forces `sys.h = h(t, q, u)` of the elements (gravity scaled by `load_factor`) plus
/// all loads, from the evaluated state in `sys` ([`evaluate`] at `(q, u)`: elements and frames).
pub fn assemble_forces(
    model: &Model,
    t: f64,
    q: &[f64],
    u: &[f64],
    load_factor: f64,
    sys: &mut SystemBuffers,
) {
    let g = model.gravity * load_factor;
    let h = &mut sys.h;
    let general = model.general_layout();
    if general {
        h.fill(0.0);
    }
    for (i, (b, e)) in model.bodies.iter().zip(sys.eval.iter_mut()).enumerate() {
        if general {
            let l = &mut sys.local[i].h;
            with_local(b, q, u, e, |qb, ub, e| {
                b.element.forces(t, qb, ub, &g, e, l)
            });
            b.dofs().u.scatter_add(l, h);
        } else {
            let (nq, nu, oq, o) = (b.element.nq(), b.element.nu(), b.q_offset, b.u_offset);
            let (qb, ub) = (&q[oq..oq + nq], &u[o..o + nu]);
            b.element.forces(t, qb, ub, &g, e, &mut h[o..o + nu]);
        }
    }
    add_load_forces(model, t, load_factor, &sys.frames, h);
}

/// Adds the generalized forces `J_T^T f + J_R^T m` of all loads to `h`.
pub fn add_load_forces(
    model: &Model,
    t: f64,
    load_factor: f64,
    frames: &[FrameKinematics],
    h: &mut [f64],
) {
    for load in &model.loads {
        add_one_load_force(model, load, t, load_factor, frames, h);
    }
}

/// Adds the generalized forces of one load to `h` (the rows of the owners of its frames).
fn add_one_load_force(
    model: &Model,
    load: &Load,
    t: f64,
    load_factor: f64,
    frames: &[FrameKinematics],
    h: &mut [f64],
) {
    let mut w: [FrameWrench; crate::load::MAX_LOAD_FRAMES] =
        [(FrameId(0), Vector3::zeros(), Vector3::zeros()); crate::load::MAX_LOAD_FRAMES];
    let n = load.wrenches(t, load_factor, frames, &mut w);
    for (frame, f, m) in &w[..n] {
        add_frame_wrench(model, *frame, f, m, frames, h);
    }
}

/// Adds the generalized force `J_T^T f + J_R^T m` of a wrench (force `f`, moment `m`, global) at
/// `frame` to `h`, in the columns of the frame's owner (nothing for a ground frame; seed 000
/// (2.76)).
pub(crate) fn add_frame_wrench(
    model: &Model,
    frame: FrameId,
    f: &Vector3<f64>,
    m: &Vector3<f64>,
    frames: &[FrameKinematics],
    h: &mut [f64],
) {
    let cols = model.frame_cols(frame);
    let k = &frames[frame.0];
    for j in 0..k.jac_t.ncols() {
        let mut s = 0.0;
        for i in 0..3 {
            s += k.jac_t[(i, j)] * f[i] + k.jac_r[(i, j)] * m[i];
        }
        h[global_col(cols, j)] += s;
    }
}

/// Tangents `ws.dh_dq` (along `q ⊕ dv`) and `ws.dh_du` of the full `h`: element blocks via
/// [`crate::Element::force_tangents`], load contributions by central differences
/// ([`add_load_tangents`]). Expects `ws` evaluated at `(q, u)` ([`evaluate`]) and leaves it there.
pub fn assemble_tangents(
    model: &Model,
    t: f64,
    q: &[f64],
    u: &[f64],
    load_factor: f64,
    ws: &mut SystemBuffers,
) {
    ws.dh_dq.fill(0.0);
    ws.dh_du.fill(0.0);
    let g = model.gravity * load_factor;
    let scratches = ws.tangent_scratch.iter_mut().zip(ws.eval.iter_mut());
    for (i, (b, (fd, e))) in model.bodies.iter().zip(scratches).enumerate() {
        if model.general_layout() {
            let l = &mut ws.local[i];
            let (dq, du) = (l.dh_dq.as_mut(), l.dh_du.as_mut());
            with_local(b, q, u, e, |qb, ub, e| {
                b.element.force_tangents(t, qb, ub, &g, e, dq, du, fd)
            });
            b.dofs().u.scatter_add_block(ws.dh_dq.as_mut(), &l.dh_dq);
            b.dofs().u.scatter_add_block(ws.dh_du.as_mut(), &l.dh_du);
        } else {
            let (nq, nu, oq, o) = (b.element.nq(), b.element.nu(), b.q_offset, b.u_offset);
            let (qb, ub) = (&q[oq..oq + nq], &u[o..o + nu]);
            let dq = ws.dh_dq.as_mut().submatrix_mut(o, o, nu, nu);
            let du = ws.dh_du.as_mut().submatrix_mut(o, o, nu, nu);
            b.element.force_tangents(t, qb, ub, &g, e, dq, du, fd);
        }
    }
    add_load_tangents(model, t, q, u, load_factor, ws);
}

/// [`assemble_constraints`] into the constraint buffers of `sys` (`g`, `G`, `g_t`, bias) from its
/// frames, which must be up to date.
pub fn update_constraints(model: &Model, t: f64, sys: &mut SystemBuffers) {
    assemble_constraints(
        model,
        t,
        &sys.frames,
        &mut sys.g,
        sys.g_jac.as_mut(),
        &mut sys.g_t,
        &mut sys.g_bias,
    );
    if !model.guides.is_empty() {
        crate::contact::guide::assemble_guides(
            model,
            &sys.frames,
            &sys.eval,
            &mut sys.guides,
            &mut sys.g,
            sys.g_jac.as_mut(),
            &mut sys.g_t,
            &mut sys.g_bias,
        );
    }
}

/// As [`update_constraints`], but the guides' rows only get their values `g`, not their `G`,
/// `g_t`, bias rows (these keep the last full update's): for iterations that need `g` at a new
/// state and keep an earlier `G` (the Moreau steppers' position projection). The values equal
/// [`update_constraints`]' bit for bit.
pub fn update_constraint_values(model: &Model, t: f64, sys: &mut SystemBuffers) {
    assemble_constraints(
        model,
        t,
        &sys.frames,
        &mut sys.g,
        sys.g_jac.as_mut(),
        &mut sys.g_t,
        &mut sys.g_bias,
    );
    if !model.guides.is_empty() {
        crate::contact::guide::guide_values(
            model,
            &sys.frames,
            &sys.eval,
            &mut sys.guides,
            &mut sys.g,
        );
    }
}

/// Constraint values `g`, Jacobian `G`, `g_t` and acceleration bias of all joints at `t`.
/// `frames` must be up to date. The rows of `G` are written, not accumulated, over the columns
/// of each joint's bodies only ([`write_joint_jacobian`]); `g_jac` must be zero elsewhere (as
/// the workspace's `G` is from its allocation on).
pub fn assemble_constraints(
    model: &Model,
    t: f64,
    frames: &[FrameKinematics],
    g: &mut [f64],
    mut g_jac: MatMut<'_, f64>,
    g_t: &mut [f64],
    g_bias: &mut [f64],
) {
    let mut rows = [ConstraintRow::ZERO; MAX_JOINT_ROWS];
    for (joint, &r0) in model.joints.iter().zip(&model.joint_rows) {
        let n = joint.num_rows();
        let (ka, kb) = (&frames[joint.frame_a.0], &frames[joint.frame_b.0]);
        joint_rows(joint, t, ka, kb, &mut rows[..n]);
        for (i, row) in rows[..n].iter().enumerate() {
            g[r0 + i] = row.g;
            g_t[r0 + i] = row.g_t;
            g_bias[r0 + i] = row.bias;
        }
        write_joint_jacobian(model, joint, &rows[..n], frames, g_jac.as_mut(), r0);
    }
}

/// Writes the rows `r0..r0 + rows.len()` of `G` of one joint: row `i` is
/// `t_a^T J_T^a + r_a^T J_R^a` in the columns of the body of frame `a`, plus
/// `t_b^T J_T^b + r_b^T J_R^b` in those of the body of frame `b` (added if it is the same body).
/// The other columns of these rows are not touched: they are zero from the allocation on (no
/// one else writes `G`), so assembling costs `O(rows x owner columns)`, not `O(nc x nu)`.
/// Column by column (contiguous Jacobian and `G` columns).
fn write_joint_jacobian(
    model: &Model,
    joint: &crate::Joint,
    rows: &[ConstraintRow],
    frames: &[FrameKinematics],
    mut g_jac: MatMut<'_, f64>,
    r0: usize,
) {
    let n = rows.len();
    let body_of = |frame: crate::FrameId| match model.frames[frame.0].owner {
        FrameOwner::Body(b) => Some(b.0),
        FrameOwner::Ground | FrameOwner::Node(_) => None,
    };
    let (body_a, body_b) = (body_of(joint.frame_a), body_of(joint.frame_b));
    let node_owned =
        |frame: crate::FrameId| matches!(model.frames[frame.0].owner, FrameOwner::Node(_));
    // overlapping (shared nodes) or node-owned column blocks: zero the rows, then accumulate
    // both sides; otherwise zero the columns of the other bodies and overwrite
    let general = model.general_layout() || node_owned(joint.frame_a) || node_owned(joint.frame_b);
    if general {
        for j in 0..g_jac.ncols() {
            col_slice_mut(g_jac.as_mut(), j)[r0..r0 + n].fill(0.0);
        }
    }
    // with finite row coefficients an all-zero Jacobian column gives exactly zero entries
    // (e.g. the modal columns of a point fixed in a floating frame): skip its products. The sum
    // of all coefficients is finite only if each one is (an overflow only disables the skip).
    let coefficient_sum: f64 = rows
        .iter()
        .map(|r| (r.t_a + r.r_a + r.t_b + r.r_b).sum())
        .sum();
    let finite = coefficient_sum.is_finite();
    let sides = [
        (joint.frame_a, !general),
        (joint.frame_b, body_a != body_b && !general),
    ];
    for (side, (frame, first)) in sides.into_iter().enumerate() {
        if model.frames[frame.0].owner == FrameOwner::Ground {
            continue;
        }
        let cols = model.frame_cols(frame);
        let k = &frames[frame.0];
        for j in 0..k.jac_t.ncols() {
            let (jt, jr) = (k.jac_t.col_as_slice(j), k.jac_r.col_as_slice(j));
            let col = &mut col_slice_mut(g_jac.as_mut(), global_col(cols, j))[r0..r0 + n];
            if finite && jt.iter().chain(jr).all(|x| *x == 0.0) {
                if first {
                    col.fill(0.0);
                }
                continue;
            }
            for (gj, row) in col.iter_mut().zip(rows) {
                let (ct, cr) = if side == 0 {
                    (&row.t_a, &row.r_a)
                } else {
                    (&row.t_b, &row.r_b)
                };
                let mut s = 0.0;
                for d in 0..3 {
                    s += ct[d] * jt[d] + cr[d] * jr[d];
                }
                if first {
                    *gj = s;
                } else {
                    *gj += s;
                }
            }
        }
    }
}

/// Global column of a frame's Jacobian column `j` (its owner's map).
fn global_col(cols: &crate::DofMap, j: usize) -> usize {
    match cols {
        crate::DofMap::Contiguous(r) => r.start + j,
        crate::DofMap::Scattered(v) => v[j],
    }
}

/// Column `j` of a matrix view with contiguous columns (as all `Mat` views here) as a slice.
fn col_slice_mut(m: MatMut<'_, f64>, j: usize) -> &mut [f64] {
    m.col_mut(j)
        .try_as_col_major_mut()
        .expect("column-major matrix")
        .as_slice_mut()
}

/// Energies at `(q, u)` from the elements evaluated there (`eval`, [`evaluate_elements`]) and
/// the frames (for the springs).
pub fn energy(
    model: &Model,
    q: &[f64],
    u: &[f64],
    eval: &mut [ElementScratch],
    frames: &[FrameKinematics],
) -> Energy {
    let mut e = Energy::default();
    for (b, s) in model.bodies.iter().zip(eval.iter_mut()) {
        with_local(b, q, u, s, |qb, ub, s| {
            e.kinetic += b.element.kinetic_energy(qb, ub, s);
            e.gravity += b.element.gravity_potential(qb, &model.gravity, s);
            e.elastic += b.element.elastic_energy_evaluated(qb, s);
        });
    }
    e.springs = model.loads.iter().map(|l| l.potential_energy(frames)).sum();
    e
}

/// `max |g|` and `max |G u + g_t|` (constraint drift) with up-to-date `ws.g`, `ws.g_jac`, `ws.g_t`.
pub fn constraint_drift(ws: &SystemBuffers, u: &[f64]) -> (f64, f64) {
    let mut gmax: f64 = 0.0;
    let mut gdmax: f64 = 0.0;
    for r in 0..ws.g.len() {
        let mut gd = ws.g_t[r];
        for (j, uj) in u.iter().enumerate() {
            gd += ws.g_jac[(r, j)] * uj;
        }
        gmax = gmax.max(ws.g[r].abs());
        gdmax = gdmax.max(gd.abs());
    }
    (gmax, gdmax)
}

/// Global `q ⊕ dv`, body by body (node by node when bodies share nodes).
pub fn integrate_positions(model: &Model, q: &[f64], dv: &[f64], q_new: &mut [f64]) {
    if model.general_layout() {
        for n in &model.nodes {
            let (rq, ru) = (n.q.clone(), n.u.clone());
            n.kind.integrate(&q[rq.clone()], &dv[ru], &mut q_new[rq]);
        }
        return;
    }
    for b in &model.bodies {
        let (nq, nu, oq, o) = (b.element.nq(), b.element.nu(), b.q_offset, b.u_offset);
        b.element
            .integrate_position(&q[oq..oq + nq], &dv[o..o + nu], &mut q_new[oq..oq + nq]);
    }
}

/// Global `q_dot = T(q) u`, body by body (node by node when bodies share nodes).
pub fn q_dot(model: &Model, q: &[f64], u: &[f64], q_dot: &mut [f64]) {
    if model.general_layout() {
        for n in &model.nodes {
            let (rq, ru) = (n.q.clone(), n.u.clone());
            n.kind.q_dot(&q[rq.clone()], &u[ru], &mut q_dot[rq]);
        }
        return;
    }
    for b in &model.bodies {
        let (nq, nu, oq, o) = (b.element.nq(), b.element.nu(), b.q_offset, b.u_offset);
        b.element
            .q_dot(&q[oq..oq + nq], &u[o..o + nu], &mut q_dot[oq..oq + nq]);
    }
}

/// Normalizes all element coordinates (unit quaternions).
pub fn normalize(model: &Model, q: &mut [f64]) {
    if model.general_layout() {
        for n in &model.nodes {
            n.kind.normalize(&mut q[n.q.clone()]);
        }
        return;
    }
    for b in &model.bodies {
        let (nq, oq) = (b.element.nq(), b.q_offset);
        b.element.normalize(&mut q[oq..oq + nq]);
    }
}

/// Position tolerance of [`check_assembly`] (m or rad); velocities are checked to this tolerance
/// times `max(1, |u|_inf)` (m/s or rad/s).
pub const ASSEMBLY_TOL: f64 = 1e-6;

/// Checks that state `s` satisfies every joint: `|g| <= tol` per row and
/// `|G u + g_t| <= tol max(1, |u|_inf)`. An unassembled start makes an index-3 integrator pull the
/// bodies together with arbitrary impulses in its first step; the error names the joint and row.
pub fn check_assembly(
    model: &Model,
    s: &State,
    ws: &mut Workspace,
    tol: f64,
) -> Result<(), SolverError> {
    check_state_size(model, s)?;
    if model.nc == 0 {
        return Ok(());
    }
    let sys = &mut ws.sys;
    evaluate(model, &s.q, &s.u, sys).map_err(|e| e.at(s.t, 0.0))?;
    update_constraints(model, s.t, sys);
    let u_scale = s.u.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (joint, &r0) in model.joints.iter().zip(&model.joint_rows) {
        for (k, row) in joint.row_names().enumerate() {
            let r = r0 + k;
            let g = sys.g[r];
            let g_dot = sys.g_t[r]
                + (0..model.nu)
                    .map(|c| sys.g_jac[(r, c)] * s.u[c])
                    .sum::<f64>();
            for (level, v, t) in [("position", g, tol), ("velocity", g_dot, tol * u_scale)] {
                if v.abs() > t || !v.is_finite() {
                    return Err(SolverError::NotAssembled {
                        joint: joint.name.clone(),
                        row,
                        level,
                        violation: v,
                        tolerance: t,
                    });
                }
            }
        }
    }
    Ok(())
}

/// The state's vectors have the model's lengths (`q`: nq; `u`, `u_dot`, `a`: nu; `lambda`: nc).
pub fn check_state_size(model: &Model, s: &State) -> Result<(), SolverError> {
    for (what, got, expected) in [
        ("q", s.q.len(), model.nq),
        ("u", s.u.len(), model.nu),
        ("u_dot", s.u_dot.len(), model.nu),
        ("a", s.a.len(), model.nu),
        ("lambda", s.lambda.len(), model.nc),
    ] {
        if got != expected {
            return Err(SolverError::StateSize {
                what,
                got,
                expected,
            });
        }
    }
    Ok(())
}
