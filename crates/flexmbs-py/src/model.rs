//! Models as plain data: TOML text <-> Python dicts (the same keys, values and units as the model
//! file), and the check of a model by the compiler of `flexmbs-sim`.

use crate::errors::{raise, sim_error, Attr, Origin};
use flexmbs_sim::CompiledModel;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};

/// A TOML value as a Python object (tables -> dict, arrays -> list, datetimes -> str).
fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => PyFloat::new(py, *x).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| toml_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => table_to_py(py, t)?.into_any(),
    })
}

fn table_to_py<'py>(py: Python<'py>, t: &toml::Table) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in t {
        d.set_item(k, toml_to_py(py, v)?)?;
    }
    Ok(d)
}

/// An unsupported value at `path` as `ModelError`.
fn bad_value(py: Python<'_>, path: &str, message: String) -> PyErr {
    raise(
        py,
        "ModelError",
        format!("model: at `{path}`: {message}"),
        &[
            ("key_path", Attr::Str(path.to_string())),
            ("file", Attr::None),
            ("line", Attr::None),
            ("reason", Attr::Str(message)),
        ],
    )
}

/// A Python value as a TOML value; `path` is its key path for errors (`body[1].mass`).
/// numpy arrays and scalars are converted through `tolist()`.
fn py_to_toml(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    let py = obj.py();
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        return match obj.extract::<i64>() {
            Ok(i) => Ok(toml::Value::Integer(i)),
            Err(_) => Err(bad_value(py, path, "integer out of range".into())),
        };
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(toml::Value::String(s.to_cow()?.into_owned()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        return Ok(toml::Value::Table(dict_to_table(d, path)?));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, item) in obj.try_iter()?.enumerate() {
            out.push(py_to_toml(&item?, &format!("{path}[{i}]"))?);
        }
        return Ok(toml::Value::Array(out));
    }
    if obj.hasattr("tolist")? {
        return py_to_toml(&obj.call_method0("tolist")?, path);
    }
    let ty = obj.get_type().name()?.to_string();
    Err(bad_value(
        py,
        path,
        format!("a value of type `{ty}` cannot be written to a model (use numbers, strings such as \"30 mm\", booleans, lists and dicts)"),
    ))
}

/// A dict as a TOML table; `None` values are left out (an absent key).
fn dict_to_table(d: &Bound<'_, PyDict>, path: &str) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let Ok(key) = k.extract::<String>() else {
            let ty = k.get_type().name()?.to_string();
            return Err(bad_value(
                d.py(),
                path,
                format!("keys must be strings, not `{ty}`"),
            ));
        };
        if v.is_none() {
            continue;
        }
        let sub = if path.is_empty() {
            key.clone()
        } else {
            format!("{path}.{key}")
        };
        t.insert(key, py_to_toml(&v, &sub)?);
    }
    Ok(t)
}

/// Parses model-file text into a dict (syntax errors as `ModelError` with the line).
#[pyfunction]
#[pyo3(signature = (text, file))]
pub fn toml_loads<'py>(py: Python<'py>, text: &str, file: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    match text.parse::<toml::Table>() {
        Ok(t) => table_to_py(py, &t),
        Err(e) => {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].lines().count().max(1))
                .unwrap_or(0);
            let message = e.message().trim_end().to_string();
            Err(raise(
                py,
                "ModelError",
                format!("{}:{line}: {message}", file.display()),
                &[
                    ("key_path", Attr::Str(String::new())),
                    ("file", Attr::Str(file.display().to_string())),
                    (
                        "line",
                        if line > 0 {
                            Attr::Int(line)
                        } else {
                            Attr::None
                        },
                    ),
                    ("reason", Attr::Str(message)),
                ],
            ))
        }
    }
}

/// Writes a dict as model-file (TOML) text; values that TOML cannot hold are `ModelError`s at
/// their key path.
#[pyfunction]
pub fn toml_dumps(data: &Bound<'_, PyDict>) -> PyResult<String> {
    let t = dict_to_table(data, "")?;
    toml::to_string(&t).map_err(|e| {
        raise(
            data.py(),
            "ModelError",
            format!("model: cannot be written as TOML: {e}"),
            &[],
        )
    })
}

/// Compiles model text from `file` (its folder resolves relative sources), with the GIL released.
pub fn compile(py: Python<'_>, text: &str, file: &Path, origin: Origin) -> PyResult<CompiledModel> {
    py.detach(|| flexmbs_sim::compile_model(text, file))
        .map_err(|e| sim_error(py, &e, origin))
}

/// The origin flag passed from Python: true for the unchanged text of a file.
pub fn origin(from_file: bool) -> Origin {
    if from_file {
        Origin::File
    } else {
        Origin::Python
    }
}

/// Compiles a model and returns what `flexmbs check` prints, as a dict.
#[pyfunction]
#[pyo3(signature = (text, file, from_file))]
pub fn check<'py>(
    py: Python<'py>,
    text: &str,
    file: PathBuf,
    from_file: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let cm = compile(py, text, &file, origin(from_file))?;
    let d = PyDict::new(py);
    d.set_item("name", &cm.name)?;
    let bodies: Vec<&str> = cm.bodies.iter().map(|b| b.name.as_str()).collect();
    d.set_item("bodies", bodies)?;
    d.set_item("frames", cm.model.frames.len())?;
    d.set_item("joints", cm.model.joints.len())?;
    d.set_item("constraint_rows", cm.model.nc)?;
    d.set_item("loads", cm.model.loads.len())?;
    d.set_item("coordinates", cm.model.nq)?;
    let signals: Vec<&str> = cm.signals.iter().map(|s| s.name.as_str()).collect();
    d.set_item("signals", signals)?;
    d.set_item("solver", describe_solver(&cm.solver))?;
    d.set_item("t_end", cm.solver.t_end())?;
    d.set_item("warnings", &cm.warnings)?;
    Ok(d)
}

/// The solver's name as in `[solver] type`.
fn describe_solver(s: &flexmbs_sim::SolverConfig) -> &'static str {
    use flexmbs_sim::SolverConfig as S;
    match s {
        S::GenAlpha { .. } => "generalized-alpha",
        S::Dopri5 { .. } => "dopri5",
        S::Statics { .. } => "statics",
        S::Moreau { .. } => "moreau",
    }
}
