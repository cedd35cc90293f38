//! The native part of the `flexmbs` Python package (`flexmbs._native`): thin bindings of the
//! model-file level of flexmbs (`flexmbs-sim`: compile and run model files; `flexmbs-io`: results
//! and body files; `flexmbs-reduce`: modal analysis and reduction). No physics here: every
//! function calls the same library functions as the command-line program. The Python side
//! (`python/flexmbs`) holds the user-facing classes; see `docs/python.md`.
#![warn(missing_docs)]

pub mod errors;
pub mod fe;
pub mod model;
pub mod results;
pub mod run;
pub mod sweep;

use pyo3::prelude::*;

/// The `flexmbs._native` module.
#[pymodule]
#[pyo3(name = "_native")]
fn flexmbs_native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(model::toml_loads, m)?)?;
    m.add_function(wrap_pyfunction!(model::toml_dumps, m)?)?;
    m.add_function(wrap_pyfunction!(model::check, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(results::read, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep, m)?)?;
    m.add_function(wrap_pyfunction!(fe::modal, m)?)?;
    m.add_function(wrap_pyfunction!(fe::reduce, m)?)?;
    m.add_function(wrap_pyfunction!(fe::read_body, m)?)?;
    m.add_class::<run::PyProgress>()?;
    m.add_class::<results::NativeResults>()?;
    Ok(())
}
