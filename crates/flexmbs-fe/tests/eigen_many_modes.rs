//! Hundreds of modes at the default tolerance (1e-9 relative residual): the 12k-DOF solid tube of
//! the FFR bench (99 x 1 x 20 hex8i ring sectors, clamped at x = 0) with 100 and 300 modes, and a
//! 400-element beam with 100 modes (the foundation's Lanczos stalled at 5e-8 and 1.8e-2 on these).
//! Every pair is checked by its explicit residual `|K x - lambda M x| / |lambda M x|`, the Sturm
//! count (no eigenvalue missed below the cut) and, for the beam, against the Euler-Bernoulli
//! cantilever frequencies of the lowest bending modes. Times are printed (no timed assertion).
//!
//! **Open (issue 12 item 1):** all three fail today and are therefore ignored, so that a run with
//! `--ignored` shows the state: measured 2026-11-25, tube 100 modes: max residual 4.0e-8 (Sturm
//! count right, 19.6 s on a loaded machine); tube 300 modes and beam 100 modes:
//! `EigenNotConverged` (beam: explicit residual 0.20 while the Ritz estimates had converged). A
//! first diagnosis on the beam: the automatic shift `-1e-5 tr(K)/tr(M)` is about -5e9 (the
//! diagonal ratio estimates the highest element frequencies, not the lowest), 3.5e5 times the
//! first eigenvalue 1.45e4, so the low modes are clustered under shift-invert and the residual,
//! normalised by `|lambda| + |sigma|`, is loose for them (at tol 1e-6 the first pair is 3.7e-6 off
//! the dense solution's eigenvalue). The block Lanczos needs a shift from the spectrum (e.g. an
//! inverse-iteration estimate of the lowest eigenvalue), a restart with locking, and a residual
//! test on each pair's own scale before these pass.

use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::{lowest_modes, EigenOptions, EigenSolution};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate::beam_line;
use flexmbs_fe::mesh::tube::tube_mesh;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{ElementKind, Material, Mesh, UnitSystem};
use std::time::Instant;

fn aluminium() -> Material {
    Material {
        e: 70e9,
        nu: 0.3,
        rho: 2700.0,
    }
}

fn clamped_system(mesh: &Mesh, set: &str, mass: MassKind) -> FeSystem {
    let bc = BoundaryConditions {
        fixed: mesh.node_set(set).expect("clamped set").to_vec(),
        rigid: Vec::new(),
    };
    FeSystem::assemble(mesh, &bc, mass, &mut |_, _| {}).expect("assembly")
}

fn solve(sys: &FeSystem, n_modes: usize, what: &str) -> EigenSolution {
    let opts = EigenOptions {
        n_modes,
        ..EigenOptions::default()
    };
    let start = Instant::now();
    let sol = lowest_modes(&sys.k, &sys.m, &opts, &mut |_| {}).expect("eigen solution");
    eprintln!(
        "{what}: {n_modes} modes of {} DOFs in {:.2} s, max residual {:.2e}, Sturm {:?}",
        sys.len(),
        start.elapsed().as_secs_f64(),
        sol.residuals.iter().fold(0.0f64, |a, &b| a.max(b)),
        sol.sturm
    );
    assert_eq!(sol.omega2.len(), n_modes);
    for (i, r) in sol.residuals.iter().enumerate() {
        assert!(*r <= 1e-9, "{what}: mode {} residual {r:e}", i + 1);
    }
    let (below, found) = sol.sturm.expect("Sturm check made");
    assert_eq!(below, found, "{what}: Sturm count");
    assert!(below >= n_modes);
    assert!(sol.omega2.windows(2).all(|w| w[0] <= w[1]));
    sol
}

fn tube() -> FeSystem {
    let mesh = tube_mesh(
        1.0,
        0.01,
        0.009,
        [99, 1, 20],
        ElementKind::Hex8I,
        aluminium(),
        UnitSystem::Si,
    )
    .expect("tube mesh");
    clamped_system(&mesh, "xmin", MassKind::Consistent)
}

#[test]
#[ignore = "fails today: max residual 4.0e-8 > 1e-9 (open, issue 12 item 1)"]
fn tube_100_modes_converge() {
    let sys = tube();
    assert!(sys.len() > 11_000);
    solve(&sys, 100, "tube");
}

#[test]
#[ignore = "fails today: EigenNotConverged (open, issue 12 item 1)"]
fn tube_300_modes_converge() {
    solve(&tube(), 300, "tube");
}

#[test]
#[ignore = "fails today: explicit residual 0.2 (automatic shift far below the spectrum; open, issue 12 item 1)"]
fn beam_400_elements_100_modes_converge() {
    let (l, r_o, wall) = (1.0, 0.01, 0.001);
    let mesh = beam_line(
        [0.0; 3],
        [l, 0.0, 0.0],
        400,
        BeamSection::tube(r_o, wall),
        BeamTheory::EulerBernoulli,
        [0.0, 1.0, 0.0],
        aluminium(),
        UnitSystem::Si,
    )
    .expect("beam mesh");
    let sys = clamped_system(&mesh, "start", MassKind::Consistent);
    let sol = solve(&sys, 100, "beam");
    // Euler-Bernoulli cantilever: omega_k = (beta_k L)^2 sqrt(E I / (rho A L^4)), each twice
    // (two bending planes of the round section): the lowest 3 pairs within 1e-4
    let (a, i) = (
        std::f64::consts::PI * (r_o * r_o - (r_o - wall).powi(2)),
        std::f64::consts::FRAC_PI_4 * (r_o.powi(4) - (r_o - wall).powi(4)),
    );
    let c = (70e9 * i / (2700.0 * a * l.powi(4))).sqrt();
    for (k, bl) in [1.875_104_069, 4.694_091_133, 7.854_757_438]
        .iter()
        .enumerate()
    {
        let exact = bl * bl * c;
        for j in [2 * k, 2 * k + 1] {
            let w = sol.omega2[j].sqrt();
            assert!(
                (w - exact).abs() <= 1e-4 * exact,
                "mode {j}: {w} vs {exact}"
            );
        }
    }
}
