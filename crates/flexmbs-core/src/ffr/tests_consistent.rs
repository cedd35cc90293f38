//! Consistent-mass FFR bodies built from a real FE model (built-in hex20 mesh, consistent mass):
//! the invariants against the FE projections and the FFR mass matrix against `L^T M L`.

use super::tests::{jt, mass_matrix, random_state};
use super::*;
use flexmbs_fe::assembly::assemble;
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::generate::box_mesh;
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance, ReducedBody};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{ElementKind, Material, SparseMatrix, UnitSystem};
use nalgebra::DMatrix;

/// A 60 x 10 x 12 mm (SI(mm)) hex20 cantilever (4 x 1 x 2 elements) clamped at x = 0 with
/// consistent mass: its reduced body (6 modes) and the full mass matrix over all nodes.
fn cantilever() -> (ReducedBody, SparseMatrix) {
    let mat = Material::new(210000.0, 0.3, 7.85e-9).unwrap();
    let mesh = box_mesh(
        [60.0, 10.0, 12.0],
        [4, 1, 2],
        ElementKind::Hex20,
        mat,
        UnitSystem::SiMm,
    )
    .unwrap();
    let bc = BoundaryConditions {
        fixed: mesh.node_set("xmin").unwrap().to_vec(),
        rigid: Vec::new(),
    };
    let a = assemble(&mesh, MassKind::Consistent, &[], &mut |_, _| {}).unwrap();
    let sys = FeSystem::from_assembled(&mesh, &a, &bc).unwrap();
    let opts = EigenOptions {
        n_modes: 6,
        ..EigenOptions::default()
    };
    let modal = modal_analysis(&sys, 6, &opts, &mut |_| {}).unwrap();
    let body = reduce_modal(&mesh, &sys, &modal, 6, "cantilever", Provenance::default()).unwrap();
    // a solid mesh: 3 translations per node in node order, so M is already the 3N x 3N matrix
    assert_eq!(a.m.nrows(), 3 * body.num_nodes());
    (body, a.m)
}

fn rel(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).abs().max() / b.abs().max()
}

/// `from_consistent` on the built-in consistent mass: `m_ff` equals the FE projection
/// `Phi^T M Phi` (= identity, mass-normalised modes) to 1e-12, the mass equals rho V and the first
/// moment rho V x_c of the box to 1e-12, and the SI conversion keeps `m_ff` (1e-12) and scales the
/// mass by 1e3 (t -> kg).
#[test]
fn consistent_invariants_match_fe_projection() {
    let (body, m) = cantilever();
    let inv = FfrInvariants::from_consistent(&body.nodes, &m, body.modes_t.as_ref()).unwrap();
    let m_red = DMatrix::from_fn(6, 6, |i, j| body.m_red[(i, j)]);
    let e = rel(&inv.m_ff, &m_red);
    assert!(e < 1e-12, "m_ff vs Phi^T M Phi: {e:e}");
    assert!(rel(&inv.m_ff, &DMatrix::identity(6, 6)) < 1e-9);
    let mass = 7.85e-9 * 60.0 * 10.0 * 12.0;
    assert!((inv.i1 - mass).abs() < 1e-12 * mass, "{} vs {mass}", inv.i1);
    let xc = nalgebra::Vector3::new(30.0, 5.0, 6.0) * mass;
    assert!((inv.i_bar - xc).norm() < 1e-12 * xc.norm());
    let si = reduced_body_to_si(&body);
    let msi = consistent_mass_to_si(&m, body.units);
    let b = FfrBody::from_reduced_consistent(&si, &msi, RotationParam::Cardan).unwrap();
    assert!((b.invariants.i1 - 1e3 * mass).abs() < 1e-12 * 1e3 * mass);
    assert!(rel(&b.invariants.m_ff, &m_red) < 1e-12);
}

/// The FFR mass matrix of the consistent-mass body equals the brute-force `L^T M L` with the
/// stacked node Jacobians `L = [J_T,1; ...; J_T,N]` (2.70) and the full FE mass matrix, at random
/// states (Cardan and quaternions), to 1e-12 relative.
#[test]
fn consistent_mass_matrix_equals_projection_of_fe_mass() {
    let (body, m) = cantilever();
    let si = reduced_body_to_si(&body);
    let msi = consistent_mass_to_si(&m, body.units);
    let dense = DMatrix::from_fn(msi.nrows(), msi.ncols(), |_, _| 0.0);
    let mut dense = dense;
    for c in 0..msi.ncols() {
        for idx in msi.symbolic().col_range(c) {
            dense[(msi.symbolic().row_idx()[idx], c)] += msi.val()[idx];
        }
    }
    let mut seed = 77;
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let b = FfrBody::from_reduced_consistent(&si, &msi, rot).unwrap();
        for _ in 0..3 {
            let (q, u) = random_state(&mut seed, &b, 1e-3);
            let n = b.num_nodes();
            let mut l = DMatrix::zeros(3 * n, b.nu());
            for j in 0..n {
                l.view_mut((3 * j, 0), (3, b.nu()))
                    .copy_from(&jt(&b, j, &q, &u));
            }
            let brute = l.transpose() * &dense * &l;
            let e = rel(&mass_matrix(&b, &q, &u), &brute);
            assert!(e < 1e-12, "{rot:?}: {e:e}");
        }
    }
}
