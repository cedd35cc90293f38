//! FFR bodies with a consistent mass matrix (seed 000 §6.2 outlook): the reduced body supplies the
//! node positions, modes and modal stiffness, the full FE mass matrix over the translational DOFs
//! supplies the inertia shape integrals through [`FfrInvariants::from_consistent`].

use super::{FfrBody, FfrError, FfrInvariants, RotationParam};
use flexmbs_fe::reduction::ReducedBody;
use flexmbs_fe::{SparseMatrix, UnitSystem};

impl FfrBody {
    /// Body of a reduced body whose inertia comes from the consistent mass matrix `m_full`
    /// (3N x 3N over the three translations of the body's N nodes, node order, the same units as
    /// `body`: convert both to SI first with [`super::reduced_body_to_si`] and
    /// [`consistent_mass_to_si`]). The invariants are the projections of `m_full` on the rigid
    /// fields and the modes ([`FfrInvariants::from_consistent`]), so `m_ff = Phi^T M Phi`; the
    /// node masses of `body`, if any, are ignored. Errors if `m_full` has the wrong size or is not
    /// block-isotropic.
    pub fn from_reduced_consistent(
        body: &ReducedBody,
        m_full: &SparseMatrix,
        rotation: RotationParam,
    ) -> Result<Self, FfrError> {
        let inv = FfrInvariants::from_consistent(&body.nodes, m_full, body.modes_t.as_ref())?;
        Self::new(
            inv,
            rotation,
            &body.nodes,
            body.modes_t.as_ref(),
            body.modes_r.as_ref().map(|m| m.as_ref()),
            body.k_red.as_ref(),
        )
    }
}

/// Copy of a mass matrix given in `units` converted to SI (every entry times
/// `units.mass_to_si()`), to go with [`super::reduced_body_to_si`] of the same body.
pub fn consistent_mass_to_si(m: &SparseMatrix, units: UnitSystem) -> SparseMatrix {
    let f = units.mass_to_si();
    let mut out = m.clone();
    if f != 1.0 {
        for v in out.val_mut() {
            *v *= f;
        }
    }
    out
}
