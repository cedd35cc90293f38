//! What a reduced-body file holds besides the body (`flexmbs reduce`, the Python `reduce`): one
//! function for both front ends, so the CLI and Python write the same file.

use crate::geometric::{centrifugal_geometric_stiffness, system_mass_kind};
use crate::pipeline::{PipelineError, PreparedBody, Stage};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::geometric::GeometricError;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::SparseMatrix;
use flexmbs_io::body_file::BodyFile;
use flexmbs_io::model::FeBodySpec;
use std::path::Path;
use thiserror::Error;

/// Why the optional parts of a body file could not be computed.
#[derive(Debug, Error)]
pub enum BodyFileBuildError {
    /// The centrifugal geometric stiffness failed.
    #[error("geometric stiffness: {0}")]
    Geometric(#[from] GeometricError),
    /// The beam node rotary inertias failed.
    #[error("node rotary inertias: {0}")]
    RotaryInertia(String),
    /// The consistent-mass inertia (Gram matrix of the node fields) failed.
    #[error("consistent inertia: {0}")]
    ConsistentInertia(#[from] flexmbs_core::ffr::FfrError),
}

/// Prepares the FE model of `spec` for a body file ([`crate::pipeline::prepare`]), with the full
/// translational mass matrix when the system's mass is consistent (built-in `mass =
/// "consistent"` or CalculiX matrices; [`crate::full_mass::prepare_with_mass`], a CalculiX deck
/// exported without its `*BOUNDARY` cards, which gives the same reduced body): the mass the
/// consistent inertia of the body file is projected from ([`body_file_of`]). `None` with lumped
/// mass (the body's node masses are its inertia).
pub fn prepare_for_body_file(
    spec: &FeBodySpec,
    base: &Path,
    progress: &mut dyn FnMut(Stage),
) -> Result<(PreparedBody, Option<SparseMatrix>), PipelineError> {
    if system_mass_kind(&spec.mesh, spec.reduction.mass) == MassKind::Consistent {
        let (prepared, m) = crate::full_mass::prepare_with_mass(spec, base, progress)?;
        Ok((prepared, Some(m)))
    } else {
        Ok((crate::pipeline::prepare(spec, base, progress)?, None))
    }
}

/// The consistent-mass Gram matrix of `body` (body units;
/// `flexmbs_core::ffr::FfrInvariants::consistent_gram`) from the full translational mass
/// `full_mass` of its solid FE model `prepared`; `None` for a beam mesh (its consistent mass is
/// not block-isotropic: beam bodies take lumped inertia) or without `full_mass`.
pub fn consistent_inertia_gram(
    prepared: &PreparedBody,
    body: &ReducedBody,
    full_mass: Option<&SparseMatrix>,
) -> Result<Option<nalgebra::DMatrix<f64>>, BodyFileBuildError> {
    let Some(m) = full_mass else {
        return Ok(None);
    };
    if prepared.mesh.node_dofs().iter().any(|&c| c >= 6) {
        return Ok(None);
    }
    let g =
        flexmbs_core::ffr::FfrInvariants::consistent_gram(&body.nodes, m, body.modes_t.as_ref())?;
    // stored symmetric, as `FfrInvariants::from_gram` uses it (0.5 (a + a) = a exactly)
    Ok(Some(0.5 * (&g + g.transpose())))
}

/// The body file of `body`, reduced from `prepared` (the FE model of `spec`): with its
/// centrifugal geometric stiffness if `geometric` and the body has fixed nodes (the unit-load
/// method, as a multibody model computes it from the FE model), the lumped node rotary inertias
/// of a beam mesh, the modal stress fields, and, given the full translational mass `full_mass` of
/// a consistent-mass model ([`prepare_for_body_file`]), the consistent inertia of a solid mesh
/// ([`consistent_inertia_gram`]). A body whose elements cannot give stresses is still written,
/// without them: the reason is returned next to the file.
pub fn body_file_of(
    spec: &FeBodySpec,
    prepared: &PreparedBody,
    full_mass: Option<&SparseMatrix>,
    body: ReducedBody,
    geometric: bool,
    stage: &mut dyn FnMut(Stage),
) -> Result<(BodyFile, Option<PipelineError>), BodyFileBuildError> {
    let geometric = if geometric && !prepared.bc.fixed.is_empty() {
        stage(Stage::Started(
            "geometric stiffness (unit-load method)".into(),
        ));
        let mass = system_mass_kind(&spec.mesh, spec.reduction.mass);
        centrifugal_geometric_stiffness(prepared, mass, &body)?
    } else {
        None
    };
    let rotary_inertia =
        crate::full_mass::beam_node_rotary_inertias(&prepared.mesh, body.num_nodes())
            .map_err(BodyFileBuildError::RotaryInertia)?;
    let (stress, no_stress) = match crate::stress::modal_stress_fields(spec, prepared, &body) {
        Ok(s) => (Some(s), None),
        Err(e) => (None, Some(e)),
    };
    let inertia_gram = consistent_inertia_gram(prepared, &body, full_mass)?;
    let file = BodyFile {
        body,
        geometric,
        rotary_inertia,
        stress,
        inertia_gram,
    };
    Ok((file, no_stress))
}
