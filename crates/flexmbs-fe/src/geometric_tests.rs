//! Tests of the geometric stiffness: beam matrix vs its Hermite integral, Euler buckling of
//! clamped columns (beam and Hex20 solid), the rotating cantilever (Southwell coefficient and the
//! exact table of Wright et al. 1982), the projected modal matrices, and input errors.

use crate::constraint::BoundaryConditions;
use crate::eigen::dense_generalized;
use crate::eigen::EigenOptions;
use crate::element::beam::plane_bending_shape;
use crate::element::gauss::gauss_legendre;
use crate::element::MassKind;
use crate::geometric::*;
use crate::mesh::generate::{beam_line, box_mesh};
use crate::mesh::{BeamSection, BeamTheory, ElementKind};
use crate::reduction::{modal_analysis, reduce_modal, Provenance};
use crate::system::FeSystem;
use crate::{Material, Mesh, UnitSystem};
use faer::Mat;

fn aluminium() -> Material {
    Material {
        e: 70e9,
        nu: 0.3,
        rho: 2700.0,
    }
}

fn dense(a: &crate::SparseMatrix) -> Mat<f64> {
    let mut d = Mat::<f64>::zeros(a.nrows(), a.ncols());
    for (i, j, v) in crate::assembly::entries(a) {
        d[(i, j)] += v;
    }
    d
}

/// Lowest positive buckling factor `lambda` of `(K + lambda K_σ) phi = 0`:
/// `-K_σ phi = mu K phi`, `lambda = 1 / mu_max`.
fn buckling_factor(k: &Mat<f64>, ks: &Mat<f64>) -> f64 {
    let neg = Mat::from_fn(ks.nrows(), ks.ncols(), |i, j| -ks[(i, j)]);
    let (mu, _) = dense_generalized(neg.as_ref(), k.as_ref()).unwrap();
    1.0 / mu.last().copied().unwrap()
}

#[test]
fn beam_geometric_stiffness_equals_hermite_integral() {
    // plane block = N int N_v'^T N_v' dx with the Euler-Bernoulli (phi = 0) interpolation,
    // N_v' = N_theta; integrated by 4-point Gauss (exact for degree 4)
    let (n, l) = (-3.7e3, 0.37);
    let k = beam_geometric_stiffness_local(n, l, 2.5e-5);
    let mut g = [[0.0; 4]; 4];
    for &(xg, wg) in gauss_legendre(4) {
        let s = 0.5 * (xg + 1.0);
        let (_, nt) = plane_bending_shape(s, l, 0.0);
        for i in 0..4 {
            for j in 0..4 {
                g[i][j] += 0.5 * wg * l * n * nt[i] * nt[j];
            }
        }
    }
    let xy = [1, 5, 7, 11];
    let xz = [2, 4, 8, 10];
    let sg = [1.0, -1.0, 1.0, -1.0];
    for i in 0..4 {
        for j in 0..4 {
            let tol = 1e-12 * n.abs();
            assert!((k[(xy[i], xy[j])] - g[i][j]).abs() < tol);
            assert!((k[(xz[i], xz[j])] - sg[i] * sg[j] * g[i][j]).abs() < tol);
        }
    }
    // textbook entries: 6N/(5L), N/10, 2NL/15, -NL/30; torsion N Ip/(A L); axial N/L
    assert!((k[(1, 1)] - 1.2 * n / l).abs() < 1e-9);
    assert!((k[(5, 11)] + n * l / 30.0).abs() < 1e-9);
    assert!((k[(3, 9)] + n * 2.5e-5 / l).abs() < 1e-12);
    assert!((k[(0, 6)] + n / l).abs() < 1e-9);
}

/// Clamped column along x, compressed by a unit tip load; returns (K, K_σ) over independent DOFs.
fn column_matrices(mesh: &Mesh, fixed: Vec<usize>, tip: &[(usize, f64)]) -> (Mat<f64>, Mat<f64>) {
    let bc = BoundaryConditions {
        fixed,
        rigid: vec![],
    };
    let sys = FeSystem::assemble(mesh, &bc, MassKind::Lumped, &mut |_, _| {}).unwrap();
    let mut f = Mat::<f64>::zeros(sys.len(), 1);
    for &(node, share) in tip {
        let p = sys.map.independent_of_node(node)[0]; // ux
        f[(p, 0)] = -share;
    }
    let v = static_solve(&sys, &f, &[], "column").unwrap();
    let col: Vec<f64> = (0..sys.len()).map(|i| v[(i, 0)]).collect();
    let ks = stress_stiffness_matrix(mesh, &sys, &col).unwrap();
    (dense(&sys.k), dense(&ks))
}

#[test]
fn clamped_beam_column_buckles_at_euler_load() {
    let (l, b, h) = (1.0, 0.02, 0.01);
    let sec = BeamSection::rectangle(b, h);
    let mesh = beam_line(
        [0.0; 3],
        [l, 0.0, 0.0],
        12,
        sec,
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        aluminium(),
        UnitSystem::Si,
    )
    .unwrap();
    let start = mesh.node_set("start").unwrap().to_vec();
    let end = mesh.node_set("end").unwrap()[0];
    let (k, ks) = column_matrices(&mesh, start, &[(end, 1.0)]);
    let lambda = buckling_factor(&k, &ks);
    let euler = std::f64::consts::PI.powi(2) * 70e9 * sec.iy.min(sec.iz) / (4.0 * l * l);
    let rel = lambda / euler - 1.0;
    eprintln!("beam column: P_cr = {lambda:.4} N, Euler {euler:.4} N, {rel:+.2e}");
    assert!(rel.abs() < 1e-4, "{rel}");
}

#[test]
fn clamped_hex20_column_buckles_at_euler_load() {
    // 0.5 m x 20 mm x 20 mm, 1 x 1 x 16 Hex20 (slenderness L/r = 87), unit load on the tip face
    // distributed consistently (corners -1/12, mid-edges 1/3)
    let (l, a) = (0.5, 0.02);
    let mesh = box_mesh(
        [l, a, a],
        [16, 1, 1],
        ElementKind::Hex20,
        aluminium(),
        UnitSystem::Si,
    )
    .unwrap();
    let fixed = mesh.node_set("xmin").unwrap().to_vec();
    let tip: Vec<(usize, f64)> = mesh
        .node_set("xmax")
        .unwrap()
        .iter()
        .map(|&n| {
            let x = mesh.nodes[n];
            let corner = [x[1], x[2]]
                .iter()
                .all(|c| c.abs() < 1e-9 || (c - a).abs() < 1e-9);
            (n, if corner { -1.0 / 12.0 } else { 1.0 / 3.0 })
        })
        .collect();
    assert_eq!(tip.len(), 8);
    let (k, ks) = column_matrices(&mesh, fixed, &tip);
    let lambda = buckling_factor(&k, &ks);
    let euler = std::f64::consts::PI.powi(2) * 70e9 * a.powi(4) / 12.0 / (4.0 * l * l);
    let rel = lambda / euler - 1.0;
    eprintln!("Hex20 column: P_cr = {lambda:.2} N, Euler {euler:.2} N, {rel:+.2e}");
    // shear flexibility lowers P_cr by ~ P/(kGA) ~ 1e-4; discretization and the clamped face's
    // Poisson restraint by a few 1e-3
    assert!(rel.abs() < 1e-2, "{rel}");
}

/// Cantilever along x spinning about z, clamped at the axis (hub radius 0).
fn spinning_cantilever(mass: MassKind) -> (Mesh, FeSystem) {
    let mesh = beam_line(
        [0.0; 3],
        [1.0, 0.0, 0.0],
        20,
        BeamSection::rectangle(0.02, 0.01), // flap (z) is the soft direction
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        aluminium(),
        UnitSystem::Si,
    )
    .unwrap();
    let bc = BoundaryConditions {
        fixed: mesh.node_set("start").unwrap().to_vec(),
        rigid: vec![],
    };
    let sys = FeSystem::assemble(&mesh, &bc, mass, &mut |_, _| {}).unwrap();
    (mesh, sys)
}

#[test]
fn rotating_cantilever_flap_frequency_matches_southwell_and_exact_table() {
    let (mesh, sys) = spinning_cantilever(MassKind::Consistent);
    let f = inertial_loads(
        &mesh,
        &sys,
        MassKind::Consistent,
        &[InertialLoad::Centrifugal(2, 2)],
    )
    .unwrap();
    let v = static_solve(&sys, &f, &[], "beam").unwrap();
    let col: Vec<f64> = (0..sys.len()).map(|i| v[(i, 0)]).collect();
    let ks = dense(&stress_stiffness_matrix(&mesh, &sys, &col).unwrap());
    let (k, m) = (dense(&sys.k), dense(&sys.m));
    let sec = BeamSection::rectangle(0.02, 0.01);
    // nondimensional speed lambda = Omega sqrt(m L^4 / EI), frequencies likewise
    let scale = (2700.0 * sec.area / (70e9 * sec.iy)).sqrt();
    let flap = |lambda: f64| {
        let om = lambda / scale;
        let kk = Mat::from_fn(k.nrows(), k.ncols(), |i, j| {
            k[(i, j)] + om * om * ks[(i, j)]
        });
        let (w2, _) = dense_generalized(kk.as_ref(), m.as_ref()).unwrap();
        w2[0].sqrt() * scale
    };
    let w0 = flap(0.0);
    assert!((w0 / 3.5160 - 1.0).abs() < 1e-3, "{w0}");
    // Southwell coefficient from a small speed: k1 = (w^2 - w0^2) / lambda^2 = 1.193
    let w1 = flap(1.0);
    let k1 = w1 * w1 - w0 * w0;
    eprintln!("Southwell k1 = {k1:.4}");
    assert!((k1 / 1.193 - 1.0).abs() < 0.01, "{k1}");
    // exact linear rotating-cantilever flap frequencies (Wright, Smith, Thresher, Wang 1982,
    // hub radius 0): lambda = 4 -> 5.5850, lambda = 12 -> 13.1702
    for (lam, exact) in [(4.0, 5.5850), (12.0, 13.1702)] {
        let w = flap(lam);
        eprintln!("lambda {lam}: {w:.4} vs {exact}");
        assert!((w / exact - 1.0).abs() < 2e-3, "{lam}: {w}");
    }
}

#[test]
fn projected_geometric_stiffness_reproduces_the_stiffened_frequency() {
    // 4 cantilever modes, lumped mass (as an FFR body), Omega = 100 rad/s about z:
    // eig(k_red + Omega^2 K_G,zz, m_red) vs the full FE problem
    let (mesh, sys) = spinning_cantilever(MassKind::Lumped);
    let modal = modal_analysis(&sys, 4, &EigenOptions::default(), &mut |_| {}).unwrap();
    let body = reduce_modal(&mesh, &sys, &modal, 4, "beam", Provenance::default()).unwrap();
    let pats = InertialLoad::centrifugal();
    let g = geometric_stiffness(&mesh, &sys, &body, MassKind::Lumped, &pats, &[]).unwrap();
    assert_eq!(g.matrices.len(), 6);
    let om = 100.0;
    let kg = g.centrifugal_matrix([0.0, 0.0, om]);
    let kk = Mat::from_fn(4, 4, |i, j| body.k_red[(i, j)] + kg[(i, j)]);
    let (w2, _) = dense_generalized(kk.as_ref(), body.m_red.as_ref()).unwrap();
    // full problem
    let f = inertial_loads(
        &mesh,
        &sys,
        MassKind::Lumped,
        &[InertialLoad::Centrifugal(2, 2)],
    )
    .unwrap();
    let v = static_solve(&sys, &f, &[], "beam").unwrap();
    let col: Vec<f64> = (0..sys.len()).map(|i| v[(i, 0)]).collect();
    let ks = dense(&stress_stiffness_matrix(&mesh, &sys, &col).unwrap());
    let (k, m) = (dense(&sys.k), dense(&sys.m));
    let kf = Mat::from_fn(k.nrows(), k.ncols(), |i, j| {
        k[(i, j)] + om * om * ks[(i, j)]
    });
    let (w2f, _) = dense_generalized(kf.as_ref(), m.as_ref()).unwrap();
    let rel = (w2[0] / w2f[0]).sqrt() - 1.0;
    eprintln!(
        "first stiffened frequency: 4 modes {:.4}, full {:.4} rad/s ({rel:+.2e})",
        w2[0].sqrt(),
        w2f[0].sqrt()
    );
    // Rayleigh-Ritz on 4 modes (2 flap modes) bounds the frequency from above
    assert!((0.0..5e-3).contains(&rel), "{rel}");
    // only the zz pattern carries axial stress for a beam on the x axis spinning about z; the xx
    // pattern (spin about the beam axis) loads the axis-line nodes with zero force
    let norm = |m: &Mat<f64>| m.norm_max();
    assert!(norm(&g.matrices[0]) < 1e-12 * norm(&g.matrices[5]));
    // symmetric
    for m in &g.matrices {
        for i in 0..4 {
            for j in 0..4 {
                assert!((m[(i, j)] - m[(j, i)]).abs() <= 1e-12 * norm(m));
            }
        }
    }
}

#[test]
fn bad_input_gives_clear_errors() {
    let (mesh, _) = spinning_cantilever(MassKind::Lumped);
    let free = FeSystem::assemble(
        &mesh,
        &BoundaryConditions::default(),
        MassKind::Lumped,
        &mut |_, _| {},
    )
    .unwrap();
    let f = Mat::<f64>::from_fn(free.len(), 1, |i, _| i as f64);
    let err = static_solve(&free, &f, &[], "free body").unwrap_err();
    assert!(matches!(err, GeometricError::NoSupports { .. }), "{err}");
    let err = static_solve(&free, &f, &[999], "free body").unwrap_err();
    assert!(matches!(
        err,
        GeometricError::SupportOutOfRange { node: 999, .. }
    ));
    // the same free body held at its first node works
    assert!(static_solve(&free, &f, &[0], "held").is_ok());
    let err = InertialLoad::Centrifugal(2, 1)
        .acceleration([1.0; 3])
        .unwrap_err();
    assert!(matches!(err, GeometricError::BadPattern { .. }));
}
