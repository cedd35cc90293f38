//! The library errors as Python exceptions. The classes live in `flexmbs._errors` (Python, so that
//! `UnknownSeriesError` can also be a `KeyError` and every class has documented attributes); this
//! module builds their instances from the typed Rust errors.

use flexmbs_io::results::ResultsError;
use flexmbs_sim::run::RunError;
use flexmbs_sim::SimError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;

/// An attribute value of an exception.
pub enum Attr {
    /// Text.
    Str(String),
    /// Number.
    Float(f64),
    /// Whole number.
    Int(usize),
    /// `None`.
    None,
}

/// An exception of class `class` (in `flexmbs._errors`) with `message` and keyword attributes.
pub fn raise(py: Python<'_>, class: &str, message: String, attrs: &[(&str, Attr)]) -> PyErr {
    let build = || -> PyResult<PyErr> {
        let cls = py.import("flexmbs._errors")?.getattr(class)?;
        let kwargs = PyDict::new(py);
        for (k, v) in attrs {
            match v {
                Attr::Str(s) => kwargs.set_item(k, s)?,
                Attr::Float(x) => kwargs.set_item(k, x)?,
                Attr::Int(n) => kwargs.set_item(k, n)?,
                Attr::None => kwargs.set_item(k, py.None())?,
            }
        }
        Ok(PyErr::from_value(cls.call((message,), Some(&kwargs))?))
    };
    build().unwrap_or_else(|e| e)
}

fn path_attr(p: &Path) -> Attr {
    Attr::Str(p.display().to_string())
}

/// Where a compiled text came from: a model file as written (errors name its file and line) or
/// a model built or changed in Python (key path only; lines of the generated text mean nothing).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// The text of the file, unchanged.
    File,
    /// Text generated from Python data.
    Python,
}

/// A model-file error as `ModelError` (key path, and file and line for a file).
pub fn sim_error(py: Python<'_>, e: &SimError, origin: Origin) -> PyErr {
    match (e, origin) {
        (SimError::Read { file, .. }, _) => {
            raise(py, "IoError", e.to_string(), &[("path", path_attr(file))])
        }
        (
            SimError::Model {
                file,
                line,
                path,
                message,
            },
            Origin::File,
        ) => raise(
            py,
            "ModelError",
            e.to_string(),
            &[
                ("key_path", Attr::Str(path.clone())),
                ("file", path_attr(file)),
                (
                    "line",
                    if *line > 0 {
                        Attr::Int(*line)
                    } else {
                        Attr::None
                    },
                ),
                ("reason", Attr::Str(message.clone())),
            ],
        ),
        (SimError::Model { path, message, .. }, Origin::Python) => raise(
            py,
            "ModelError",
            format!("model: at `{path}`: {message}"),
            &[
                ("key_path", Attr::Str(path.clone())),
                ("file", Attr::None),
                ("line", Attr::None),
                ("reason", Attr::Str(message.clone())),
            ],
        ),
        (SimError::Engine { file, source }, _) => {
            let (message, file) = match origin {
                Origin::File => (e.to_string(), path_attr(file)),
                Origin::Python => (format!("model: invalid model: {source}"), Attr::None),
            };
            raise(
                py,
                "ModelError",
                message,
                &[
                    ("key_path", Attr::None),
                    ("file", file),
                    ("line", Attr::None),
                    ("reason", Attr::Str(source.to_string())),
                ],
            )
        }
    }
}

/// A results-file error as `IoError` (`UnknownSeriesError` for an unknown series name).
pub fn results_error(py: Python<'_>, e: &ResultsError) -> PyErr {
    match e {
        ResultsError::UnknownSeries { path, name, close } => raise(
            py,
            "UnknownSeriesError",
            e.to_string()
                .replace("`flexmbs plot RESULTS --list`", "`Results.names()`"),
            &[
                ("path", path_attr(path)),
                ("name", Attr::Str(name.clone())),
                ("close", Attr::Str(close.join(", "))),
            ],
        ),
        _ => {
            let path = path_attr(results_path(e));
            raise(py, "IoError", e.to_string(), &[("path", path)])
        }
    }
}

/// The file a results-file error is about (every variant names one).
fn results_path(e: &ResultsError) -> &Path {
    use flexmbs_io::plot::PlotError;
    use flexmbs_io::vtk::VtkError;
    match e {
        ResultsError::UnsafeTarget { path, .. }
        | ResultsError::Io { path, .. }
        | ResultsError::Hdf5 { path, .. }
        | ResultsError::NotAResultsFile { path, .. }
        | ResultsError::UnsupportedVersion { path, .. }
        | ResultsError::MissingDataset { path, .. }
        | ResultsError::BadAttribute { path, .. }
        | ResultsError::WrongShape { path, .. }
        | ResultsError::InvalidLayout { path, .. }
        | ResultsError::BadUserAttribute { path, .. }
        | ResultsError::RowLength { path, .. }
        | ResultsError::UnknownSeries { path, .. }
        | ResultsError::NoSeries { path }
        | ResultsError::UnsupportedPlotFormat { path, .. }
        | ResultsError::InvalidAnimation { path, .. }
        | ResultsError::Vtk(VtkError::Io { path, .. } | VtkError::Invalid { path, .. }) => path,
        ResultsError::Plot(PlotError::Draw { file, .. } | PlotError::Empty { file }) => file,
    }
}

/// A run error: `ModelError`, `SolverError` (time, step, residual, results file, and the hint
/// chosen by the cause of the failure for a run with `solver`), `IoError`, or `Error` for an
/// internal error.
pub fn run_error(
    py: Python<'_>,
    e: &RunError,
    origin: Origin,
    solver: &flexmbs_sim::SolverConfig,
) -> PyErr {
    match e {
        RunError::Model(m) => sim_error(py, m, origin),
        RunError::Results(r) => results_error(py, r),
        RunError::Locked(_) => raise(py, "IoError", e.to_string(), &[]),
        RunError::Io { path, .. } => {
            raise(py, "IoError", e.to_string(), &[("path", path_attr(path))])
        }
        RunError::Solver {
            t,
            h,
            residual,
            results,
            cause,
            ..
        } => raise(
            py,
            "SolverError",
            e.to_string(),
            &[
                ("t", Attr::Float(*t)),
                ("h", Attr::Float(*h)),
                ("residual", Attr::Float(*residual)),
                ("results", path_attr(results)),
                ("hint", Attr::Str(cause.hint(solver))),
            ],
        ),
        RunError::Internal { results, .. } => raise(
            py,
            "Error",
            e.to_string(),
            &[("results", path_attr(results))],
        ),
    }
}

/// A body-file or FE-model error as `IoError` or `ModelError`.
pub fn fe_error(py: Python<'_>, e: &flexmbs_io::model::ModelError) -> PyErr {
    let attrs = [
        (
            "key_path",
            e.key_path()
                .map_or(Attr::None, |p| Attr::Str(p.to_string())),
        ),
        ("file", path_attr(e.file())),
        (
            "line",
            e.line().filter(|l| *l > 0).map_or(Attr::None, Attr::Int),
        ),
        ("reason", Attr::Str(e.to_string())),
    ];
    raise(py, "ModelError", e.to_string(), &attrs)
}
