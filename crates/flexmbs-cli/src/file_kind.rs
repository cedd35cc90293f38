//! Refuses the wrong kind of file before a command tries to parse it: an FE body file given to
//! `run`, an HDF5 file given to `check`, a model file given to `plot`. The messages say what the
//! file is and what the command expects.

use anyhow::{bail, Result};
use flexmbs_io::file_kind::{classify_model_file, ModelFileKind};
use std::path::Path;

/// What an HDF5 file holds, for messages: a reduced-body file, a results file, or neither.
fn describe_hdf5(path: &Path) -> &'static str {
    if flexmbs_io::body_file::read_body(path).is_ok() {
        "a reduced-body file (as `flexmbs reduce` writes)"
    } else if flexmbs_io::results::read_results(path).is_ok() {
        "a flexmbs results file (view it with `flexmbs plot --list`)"
    } else {
        "an HDF5 file that is neither a reduced-body nor a results file"
    }
}

/// Fails unless `path` can be a TOML model file for `command`; `multibody_only` for `run`.
/// Unreadable files pass (the command's own reader reports them).
pub fn expect_model_file(path: &Path, command: &str, multibody_only: bool) -> Result<()> {
    let Ok(bytes) = flexmbs_io::source_file::read(path) else {
        return Ok(());
    };
    let expects = if multibody_only {
        "a multibody model file (TOML with a [model] table)"
    } else {
        "a TOML model file: an FE body file ([body] table) or a multibody model file ([model] table)"
    };
    match classify_model_file(&bytes) {
        ModelFileKind::Hdf5 => bail!(
            "{} is {}, not a model file: `flexmbs {command}` expects {expects}",
            path.display(),
            describe_hdf5(path)
        ),
        ModelFileKind::Binary => bail!(
            "{} is a binary file (not UTF-8 text), not a model file: `flexmbs {command}` expects {expects}",
            path.display()
        ),
        ModelFileKind::FeBody if multibody_only => {
            bail!(
                "{} is an FE body file (no [model] table): use `flexmbs modal`, `reduce` or \
                 `check` on it, or reference it from a multibody model as a body's `source`",
                path.display()
            )
        }
        _ => Ok(()),
    }
}

/// Fails unless `path` is a flexmbs results file; `err` is the reader's error.
pub fn not_a_results_file(path: &Path, err: &dyn std::fmt::Display) -> anyhow::Error {
    let Ok(bytes) = flexmbs_io::source_file::read(path) else {
        return anyhow::anyhow!("reading {}: {err}", path.display());
    };
    let what = match classify_model_file(&bytes) {
        ModelFileKind::Hdf5 => match describe_hdf5(path) {
            d if d.starts_with("a flexmbs results") => {
                return anyhow::anyhow!("reading {}: {err}", path.display())
            }
            d => d.to_string(),
        },
        ModelFileKind::Multibody => {
            "a multibody model file: run it first with `flexmbs run`".into()
        }
        ModelFileKind::Binary => "a binary file, not HDF5".into(),
        ModelFileKind::FeBody | ModelFileKind::Other => "a text file, not HDF5".into(),
    };
    anyhow::anyhow!(
        "{} is not a flexmbs results file: it is {what}; `flexmbs plot` reads the results.h5 that \
         `flexmbs run` writes to its output folder",
        path.display()
    )
}
