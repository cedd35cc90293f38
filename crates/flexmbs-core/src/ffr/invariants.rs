//! Inertia shape integrals (invariants) of an FFR body, seed 000 (2.53)-(2.69), seed 001 (2.35)-(2.40).
//!
//! All invariants are entries of one Gram matrix. With the scalar node fields
//! `f = [1, x_1, x_2, x_3, Phi_1, Phi_2, Phi_3]` (`x_k` = component `k` of the undeformed node
//! positions `u0`, `Phi_k` = the `N x n_f` rows of component `k` of the translational modes),
//! and a scalar node mass operator `m` (`N x N`: `diag(m_j)` for lumped masses, the consistent
//! mass matrix for consistent masses), `G = f^T m f` holds
//!
//! | invariant | entry of `G` | seed 000 |
//! |---|---|---|
//! | `i1` = mass | `1^T m 1` | (2.47) |
//! | `i_bar` = sum m u0 | `1^T m x_k` | `I_1` (2.53) |
//! | `s_bar` = sum m Phi | `1^T m Phi_k` | (2.54) |
//! | `i_kl` = sum m x_k x_l | `x_k^T m x_l` | (2.65) |
//! | `i_kl_bar` = sum m x_k Phi_l | `x_k^T m Phi_l` | (2.65) |
//! | `s_kl` = sum m Phi_k^T Phi_l | `Phi_k^T m Phi_l` | (2.65) |
//! | `m_ff` = S_11 + S_22 + S_33 | | (2.69) |
//!
//! For a consistent 3N x 3N mass matrix `M` (3 translational DOFs per node, node order),
//! `x^T m y = 1/3 sum_d L_d(x)^T M L_d(y)` where `L_d(x)` is the 3N vector with the node field
//! `x` in direction `d`: e.g. `i1 = 1/3 trace(T^T M T)` with the 3N x 3 matrix of rigid
//! translations `T`, `s_bar = T^T M Phi`, `m_ff = Phi^T M Phi`. This is exact because the
//! consistent mass of a continuum has isotropic node blocks `M_ij = m_ij I_3`, which is checked.

use super::FfrError;
use flexmbs_fe::SparseMatrix;
use nalgebra::{DMatrix, Matrix3, Vector3};
use std::collections::BTreeMap;

/// Relative tolerance of the isotropy check of a consistent mass matrix.
pub const ISOTROPY_TOLERANCE: f64 = 1e-9;

/// The constant inertia shape integrals of an FFR body (computed once).
#[derive(Debug, Clone, PartialEq)]
pub struct FfrInvariants {
    /// Number of modes n_f.
    pub nf: usize,
    /// Total mass `I1 = sum m_j`, seed 000 (2.47).
    pub i1: f64,
    /// First moment of mass of the undeformed body `I_bar = sum m_j u0_j`, seed 000 `I_1` (2.53).
    pub i_bar: Vector3<f64>,
    /// Modal first moments `S_bar = sum m_j Phi_j` (3 x n_f), seed 000 (2.54).
    pub s_bar: DMatrix<f64>,
    /// Second moments `I_kl = sum m_j x_k^j x_l^j`, seed 000 (2.65).
    pub i_kl: Matrix3<f64>,
    /// `I_kl_bar = sum m_j x_k^j Phi_l^j`, row `3 k + l` (1 x n_f each, 9 x n_f), seed 000 (2.65).
    pub i_kl_bar: DMatrix<f64>,
    /// `S_kl = sum m_j Phi_k^jT Phi_l^j` (n_f x n_f), index `3 k + l`, seed 000 (2.65);
    /// `S_lk = S_kl^T`.
    pub s_kl: Vec<DMatrix<f64>>,
    /// Modal mass `m_ff = S_11 + S_22 + S_33`, seed 000 (2.69) (= (2.18) `Phi^T M Phi`).
    pub m_ff: DMatrix<f64>,
}

/// Scalar node fields `[1, x1, x2, x3, Phi_1, Phi_2, Phi_3]` as an N x (4 + 3 n_f) matrix.
fn node_fields(u0: &[[f64; 3]], modes_t: faer::MatRef<'_, f64>) -> Result<DMatrix<f64>, FfrError> {
    let n = u0.len();
    if modes_t.nrows() != 3 * n {
        return Err(FfrError::DimensionMismatch {
            what: "rows of modes_t (3 x nodes)",
            expected: 3 * n,
            found: modes_t.nrows(),
        });
    }
    let nf = modes_t.ncols();
    let mut f = DMatrix::zeros(n, 4 + 3 * nf);
    for (j, x) in u0.iter().enumerate() {
        f[(j, 0)] = 1.0;
        for k in 0..3 {
            if !x[k].is_finite() {
                return Err(FfrError::NonFinite {
                    what: "node position",
                });
            }
            f[(j, 1 + k)] = x[k];
            for a in 0..nf {
                let v = modes_t[(3 * j + k, a)];
                if !v.is_finite() {
                    return Err(FfrError::NonFinite { what: "mode shape" });
                }
                f[(j, 4 + k * nf + a)] = v;
            }
        }
    }
    Ok(f)
}

impl FfrInvariants {
    /// Invariants of a body with lumped node masses (seed 000 §2.4.6): `u0` node positions,
    /// `masses` one per node (>= 0), `modes_t` the 3N x n_f translational modes.
    pub fn from_lumped(
        u0: &[[f64; 3]],
        masses: &[f64],
        modes_t: faer::MatRef<'_, f64>,
    ) -> Result<Self, FfrError> {
        if masses.len() != u0.len() {
            return Err(FfrError::DimensionMismatch {
                what: "node masses",
                expected: u0.len(),
                found: masses.len(),
            });
        }
        for (node, &mass) in masses.iter().enumerate() {
            if !(mass.is_finite() && mass >= 0.0) {
                return Err(FfrError::InvalidMass { node, mass });
            }
        }
        let f = node_fields(u0, modes_t)?;
        let mut mf = f.clone();
        for (j, &m) in masses.iter().enumerate() {
            mf.row_mut(j).scale_mut(m);
        }
        Self::from_gram(&(f.transpose() * mf), modes_t.ncols())
    }

    /// Invariants of a body with a consistent mass matrix `m_full` (3N x 3N over the three
    /// translational DOFs of every node, node order; seed 000 §6.2): every invariant is the
    /// projection `1/3 sum_d L_d(x)^T M L_d(y)` described in the module documentation
    /// ([`Self::consistent_gram`], then [`Self::from_gram`]). Errors if `M` is not
    /// block-isotropic (`M_ij = m_ij I_3`) to [`ISOTROPY_TOLERANCE`].
    pub fn from_consistent(
        u0: &[[f64; 3]],
        m_full: &SparseMatrix,
        modes_t: faer::MatRef<'_, f64>,
    ) -> Result<Self, FfrError> {
        Self::from_gram(
            &Self::consistent_gram(u0, m_full, modes_t)?,
            modes_t.ncols(),
        )
    }

    /// The Gram matrix `G = f^T m f` of the scalar node fields `f = [1, x_1, x_2, x_3, Phi_1,
    /// Phi_2, Phi_3]` (module documentation) under the scalar node mass operator `m` of a
    /// consistent mass matrix `m_full` (3N x 3N over the three translational DOFs of every node,
    /// node order, `M_ij = m_ij I_3`): a `(4 + 3 n_f)` square matrix, in the units of its inputs.
    /// It holds every inertia shape integral ([`Self::from_gram`]), so a reduced-body file can
    /// store it instead of the FE mass matrix. Errors if `M` has the wrong size, a non-finite
    /// entry or is not block-isotropic to [`ISOTROPY_TOLERANCE`].
    pub fn consistent_gram(
        u0: &[[f64; 3]],
        m_full: &SparseMatrix,
        modes_t: faer::MatRef<'_, f64>,
    ) -> Result<DMatrix<f64>, FfrError> {
        let n = u0.len();
        if m_full.nrows() != 3 * n || m_full.ncols() != 3 * n {
            return Err(FfrError::DimensionMismatch {
                what: "consistent mass matrix size (3 x nodes)",
                expected: 3 * n,
                found: m_full.nrows().max(m_full.ncols()),
            });
        }
        let f = node_fields(u0, modes_t)?;
        // scalar node blocks: diagonal entries per direction, off-diagonal direction coupling;
        // ordered, so that `G` is the same bitwise in every run
        let mut blocks: BTreeMap<(usize, usize), [f64; 3]> = BTreeMap::new();
        let mut max_abs = 0.0f64;
        let mut max_cross = (0.0f64, 0usize, 0usize);
        let sym = m_full.symbolic();
        let val = m_full.val();
        for c in 0..3 * n {
            for idx in sym.col_range(c) {
                let r = sym.row_idx()[idx];
                let v = val[idx];
                if !v.is_finite() {
                    return Err(FfrError::NonFinite {
                        what: "consistent mass entry",
                    });
                }
                max_abs = max_abs.max(v.abs());
                if r % 3 == c % 3 {
                    blocks.entry((r / 3, c / 3)).or_insert([0.0; 3])[r % 3] += v;
                } else if v.abs() > max_cross.0 {
                    max_cross = (v.abs(), r, c);
                }
            }
        }
        let tol = ISOTROPY_TOLERANCE * max_abs;
        if max_cross.0 > tol {
            return Err(FfrError::NonIsotropicMass {
                row: max_cross.1,
                col: max_cross.2,
                deviation: max_cross.0,
            });
        }
        let mut mf = DMatrix::zeros(n, f.ncols());
        for (&(i, j), d) in &blocks {
            let mean = (d[0] + d[1] + d[2]) / 3.0;
            for (k, &dk) in d.iter().enumerate() {
                if (dk - mean).abs() > tol {
                    return Err(FfrError::NonIsotropicMass {
                        row: 3 * i + k,
                        col: 3 * j + k,
                        deviation: (dk - mean).abs(),
                    });
                }
            }
            for col in 0..f.ncols() {
                mf[(i, col)] += mean * f[(j, col)];
            }
        }
        Ok(f.transpose() * mf)
    }

    /// The invariants of a body with `nf` modes from its Gram matrix `G = f^T m f`
    /// (`(4 + 3 nf)` square; rows and columns in the order `1, x_1, x_2, x_3`, then the `nf`
    /// modes of `Phi_1`, of `Phi_2` and of `Phi_3`, see the module documentation): `G` is
    /// symmetrized, then split into the named invariants (seed 000 (2.47), (2.53), (2.54), (2.65),
    /// (2.69)). [`Self::from_lumped`] and [`Self::from_consistent`] build `G` from node masses or
    /// a consistent mass matrix; a reduced-body file stores the consistent one. Errors if `G` has
    /// the wrong size, a non-finite entry or a total mass `G[0, 0]` that is not positive.
    pub fn from_gram(g: &DMatrix<f64>, nf: usize) -> Result<Self, FfrError> {
        let size = 4 + 3 * nf;
        if g.nrows() != size || g.ncols() != size {
            return Err(FfrError::DimensionMismatch {
                what: "Gram matrix size (4 + 3 x modes)",
                expected: size,
                found: if g.nrows() != size {
                    g.nrows()
                } else {
                    g.ncols()
                },
            });
        }
        if g.iter().any(|v| !v.is_finite()) {
            return Err(FfrError::NonFinite {
                what: "Gram matrix",
            });
        }
        let g = 0.5 * (g + g.transpose());
        let i1 = g[(0, 0)];
        if i1.is_nan() || i1 <= 0.0 {
            return Err(FfrError::InvalidMass {
                node: usize::MAX,
                mass: i1,
            });
        }
        let phi = |k: usize| 4 + k * nf;
        let i_bar = Vector3::new(g[(0, 1)], g[(0, 2)], g[(0, 3)]);
        let mut s_bar = DMatrix::zeros(3, nf);
        let mut i_kl = Matrix3::zeros();
        let mut i_kl_bar = DMatrix::zeros(9, nf);
        let mut s_kl = Vec::with_capacity(9);
        for k in 0..3 {
            for a in 0..nf {
                s_bar[(k, a)] = g[(0, phi(k) + a)];
            }
            for l in 0..3 {
                i_kl[(k, l)] = g[(1 + k, 1 + l)];
                for a in 0..nf {
                    i_kl_bar[(3 * k + l, a)] = g[(1 + k, phi(l) + a)];
                }
                s_kl.push(g.view((phi(k), phi(l)), (nf, nf)).into_owned());
            }
        }
        let m_ff = &s_kl[0] + &s_kl[4] + &s_kl[8];
        Ok(Self {
            nf,
            i1,
            i_bar,
            s_bar,
            i_kl,
            i_kl_bar,
            s_kl,
            m_ff,
        })
    }

    /// `S_kl` (0-based `k`, `l`).
    pub fn s(&self, k: usize, l: usize) -> &DMatrix<f64> {
        &self.s_kl[3 * k + l]
    }

    /// Largest absolute difference of all invariants to `other` (for cross-checks).
    pub fn max_abs_difference(&self, other: &Self) -> f64 {
        let mut d = (self.i1 - other.i1).abs();
        d = d.max((self.i_bar - other.i_bar).abs().max());
        d = d.max((&self.s_bar - &other.s_bar).abs().max());
        d = d.max((self.i_kl - other.i_kl).abs().max());
        d = d.max((&self.i_kl_bar - &other.i_kl_bar).abs().max());
        for (a, b) in self.s_kl.iter().zip(&other.s_kl) {
            d = d.max((a - b).abs().max());
        }
        d.max((&self.m_ff - &other.m_ff).abs().max())
    }
}
