//! Stress recovery in a run (issue 11 item 5): the modal stress fields of an ffr body
//! ([`flexmbs_fe::stress`], computed from its FE model file or stored in its reduced-body file)
//! times its elastic coordinates, `sigma = sum_k S_k q_k` (linear FFR recovery), at output time
//! only: as the signal `<frame>.stress` at node frames and, with `output.stress = true`, as the
//! point fields `stress` and `von_mises` of the ParaView animation.

use crate::bodies::{BodyGeometry, LoadedBody};
use crate::compile::{BodyInfo, CompiledModel, Ctx};
use crate::error::SimError;
use crate::signals::{Signal, SignalKind};
use flexmbs_core::model::FrameOwner;
use flexmbs_core::{FrameId, Model};
use flexmbs_fe::stress::{equivalent_stress, ModalStress, NodeStressKind};
use std::sync::Arc;

/// Why a rigid body has no stress fields.
pub const RIGID_BODY: &str = "a rigid body has no stress (stress is recovered on ffr bodies)";

/// Why a seed-folder body has no stress fields.
pub const NO_FE_MESH: &str = "the body's source is a seed folder, which has no FE mesh to \
     recover stresses from: use an FE model file (.toml) or a reduced-body file (.fmb.h5) \
     written by `flexmbs reduce` as `source`";

/// Why a reduced-body file without the `stress` group has no stress fields.
pub const NO_STORED_STRESS: &str = "the reduced-body file has no modal stress fields (group \
     `stress`, written by `flexmbs reduce` since stress recovery exists): re-run `flexmbs \
     reduce` on its FE model file, or use that FE model file as `source`";

/// Component names of a stress signal at a solid node and at a beam node.
const SOLID_COMPONENTS: [&str; 7] = ["von_mises", "xx", "yy", "zz", "xy", "yz", "zx"];
const BEAM_COMPONENTS: [&str; 7] = [
    "von_mises",
    "axial",
    "bending_y",
    "bending_z",
    "torsion",
    "shear_y",
    "shear_z",
];

/// The stress fields of a loaded body for the modes `cols(nf)` selects, in SI (Pa per unit
/// SI modal coordinate of the body converted to SI), or the reason it has none. Takes them out of `loaded`.
pub(crate) fn selected_stress(
    loaded: &mut LoadedBody,
    cols: impl FnOnce(usize) -> Result<Vec<usize>, SimError>,
) -> Result<Result<Arc<ModalStress>, String>, SimError> {
    let stress = std::mem::replace(&mut loaded.stress, Err(String::new()));
    Ok(match stress {
        Ok(s) => {
            let cols = cols(s.num_modes())?;
            // sigma = S q with the body's modal coordinate q = q_si c / L
            // (`flexmbs_core::ffr::reduced_body_to_si`): S_si = S stress_to_si c / L
            let u = loaded.reduced.units;
            let factor = u.stress_to_si() * u.mode_to_si() / u.length_to_si();
            Ok(Arc::new(s.select_modes(&cols).scaled(factor)))
        }
        Err(reason) => Err(reason),
    })
}

/// The signal `<item>.stress` at node frame `f` (von Mises and the six components, Pa).
pub(crate) fn stress_signal(
    model: &Model,
    bodies: &[BodyInfo],
    item: &str,
    f: FrameId,
) -> Result<(String, Vec<String>, SignalKind), String> {
    let fr = &model.frames[f.0];
    let (Some(node), FrameOwner::Body(b)) = (fr.local.mesh_node, fr.owner) else {
        return Err(format!(
            "`{item}` is not a node frame of an ffr body: `stress` needs `node` or `nearest`"
        ));
    };
    let info = bodies
        .iter()
        .find(|x| x.id == b)
        .ok_or_else(|| "internal: body without info".to_string())?;
    let fields = info
        .geometry
        .stress
        .as_ref()
        .map_err(|reason| format!("`{item}.stress` on body `{}`: {reason}", info.name))?;
    let names = match fields.kinds[node] {
        NodeStressKind::Solid => SOLID_COMPONENTS,
        NodeStressKind::Beam => BEAM_COMPONENTS,
        NodeStressKind::None => {
            return Err(format!(
                "frame `{item}` is on a node without elements (a rigid-interface node): stresses \
                 are recovered at mesh nodes; put a frame on a mesh node (`node` or `nearest`)"
            ))
        }
    };
    let kind = SignalKind::Stress {
        body: b,
        node,
        fields: Arc::clone(fields),
    };
    let comps = names.iter().map(|c| c.to_string()).collect();
    Ok(("Pa".to_string(), comps, kind))
}

/// The elastic coordinates of a body with `nf` modes: the last `nf` of its coordinates
/// (`R`, rotation parameters, `q_f`).
fn elastic_coordinates<'a>(
    model: &Model,
    body: flexmbs_core::BodyId,
    q: &'a [f64],
    nf: usize,
) -> &'a [f64] {
    let bq = model.body_q(body, q);
    &bq[bq.len().saturating_sub(nf)..]
}

/// Writes the stress signals of state `q` into their places in `out` (laid out by
/// [`crate::signals::evaluate_signals`], which leaves them NaN). No allocation.
pub(crate) fn fill_stress_signals(signals: &[Signal], model: &Model, q: &[f64], out: &mut [f64]) {
    let mut at = 0;
    for s in signals {
        if let SignalKind::Stress { body, node, fields } = &s.kind {
            let qf = elastic_coordinates(model, *body, q, fields.num_modes());
            let v = fields.node_stress(*node, qf);
            if let Some(dst) = out.get_mut(at..at + 7) {
                dst[0] = equivalent_stress(fields.kinds[*node], &v);
                dst[1..].copy_from_slice(&v);
            }
        }
        at += s.components.len();
    }
}

/// The animation's point fields `stress` (6 components) and `von_mises` of every body's points
/// at state `q` (zero for rigid bodies and nodes without elements), in Pa.
pub(crate) fn point_stress_fields(cm: &CompiledModel, q: &[f64]) -> Vec<(String, usize, Vec<f64>)> {
    let n: usize = cm.bodies.iter().map(|b| b.geometry.points.len()).sum();
    let (mut stress, mut vm) = (Vec::with_capacity(6 * n), Vec::with_capacity(n));
    for b in &cm.bodies {
        let np = b.geometry.points.len();
        match &b.geometry.stress {
            Ok(f) if f.num_nodes() == np => {
                let qf = elastic_coordinates(&cm.model, b.id, q, f.num_modes());
                for node in 0..np {
                    let v = f.node_stress(node, qf);
                    stress.extend_from_slice(&v);
                    vm.push(equivalent_stress(f.kinds[node], &v));
                }
            }
            _ => {
                stress.extend(std::iter::repeat_n(0.0, 6 * np));
                vm.extend(std::iter::repeat_n(0.0, np));
            }
        }
    }
    vec![("stress".into(), 6, stress), ("von_mises".into(), 1, vm)]
}

/// `output.stress = true` needs the animation and stress fields on every ffr body.
pub(crate) fn check_stress_output(
    ctx: &Ctx,
    animation: bool,
    bodies: &[BodyInfo],
) -> Result<(), SimError> {
    if !animation {
        return Err(ctx.err(
            "output.stress",
            "stress fields are written into the ParaView animation, which `animation = false` \
             turns off; for stresses without the animation use `<frame>.stress` signals",
        ));
    }
    for b in bodies {
        if let (true, Err(reason)) = (is_ffr(&b.geometry), &b.geometry.stress) {
            return Err(ctx.err("output.stress", format!("body `{}`: {reason}", b.name)));
        }
    }
    Ok(())
}

fn is_ffr(g: &BodyGeometry) -> bool {
    g.fe_nodes
}
