//! `run`: integrates a model with `flexmbs_sim::run::run_model`, the GIL released. A poll from
//! the run's progress hook (at most every 50 ms) takes the GIL, runs Python's signal handlers
//! (`py.check_signals()`: Ctrl-C becomes `KeyboardInterrupt`) and calls the user's progress
//! callback; an exception from either sets the run's stop flag, so the run ends after its step
//! with a finished results file (status `interrupted`), and is raised after that.

use crate::errors::run_error;
use crate::model::{compile, origin};
use flexmbs_sim::run::{run_model, Progress, RunOptions, RunSummary};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Time between two polls of Python's signal handlers during a run.
pub const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Progress of a run, handed to the `progress` callback of `flexmbs.run`.
#[pyclass(frozen, get_all, module = "flexmbs._native", name = "Progress")]
#[derive(Debug, Clone)]
pub struct PyProgress {
    /// Simulated time in s (statics: load factor).
    pub t: f64,
    /// End time in s (statics: 1).
    pub t_end: f64,
    /// Accepted steps.
    pub steps: usize,
    /// Newton iterations (implicit solvers) or function evaluations (explicit) so far.
    pub newton_iterations: usize,
    /// Last step size in s (statics: load increment).
    pub h: f64,
    /// Rejected steps so far (adaptive solvers).
    pub rejected: usize,
}

#[pymethods]
impl PyProgress {
    /// Fraction of the run done, 0..1.
    #[getter]
    fn fraction(&self) -> f64 {
        if self.t_end > 0.0 {
            (self.t / self.t_end).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "Progress(t={}, t_end={}, steps={}, newton_iterations={}, h={}, rejected={})",
            self.t, self.t_end, self.steps, self.newton_iterations, self.h, self.rejected
        )
    }
}

impl From<&Progress> for PyProgress {
    fn from(p: &Progress) -> Self {
        Self {
            t: p.t,
            t_end: p.t_end,
            steps: p.steps,
            newton_iterations: p.newton_iterations,
            h: p.h,
            rejected: p.rejected,
        }
    }
}

/// Python's part of a run: signal polls and progress calls, and the first exception raised.
struct PythonHooks {
    callback: Option<Py<PyAny>>,
    interval: Duration,
    last_poll: Instant,
    last_report: Option<Instant>,
    pending: Option<PyErr>,
}

impl PythonHooks {
    /// Called after every accepted step (GIL released): polls when due; on an exception sets
    /// `stop` and keeps the exception.
    fn on_progress(&mut self, p: &Progress, stop: &AtomicBool) {
        if self.pending.is_some() {
            return;
        }
        let now = Instant::now();
        let poll = now.duration_since(self.last_poll) >= SIGNAL_POLL;
        let report = self.callback.is_some()
            && self
                .last_report
                .is_none_or(|t| now.duration_since(t) >= self.interval);
        if !poll && !report {
            return;
        }
        self.last_poll = now;
        let outcome = Python::attach(|py| -> PyResult<()> {
            py.check_signals()?;
            if report {
                self.last_report = Some(now);
                if let Some(cb) = &self.callback {
                    cb.call1(py, (PyProgress::from(p),))?;
                }
            }
            Ok(())
        });
        if let Err(e) = outcome {
            self.pending = Some(e);
            stop.store(true, Ordering::SeqCst);
        }
    }
}

/// The run summary as a dict (status, steps, energy balance, drift, files, wall time).
fn summary_dict<'py>(py: Python<'py>, s: &RunSummary) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("status", s.status.name())?;
    d.set_item("t", s.t)?;
    d.set_item("steps", s.steps)?;
    d.set_item("rejected", s.rejected)?;
    d.set_item("newton_iterations", s.newton_iterations)?;
    d.set_item("wall_time", s.wall_time.as_secs_f64())?;
    d.set_item("energy_initial", s.energy_initial)?;
    d.set_item("energy_drift", s.energy_drift)?;
    d.set_item("external_work", s.external_work)?;
    let work = PyDict::new(py);
    work.set_item("loads", s.work.loads)?;
    work.set_item("dampers", s.work.dampers)?;
    work.set_item("drives", s.work.drives)?;
    work.set_item("stiffening", s.work.stiffening)?;
    d.set_item("work", work)?;
    d.set_item("position_drift", s.position_drift)?;
    d.set_item("velocity_drift", s.velocity_drift)?;
    d.set_item("warnings", s.warnings.clone())?;
    d.set_item("rows", s.rows)?;
    let files: Vec<String> = s.files.iter().map(|f| f.display().to_string()).collect();
    d.set_item("files", files)?;
    Ok(d)
}

/// Compiles and runs a model into `out_dir`; returns the run summary as a dict. Raises the
/// pending `KeyboardInterrupt` (or the progress callback's exception) after an interrupted run
/// has finished its results file.
#[pyfunction]
#[pyo3(signature = (text, file, from_file, out_dir, progress=None, interval=0.1))]
pub fn run<'py>(
    py: Python<'py>,
    text: &str,
    file: PathBuf,
    from_file: bool,
    out_dir: PathBuf,
    progress: Option<Py<PyAny>>,
    interval: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let origin = origin(from_file);
    let cm = compile(py, text, &file, origin)?;
    let opts = RunOptions::new(&out_dir);
    let mut hooks = PythonHooks {
        callback: progress,
        interval: Duration::from_secs_f64(interval.max(0.0)),
        last_poll: Instant::now(),
        last_report: None,
        pending: None,
    };
    let result = py.detach(|| {
        let stop = opts.stop.clone();
        run_model(&cm, &opts, &mut |p| hooks.on_progress(p, &stop))
    });
    if let Some(e) = hooks.pending.take() {
        return Err(e);
    }
    match result {
        Ok(summary) => summary_dict(py, &summary),
        Err(e) => Err(run_error(py, &e, origin, &cm.solver)),
    }
}
