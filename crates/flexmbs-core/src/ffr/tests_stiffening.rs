//! Geometric stiffening of the FFR body: force and analytic tangent against finite differences,
//! switch-off default, input errors, and the Southwell frequency of a spinning modal coordinate.

use super::tests::{body_of, random_data, random_state, rnd};
use super::*;
use crate::element::{finite_difference_tangents, Element, TangentScratch};
use faer::Mat;
use flexmbs_fe::geometric::{GeometricStiffness, InertialLoad};
use nalgebra::{DMatrix, Vector3};

fn random_geometric(seed: &mut u64, nf: usize) -> GeometricStiffness {
    let pats = InertialLoad::centrifugal();
    let matrices = pats
        .iter()
        .map(|_| {
            let a = Mat::from_fn(nf, nf, |_, _| 3.0 * rnd(seed));
            Mat::from_fn(nf, nf, |i, j| a[(i, j)] + a[(j, i)])
        })
        .collect();
    GeometricStiffness {
        load_patterns: pats,
        matrices,
    }
}

fn fd_tangents(e: &FfrElement, q: &[f64], u: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
    let nu = e.nu();
    let mut dq = DMatrix::zeros(nu, nu);
    let mut du = DMatrix::zeros(nu, nu);
    let mut s = TangentScratch::new(e);
    finite_difference_tangents(
        e,
        0.0,
        q,
        u,
        &Vector3::new(0.0, 0.0, -9.81),
        body::faer_view_mut(&mut dq),
        body::faer_view_mut(&mut du),
        &mut s,
    );
    (dq, du)
}

#[test]
fn stiffening_force_and_tangent_match_finite_differences() {
    let mut seed = 17u64;
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let d = random_data(&mut seed, 7, 4, 0.2);
        let plain = body_of(&d, rot, true);
        let g = random_geometric(&mut seed, 4);
        let stiff = plain.clone().with_geometric_stiffening(&g).unwrap();
        let (q, u) = random_state(&mut seed, &plain, 0.3);
        // force: -K_geo(omega_bar) q_f with omega_bar from the update
        let mut s = FfrScratch::new(4);
        stiff.update(&q, &u, &mut s).unwrap();
        let mut h = vec![0.0; stiff.nu()];
        stiff.add_geometric_stiffening_force(&s, &mut h);
        let kg = stiff.geometric_stiffness_matrix(&s.omega);
        let want = -(&kg * &s.qf);
        for i in 0..4 {
            assert!((h[6 + i] - want[i]).abs() < 1e-12 * want.amax());
        }
        assert!(h[..6].iter().all(|&x| x == 0.0));
        // tangent: FD of (element with) - (element without) vs analytic
        let (dq1, du1) = fd_tangents(&FfrElement::new(stiff.clone()), &q, &u);
        let (dq0, du0) = fd_tangents(&FfrElement::new(plain.clone()), &q, &u);
        let nu = stiff.nu();
        let mut aq = DMatrix::zeros(nu, nu);
        let mut au = DMatrix::zeros(nu, nu);
        stiff.add_geometric_stiffening_tangent(
            &q,
            &u,
            &s,
            body::faer_view_mut(&mut aq),
            body::faer_view_mut(&mut au),
        );
        let (fq, fu) = (dq1 - dq0, du1 - du0);
        let scale = aq.amax().max(au.amax());
        let err = (&fq - &aq).amax().max((&fu - &au).amax()) / scale;
        eprintln!("{rot:?}: tangent error {err:.2e} (scale {scale:.3e})");
        assert!(err < 1e-6, "{rot:?}: {err}");
        // the omega dependence is really exercised
        assert!(au.rows(6, 4).columns(3, 3).amax() > 1e-2 * scale);
        if rot == RotationParam::Cardan {
            assert!(aq.rows(6, 4).columns(3, 3).amax() > 1e-3 * scale);
        }
    }
}

#[test]
fn stiffening_is_off_by_default_and_rejects_bad_input() {
    let mut seed = 5u64;
    let d = random_data(&mut seed, 5, 3, 0.2);
    let plain = body_of(&d, RotationParam::Cardan, false);
    assert!(plain.geometric_stiffening().is_none());
    let (q, u) = random_state(&mut seed, &plain, 0.3);
    let mut s = FfrScratch::new(3);
    plain.update(&q, &u, &mut s).unwrap();
    let mut h = vec![0.0; plain.nu()];
    plain.add_geometric_stiffening_force(&s, &mut h);
    assert!(h.iter().all(|&x| x == 0.0));
    // wrong size
    let g = random_geometric(&mut seed, 4);
    let err = plain.clone().with_geometric_stiffening(&g).unwrap_err();
    assert!(
        matches!(
            err,
            FfrError::DimensionMismatch {
                expected: 3,
                found: 4,
                ..
            }
        ),
        "{err}"
    );
    // non-centrifugal pattern
    let g = GeometricStiffness {
        load_patterns: vec![InertialLoad::Translation(0)],
        matrices: vec![Mat::zeros(3, 3)],
    };
    let err = plain.with_geometric_stiffening(&g).unwrap_err();
    assert!(
        matches!(err, FfrError::UnsupportedLoadPattern { .. }),
        "{err}"
    );
}

#[test]
fn spinning_modal_coordinate_oscillates_at_the_southwell_frequency() {
    // one node of mass m at x = (1, 0, 0) moving in y (one mode, phi = 1/sqrt(m)), k = w0^2,
    // frame spinning at Omega about z: linearized q'' = -(w0^2 - Omega^2 + Omega^2 k_g) q
    // (spin softening from Q_v, stiffening from K_G); checked through the body's accelerations
    let (m, w0, om, kg): (f64, f64, f64, f64) = (2.0, 30.0, 20.0, 1.193);
    let u0 = [[1.0, 0.0, 0.0]];
    let modes = Mat::from_fn(3, 1, |i, _| if i == 1 { 1.0 / m.sqrt() } else { 0.0 });
    let inv = FfrInvariants::from_lumped(&u0, &[m], modes.as_ref()).unwrap();
    let k = Mat::from_fn(1, 1, |_, _| w0 * w0);
    let body = FfrBody::new(
        inv,
        RotationParam::Quaternion,
        &u0,
        modes.as_ref(),
        None,
        k.as_ref(),
    )
    .unwrap();
    let g = GeometricStiffness {
        load_patterns: vec![InertialLoad::Centrifugal(2, 2)],
        matrices: vec![Mat::from_fn(1, 1, |_, _| kg)],
    };
    let body = body.with_geometric_stiffening(&g).unwrap();
    // the modal acceleration of the constrained problem (frame at constant spin): read the f row
    // of the force vector, M_ff = 1
    let mut s = FfrScratch::new(1);
    let eps = 1e-6;
    let q = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, eps];
    let u = [0.0, 0.0, 0.0, 0.0, 0.0, om, 0.0];
    body.update(&q, &u, &mut s).unwrap();
    let mut h = [0.0; 7];
    body.quadratic_velocity(&s, &mut h);
    body.add_internal_forces(&s, &mut h);
    let stiffness = -h[6] / eps;
    let want = w0 * w0 - om * om + om * om * kg;
    assert!(
        (stiffness / want - 1.0).abs() < 1e-9,
        "{stiffness} vs {want}"
    );
}

/// The element's analytic tangent (`ffr/tangent.rs`, including the stiffening terms) equals the
/// finite-difference tangent of the stiffened element.
#[test]
fn analytic_element_tangent_includes_stiffening() {
    let mut seed = 29u64;
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let d = random_data(&mut seed, 7, 4, 0.2);
        let plain = body_of(&d, rot, true);
        let g = random_geometric(&mut seed, 4);
        let stiff = plain.clone().with_geometric_stiffening(&g).unwrap();
        let (q, u) = random_state(&mut seed, &plain, 0.3);
        let e = FfrElement::new(stiff);
        let (fq, fu) = fd_tangents(&e, &q, &u);
        let nu = e.nu();
        let mut aq = DMatrix::zeros(nu, nu);
        let mut au = DMatrix::zeros(nu, nu);
        let mut ts = TangentScratch::new(&e);
        let mut ev = e.evaluated(&q, &u).unwrap();
        e.force_tangents(
            0.0,
            &q,
            &u,
            &Vector3::new(0.0, 0.0, -9.81),
            &mut ev,
            body::faer_view_mut(&mut aq),
            body::faer_view_mut(&mut au),
            &mut ts,
        );
        let scale = fq.amax().max(fu.amax());
        let err = (&fq - &aq).amax().max((&fu - &au).amax()) / scale;
        eprintln!("{rot:?}: element tangent error {err:.2e} (scale {scale:.3e})");
        assert!(err < 1e-6, "{rot:?}: {err}");
    }
}
