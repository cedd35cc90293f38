//! Frames, signals and coordinate names of superelement beams ([`crate::superelements`]):
//! `[[frame]]` entries on interface points, the signals `<body>.s<k>.deformation` (local interface
//! coordinates and internal-mode amplitudes) and `<body>.s<k>.frame_iterations` (Newton iterations
//! of the floating-frame recovery), and names of the coordinates of shared nodes.

use crate::compile::{BodyInfo, Ctx};
use crate::error::SimError;
use crate::schema::FrameSpec;
use crate::signals::{Signal, SignalKind};
use crate::superelements::{Component, SuperelementBuild};
use crate::units::Dimension;
use flexmbs_core::superelement::SuperelementEval;
use flexmbs_core::{BodyId, ElementScratch, FrameId, Model, ModelSpec, NodeKind};
use nalgebra::{Matrix3, Vector3};

/// A `[[frame]]` on an interface point of component `c` (`interface = "<name>"` or `"i<k>"`),
/// offset by `position` / `orientation` in the interface node's axes.
pub(crate) fn interface_frame(
    ctx: &Ctx,
    p: &str,
    f: &FrameSpec,
    c: &Component,
    se: &SuperelementBuild,
    spec: &mut ModelSpec,
) -> Result<FrameId, SimError> {
    if f.node.is_some() || f.nearest.is_some() {
        return Err(ctx.err(
            p,
            format!(
                "`{}` is a superelement_beam body: its frames sit on interface points \
                 (`interface`), not on FE nodes",
                c.name
            ),
        ));
    }
    let Some(name) = &f.interface else {
        return Err(ctx.err(
            p,
            format!(
                "`{}` is a superelement_beam body: give the interface point the frame sits on, \
                 `interface` = one of {} (or i0 .. i{})",
                c.name,
                c.interfaces.join(", "),
                c.interfaces.len() - 1
            ),
        ));
    };
    let by_index = name
        .strip_prefix('i')
        .and_then(|k| k.parse::<usize>().ok())
        .and_then(|k| c.interfaces.get(k));
    let full = c.interfaces.iter().find(|n| *n == name).or(by_index);
    let node = full.and_then(|n| se.interface_node(n)).ok_or_else(|| {
        ctx.err(
            &format!("{p}.interface"),
            format!(
                "unknown interface `{name}` of `{}` (interfaces: {}, or i0 .. i{})",
                c.name,
                c.interfaces.join(", "),
                c.interfaces.len() - 1
            ),
        )
    })?;
    let position = match &f.position {
        Some(v) => ctx.vec3(v, Dimension::Length, &format!("{p}.position"))?,
        None => Vector3::zeros(),
    };
    let rotation = match &f.orientation {
        Some(o) => crate::config::orientation(ctx, o, &format!("{p}.orientation"))?,
        None => Matrix3::identity(),
    };
    Ok(spec.add_node_owned_frame(&f.name, node, position, rotation))
}

/// True if `body` is a superelement.
fn is_superelement(model: &Model, body: BodyId) -> bool {
    model.bodies[body.0]
        .element
        .new_scratch()
        .try_get::<SuperelementEval>()
        .is_some()
}

/// The signal `what` of frame `frame` if it is the floating frame of a superelement:
/// `deformation` (its local coordinates `q_loc`: per interface `u` (m) and `theta` (rad) in the
/// floating-frame axes, then the internal-mode amplitudes) or `frame_iterations`.
pub(crate) fn segment_signal(
    model: &Model,
    bodies: &[BodyInfo],
    frame: FrameId,
    what: &str,
) -> Option<(String, Vec<String>, SignalKind)> {
    let info = bodies.iter().find(|b| b.frame == frame)?;
    if !is_superelement(model, info.id) {
        return None;
    }
    match what {
        "deformation" => {
            let scratch = model.bodies[info.id.0].element.new_scratch();
            let e = scratch.try_get::<SuperelementEval>()?;
            let n = e.q_loc.len();
            let kinds = model.bodies[info.id.0].element.node_kinds();
            let interfaces = kinds.iter().filter(|k| **k == NodeKind::Pose).count();
            let mut names = Vec::with_capacity(n);
            for k in 0..interfaces {
                for q in ["u", "theta"] {
                    names.extend(["x", "y", "z"].iter().map(|c| format!("{q}{k}_{c}")));
                }
            }
            names.extend((1..=n - 6 * interfaces).map(|j| format!("eta{j}")));
            Some((
                "m | rad | 1".into(),
                names,
                SignalKind::SuperelementDeformation(info.id),
            ))
        }
        "frame_iterations" => Some((
            "1".into(),
            vec!["value".into()],
            SignalKind::FrameIterations(info.id),
        )),
        _ => None,
    }
}

/// Writes the superelement signals into `out` (laid out like [`crate::signals::evaluate_signals`])
/// from the evaluated elements `eval`.
pub(crate) fn fill_superelement_signals(
    signals: &[Signal],
    eval: &[ElementScratch],
    out: &mut [f64],
) {
    let mut at = 0;
    for s in signals {
        let width = s.components.len();
        let e = match &s.kind {
            SignalKind::SuperelementDeformation(b) | SignalKind::FrameIterations(b) => {
                eval[b.0].try_get::<SuperelementEval>()
            }
            _ => None,
        };
        if let (Some(e), Some(dst)) = (e, out.get_mut(at..at + width)) {
            match &s.kind {
                SignalKind::FrameIterations(_) => dst[0] = e.iterations as f64,
                _ => dst.copy_from_slice(e.q_loc.as_slice()),
            }
        }
        at += width;
    }
}

/// Names of a superelement's position and velocity coordinates, from its nodes (shared interface
/// nodes get the same names from every body on them): `<interface>.x|y|z|p0..p3` and
/// `<interface>.v_x..w_z`, `<body>.eta<j>` and `<body>.etad<j>`; `None` for other bodies.
pub(crate) fn node_coordinate_names(
    model: &Model,
    body: BodyId,
) -> Option<(Vec<String>, Vec<String>)> {
    if !is_superelement(model, body) {
        return None;
    }
    let dofs = model.body_dofs(body);
    let name = |g: usize, q: bool| {
        let (id, k) = if q {
            model.q_owner(g)
        } else {
            model.u_owner(g)
        }?;
        let node = &model.nodes[id.index()];
        let pose_q = ["x", "y", "z", "p0", "p1", "p2", "p3"];
        let pose_u = ["v_x", "v_y", "v_z", "w_x", "w_y", "w_z"];
        let local = match (node.kind, q) {
            (NodeKind::Pose, true) => pose_q[k].to_string(),
            (NodeKind::Pose, false) => pose_u[k].to_string(),
            (_, true) => format!("{}", k + 1),
            (_, false) => format!("d{}", k + 1),
        };
        Some(format!("{}.{local}", node.name))
    };
    let q = dofs
        .q
        .iter()
        .map(|g| name(g, true))
        .collect::<Option<_>>()?;
    let u = dofs
        .u
        .iter()
        .map(|g| name(g, false))
        .collect::<Option<_>>()?;
    Some((q, u))
}
