//! Checks and completions that need the compiled model and its initial state: joints assembled
//! and velocities consistent at `t = 0`, spring free lengths from the initial configuration.

use crate::compile::Ctx;
use crate::error::SimError;
use flexmbs_core::{system, Load, Model, SolverError, State, Workspace};

/// Spring-dampers given without `free_length` are unstressed in the initial state: their free
/// length is the initial distance of their frames. Part of compiling the model file (the model
/// is not handed out before), since the distance needs the compiled frames and initial poses.
pub(crate) fn spring_free_lengths_from_initial_state(
    model: &mut Model,
    initial: &State,
    loads: &[usize],
) {
    if loads.is_empty() {
        return;
    }
    let mut ws = Workspace::new(model);
    if system::evaluate(model, &initial.q, &initial.u, &mut ws.sys).is_err() {
        return; // the initial state cannot be evaluated: the run's initialization reports it
    }
    for &i in loads {
        if let Load::SpringDamper {
            frame_a,
            frame_b,
            free_length,
            ..
        } = &mut model.loads[i]
        {
            let f = &ws.sys.frames;
            *free_length = (f[frame_b.0].position - f[frame_a.0].position).norm();
        }
    }
}

/// The initial state must satisfy the joints ([`flexmbs_core::system::check_assembly`],
/// tolerance [`flexmbs_core::system::ASSEMBLY_TOL`]): otherwise the index-3 integrator would snap
/// the bodies together in the first step with arbitrary impulses (energy out of nowhere). The
/// error is located at the joint and says what to change.
pub(crate) fn check_initial_assembly(
    ctx: &Ctx,
    model: &Model,
    initial: &State,
) -> Result<(), SimError> {
    let mut ws = Workspace::new(model);
    match system::check_assembly(model, initial, &mut ws, system::ASSEMBLY_TOL) {
        Ok(()) => Ok(()),
        Err(SolverError::NotAssembled {
            joint,
            row,
            level,
            violation,
            tolerance,
        }) => {
            let j = model
                .joints
                .iter()
                .position(|x| x.name == joint)
                .unwrap_or(0);
            let unit = model.joints[j].row_unit(row);
            let message = if level == "position" {
                format!("joint `{joint}` is not assembled in the initial state: row {row} is off by {violation:.3e} {unit} (tolerance {tolerance:e}); place the bodies (`position`, `orientation`) so that its frames `a` and `b` coincide in the locked directions, or the solver would pull them together with arbitrary forces")
            } else {
                format!("joint `{joint}`: the initial velocities violate row {row} by {violation:.3e} {unit}/s (tolerance {tolerance:e}); set the bodies' `velocity` and `angular_velocity` consistently with the joint (and its prescribed motion)")
            };
            Err(ctx.err(&format!("joint[{j}]"), message))
        }
        Err(e) => Err(ctx.err("model", e.to_string())),
    }
}
