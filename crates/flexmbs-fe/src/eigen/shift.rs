//! The automatic shift of the Lanczos solver, taken from the spectrum.
//!
//! The starting shift `-1e-5 tr(K)/tr(M)` is safe (below the spectrum for any positive
//! semi-definite `K`) but can lie far below it: on a slender beam it is 3.5e5 times the lowest
//! eigenvalue, so the wanted `theta = 1 / (lambda - sigma)` cluster and neither the Lanczos
//! iteration nor a residual on the pair's own scale converges. A few short Lanczos runs move the
//! shift to half the lowest nonzero eigenvalue, below zero: `sigma = -lambda_e / 2`.

use super::cholesky::SparseCholesky;
use super::lanczos::BlockLanczos;
use super::shifted_lower;
use crate::mechanism::{spectrum_scale, ZERO_ENERGY_TOLERANCE};
use crate::{FeError, SparseMatrix};

/// Block steps of one probe run (basis `PROBE_STEPS` blocks).
const PROBE_STEPS: usize = 3;
/// At most this many shift moves (each a numeric refactorization).
const MAX_MOVES: usize = 4;

/// Moves the automatic shift `sigma0` (factored in `chol`) towards the spectrum and returns the
/// shift `chol` factors on return.
///
/// Each round runs a short block Lanczos at the current shift; its Ritz values are upper bounds
/// of the eigenvalues (Cauchy interlacing: the `i`-th lowest Ritz value is at least the `i`-th
/// lowest eigenvalue). With `lambda_e` the lowest Ritz value above the zero-energy level
/// (`ZERO_ENERGY_TOLERANCE` times [`spectrum_scale`], the rigid-body and round-off zeros), the new
/// shift is `-max(lambda_e / 2, zero level / 10)`: negative, so `K - sigma M` stays positive
/// definite for any positive semi-definite `K` (free-free bodies and mechanisms included), and
/// the refactorization proves it (a failing one restores the previous shift). Rounds stop when
/// the shift no longer halves, after [`MAX_MOVES`] moves, or when a Ritz value lies below minus
/// the zero level (`K` indefinite: the safe starting shift is kept).
pub(super) fn spectrum_shift(
    k: &SparseMatrix,
    m: &SparseMatrix,
    chol: &mut SparseCholesky,
    sigma0: f64,
    block: usize,
) -> Result<f64, FeError> {
    let zero = ZERO_ENERGY_TOLERANCE * spectrum_scale(k, m);
    let mut sigma = sigma0;
    for round in 0..MAX_MOVES {
        // a probe that fails (a tiny model exhausting its Krylov space) leaves the shift as is
        let Ok(lam) = probe_ritz_values(m, chol, sigma, block, round as u64) else {
            break;
        };
        if lam.first().is_none_or(|&l| l < -zero) {
            break;
        }
        let Some(&lambda_e) = lam.iter().find(|&&l| l > zero) else {
            break;
        };
        let target = -(0.5 * lambda_e).max(0.1 * zero);
        if target.abs() > 0.5 * sigma.abs() {
            break;
        }
        match chol.refactor(&shifted_lower(k, m, target)?) {
            Ok(()) => sigma = target,
            Err(FeError::NotPositiveDefinite { .. }) => {
                chol.refactor(&shifted_lower(k, m, sigma)?)?;
                break;
            }
            Err(e) => return Err(e),
        }
    }
    Ok(sigma)
}

/// Ritz values `lambda = sigma + 1 / theta` (ascending) of a short block Lanczos run.
fn probe_ritz_values(
    m: &SparseMatrix,
    chol: &SparseCholesky,
    sigma: f64,
    block: usize,
    seed: u64,
) -> Result<Vec<f64>, FeError> {
    let n = m.nrows();
    let cap = (PROBE_STEPS + 1) * block;
    let mut lz = BlockLanczos::new(m, block, cap, 0x5_4ee5_0000 + seed)?;
    let report = (PROBE_STEPS * block).min(n);
    let (pairs, _) = lz.run(
        chol,
        sigma,
        report,
        report,
        1e-3,
        PROBE_STEPS,
        &mut |_, _| {},
    )?;
    let mut lam: Vec<f64> = pairs
        .lambda
        .iter()
        .copied()
        .filter(|l| l.is_finite())
        .collect();
    lam.sort_by(f64::total_cmp);
    Ok(lam)
}
