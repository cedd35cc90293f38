//! Tests of the eigen solvers against closed-form spectra and the dense solver.
#![allow(clippy::needless_range_loop)] // index loops mirror the formulas

use super::lanczos::BlockLanczos;
use super::*;
use faer::sparse::{SparseColMat, Triplet};
use std::f64::consts::PI;

fn sparse(n: usize, t: &[Triplet<usize, usize, f64>]) -> SparseMatrix {
    SparseColMat::try_new_from_triplets(n, n, t).unwrap()
}

/// 1D matrices on `nx` interior nodes: stiffness tridiag(-1, 2, -1), mass tridiag(1, 4, 1)/6.
fn one_d(nx: usize) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let k = (0..nx).map(|_| [-1.0, 2.0, -1.0]).collect();
    let m = (0..nx).map(|_| [1.0 / 6.0, 4.0 / 6.0, 1.0 / 6.0]).collect();
    (k, m)
}

/// crate-stack.md §2.1 style pair on an `nx^3` grid with 3 DOF/node:
/// `K = (K1 M1 M1 + M1 K1 M1 + M1 M1 K1) (x) B`, `M = (M1 M1 M1) (x) I3`, with
/// `B = [[2,.5,.5],[.5,2,.5],[.5,.5,2]]` (eigenvalues 1.5, 1.5, 3). Both are 27-point
/// stencils (81 nonzeros per interior row); `lumped` replaces M1 by the identity.
fn grid_model(nx: usize, lumped: bool) -> (SparseMatrix, SparseMatrix) {
    let (k1, mut m1) = one_d(nx);
    if lumped {
        m1 = (0..nx).map(|_| [0.0, 1.0, 0.0]).collect();
    }
    let bmat = [[2.0, 0.5, 0.5], [0.5, 2.0, 0.5], [0.5, 0.5, 2.0]];
    let node = |i: usize, j: usize, l: usize| (i * nx + j) * nx + l;
    let n = 3 * nx * nx * nx;
    let (mut kt, mut mt) = (Vec::new(), Vec::new());
    for i in 0..nx {
        for j in 0..nx {
            for l in 0..nx {
                for di in 0..3usize {
                    for dj in 0..3usize {
                        for dl in 0..3usize {
                            let (Some(i2), Some(j2), Some(l2)) = (
                                (i + di).checked_sub(1),
                                (j + dj).checked_sub(1),
                                (l + dl).checked_sub(1),
                            ) else {
                                continue;
                            };
                            if i2 >= nx || j2 >= nx || l2 >= nx {
                                continue;
                            }
                            let mm = m1[i][di] * m1[j][dj] * m1[l][dl];
                            let kk = k1[i][di] * m1[j][dj] * m1[l][dl]
                                + m1[i][di] * k1[j][dj] * m1[l][dl]
                                + m1[i][di] * m1[j][dj] * k1[l][dl];
                            let (p, q) = (node(i, j, l), node(i2, j2, l2));
                            for a in 0..3 {
                                if mm != 0.0 {
                                    mt.push(Triplet::new(3 * p + a, 3 * q + a, mm));
                                }
                                for b in 0..3 {
                                    if kk != 0.0 {
                                        kt.push(Triplet::new(
                                            3 * p + a,
                                            3 * q + b,
                                            kk * bmat[a][b],
                                        ));
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    (sparse(n, &kt), sparse(n, &mt))
}

/// Closed-form lowest `count` eigenvalues of [`grid_model`]:
/// `(mu_a + mu_b + mu_c) * beta`, `mu_j = (2 - 2 cos t_j) / w_j`, `t_j = j pi/(nx+1)`,
/// `w_j = (4 + 2 cos t_j)/6` (consistent) or 1 (lumped), `beta in {1.5, 1.5, 3}`.
fn grid_exact(nx: usize, lumped: bool, count: usize) -> Vec<f64> {
    let mu: Vec<f64> = (1..=nx)
        .map(|j| {
            let t = j as f64 * PI / (nx as f64 + 1.0);
            let w = if lumped {
                1.0
            } else {
                (4.0 + 2.0 * t.cos()) / 6.0
            };
            (2.0 - 2.0 * t.cos()) / w
        })
        .collect();
    let mut all = Vec::new();
    for a in &mu {
        for b in &mu {
            for c in &mu {
                for beta in [1.5, 1.5, 3.0] {
                    all.push((a + b + c) * beta);
                }
            }
        }
    }
    all.sort_by(f64::total_cmp);
    all.truncate(count);
    all
}

/// Free-free spring lattice: `nx^3` nodes on a unit cube grid, springs (stiffness 1/length)
/// to all 26 neighbours (rigid truss, so exactly 6 zero eigenvalues), node masses
/// `mass(node)` (lumped, 3 DOF per node).
fn spring_lattice(nx: usize, mass: impl Fn(usize) -> f64) -> (SparseMatrix, SparseMatrix) {
    let node = |i: usize, j: usize, l: usize| (i * nx + j) * nx + l;
    let nn = nx * nx * nx;
    let (mut kt, mut mt) = (Vec::new(), Vec::new());
    for i in 0..nx {
        for j in 0..nx {
            for l in 0..nx {
                let p = node(i, j, l);
                for a in 0..3 {
                    mt.push(Triplet::new(3 * p + a, 3 * p + a, mass(p)));
                }
                for d in 0..27usize {
                    let off = [d / 9, (d / 3) % 3, d % 3];
                    if off == [1, 1, 1] {
                        continue;
                    }
                    let (Some(i2), Some(j2), Some(l2)) = (
                        (i + off[0]).checked_sub(1),
                        (j + off[1]).checked_sub(1),
                        (l + off[2]).checked_sub(1),
                    ) else {
                        continue;
                    };
                    if i2 >= nx || j2 >= nx || l2 >= nx {
                        continue;
                    }
                    let q = node(i2, j2, l2);
                    let e: Vec<f64> = off.iter().map(|&o| o as f64 - 1.0).collect();
                    let len = e.iter().map(|x| x * x).sum::<f64>().sqrt();
                    let ks = 1.0 / len;
                    for a in 0..3 {
                        for b in 0..3 {
                            let v = ks * e[a] * e[b] / (len * len);
                            // each spring is visited from both ends: add only the p-rows
                            kt.push(Triplet::new(3 * p + a, 3 * p + b, v));
                            kt.push(Triplet::new(3 * p + a, 3 * q + b, -v));
                        }
                    }
                }
            }
        }
    }
    (sparse(3 * nn, &kt), sparse(3 * nn, &mt))
}

fn rel_err(a: f64, b: f64, scale: f64) -> f64 {
    (a - b).abs() / scale
}

fn lanczos_opts(n_modes: usize) -> EigenOptions {
    EigenOptions {
        n_modes,
        method: EigenMethod::Lanczos,
        ..Default::default()
    }
}

/// Asserts that the first `count` eigenvalues of `sol` equal `reference` to 1e-9 relative.
fn assert_eigenvalues_match(sol: &EigenSolution, reference: &[f64], count: usize, what: &str) {
    for i in 0..count {
        assert!(
            rel_err(sol.omega2[i], reference[i], reference[i]) < 1e-9,
            "{what} mode {i}: {} vs {}",
            sol.omega2[i],
            reference[i]
        );
    }
}

/// `A X` by faer's compressed-column product (independent of the eigen module's products).
fn faer_product(a: &SparseMatrix, x: &Mat<f64>) -> Mat<f64> {
    let mut ax = Mat::zeros(x.nrows(), x.ncols());
    faer::sparse::linalg::matmul::sparse_dense_matmul(
        ax.as_mut(),
        faer::Accum::Replace,
        a.as_ref(),
        x.as_ref(),
        1.0,
        faer::Par::Seq,
    );
    ax
}

/// `||A X - B||_max / ||B||_max` with faer's sparse product.
fn relative_residual(a: &SparseMatrix, x: &Mat<f64>, b: &Mat<f64>) -> f64 {
    (&faer_product(a, x) - b).norm_max() / b.norm_max()
}

/// `||X^T M X - I||_max`.
fn m_orthonormality(m: &SparseMatrix, x: &Mat<f64>) -> f64 {
    let mx = m * x;
    let g = x.transpose() * &mx;
    let mut e = 0.0f64;
    for i in 0..g.nrows() {
        for j in 0..g.ncols() {
            e = e.max((g[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    e
}

/// Lanczos vs dense on the consistent-mass grid (n = 648, multiplicities up to 12 > block 8):
/// lowest 20 eigenvalues agree to 1e-9 relative, the Sturm check passes, X^T M X = I to 1e-10.
#[test]
fn lanczos_matches_dense_on_grid_with_multiplicities() {
    let nx = 6;
    let (k, m) = grid_model(nx, false);
    let (ld, _) = dense_generalized(k.to_dense().as_ref(), m.to_dense().as_ref()).unwrap();
    let exact = grid_exact(nx, false, 20);
    for (d, e) in ld.iter().zip(&exact) {
        assert!(rel_err(*d, *e, *e) < 1e-12, "dense {d} vs closed form {e}");
    }
    let sol = lowest_modes(&k, &m, &lanczos_opts(20), &mut |_| {}).unwrap();
    assert_eigenvalues_match(&sol, &ld, 20, "consistent grid");
    for i in 0..20 {
        assert!(
            sol.residuals[i] < 1e-9,
            "residual {i}: {}",
            sol.residuals[i]
        );
    }
    let (exp, found) = sol.sturm.unwrap();
    assert_eq!(exp, found);
    assert!(m_orthonormality(&m, &sol.vectors) < 1e-10);
}

/// n = 3000 grid (nx = 10), lumped and consistent mass, lowest 20 vs the closed form to 1e-9.
#[test]
fn lanczos_grid_3000_matches_closed_form_lumped_and_consistent() {
    for lumped in [true, false] {
        let nx = 10;
        let (k, m) = grid_model(nx, lumped);
        let exact = grid_exact(nx, lumped, 20);
        let mut events = Vec::new();
        let sol = lowest_modes(&k, &m, &lanczos_opts(20), &mut |e| events.push(e)).unwrap();
        assert_eigenvalues_match(&sol, &exact, 20, &format!("lumped={lumped}"));
        assert!(sol.sturm.is_some_and(|(a, b)| a == b && a >= 20));
        assert!(m_orthonormality(&m, &sol.vectors) < 1e-10);
        assert!(events
            .iter()
            .any(|e| matches!(e, EigenEvent::Factorized { .. })));
        assert!(events
            .iter()
            .any(|e| matches!(e, EigenEvent::Iteration { .. })));
    }
}

/// Plain Lanczos (block size 1) misses copies of repeated eigenvalues in exact
/// arithmetic; the Sturm count flags the miss (a SturmCheck event with found >
/// expected) and the driver recovers all copies by injecting fresh directions.
#[test]
fn sturm_check_catches_block_one_misses() {
    let nx = 6;
    let (k, m) = grid_model(nx, false);
    let exact = grid_exact(nx, false, 12);
    // internal run: block 1 converges to 12 Ritz values that are not the 12 lowest
    let sigma = automatic_shift(&k, &m);
    let chol = SparseCholesky::factor(&shifted(&k, &m, sigma).unwrap()).unwrap();
    let mut lz = BlockLanczos::new(&m, 1, 60, 7).unwrap();
    let (pairs, outcome) = lz
        .run(&chol, sigma, 12, 13, 1e-10, 500, &mut |_, _| {})
        .unwrap();
    assert_eq!(outcome, super::lanczos::Outcome::Converged);
    let lam = pairs.lambda;
    let cut = 0.5 * (lam[11] + lam[12]);
    let below = exact.iter().filter(|&&e| e < cut).count();
    let inertia = ldlt_inertia(&shifted(&k, &m, cut).unwrap())
        .unwrap()
        .unwrap();
    assert!(
        inertia.negative > 12,
        "block-1 Lanczos found all copies?! {lam:?}"
    );
    assert!(inertia.negative >= below);
    // driver with block size 1 recovers
    let mut mismatch = false;
    let opts = EigenOptions {
        block_size: 1,
        max_basis: 80,
        ..lanczos_opts(12)
    };
    let sol = lowest_modes(&k, &m, &opts, &mut |e| {
        if let EigenEvent::SturmCheck { expected, found } = e {
            mismatch |= expected != found;
        }
    })
    .unwrap();
    assert!(
        mismatch,
        "the Sturm check should have flagged missed copies"
    );
    for i in 0..12 {
        assert!(
            rel_err(sol.omega2[i], exact[i], exact[i]) < 1e-9,
            "mode {i}: {} vs {}",
            sol.omega2[i],
            exact[i]
        );
    }
}

/// Free-free spring lattice (5^3 nodes, n = 375, cube symmetry): 6 rigid modes with
/// |lambda| < 1e-8 lambda_7, remaining lowest 20 equal to dense to 1e-9 relative;
/// uniform masses (repeated eigenvalues) and varying masses.
#[test]
fn free_free_spring_lattice_has_six_rigid_modes() {
    for uniform in [true, false] {
        let (k, m) = spring_lattice(5, |p| {
            if uniform {
                2.0
            } else {
                1.0 + 0.37 * (p % 5) as f64
            }
        });
        let (ld, _) = dense_generalized(k.to_dense().as_ref(), m.to_dense().as_ref()).unwrap();
        let sol = lowest_modes(&k, &m, &lanczos_opts(26), &mut |_| {}).unwrap();
        let l7 = ld[6];
        assert!(l7 > 1e-3, "lattice must be rigid: lambda_7 = {l7}");
        for i in 0..6 {
            assert!(
                sol.omega2[i].abs() < 1e-8 * l7,
                "rigid mode {i}: {}",
                sol.omega2[i]
            );
            assert!(ld[i].abs() < 1e-8 * l7);
        }
        for i in 6..26 {
            assert!(
                rel_err(sol.omega2[i], ld[i], ld[i]) < 1e-9,
                "mode {i}: {} vs {}",
                sol.omega2[i],
                ld[i]
            );
        }
        assert!(m_orthonormality(&m, &sol.vectors) < 1e-10);
        assert!(sol.sturm.is_some_and(|(a, b)| a == b));
        // dense path through the same driver
        let dense = lowest_modes(
            &k,
            &m,
            &EigenOptions {
                method: EigenMethod::Dense,
                ..lanczos_opts(26)
            },
            &mut |_| {},
        )
        .unwrap();
        for i in 6..26 {
            assert!(rel_err(dense.omega2[i], ld[i], ld[i]) < 1e-12);
        }
        assert!(
            dense.residuals.iter().all(|&r| r < 1e-9),
            "{:?}",
            dense.residuals
        );
    }
}

/// Bad input is reported as an error, never a panic.
#[test]
fn bad_input_is_an_error() {
    let (k, m) = grid_model(3, true);
    let n = k.nrows();
    let mut t: Vec<_> = k
        .triplet_iter()
        .map(|t| Triplet::new(t.row, t.col, *t.val))
        .collect();
    t.push(Triplet::new(0, 5, 1.0));
    let k_ns = sparse(n, &t);
    assert!(matches!(
        lowest_modes(&k_ns, &m, &lanczos_opts(3), &mut |_| {}),
        Err(FeError::Invalid(_))
    ));
    let (k2, _) = grid_model(2, true);
    assert!(matches!(
        lowest_modes(&k2, &m, &lanczos_opts(3), &mut |_| {}),
        Err(FeError::Invalid(_))
    ));
    assert!(matches!(
        lowest_modes(&k, &m, &lanczos_opts(n + 1), &mut |_| {}),
        Err(FeError::Invalid(_))
    ));
    // M with a negative diagonal entry
    let mut tm: Vec<_> = m
        .triplet_iter()
        .map(|t| Triplet::new(t.row, t.col, *t.val))
        .collect();
    tm.push(Triplet::new(4, 4, -3.0));
    let m_neg = sparse(n, &tm);
    for method in [EigenMethod::Lanczos, EigenMethod::Dense] {
        let o = EigenOptions {
            method,
            ..lanczos_opts(3)
        };
        assert!(matches!(
            lowest_modes(&k, &m_neg, &o, &mut |_| {}),
            Err(FeError::NotPositiveDefinite { .. })
        ));
    }
    // M indefinite with positive diagonal: 2x2 blocks [[1, 2], [2, 1]]
    let tm: Vec<_> = (0..n / 2)
        .flat_map(|b| {
            let (p, q) = (2 * b, 2 * b + 1);
            [
                Triplet::new(p, p, 1.0),
                Triplet::new(q, q, 1.0),
                Triplet::new(p, q, 2.0),
                Triplet::new(q, p, 2.0),
            ]
        })
        .chain((n / 2 * 2..n).map(|i| Triplet::new(i, i, 1.0)))
        .collect();
    let m_ind = sparse(n, &tm);
    for method in [EigenMethod::Lanczos, EigenMethod::Dense] {
        let o = EigenOptions {
            method,
            ..lanczos_opts(3)
        };
        assert!(lowest_modes(&k, &m_ind, &o, &mut |_| {}).is_err());
    }
    // user shift above the lowest eigenvalue: K - sigma M indefinite
    let o = EigenOptions {
        shift: Some(100.0),
        ..lanczos_opts(3)
    };
    assert!(matches!(
        lowest_modes(&k, &m, &o, &mut |_| {}),
        Err(FeError::NotPositiveDefinite { .. })
    ));
}

/// One-off timing on the crate-stack §2.1 matrix with nx = 22 (n = 31,944):
/// `cargo test --release -p flexmbs-fe -- --ignored eigen_timing --nocapture`.
#[test]
#[ignore = "one-off timing run on a 31 944-DOF matrix, not a test: run with --ignored in release"]
fn eigen_timing_31944() {
    let t0 = std::time::Instant::now();
    let (k, m) = grid_model(22, false);
    println!(
        "assembly {:?}, n = {}, nnz = {}",
        t0.elapsed(),
        k.nrows(),
        k.compute_nnz()
    );
    let t1 = std::time::Instant::now();
    let mut last = std::time::Instant::now();
    let sol = lowest_modes(&k, &m, &lanczos_opts(20), &mut |e| {
        println!("{:>8.2?} {e:?}", last.elapsed());
        last = std::time::Instant::now();
    })
    .unwrap();
    println!("lowest_modes total {:?}", t1.elapsed());
    let exact = grid_exact(22, false, 20);
    let err = (0..20)
        .map(|i| rel_err(sol.omega2[i], exact[i], exact[i]))
        .fold(0.0, f64::max);
    let rmax = sol.residuals.iter().fold(0.0f64, |a, &b| a.max(b));
    println!(
        "max rel. eigenvalue error {err:e}, max residual {rmax:e}, sturm {:?}",
        sol.sturm
    );
    assert!(err < 1e-9);
}

/// A supported model (`EigenOptions::supported`) starts at `sigma = 0`; the same problem without
/// the hint starts at the spectrum-probing shift below zero; both match the dense eigenvalues to
/// 1e-9 with the Sturm check passing. A singular `K` (free-free lattice) with the hint falls back
/// to the negative shift and still finds its six rigid-body modes.
#[test]
fn supported_models_start_at_zero_shift() {
    let (k, m) = grid_model(6, false);
    let (ld, _) = dense_generalized(k.to_dense().as_ref(), m.to_dense().as_ref()).unwrap();
    for supported in [true, false] {
        let opts = EigenOptions {
            supported,
            ..lanczos_opts(20)
        };
        let sol = lowest_modes(&k, &m, &opts, &mut |_| {}).unwrap();
        if supported {
            assert_eq!(sol.start_shift, 0.0);
        } else {
            assert!(sol.start_shift < 0.0, "shift {}", sol.start_shift);
        }
        assert_eigenvalues_match(&sol, &ld, 20, &format!("supported={supported}"));
        assert!(sol.sturm.is_some_and(|(a, b)| a == b));
        assert!(m_orthonormality(&m, &sol.vectors) < 1e-10);
    }
    let (k, m) = spring_lattice(5, |_| 2.0);
    let opts = EigenOptions {
        supported: true,
        ..lanczos_opts(12)
    };
    let sol = lowest_modes(&k, &m, &opts, &mut |_| {}).unwrap();
    assert!(sol.start_shift < 0.0, "shift {}", sol.start_shift);
    let l7 = sol.omega2[6];
    assert!(sol.omega2[..6].iter().all(|w| w.abs() < 1e-8 * l7));
}

/// Started from a factorization of `K` made beforehand (as Craig-Bampton does for its static
/// modes), the solver gives the same pairs as [`lowest_modes`] with the supported hint, bit for
/// bit (the same factor, the same start), still matching the dense eigenvalues to 1e-9 with the
/// Sturm check; a factor of another dimension is refused.
#[test]
fn a_given_factor_of_k_starts_the_solver() {
    let (k, m) = grid_model(6, false);
    let (ld, _) = dense_generalized(k.to_dense().as_ref(), m.to_dense().as_ref()).unwrap();
    let opts = EigenOptions {
        supported: true,
        ..lanczos_opts(20)
    };
    let reference = lowest_modes(&k, &m, &opts, &mut |_| {}).unwrap();
    let chol = SparseCholesky::factor_shifted_observed(&k, &m, 0.0, &mut |_, _| {}).unwrap();
    let mut factorizations = 0;
    let sol = lowest_modes_from_k_factor(&k, &m, &opts, chol, &mut |e| {
        factorizations += matches!(e, EigenEvent::Factorizing { .. }) as usize
    })
    .unwrap();
    assert_eq!(factorizations, 0, "the given factor is the start");
    assert_eq!(sol.start_shift, 0.0);
    assert_eq!(sol.omega2, reference.omega2);
    assert_eq!(sol.vectors, reference.vectors);
    assert_eigenvalues_match(&sol, &ld, 20, "given factor");
    assert!(sol.sturm.is_some_and(|(a, b)| a == b));
    let (k4, m4) = grid_model(4, false);
    let small = SparseCholesky::factor_shifted_observed(&k4, &m4, 0.0, &mut |_, _| {}).unwrap();
    let e = lowest_modes_from_k_factor(&k, &m, &opts, small, &mut |_| {}).unwrap_err();
    assert!(matches!(e, FeError::Invalid(_)), "{e}");
}

/// From `SPLIT_MIN_DIM` unknowns the Lanczos driver factors in two domains (a 24 000-DOF grid
/// whose separator is a twentieth of it): the lowest eigenvalues match the closed form to 1e-9,
/// the Sturm check passes, the vectors are M-orthonormal.
#[test]
fn large_models_use_two_domains_and_match_the_closed_form() {
    let nx = 20;
    let (k, m) = grid_model(nx, false);
    assert!(k.nrows() >= super::split::SPLIT_MIN_DIM);
    let chol = SparseCholesky::factor_shifted_observed(&k, &m, 0.0, &mut |_, _| {}).unwrap();
    assert!(chol.is_split(), "the grid splits in two domains");
    drop(chol);
    let opts = EigenOptions {
        supported: true,
        ..lanczos_opts(12)
    };
    let sol = lowest_modes(&k, &m, &opts, &mut |_| {}).unwrap();
    assert_eigenvalues_match(&sol, &grid_exact(nx, false, 12), 12, "two domains");
    // the count is taken at the first gap after the 12th eigenvalue (a cluster ends at 15)
    let (below, found) = sol.sturm.expect("Sturm check");
    assert!(below >= 12 && found == below, "{below} {found}");
    assert!(m_orthonormality(&m, &sol.vectors) < 1e-10);
}

mod factor;
