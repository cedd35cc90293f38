//! Centrifugal geometric stiffness of a body prepared by the pipeline: the six projected matrices
//! `K_G,ab` of the unit-load method ([`flexmbs_fe::geometric::geometric_stiffness`]) supported on
//! the FE model's fixed nodes. One function for both users, so that they agree bitwise: the
//! multibody model compiler (`geometric_stiffening = true` with an FE model file as source) and the
//! writer of reduced-body files (`flexmbs reduce`), which stores them in the optional `geometric`
//! group of the `.fmb.h5` file (`docs/formats/reduced-body.md`).

use crate::pipeline::PreparedBody;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::geometric::{
    geometric_stiffness, GeometricError, GeometricStiffness, InertialLoad,
};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_io::model::{CcxMatrices, MassName, MeshSpec};

/// Element mass kind of the system [`crate::pipeline::prepare`] assembles for `mesh`/`mass` of an
/// FE model file: the requested kind, except that matrices exported by CalculiX are consistent.
/// Inertial loads of the unit-load method must use the same kind.
pub fn system_mass_kind(mesh: &MeshSpec, mass: MassName) -> MassKind {
    match (mesh, mass) {
        (
            MeshSpec::Calculix {
                matrices: CcxMatrices::Ccx,
                ..
            },
            _,
        ) => MassKind::Consistent,
        (_, MassName::Lumped) => MassKind::Lumped,
        (_, MassName::Consistent) => MassKind::Consistent,
    }
}

/// The six centrifugal geometric stiffness matrices `K_G,ab` (patterns
/// [`InertialLoad::centrifugal`], order xx, xy, xz, yy, yz, zz) of `body`, reduced from
/// `prepared`, over all modes of `body`, in the body's units (per (rad/s)²), the static unit-load
/// problems supported on the fixed nodes of `prepared`. `mass` is the element mass kind of the
/// system ([`system_mass_kind`]). `Ok(None)` for a body without fixed nodes (free-free: the static
/// problem is singular, inertia relief is not implemented).
///
/// Cost: one sparse Cholesky factorization of the constrained stiffness and, per element, six
/// stress stiffnesses projected on the `n_f` modes.
pub fn centrifugal_geometric_stiffness(
    prepared: &PreparedBody,
    mass: MassKind,
    body: &ReducedBody,
) -> Result<Option<GeometricStiffness>, GeometricError> {
    if prepared.bc.fixed.is_empty() {
        return Ok(None);
    }
    geometric_stiffness(
        &prepared.mesh,
        &prepared.system,
        body,
        mass,
        &InertialLoad::centrifugal(),
        &[],
    )
    .map(Some)
}
