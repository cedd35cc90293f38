//! Modal stress fields of a reduced body (issue 11 item 5): the nodal stress of every basis
//! vector (normal modes and Craig-Bampton static modes), computed from the FE model at reduction
//! ([`flexmbs_fe::stress`]) and stored in the reduced-body file (dataset `stress/modal`), so
//! that a run recovers stresses linearly: `sigma = sum_k S_k q_k`.

use crate::pipeline::{PipelineError, PreparedBody};
use flexmbs_fe::mesh::BeamSection;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::stress::{modal_stress, BeamFibres, ModalStress};
use flexmbs_io::model::{FeBodySpec, MeshSpec, SectionSpec};

/// The stress points of the beam section of `spec` (body units): the rectangle's half-sides and
/// Roark's torsion point, the outer radius of circles and tubes, and the equivalent rectangle
/// (`c = sqrt(3 I / A)`) of a section given by its constants or of a beam from a CalculiX deck.
pub fn section_fibres(spec: &FeBodySpec, section: &BeamSection) -> BeamFibres {
    match &spec.mesh {
        MeshSpec::Beam { section: s, .. } => match *s {
            SectionSpec::Rectangle { width, height } => {
                BeamFibres::rectangle(width, height, section.j)
            }
            SectionSpec::Circle { diameter } => BeamFibres::round(0.5 * diameter),
            SectionSpec::Tube { outer_radius, .. } => BeamFibres::round(outer_radius),
            SectionSpec::General { .. } => BeamFibres::equivalent_rectangle(section),
        },
        _ => BeamFibres::equivalent_rectangle(section),
    }
}

/// The modal stress fields of `body`, reduced from `prepared` (its mesh, same node numbering),
/// in the body's units (stress = force / length²).
pub fn modal_stress_fields(
    spec: &FeBodySpec,
    prepared: &PreparedBody,
    body: &ReducedBody,
) -> Result<ModalStress, PipelineError> {
    let fibres = |_: usize, s: &BeamSection| section_fibres(spec, s);
    modal_stress(&prepared.mesh, body, &fibres).map_err(|source| PipelineError::Fe {
        context: "modal stress fields".into(),
        source,
    })
}
