//! The results reader of `flexmbs-io` for Python: columns as numpy arrays (SI units). The
//! user-facing `flexmbs.Results` (Python) wraps this class.

use crate::errors::results_error;
use flexmbs_io::results::{read_results, Results, RunStatus};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A results file read into memory.
#[pyclass(frozen, module = "flexmbs._native", name = "NativeResults")]
pub struct NativeResults {
    r: Results,
}

/// The fixed column groups and their widths, as `Results::row` returns them.
const GROUPS: [&str; 7] = ["q", "u", "lambda", "energy", "drift", "step", "signals"];

impl NativeResults {
    /// The values of group `name` in row `i`.
    fn group_row<'a>(row: &flexmbs_io::results::ResultsRow<'a>, name: &str) -> Vec<f64> {
        match name {
            "q" => row.q.to_vec(),
            "u" => row.u.to_vec(),
            "lambda" => row.lambda.to_vec(),
            "energy" => row.energy.to_vec(),
            "drift" => row.drift.to_vec(),
            "step" => row.step.to_vec(),
            _ => row.signals.to_vec(),
        }
    }

    /// Width of group `name`.
    fn group_width(&self, name: &str) -> usize {
        let l = &self.r.layout;
        match name {
            "q" => l.coordinates.len(),
            "u" => l.velocities.len(),
            "lambda" => l.multipliers.len(),
            "energy" => 4,
            "drift" => 2,
            "step" => 3,
            _ => l.signal_width(),
        }
    }
}

/// Reads a results file (also one of a run that was interrupted, failed or is still going).
#[pyfunction]
pub fn read(py: Python<'_>, path: PathBuf) -> PyResult<NativeResults> {
    py.detach(|| read_results(&path))
        .map(|r| NativeResults { r })
        .map_err(|e| results_error(py, &e))
}

#[pymethods]
impl NativeResults {
    /// Output times in s, shape `(n,)`.
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.r.time)
    }

    /// Every series name, as `Results::series_names`.
    fn names(&self) -> Vec<String> {
        self.r.series_names()
    }

    /// One series, shape `(n,)`.
    fn column<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = self.r.series(name).map_err(|e| results_error(py, &e))?;
        Ok(PyArray1::from_vec(py, v))
    }

    /// A group of columns (`q`, `u`, `lambda`, `energy`, `drift`, `step`, `signals`), shape
    /// `(n, width)`; `None` for another name.
    fn group<'py>(
        &self,
        py: Python<'py>,
        name: &str,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        if !GROUPS.contains(&name) {
            return Ok(None);
        }
        let (n, w) = (self.r.rows(), self.group_width(name));
        let mut data = Vec::with_capacity(n * w);
        for i in 0..n {
            if let Some(row) = self.r.row(i) {
                data.extend(Self::group_row(&row, name));
            }
        }
        Ok(Some(PyArray1::from_vec(py, data).reshape([n, w])?))
    }

    /// Column names of a group, in order (energy: kinetic, gravity, elastic, springs).
    fn group_columns(&self, name: &str) -> Vec<String> {
        let l = &self.r.layout;
        let fixed = |c: &[&str]| c.iter().map(|s| s.to_string()).collect();
        match name {
            "q" => l.coordinates.clone(),
            "u" => l.velocities.clone(),
            "lambda" => l.multipliers.clone(),
            "energy" => fixed(&flexmbs_io::results::ENERGY_COLUMNS),
            "drift" => fixed(&flexmbs_io::results::DRIFT_COLUMNS),
            "step" => fixed(&flexmbs_io::results::STEP_COLUMNS),
            "signals" => l
                .signals
                .iter()
                .flat_map(|s| s.components.iter().map(move |c| format!("{}.{c}", s.name)))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// The requested output signals: `(name, unit, components)` each.
    fn signals(&self) -> Vec<(String, String, Vec<String>)> {
        self.r
            .layout
            .signals
            .iter()
            .map(|s| (s.name.clone(), s.unit.clone(), s.components.clone()))
            .collect()
    }

    /// Number of output rows.
    fn rows(&self) -> usize {
        self.r.rows()
    }

    /// Model name.
    fn model(&self) -> String {
        self.r.layout.model.clone()
    }

    /// The file read.
    fn path(&self) -> String {
        self.r.path().display().to_string()
    }

    /// `(status, time, message)`: `completed`, `interrupted`, `failed` or `running`; the time
    /// of an interruption or failure (else `None`); the failure message (else `None`).
    fn status(&self) -> (String, Option<f64>, Option<String>) {
        let name = self.r.status.name().to_string();
        match &self.r.status {
            RunStatus::Interrupted { t } => (name, Some(*t), None),
            RunStatus::Failed { t, message } => (name, Some(*t), Some(message.clone())),
            _ => (name, None, None),
        }
    }

    /// The user attributes of the file (model file, solver, program).
    fn attributes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in self.r.attributes() {
            d.set_item(k, v)?;
        }
        Ok(d)
    }
}
