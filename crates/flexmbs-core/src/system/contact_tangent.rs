//! Tangent of the regularized contact forces ([`crate::contact::regularized`]): the stiffness
//! part `d(W_N F_N + W_T F_T)/dq` (along `q ⊕ dv`) and the damping part `d(..)/du` by central
//! differences on the coordinates of the contact's two owners only (a contour's body or node),
//! re-evaluating only those owners (kinematics path, `Element::update_kinematics` into the
//! probe scratches) and the contact search; the same scheme, steps and sinks (dense `dh_dq`,
//! `dh_du` or the sparse slots) as the local tangents of loads and force elements
//! ([`super::add_load_tangents`]). The differences include everything the forces depend on: the
//! law (`k`, `d`, friction), the moving contact point and frame, and a flexible contour's
//! deformation.

use super::local_tangent::{
    integrate_owner, owner_ranges, update_owned_frames, DenseTangents, TangentSink,
};
use crate::contact::regularized::add_regularized_contact_force;
use crate::contact::{Contact, ContactWork, ContourScratch, Friction, NormalLaw};
use crate::ids::FrameId;
use crate::model::{FrameOwner, Model};
use crate::state::SystemBuffers;

/// Whether a regularized contact's forces depend on the velocities (damping or friction).
fn depends_on_velocity(c: &Contact) -> bool {
    let damped = matches!(c.law.normal, NormalLaw::Regularized { damping, .. } if damping > 0.0);
    damped || matches!(c.law.friction, Friction::Regularized { .. })
}

/// The contact's frames and their owners.
fn contact_owners(model: &Model, c: &Contact) -> ([FrameId; 2], [FrameOwner; 2]) {
    let (fa, fb) = c.frames();
    (
        [fa, fb],
        [model.frames[fa.0].owner, model.frames[fb.0].owner],
    )
}

/// Adds the tangents `d h_c / dq` and (damping or friction) `d h_c / du` of the generalized
/// force `h_c = W_N F_N + W_T F_T` of one regularized contact `c` at `(q, u)` to `sink` (rows
/// and columns of the two owners; module documentation). `work` are the contact's contour
/// buffers, `start_gap` its gap at the start of the step ([`ContactWork::start_gap`]). Expects `ws.frames`
/// at `(q, u)` and leaves them there; a set-valued contact adds nothing. Steps: `1e-6` for
/// positions, `1e-6 max(1, |u_j|)` for velocities.
#[allow(clippy::too_many_arguments)]
pub(crate) fn add_contact_tangent(
    model: &Model,
    c: &Contact,
    q: &[f64],
    u: &[f64],
    ws: &mut SystemBuffers,
    work: &mut [ContourScratch; 2],
    start_gap: f64,
    sink: &mut impl TangentSink,
) {
    if c.law.set_valued_normal() {
        return;
    }
    let (frames, owners) = contact_owners(model, c);
    // both owners' probes at (q, u): a flexible contour reads its body's probe
    for &o in &owners {
        update_owned_frames(
            model,
            o,
            false,
            &frames,
            q,
            u,
            &mut ws.probe,
            &mut ws.frames,
        );
    }
    let velocity = depends_on_velocity(c);
    let overlap = owner_ranges(model, owners[0])
        .1
        .overlaps(&owner_ranges(model, owners[1]).1);
    for &o in &owners {
        let (rq, ru) = owner_ranges(model, o);
        rq.iter().for_each(|i| ws.q_pert[i] = q[i]);
        for i in ru.iter() {
            ws.u_pert[i] = u[i];
            ws.dv_pert[i] = 0.0;
        }
    }
    for &o in &owners {
        if o == FrameOwner::Ground {
            continue;
        }
        let ru = owner_ranges(model, o).1;
        for j in 0..ru.len() {
            let column = Column {
                model,
                c,
                q,
                u,
                frames: &frames,
                owners: &owners,
                owner: o,
                start_gap,
                overlap,
                gj: ru.at(j),
            };
            column.add(true, ws, work, sink);
            if velocity {
                column.add(false, ws, work, sink);
            }
        }
        update_owned_frames(
            model,
            o,
            overlap,
            &frames,
            q,
            u,
            &mut ws.probe,
            &mut ws.frames,
        );
    }
}

/// One column of the contact tangent: coordinate `gj` (global velocity index) of `owner`.
struct Column<'a> {
    model: &'a Model,
    c: &'a Contact,
    q: &'a [f64],
    u: &'a [f64],
    frames: &'a [FrameId; 2],
    owners: &'a [FrameOwner; 2],
    owner: FrameOwner,
    /// The contact's gap at the start of the step.
    start_gap: f64,
    /// The owners share coordinates (bodies on one node): each row once.
    overlap: bool,
    gj: usize,
}

impl Column<'_> {
    /// Central difference along the position (`q ⊕ dv`) or velocity of the column into `sink`.
    fn add(
        &self,
        position: bool,
        ws: &mut SystemBuffers,
        work: &mut [ContourScratch; 2],
        sink: &mut impl TangentSink,
    ) {
        let (model, gj) = (self.model, self.gj);
        let eps = if position {
            1e-6
        } else {
            1e-6 * self.u[gj].abs().max(1.0)
        };
        for plus in [true, false] {
            let e = if plus { eps } else { -eps };
            let o = self.owner;
            if position {
                ws.dv_pert[gj] = e;
                integrate_owner(model, o, self.q, &ws.dv_pert, &mut ws.q_pert);
                let (qp, pr, fr) = (&ws.q_pert, &mut ws.probe, &mut ws.frames);
                update_owned_frames(model, o, self.overlap, self.frames, qp, self.u, pr, fr);
            } else {
                ws.u_pert[gj] = self.u[gj] + e;
                let (up, pr, fr) = (&ws.u_pert, &mut ws.probe, &mut ws.frames);
                update_owned_frames(model, o, self.overlap, self.frames, self.q, up, pr, fr);
            }
            let hh = if plus {
                &mut ws.h_plus
            } else {
                &mut ws.h_minus
            };
            for &ow in self.owners {
                owner_ranges(model, ow).1.iter().for_each(|i| hh[i] = 0.0);
            }
            let geo = self.c.geometry(model, &ws.frames, &ws.probe, work);
            add_regularized_contact_force(
                model,
                self.c,
                &ws.frames,
                work,
                &geo,
                self.start_gap,
                hh,
            );
        }
        ws.dv_pert[gj] = 0.0;
        ws.u_pert[gj] = self.u[gj];
        for (k, &ow) in self.owners.iter().enumerate() {
            let rows = owner_ranges(model, ow).1;
            for i in rows.iter() {
                if self.overlap
                    && k == 1
                    && owner_ranges(model, self.owners[0]).1.iter().any(|r| r == i)
                {
                    continue;
                }
                let value = (ws.h_plus[i] - ws.h_minus[i]) / (2.0 * eps);
                sink.add(ws, i, gj, !position, value);
            }
        }
    }
}

/// Adds the tangents of every regularized contact of `model` at `(q, u)` to `sys.dh_dq` and
/// `sys.dh_du` (dense; [`add_contact_tangent`] per contact). Expects `sys` evaluated at
/// `(q, u)` ([`super::evaluate`]) and leaves its frames there.
pub fn add_contact_tangents(
    model: &Model,
    q: &[f64],
    u: &[f64],
    sys: &mut SystemBuffers,
    work: &mut ContactWork,
) {
    let all = model
        .contacts
        .iter()
        .zip(&mut work.sides)
        .zip(&work.start_gap);
    for ((c, w), &g0) in all {
        add_contact_tangent(model, c, q, u, sys, w, g0, &mut DenseTangents);
    }
}
