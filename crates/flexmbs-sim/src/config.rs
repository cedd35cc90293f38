//! Solver and output configuration, orientations and time functions of a model file.

use crate::compile::{BodyInfo, Ctx};
use crate::error::SimError;
use crate::schema::{AdaptiveSpec, ModelFile, OrientationSpec, SolverType, TimeSpec, TimeType};
use crate::signals::{series_names, Signal};
use crate::units::{Dimension, Quantity};
use flexmbs_core::integrator::{
    AdaptiveSettings, Dopri5Settings, GenAlphaSettings, MoreauSscSettings, NewtonSettings,
    StaticsSettings,
};
use flexmbs_core::{Model, MotionLaw, TimeFunction};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
/// Solver configuration.
#[derive(Debug, Clone, PartialEq)]
pub enum SolverConfig {
    /// Generalized-alpha, fixed step `h` or adaptive.
    GenAlpha {
        /// Settings.
        settings: GenAlphaSettings,
        /// Step (first step when adaptive).
        h: f64,
        /// End time.
        t_end: f64,
        /// Step-size control.
        adaptive: Option<AdaptiveSettings>,
    },
    /// DOPRI5.
    Dopri5 {
        /// Settings.
        settings: Dopri5Settings,
        /// End time.
        t_end: f64,
    },
    /// Static equilibrium.
    Statics {
        /// Settings.
        settings: StaticsSettings,
    },
    /// Moreau time-stepping, fixed step `h` or with step-size control.
    Moreau {
        /// Step (first step when adaptive).
        h: f64,
        /// End time.
        t_end: f64,
        /// Step-size control.
        adaptive: Option<MoreauSscSettings>,
    },
}

/// Error of adaptive generalized-alpha with `rho_inf = 1` on a model with joints.
const ADAPTIVE_UNDAMPED: &str = "adaptive step size control needs numerical damping (rho_inf < 1) \
     when the model has joints: with rho_inf = 1 the constraint forces keep a spurious oscillation \
     at the step frequency, the error estimate sees it, and the step collapses (a double pendulum \
     fell to 3e-9 s). Use rho_inf = 0.9 (the default) or a fixed step";

impl SolverConfig {
    /// End time (0 for statics).
    pub fn t_end(&self) -> f64 {
        match self {
            SolverConfig::GenAlpha { t_end, .. }
            | SolverConfig::Dopri5 { t_end, .. }
            | SolverConfig::Moreau { t_end, .. } => *t_end,
            SolverConfig::Statics { .. } => 0.0,
        }
    }
}

/// When output rows are written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutputEvery {
    /// Every n-th accepted step.
    Steps(usize),
    /// Whenever the time passes a multiple of dt.
    Time(f64),
}

/// Output configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputConfig {
    /// Output rows.
    pub every: OutputEvery,
    /// Write an animation.
    pub animation: bool,
    /// Animation frame every n-th output row.
    pub animation_every: usize,
    /// The animation's points are the rigidly moved bodies plus this multiple of the elastic
    /// deformation (1: the true shape).
    pub deformation_scale: f64,
    /// Point fields `stress` and `von_mises` in the animation (`output.stress`).
    pub stress: bool,
    /// Plots: file stem and series.
    pub plots: Vec<(String, Vec<String>)>,
    /// Series for `<model>.csv`.
    pub csv: Vec<String>,
}

/// Rotation matrix of an orientation (exactly one of matrix, axis + angle, cardan).
pub fn orientation(ctx: &Ctx, o: &OrientationSpec, p: &str) -> Result<Matrix3<f64>, SimError> {
    match (&o.matrix, &o.axis, &o.angle, &o.cardan) {
        (Some(m), None, None, None) => {
            let a = Matrix3::from_fn(|r, c| m[r][c]);
            let dev = (a.transpose() * a - Matrix3::identity()).abs().max();
            if !(dev < 1e-6 && a.determinant() > 0.0) {
                return Err(ctx.err(
                    &format!("{p}.matrix"),
                    format!(
                        "not a rotation matrix (|A^T A - I| = {dev:e}, det = {:.3})",
                        a.determinant()
                    ),
                ));
            }
            Ok(a)
        }
        (None, Some(axis), Some(angle), None) => {
            let v = Vector3::from(*axis);
            if !(v.norm() > 0.0 && v.norm().is_finite()) {
                return Err(ctx.err(&format!("{p}.axis"), "the axis must be a non-zero vector"));
            }
            let phi = ctx.q(angle, Dimension::Angle, &format!("{p}.angle"))?;
            Ok(Rotation3::from_axis_angle(&Unit::new_normalize(v), phi).into_inner())
        }
        (None, None, None, Some(c)) => {
            let th = ctx.vec3(c, Dimension::Angle, &format!("{p}.cardan"))?;
            Ok(flexmbs_core::rotation::cardan_matrix(&th))
        }
        _ => Err(ctx.err(
            p,
            "give exactly one of `matrix`, `axis` with `angle`, `cardan`",
        )),
    }
}

/// A time function whose values have dimension `dim` (times in s, frequency in Hz, phase in rad).
pub fn time_function(
    ctx: &Ctx,
    t: &TimeSpec,
    dim: Dimension,
    p: &str,
) -> Result<TimeFunction, SimError> {
    let f = match t {
        TimeSpec::Constant(q) => return Ok(TimeFunction::Constant(ctx.q(q, dim, p)?)),
        TimeSpec::Function(f) => f,
    };
    let key = |k: &str| format!("{p}.{k}");
    let val = |q: &Option<Quantity>,
               k: &str,
               d: Dimension,
               default: Option<f64>|
     -> Result<f64, SimError> {
        match (q, default) {
            (Some(q), _) => ctx.q(q, d, &key(k)),
            (None, Some(v)) => Ok(v),
            (None, None) => Err(ctx.err(
                p,
                format!("a {:?} time function needs `{k}`", f.kind).to_lowercase(),
            )),
        }
    };
    let present = [
        ("value", f.value.is_some()),
        ("t0", f.t0.is_some()),
        ("t1", f.t1.is_some()),
        ("v0", f.v0.is_some()),
        ("v1", f.v1.is_some()),
        ("before", f.before.is_some()),
        ("after", f.after.is_some()),
        ("amplitude", f.amplitude.is_some()),
        ("frequency", f.frequency.is_some()),
        ("phase", f.phase.is_some()),
        ("offset", f.offset.is_some()),
        ("times", f.times.is_some()),
        ("values", f.values.is_some()),
        ("ramp", f.ramp.is_some()),
    ];
    let allowed: &[&str] = match f.kind {
        TimeType::Constant => &["value"],
        TimeType::Ramp => &["t0", "t1", "v0", "v1"],
        TimeType::Step => &["t0", "before", "after"],
        TimeType::Pulse => &["t0", "t1", "value"],
        TimeType::Harmonic => &["amplitude", "frequency", "phase", "offset"],
        TimeType::Table => &["times", "values"],
        TimeType::Step3 | TimeType::Step5 | TimeType::Cycloidal => &["t0", "t1", "v0", "v1"],
        TimeType::Move => &["t0", "t1", "v0", "v1", "ramp"],
    };
    ctx.only(
        p,
        &format!("a {:?} time function", f.kind).to_lowercase(),
        &present,
        allowed,
    )?;
    use Dimension::Time;
    let tf = match f.kind {
        TimeType::Constant => TimeFunction::Constant(val(&f.value, "value", dim, None)?),
        TimeType::Ramp => TimeFunction::Ramp {
            t0: val(&f.t0, "t0", Time, Some(0.0))?,
            t1: val(&f.t1, "t1", Time, None)?,
            v0: val(&f.v0, "v0", dim, Some(0.0))?,
            v1: val(&f.v1, "v1", dim, None)?,
        },
        TimeType::Step => TimeFunction::Step {
            t0: val(&f.t0, "t0", Time, None)?,
            before: val(&f.before, "before", dim, Some(0.0))?,
            after: val(&f.after, "after", dim, None)?,
        },
        TimeType::Pulse => TimeFunction::Pulse {
            t0: val(&f.t0, "t0", Time, Some(0.0))?,
            t1: val(&f.t1, "t1", Time, None)?,
            value: val(&f.value, "value", dim, None)?,
        },
        TimeType::Harmonic => TimeFunction::Harmonic {
            amplitude: val(&f.amplitude, "amplitude", dim, None)?,
            frequency_hz: val(&f.frequency, "frequency", Dimension::Frequency, None)?,
            phase: val(&f.phase, "phase", Dimension::Angle, Some(0.0))?,
            offset: val(&f.offset, "offset", dim, Some(0.0))?,
        },
        TimeType::Table => {
            let (Some(ts), Some(vs)) = (&f.times, &f.values) else {
                return Err(ctx.err(p, "a table time function needs `times` and `values`"));
            };
            if ts.len() != vs.len() || ts.is_empty() {
                return Err(ctx.err(
                    &key("values"),
                    format!(
                        "`times` and `values` need the same non-zero length ({} vs {})",
                        ts.len(),
                        vs.len()
                    ),
                ));
            }
            let times = ts
                .iter()
                .enumerate()
                .map(|(k, q)| ctx.q(q, Time, &format!("{p}.times[{k}]")))
                .collect::<Result<Vec<_>, _>>()?;
            if let Some(k) = times.windows(2).position(|w| w[1] <= w[0]) {
                return Err(ctx.err(
                    &format!("{p}.times[{}]", k + 1),
                    "times must be strictly increasing",
                ));
            }
            // values are not checked for finiteness here: a NaN table is a legal way to make a
            // run fail (tests of the failure path); the integrators report it with time and step
            let values = vs
                .iter()
                .enumerate()
                .map(|(k, q)| {
                    q.to_si(dim)
                        .map_err(|m| ctx.err(&format!("{p}.values[{k}]"), m))
                })
                .collect::<Result<Vec<_>, _>>()?;
            TimeFunction::Table { times, values }
        }
        TimeType::Step3 | TimeType::Step5 | TimeType::Cycloidal | TimeType::Move => {
            let law = match f.kind {
                TimeType::Step3 => MotionLaw::Cubic,
                TimeType::Step5 => MotionLaw::Quintic,
                TimeType::Cycloidal => MotionLaw::Cycloidal,
                _ => {
                    let ramp = val(&f.ramp, "ramp", Dimension::Dimensionless, Some(0.25))?;
                    if !(ramp > 0.0 && ramp <= 0.5) {
                        return Err(ctx.err(
                            &key("ramp"),
                            format!("the ramp fraction must be in (0, 0.5], got {ramp}"),
                        ));
                    }
                    MotionLaw::Trapezoid { ramp }
                }
            };
            TimeFunction::Move {
                t0: val(&f.t0, "t0", Time, Some(0.0))?,
                t1: val(&f.t1, "t1", Time, None)?,
                v0: val(&f.v0, "v0", dim, Some(0.0))?,
                v1: val(&f.v1, "v1", dim, None)?,
                law,
            }
        }
    };
    if let TimeFunction::Harmonic { frequency_hz, .. } = tf {
        if !(2.0 * std::f64::consts::PI * frequency_hz).is_finite() {
            // sin(inf t) is NaN: the run would fail at its first step
            return Err(ctx.err(
                &key("frequency"),
                format!("frequency {frequency_hz:e} Hz overflows the phase 2 pi f t"),
            ));
        }
    }
    if let TimeFunction::Ramp { t0, t1, .. }
    | TimeFunction::Pulse { t0, t1, .. }
    | TimeFunction::Move { t0, t1, .. } = tf
    {
        if t1 <= t0 {
            return Err(ctx.err(
                &key("t1"),
                format!("t1 = {t1} s must be greater than t0 = {t0} s"),
            ));
        }
    }
    Ok(tf)
}

/// The linear-solver backend of `solver.linear_solver` (default `auto`).
pub(crate) fn linear_solver(mf: &ModelFile) -> flexmbs_core::algebra::LinearSolver {
    use crate::schema::LinearSolverName as N;
    use flexmbs_core::algebra::LinearSolver as L;
    match mf.solver.linear_solver {
        None | Some(N::Auto) => L::Auto,
        Some(N::Dense) => L::Dense,
        Some(N::Sparse) => L::Sparse,
    }
}

pub(crate) fn solver_config(
    ctx: &Ctx,
    mf: &ModelFile,
    has_joints: &bool,
) -> Result<SolverConfig, SimError> {
    let s = &mf.solver;
    let present = [
        ("t_end", s.t_end.is_some()),
        ("h", s.h.is_some()),
        ("rho_inf", s.rho_inf.is_some()),
        ("adaptive", s.adaptive.is_some()),
        ("newton", s.newton.is_some()),
        ("rtol", s.rtol.is_some()),
        ("atol", s.atol.is_some()),
        ("h_max", s.h_max.is_some()),
        ("load_steps", s.load_steps.is_some()),
        ("initial", s.initial.is_some()),
    ];
    let positive = |q: &Quantity, key: &str| -> Result<f64, SimError> {
        let v = ctx.q(q, Dimension::Time, key)?;
        if v <= 0.0 {
            return Err(ctx.err(key, format!("must be > 0, got {v} s")));
        }
        Ok(v)
    };
    let t_end = || -> Result<f64, SimError> {
        positive(
            s.t_end
                .as_ref()
                .ok_or_else(|| ctx.err("solver", "needs `t_end`"))?,
            "solver.t_end",
        )
    };
    let mut newton = NewtonSettings::default();
    if let Some(n) = &s.newton {
        if let Some(m) = n.max_iterations {
            if m == 0 {
                return Err(ctx.err("solver.newton.max_iterations", "must be >= 1"));
            }
            newton.max_iterations = m;
        }
        if let Some(t) = n.tol {
            if !(t > 0.0 && t < 1.0) {
                return Err(ctx.err("solver.newton.tol", format!("must be in (0, 1), got {t}")));
            }
            (newton.rtol, newton.atol) = (t, t);
        }
        if let Some(t) = n.constraint_tol {
            if !(t > 0.0 && t < 1.0) {
                return Err(ctx.err(
                    "solver.newton.constraint_tol",
                    format!("must be in (0, 1), got {t}"),
                ));
            }
            newton.constraint_tol = t;
        }
        if let Some(m) = n.modified {
            if m && s.kind != SolverType::GeneralizedAlpha {
                return Err(ctx.err(
                    "solver.newton.modified",
                    "modified Newton is available for generalized-alpha only",
                ));
            }
            newton.modified = m;
        }
    }
    match s.kind {
        SolverType::GeneralizedAlpha => {
            ctx.only(
                "solver",
                "generalized-alpha",
                &present,
                &["t_end", "h", "rho_inf", "adaptive", "newton", "initial"],
            )?;
            let t_end = t_end()?;
            let h = positive(
                s.h.as_ref()
                    .ok_or_else(|| ctx.err("solver", "generalized-alpha needs the step `h`"))?,
                "solver.h",
            )?;
            let rho_inf = s.rho_inf.unwrap_or(0.9);
            if !(0.0..=1.0).contains(&rho_inf) {
                return Err(ctx.err(
                    "solver.rho_inf",
                    format!("must be in [0, 1], got {rho_inf}"),
                ));
            }
            let adaptive = match &s.adaptive {
                None => None,
                Some(a) => {
                    let d = AdaptiveSettings::default();
                    let [h_min, h_max, rtol, atol] =
                        step_limits(ctx, a, [d.h_min, d.h_max, d.rtol, d.atol])?;
                    if rho_inf >= 1.0 && !mf.joint.is_empty() {
                        return Err(ctx.err("solver.rho_inf", ADAPTIVE_UNDAMPED));
                    }
                    Some(AdaptiveSettings {
                        h_init: h,
                        h_min,
                        h_max,
                        rtol,
                        atol,
                        max_penetration: max_penetration(ctx, a, d.max_penetration)?,
                    })
                }
            };
            Ok(SolverConfig::GenAlpha {
                settings: GenAlphaSettings { rho_inf, newton },
                h,
                t_end,
                adaptive,
            })
        }
        SolverType::Dopri5 => {
            ctx.only(
                "solver",
                "dopri5",
                &present,
                &["t_end", "h", "rtol", "atol", "h_max", "initial"],
            )?;
            if *has_joints {
                return Err(ctx.err("solver.type", format!("dopri5 integrates unconstrained models only, but the model has {} joint(s): use generalized-alpha", mf.joint.len())));
            }
            let mut settings = Dopri5Settings::default();
            if let Some(q) = &s.h {
                settings.h_init = positive(q, "solver.h")?;
            }
            if let Some(q) = &s.h_max {
                settings.h_max = positive(q, "solver.h_max")?;
            }
            for (v, k, dst) in [
                (s.rtol, "rtol", &mut settings.rtol),
                (s.atol, "atol", &mut settings.atol),
            ] {
                if let Some(v) = v {
                    if v.is_nan() || v <= 0.0 {
                        return Err(
                            ctx.err(&format!("solver.{k}"), format!("must be > 0, got {v}"))
                        );
                    }
                    *dst = v;
                }
            }
            Ok(SolverConfig::Dopri5 {
                settings,
                t_end: t_end()?,
            })
        }
        SolverType::Moreau => {
            ctx.only("solver", "moreau", &present, &["t_end", "h", "adaptive"])?;
            let t_end = t_end()?;
            let h = positive(
                s.h.as_ref()
                    .ok_or_else(|| ctx.err("solver", "moreau needs the step `h`"))?,
                "solver.h",
            )?;
            let adaptive = match &s.adaptive {
                None => None,
                Some(a) => {
                    let d = MoreauSscSettings::default();
                    let [h_min, h_max, rtol, atol] =
                        step_limits(ctx, a, [d.h_min, d.h_max, d.rtol, d.atol])?;
                    Some(MoreauSscSettings {
                        h_init: h,
                        h_min,
                        h_max,
                        rtol,
                        atol,
                        max_penetration: max_penetration(ctx, a, d.max_penetration)?,
                        ..d
                    })
                }
            };
            Ok(SolverConfig::Moreau { h, t_end, adaptive })
        }
        SolverType::Statics => {
            ctx.only("solver", "statics", &present, &["load_steps", "newton"])?;
            let load_steps = s.load_steps.unwrap_or(1);
            if load_steps == 0 {
                return Err(ctx.err("solver.load_steps", "must be >= 1"));
            }
            Ok(SolverConfig::Statics {
                settings: StaticsSettings {
                    load_steps,
                    newton,
                    ..StaticsSettings::default()
                },
            })
        }
    }
}

/// `solver.adaptive.max_penetration` (a length > 0) or `default`.
fn max_penetration(ctx: &Ctx, a: &AdaptiveSpec, default: f64) -> Result<f64, SimError> {
    let Some(q) = &a.max_penetration else {
        return Ok(default);
    };
    let key = "solver.adaptive.max_penetration";
    let v = ctx.q(q, Dimension::Length, key)?;
    if v <= 0.0 {
        return Err(ctx.err(key, format!("must be > 0, got {v} m")));
    }
    Ok(v)
}

/// `[solver.adaptive]` of a step-size controlled solver: `[h_min, h_max, rtol, atol]`, each the
/// given key or its default in `defaults` (steps in s and positive, tolerances positive,
/// `h_min <= h_max`), errors at the key.
fn step_limits(ctx: &Ctx, a: &AdaptiveSpec, defaults: [f64; 4]) -> Result<[f64; 4], SimError> {
    let mut out = defaults;
    for (i, (q, key)) in [(&a.h_min, "h_min"), (&a.h_max, "h_max")]
        .into_iter()
        .enumerate()
    {
        if let Some(q) = q {
            let key = format!("solver.adaptive.{key}");
            let v = ctx.q(q, Dimension::Time, &key)?;
            if v <= 0.0 {
                return Err(ctx.err(&key, format!("must be > 0, got {v} s")));
            }
            out[i] = v;
        }
    }
    for (i, (v, key)) in [(a.rtol, "rtol"), (a.atol, "atol")].into_iter().enumerate() {
        if let Some(v) = v {
            if v.is_nan() || v <= 0.0 {
                return Err(ctx.err(
                    &format!("solver.adaptive.{key}"),
                    format!("must be > 0, got {v}"),
                ));
            }
            out[2 + i] = v;
        }
    }
    if out[0] > out[1] {
        return Err(ctx.err("solver.adaptive.h_min", "h_min must not exceed h_max"));
    }
    Ok(out)
}

pub(crate) fn output_config(
    ctx: &Ctx,
    mf: &ModelFile,
    model: &Model,
    bodies: &[BodyInfo],
    signals: &[Signal],
) -> Result<OutputConfig, SimError> {
    let o = &mf.output;
    let every = match (o.every, &o.dt) {
        (Some(_), Some(_)) => return Err(ctx.err("output.dt", "give `every` or `dt`, not both")),
        (Some(0), None) => return Err(ctx.err("output.every", "must be >= 1")),
        (Some(n), None) => OutputEvery::Steps(n),
        (None, Some(q)) => {
            let dt = ctx.q(q, Dimension::Time, "output.dt")?;
            if dt <= 0.0 {
                return Err(ctx.err("output.dt", format!("must be > 0, got {dt} s")));
            }
            OutputEvery::Time(dt)
        }
        (None, None) => OutputEvery::Steps(1),
    };
    let animation_every = o.animation_every.unwrap_or(1);
    if animation_every == 0 {
        return Err(ctx.err("output.animation_every", "must be >= 1"));
    }
    let deformation_scale = o.deformation_scale.unwrap_or(1.0);
    if !(deformation_scale.is_finite() && deformation_scale >= 0.0) {
        return Err(ctx.err(
            "output.deformation_scale",
            format!("must be a finite number >= 0, got {deformation_scale}"),
        ));
    }
    let names = series_names(model, bodies, signals);
    let check = |list: &[String], key: &str| -> Result<(), SimError> {
        for (k, s) in list.iter().enumerate() {
            if !names.iter().any(|n| n == s) {
                let close: Vec<&str> = names
                    .iter()
                    .filter(|n| n.contains(s.split('.').next().unwrap_or(s)))
                    .map(|s| s.as_str())
                    .take(12)
                    .collect();
                return Err(ctx.err(&format!("{key}[{k}]"), format!("unknown series `{s}`{}", if close.is_empty() { " (see `flexmbs plot RESULTS --list`; signals must be listed in output.signals)".to_string() } else { format!(" (close: {})", close.join(", ")) })));
            }
        }
        Ok(())
    };
    let mut plots = Vec::new();
    for (name, list) in &o.plots {
        if !is_plain_file_stem(name) {
            return Err(ctx.err(
                &format!("output.plots.{name}"),
                format!("invalid plot name `{name}`: {PLAIN_FILE_STEM}"),
            ));
        }
        check(list, &format!("output.plots.{name}"))?;
        if list.is_empty() {
            return Err(ctx.err(
                &format!("output.plots.{name}"),
                "a plot needs at least one series",
            ));
        }
        plots.push((name.clone(), list.clone()));
    }
    check(&o.csv, "output.csv")?;
    if o.stress {
        crate::stress::check_stress_output(ctx, o.animation, bodies)?;
    }
    Ok(OutputConfig {
        every,
        animation: o.animation,
        animation_every,
        deformation_scale,
        stress: o.stress,
        plots,
        csv: o.csv.clone(),
    })
}

/// What a name that becomes a file name in the output folder (model name, plot names) may be.
pub(crate) const PLAIN_FILE_STEM: &str = "it names a file in the output folder, so it must be \
     a non-empty plain file name (not `.` or `..`, no `/`, `\\` or control characters)";

/// True if `name` can be used as a file name stem inside the output folder: not empty, not `.`
/// or `..`, no path separator, no control character.
pub(crate) fn is_plain_file_stem(name: &str) -> bool {
    !(name.is_empty()
        || name == "."
        || name == ".."
        || name.contains(['/', '\\'])
        || name.chars().any(char::is_control))
}

/// Largest estimated size of the output rows a run writes to its results file (bytes). The
/// results writer streams rows to the file (its memory does not grow with the run), so this
/// guards the disk against a mistyped output step, not the memory.
pub const MAX_OUTPUT_BYTES: f64 = 32.0 * 1024.0 * 1024.0 * 1024.0;

/// Largest number of animation frames (one `.vtu` file each).
pub const MAX_ANIMATION_FRAMES: f64 = 50_000.0;

/// Refuses output settings that would exhaust memory or flood the disk, before the run starts:
/// rows estimated from `t_end`, the fixed step `h` and `every` / `dt` (runs with step size
/// control are estimated from `dt` only). `row_values` is the number of values per row.
pub(crate) fn check_output_size(
    ctx: &Ctx,
    solver: &SolverConfig,
    output: &OutputConfig,
    row_values: usize,
) -> Result<(), SimError> {
    let (t_end, h) = match solver {
        SolverConfig::GenAlpha {
            h,
            t_end,
            adaptive: None,
            ..
        }
        | SolverConfig::Moreau {
            h,
            t_end,
            adaptive: None,
        } => (*t_end, Some(*h)),
        SolverConfig::GenAlpha { t_end, .. }
        | SolverConfig::Dopri5 { t_end, .. }
        | SolverConfig::Moreau { t_end, .. } => (*t_end, None),
        SolverConfig::Statics { .. } => return Ok(()),
    };
    let (rows, key) = match (output.every, h) {
        (OutputEvery::Steps(n), Some(h)) => (t_end / h / n as f64, "output.every"),
        (OutputEvery::Time(dt), Some(h)) => (t_end / dt.max(h), "output.dt"),
        (OutputEvery::Time(dt), None) => (t_end / dt, "output.dt"),
        (OutputEvery::Steps(_), None) => return Ok(()),
    };
    let bytes = rows * 8.0 * row_values as f64;
    if bytes > MAX_OUTPUT_BYTES {
        return Err(ctx.err(
            key,
            format!(
                "this run would write about {rows:.3e} output rows ({:.1} GB) to its results file: raise `output.every` or set a coarser `output.dt`",
                bytes / 1e9
            ),
        ));
    }
    let frames = rows / output.animation_every as f64;
    if output.animation && frames > MAX_ANIMATION_FRAMES {
        return Err(ctx.err(
            "output.animation_every",
            format!(
                "this run would write about {frames:.3e} animation frames (one .vtu file each, at most {MAX_ANIMATION_FRAMES:e}): raise `output.animation_every` or set `animation = false`"
            ),
        ));
    }
    Ok(())
}
