//! The automatic shift of the Lanczos solver, taken from the spectrum.
//!
//! The starting shift `-1e-5 tr(K)/tr(M)` is safe (below the spectrum for any positive
//! semi-definite `K`) but can lie far below it: on a slender beam it is 3.5e5 times the lowest
//! eigenvalue, so the wanted `theta = 1 / (lambda - sigma)` cluster and neither the Lanczos
//! iteration nor a residual on the pair's own scale converges. A few short Lanczos runs move the
//! shift to half the lowest nonzero eigenvalue, below zero: `sigma = -lambda_e / 2`.

use super::cholesky::SparseCholesky;
use super::lanczos::BlockLanczos;
use crate::mechanism::{spectrum_scale, ZERO_ENERGY_TOLERANCE};
use crate::{FeError, SparseMatrix};

/// Block steps of one probe run (basis `PROBE_STEPS` blocks).
const PROBE_STEPS: usize = 3;
/// At most this many shift moves (each a numeric refactorization).
const MAX_MOVES: usize = 4;

/// Moves the automatic shift `sigma0` (factored in `chol`) towards the spectrum and returns the
/// shift `chol` factors on return, with the last probe's Lanczos state if it ran at that shift
/// (the main run continues its Krylov space: no probe work is lost when the shift stays).
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
pub(super) fn spectrum_shift<'a>(
    k: &SparseMatrix,
    m: &'a SparseMatrix,
    chol: &mut SparseCholesky,
    sigma0: f64,
    block: usize,
) -> Result<(f64, Option<BlockLanczos<'a>>), FeError> {
    let zero = ZERO_ENERGY_TOLERANCE * spectrum_scale(k, m);
    let mut sigma = sigma0;
    for round in 0..MAX_MOVES {
        let mut lz = BlockLanczos::new(
            m,
            block,
            (PROBE_STEPS + 1) * block,
            0x5eed_1234 + round as u64,
        )?;
        // a probe that fails (a tiny model exhausting its Krylov space) leaves the shift as is
        let Ok(lam) = lz.probe(chol, sigma, PROBE_STEPS) else {
            return Ok((sigma, None));
        };
        let lambda_e = lam.iter().copied().find(|&l| l > zero);
        let target = lambda_e.map(|l| -(0.5 * l).max(0.1 * zero));
        let Some(target) = target
            .filter(|t| lam.first().is_some_and(|&l| l >= -zero) && t.abs() <= 0.5 * sigma.abs())
        else {
            // no move: the main run continues this probe's Krylov space
            return Ok((sigma, Some(lz)));
        };
        match chol.refactor_shifted(k, m, target) {
            Ok(()) => sigma = target,
            Err(FeError::NotPositiveDefinite { .. }) => {
                chol.refactor_shifted(k, m, sigma)?;
                return Ok((sigma, None));
            }
            Err(e) => return Err(e),
        }
    }
    Ok((sigma, None))
}
