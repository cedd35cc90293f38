//! Checks and completions that need the compiled model and its initial state: joints assembled
//! and velocities consistent at `t = 0`, spring free lengths from the initial configuration.

use crate::compile::{Ctx, DOFS};
use crate::error::SimError;
use flexmbs_core::{system, Load, Model, PrescribedMotion, State, Workspace};

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
    system::update_frames(model, &initial.q, &initial.u, &mut ws.sys.frames);
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

/// Largest position violation `|g|` of a joint row accepted in the initial state (m or rad).
pub const ASSEMBLY_TOL: f64 = 1e-6;

/// The initial state must satisfy the joints: frames `a` and `b` of every joint coincide in
/// their locked directions (`|g| <= ASSEMBLY_TOL`) and the velocities are consistent
/// (`|G u + g_t| <= ASSEMBLY_TOL * max(1, |u|_inf)`). Otherwise the index-3 integrator would snap
/// the bodies together in the first step with arbitrary impulses (energy out of nowhere); the
/// error names the joint, the row and the violation.
pub(crate) fn check_initial_assembly(
    ctx: &Ctx,
    model: &Model,
    initial: &State,
) -> Result<(), SimError> {
    if model.nc == 0 {
        return Ok(());
    }
    let mut ws = Workspace::new(model);
    let sys = &mut ws.sys;
    system::update_frames(model, &initial.q, &initial.u, &mut sys.frames);
    system::assemble_constraints(
        model,
        initial.t,
        &sys.frames,
        &mut sys.g,
        sys.g_jac.as_mut(),
        &mut sys.g_t,
        &mut sys.g_bias,
    );
    let u_max = initial.u.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (j, (joint, &r0)) in model.joints.iter().zip(&model.joint_rows).enumerate() {
        let names: Vec<&str> = (0..6)
            .filter(|&d| joint.locked[d])
            .map(|d| DOFS[d])
            .chain(joint.prescribed.as_ref().map(|_| "motion"))
            .collect();
        for (k, name) in names.iter().enumerate() {
            let r = r0 + k;
            let unit = match (*name, &joint.prescribed) {
                ("tx" | "ty" | "tz", _) => "m",
                ("motion", Some(PrescribedMotion::PrismaticDisplacement(_))) => "m",
                _ => "rad",
            };
            let g = sys.g[r];
            if g.abs() > ASSEMBLY_TOL || !g.is_finite() {
                return Err(ctx.err(
                    &format!("joint[{j}]"),
                    format!(
                        "joint `{}` is not assembled in the initial state: row {name} is off by {g:.3e} {unit} (tolerance {ASSEMBLY_TOL:e}); place the bodies (`position`, `orientation`) so that its frames `a` and `b` coincide in the locked directions, or the solver would pull them together with arbitrary forces",
                        joint.name
                    ),
                ));
            }
            let gd = sys.g_t[r]
                + (0..model.nu)
                    .map(|c| sys.g_jac[(r, c)] * initial.u[c])
                    .sum::<f64>();
            if gd.abs() > ASSEMBLY_TOL * u_max || !gd.is_finite() {
                return Err(ctx.err(
                    &format!("joint[{j}]"),
                    format!(
                        "joint `{}`: the initial velocities violate row {name} by {gd:.3e} {unit}/s (tolerance {:e}); set the bodies' `velocity` and `angular_velocity` consistently with the joint (and its prescribed motion)",
                        joint.name,
                        ASSEMBLY_TOL * u_max
                    ),
                ));
            }
        }
    }
    Ok(())
}
