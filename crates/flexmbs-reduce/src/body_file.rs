//! What a reduced-body file holds besides the body (`flexmbs reduce`, the Python `reduce`): one
//! function for both front ends, so the CLI and Python write the same file.

use crate::geometric::{centrifugal_geometric_stiffness, system_mass_kind};
use crate::pipeline::{PipelineError, PreparedBody, Stage};
use flexmbs_fe::geometric::GeometricError;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_io::body_file::BodyFile;
use flexmbs_io::model::FeBodySpec;
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
}

/// The body file of `body`, reduced from `prepared` (the FE model of `spec`): with its
/// centrifugal geometric stiffness if `geometric` and the body has fixed nodes (the unit-load
/// method, as a multibody model computes it from the FE model), the lumped node rotary inertias
/// of a beam mesh, and the modal stress fields. A body whose elements cannot give stresses is
/// still written, without them: the reason is returned next to the file.
pub fn body_file_of(
    spec: &FeBodySpec,
    prepared: &PreparedBody,
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
    let file = BodyFile {
        body,
        geometric,
        rotary_inertia,
        stress,
    };
    Ok((file, no_stress))
}
