//! Checks that need the compiled model and its initial state: joints assembled
//! and velocities consistent at `t = 0`.

use crate::compile::Ctx;
use crate::error::SimError;
use flexmbs_core::{system, Model, SolverError, State, Workspace};

/// `solver.initial = "static"` starts at rest: initial body velocities would be discarded, so
/// they are refused with their key.
pub(crate) fn check_static_start(ctx: &Ctx, mf: &crate::schema::ModelFile) -> Result<(), SimError> {
    for (i, b) in mf.body.iter().enumerate() {
        for (key, given) in [
            ("velocity", b.velocity.is_some()),
            ("angular_velocity", b.angular_velocity.is_some()),
            ("modal_coordinates", b.modal_coordinates.is_some()),
            ("modal_velocities", b.modal_velocities.is_some()),
        ] {
            if given {
                return Err(ctx.err(
                    &format!("body[{i}].{key}"),
                    format!("solver.initial = \"static\" starts from static equilibrium at rest: remove `{key}` (or use initial = \"given\")"),
                ));
            }
        }
    }
    Ok(())
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

/// `modal_coordinates` / `modal_velocities` of an ffr body: checked against the kept modes and
/// handed to [`flexmbs_core::ModelSpec::set_initial_elastic`].
pub(crate) fn set_initial_modal(
    ctx: &Ctx,
    spec: &mut flexmbs_core::ModelSpec,
    b: &crate::schema::BodySpec,
    info: &crate::compile::BodyInfo,
    p: &str,
) -> Result<(), SimError> {
    if b.modal_coordinates.is_none() && b.modal_velocities.is_none() {
        return Ok(());
    }
    let n = info.geometry.modes;
    let mut values = Vec::with_capacity(2);
    for (key, v) in [
        ("modal_coordinates", &b.modal_coordinates),
        ("modal_velocities", &b.modal_velocities),
    ] {
        let path = format!("{p}.{key}");
        let Some(v) = v else {
            values.push(vec![0.0; n]);
            continue;
        };
        if b.kind != crate::schema::BodyType::Ffr {
            return Err(ctx.err(&path, "only ffr bodies have modal coordinates"));
        }
        if v.len() != n {
            let msg = format!(
                "{} values given, the body keeps {n} modes (one value per kept mode, in the order of `modes`)",
                v.len()
            );
            return Err(ctx.err(&path, msg));
        }
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            return Err(ctx.err(&path, format!("{x} is not a finite number")));
        }
        values.push(v.clone());
    }
    let u = values.pop().unwrap_or_default();
    let q = values.pop().unwrap_or_default();
    spec.set_initial_elastic(info.id, q, u);
    Ok(())
}

/// `solver.restart` needs a time integrator and excludes `initial = "static"` and initial
/// velocities or modal coordinates given in the bodies (the restart row replaces them).
pub(crate) fn check_restart_allowed(
    ctx: &Ctx,
    mf: &crate::schema::ModelFile,
    solver: &crate::SolverConfig,
) -> Result<(), SimError> {
    if matches!(solver, crate::SolverConfig::Statics { .. }) {
        return Err(ctx.err(
            "solver.restart",
            "statics has no initial state to restart from: remove `restart`",
        ));
    }
    if mf.solver.initial == Some(crate::schema::InitialName::Static) {
        return Err(ctx.err(
            "solver.initial",
            "`initial = \"static\"` and `restart` both define the initial state: keep one",
        ));
    }
    for (i, b) in mf.body.iter().enumerate() {
        for (key, given) in [
            ("velocity", b.velocity.is_some()),
            ("angular_velocity", b.angular_velocity.is_some()),
            ("modal_coordinates", b.modal_coordinates.is_some()),
            ("modal_velocities", b.modal_velocities.is_some()),
        ] {
            if given {
                return Err(ctx.err(
                    &format!("body[{i}].{key}"),
                    format!("with `solver.restart` the state comes from the results file: remove `{key}`"),
                ));
            }
        }
    }
    Ok(())
}
