//! Hundreds of modes at the default tolerance (1e-9 relative residual): the 12k-DOF solid tube of
//! the FFR bench (99 x 1 x 20 hex8i ring sectors, clamped at x = 0) with 100 and 300 modes, and a
//! 400-element beam with 100 modes (the foundation's Lanczos stalled at 5e-8 and 1.8e-2 on these).
//! Every pair is checked by its explicit residual ([`EigenSolution::residuals`]: the residual of
//! the shift-inverted operator, which bounds the eigenvalue error relative to `|lambda - sigma|`),
//! the Sturm count (no eigenvalue missed below the cut) and, for the beam, against the
//! cantilever frequencies of the lowest bending modes (Euler-Bernoulli with the section's rotary
//! inertia, which the consistent beam mass carries). Times are printed (no timed assertion).
//!
//! History (issue 12 item 1): until 2026-11-25 all three failed (tube 100 modes: residual 4.0e-8;
//! tube 300 and beam: `EigenNotConverged`). Causes: the automatic shift `-1e-5 tr(K)/tr(M)` lay
//! 3.5e5 times the first eigenvalue below the beam's spectrum; the residual
//! `|K x - lambda M x| / |lambda M x|` has a round-off floor of `eps |K| |x| / |lambda M x|`
//! (2.2e-5 for the beam's first mode: even the dense solution shows 7.4e-6); and one shift cannot
//! resolve a wanted range of `lambda_100 / lambda_1 = 4e6` (the Krylov relation holds to about
//! `eps ||OP||`, i.e. `eps (lambda - sigma) / (lambda_1 - sigma)` relative for each pair). Now: a
//! shift from the spectrum, the shift-inverted residual per pair, locking and spectrum slicing.

use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::{lowest_modes, EigenEvent, EigenOptions, EigenSolution};
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
    // clamped models: the modal analysis' path (`supported`: K factored at sigma = 0 first)
    let opts = EigenOptions {
        n_modes,
        supported: true,
        ..EigenOptions::default()
    };
    let start = Instant::now();
    // every shift inside the spectrum (a slice) is proved by a Sturm count, as is the final cut
    let mut sturm_counts = 0;
    let sol = lowest_modes(&sys.k, &sys.m, &opts, &mut |e| {
        sturm_counts += usize::from(matches!(e, EigenEvent::SturmCheck { .. }))
    })
    .expect("eigen solution");
    eprintln!(
        "{what}: {n_modes} modes of {} DOFs in {:.2} s, max residual {:.2e}, Sturm {:?}, {} Sturm counts",
        sys.len(),
        start.elapsed().as_secs_f64(),
        sol.residuals.iter().fold(0.0f64, |a, &b| a.max(b)),
        sol.sturm,
        sturm_counts
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
fn tube_100_modes_converge() {
    let sys = tube();
    assert!(sys.len() > 11_000);
    solve(&sys, 100, "tube");
}

#[test]
fn tube_300_modes_converge() {
    solve(&tube(), 300, "tube");
}

#[test]
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
    // Euler-Bernoulli cantilever: omega_k = (beta_k L)^2 sqrt(E I / (rho A L^4)), each twice (two
    // bending planes of the round section). The element's consistent mass carries the section's
    // rotary inertia rho I (a Rayleigh beam), which lowers omega_k by 1e-4 (k = 1) to 2e-3 (k = 3):
    // the reference is the Rayleigh quotient of the exact Euler-Bernoulli mode shape with that
    // rotary inertia in the kinetic energy, omega_k / sqrt(1 + (I/A) int phi'^2 / int phi^2)
    // (first order in (I/A) beta_k^2 / L^2 <= 3.5e-3; the second-order term is below 1e-5). The
    // lowest 3 pairs within 1e-4.
    let (a, i) = (
        std::f64::consts::PI * (r_o * r_o - (r_o - wall).powi(2)),
        std::f64::consts::FRAC_PI_4 * (r_o.powi(4) - (r_o - wall).powi(4)),
    );
    let c = (70e9 * i / (2700.0 * a * l.powi(4))).sqrt();
    for (k, bl) in [1.875_104_069, 4.694_091_133, 7.854_757_438]
        .iter()
        .enumerate()
    {
        let exact = bl * bl * c / (1.0 + i / a * slope_ratio(*bl, l)).sqrt();
        for j in [2 * k, 2 * k + 1] {
            let w = sol.omega2[j].sqrt();
            assert!(
                (w - exact).abs() <= 1e-4 * exact,
                "mode {j}: {w} vs {exact}"
            );
        }
    }
}

/// `int_0^L phi'^2 dx / int_0^L phi^2 dx` of the Euler-Bernoulli cantilever mode with
/// `beta L = bl` (composite Simpson, 20 000 intervals).
fn slope_ratio(bl: f64, l: f64) -> f64 {
    let b = bl / l;
    let s = (bl.cosh() + bl.cos()) / (bl.sinh() + bl.sin());
    let phi = |x: f64| (b * x).cosh() - (b * x).cos() - s * ((b * x).sinh() - (b * x).sin());
    let dphi = |x: f64| b * ((b * x).sinh() + (b * x).sin() - s * ((b * x).cosh() - (b * x).cos()));
    let n = 20_000;
    let h = l / n as f64;
    let simpson = |f: &dyn Fn(f64) -> f64| {
        (0..=n)
            .map(|j| {
                let w = if j == 0 || j == n {
                    1.0
                } else if j % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * f(j as f64 * h)
            })
            .sum::<f64>()
            * h
            / 3.0
    };
    simpson(&|x| dphi(x).powi(2)) / simpson(&|x| phi(x).powi(2))
}
