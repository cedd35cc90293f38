//! The sparse path of [`super::lowest_modes`]: factorization, shift from the spectrum, block
//! Lanczos with locking until every wanted pair has its explicit residual below the tolerance,
//! and the Sturm check proving that no eigenvalue below the cut was missed.

use faer::Mat;

use super::cholesky::SparseCholesky;
use super::lanczos::{BlockLanczos, Outcome, RitzPairs};
use super::ops::apply_mass;
use super::ordering::FillOrdering;
use super::{automatic_shift, shift, sort_pairs};
use super::{EigenEvent, EigenOptions, EigenSolution};
use crate::{FeError, SparseMatrix};

/// Block Lanczos on `K - sigma M` with the Sturm check (input already validated, `n_modes > 0`).
/// `ordering`: the fill-reducing ordering of `K - s M` if already computed; `k_factor`: the
/// factorization of `K` (shift 0) to start from, if the caller has it.
pub(super) fn lanczos_solution(
    k: &SparseMatrix,
    m: &SparseMatrix,
    opts: &EigenOptions,
    ordering: Option<FillOrdering>,
    k_factor: Option<SparseCholesky>,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<EigenSolution, FeError> {
    let n = k.nrows();
    let nm = opts.n_modes;
    let b = opts.block_size.max(1);
    let (mut chol, sigma, probe) = match k_factor {
        Some(chol) => (chol, 0.0, None),
        None => start(k, m, opts, b, ordering, progress)?,
    };
    let sigma0 = sigma;
    let mut need = nm;
    let cap = basis_cap(opts).max(need + 3 * b);
    // the probe's Krylov space at the final shift is the start of the main run
    let mut lz = match probe {
        Some(lz) => lz,
        None => BlockLanczos::new(m, b, cap, 0x5eed_1234)?,
    };
    lz.ensure_capacity(cap);
    let max_steps = 100 + 20 * cap / b;
    let gap_rel = (1e3 * opts.tol).max(1e-6);
    let mut sturm_failures = 0usize;
    let mut slices = 0usize;
    // the current shift and whether it lies inside the spectrum (L D L^T)
    let mut shift = (sigma, false);
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
        let sigma = shift.0;
        if chol.is_stale() {
            factor_at(k, m, &mut chol, sigma, shift.1)?;
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
                && move_shift(
                    k, m, &mut chol, &mut lz, &pairs, &mut shift, gap_rel, progress,
                )?;
            if !moved && (outcome == Outcome::Budget || !lz.distrust_estimates()) {
                return Err(not_converged(&pairs, wanted, max_steps, shift.0, opts.tol));
            }
            continue;
        }
        let mut sturm = None;
        if opts.sturm_check && nm < n {
            let counts = (&mut need, &mut sturm_failures);
            match sturm_step(
                k,
                m,
                &mut chol,
                &mut lz,
                &pairs,
                (nm, b),
                (sigma, gap_rel),
                counts,
                progress,
            )? {
                Some(s) => sturm = Some(s),
                None => continue,
            }
        }
        return Ok(solution(m, &pairs, nm, sturm, sigma0));
    }
}

/// The Sturm check of a converged run ([`sturm_at_gap`]): `Some((below, found))` if it passes;
/// `None` if the run must go on (no gap yet: `need` grows by a block; missed copies of repeated
/// eigenvalues: fresh random directions and `need` raised to the count); an error if the count
/// is below the pairs found or keeps failing.
#[allow(clippy::too_many_arguments)]
fn sturm_step(
    k: &SparseMatrix,
    m: &SparseMatrix,
    chol: &mut SparseCholesky,
    lz: &mut BlockLanczos<'_>,
    pairs: &RitzPairs,
    (nm, b): (usize, usize),
    (sigma, gap_rel): (f64, f64),
    (need, failures): (&mut usize, &mut usize),
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<Option<(usize, usize)>, FeError> {
    let lam = &pairs.lambda;
    let nconv = pairs.locked.iter().take_while(|&&l| l).count();
    // the storage then holds the L D L^T of the cut: refactored before the next solve
    lz.release_mass_products();
    let (below, found) = match sturm_at_gap(k, m, chol, lam, (nm, nconv), sigma, gap_rel)? {
        Cut::NoGap => {
            *need = nconv.max(*need) + b;
            return Ok(None);
        }
        Cut::Counted { below, found } => (below, found),
    };
    progress(EigenEvent::SturmCheck {
        expected: below,
        found,
    });
    if found == below {
        return Ok(Some((below, found)));
    }
    *failures += 1;
    if found < below || *failures > 4 {
        return Err(FeError::EigenNotConverged(format!(
            "Sturm check: {below} eigenvalues found below the cut after {:e} but the inertia of \
             K - b M gives {found}",
            lam[below - 1]
        )));
    }
    // missed copies of (repeated) eigenvalues: add fresh directions, ask for more
    lz.inject_random((found - below).max(b));
    *need = (*need).max(found);
    Ok(None)
}

/// The basis cap: `max_basis`, or `max(4 n_modes, 2 n_modes + 10 block)` if 0.
fn basis_cap(opts: &EigenOptions) -> usize {
    if opts.max_basis > 0 {
        opts.max_basis
    } else {
        (4 * opts.n_modes).max(2 * opts.n_modes + 10 * opts.block_size.max(1))
    }
}

/// The factor and shift the iteration starts with, and the Lanczos state of a shift probe that
/// ran at that shift: the given shift; or `sigma = 0` for a supported model whose `K` factors
/// ([`EigenOptions::supported`]); or the shift from the spectrum ([`shift::spectrum_shift`]),
/// starting at [`automatic_shift`].
fn start<'a>(
    k: &SparseMatrix,
    m: &'a SparseMatrix,
    opts: &EigenOptions,
    block: usize,
    ordering: Option<FillOrdering>,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<(SparseCholesky, f64, Option<BlockLanczos<'a>>), FeError> {
    if let Some(s) = opts.shift {
        return Ok((first_factor(k, m, &[s], ordering, progress)?.0, s, None));
    }
    let safe = automatic_shift(k, m);
    let shifts: &[f64] = if opts.supported {
        &[0.0, safe]
    } else {
        &[safe]
    };
    let (mut chol, used) = first_factor(k, m, shifts, ordering, progress)?;
    if opts.supported && used == 0 {
        return Ok((chol, 0.0, None));
    }
    let (sigma, probe) = shift::spectrum_shift(k, m, &mut chol, safe, block)?;
    Ok((chol, sigma, probe))
}

/// The leading `nm` pairs, M-normalised, as the solution.
fn solution(
    m: &SparseMatrix,
    pairs: &RitzPairs,
    nm: usize,
    sturm: Option<(usize, usize)>,
    start_shift: f64,
) -> EigenSolution {
    let mut x = pairs.vectors.subcols(0, nm).to_owned();
    m_normalize(m, &mut x);
    let (omega2, residuals, vectors) = sort_pairs(
        pairs.lambda[..nm].to_vec(),
        pairs.estimate[..nm].to_vec(),
        &x,
    );
    EigenSolution {
        omega2,
        vectors,
        residuals,
        sturm,
        start_shift,
    }
}

/// Factorization of `K - s M` for the first shift `s` of `shifts` at which it is positive
/// definite ([`SparseCholesky::factor_first_definite`]), with its progress events.
fn first_factor(
    k: &SparseMatrix,
    m: &SparseMatrix,
    shifts: &[f64],
    ordering: Option<FillOrdering>,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<(SparseCholesky, usize), FeError> {
    let sigma0 = shifts.last().copied().unwrap_or(0.0);
    progress(EigenEvent::Factorizing {
        n: k.nrows(),
        nnz: k.compute_nnz(),
    });
    let chol =
        SparseCholesky::factor_first_definite(k, m, shifts, ordering, &mut |nnz_l, bytes| {
            progress(EigenEvent::FactorEstimate { nnz_l, bytes })
        })
        .map_err(|e| {
            match e {
        e @ FeError::MemoryRefused { .. } => e,
        _ => FeError::NotPositiveDefinite {
            what: format!("K - sigma M with sigma = {sigma0:e}"),
            hint:
                ": the shift must lie below the lowest eigenvalue and M must be positive definite"
                    .into(),
        },
    }
        })?;
    progress(EigenEvent::Factorized {
        nnz_l: chol.0.nnz_l(),
    });
    Ok(chol)
}

/// Moves the shift into the spectrum ([`next_slice`]) and prepares the Lanczos state for it
/// ([`BlockLanczos::reshift`]: the locked pairs in the upper half between the old and the new
/// shift are unlocked); `false` if there is no new shift.
#[allow(clippy::too_many_arguments)]
fn move_shift(
    k: &SparseMatrix,
    m: &SparseMatrix,
    chol: &mut SparseCholesky,
    lz: &mut BlockLanczos<'_>,
    pairs: &RitzPairs,
    shift: &mut (f64, bool),
    gap_rel: f64,
    progress: &mut dyn FnMut(EigenEvent),
) -> Result<bool, FeError> {
    let Some(s) = next_slice(k, m, chol, lz, pairs, *shift, gap_rel, progress)? else {
        return Ok(false);
    };
    lz.reshift(s - 0.5 * (s - shift.0));
    *shift = (s, true);
    Ok(true)
}

/// Result of [`sturm_at_gap`].
enum Cut {
    /// No relative gap among the converged pairs at or after the wanted count.
    NoGap,
    /// `below` pairs lie below the cut, the inertia of `K - b M` counts `found` eigenvalues.
    Counted { below: usize, found: usize },
}

/// The Sturm check at the first relative gap (`> gap_rel` times the scale) at or after the
/// `wanted` count among the `nconv` leading converged pairs of `lam` (the value after them is an
/// upper bound of the next eigenvalue).
fn sturm_at_gap(
    k: &SparseMatrix,
    m: &SparseMatrix,
    chol: &mut SparseCholesky,
    lam: &[f64],
    (wanted, nconv): (usize, usize),
    sigma: f64,
    gap_rel: f64,
) -> Result<Cut, FeError> {
    let scale = |i: usize| lam[i].abs().max(lam[i - 1].abs()).max(sigma.abs());
    let cut =
        (wanted..lam.len().min(nconv + 1)).find(|&j| lam[j] - lam[j - 1] > gap_rel * scale(j));
    let Some(j) = cut else {
        return Ok(Cut::NoGap);
    };
    let found = sturm_count(k, m, chol, lam[j - 1], lam[j])?;
    Ok(Cut::Counted { below: j, found })
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
    if !interior {
        return chol.refactor_shifted(k, m, sigma);
    }
    match chol.factor_ldlt_shifted_in_place(k, m, sigma)? {
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
        let inertia = chol.factor_ldlt_shifted_in_place(k, m, cut)?;
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
        if let Some(inertia) = chol.inertia_shifted_in_place(k, m, bound)? {
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
