//! FE bodies from Python: modal analysis, reduction to a `.fmb.h5` body file and reading body
//! files, through the same library functions as `flexmbs modal` and `flexmbs reduce`.

use crate::errors::{fe_error, raise, Attr, Origin};
use flexmbs_io::body_file::BodyFile;
use flexmbs_io::model::{parse_fe_model, MeshSpec, ModelError};
use flexmbs_io::model_check::{ErrorAtKey, FeModelSource};
use flexmbs_reduce::pipeline::{prepare, run_modal, run_reduction, PreparedBody, Stage};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::path::{Path, PathBuf};

/// An FE-model error as `ModelError`; for a model changed in Python without file and line.
fn model_error(py: Python<'_>, e: &ModelError, origin: Origin) -> PyErr {
    match (origin, e.key_path()) {
        (Origin::Python, Some(path)) => raise(
            py,
            "ModelError",
            format!("body model: at `{path}`: {e}"),
            &[
                ("key_path", Attr::Str(path.to_string())),
                ("file", Attr::None),
                ("line", Attr::None),
                ("reason", Attr::Str(e.to_string())),
            ],
        ),
        _ => fe_error(py, e),
    }
}

/// Parses an FE body model text (checked like the file).
fn source(py: Python<'_>, text: &str, file: PathBuf, origin: Origin) -> PyResult<FeModelSource> {
    let model = parse_fe_model(text, &file).map_err(|e| model_error(py, &e, origin))?;
    Ok(FeModelSource {
        file,
        text: text.to_string(),
        model,
    })
}

/// A pipeline error located at its key.
fn located(py: Python<'_>, src: &FeModelSource, e: impl ErrorAtKey, origin: Origin) -> PyErr {
    model_error(py, &src.locate(e), origin)
}

/// Meshes the body and applies its supports (GIL released).
fn prepared(py: Python<'_>, src: &FeModelSource, origin: Origin) -> PyResult<PreparedBody> {
    let base = src.file.parent().unwrap_or(Path::new(".")).to_path_buf();
    py.detach(|| prepare(&src.model.body, &base, &mut |_| {}))
        .map_err(|e| located(py, src, e, origin))
}

/// Nodal fields `(3 N) x k` as an array `(k, N, 3)`.
fn mode_array<'py>(py: Python<'py>, m: faer::MatRef<'_, f64>) -> PyResult<Bound<'py, PyAny>> {
    let (rows, k) = (m.nrows(), m.ncols());
    let mut data = Vec::with_capacity(rows * k);
    for c in 0..k {
        for r in 0..rows {
            data.push(m[(r, c)]);
        }
    }
    Ok(PyArray1::from_vec(py, data)
        .reshape([k, rows / 3, 3])?
        .into_any())
}

/// A matrix as a 2-D array.
fn matrix<'py>(py: Python<'py>, m: faer::MatRef<'_, f64>) -> PyResult<Bound<'py, PyAny>> {
    let (r, c) = (m.nrows(), m.ncols());
    let data: Vec<f64> = (0..r)
        .flat_map(|i| (0..c).map(move |j| m[(i, j)]))
        .collect();
    Ok(PyArray1::from_vec(py, data).reshape([r, c])?.into_any())
}

/// Strings as a 1-D numpy array of `str` objects (dtype `object`, as the text columns of
/// `sweep`).
fn strings<'py, S: AsRef<str>>(
    py: Python<'py>,
    items: impl IntoIterator<Item = S>,
) -> Bound<'py, PyArray1<Py<PyAny>>> {
    let objects: Vec<Py<PyAny>> = items
        .into_iter()
        .map(|s| PyString::new(py, s.as_ref()).into_any().unbind())
        .collect();
    PyArray1::from_vec(py, objects)
}

/// Node coordinates `(N, 3)`.
fn points<'py>(py: Python<'py>, nodes: &[[f64; 3]]) -> PyResult<Bound<'py, PyAny>> {
    let data: Vec<f64> = nodes.iter().flatten().copied().collect();
    Ok(PyArray1::from_vec(py, data)
        .reshape([nodes.len(), 3])?
        .into_any())
}

/// Modal analysis of an FE body model (as `flexmbs modal`).
#[pyfunction]
#[pyo3(signature = (text, file, from_file, modes=None))]
pub fn modal<'py>(
    py: Python<'py>,
    text: &str,
    file: PathBuf,
    from_file: bool,
    modes: Option<usize>,
) -> PyResult<Bound<'py, PyDict>> {
    let origin = crate::model::origin(from_file);
    let src = source(py, text, file, origin)?;
    let body = prepared(py, &src, origin)?;
    let spec = &src.model.body;
    let n = modes.unwrap_or(spec.reduction.modes);
    let modal = py
        .detach(|| run_modal(spec, &body, n, &mut |_| {}))
        .map_err(|e| located(py, &src, e, origin))?;
    let rows = flexmbs_reduce::report::modal_rows(&modal);
    let d = PyDict::new(py);
    d.set_item("name", &spec.name)?;
    let f: Vec<f64> = rows.iter().map(|r| r.frequency_hz).collect();
    d.set_item("frequencies_hz", PyArray1::from_vec(py, f))?;
    d.set_item("omega2", PyArray1::from_slice(py, &modal.omega2))?;
    d.set_item("labels", strings(py, rows.iter().map(|r| &r.dominant)))?;
    let eff: Vec<f64> = rows
        .iter()
        .flat_map(|r| r.effective_mass_fraction)
        .collect();
    d.set_item(
        "effective_mass_fraction",
        PyArray1::from_vec(py, eff).reshape([rows.len(), 3])?,
    )?;
    d.set_item("n_rigid", modal.n_rigid)?;
    d.set_item("nodes", points(py, &body.system.map.nodes)?)?;
    let (t, r) = body.system.map.expand(modal.vectors.as_ref());
    d.set_item("modes", mode_array(py, t.as_ref())?)?;
    d.set_item("rotations", mode_array(py, r.as_ref())?)?;
    d.set_item("elements", body.mesh.elements.len())?;
    d.set_item("independent_dofs", body.system.len())?;
    Ok(d)
}

/// The body file of an FE body model, as `flexmbs reduce` writes it (geometric stiffness for a
/// body with fixed nodes if `geometric`, beam node rotary inertias).
fn reduce_body(
    py: Python<'_>,
    src: &FeModelSource,
    origin: Origin,
    geometric: bool,
) -> PyResult<BodyFile> {
    let spec = &src.model.body;
    let base = src.file.parent().unwrap_or(Path::new(".")).to_path_buf();
    let io = |e: String| raise(py, "IoError", e, &[]);
    if let MeshSpec::Seed { dir } = &spec.mesh {
        let dir = flexmbs_reduce::pipeline::resolve(&base, dir);
        let body = flexmbs_io::seed_body::read_seed_body(&dir, &spec.name, spec.units)
            .map_err(|e| io(e.to_string()))?;
        return Ok(BodyFile::plain(body));
    }
    let (prepared, full_mass) = py
        .detach(|| {
            flexmbs_reduce::body_file::prepare_for_body_file(spec, &base, &mut |_: Stage| {})
        })
        .map_err(|e| located(py, src, e, origin))?;
    let body = py
        .detach(|| run_reduction(spec, &prepared, &mut |_: Stage| {}))
        .map_err(|e| located(py, src, e, origin))?;
    let built = py.detach(|| {
        let m = full_mass.as_ref();
        flexmbs_reduce::body_file::body_file_of(spec, &prepared, m, body, geometric, &mut |_| {})
    });
    // a body whose elements cannot give stresses is written without them, as by `flexmbs reduce`
    let (file, _no_stress) = built.map_err(|e| raise(py, "Error", e.to_string(), &[]))?;
    Ok(file)
}

/// Reduces an FE body model and writes the reduced-body file `output` (as `flexmbs reduce`);
/// returns what was written.
#[pyfunction]
#[pyo3(signature = (text, file, from_file, output, geometric=true))]
pub fn reduce<'py>(
    py: Python<'py>,
    text: &str,
    file: PathBuf,
    from_file: bool,
    output: PathBuf,
    geometric: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let origin = crate::model::origin(from_file);
    let src = source(py, text, file, origin)?;
    let f = reduce_body(py, &src, origin, geometric)?;
    f.write(&output).map_err(|e| {
        let path = Attr::Str(output.display().to_string());
        raise(py, "IoError", e.to_string(), &[("path", path)])
    })?;
    let d = PyDict::new(py);
    d.set_item("path", output.display().to_string())?;
    d.set_item("nodes", f.body.num_nodes())?;
    d.set_item("modes", f.body.num_modes())?;
    d.set_item(
        "geometric_load_patterns",
        f.geometric.as_ref().map_or(0, |g| g.matrices.len()),
    )?;
    d.set_item("rotary_inertia", f.rotary_inertia.is_some())?;
    Ok(d)
}

/// Reads a reduced-body file (`.fmb.h5`): nodes, mode shapes, reduced matrices, frequencies.
#[pyfunction]
pub fn read_body<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let f = py
        .detach(|| flexmbs_io::body_file::read_body_file(&path))
        .map_err(|e| {
            let p = Attr::Str(path.display().to_string());
            raise(py, "IoError", e.to_string(), &[("path", p)])
        })?;
    let b = &f.body;
    let d = PyDict::new(py);
    d.set_item("name", &b.name)?;
    d.set_item("units", format!("{:?}", b.units))?;
    d.set_item("kind", format!("{:?}", b.kind))?;
    d.set_item("nodes", points(py, &b.nodes)?)?;
    d.set_item("node_ids", b.node_ids.clone())?;
    d.set_item("modes", mode_array(py, b.modes_t.as_ref())?)?;
    match &b.modes_r {
        Some(r) => d.set_item("rotations", mode_array(py, r.as_ref())?)?,
        None => d.set_item("rotations", py.None())?,
    }
    d.set_item("k_red", matrix(py, b.k_red.as_ref())?)?;
    d.set_item("m_red", matrix(py, b.m_red.as_ref())?)?;
    d.set_item(
        "frequencies_hz",
        PyArray1::from_slice(py, &b.frequencies_hz),
    )?;
    d.set_item("labels", strings(py, b.labels.iter().map(|l| &l.dominant)))?;
    d.set_item("interface_nodes", b.interface_nodes.clone())?;
    d.set_item("fixed_nodes", b.fixed_nodes.clone())?;
    d.set_item(
        "geometric_load_patterns",
        f.geometric.as_ref().map_or(0, |g| g.matrices.len()),
    )?;
    Ok(d)
}
