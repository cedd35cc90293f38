//! Dense generalized symmetric eigenproblem `K x = lambda M x` by Cholesky reduction:
//! `M = L L^T`, `C = L^{-1} K L^{-T}`, `C y = lambda y`, `x = L^{-T} y`
//! (crate-stack.md §1.1). The eigenvectors are then M-orthonormal: `X^T M X = I`.

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, MatRef, Par, Side};

use crate::FeError;

/// All eigenpairs of `K x = lambda M x` for dense symmetric `K` and symmetric
/// positive definite `M`, eigenvalues ascending, eigenvectors M-normalised.
///
/// Errors: [`FeError::Invalid`] for non-square or mismatched dimensions or
/// non-finite entries, [`FeError::NotPositiveDefinite`] if `M` is not positive definite,
/// [`FeError::EigenNotConverged`] if the symmetric eigen solver fails.
pub fn dense_generalized(k: MatRef<f64>, m: MatRef<f64>) -> Result<(Vec<f64>, Mat<f64>), FeError> {
    let n = check_pair("dense_generalized", k, m)?;
    for (name, a) in [("K", k), ("M", m)] {
        let scale = a.norm_max();
        if !scale.is_finite() {
            return Err(FeError::Invalid(format!(
                "dense_generalized: {name} has non-finite entries"
            )));
        }
        for j in 0..n {
            for i in 0..j {
                if (a[(i, j)] - a[(j, i)]).abs() > 1e-10 * scale {
                    return Err(FeError::Invalid(format!(
                        "dense_generalized: {name} is not symmetric ({name}[{i},{j}] = {:e}, {name}[{j},{i}] = {:e})",
                        a[(i, j)],
                        a[(j, i)]
                    )));
                }
            }
        }
    }
    if n == 0 {
        return Ok((Vec::new(), Mat::zeros(0, 0)));
    }
    let llt = m
        .llt(Side::Lower)
        .map_err(|e| FeError::NotPositiveDefinite {
            what: "mass matrix M".into(),
            hint: format!(" ({e:?}); the dense generalized eigen solver needs an SPD mass matrix"),
        })?;
    let l = llt.L();
    // C = L^{-1} K L^{-T}: solve L Z = K, then L C^T = Z^T (C symmetric).
    let mut z = k.to_owned();
    solve_lower_triangular_in_place(l, z.as_mut(), Par::Seq);
    let mut c = z.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq);
    // symmetrise against round-off
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let evd = c.self_adjoint_eigen(Side::Lower).map_err(|e| {
        FeError::EigenNotConverged(format!("dense symmetric eigen solver failed: {e:?}"))
    })?;
    let lambda: Vec<f64> = (0..n).map(|i| evd.S()[i]).collect();
    let mut x = evd.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), Par::Seq);
    Ok((lambda, x))
}

/// All eigenpairs of `K x = lambda M x` by dense shift-invert: with `A = K - sigma M = L L^T`
/// (SPD for `sigma` below the spectrum), `C = L^{-1} M L^{-T}` has eigenvalues
/// `mu = 1 / (lambda - sigma)`. The lowest `lambda` (the largest `mu`) are then accurate to
/// about `eps |lambda - sigma|` instead of `eps lambda_max` (the plain Cholesky reduction of M
/// loses near-zero and rigid-body eigenvalues of FE models in the round-off of the stiff end).
/// `M` may be singular; eigenvalues ascending, eigenvectors M-normalised, only pairs with
/// `mu > 0` (finite `lambda`) returned.
pub fn dense_shift_invert(
    k: MatRef<f64>,
    m: MatRef<f64>,
    sigma: f64,
) -> Result<(Vec<f64>, Mat<f64>), FeError> {
    let n = check_pair("dense_shift_invert", k, m)?;
    let a = Mat::from_fn(n, n, |i, j| k[(i, j)] - sigma * m[(i, j)]);
    let llt = a
        .llt(Side::Lower)
        .map_err(|e| FeError::NotPositiveDefinite {
            what: format!("K - sigma M (sigma = {sigma:e})"),
            hint: format!(" ({e:?}); the shift must lie below the lowest eigenvalue"),
        })?;
    let l = llt.L();
    let mut z = m.to_owned();
    solve_lower_triangular_in_place(l, z.as_mut(), Par::Seq);
    let mut c = z.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq);
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let evd = c.self_adjoint_eigen(Side::Lower).map_err(|e| {
        FeError::EigenNotConverged(format!("dense symmetric eigen solver failed: {e:?}"))
    })?;
    let mu_max = (0..n).map(|i| evd.S()[i]).fold(0.0f64, f64::max);
    let mu_min = (0..n).map(|i| evd.S()[i]).fold(0.0f64, f64::min);
    if mu_min < -1e-10 * mu_max {
        return Err(FeError::NotPositiveDefinite {
            what: "mass matrix M".into(),
            hint: " (it has negative eigenvalues; a mass matrix must be positive semidefinite)"
                .into(),
        });
    }
    // ascending lambda = descending mu; keep mu clearly positive
    let keep: Vec<usize> = (0..n)
        .rev()
        .filter(|&i| evd.S()[i] > 1e-14 * mu_max)
        .collect();
    let mut y = Mat::<f64>::zeros(n, keep.len());
    for (c, &i) in keep.iter().enumerate() {
        y.col_mut(c).copy_from(evd.U().col(i));
    }
    solve_upper_triangular_in_place(l.transpose(), y.as_mut(), Par::Seq);
    let lambda: Vec<f64> = keep.iter().map(|&i| sigma + 1.0 / evd.S()[i]).collect();
    for (c, &i) in keep.iter().enumerate() {
        // x^T A x = 1 and x^T M x = mu: normalise to x^T M x = 1
        let s = 1.0 / evd.S()[i].sqrt();
        for r in 0..n {
            y[(r, c)] *= s;
        }
    }
    Ok((lambda, y))
}

/// Checks that `K` and `M` are square and of equal size; returns the size.
fn check_pair(what: &str, k: MatRef<f64>, m: MatRef<f64>) -> Result<usize, FeError> {
    let n = k.nrows();
    if k.ncols() != n || m.nrows() != n || m.ncols() != n {
        return Err(FeError::Invalid(format!(
            "{what}: K is {}x{}, M is {}x{} (both must be square and equal)",
            k.nrows(),
            k.ncols(),
            m.nrows(),
            m.ncols()
        )));
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2-DOF spring-mass chain with the closed-form eigenvalues
    /// lambda = k/m * (3 -+ sqrt(5))/2 for K = k[[2,-1],[-1,1]], M = m I.
    #[test]
    fn two_dof_chain_matches_closed_form() {
        let (kk, mm) = (3.0, 2.0);
        let k = Mat::from_fn(2, 2, |i, j| kk * [[2.0, -1.0], [-1.0, 1.0]][i][j]);
        let m = Mat::from_fn(2, 2, |i, j| if i == j { mm } else { 0.0 });
        let (l, x) = dense_generalized(k.as_ref(), m.as_ref()).unwrap();
        let s5 = 5f64.sqrt();
        assert!((l[0] - kk / mm * (3.0 - s5) / 2.0).abs() < 1e-14);
        assert!((l[1] - kk / mm * (3.0 + s5) / 2.0).abs() < 1e-14);
        let xtmx = x.transpose() * &m * &x;
        for i in 0..2 {
            for j in 0..2 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((xtmx[(i, j)] - e).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn indefinite_mass_is_an_error() {
        let k = Mat::<f64>::identity(2, 2);
        let m = Mat::from_fn(2, 2, |i, j| if i == j { 1.0 } else { 2.0 });
        assert!(matches!(
            dense_generalized(k.as_ref(), m.as_ref()),
            Err(FeError::NotPositiveDefinite { .. })
        ));
        let ns = Mat::from_fn(2, 2, |i, j| (i + 2 * j) as f64);
        assert!(matches!(
            dense_generalized(ns.as_ref(), k.as_ref()),
            Err(FeError::Invalid(_))
        ));
        let r = Mat::<f64>::zeros(2, 3);
        assert!(matches!(
            dense_generalized(k.as_ref(), r.as_ref()),
            Err(FeError::Invalid(_))
        ));
    }
}
