//! The sparse path of [`super::lowest_modes`]: factorization, shift from the spectrum, block
//! Lanczos with locking until every wanted pair has its explicit residual below the tolerance,
//! and the Sturm check proving that no eigenvalue below the cut was missed.

use faer::Mat;

use super::cholesky::SparseCholesky;
use super::lanczos::{BlockLanczos, Outcome, RitzPairs};
use super::ops::apply_mass;
use super::{automatic_shift, shift, shifted_lower, sort_pairs};
use super::{EigenEvent, EigenOptions, EigenSolution};
use crate::{FeError, SparseMatrix};

/// Block Lanczos on `K - sigma M` with the Sturm check (input already validated, `n_modes > 0`).
pub(super) fn lanczos_solution(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<EigenSolution, FeError> {
    let n = k.nrows();
    let nm = opts.n_modes;
    let sigma0 = opts.shift.unwrap_or_else(|| automatic_shift(k, m));
    progress(EigenEvent::Factorizing {
        n,
        nnz: k.compute_nnz(),
    });
    let mut chol = SparseCholesky::factor_shifted_observed(k, m, sigma0, &mut |nnz_l, bytes| {
        progress(EigenEvent::FactorEstimate { nnz_l, bytes })
    })
    .map_err(|e| match e {
        e @ FeError::MemoryRefused { .. } => e,
        _ => FeError::NotPositiveDefinite {
            what: format!("K - sigma M with sigma = {sigma0:e}"),
            hint:
                ": the shift must lie below the lowest eigenvalue and M must be positive definite"
                    .into(),
        },
    })?;
    progress(EigenEvent::Factorized {
        nnz_l: chol.nnz_l(),
    });
    let b = opts.block_size.max(1);
    let (mut sigma, probe) = match opts.shift {
        Some(s) => (s, None),
        None => shift::spectrum_shift(k, m, &mut chol, sigma0, b)?,
    };
    let cap = if opts.max_basis > 0 {
        opts.max_basis
    } else {
        (4 * nm).max(2 * nm + 10 * b)
    };
    let mut need = nm;
    let cap = cap.max(need + 3 * b);
    let mut lz = match probe {
        Some(lz) => lz,
        None => BlockLanczos::new(m, b, cap, 0x5eed_1234)?,
    };
    lz.ensure_capacity(cap);
    let max_steps = 100 + 20 * cap / b;
    let gap_rel = (1e3 * opts.tol).max(1e-6);
    let mut sturm_failures = 0usize;
    let mut slices = 0usize;
    let mut interior = false;
    loop {
        let wanted = need.min(n);
        lz.ensure_capacity(cap.max(wanted + 3 * b));
        let mut cb = |basis, converged| {
            progress(EigenEvent::Iteration {
                basis,
                converged,
                wanted,
            })
        };
        if chol.is_stale() {
            factor_at(k, m, &mut chol, sigma, interior)?;
        }
        let (pairs, outcome) = lz.run(
            &chol,
            sigma,
            wanted,
            wanted + b,
            opts.tol,
            max_steps,
            &mut cb,
        )?;
        if outcome != Outcome::Converged {
            // the round-off floor of this shift (or the budget) is reached: next slice
            slices += 1;
            let moved = slices <= MAX_SLICES
                && next_slice(
                    k,
                    m,
                    &mut chol,
                    &lz,
                    &pairs,
                    (sigma, interior),
                    gap_rel,
                    progress,
                )?
                .map(|s| {
                    // unlock the upper half between the old and the new shift
                    lz.reshift(s - 0.5 * (s - sigma));
                    sigma = s;
                    interior = true;
                })
                .is_some();
            if !moved && (outcome == Outcome::Budget || !lz.distrust_estimates()) {
                return Err(not_converged(&pairs, wanted, max_steps, sigma, opts.tol));
            }
            continue;
        }
        let lam_ritz = &pairs.lambda;
        let nconv = pairs.locked.iter().take_while(|&&l| l).count();
        let mut sturm = None;
        if opts.sturm_check && nm < n {
            // cut at the first relative gap at or after the wanted count
            let scale = |i: usize| {
                lam_ritz[i]
                    .abs()
                    .max(lam_ritz[i - 1].abs())
                    .max(sigma.abs())
            };
            let cut = (nm..lam_ritz.len().min(nconv + 1))
                .find(|&j| lam_ritz[j] - lam_ritz[j - 1] > gap_rel * scale(j));
            let Some(j) = cut else {
                need = nconv.max(need) + b;
                continue;
            };
            let (lo, hi) = (lam_ritz[j - 1], lam_ritz[j]);
            // the storage now holds the L D L^T of the cut: refactored at the loop start if needed
            let found = sturm_count(k, m, &mut chol, lo, hi)?;
            progress(EigenEvent::SturmCheck { expected: j, found });
            if found != j {
                sturm_failures += 1;
                if found < j || sturm_failures > 4 {
                    return Err(FeError::EigenNotConverged(format!(
                        "Sturm check: {j} eigenvalues found below {:e} but the inertia of K - b M gives {found}",
                        lo + 0.5 * (hi - lo)
                    )));
                }
                // missed copies of (repeated) eigenvalues: add fresh directions, ask for more
                lz.inject_random((found - j).max(b));
                need = need.max(found);
                continue;
            }
            sturm = Some((j, found));
        }
        let mut x = pairs.vectors.subcols(0, nm).to_owned();
        m_normalize(m, &mut x);
        let (omega2, residuals, vectors) =
            sort_pairs(lam_ritz[..nm].to_vec(), pairs.estimate[..nm].to_vec(), &x);
        return Ok(EigenSolution {
            omega2,
            vectors,
            residuals,
            sturm,
        });
    }
}

/// At most this many shift moves (slices) after the first shift.
const MAX_SLICES: usize = 24;

/// `K - sigma M` factored into `chol`: `L L^T` below the spectrum, `L D L^T` inside it.
fn factor_at(
    k: &SparseMatrix,
    m: &SparseMatrix,
    chol: &mut SparseCholesky,
    sigma: f64,
    interior: bool,
) -> Result<(), FeError> {
    let a = shifted_lower(k, m, sigma)?;
    if !interior {
        return chol.refactor(&a);
    }
    match chol.factor_ldlt_in_place(&a)? {
        Some(_) => Ok(()),
        None => Err(FeError::EigenNotConverged(format!(
            "L D L^T of K - sigma M singular at the slice shift {sigma:e}"
        ))),
    }
}

/// Spectrum slicing: a new shift in the gap just below the lowest unconverged Ritz value (the
/// midpoint between it and the highest locked eigenvalue below it with a relative gap of at least
/// `gap_rel`, trying lower gaps if needed), factored `L D L^T` into `chol` after its inertia
/// proves that exactly the locked eigenvalues lie below it (none missed between the slices).
/// `None` (with the factor of `sigma` restored) if no such shift above `sigma` exists.
#[allow(clippy::too_many_arguments)]
fn next_slice(
    k: &SparseMatrix,
    m: &SparseMatrix,
    chol: &mut SparseCholesky,
    lz: &BlockLanczos<'_>,
    pairs: &RitzPairs,
    (sigma, interior): (f64, bool),
    gap_rel: f64,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<Option<f64>, FeError> {
    let Some(u) = pairs
        .lambda
        .iter()
        .zip(&pairs.locked)
        .filter(|(_, &l)| !l)
        .map(|(&x, _)| x)
        .find(|x| x.is_finite())
    else {
        return Ok(None);
    };
    let mut below: Vec<f64> = lz
        .locked_lambda()
        .iter()
        .copied()
        .filter(|&x| x < u)
        .collect();
    below.sort_by(f64::total_cmp);
    below.push(u);
    let mut tries = 0;
    for i in (0..below.len() - 1).rev() {
        let (lo, hi) = (below[i], below[i + 1]);
        if hi - lo <= gap_rel.max(1e-3) * hi.abs().max(lo.abs()) {
            continue;
        }
        let cut = lo + 0.5 * (hi - lo);
        if cut <= sigma || tries >= 3 {
            break;
        }
        tries += 1;
        let expected = lz.locked_lambda().iter().filter(|&&x| x < cut).count();
        let inertia = chol.factor_ldlt_in_place(&shifted_lower(k, m, cut)?)?;
        if let Some(inertia) = inertia {
            progress(EigenEvent::SturmCheck {
                expected,
                found: inertia.negative,
            });
            if inertia.near_zero == 0 && inertia.negative == expected {
                return Ok(Some(cut));
            }
        }
    }
    if tries > 0 {
        factor_at(k, m, chol, sigma, interior)?;
    }
    Ok(None)
}

/// The number of eigenvalues below a cut between `lo` and `hi` (inertia of `K - b M`, computed
/// in the factor's storage), trying cuts at 0.5, 0.3 and 0.7 of the gap until the `L D L^T`
/// has no near-zero pivot.
fn sturm_count(
    k: &SparseMatrix,
    m: &SparseMatrix,
    chol: &mut SparseCholesky,
    lo: f64,
    hi: f64,
) -> Result<usize, FeError> {
    for frac in [0.5, 0.3, 0.7] {
        let bound = lo + frac * (hi - lo);
        let kb = shifted_lower(k, m, bound)?;
        if let Some(inertia) = chol.inertia_in_place(&kb)? {
            if inertia.near_zero == 0 {
                return Ok(inertia.negative);
            }
        }
    }
    Err(FeError::EigenNotConverged(format!(
        "Sturm check inconclusive: LDL^T of K - b M singular for cuts between {lo:e} and {hi:e}"
    )))
}

/// Scales the columns of `x` to `x^T M x = 1`.
fn m_normalize(m: &SparseMatrix, x: &mut Mat<f64>) {
    let mut mx = Mat::zeros(x.nrows(), x.ncols());
    apply_mass(m, x.as_ref(), mx.as_mut());
    for j in 0..x.ncols() {
        let s = 1.0 / (x.col(j).transpose() * mx.col(j)).sqrt();
        for i in 0..x.nrows() {
            x[(i, j)] *= s;
        }
    }
}

fn not_converged(
    pairs: &RitzPairs,
    wanted: usize,
    max_steps: usize,
    sigma: f64,
    tol: f64,
) -> FeError {
    let locked = pairs.locked.iter().filter(|&&l| l).count();
    let worst = pairs
        .estimate
        .iter()
        .take(wanted)
        .fold(0.0f64, |a, &b| a.max(b));
    FeError::EigenNotConverged(format!(
        "{locked} of {wanted} wanted pairs converged to {tol:e} after {max_steps} block steps \
         (basis {}, shift {sigma:e}); largest residual estimate {worst:e}",
        pairs.basis
    ))
}
