//! The run driver: integrates a [`CompiledModel`] and writes `results.h5`, the ParaView
//! animation, and at the end the requested CSV and plots. A stop flag ends the run cleanly
//! (status `interrupted`); a solver error ends it with status `failed` and a typed error; in
//! both cases the results written so far stay readable.

use crate::compile::{CompiledModel, OutputEvery, SolverConfig};
use crate::error::SimError;
use crate::signals::{coordinate_names, evaluate_signals, signal_width};
use flexmbs_core::ffr::FfrScratch;
use flexmbs_core::integrator::{
    self, Dopri5, Dopri5Stepper, GenAlpha, GenAlphaStepper, Statics, StaticsSettings,
    StaticsStepper, StepControl, StepStats, Stepper,
};
use flexmbs_core::power::{
    external_power, has_external_work, power_frames, stiffening_power, WorkMeter,
};
use flexmbs_core::{
    system, ElementScratch, FrameId, FrameKinematics, Model, SolverError, State, Workspace,
};
use flexmbs_io::results::{
    plot_series, read_results, write_csv, AnimationBody, AnimationWriter, ResultsError,
    ResultsLayout, ResultsRow, ResultsWriter, RunStatus, SignalSpec,
};
use std::ops::ControlFlow;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use thiserror::Error;

/// Options of a run.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Output folder (created if needed).
    pub out_dir: PathBuf,
    /// Set to true to stop the run after the current step (status `interrupted`).
    pub stop: Arc<AtomicBool>,
}

impl RunOptions {
    /// Options writing to `out_dir` with a fresh stop flag.
    pub fn new(out_dir: impl Into<PathBuf>) -> Self {
        Self {
            out_dir: out_dir.into(),
            stop: Arc::new(AtomicBool::new(false)),
        }
    }
}

/// Progress report after every accepted step (statics: after every load increment).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Progress {
    /// Simulated time (statics: load factor).
    pub t: f64,
    /// End time (statics: 1, the full load).
    pub t_end: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Newton iterations (implicit) or function evaluations (explicit) so far.
    pub newton_iterations: usize,
    /// Last step size (statics: load increment).
    pub h: f64,
    /// Rejected steps so far (adaptive integrators).
    pub rejected: usize,
}

/// Summary of a finished (completed or interrupted) run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSummary {
    /// Final status.
    pub status: RunStatus,
    /// Final time.
    pub t: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (adaptive integrators).
    pub rejected: usize,
    /// Newton iterations (implicit) or function evaluations (explicit).
    pub newton_iterations: usize,
    /// Wall-clock time of the integration and output.
    pub wall_time: Duration,
    /// Total energy at the start.
    pub energy_initial: f64,
    /// Largest `|E(t) - W(t) - E(0)|` over the output rows: the error of the energy balance, with
    /// `W` the work of point loads, dampers, drives and geometric stiffening
    /// ([`RunSummary::external_work`]); zero for an exact solution. Statics: `|E(mu) - E(0)|`
    /// over the load steps.
    pub energy_drift: f64,
    /// Work `W` done on the model by point loads, dampers, prescribed motions (drives) and the
    /// geometric stiffening forces up to the end, accumulated over the accepted steps
    /// (trapezoidal rule on the power of `flexmbs_core::power`); 0 for statics. The sum of
    /// [`RunSummary::work`].
    pub external_work: f64,
    /// [`RunSummary::external_work`] by source.
    pub work: WorkParts,
    /// Largest position constraint violation `max |g|`.
    pub position_drift: f64,
    /// Largest velocity constraint violation `max |G u + g_t|`.
    pub velocity_drift: f64,
    /// Plausibility warnings (large elastic deformation, constraint drift;
    /// `crate::plausibility`).
    pub warnings: Vec<String>,
    /// Output rows written.
    pub rows: usize,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// The work of the sources the energy does not contain, by part (J; each the trapezoidal rule on
/// its power over the accepted steps, `flexmbs_core::power`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WorkParts {
    /// Point forces and torques, and the non-conservative part of force elements.
    pub loads: f64,
    /// Dampers of spring-dampers (never positive).
    pub dampers: f64,
    /// Prescribed motions (drives): `lambda g_t` of their joint rows.
    pub drives: f64,
    /// Geometric stiffening forces of FFR bodies (centrifugal patterns and node loads); `None`
    /// when the model has no stiffening (nothing accounted).
    pub stiffening: Option<f64>,
}

impl WorkParts {
    /// Sum of the parts.
    pub fn total(&self) -> f64 {
        self.loads + self.dampers + self.drives + self.stiffening.unwrap_or(0.0)
    }
}

/// One [`WorkMeter`] per part of [`WorkParts`].
#[derive(Debug, Default)]
struct WorkMeters {
    loads: WorkMeter,
    dampers: WorkMeter,
    drives: WorkMeter,
    stiffening: Option<WorkMeter>,
}

impl WorkMeters {
    fn parts(&self) -> WorkParts {
        WorkParts {
            loads: self.loads.work(),
            dampers: self.dampers.work(),
            drives: self.drives.work(),
            stiffening: self.stiffening.as_ref().map(WorkMeter::work),
        }
    }
}

/// A run that could not be completed.
#[derive(Debug, Error)]
pub enum RunError {
    /// The model file is invalid.
    #[error(transparent)]
    Model(#[from] SimError),
    /// Writing or reading results failed.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// Another run writes into the output folder (or its lock cannot be created).
    #[error(transparent)]
    Locked(#[from] flexmbs_io::output_safety::LockError),
    /// The output folder could not be created.
    #[error("cannot create the output folder {}: {source} (choose another with -o)", path.display())]
    Io {
        /// Path.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// The solver failed; the results file holds everything up to the last accepted step and has
    /// status `failed`.
    #[error("simulation failed: {source}; results so far in {}", results.display())]
    Solver {
        /// Time at the start of the failed step.
        t: f64,
        /// Step size of the failed step.
        h: f64,
        /// Last residual (NaN if unknown).
        residual: f64,
        /// The solver error (boxed: keeps the error small).
        source: Box<SolverError>,
        /// The results file (status `failed`).
        results: PathBuf,
        /// The cause of the failure as far as the run could tell; its
        /// [`hint`](crate::failure_hint::FailureCause::hint) says what to try.
        cause: crate::failure_hint::FailureCause,
    },
    /// A bug: the integration panicked. The results file holds the rows written before and has
    /// status `failed`.
    #[error("internal error at t = {t} s: {message} (a bug in flexmbs; please report it with the model file); results so far in {}", results.display())]
    Internal {
        /// Time of the last accepted step.
        t: f64,
        /// The panic message.
        message: String,
        /// The results file (status `failed`).
        results: PathBuf,
    },
}

/// Finishes the animation and the results file (status `failed`) after a panic inside the
/// integration, so that the rows written so far stay readable and the file does not stay
/// `running`; returns the error to report.
fn finish_after_panic(
    rec: &mut Recorder,
    t: f64,
    payload: &(dyn std::any::Any + Send),
    results: PathBuf,
) -> RunError {
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    let flushed = rec.anim.as_mut().map_or(Ok(()), AnimationWriter::flush);
    let finished = rec.writer.take().map_or(Ok(()), |w| {
        w.finish(&RunStatus::Failed {
            t,
            message: format!("internal error: {message}"),
        })
        .map(|_| ())
    });
    match flushed.and(finished) {
        Ok(()) => RunError::Internal {
            t,
            message,
            results,
        },
        Err(e) => e.into(),
    }
}

/// Time, step size and residual of a solver error.
fn error_point(e: &SolverError) -> (f64, f64, f64) {
    match *e {
        SolverError::NewtonFailed { t, h, residual, .. }
        | SolverError::NonFinite { t, h, residual, .. }
        | SolverError::ContactSolve { t, h, residual, .. } => (t, h, residual),
        SolverError::Singular { t, h, .. } | SolverError::Element { t, h, .. } => (t, h, f64::NAN),
        SolverError::StepTooSmall { t, h, error, .. } => (t, h, error),
        SolverError::ConstraintsUnsupported { .. }
        | SolverError::InvalidSetting { .. }
        | SolverError::NotAssembled { .. }
        | SolverError::StateSize { .. } => (0.0, 0.0, f64::NAN),
    }
}

/// Writes output rows and animation frames; owns its own frame buffers so it needs only the
/// state (the integrators hold the workspace while calling back).
struct Recorder<'a> {
    cm: &'a CompiledModel,
    writer: Option<ResultsWriter>,
    anim: Option<AnimationWriter>,
    frames: Vec<FrameKinematics>,
    /// Every body's element evaluated at the recorded state.
    eval: Vec<ElementScratch>,
    /// The contacts' contour buffers (penalty energy of the output rows).
    contact: flexmbs_core::contact::ContactWork,
    body_fk: Vec<FrameKinematics>,
    signals: Vec<f64>,
    positions: Vec<Vec<[f64; 3]>>,
    /// Elastic displacement of every animation point (global axes).
    elastic: Vec<Vec<[f64; 3]>>,
    steps: usize,
    newton: usize,
    next_time: f64,
    energy0: Option<f64>,
    energy_drift: f64,
    /// Work of loads, dampers, drives and geometric stiffening (time-stepping solvers with any
    /// of them).
    work: Option<WorkMeters>,
    /// Scratch and force buffer of each stiffened body (`CompiledModel::stiffened`).
    stiffening: Vec<(FfrScratch, Vec<f64>)>,
    /// The frames the external power reads (`power::power_frames`).
    power_frames: Vec<FrameId>,
    g_max: f64,
    g_dot_max: f64,
    last_t: f64,
    last_h: f64,
    error: Option<ResultsError>,
    /// Statics: every load increment is a row, at "time" = load factor.
    statics: bool,
    /// Plausibility warnings (large deformation, constraint drift).
    plausibility: crate::plausibility::Plausibility,
    /// Continuous angles of the revolute joints with a `coordinates` signal.
    angles: crate::motion_signals::JointAngleTracker,
    /// Whether the state's `u_dot` are accelerations of the state (false for the first row of
    /// the moreau solver, which computes them per step).
    accelerations_known: bool,
    /// Step-frequency part of the multipliers, for the failure hint (`crate::failure_hint`).
    oscillation: crate::failure_hint::StepOscillation,
}

impl<'a> Recorder<'a> {
    fn record(&mut self, s: &State, st: &StepStats) -> Result<(), ResultsError> {
        self.record_at(s, s.t, st)
    }

    /// [`Recorder::record`] with the row's time column `t` given (statics: the load factor).
    fn record_at(&mut self, s: &State, t: f64, st: &StepStats) -> Result<(), ResultsError> {
        let m = &self.cm.model;
        self.evaluate(s);
        evaluate_signals(
            &self.cm.signals,
            m,
            s.t,
            &self.frames,
            &s.lambda,
            &s.contacts,
            &mut self.signals,
        );
        crate::stress::fill_stress_signals(&self.cm.signals, m, &s.q, &mut self.signals);
        self.angles.observe(m, t, &self.frames);
        crate::motion_signals::fill_motion_signals(
            &self.cm.signals,
            m,
            self.accelerations_known.then_some(s.u_dot.as_slice()),
            &self.frames,
            &self.angles,
            &mut self.signals,
        );
        crate::superelement_output::fill_superelement_signals(
            &self.cm.signals,
            &self.eval,
            &mut self.signals,
        );
        // energies of the output row from the state itself (the integrator computes none per
        // step, see `GenAlpha::step_energy`); the same function the integrator monitor uses
        let mut e = system::energy(m, &s.q, &s.u, &mut self.eval, &self.frames);
        // penalty (regularized) contacts store energy like springs
        e.springs += flexmbs_core::contact::regularized_energy(
            m,
            &self.frames,
            &self.eval,
            &mut self.contact,
        );
        let total = e.total();
        if self.energy0.is_none() {
            self.meter_work(s);
        }
        let e0 = *self.energy0.get_or_insert(total);
        let work = self.work.as_ref().map_or(0.0, |w| w.parts().total());
        self.energy_drift = self.energy_drift.max((total - work - e0).abs());
        let row = ResultsRow {
            t,
            q: &s.q,
            u: &s.u,
            lambda: &s.lambda,
            energy: [e.kinetic, e.gravity, e.elastic, e.springs],
            drift: [st.g_max, st.g_dot_max],
            step: [st.h, st.iterations as f64, st.residual],
            signals: &self.signals,
        };
        let Some(w) = self.writer.as_mut() else {
            return Ok(());
        };
        w.push(&row)?;
        self.last_t = t;
        let rows = w.rows();
        let anim_row = self.anim.is_some() && (rows - 1) % self.cm.output.animation_every == 0;
        if anim_row || (rows - 1) % crate::plausibility::DEFORMATION_CHECK_EVERY == 0 {
            let (fk, pos, el) = (&mut self.body_fk, &mut self.positions, &mut self.elastic);
            crate::animation_points::body_points(m, self.cm, s, &mut self.eval, fk, pos, el);
            self.plausibility.observe_deformation(t, &self.elastic);
        }
        if let Some(anim) = self.anim.as_mut() {
            if anim_row {
                let refs: Vec<&[[f64; 3]]> = self.positions.iter().map(|p| p.as_slice()).collect();
                let el: Vec<&[[f64; 3]]> = self.elastic.iter().map(|p| p.as_slice()).collect();
                if self.cm.output.stress {
                    anim.set_next_point_fields(crate::stress::point_stress_fields(self.cm, &s.q));
                }
                if !m.contacts.is_empty() {
                    let (fr, ev, w) = (&self.frames, &self.eval, &mut self.contact);
                    let parts = crate::contact_drawing::contact_parts(self.cm, s, st.h, fr, ev, w);
                    anim.set_next_parts(parts);
                }
                anim.write_frame_elastic(t, &refs, Some(&el))?;
            }
        }
        Ok(())
    }

    /// Evaluates the elements and all frames at `s` (an accepted state: the integrator evaluated
    /// it; should it fail anyway, the frames become NaN and so do the written values).
    fn evaluate(&mut self, s: &State) {
        let m = &self.cm.model;
        if system::evaluate_elements(m, &s.q, &s.u, &mut self.eval).is_err() {
            for k in &mut self.frames {
                k.position.fill(f64::NAN);
                k.velocity.fill(f64::NAN);
            }
            return;
        }
        system::update_frames(m, &s.q, &s.u, &mut self.eval, &mut self.frames);
    }

    /// Adds the step to `s.t` to the external work (with frames updated to `s`), if tracked.
    fn meter_work(&mut self, s: &State) {
        if self.work.is_none() {
            return;
        }
        // node-load stiffening: coefficients from all frames at the accepted state
        let load_stiffening = if has_load_stiffening(&self.cm.model) {
            self.evaluate(s);
            let (m, eval, frames) = (&self.cm.model, &mut self.eval, &self.frames);
            system::load_stiffening_power(m, s.t, &s.u, &s.u_dot, &s.lambda, eval, frames)
        } else {
            0.0
        };
        let Some(meter) = self.work.as_mut() else {
            return;
        };
        let m = &self.cm.model;
        // only frames: the kinematics-only evaluation (O(n_f) per FFR body)
        if system::evaluate_kinematics(m, &s.q, &s.u, &mut self.eval).is_err() {
            for w in [&mut meter.loads, &mut meter.dampers, &mut meter.drives] {
                w.advance(s.t, f64::NAN);
            }
            if let Some(w) = meter.stiffening.as_mut() {
                w.advance(s.t, f64::NAN);
            }
            return;
        }
        let (ids, eval) = (&self.power_frames, &mut self.eval);
        system::update_selected_frames(m, &s.q, &s.u, eval, ids, &mut self.frames);
        let p = external_power(m, s.t, &self.frames, &s.lambda);
        meter.loads.advance(s.t, p.loads);
        meter.dampers.advance(s.t, p.dampers);
        meter.drives.advance(s.t, p.drives);
        if let Some(w) = meter.stiffening.as_mut() {
            let mut power = load_stiffening;
            for ((id, body), (scratch, buf)) in self.cm.stiffened.iter().zip(&mut self.stiffening) {
                let (q, u) = (m.body_q(*id, &s.q), m.body_u(*id, &s.u));
                power += stiffening_power(body, q, u, scratch, buf);
            }
            w.advance(s.t, power);
        }
    }

    /// Observes the tracked joint angles at the accepted state `s` (row time `t`), through the
    /// kinematics-only evaluation of their frames; nothing without tracked angles.
    fn observe_angles(&mut self, s: &State, t: f64) {
        if self.angles.is_empty() {
            return;
        }
        let m = &self.cm.model;
        if system::evaluate_kinematics(m, &s.q, &s.u, &mut self.eval).is_err() {
            return;
        }
        let (ids, eval) = (self.angles.frames(), &mut self.eval);
        system::update_selected_frames(m, &s.q, &s.u, eval, ids, &mut self.frames);
        self.angles.observe(m, t, &self.frames);
    }

    /// Called after every accepted step: statistics, output selection, stop flag.
    fn on_step(
        &mut self,
        s: &State,
        st: &StepStats,
        stop: &AtomicBool,
        progress: &mut dyn FnMut(&Progress),
    ) -> ControlFlow<()> {
        self.meter_work(s);
        self.observe_angles(s, st.t);
        self.accelerations_known = true;
        self.steps += 1;
        self.newton += st.iterations;
        self.last_h = st.h;
        self.g_max = self.g_max.max(st.g_max);
        self.g_dot_max = self.g_dot_max.max(st.g_dot_max);
        if !self.statics {
            self.plausibility
                .observe_drift(st.t, st.g_max, st.g_dot_max, &s.u);
            self.plausibility.observe_contacts(st.t, &s.contacts);
            self.oscillation.observe(st.t, &s.lambda);
        }
        let due = match self.cm.output.every {
            _ if self.statics => true,
            OutputEvery::Steps(n) => self.steps.is_multiple_of(n),
            OutputEvery::Time(dt) => {
                if s.t >= self.next_time - 1e-9 * dt {
                    while self.next_time <= s.t + 1e-9 * dt {
                        self.next_time += dt;
                    }
                    true
                } else {
                    false
                }
            }
        };
        if due {
            if let Err(e) = self.record_at(s, st.t, st) {
                self.error = Some(e);
                return ControlFlow::Break(());
            }
        }
        progress(&Progress {
            t: st.t,
            t_end: if self.statics {
                1.0
            } else {
                self.cm.solver.t_end()
            },
            steps: self.steps,
            newton_iterations: self.newton,
            h: st.h,
            rejected: st.rejected,
        });
        if stop.load(Ordering::Relaxed) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// Runs a compiled model. `progress` is called after every accepted step.
/// Returns the summary of a completed or interrupted run; a solver failure is an error (the
/// results file is finished with status `failed` first).
pub fn run_model(
    cm: &CompiledModel,
    opts: &RunOptions,
    progress: &mut dyn FnMut(&Progress),
) -> Result<RunSummary, RunError> {
    let start = Instant::now();
    let out = &opts.out_dir;
    std::fs::create_dir_all(out).map_err(|source| RunError::Io {
        path: out.clone(),
        source,
    })?;
    // one run per output folder: a second one would interleave its files with ours
    let _lock = flexmbs_io::output_safety::OutputLock::acquire(out)?;
    let m = &cm.model;
    let (coordinates, velocities, multipliers) = coordinate_names(m, &cm.bodies);
    let layout = ResultsLayout {
        model: cm.name.clone(),
        coordinates,
        velocities,
        multipliers,
        signals: cm
            .signals
            .iter()
            .map(|s| SignalSpec {
                name: s.name.clone(),
                unit: s.unit.clone(),
                components: s.components.clone(),
            })
            .collect(),
    };
    let results_path = out.join("results.h5");
    let model_file = cm.file.display().to_string();
    let solver_name = match cm.solver {
        SolverConfig::GenAlpha {
            adaptive: Some(_), ..
        } => "generalized-alpha (adaptive)",
        SolverConfig::GenAlpha { .. } => "generalized-alpha",
        SolverConfig::Dopri5 { .. } => "dopri5",
        SolverConfig::Statics { .. } => "statics",
        SolverConfig::Moreau {
            adaptive: Some(_), ..
        } => "moreau (adaptive)",
        SolverConfig::Moreau { .. } => "moreau",
    };
    let version = format!("flexmbs {}", env!("CARGO_PKG_VERSION"));
    let sources = crate::provenance::sha256_lines(&crate::provenance::source_files(cm));
    let writer = ResultsWriter::create(
        &results_path,
        layout,
        &[
            ("model_file", model_file.as_str()),
            ("solver", solver_name),
            ("program", version.as_str()),
            ("model_text", cm.text.as_str()),
            ("source_sha256", sources.as_str()),
        ],
    )?;
    let mut files = vec![results_path.clone()];
    let anim = if cm.output.animation {
        let bodies = cm
            .bodies
            .iter()
            .map(|b| AnimationBody {
                name: b.name.clone(),
                reference_points: b.geometry.points.clone(),
                cells: b.geometry.cells.clone(),
            })
            .collect();
        let a = AnimationWriter::create(out, &cm.name, bodies)?;
        files.push(a.pvd_path());
        Some(a)
    } else {
        None
    };
    let mut rec = Recorder {
        cm,
        writer: Some(writer),
        anim,
        frames: m.frame_buffers(),
        eval: m.bodies.iter().map(|b| b.element.new_scratch()).collect(),
        contact: flexmbs_core::contact::ContactWork::new(m),
        body_fk: cm
            .bodies
            .iter()
            .map(|b| FrameKinematics::for_body(m, b.id))
            .collect(),
        signals: Vec::with_capacity(signal_width(&cm.signals)),
        positions: cm
            .bodies
            .iter()
            .map(|b| Vec::with_capacity(b.geometry.points.len()))
            .collect(),
        elastic: cm
            .bodies
            .iter()
            .map(|b| Vec::with_capacity(b.geometry.points.len()))
            .collect(),
        steps: 0,
        newton: 0,
        next_time: 0.0,
        energy0: None,
        energy_drift: 0.0,
        work: ((has_external_work(m) || !cm.stiffened.is_empty() || has_load_stiffening(m))
            && !matches!(cm.solver, SolverConfig::Statics { .. }))
        .then(|| WorkMeters {
            stiffening: (!cm.stiffened.is_empty() || has_load_stiffening(m))
                .then(WorkMeter::default),
            ..WorkMeters::default()
        }),
        stiffening: cm
            .stiffened
            .iter()
            .map(|(_, b)| (FfrScratch::new(b.nf()), vec![0.0; b.nu()]))
            .collect(),
        power_frames: power_frames(m),
        g_max: 0.0,
        g_dot_max: 0.0,
        last_t: f64::NAN,
        last_h: 0.0,
        error: None,
        statics: matches!(cm.solver, SolverConfig::Statics { .. }),
        plausibility: crate::plausibility::Plausibility::new(cm),
        angles: crate::motion_signals::JointAngleTracker::restarted(
            m,
            &cm.signals,
            cm.initial.t,
            &cm.restart_angles,
        ),
        accelerations_known: !matches!(cm.solver, SolverConfig::Moreau { .. }),
        oscillation: crate::failure_hint::StepOscillation::new(m.nc),
    };
    let mut s = cm.initial.clone();
    let mut ws = Workspace::with_linear_solver(m, cm.linear_solver);
    let stop = opts.stop.clone();
    // a panic (a bug) still leaves a finished results file with status `failed`
    let result = match std::panic::catch_unwind(AssertUnwindSafe(|| {
        integrate(cm, &mut s, &mut ws, &mut rec, &stop, progress)
    })) {
        Ok(result) => result,
        Err(payload) => return Err(finish_after_panic(&mut rec, s.t, &*payload, results_path)),
    };
    if let Some(e) = rec.error.take() {
        // a row or frame could not be written: still mark the file (best effort; the first
        // error is the one reported)
        if let Some(w) = rec.writer.take() {
            let message = format!("writing the results failed: {e}");
            let _ = w.finish(&RunStatus::Failed { t: s.t, message });
        }
        return Err(e.into());
    }
    let (status, rejected) = match result {
        Ok((rejected, stopped)) => {
            // the final state is always in the file
            if rec.last_t != s.t && cm.solver.t_end() > 0.0 {
                let (energy, g, gd) = integrator::monitor(m, &s, &mut ws);
                let st = StepStats {
                    t: s.t,
                    h: rec.last_h,
                    energy,
                    g_max: g,
                    g_dot_max: gd,
                    ..Default::default()
                };
                rec.record(&s, &st)?;
            }
            let status = if stopped {
                RunStatus::Interrupted { t: s.t }
            } else {
                RunStatus::Completed
            };
            (status, rejected)
        }
        Err(source) => {
            let (t, h, residual) = error_point(&source);
            // every solver error that happens in a step names its time and step itself
            let message = source.to_string();
            if let Some(a) = rec.anim.as_mut() {
                a.flush()?;
            }
            if let Some(w) = rec.writer.take() {
                w.finish(&RunStatus::Failed { t, message })?;
            }
            return Err(RunError::Solver {
                t,
                h,
                residual,
                source: Box::new(source),
                results: results_path,
                cause: rec.oscillation.cause(&cm.solver),
            });
        }
    };
    let rows = rec.writer.as_ref().map_or(0, |w| w.rows());
    if let Some(a) = rec.anim.as_mut() {
        a.flush()?;
    }
    if let Some(w) = rec.writer.take() {
        w.finish(&status)?;
    }
    files.extend(write_requested_outputs(cm, &results_path, out)?);
    Ok(RunSummary {
        status,
        t: s.t,
        steps: rec.steps,
        rejected,
        newton_iterations: rec.newton,
        wall_time: start.elapsed(),
        energy_initial: rec.energy0.unwrap_or(0.0),
        energy_drift: rec.energy_drift,
        external_work: rec.work.as_ref().map_or(0.0, |w| w.parts().total()),
        work: rec
            .work
            .as_ref()
            .map_or(WorkParts::default(), WorkMeters::parts),
        position_drift: rec.g_max,
        velocity_drift: rec.g_dot_max,
        rows,
        files,
        warnings: rec.plausibility.warnings(cm),
    })
}

/// The stepper, step control and end point (time, or load factor 1 for statics) of a solver
/// configuration.
fn stepper_of(solver: &SolverConfig) -> Result<(Box<dyn Stepper>, StepControl, f64), SolverError> {
    Ok(match solver {
        SolverConfig::GenAlpha {
            settings,
            h,
            t_end,
            adaptive,
        } => {
            // energies only at output rows (`Recorder::record`)
            let ga = GenAlpha::new(*settings)?.with_step_energy(false);
            let stepper = GenAlphaStepper::new(ga, *adaptive);
            let control = stepper.control(*h);
            (Box::new(stepper), control, *t_end)
        }
        SolverConfig::Dopri5 { settings, t_end } => {
            let stepper = Dopri5Stepper::new(Dopri5::new(*settings));
            let control = stepper.control();
            (Box::new(stepper), control, *t_end)
        }
        SolverConfig::Statics { settings } => {
            let solver = Statics::new(*settings);
            (Box::new(StaticsStepper::new(solver)), solver.control(), 1.0)
        }
        SolverConfig::Moreau { h, t_end, adaptive } => match adaptive {
            None => {
                let stepper = integrator::MoreauStepper::new(Default::default());
                let control = stepper.control(*h);
                (Box::new(stepper), control, *t_end)
            }
            Some(settings) => {
                let stepper = integrator::MoreauSscStepper::new(*settings);
                let control = stepper.control();
                (Box::new(stepper), control, *t_end)
            }
        },
    })
}

/// Initializes and runs the stepper of the solver through the one driver; returns (rejected
/// steps, stopped). Time integrators write a first row at the initial state; statics writes one
/// row per converged load increment, at "time" = load factor.
fn integrate(
    cm: &CompiledModel,
    s: &mut State,
    ws: &mut Workspace,
    rec: &mut Recorder,
    stop: &AtomicBool,
    progress: &mut dyn FnMut(&Progress),
) -> Result<(usize, bool), SolverError> {
    let m = &cm.model;
    if cm.initial_static {
        static_equilibrium_start(m, s, ws)?;
    }
    let (mut stepper, control, end) = stepper_of(&cm.solver)?;
    stepper.initialize(m, s, ws)?;
    if !rec.statics {
        let (energy, g, gd) = integrator::monitor(m, s, ws);
        let st = StepStats {
            t: s.t,
            energy,
            g_max: g,
            g_dot_max: gd,
            ..Default::default()
        };
        if let Err(e) = rec.record(s, &st) {
            rec.error = Some(e);
            return Ok((0, true));
        }
        rec.next_time = next_output_time(cm, s.t);
    }
    let r = integrator::drive(stepper.as_mut(), m, s, ws, control, end, |s, st| {
        rec.on_step(s, st, stop, progress)
    })?;
    Ok((r.rejected, r.stopped))
}

/// `solver.initial = "static"`: static equilibrium at `t = s.t` (gravity, loads and drive
/// positions at that time; the statics solver's default load stepping), at rest; then the joints
/// must hold at velocity level too (a drive with a non-zero rate at t = 0 cannot start at rest).
fn static_equilibrium_start(
    m: &Model,
    s: &mut State,
    ws: &mut Workspace,
) -> Result<(), SolverError> {
    let t0 = s.t;
    let statics = Statics::new(StaticsSettings::default());
    let mut stepper = StaticsStepper::new(statics);
    stepper.initialize(m, s, ws)?;
    integrator::drive(&mut stepper, m, s, ws, statics.control(), 1.0, |_, _| {
        ControlFlow::Continue(())
    })?;
    s.t = t0;
    s.u.fill(0.0);
    system::check_assembly(m, s, ws, system::ASSEMBLY_TOL)
}

fn next_output_time(cm: &CompiledModel, t: f64) -> f64 {
    match cm.output.every {
        OutputEvery::Time(dt) => t + dt,
        OutputEvery::Steps(_) => 0.0,
    }
}

/// CSV and plots requested in `[output]`, from the finished results file.
fn write_requested_outputs(
    cm: &CompiledModel,
    results: &Path,
    out: &Path,
) -> Result<Vec<PathBuf>, ResultsError> {
    if cm.output.csv.is_empty() && cm.output.plots.is_empty() {
        return Ok(Vec::new());
    }
    let r = read_results(results)?;
    let mut files = Vec::new();
    if !cm.output.csv.is_empty() {
        let names: Vec<&str> = cm.output.csv.iter().map(|s| s.as_str()).collect();
        let p = out.join(format!("{}.csv", cm.name));
        write_csv(&r, &names, &p)?;
        files.push(p);
    }
    for (stem, series) in &cm.output.plots {
        let names: Vec<&str> = series.iter().map(|s| s.as_str()).collect();
        let p = out.join(format!("{stem}.png"));
        plot_series(&r, &names, &p)?;
        files.push(p);
    }
    Ok(files)
}

/// Whether a body of `m` has node-load stiffening (`load_stiffening = true`), whose power the
/// energy balance adds.
fn has_load_stiffening(m: &flexmbs_core::Model) -> bool {
    m.bodies
        .iter()
        .any(|b| b.element.load_stiffened_ffr().is_some())
}
