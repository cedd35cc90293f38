//! Errors of reading and compiling a multibody model file.

use std::path::PathBuf;
use thiserror::Error;

/// A model file that cannot be read or compiled. Every variant names the file; schema and
/// value errors also the key path and the 1-based line (0 if unknown).
#[derive(Debug, Error)]
pub enum SimError {
    /// The file could not be read.
    #[error("{file}: cannot read: {source}")]
    Read {
        /// File.
        file: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// TOML syntax, schema or value error at a key path.
    #[error("{file}:{line}: at `{path}`: {message}")]
    Model {
        /// File.
        file: PathBuf,
        /// 1-based line (0 if unknown).
        line: usize,
        /// Key path, e.g. `joint[1].a`.
        path: String,
        /// What was wrong.
        message: String,
    },
    /// The engine rejected the assembled model (reported without a key path).
    #[error("{file}: invalid model: {source}")]
    Engine {
        /// File.
        file: PathBuf,
        /// Cause.
        source: flexmbs_core::ModelError,
    },
}

impl SimError {
    /// Key path of a schema/value error.
    pub fn path(&self) -> Option<&str> {
        match self {
            SimError::Model { path, .. } => Some(path),
            _ => None,
        }
    }
    /// Line of a schema/value error.
    pub fn line(&self) -> Option<usize> {
        match self {
            SimError::Model { line, .. } => Some(*line),
            _ => None,
        }
    }
}
