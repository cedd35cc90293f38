//! Factorizations, orderings and products of the eigen solver: solves and inertia against
//! separate factorizations and faer, orderings against METIS and AMD.

use super::*;

/// SparseCholesky solves a multi-RHS system of the grid matrix to 1e-12 relative residual
/// (METIS path, n = 3000) and an SPD 3x3 (AMD path) exactly.
#[test]
fn sparse_cholesky_solves_multi_rhs() {
    let (k, m) = grid_model(10, false);
    let a = shifted(&k, &m, -0.5).unwrap();
    let chol = SparseCholesky::factor(&a).unwrap();
    assert_eq!(chol.dim(), 3000);
    let x0 = Mat::from_fn(3000, 3, |i, j| ((i * 7 + j * 13) % 11) as f64 - 5.0);
    let b = &a * &x0;
    let mut x = b.clone();
    chol.solve_in_place(x.as_mut());
    let err = (&x - &x0).norm_max() / x0.norm_max();
    assert!(err < 1e-12, "solve error {err}");
    let small = sparse(
        3,
        &[
            Triplet::new(0, 0, 4.0),
            Triplet::new(0, 1, 1.0),
            Triplet::new(1, 0, 1.0),
            Triplet::new(1, 1, 3.0),
            Triplet::new(2, 2, 2.0),
        ],
    );
    let c = SparseCholesky::factor(&small).unwrap();
    let mut r = Mat::from_fn(3, 1, |i, _| [5.0, 4.0, 2.0][i]);
    c.solve_in_place(r.as_mut());
    for i in 0..3 {
        assert!((r[(i, 0)] - 1.0).abs() < 1e-15);
    }
    // indefinite -> error
    let indef = sparse(
        2,
        &[
            Triplet::new(0, 0, 1.0),
            Triplet::new(0, 1, 2.0),
            Triplet::new(1, 0, 2.0),
            Triplet::new(1, 1, 1.0),
        ],
    );
    assert!(matches!(
        SparseCholesky::factor(&indef),
        Err(FeError::NotPositiveDefinite { .. })
    ));
}

/// METIS ordering is used (not the AMD fallback) for the grid matrix, is a valid
/// permutation, and gives less fill than faer's AMD (crate-stack.md §2.2).
#[test]
fn metis_ordering_is_valid_and_reduces_fill() {
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
    let (k, _) = grid_model(12, false);
    let p = super::ordering::metis_nested_dissection(&k).expect("METIS must succeed");
    let (fwd, inv) = p.as_ref().arrays();
    assert_eq!(fwd.len(), k.nrows());
    assert!((0..fwd.len()).all(|i| inv[fwd[i]] == i));
    let metis = SparseCholesky::factor(&k).unwrap().nnz_l();
    let amd = factorize_symbolic_cholesky(
        k.symbolic(),
        faer::Side::Lower,
        SymmetricOrdering::Amd,
        Default::default(),
    )
    .unwrap()
    .len_val();
    println!("nnz(L): METIS {metis}, AMD {amd}");
    assert!(metis < amd, "METIS {metis} vs AMD {amd}");
}

/// The lower triangle of `K - sigma M` gives the same factor as the full matrix (the
/// factorization reads the lower triangle only), and the Sturm check's `L D L^T` in the factor's
/// own storage gives the inertia of a separate factorization; the factor is restored by
/// `refactor` bit for bit.
#[test]
fn lower_triangle_factor_and_in_place_inertia() {
    let (k, m) = grid_model(4, false);
    let n = k.nrows();
    let sigma = -1.0;
    let full = shifted(&k, &m, sigma).unwrap();
    let lower = shifted_lower(&k, &m, sigma).unwrap();
    assert!(lower.compute_nnz() < full.compute_nnz());
    for j in 0..full.ncols() {
        let rows = full.row_idx_of_col_raw(j);
        let first = rows.partition_point(|&i| i < j);
        assert_eq!(&rows[first..], lower.row_idx_of_col_raw(j));
        assert_eq!(&full.val_of_col(j)[first..], lower.val_of_col(j));
    }
    let mut chol = SparseCholesky::factor(&full).unwrap();
    let mut x = Mat::<f64>::from_fn(n, 1, |i, _| (i as f64).sin());
    let reference = x.clone();
    chol.solve_in_place(x.as_mut());
    for cut in [0.5, 3.0, 9.0] {
        let expected = ldlt_inertia(&shifted(&k, &m, cut).unwrap())
            .unwrap()
            .unwrap();
        let in_place = chol
            .inertia_in_place(&shifted_lower(&k, &m, cut).unwrap())
            .unwrap()
            .unwrap();
        assert_eq!(in_place, expected);
        assert!(chol.is_stale());
    }
    chol.refactor(&lower).unwrap();
    let mut y = reference.clone();
    chol.solve_in_place(y.as_mut());
    assert_eq!(x, y);
}

/// The factor of `K - sigma M` on the ordered lower pattern (identity ordering in faer, the
/// ordering applied by the solve) has the size of faer's factor of the full matrix with the same
/// ordering and solves to round-off like it; the in-place Sturm counts and the refactorization on
/// that pattern agree with separate factorizations (lumped `M`: patterns of `K` and `M` differ).
#[test]
fn ordered_pattern_factor_matches_faer_ordering() {
    for lumped in [false, true] {
        let (k, m) = grid_model(5, lumped);
        let n = k.nrows();
        let sigma = -1.0;
        let full = shifted(&k, &m, sigma).unwrap();
        let reference = SparseCholesky::factor(&full).unwrap();
        let mut chol =
            SparseCholesky::factor_shifted_observed(&k, &m, sigma, &mut |_, _| {}).unwrap();
        assert_eq!(chol.nnz_l(), reference.nnz_l());
        let b = Mat::<f64>::from_fn(n, 3, |i, j| ((i * 7 + j * 3) as f64).sin());
        let solve = |c: &SparseCholesky| {
            let mut x = b.clone();
            c.solve_in_place(x.as_mut());
            x
        };
        let (x, xr) = (solve(&chol), solve(&reference));
        let scale = xr.norm_max();
        assert!((&x - &xr).norm_max() <= 1e-12 * scale, "lumped {lumped}");
        // the residual of the solve with the full matrix
        assert!(relative_residual(&full, &x, &b) <= 1e-12 * 1e2);
        // (9 is an eigenvalue of the lumped model: cuts off the spectrum)
        for cut in [0.5, 3.1, 8.7] {
            let expected = ldlt_inertia(&shifted(&k, &m, cut).unwrap())
                .unwrap()
                .unwrap();
            let in_place = chol.inertia_shifted_in_place(&k, &m, cut).unwrap().unwrap();
            assert_eq!(in_place, expected);
            assert!(chol.is_stale());
        }
        chol.refactor_shifted(&k, &m, sigma).unwrap();
        assert_eq!(solve(&chol), x, "refactor restores the factor bit for bit");
        // L D L^T inside the spectrum: solves with the indefinite matrix
        let cut = 3.1;
        chol.factor_ldlt_shifted_in_place(&k, &m, cut)
            .unwrap()
            .unwrap();
        let y = solve(&chol);
        let a = shifted(&k, &m, cut).unwrap();
        assert!(relative_residual(&a, &y, &b) <= 1e-9);
    }
}

/// The block product with a symmetric matrix equals faer's sparse product (to round-off: the
/// summation order differs), for block widths below, at and above one pass, on one thread and
/// (5184 rows) on two.
#[test]
fn symmetric_block_product_matches_faer() {
    for (nx, p) in [(4, 1), (4, 8), (4, 11), (12, 11)] {
        let (k, _) = grid_model(nx, false);
        let n = k.nrows();
        let x = Mat::<f64>::from_fn(n, p, |i, j| ((i * 5 + j * 13) as f64).cos());
        let mut y = Mat::zeros(n, p);
        apply_stiffness(&k, x.as_ref(), y.as_mut());
        let r = faer_product(&k, &x);
        assert!(
            (&y - &r).norm_max() <= 1e-13 * r.norm_max(),
            "n = {n}, p = {p}"
        );
    }
}

/// The ordering read from the patterns of `K` and `M` (whose patterns differ: the grid's `M`
/// couples equal directions only) is the ordering of the formed union `K - s M`, so the DOFs of
/// a node stay one METIS vertex.
#[test]
fn metis_on_two_patterns_equals_metis_on_their_union() {
    let (k, m) = grid_model(8, false);
    let union = shifted(&k, &m, 1.0).unwrap();
    let a = super::ordering::metis_nested_dissection(&union).unwrap();
    let b = super::ordering::metis_on_patterns(&[&k, &m]).unwrap();
    assert_eq!(a.arrays().0, b.arrays().0);
    let m_alone = super::ordering::metis_nested_dissection(&m).unwrap();
    assert_ne!(
        a.arrays().0,
        m_alone.arrays().0,
        "the test must see M's pattern"
    );
    // neither pattern lies within the other here (K's stencil has exact zeros where M's has
    // none): the union above; a pattern within another adds nothing to the union (equal
    // patterns; a lumped M's diagonal within K's)
    use super::ordering::pattern_within;
    assert!(!pattern_within(&m, &k) && !pattern_within(&k, &m));
    let (kl, ml) = grid_model(8, true);
    assert!(pattern_within(&ml, &kl) && !pattern_within(&kl, &ml));
    let k_alone = super::ordering::metis_nested_dissection(&kl).unwrap();
    for pair in [[&kl, &kl], [&kl, &ml], [&ml, &kl]] {
        let p = super::ordering::metis_on_patterns(&pair).unwrap();
        assert_eq!(p.arrays().0, k_alone.arrays().0);
    }
}

/// The solve with a factor on an ordered pattern (rows permuted in place, no copy) equals the
/// solve of faer's own ordering of the same matrix to 1e-12, for 1, 8 and 13 right-hand sides.
#[test]
fn ordered_pattern_solve_permutes_in_place() {
    let (k, m) = grid_model(7, false);
    let sigma = -0.1;
    let ordered = SparseCholesky::factor_shifted_observed(&k, &m, sigma, &mut |_, _| {}).unwrap();
    let plain = SparseCholesky::factor(&shifted(&k, &m, sigma).unwrap()).unwrap();
    let n = k.nrows();
    for p in [1, 8, 13] {
        let b = Mat::from_fn(n, p, |i, j| ((i * 7 + j * 13) % 17) as f64 - 8.0);
        let (mut x1, mut x2) = (b.clone(), b.clone());
        ordered.solve_in_place(x1.as_mut());
        plain.solve_in_place(x2.as_mut());
        let scale = x2.norm_max();
        assert!((&x1 - &x2).norm_max() < 1e-12 * scale);
    }
}

/// The one-pass asymmetry measure: zero for the symmetric grid matrix, the difference for a
/// mirror pair with different values, the value for an entry without a mirror.
#[test]
fn asymmetry_finds_differing_and_missing_mirrors() {
    let (k, _) = grid_model(3, false);
    assert_eq!(super::max_asymmetry(&k), 0.0);
    let mut t: Vec<_> = k
        .triplet_iter()
        .map(|t| Triplet::new(t.row, t.col, *t.val))
        .collect();
    t.push(Triplet::new(0, 5, 0.25));
    assert!((super::max_asymmetry(&sparse(k.nrows(), &t)) - 0.25).abs() < 1e-15);
    let lone = [
        Triplet::new(0, 0, 1.0),
        Triplet::new(1, 1, 1.0),
        Triplet::new(2, 2, 1.0),
        Triplet::new(2, 0, 0.5),
        Triplet::new(1, 2, 0.125),
        Triplet::new(2, 1, 0.125),
    ];
    assert_eq!(super::max_asymmetry(&sparse(3, &lone)), 0.5);
}

/// The two-domain factorization (METIS' top bisection, halves factored on two threads, dense
/// Schur complement of the separator) solves like one factorization of the whole matrix and
/// counts eigenvalues below a cut (Sturm) like one `L D L^T`: `L L^T` below the spectrum, `L D
/// L^T` inside it (solves with the indefinite matrix), refactorization bit for bit; consistent
/// and lumped `M`.
#[test]
fn two_domain_factor_matches_one_factor() {
    for lumped in [false, true] {
        let (k, m) = grid_model(9, lumped);
        let n = k.nrows();
        let (perm, d) = super::ordering::metis_two_domains(&[&k, &m]).expect("two domains");
        assert!(
            d.first > n / 4 && d.second > n / 4 && d.separator > 0,
            "{d:?}"
        );
        assert_eq!(d.first + d.second + d.separator, n);
        let (fwd, _) = perm.as_ref().arrays();
        let mut split = super::split::SplitFactor::new(&k, &m, fwd, d, &mut |_, _| {}).unwrap();
        assert_eq!(split.dim(), n);
        let sigma = -1.0;
        split.factor_llt(&k, &m, sigma).unwrap();
        let full = shifted(&k, &m, sigma).unwrap();
        let one = SparseCholesky::factor(&full).unwrap();
        let b = Mat::<f64>::from_fn(n, 5, |i, j| ((i * 7 + j * 3) as f64).sin());
        let mut x = b.clone();
        split.solve_in_place(x.as_mut());
        let mut xr = b.clone();
        one.solve_in_place(xr.as_mut());
        assert!(
            (&x - &xr).norm_max() <= 1e-12 * xr.norm_max(),
            "lumped {lumped}"
        );
        for cut in [0.5, 3.1, 8.7] {
            let a = shifted(&k, &m, cut).unwrap();
            let expected = ldlt_inertia(&a).unwrap().unwrap();
            let counted = split.factor_ldlt(&k, &m, cut).unwrap().unwrap();
            assert_eq!(counted, expected, "lumped {lumped}, cut {cut}");
            assert!(counted.negative > 0 && counted.near_zero == 0);
            let mut y = b.clone();
            split.solve_in_place(y.as_mut());
            assert!(relative_residual(&a, &y, &b) <= 1e-9, "cut {cut}");
        }
        split.factor_llt(&k, &m, sigma).unwrap();
        let mut x2 = b.clone();
        split.solve_in_place(x2.as_mut());
        assert_eq!(x2, x, "refactor restores the factor bit for bit");
        // K - s M above the lowest eigenvalue is not positive definite
        assert!(matches!(
            split.factor_llt(&k, &m, 3.1),
            Err(FeError::NotPositiveDefinite { .. })
        ));
    }
}
