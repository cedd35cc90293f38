//! Error type of the file-format readers and writers.
//!
//! Every parse error is located: it names the file and, where the problem sits on one line,
//! the 1-based line number, so a message reads like
//! `u0.dat:17: expected 3 numbers (x y z), found 2`.

use std::path::{Path, PathBuf};
use thiserror::Error;

/// Errors of reading, writing and running external FE tools.
#[derive(Debug, Error)]
pub enum IoError {
    /// The operating system refused to read or write a file.
    #[error("{}: {source}", file.display())]
    Io {
        /// File concerned.
        file: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// A line does not have the expected syntax.
    #[error("{}:{line}: expected {expected}, found {found}", file.display())]
    Parse {
        /// File concerned.
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What the reader expected.
        expected: String,
        /// What it found instead.
        found: String,
    },
    /// A line is syntactically fine but its content is invalid (duplicate label, missing node,
    /// non-symmetric entry, ...).
    #[error("{}:{line}: {what}", file.display())]
    Invalid {
        /// File concerned.
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Description of the problem.
        what: String,
    },
    /// The file as a whole (or a set of files) is inconsistent, e.g. the mode-shape matrix has a
    /// row count different from 3 x the number of nodes.
    #[error("{}: {what}", file.display())]
    Inconsistent {
        /// File (or directory) concerned.
        file: PathBuf,
        /// Description, naming both numbers that disagree.
        what: String,
    },
    /// No CalculiX executable was found.
    #[error(
        "CalculiX (ccx) not found: install the Debian package calculix-ccx or set FLEXMBS_CCX"
    )]
    CcxMissing,
    /// CalculiX ran but failed (non-zero exit status or `*ERROR` in its output).
    #[error("CalculiX failed on {} (exit status {status:?}): {message}", deck.display())]
    CcxFailed {
        /// Deck that was run.
        deck: PathBuf,
        /// Exit status, `None` if killed by a signal.
        status: Option<i32>,
        /// The `*ERROR` lines of its output, or its last lines.
        message: String,
    },
}

impl IoError {
    /// The file (or directory) the error refers to, if any.
    pub fn file(&self) -> Option<&Path> {
        match self {
            IoError::Io { file, .. }
            | IoError::Parse { file, .. }
            | IoError::Invalid { file, .. }
            | IoError::Inconsistent { file, .. } => Some(file),
            IoError::CcxFailed { deck, .. } => Some(deck),
            IoError::CcxMissing => None,
        }
    }

    /// The 1-based line number the error refers to, if it is tied to one line.
    pub fn line(&self) -> Option<usize> {
        match self {
            IoError::Parse { line, .. } | IoError::Invalid { line, .. } => Some(*line),
            _ => None,
        }
    }

    /// Builds a [`IoError::Parse`].
    pub(crate) fn parse(
        file: &Path,
        line: usize,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> Self {
        IoError::Parse {
            file: file.to_path_buf(),
            line,
            expected: expected.into(),
            found: found.into(),
        }
    }

    /// Builds a [`IoError::Invalid`].
    pub(crate) fn invalid(file: &Path, line: usize, what: impl Into<String>) -> Self {
        IoError::Invalid {
            file: file.to_path_buf(),
            line,
            what: what.into(),
        }
    }

    /// Builds a [`IoError::Inconsistent`].
    pub(crate) fn inconsistent(file: &Path, what: impl Into<String>) -> Self {
        IoError::Inconsistent {
            file: file.to_path_buf(),
            what: what.into(),
        }
    }
}

/// Reads a whole text file, mapping the failure to [`IoError::Io`].
pub(crate) fn read_text(path: &Path) -> Result<String, IoError> {
    crate::source_file::read_to_string(path).map_err(|source| IoError::Io {
        file: path.to_path_buf(),
        source,
    })
}

/// Writes a whole text file, mapping the failure to [`IoError::Io`].
pub(crate) fn write_text(path: &Path, text: &str) -> Result<(), IoError> {
    std::fs::write(path, text).map_err(|source| IoError::Io {
        file: path.to_path_buf(),
        source,
    })
}

/// Shortens a found token for an error message (fuzzed input can have huge lines).
pub(crate) fn excerpt(s: &str) -> String {
    const MAX: usize = 60;
    let s = s.trim();
    if s.chars().count() <= MAX {
        format!("'{s}'")
    } else {
        let head: String = s.chars().take(MAX).collect();
        format!("'{head}...'")
    }
}

/// Parses a finite `f64`, or returns a located [`IoError::Parse`] naming `what`.
pub(crate) fn parse_finite(
    tok: &str,
    file: &Path,
    line: usize,
    what: &str,
) -> Result<f64, IoError> {
    match tok.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(IoError::parse(
            file,
            line,
            format!("a finite number ({what})"),
            excerpt(tok),
        )),
        Err(_) => Err(IoError::parse(
            file,
            line,
            format!("a number ({what})"),
            excerpt(tok),
        )),
    }
}

/// Formats an `f64` like C's `%.16e` (17 significant digits, signed two-digit exponent), which
/// reads back bit-identically.
pub(crate) fn fmt_exact(v: f64) -> String {
    let s = format!("{v:.16e}");
    match s.split_once('e') {
        Some((mant, exp)) => {
            let (sign, digits) = match exp.strip_prefix('-') {
                Some(d) => ('-', d),
                None => ('+', exp),
            };
            format!("{mant}e{sign}{digits:0>2}")
        }
        None => s,
    }
}
