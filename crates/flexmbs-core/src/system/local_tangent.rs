//! Local finite-difference tangents of loads and constraint forces: per load (per joint), only
//! the coordinates of the owners of its frames are perturbed and only its frames re-evaluated
//! (`Element::update_kinematics`), so the cost does not grow with the rest of the model.
//!
//! The one implementation for both algebra backends: the entries go to a [`TangentSink`], the
//! dense `ws.dh_dq` / `ws.dh_du` ([`DenseTangents`]) or the compressed-column slots of the sparse
//! backend (`crate::algebra`).

use super::{add_frame_wrench, add_one_load_force};
use crate::element::{ElementScratch, FrameKinematics};
use crate::gather::with_local;
use crate::ids::FrameId;
use crate::joint::{joint_rows, ConstraintRow, MAX_JOINT_ROWS};
use crate::load::{Load, MAX_LOAD_FRAMES};
use crate::model::{FrameOwner, Model};
use crate::node::DofMap;
use crate::state::SystemBuffers;
use nalgebra::Vector3;

/// The frames a load acts on (one for point loads, two for a spring-damper, up to
/// [`MAX_LOAD_FRAMES`] for a force element).
fn load_frames(load: &Load) -> ([FrameId; MAX_LOAD_FRAMES], usize) {
    let mut ids = [FrameId(0); MAX_LOAD_FRAMES];
    let n = load.frames(&mut ids);
    (ids, n)
}

/// The distinct owners (bodies or nodes) of `frames` (ground frames have none), at most
/// [`MAX_LOAD_FRAMES`].
fn frame_owners(model: &Model, frames: &[FrameId]) -> ([FrameOwner; MAX_LOAD_FRAMES], usize) {
    let mut owners = [FrameOwner::Ground; MAX_LOAD_FRAMES];
    let mut n = 0;
    for f in frames {
        let o = model.frames[f.0].owner;
        if o != FrameOwner::Ground && !owners[..n].contains(&o) {
            owners[n] = o;
            n += 1;
        }
    }
    (owners, n)
}

/// Global indices of a frame owner's coordinates: a range (a node, a contiguous body) or a
/// list (a scattered body).
#[derive(Debug, Clone)]
pub(super) enum Cols<'a> {
    Range(std::ops::Range<usize>),
    List(&'a [usize]),
}

impl<'a> Cols<'a> {
    fn of(map: &'a DofMap) -> Self {
        match map {
            DofMap::Contiguous(r) => Cols::Range(r.clone()),
            DofMap::Scattered(v) => Cols::List(v),
        }
    }

    pub(super) fn len(&self) -> usize {
        match self {
            Cols::Range(r) => r.len(),
            Cols::List(v) => v.len(),
        }
    }

    /// Global index of local coordinate `j`.
    pub(super) fn at(&self, j: usize) -> usize {
        match self {
            Cols::Range(r) => r.start + j,
            Cols::List(v) => v[j],
        }
    }

    fn contains(&self, i: usize) -> bool {
        match self {
            Cols::Range(r) => r.contains(&i),
            Cols::List(v) => v.contains(&i),
        }
    }

    pub(super) fn overlaps(&self, other: &Cols) -> bool {
        match (self, other) {
            (Cols::Range(a), Cols::Range(b)) => a.start < b.end && b.start < a.end,
            _ => (0..self.len()).any(|j| other.contains(self.at(j))),
        }
    }

    pub(super) fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.len()).map(|j| self.at(j))
    }
}

/// Global `q` and `u` indices of a frame owner (empty for ground).
pub(super) fn owner_ranges(model: &Model, owner: FrameOwner) -> (Cols<'_>, Cols<'_>) {
    match owner {
        FrameOwner::Ground => (Cols::Range(0..0), Cols::Range(0..0)),
        FrameOwner::Body(b) => {
            let d = model.bodies[b.0].dofs();
            (Cols::of(&d.q), Cols::of(&d.u))
        }
        FrameOwner::Node(n) => (
            Cols::Range(model.nodes[n.0].q.clone()),
            Cols::Range(model.nodes[n.0].u.clone()),
        ),
    }
}

/// `q_new = q ⊕ dv` on the coordinates of `owner` (global vectors; a scattered body node by
/// node).
pub(super) fn integrate_owner(
    model: &Model,
    owner: FrameOwner,
    q: &[f64],
    dv: &[f64],
    q_new: &mut [f64],
) {
    let node = |n: crate::NodeId, q_new: &mut [f64]| {
        let n = &model.nodes[n.0];
        let (rq, ru) = (n.q.clone(), n.u.clone());
        n.kind.integrate(&q[rq.clone()], &dv[ru], &mut q_new[rq]);
    };
    match owner {
        FrameOwner::Ground => {}
        FrameOwner::Body(b) => {
            let b = &model.bodies[b.0];
            if b.is_scattered() {
                for n in &b.nodes {
                    node(*n, q_new);
                }
                return;
            }
            let (oq, o, nq, nu) = (b.q_offset, b.u_offset, b.element.nq(), b.element.nu());
            let (qo, dvo) = (&q[oq..oq + nq], &dv[o..o + nu]);
            b.element
                .integrate_position(qo, dvo, &mut q_new[oq..oq + nq]);
        }
        FrameOwner::Node(n) => node(n, q_new),
    }
}

/// Re-evaluates the frames in `frames` (all of them with `all`, else those owned by `owner`) at
/// `(q, u)` through the kinematics-only path ([`crate::Element::update_kinematics`] into the
/// body's `probe` scratch, so the evaluated state of the iterate is left alone). A perturbed
/// state the element cannot evaluate gives NaN frames (a non-finite tangent).
#[allow(clippy::too_many_arguments)]
pub(super) fn update_owned_frames(
    model: &Model,
    owner: FrameOwner,
    all: bool,
    frames: &[FrameId],
    q: &[f64],
    u: &[f64],
    probe: &mut [ElementScratch],
    out: &mut [FrameKinematics],
) {
    for f in frames {
        let frame = &model.frames[f.0];
        if !(all || frame.owner == owner) {
            continue;
        }
        let k = &mut out[f.0];
        match frame.owner {
            FrameOwner::Ground => {}
            FrameOwner::Body(b) => {
                let (body, p) = (&model.bodies[b.0], &mut probe[b.0]);
                let element = &body.element;
                with_local(body, q, u, p, |qo, uo, p| {
                    match element.update_kinematics(qo, uo, p) {
                        Ok(()) => element.frame_kinematics(qo, uo, p, &frame.local, k),
                        Err(_) => {
                            k.position.fill(f64::NAN);
                            k.velocity.fill(f64::NAN);
                        }
                    }
                });
            }
            FrameOwner::Node(n) => {
                let n = &model.nodes[n.0];
                let (qo, uo) = (&q[n.q.clone()], &u[n.u.clone()]);
                n.kind.frame_kinematics(qo, uo, &frame.local, k)
            }
        }
    }
}

/// Target of local tangent entries: `value` is entry `(row, col)` (global velocity indices) of
/// `d(force)/dq` (along `q ⊕ dv`), or of `d(force)/du` with `velocity`, to be added.
pub(crate) trait TangentSink {
    /// Adds one entry (`ws` is the workspace the tangent is computed with).
    fn add(&mut self, ws: &mut SystemBuffers, row: usize, col: usize, velocity: bool, value: f64);
}

/// The dense target: `ws.dh_dq` and `ws.dh_du`.
pub(crate) struct DenseTangents;

impl TangentSink for DenseTangents {
    fn add(&mut self, ws: &mut SystemBuffers, row: usize, col: usize, velocity: bool, value: f64) {
        let m = if velocity {
            &mut ws.dh_du
        } else {
            &mut ws.dh_dq
        };
        m[(row, col)] += value;
    }
}

/// A generalized force of some frames (one load, or one joint's constraint forces) evaluated
/// from the frame kinematics into the rows of the frames' owners.
trait FrameForce {
    /// Adds the force to `h` with `frames` evaluated at the current state.
    fn add(&self, frames: &[FrameKinematics], h: &mut [f64]);
}

/// A [`FrameForce`] to differentiate locally, with the owners of its frames.
struct LocalTangent<'a> {
    model: &'a Model,
    q: &'a [f64],
    u: &'a [f64],
    frames: &'a [FrameId],
    force: &'a dyn FrameForce,
    /// `+1` adds the derivative, `-1` subtracts it.
    sign: f64,
    /// The distinct owners of `frames`.
    owners: &'a [FrameOwner],
    /// Their velocity coordinates (rows and columns).
    rows: [Cols<'a>; MAX_LOAD_FRAMES],
    /// The owners share coordinates (bodies on a shared node, a node frame and a body on that
    /// node): each global column / row once, and a perturbation moves every frame.
    overlap: bool,
}

impl LocalTangent<'_> {
    /// Global index `i` belongs to an owner before the `k`-th (already differentiated).
    fn covered(&self, k: usize, i: usize) -> bool {
        self.overlap && self.rows[..k].iter().any(|r| r.contains(i))
    }

    /// Adds `sign` times the central difference along coordinate `j` of `owner` (position along
    /// `q ⊕ dv`, or velocity) to `sink` (column of `d/dq` / `d/du`, rows of all owners).
    fn add_column(
        &self,
        owner: FrameOwner,
        j: usize,
        position: bool,
        ws: &mut SystemBuffers,
        sink: &mut impl TangentSink,
    ) {
        let (model, q, u, frames) = (self.model, self.q, self.u, self.frames);
        let gj = owner_ranges(model, owner).1.at(j);
        let eps = if position {
            1e-6
        } else {
            1e-6 * u[gj].abs().max(1.0)
        };
        for plus in [true, false] {
            let e = if plus { eps } else { -eps };
            if position {
                ws.dv_pert[gj] = e;
                integrate_owner(model, owner, q, &ws.dv_pert, &mut ws.q_pert);
                let qp = &ws.q_pert;
                let (pr, fr) = (&mut ws.probe, &mut ws.frames);
                update_owned_frames(model, owner, self.overlap, frames, qp, u, pr, fr);
            } else {
                ws.u_pert[gj] = u[gj] + e;
                let up = &ws.u_pert;
                let (pr, fr) = (&mut ws.probe, &mut ws.frames);
                update_owned_frames(model, owner, self.overlap, frames, q, up, pr, fr);
            }
            let hh = if plus {
                &mut ws.h_plus
            } else {
                &mut ws.h_minus
            };
            for r in &self.rows[..self.owners.len()] {
                match r {
                    Cols::Range(r) => hh[r.clone()].fill(0.0),
                    Cols::List(v) => v.iter().for_each(|&i| hh[i] = 0.0),
                }
            }
            self.force.add(&ws.frames, hh);
        }
        ws.dv_pert[gj] = 0.0;
        ws.u_pert[gj] = u[gj];
        for (kr, r) in self.rows[..self.owners.len()].iter().enumerate() {
            for i in r.iter().filter(|&i| !self.covered(kr, i)) {
                let value = self.sign * (ws.h_plus[i] - ws.h_minus[i]) / (2.0 * eps);
                sink.add(ws, i, gj, !position, value);
            }
        }
    }
}

/// Central differences of a [`FrameForce`] along `q ⊕ dv` (position columns) and `u` (velocity
/// columns) of the owners of its frames only, re-evaluating only those frames: adds
/// `sign * d(force)/dq` and, with `velocity`, `sign * d(force)/du` to `sink` (rows and columns
/// of the owners, each global entry once). Expects `ws.frames` of `frames` at `(q, u)` and leaves them
/// there. Steps: `1e-6` for positions, `1e-6 max(1, |u_j|)` for velocities.
#[allow(clippy::too_many_arguments)]
fn add_local_force_tangent(
    model: &Model,
    q: &[f64],
    u: &[f64],
    frames: &[FrameId],
    force: &dyn FrameForce,
    sign: f64,
    velocity: bool,
    ws: &mut SystemBuffers,
    sink: &mut impl TangentSink,
) {
    let (owners, n_owners) = frame_owners(model, frames);
    let owners = &owners[..n_owners];
    let rows: [_; MAX_LOAD_FRAMES] = std::array::from_fn(|k| {
        owners
            .get(k)
            .map_or(Cols::Range(0..0), |&o| owner_ranges(model, o).1)
    });
    let overlap = (0..n_owners).any(|i| (i + 1..n_owners).any(|j| rows[i].overlaps(&rows[j])));
    let lt = LocalTangent {
        model,
        q,
        u,
        frames,
        force,
        sign,
        owners,
        rows,
        overlap,
    };
    for (k, &ob) in owners.iter().enumerate() {
        let (rq, ru) = owner_ranges(model, ob);
        for i in rq.iter() {
            ws.q_pert[i] = q[i];
        }
        for i in ru.iter() {
            ws.u_pert[i] = u[i];
            ws.dv_pert[i] = 0.0;
        }
        for j in 0..ru.len() {
            if lt.covered(k, ru.at(j)) {
                continue;
            }
            lt.add_column(ob, j, true, ws, sink);
            if velocity {
                lt.add_column(ob, j, false, ws, sink);
            }
        }
        update_owned_frames(
            model,
            ob,
            overlap,
            frames,
            q,
            u,
            &mut ws.probe,
            &mut ws.frames,
        );
    }
}

/// One load as a [`FrameForce`].
struct LoadForce<'a> {
    model: &'a Model,
    load: &'a Load,
    t: f64,
    load_factor: f64,
}

impl FrameForce for LoadForce<'_> {
    fn add(&self, frames: &[FrameKinematics], h: &mut [f64]) {
        add_one_load_force(self.model, self.load, self.t, self.load_factor, frames, h);
    }
}

/// Adds the load tangents `d(J^T w)/dq` and `d(J^T w)/du` of every load to `ws.dh_dq`, `ws.dh_du`
/// by central differences ([`add_local_force_tangent`]): per load, only the coordinates of the
/// owners of its frames are perturbed and only its frames re-evaluated, so the cost does not grow
/// with the size of the rest of the model; velocity columns only for damped springs (point loads
/// and undamped springs do not depend on `u`: their `dh_du` is exactly zero). Expects `ws.frames` at `(q, u)` and leaves them there.
pub fn add_load_tangents(
    model: &Model,
    t: f64,
    q: &[f64],
    u: &[f64],
    load_factor: f64,
    ws: &mut SystemBuffers,
) {
    for load in &model.loads {
        add_one_load_tangent(model, load, t, q, u, load_factor, ws, &mut DenseTangents);
    }
}

/// The tangents `d(J^T w)/dq`, `d(J^T w)/du` of one load (load factor `load_factor`) into
/// `sink`, as in [`add_load_tangents`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn add_one_load_tangent(
    model: &Model,
    load: &Load,
    t: f64,
    q: &[f64],
    u: &[f64],
    load_factor: f64,
    ws: &mut SystemBuffers,
    sink: &mut impl TangentSink,
) {
    if add_analytic_force_tangent(model, load, t, q, u, load_factor, ws, sink) {
        return;
    }
    let (frames, n) = load_frames(load);
    let force = LoadForce {
        model,
        load,
        t,
        load_factor,
    };
    // point loads and undamped springs do not depend on u: no velocity columns
    let velocity = load.depends_on_velocity();
    add_local_force_tangent(model, q, u, &frames[..n], &force, 1.0, velocity, ws, sink);
}

/// The tangent of a point force on a body whose element provides it analytically
/// ([`crate::Element::force_load_tangent`]) into `sink` (the body's rows and columns); `false`
/// for any other load (the caller differentiates it numerically).
#[allow(clippy::too_many_arguments)]
fn add_analytic_force_tangent(
    model: &Model,
    load: &Load,
    t: f64,
    q: &[f64],
    u: &[f64],
    load_factor: f64,
    ws: &mut SystemBuffers,
    sink: &mut impl TangentSink,
) -> bool {
    let Load::Force {
        frame,
        vector,
        time,
        coordinates,
    } = load
    else {
        return false;
    };
    let f = &model.frames[frame.0];
    let FrameOwner::Body(b) = f.owner else {
        return false;
    };
    let ru = owner_ranges(model, f.owner).1;
    let n = ru.len();
    let force = vector * (time.value(t) * load_factor);
    let follower = *coordinates == crate::load::LoadCoordinates::Frame;
    let body = &model.bodies[b.0];
    let (e, block) = (
        &mut ws.eval[b.0],
        ws.load_block.as_mut().submatrix_mut(0, 0, n, n),
    );
    let provided = with_local(body, q, u, e, |qb, ub, e| {
        let element = &body.element;
        element.force_load_tangent(qb, ub, e, &f.local, &force, follower, block)
    });
    if !provided {
        return false;
    }
    for j in 0..n {
        for i in 0..n {
            let value = ws.load_block[(i, j)];
            if value != 0.0 {
                sink.add(ws, ru.at(i), ru.at(j), false, value);
            }
        }
    }
    true
}

/// The constraint forces `G_j^T lambda_j` of one joint as a [`FrameForce`].
struct JointForce<'a> {
    model: &'a Model,
    joint: &'a crate::Joint,
    t: f64,
    lambda: &'a [f64],
}

impl FrameForce for JointForce<'_> {
    fn add(&self, frames: &[FrameKinematics], h: &mut [f64]) {
        let joint = self.joint;
        let n = joint.num_rows();
        let mut rows = [ConstraintRow::ZERO; MAX_JOINT_ROWS];
        let (ka, kb) = (&frames[joint.frame_a.0], &frames[joint.frame_b.0]);
        joint_rows(joint, self.t, ka, kb, &mut rows[..n]);
        // G^T lambda = sum_rows lambda_i (J_T^T t + J_R^T r) per side: a wrench per frame
        let mut sides = [(Vector3::zeros(), Vector3::zeros()); 2];
        for (row, l) in rows[..n].iter().zip(self.lambda) {
            sides[0].0 += row.t_a * *l;
            sides[0].1 += row.r_a * *l;
            sides[1].0 += row.t_b * *l;
            sides[1].1 += row.r_b * *l;
        }
        for (frame, (f, m)) in [joint.frame_a, joint.frame_b].into_iter().zip(sides) {
            add_frame_wrench(self.model, frame, &f, &m, frames, h);
        }
    }
}

/// Subtracts the geometric stiffness of the constraint forces, `d(G^T lambda)/dq` (along
/// `q ⊕ dv`, central differences), from `sys.dh_dq`. Needed by statics, where the reduced
/// stiffness of a mechanism comes from it. Per joint, only the coordinates of the owners of its
/// two frames are perturbed and only those frames re-evaluated ([`add_local_force_tangent`]).
/// Expects `sys.frames` at `(q, u)` and leaves them there; the constraint buffers are untouched.
pub fn subtract_constraint_force_tangent(
    model: &Model,
    t: f64,
    q: &[f64],
    u: &[f64],
    lambda: &[f64],
    sys: &mut SystemBuffers,
) {
    for (joint, &r0) in model.joints.iter().zip(&model.joint_rows) {
        let lambda = &lambda[r0..r0 + joint.num_rows()];
        subtract_one_constraint_force_tangent(
            model,
            joint,
            t,
            q,
            u,
            lambda,
            sys,
            &mut DenseTangents,
        );
    }
}

/// `-d(G_j^T lambda_j)/dq` of one joint (`lambda`: its rows) into `sink`, as in
/// [`subtract_constraint_force_tangent`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn subtract_one_constraint_force_tangent(
    model: &Model,
    joint: &crate::Joint,
    t: f64,
    q: &[f64],
    u: &[f64],
    lambda: &[f64],
    ws: &mut SystemBuffers,
    sink: &mut impl TangentSink,
) {
    let force = JointForce {
        model,
        joint,
        t,
        lambda,
    };
    let frames = [joint.frame_a, joint.frame_b];
    add_local_force_tangent(model, q, u, &frames, &force, -1.0, false, ws, sink);
}
