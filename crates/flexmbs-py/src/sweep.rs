//! `sweep`: runs model variants on Rust threads (no GIL: each worker compiles and runs its variant
//! with `flexmbs_sim`, writes its results file and reduces the chosen series to numbers). The
//! calling thread polls Python's signal handlers; Ctrl-C stops every running variant after its
//! step (status `interrupted`), starts no new one, and is raised after the workers have ended.

use crate::run::SIGNAL_POLL;
use flexmbs_io::results::read_results;
use flexmbs_sim::run::{run_model, RunError, RunOptions};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// How a series is reduced to one number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    /// Value at the last output row.
    Final,
    /// Largest value.
    Max,
    /// Smallest value.
    Min,
    /// Largest absolute value.
    AbsMax,
    /// Mean over the output rows.
    Mean,
}

impl Statistic {
    /// The statistic named `name` (`final`, `max`, `min`, `absmax`, `mean`).
    pub fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "final" => Self::Final,
            "max" => Self::Max,
            "min" => Self::Min,
            "absmax" => Self::AbsMax,
            "mean" => Self::Mean,
            _ => return None,
        })
    }

    /// The statistic of `v` (NaN for no rows).
    pub fn of(self, v: &[f64]) -> f64 {
        if v.is_empty() {
            return f64::NAN;
        }
        match self {
            Self::Final => v[v.len() - 1],
            Self::Max => v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            Self::Min => v.iter().copied().fold(f64::INFINITY, f64::min),
            Self::AbsMax => v.iter().fold(0.0, |m: f64, x| m.max(x.abs())),
            Self::Mean => v.iter().sum::<f64>() / v.len() as f64,
        }
    }
}

/// What one variant gave: status (`completed`, `interrupted`, `failed`, `invalid`, `error`),
/// message (empty if completed) and one value per output (NaN unless completed or interrupted).
#[derive(Debug, Clone)]
pub struct VariantOutcome {
    /// Status.
    pub status: String,
    /// Message of a failure.
    pub message: String,
    /// Output values.
    pub values: Vec<f64>,
}

/// Compiles and runs one variant into `out`, and reduces its results.
pub fn run_variant(
    text: &str,
    file: &Path,
    out: &Path,
    outputs: &[(String, Statistic)],
    stop: &Arc<AtomicBool>,
) -> VariantOutcome {
    let nan = vec![f64::NAN; outputs.len()];
    let fail = |status: &str, message: String| VariantOutcome {
        status: status.into(),
        message,
        values: nan.clone(),
    };
    let cm = match flexmbs_sim::compile_model(text, file) {
        Ok(cm) => cm,
        // the lines of the generated variant text mean nothing: the key path and the reason
        Err(flexmbs_sim::SimError::Model { path, message, .. }) => {
            return fail("invalid", format!("at `{path}`: {message}"))
        }
        Err(e) => return fail("invalid", e.to_string()),
    };
    let opts = RunOptions {
        out_dir: out.to_path_buf(),
        stop: stop.clone(),
    };
    let summary = match run_model(&cm, &opts, &mut |_| {}) {
        Ok(s) => s,
        Err(e @ RunError::Solver { .. }) => return fail("failed", e.to_string()),
        Err(e) => return fail("error", e.to_string()),
    };
    let results = match read_results(&out.join("results.h5")) {
        Ok(r) => r,
        Err(e) => return fail("error", e.to_string()),
    };
    let mut values = Vec::with_capacity(outputs.len());
    for (name, stat) in outputs {
        match results.series(name) {
            Ok(v) => values.push(stat.of(&v)),
            Err(e) => return fail("error", e.to_string()),
        }
    }
    VariantOutcome {
        status: summary.status.name().into(),
        message: String::new(),
        values,
    }
}

/// Runs the variant texts on `workers` threads, variant `k` into `out_root/variant_<k>`.
/// `outputs` are `(series, statistic)` pairs. Returns the values `(variants, outputs)`, the
/// statuses and the messages. Raises `KeyboardInterrupt` after the workers stopped on Ctrl-C.
#[pyfunction]
#[pyo3(signature = (texts, file, out_root, outputs, workers))]
#[allow(clippy::type_complexity)]
pub fn sweep<'py>(
    py: Python<'py>,
    texts: Vec<String>,
    file: PathBuf,
    out_root: PathBuf,
    outputs: Vec<(String, String)>,
    workers: usize,
) -> PyResult<(Bound<'py, PyArray2<f64>>, Vec<String>, Vec<String>)> {
    let mut parsed = Vec::with_capacity(outputs.len());
    for (name, stat) in &outputs {
        let s = Statistic::parse(stat).ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "unknown statistic `{stat}` for `{name}` (final, max, min, absmax, mean)"
            ))
        })?;
        parsed.push((name.clone(), s));
    }
    let n = texts.len();
    let workers = workers.clamp(1, n.max(1));
    let slots: Vec<Mutex<Option<VariantOutcome>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let stop = Arc::new(AtomicBool::new(false));
    let (next, finished) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let mut pending: Option<PyErr> = None;
    py.detach(|| {
        std::thread::scope(|s| {
            for _ in 0..workers {
                s.spawn(|| {
                    loop {
                        let k = next.fetch_add(1, Ordering::SeqCst);
                        if k >= n || stop.load(Ordering::SeqCst) {
                            break;
                        }
                        let out = out_root.join(format!("variant_{k:04}"));
                        let r = run_variant(&texts[k], &file, &out, &parsed, &stop);
                        if let Ok(mut slot) = slots[k].lock() {
                            *slot = Some(r);
                        }
                    }
                    finished.fetch_add(1, Ordering::SeqCst);
                });
            }
            while finished.load(Ordering::SeqCst) < workers {
                std::thread::sleep(SIGNAL_POLL);
                if pending.is_none() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        pending = Some(e);
                        stop.store(true, Ordering::SeqCst);
                    }
                }
            }
        })
    });
    if let Some(e) = pending {
        return Err(e);
    }
    let m = parsed.len();
    let (mut values, mut status, mut message) = (Vec::with_capacity(n * m), vec![], vec![]);
    for slot in slots {
        let r = slot.into_inner().ok().flatten().unwrap_or(VariantOutcome {
            status: "not run".into(),
            message: String::new(),
            values: vec![f64::NAN; m],
        });
        values.extend(r.values);
        status.push(r.status);
        message.push(r.message);
    }
    let table = PyArray1::from_vec(py, values).reshape([n, m])?;
    Ok((table, status, message))
}
