//! FFR bodies with a consistent mass matrix (seed 000 §6.2 outlook): the reduced body supplies the
//! node positions, modes and modal stiffness, the full FE mass matrix over the translational DOFs
//! supplies the inertia shape integrals through [`FfrInvariants::from_consistent`].

use super::{FfrBody, FfrError, FfrInvariants, RotationParam};
use faer::sparse::Triplet;
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

/// The translational block of a mass matrix numbered node by node with `dofs_per_node[j]` DOFs at
/// node `j` (translations first: 3 for solid nodes, 6 for beam nodes, 0 for unused nodes), as a
/// 3N' x 3N' matrix over `n_nodes >= dofs_per_node.len()` nodes (nodes beyond the list, e.g.
/// rigid-interface nodes appended by a constraint map, get zero rows). Rotational DOFs are dropped.
pub fn translational_mass(
    m: &SparseMatrix,
    dofs_per_node: &[usize],
    n_nodes: usize,
) -> Result<SparseMatrix, FfrError> {
    let total: usize = dofs_per_node.iter().sum();
    if m.nrows() != total || m.ncols() != total {
        return Err(FfrError::DimensionMismatch {
            what: "mass matrix size (sum of DOFs per node)",
            expected: total,
            found: m.nrows().max(m.ncols()),
        });
    }
    if n_nodes < dofs_per_node.len() {
        return Err(FfrError::DimensionMismatch {
            what: "number of body nodes",
            expected: dofs_per_node.len(),
            found: n_nodes,
        });
    }
    // equation -> translational row 3 j + d (None for rotations)
    let mut map = vec![None; total];
    let mut first = 0;
    for (j, &c) in dofs_per_node.iter().enumerate() {
        for d in 0..c.min(3) {
            map[first + d] = Some(3 * j + d);
        }
        first += c;
    }
    let sym = m.symbolic();
    let mut trip = Vec::with_capacity(m.val().len());
    for c in 0..total {
        let Some(tc) = map[c] else { continue };
        for idx in sym.col_range(c) {
            if let Some(tr) = map[sym.row_idx()[idx]] {
                trip.push(Triplet::new(tr, tc, m.val()[idx]));
            }
        }
    }
    SparseMatrix::try_new_from_triplets(3 * n_nodes, 3 * n_nodes, &trip).map_err(|_| {
        FfrError::DimensionMismatch {
            what: "translational mass matrix",
            expected: 3 * n_nodes,
            found: 0,
        }
    })
}
