//! Mass model of an FFR body of a model file (`inertia = "lumped" | "consistent"`) and the lumped
//! node rotary inertias of beam meshes.
//!
//! - `"lumped"` (default): the invariants of the reduced body's node masses (seed 000 §2.4).
//! - `"consistent"`: the invariants are projections of the full translational FE mass matrix
//!   ([`flexmbs_core::ffr::FfrBody::from_reduced_consistent`], seed 000 §6.2 outlook), read from
//!   the same FE system the modes were computed with (built-in `mass = "consistent"` or a
//!   CalculiX export, `matrices = "ccx"`), so that `m_ff = Phi^T M Phi` holds; or, for a
//!   reduced-body file, from the Gram matrix of that projection the file stores (dataset
//!   `inertia/gram`, written by `flexmbs reduce` for consistent-mass solid meshes;
//!   [`stored_consistent_inertia`]), restricted to the selected modes.
//! - Beam meshes (6 DOFs per node) get lumped node rotary inertias in either case: the 3 x 3
//!   rotational diagonal blocks of the lumped beam mass matrix (torsion `rho I_p L/2`, bending
//!   `rho A L^3/78 + rho I L/2` per element end, `flexmbs_fe::element::beam`), added through
//!   [`flexmbs_core::ffr::FfrBody::set_rotary_inertia`]. Without them a torsion mode moves no
//!   node mass and the modal mass matrix is singular.

use crate::stiffening::FeModel;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::SparseMatrix;
use flexmbs_reduce::full_mass::{beam_node_rotary_inertias, rotary_inertias_to_si};
use nalgebra::Matrix3;

/// Message of `inertia = "consistent"` on a source without an FE model.
pub const CONSISTENT_NEEDS_FE_MODEL: &str = "inertia = \"consistent\" needs an FE model file \
     (.toml with a built-in mesh or a CalculiX deck) or a reduced-body file (.h5) that stores \
     the consistent inertia as `source`; a seed folder has no FE mass matrix";

/// Message of `inertia = "consistent"` on a reduced-body file without a stored consistent
/// inertia.
pub const NO_STORED_CONSISTENT_INERTIA: &str = "the reduced-body file stores no consistent \
     inertia (dataset `inertia/gram`): re-export it with `flexmbs reduce` from an FE model with \
     consistent mass (`mass = \"consistent\"` or a CalculiX deck, solid mesh), or use the FE \
     model file (.toml) as `source`";

/// Hint added to a missing-node-mass error of a reduced-body file that stores the consistent
/// inertia.
pub const USE_STORED_CONSISTENT_INERTIA: &str =
    " (the file stores the consistent inertia: set `inertia = \"consistent\"`)";

/// Message of `inertia = "consistent"` on a beam mesh.
pub const CONSISTENT_NOT_FOR_BEAMS: &str = "inertia = \"consistent\" needs a solid mesh: the \
     consistent beam mass is not block-isotropic (axial and bending shape functions differ); use \
     \"lumped\" for beam meshes";

/// Checks that the FE model `fe` can supply consistent-mass invariants: solid nodes only and a
/// consistent system mass (`mass = "consistent"` or CalculiX matrices), the mass the modes were
/// normalised with. Errors as text.
pub fn check_consistent_source(fe: &FeModel) -> Result<(), String> {
    if has_rotational_dofs(fe) {
        return Err(CONSISTENT_NOT_FOR_BEAMS.to_string());
    }
    if fe.mass != MassKind::Consistent {
        return Err(
            "inertia = \"consistent\" needs the consistent FE mass the modes are computed \
             with: set `mass = \"consistent\"` in [body.reduction] of the FE model file"
                .to_string(),
        );
    }
    Ok(())
}

/// True if any node of the FE mesh has rotational DOFs (beam elements).
pub fn has_rotational_dofs(fe: &FeModel) -> bool {
    fe.prepared.mesh.node_dofs().iter().any(|&c| c >= 6)
}

/// Lumped node rotary inertias of the beam nodes of `fe` (SI, one per node of `body`, which
/// was reduced from `fe`): the rotational 3 x 3 diagonal blocks of the lumped beam mass matrix
/// ([`beam_node_rotary_inertias`]), converted with [`rotary_inertias_to_si`]. `None` without
/// rotational DOFs (solid meshes). Errors as text.
pub fn beam_rotary_inertias(
    fe: &FeModel,
    body: &ReducedBody,
) -> Result<Option<Vec<Matrix3<f64>>>, String> {
    let inertias = beam_node_rotary_inertias(&fe.prepared.mesh, body.nodes.len())?;
    Ok(inertias.map(|i| rotary_inertias_to_si(&i, body.units)))
}

/// The consistent inertia stored in a reduced-body file for the selected modes, in SI: the Gram
/// matrix `gram` (body units, over all `nf` modes of the file) restricted to the 0-based mode
/// columns `cols` ([`flexmbs_core::ffr::restrict_gram`], all modes if `None`) and converted with
/// [`flexmbs_core::ffr::gram_to_si`], to go with `reduced_body_to_si` of the restricted body.
/// Errors as text (a column out of range).
pub fn stored_consistent_inertia(
    gram: &nalgebra::DMatrix<f64>,
    nf: usize,
    cols: Option<&[usize]>,
    units: flexmbs_fe::UnitSystem,
) -> Result<nalgebra::DMatrix<f64>, String> {
    let (g, n) = match cols {
        None => (gram.clone(), nf),
        Some(c) => (
            flexmbs_core::ffr::restrict_gram(gram, nf, c).ok_or_else(|| {
                format!("consistent inertia of {nf} modes cannot take the modes {c:?}")
            })?,
            c.len(),
        ),
    };
    Ok(flexmbs_core::ffr::gram_to_si(&g, n, units))
}

/// The full translational mass matrix of a body in SI (see
/// [`flexmbs_core::ffr::consistent_mass_to_si`]).
pub fn full_mass_to_si(m: &SparseMatrix, body: &ReducedBody) -> SparseMatrix {
    flexmbs_core::ffr::consistent_mass_to_si(m, body.units)
}
