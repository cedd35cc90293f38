//! The system stage of the FFR geometric stiffening by node loads ([`crate::ffr::LoadStiffening`]):
//! the load coefficients of each load-stiffened body from the joint multipliers, the loads and the
//! accelerations of an iterate, and the force `−K_load(c) q_f` they give.

use crate::element::{ElementScratch, FrameKinematics};
use crate::ffr::{FfrBody, FfrEval, LoadStiffening};
use crate::ids::BodyId;
use crate::joint::{joint_rows, ConstraintRow, MAX_JOINT_ROWS};
use crate::load::{FrameWrench, MAX_LOAD_FRAMES};
use crate::model::{FrameOwner, Model};
use crate::state::SystemBuffers;
use nalgebra::{Matrix3, Vector3};

/// Interface index of frame `f` if it is a mesh-node frame of body `b` at a node with load
/// patterns.
fn interface_of_frame(model: &Model, b: usize, ls: &LoadStiffening, f: usize) -> Option<usize> {
    let frame = &model.frames[f];
    match frame.owner {
        FrameOwner::Body(BodyId(o)) if o == b => ls.interface_of(frame.local.mesh_node?),
        _ => None,
    }
}

/// Adds a global wrench (force `f`, moment `m` about the node) to interface `k`'s coefficients in
/// body axes (`Aᵀ`).
fn add_wrench(c: &mut [f64], k: usize, a: &Matrix3<f64>, f: &Vector3<f64>, m: &Vector3<f64>) {
    let (fb, mb) = (a.transpose() * f, a.transpose() * m);
    for d in 0..3 {
        c[6 * k + d] += fb[d];
        c[6 * k + 3 + d] += mb[d];
    }
}

/// The load coefficients `c` of body `b` (see [`LoadStiffening`]) at time `t` from the frames in
/// `frames`, the multipliers `lambda`, the body's accelerations `u_dot_b`, its evaluated state
/// and `gravity` (scaled by the load factor), written to `c` (length
/// [`LoadStiffening::num_coefficients`]). No allocation.
#[allow(clippy::too_many_arguments)]
pub fn load_coefficients(
    model: &Model,
    b: usize,
    body: &FfrBody,
    t: f64,
    load_factor: f64,
    frames: &[FrameKinematics],
    lambda: &[f64],
    u_dot_b: &[f64],
    e: &FfrEval,
    c: &mut [f64],
) {
    let Some(ls) = body.load_stiffening() else {
        return;
    };
    c.fill(0.0);
    let a = e.state.a;
    let mut rows = [ConstraintRow::ZERO; MAX_JOINT_ROWS];
    for (joint, &first) in model.joints.iter().zip(&model.joint_rows) {
        let (fa, fb) = (joint.frame_a.index(), joint.frame_b.index());
        let (ka_if, kb_if) = (
            interface_of_frame(model, b, ls, fa),
            interface_of_frame(model, b, ls, fb),
        );
        if ka_if.is_none() && kb_if.is_none() {
            continue;
        }
        let n = joint.num_rows();
        joint_rows(joint, t, &frames[fa], &frames[fb], &mut rows[..n]);
        let l = &lambda[first..first + n];
        let sum = |pick: fn(&ConstraintRow) -> Vector3<f64>| {
            rows[..n]
                .iter()
                .zip(l)
                .fold(Vector3::zeros(), |s, (r, l)| s - pick(r) * *l)
        };
        if let Some(k) = ka_if {
            add_wrench(c, k, &a, &sum(|r| r.t_a), &sum(|r| r.r_a));
        }
        if let Some(k) = kb_if {
            add_wrench(c, k, &a, &sum(|r| r.t_b), &sum(|r| r.r_b));
        }
    }
    let z = Vector3::zeros();
    let mut w: [FrameWrench; MAX_LOAD_FRAMES] = [(crate::ids::FrameId(0), z, z); MAX_LOAD_FRAMES];
    for load in &model.loads {
        let n = load.wrenches(t, load_factor, frames, &mut w);
        for (frame, f, m) in &w[..n] {
            if let Some(k) = interface_of_frame(model, b, ls, frame.index()) {
                add_wrench(c, k, &a, f, m);
            }
        }
    }
    if ls.acceleration.is_some() {
        let o = 6 * ls.interfaces.len();
        let g = model.gravity * load_factor;
        let acc = a.transpose() * (Vector3::new(u_dot_b[0], u_dot_b[1], u_dot_b[2]) - g);
        let alpha = e.state.h * Vector3::new(u_dot_b[3], u_dot_b[4], u_dot_b[5]) + e.state.hdot_w;
        for d in 0..3 {
            c[o + d] = acc[d];
            c[o + 3 + d] = alpha[d];
        }
    }
}

/// For every body with node-load stiffening ([`crate::Element::load_stiffened_ffr`]): with
/// `update_coefficients`, its load coefficients at the iterate evaluated in `sys`
/// ([`super::evaluate`]; multipliers `lambda`, accelerations `u_dot`, loads scaled by
/// `load_factor`) into its scratch ([`FfrEval::load_coefficients`], which the element's tangent
/// reads); without, the coefficients kept there (frozen, see `docs/engine.md`); then the force
/// `−K_load(c) q_f` added to `sys.h` (after [`super::assemble_forces`]). No-op for a model without
/// such bodies; no allocation.
pub fn add_load_stiffening_forces(
    model: &Model,
    t: f64,
    load_factor: f64,
    u_dot: &[f64],
    lambda: &[f64],
    update_coefficients: bool,
    sys: &mut SystemBuffers,
) {
    for (i, b) in model.bodies.iter().enumerate() {
        let Some(body) = b.element.load_stiffened_ffr() else {
            continue;
        };
        let Some(ls) = body.load_stiffening() else {
            continue;
        };
        let (o, nu) = (b.u_offset, b.element.nu());
        let e = sys.eval[i].get_mut::<FfrEval>();
        let mut c = std::mem::take(&mut e.load_coefficients);
        if update_coefficients {
            load_coefficients(
                model,
                i,
                body,
                t,
                load_factor,
                &sys.frames,
                lambda,
                &u_dot[o..o + nu],
                e,
                &mut c,
            );
        }
        ls.add_force(&c, &e.state.qf, &mut sys.h[o..o + nu]);
        e.load_coefficients = c;
    }
}

/// Power `q̇_fᵀ (−K_load(c) q_f)` of the node-load stiffening forces of all bodies at an accepted
/// state `(t, u)` with its accelerations `u_dot` and multipliers `lambda`, from the elements
/// evaluated there (`eval`, [`super::evaluate_elements`]) and all frames (`frames`,
/// [`super::update_frames`]); the coefficients are recomputed into the scratches. The power the
/// energy balance adds for this non-potential force, like [`crate::power::stiffening_power`] for
/// the centrifugal one. Zero without such bodies; no allocation.
#[allow(clippy::too_many_arguments)]
pub fn load_stiffening_power(
    model: &Model,
    t: f64,
    u: &[f64],
    u_dot: &[f64],
    lambda: &[f64],
    eval: &mut [ElementScratch],
    frames: &[FrameKinematics],
) -> f64 {
    let mut p = 0.0;
    for (i, b) in model.bodies.iter().enumerate() {
        let Some(body) = b.element.load_stiffened_ffr() else {
            continue;
        };
        let Some(ls) = body.load_stiffening() else {
            continue;
        };
        let (o, nu) = (b.u_offset, b.element.nu());
        let e = eval[i].get_mut::<FfrEval>();
        let mut c = std::mem::take(&mut e.load_coefficients);
        let ud = &u_dot[o..o + nu];
        load_coefficients(model, i, body, t, 1.0, frames, lambda, ud, e, &mut c);
        p += ls.power(&c, &e.state.qf, &u[o + 6..o + nu]);
        e.load_coefficients = c;
    }
    p
}
