//! The versioned reduced-body file: one HDF5 file per [`ReducedBody`].
//!
//! The file is written and read with the pure-Rust `hdf5-pure` crate (no libhdf5 is linked) and
//! is an ordinary HDF5 file that `h5py`, `h5dump` and any other HDF5 tool can open. The layout
//! (groups, datasets, shapes, attributes) is documented in `docs/formats/reduced-body.md`; its
//! version is the root attribute `format_version` ([`FORMAT_VERSION`]).
//!
//! Reading validates everything a multibody model relies on (shapes consistent with the node and
//! mode counts, indices in range, cell node counts matching their kinds) and reports the first
//! problem as a [`BodyFileError`] naming the file and the dataset; it never panics, also not on a
//! truncated or corrupted file.

mod consistency;
mod geometric;
mod h5;
mod inertia;
mod rotary;
mod stress;
mod text_digest;

pub use consistency::{
    FREQUENCY_TOLERANCE, MATRIX_SYMMETRY_TOLERANCE, NODE_MASS_TOLERANCE, NULL_SPACE_TOLERANCE,
};
pub use geometric::{parse_pattern_name, pattern_name, SYMMETRY_TOLERANCE};
pub use inertia::GRAM_TOLERANCE;
pub use rotary::ROTARY_INERTIA_TOLERANCE;
pub use text_digest::text_sha256;

use flexmbs_fe::geometric::GeometricStiffness;
use flexmbs_fe::reduction::ReducedBody;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Value of the root attribute `format` that marks a flexmbs reduced-body file.
pub const FORMAT_NAME: &str = "flexmbs.reduced_body";

/// Version of the on-disk layout written by [`write_body`]; [`read_body`] reads this version and
/// version 1 (no `text_sha256`).
pub const FORMAT_VERSION: i64 = 2;

/// Recommended file name extension of a reduced-body file.
pub const FILE_EXTENSION: &str = "fmb.h5";

/// Errors of writing or reading a reduced-body file. Every variant names the file.
#[derive(Debug, Error)]
pub enum BodyFileError {
    /// The output path holds something that is not a regular file (a symlink, device, FIFO or
    /// folder): it is not replaced.
    #[error("{path}: is {kind}; refusing to replace it (choose another output path)")]
    UnsafeTarget {
        /// The path.
        path: PathBuf,
        /// What is there.
        kind: &'static str,
    },
    /// The file could not be read or written at the operating-system level.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The HDF5 layer rejected the file (not HDF5, truncated, corrupted) or an object in it.
    #[error("{path}: HDF5 error at '{object}': {message}")]
    Hdf5 {
        /// File concerned.
        path: PathBuf,
        /// HDF5 object (dataset, group, attribute or `/` for the file) being accessed.
        object: String,
        /// Message of the HDF5 layer.
        message: String,
    },
    /// The file is HDF5 but not a flexmbs reduced-body file (the root attribute `format` is
    /// missing or different).
    #[error("{path}: not a flexmbs reduced-body file ({reason})")]
    NotABodyFile {
        /// File concerned.
        path: PathBuf,
        /// What was found instead.
        reason: String,
    },
    /// The file was written with a layout version this program does not read.
    #[error("{path}: unsupported format_version {found} (this program reads version {supported})")]
    UnsupportedVersion {
        /// File concerned.
        path: PathBuf,
        /// Version found in the file.
        found: i64,
        /// Version this program reads.
        supported: i64,
    },
    /// A required dataset is missing.
    #[error("{path}: missing dataset '{dataset}'")]
    MissingDataset {
        /// File concerned.
        path: PathBuf,
        /// Full dataset path inside the file.
        dataset: String,
    },
    /// A required attribute is missing or has the wrong type.
    #[error("{path}: missing or ill-typed attribute '{attribute}' ({expected} expected)")]
    BadAttribute {
        /// File concerned.
        path: PathBuf,
        /// Object path and attribute name, e.g. `/@units`.
        attribute: String,
        /// Expected type or value.
        expected: String,
    },
    /// A dataset has a shape inconsistent with the rest of the body.
    #[error("{path}: dataset '{dataset}' has shape {found:?}, expected {expected}")]
    WrongShape {
        /// File concerned.
        path: PathBuf,
        /// Full dataset path inside the file.
        dataset: String,
        /// Expected shape, e.g. `[N, 3] = [12, 3]`.
        expected: String,
        /// Shape found.
        found: Vec<u64>,
    },
    /// A dataset has an element type that cannot hold its data without loss.
    #[error("{path}: dataset '{dataset}' has element type {found}, expected {expected}")]
    WrongType {
        /// File concerned.
        path: PathBuf,
        /// Full dataset path inside the file.
        dataset: String,
        /// Expected element type.
        expected: String,
        /// Element type found.
        found: String,
    },
    /// The data are inconsistent (index out of range, unknown element kind, inconsistent body
    /// handed to the writer).
    #[error("{path}: invalid data in '{object}': {message}")]
    Invalid {
        /// File concerned.
        path: PathBuf,
        /// Dataset, attribute or body field concerned.
        object: String,
        /// What is wrong.
        message: String,
    },
}

/// Contents of a reduced-body file: the body and, if stored, its geometric stiffness and node
/// rotary inertias.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyFile {
    /// The reduced body.
    pub body: ReducedBody,
    /// Projected geometric stiffness matrices `K_G,i` over all `N_f` modes of `body`, in its
    /// units (optional group `geometric`; written by `flexmbs reduce` for bodies with fixed
    /// nodes: the six centrifugal patterns, supported on the fixed nodes).
    pub geometric: Option<GeometricStiffness>,
    /// Lumped node rotary inertias `I_j` (one 3 x 3 matrix per node of `body`, body frame, units
    /// of `body`: mass · length²; optional dataset `nodes/rotary_inertia`, written by
    /// `flexmbs reduce` for beam meshes, see
    /// `flexmbs_reduce::full_mass::beam_node_rotary_inertias`). `None` for solid bodies and files
    /// written before the dataset existed.
    pub rotary_inertia: Option<Vec<nalgebra::Matrix3<f64>>>,
    /// Modal stress fields (optional group `stress`: datasets `stress/modal`, `[6 N, N_f]`, and
    /// `stress/node_kind`, `[N]`), written by `flexmbs reduce` from an FE model; `None` for
    /// seed folders and files written before the group existed.
    pub stress: Option<flexmbs_fe::stress::ModalStress>,
    /// Consistent-mass Gram matrix of the node fields (optional dataset `inertia/gram`,
    /// `(4 + 3 N_f)` square, units of `body`; `flexmbs_core::ffr::FfrInvariants::consistent_gram`):
    /// the inertia shape integrals of a body reduced from a consistent mass matrix, written by
    /// `flexmbs reduce` for solid meshes with consistent mass. `None` for other bodies and files
    /// written before the dataset existed (their inertia comes from the node masses).
    pub inertia_gram: Option<nalgebra::DMatrix<f64>>,
}

impl BodyFile {
    /// A file holding `body` only (no geometric stiffness, no node rotary inertias).
    pub fn plain(body: ReducedBody) -> Self {
        Self {
            body,
            geometric: None,
            rotary_inertia: None,
            stress: None,
            inertia_gram: None,
        }
    }

    /// Writes the body and its optional parts to the reduced-body file `path` (see
    /// [`write_body_file`]). The node rotary inertias must be one per node, finite, symmetric
    /// and positive semi-definite (to [`ROTARY_INERTIA_TOLERANCE`] relative), else the result is
    /// a [`BodyFileError::Invalid`] naming `nodes/rotary_inertia` and nothing is written; the
    /// modal stress fields must be `6 N x N_f` and finite with one kind per node (else an
    /// [`BodyFileError::Invalid`] naming `stress/modal` or `stress/node_kind`); the Gram matrix
    /// must be `(4 + 3 N_f)` square, finite, symmetric, with a positive total mass and a modal
    /// block equal to `M_red` (to [`GRAM_TOLERANCE`], else an [`BodyFileError::Invalid`] naming
    /// `inertia/gram`).
    pub fn write(&self, path: &Path) -> Result<(), BodyFileError> {
        write_parts(
            path,
            &self.body,
            self.geometric.as_ref(),
            self.rotary_inertia.as_deref(),
            Optional {
                stress: self.stress.as_ref(),
                inertia_gram: self.inertia_gram.as_ref(),
            },
        )
    }
}

/// Writes `body` to the reduced-body file `path` (HDF5, layout version [`FORMAT_VERSION`]),
/// without geometric stiffness ([`write_body_file`] with `None`).
///
/// The body is checked for consistency first (mode shape rows `3 N`, square reduced matrices of
/// size `N_f`, one frequency and one label per mode, indices in range); an inconsistent body is
/// an [`BodyFileError::Invalid`] and nothing is written. The file is written to a temporary
/// sibling and renamed, so an existing file is replaced only by a complete one.
pub fn write_body(path: &Path, body: &ReducedBody) -> Result<(), BodyFileError> {
    write_body_file(path, body, None)
}

/// Writes `body` and, if given, its geometric stiffness `geometric` (optional group `geometric`
/// of the layout) to the reduced-body file `path`; as [`write_body`] otherwise.
///
/// `geometric` must hold at least one valid, distinct load pattern and one finite, symmetric
/// (to [`SYMMETRY_TOLERANCE`] relative) `N_f × N_f` matrix per pattern, else the result is a
/// [`BodyFileError::Invalid`] naming `geometric/stiffness` and nothing is written. Node rotary
/// inertias are written by [`BodyFile::write`].
pub fn write_body_file(
    path: &Path,
    body: &ReducedBody,
    geometric: Option<&GeometricStiffness>,
) -> Result<(), BodyFileError> {
    write_parts(path, body, geometric, None, Optional::default())
}

/// Further optional parts of a body file (beside the geometric stiffness and rotary inertias).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Optional<'a> {
    /// Modal stress fields.
    pub(crate) stress: Option<&'a flexmbs_fe::stress::ModalStress>,
    /// Consistent-mass Gram matrix.
    pub(crate) inertia_gram: Option<&'a nalgebra::DMatrix<f64>>,
}

/// Checks and writes a body with its optional parts (atomic replace of `path`).
fn write_parts(
    path: &Path,
    body: &ReducedBody,
    geometric: Option<&GeometricStiffness>,
    rotary_inertia: Option<&[nalgebra::Matrix3<f64>]>,
    optional: Optional<'_>,
) -> Result<(), BodyFileError> {
    h5::check_body(path, body)?;
    consistency::check_physics(path, body)?;
    if let Some(g) = optional.inertia_gram {
        inertia::check(path, g, body)?;
    }
    if let Some(s) = optional.stress {
        stress::check(path, s, body.num_nodes(), body.num_modes())?;
    }
    if let Some(g) = geometric {
        geometric::check(path, geometric::STIFFNESS, g, body.num_modes())?;
    }
    if let Some(r) = rotary_inertia {
        rotary::check(path, rotary::ROTARY_INERTIA, r, body.num_nodes())?;
    }
    if let Some(kind) = crate::output_safety::unsafe_target_kind(path) {
        return Err(BodyFileError::UnsafeTarget {
            path: path.to_path_buf(),
            kind,
        });
    }
    let bytes = h5::encode_body(path, body, geometric, rotary_inertia, optional)?;
    let tmp = temporary_sibling(path);
    std::fs::write(&tmp, &bytes).map_err(|source| BodyFileError::Io {
        path: tmp.clone(),
        source,
    })?;
    std::fs::rename(&tmp, path).map_err(|source| {
        let _ = std::fs::remove_file(&tmp);
        BodyFileError::Io {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Reads a reduced-body file written by [`write_body`] (or by any HDF5 writer following the
/// documented layout, e.g. h5py). A stored geometric stiffness or node rotary inertia is checked
/// but not returned (see [`read_body_file`]).
pub fn read_body(path: &Path) -> Result<ReducedBody, BodyFileError> {
    read_body_file(path).map(|f| f.body)
}

/// Reads a reduced-body file with its optional geometric stiffness (`None` if the file has no
/// `geometric` group, as files written before it existed) and node rotary inertias (`None`
/// without `nodes/rotary_inertia`). A malformed group (one dataset without the other, unknown
/// pattern name, wrong shape or type, non-finite or unsymmetric matrix) or node inertia
/// dataset (shape other than `[N, 3, 3]`, not float64, non-finite, unsymmetric or indefinite
/// matrix) is an error naming the dataset.
pub fn read_body_file(path: &Path) -> Result<BodyFile, BodyFileError> {
    let bytes = crate::source_file::read(path).map_err(|source| BodyFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_body_file(path, bytes)
}

/// Decodes the bytes of a reduced-body file; `path` only labels errors.
///
/// The HDF5 layer is trusted not to panic on malformed input, but a panic inside it would be a
/// bug there, not a property of the file: it is caught and reported as [`BodyFileError::Hdf5`]
/// so that a damaged file can never bring down a simulation.
pub fn decode_body(path: &Path, bytes: Vec<u8>) -> Result<ReducedBody, BodyFileError> {
    decode_body_file(path, bytes).map(|f| f.body)
}

/// [`decode_body`] with the optional geometric stiffness and node rotary inertias (see
/// [`read_body_file`]).
pub fn decode_body_file(path: &Path, bytes: Vec<u8>) -> Result<BodyFile, BodyFileError> {
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        h5::decode_body(path, bytes)
    }));
    match outcome {
        Ok(result) => result,
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_string());
            Err(BodyFileError::Hdf5 {
                path: path.to_path_buf(),
                object: "/".into(),
                message: format!("corrupted file (HDF5 decoder panicked: {message})"),
            })
        }
    }
}

/// `dir/.name.tmp-<pid>`: a temporary file next to `path` (same file system, so rename is atomic).
fn temporary_sibling(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "body".into());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}
