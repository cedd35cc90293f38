//! `solver.restart`: a time integration that starts from a row of an earlier run's results file
//! (positions, velocities and multipliers at that output time), continuing to `t_end` with this
//! model file, which may differ from the earlier one in anything that keeps the coordinates (loads,
//! drives after the restart time, solver settings, outputs).

use crate::compile::{BodyInfo, Ctx};
use crate::error::SimError;
use crate::schema::RestartSpec;
use crate::units::Dimension;
use flexmbs_core::{Model, State};
use std::path::Path;

/// Relative tolerance of the restart time against the stored output times.
pub const RESTART_TIME_TOLERANCE: f64 = 1e-9;

/// Replaces `initial` by the results row that `spec` names (time, q, u, lambda); the result file
/// must hold this model's coordinates (same names, in the same order). Returns the unwrapped
/// revolute angles stored at that row ([`restart_angles`]).
pub(crate) fn apply_restart(
    ctx: &Ctx,
    spec: &RestartSpec,
    base: &Path,
    model: &Model,
    bodies: &[BodyInfo],
    t_end: f64,
    initial: &mut State,
) -> Result<Vec<(usize, f64)>, SimError> {
    let path = base.join(&spec.results);
    let results = flexmbs_io::results::read_results(&path)
        .map_err(|e| ctx.err("solver.restart.results", e.to_string()))?;
    let (q_names, u_names, _) = crate::signals::coordinate_names(model, bodies);
    for (what, ours, theirs) in [
        ("coordinates", &q_names, &results.layout.coordinates),
        ("velocities", &u_names, &results.layout.velocities),
    ] {
        if ours != theirs {
            let first = (0..ours.len().max(theirs.len()))
                .find(|&k| ours.get(k) != theirs.get(k))
                .unwrap_or(0);
            let name = |v: &Vec<String>| v.get(first).cloned().unwrap_or("(none)".into());
            let msg = format!(
                "{} has {} {what}, this model {}; they differ first at position {first}: `{}` in the results, `{}` here (a restart needs the same bodies, rotation parametrizations and modes)",
                path.display(),
                theirs.len(),
                ours.len(),
                name(theirs),
                name(ours),
            );
            return Err(ctx.err("solver.restart.results", msg));
        }
    }
    let row_index = restart_row(ctx, spec, &results, &path)?;
    let row = results
        .row(row_index)
        .ok_or_else(|| ctx.err("solver.restart.time", "no such row"))?;
    if row.t >= t_end {
        let msg = format!(
            "the restart time {} s is not before t_end = {t_end} s",
            row.t
        );
        return Err(ctx.err("solver.t_end", msg));
    }
    if let Some(k) = row.q.iter().chain(row.u).position(|x| !x.is_finite()) {
        let msg = format!("row at t = {} s has a non-finite value (column {k})", row.t);
        return Err(ctx.err("solver.restart.time", msg));
    }
    initial.t = row.t;
    initial.q.copy_from_slice(row.q);
    initial.u.copy_from_slice(row.u);
    if row.lambda.len() == initial.lambda.len() {
        initial.lambda.copy_from_slice(row.lambda);
    }
    Ok(restart_angles(model, &results, row_index))
}

/// The unwrapped angles `(joint index, rad)` of this model's revolute joints whose
/// `<joint>.coordinates` signal `results` holds, at row `row`: a restarted run continues each
/// angle on the branch it had (a crank after three turns restarts near 6 pi, not near 0).
fn restart_angles(
    model: &Model,
    results: &flexmbs_io::results::Results,
    row: usize,
) -> Vec<(usize, f64)> {
    use crate::motion_signals::JointCoordinates;
    model
        .joints
        .iter()
        .enumerate()
        .filter(|(_, joint)| JointCoordinates::of(joint) == JointCoordinates::Angle)
        .filter_map(|(j, joint)| {
            let series = results
                .series(&format!("{}.coordinates.rz", joint.name))
                .ok()?;
            let angle = *series.get(row)?;
            angle.is_finite().then_some((j, angle))
        })
        .collect()
}

/// The row at `spec.time` (within [`RESTART_TIME_TOLERANCE`]), or the last row.
fn restart_row(
    ctx: &Ctx,
    spec: &RestartSpec,
    results: &flexmbs_io::results::Results,
    path: &Path,
) -> Result<usize, SimError> {
    let n = results.rows();
    if n == 0 {
        let msg = format!("{} has no output rows", path.display());
        return Err(ctx.err("solver.restart.results", msg));
    }
    let Some(t) = &spec.time else {
        return Ok(n - 1);
    };
    let t = ctx.q(t, Dimension::Time, "solver.restart.time")?;
    let tol = RESTART_TIME_TOLERANCE * t.abs().max(1.0);
    if let Some(k) = results.time.iter().position(|&x| (x - t).abs() <= tol) {
        return Ok(k);
    }
    let after = results.time.iter().position(|&x| x > t);
    let nearest = match after {
        Some(0) => format!("the first row is at {} s", results.time[0]),
        Some(k) => format!(
            "the nearest rows are at {} s and {} s",
            results.time[k - 1],
            results.time[k]
        ),
        None => format!("the last row is at {} s", results.time[n - 1]),
    };
    let msg = format!(
        "{} has no output row at t = {t} s ({nearest}); restart at a stored output time, or omit `time` for the last row",
        path.display()
    );
    Err(ctx.err("solver.restart.time", msg))
}
