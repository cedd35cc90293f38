//! FFR bodies with a consistent mass matrix (seed 000 §6.2 outlook): the reduced body supplies the
//! node positions, modes and modal stiffness, the full FE mass matrix over the translational DOFs
//! supplies the inertia shape integrals through [`FfrInvariants::from_consistent`]; or the Gram
//! matrix of that projection, as a reduced-body file stores it ([`FfrBody::from_reduced_gram`]).

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

    /// Body of a reduced body whose inertia comes from the Gram matrix `gram` of its node fields
    /// under the consistent mass ([`FfrInvariants::consistent_gram`], `(4 + 3 n_f)` square over
    /// the modes of `body`), as a reduced-body file stores it. `body` and `gram` in the same
    /// units: convert both to SI first with [`super::reduced_body_to_si`] and
    /// [`gram_to_si`]. The node masses of `body`, if any, are ignored.
    pub fn from_reduced_gram(
        body: &ReducedBody,
        gram: &nalgebra::DMatrix<f64>,
        rotation: RotationParam,
    ) -> Result<Self, FfrError> {
        let inv = FfrInvariants::from_gram(gram, body.num_modes())?;
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

/// Copy of the Gram matrix `g` of a body with `nf` modes given in `units`
/// ([`FfrInvariants::consistent_gram`]) converted to SI, to go with [`super::reduced_body_to_si`]
/// of the same body: the node fields scale by `s = [1, L, L, L, c, ..., c]` (`L =
/// units.length_to_si()`, `c = units.mode_to_si()` for all `3 nf` mode columns) and the mass by
/// `Ms = units.mass_to_si()`, so `G_ij *= Ms s_i s_j`. An SI body's matrix is returned unchanged.
pub fn gram_to_si(
    g: &nalgebra::DMatrix<f64>,
    nf: usize,
    units: UnitSystem,
) -> nalgebra::DMatrix<f64> {
    if units == UnitSystem::Si {
        return g.clone();
    }
    let (l, c, ms) = (units.length_to_si(), units.mode_to_si(), units.mass_to_si());
    let scale = |i: usize| match i {
        0 => 1.0,
        1..=3 => l,
        _ => c,
    };
    debug_assert_eq!(g.nrows(), 4 + 3 * nf);
    nalgebra::DMatrix::from_fn(g.nrows(), g.ncols(), |i, j| {
        g[(i, j)] * ms * scale(i) * scale(j)
    })
}

/// The Gram matrix of the modes `cols` (0-based columns of the `nf` modes of `g`, in the order
/// given) of a body's Gram matrix `g` ([`FfrInvariants::consistent_gram`]): the rows and
/// columns `0..4` and, for each direction `k`, `4 + k nf + cols[a]`, as `g` would be computed
/// from the selected modes alone. `None` if `g` is not `(4 + 3 nf)` square or a column is out
/// of range.
pub fn restrict_gram(
    g: &nalgebra::DMatrix<f64>,
    nf: usize,
    cols: &[usize],
) -> Option<nalgebra::DMatrix<f64>> {
    if g.nrows() != 4 + 3 * nf || g.ncols() != g.nrows() || cols.iter().any(|&c| c >= nf) {
        return None;
    }
    let m = cols.len();
    let index = |i: usize| {
        if i < 4 {
            i
        } else {
            let (k, a) = ((i - 4) / m, (i - 4) % m);
            4 + k * nf + cols[a]
        }
    };
    let size = 4 + 3 * m;
    Some(nalgebra::DMatrix::from_fn(size, size, |i, j| {
        g[(index(i), index(j))]
    }))
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
