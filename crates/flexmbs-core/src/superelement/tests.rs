//! Unit tests of the superelement: frame recovery, mass, tangent = finite differences.

use super::*;
use crate::element::{finite_difference_tangents, Element, TangentScratch};
use faer::Mat;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{Rotation3, Vector3};

/// The tube of `benchmarks.md` (seed 001), segment of length `l`.
pub(super) fn tube_segment(
    l: f64,
    internal_modes: usize,
    frame: FrameLocation,
) -> SuperelementData {
    beam_segment(&BeamSegmentSpec {
        length: l,
        material: Material {
            e: 70e9,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements: 4,
        internal_modes,
        frame,
    })
    .unwrap()
}

/// A deformed state: interface `k` displaced and rotated by 0.1-1 rad.
fn deformed_state(se: &Superelement, l: f64) -> (Vec<f64>, Vec<f64>) {
    let (mut q, mut u) = (vec![0.0; se.nq()], vec![0.0; se.nu()]);
    se.reference_coordinates(&mut q, &mut u);
    let base = Rotation3::from_scaled_axis(Vector3::new(0.3, -0.7, 0.5));
    se.set_pose(&mut q, &Vector3::new(0.2, -0.1, 0.4), base.matrix());
    let rots = [Vector3::new(0.1, 0.25, -0.4), Vector3::new(-0.3, 0.5, 0.6)];
    let offs = [
        Vector3::new(0.01, -0.02, 0.015) * l,
        Vector3::new(-0.03, 0.05, 0.02) * l,
    ];
    for k in 0..2 {
        let o = se.q_offset[k];
        let p = crate::NodeKind::Pose;
        let r = p.rotation(&q[o..o + 7]) * Rotation3::from_scaled_axis(rots[k]).matrix();
        let x = Vector3::new(q[o], q[o + 1], q[o + 2]) + offs[k];
        p.set_pose(&mut q[o..o + 7], &x, &r);
    }
    for i in 0..se.data.internal_modes {
        q[se.q_eta + i] = 1e-3 * (i as f64 + 1.0);
    }
    (q, u)
}

fn check_tangent(se: &Superelement, gravity: Vector3<f64>) -> f64 {
    let (q, u) = deformed_state(se, 0.3);
    let mut s = se.evaluated(&q, &u).unwrap();
    let n = se.nu();
    let (mut a, mut a_u) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
    let (mut f, mut f_u) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
    let mut fd = TangentScratch::new(se);
    se.force_tangents(
        0.0,
        &q,
        &u,
        &gravity,
        &mut s,
        a.as_mut(),
        a_u.as_mut(),
        &mut fd,
    );
    finite_difference_tangents(se, 0.0, &q, &u, &gravity, f.as_mut(), f_u.as_mut(), &mut fd);
    let (mut err, mut scale) = (0.0_f64, 0.0_f64);
    for i in 0..n {
        for j in 0..n {
            err = err.max((a[(i, j)] - f[(i, j)]).abs());
            scale = scale.max(f[(i, j)].abs());
        }
    }
    err / scale
}

#[test]
fn frame_recovery_satisfies_the_frame_condition_at_a_deformed_state() {
    for frame in [FrameLocation::CentreOfMass, FrameLocation::FirstInterface] {
        let se = Superelement::new(tube_segment(0.3, 2, frame)).unwrap();
        let (q, u) = deformed_state(&se, 0.3);
        let mut s = se.evaluated(&q, &u).unwrap();
        let e = s.get_mut::<SuperelementEval>();
        let c = &se.data.phi_cb * &e.q_loc;
        assert!(c.amax() < 1e-14, "{c}");
        assert!(e.iterations <= 6, "{} iterations", e.iterations);
    }
}

#[test]
fn rigid_placement_has_no_deformation_and_the_mass_of_the_tube() {
    let se = Superelement::new(tube_segment(0.3, 2, FrameLocation::CentreOfMass)).unwrap();
    let (mut q, mut u) = (vec![0.0; se.nq()], vec![0.0; se.nu()]);
    se.reference_coordinates(&mut q, &mut u);
    let r = Rotation3::from_scaled_axis(Vector3::new(0.4, 1.1, -0.3));
    se.set_pose(&mut q, &Vector3::new(1.0, 2.0, 3.0), r.matrix());
    let mut s = se.evaluated(&q, &u).unwrap();
    let e = s.get_mut::<SuperelementEval>();
    assert!(e.q_loc.amax() < 1e-14);
    assert!((e.x_j - Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-14);
    // m = rho A L
    let a = std::f64::consts::PI * (0.01f64.powi(2) - 0.009f64.powi(2));
    assert!((se.mass() - 2700.0 * a * 0.3).abs() < 1e-12 * se.mass());
}

/// The exact and approximated matrices give different forces at a deformed state (so the
/// tangent test below checks two different functions).
#[test]
fn exact_and_approximated_forces_differ_at_a_deformed_state() {
    let data = tube_segment(0.3, 0, FrameLocation::CentreOfMass);
    let forces = |m: TransformMatrices| {
        let se = Superelement::new(data.clone()).unwrap().with_matrices(m);
        let (q, u) = deformed_state(&se, 0.3);
        let mut s = se.evaluated(&q, &u).unwrap();
        let mut h = vec![0.0; se.nu()];
        se.forces(0.0, &q, &u, &Vector3::zeros(), &mut s, &mut h);
        nalgebra::DVector::from_vec(h)
    };
    let (a, b) = (
        forces(TransformMatrices::Exact),
        forces(TransformMatrices::Approximated),
    );
    let rel = (&a - &b).amax() / a.amax();
    assert!(rel > 1e-3, "{rel:e}");
}

#[test]
fn tangent_equals_finite_difference_jacobian() {
    let g = Vector3::new(0.0, -9.81, 3.0);
    for matrices in [TransformMatrices::Exact, TransformMatrices::Approximated] {
        for modes in [0, 2] {
            for frame in [FrameLocation::CentreOfMass, FrameLocation::FirstInterface] {
                let se = Superelement::new(tube_segment(0.3, modes, frame))
                    .unwrap()
                    .with_matrices(matrices);
                let rel = check_tangent(&se, g);
                println!("{matrices:?} modes {modes} {frame:?}: {rel:e}");
                assert!(rel < 1e-6, "{matrices:?} modes {modes} {frame:?}: {rel:e}");
            }
        }
    }
}

/// The fictitious forces of `T = ½ vᵀ M(q) v` satisfy the power identity of the Lagrange
/// equations, `vᵀ h_C = −½ vᵀ (dM/dt) v` (gyroscopic part does no work), with `dM/dt` by
/// central differences along `q ⊕ ±ε v`.
#[test]
fn fictitious_forces_satisfy_the_power_identity() {
    let data = tube_segment(0.3, 2, FrameLocation::CentreOfMass);
    let with = Superelement::new(data.clone())
        .unwrap()
        .with_fictitious_forces(FictitiousForces::FromMcb);
    let without = Superelement::new(data).unwrap();
    let (q, _) = deformed_state(&with, 0.3);
    let n = with.nu();
    let u: Vec<f64> = (0..n).map(|i| ((i * 7 % 11) as f64 - 5.0) * 0.3).collect();
    let g = Vector3::zeros();
    let h_of = |se: &Superelement| {
        let mut s = se.evaluated(&q, &u).unwrap();
        let mut h = vec![0.0; n];
        se.forces(0.0, &q, &u, &g, &mut s, &mut h);
        h
    };
    let (h1, h0) = (h_of(&with), h_of(&without));
    let power: f64 = (0..n).map(|i| u[i] * (h1[i] - h0[i])).sum();
    let ke = |dq: f64| {
        let dv: Vec<f64> = u.iter().map(|x| x * dq).collect();
        let mut qp = vec![0.0; q.len()];
        with.integrate_position(&q, &dv, &mut qp);
        let mut s = with.evaluated(&qp, &u).unwrap();
        with.kinetic_energy(&qp, &u, &mut s)
    };
    let eps = 1e-6;
    let dt_m = (ke(eps) - ke(-eps)) / (2.0 * eps); // ½ vᵀ (dM/dt) v
    println!("vᵀ h_C = {power:e}, −½ vᵀ Ṁ v = {:e}", -dt_m);
    assert!(
        (power + dt_m).abs() < 1e-6 * dt_m.abs().max(1e-3),
        "{power} vs {}",
        -dt_m
    );
}

/// One interface point with the floating frame on it is a rigid body: with
/// [`FictitiousForces::FromMcb`] the forces are the exact rigid-body velocity terms about a point
/// off the centre of mass, `h_t = −m R (ω̄ × (ω̄ × c))`, `h_r = −ω̄ × J ω̄` (`J` about the point).
#[test]
fn one_interface_point_is_a_rigid_body_with_exact_gyroscopic_forces() {
    use nalgebra::{DMatrix, Matrix3};
    let (m, c) = (2.5, Vector3::new(0.3, -0.1, 0.2));
    let j_c = Matrix3::new(0.4, 0.05, -0.02, 0.05, 0.3, 0.01, -0.02, 0.01, 0.2);
    let cs = crate::rotation::skew(&c);
    let j = j_c - m * cs * cs; // about the point
    let mut m_cb = DMatrix::zeros(6, 6);
    m_cb.view_mut((0, 0), (3, 3))
        .copy_from(&(Matrix3::identity() * m));
    m_cb.view_mut((0, 3), (3, 3)).copy_from(&(-m * cs));
    m_cb.view_mut((3, 0), (3, 3)).copy_from(&(m * cs));
    m_cb.view_mut((3, 3), (3, 3)).copy_from(&j);
    let data = SuperelementData {
        interfaces: vec![Interface {
            position: Vector3::zeros(),
            rotation: Matrix3::identity(),
        }],
        internal_modes: 0,
        m_cb,
        k_cb: DMatrix::zeros(6, 6),
        phi_cb: DMatrix::identity(6, 6),
        centre_of_mass: c,
    };
    let se = Superelement::new(data)
        .unwrap()
        .with_fictitious_forces(FictitiousForces::FromMcb);
    let (mut q, mut u) = (vec![0.0; 7], vec![0.0; 6]);
    let r = Rotation3::from_scaled_axis(Vector3::new(0.3, -0.8, 0.5));
    se.set_pose(&mut q, &Vector3::new(1.0, 2.0, -1.0), r.matrix());
    u.copy_from_slice(&[0.4, -1.0, 2.0, 3.0, -5.0, 7.0]);
    let mut s = se.evaluated(&q, &u).unwrap();
    let mut h = vec![0.0; 6];
    se.forces(0.0, &q, &u, &Vector3::zeros(), &mut s, &mut h);
    let w = Vector3::new(u[3], u[4], u[5]);
    let h_t = -m * r.matrix() * w.cross(&w.cross(&c));
    let h_r = -w.cross(&(j * w));
    let exact = [h_t[0], h_t[1], h_t[2], h_r[0], h_r[1], h_r[2]];
    for i in 0..6 {
        assert!(
            (h[i] - exact[i]).abs() < 1e-12 * 100.0,
            "{h:?} vs {exact:?}"
        );
    }
}

/// Exact matrices: the elastic forces are minus the gradient of `½ q_locᵀ K_CB q_loc` along
/// `q ⊕ dv` (central differences).
#[test]
fn exact_elastic_forces_are_the_gradient_of_the_strain_energy() {
    let se = Superelement::new(tube_segment(0.3, 2, FrameLocation::CentreOfMass)).unwrap();
    let (q, u) = deformed_state(&se, 0.3);
    let n = se.nu();
    let mut s = se.evaluated(&q, &u).unwrap();
    let mut h = vec![0.0; n];
    se.forces(0.0, &q, &u, &Vector3::zeros(), &mut s, &mut h);
    let scale = h.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
    for j in 0..n {
        let energy = |e: f64| {
            let mut dv = vec![0.0; n];
            dv[j] = e;
            let mut qp = vec![0.0; q.len()];
            se.integrate_position(&q, &dv, &mut qp);
            se.elastic_energy(&qp)
        };
        let grad = (energy(1e-6) - energy(-1e-6)) / 2e-6;
        assert!(
            (h[j] + grad).abs() < 1e-6 * scale,
            "{j}: {} vs {}",
            h[j],
            -grad
        );
    }
}

/// Bad data and unevaluable states give typed errors.
#[test]
fn bad_input_gives_typed_errors() {
    let good = tube_segment(0.3, 0, FrameLocation::CentreOfMass);
    let mut d = good.clone();
    d.phi_cb.fill(0.0);
    assert!(matches!(
        Superelement::new(d),
        Err(SuperelementError::SingularFrameCondition { .. })
    ));
    let mut d = good.clone();
    d.m_cb = nalgebra::DMatrix::zeros(6, 6);
    assert!(matches!(
        Superelement::new(d),
        Err(SuperelementError::Dimension { what: "M_CB", .. })
    ));
    let mut d = good.clone();
    d.k_cb[(0, 1)] += 1.0;
    assert!(matches!(
        Superelement::new(d),
        Err(SuperelementError::NotSymmetric { what: "K_CB" })
    ));
    let mut d = good.clone();
    d.interfaces.clear();
    assert!(matches!(
        Superelement::new(d),
        Err(SuperelementError::NoInterface)
    ));
    let se = Superelement::new(good).unwrap();
    let (mut q, u) = deformed_state(&se, 0.3);
    q[0] = f64::NAN;
    assert!(matches!(
        se.evaluated(&q, &u),
        Err(crate::ElementError::InternalSolve { .. })
    ));
}

/// Three interface points (a beam with interfaces at x = 0, L/4, L, floating frame at the centre
/// of mass, an interior FE node): rigid placement is undeformed, the frame condition holds at a
/// deformed state, and the tangent equals the finite-difference Jacobian (exact and approximated).
#[test]
fn three_interface_points() {
    use flexmbs_fe::element::MassKind;
    let spec = BeamSegmentSpec {
        length: 0.4,
        material: Material {
            e: 70e9,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements: 4,
        internal_modes: 1,
        frame: FrameLocation::CentreOfMass,
    };
    let (data, _, _) =
        beam_segment_with_interfaces(&spec, MassKind::Consistent, &[0, 1, 4]).unwrap();
    assert_eq!(data.interfaces.len(), 3);
    for matrices in [TransformMatrices::Exact, TransformMatrices::Approximated] {
        let se = Superelement::new(data.clone())
            .unwrap()
            .with_matrices(matrices);
        assert_eq!(se.nu(), 19);
        let (mut q, mut u) = (vec![0.0; se.nq()], vec![0.0; se.nu()]);
        se.reference_coordinates(&mut q, &mut u);
        let r = Rotation3::from_scaled_axis(Vector3::new(0.2, -0.9, 0.4));
        se.set_pose(&mut q, &Vector3::new(0.3, 0.1, -0.2), r.matrix());
        let mut s = se.evaluated(&q, &u).unwrap();
        assert!(s.get_mut::<SuperelementEval>().q_loc.amax() < 1e-14);
        // deform: move and turn every interface
        for k in 0..3 {
            let o = se.q_offset[k];
            let p = crate::NodeKind::Pose;
            let turn = Rotation3::from_scaled_axis(Vector3::new(0.1, 0.2 * k as f64, -0.3));
            let rk = p.rotation(&q[o..o + 7]) * turn.matrix();
            let xk = Vector3::new(q[o], q[o + 1], q[o + 2])
                + Vector3::new(0.004, -0.006, 0.003) * k as f64;
            p.set_pose(&mut q[o..o + 7], &xk, &rk);
        }
        let mut s = se.evaluated(&q, &u).unwrap();
        let c = &se.data.phi_cb * &s.get_mut::<SuperelementEval>().q_loc;
        assert!(c.amax() < 1e-13, "{c}");
        let n = se.nu();
        let (mut a, mut a_u) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
        let (mut f, mut f_u) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
        let g = Vector3::new(0.0, -9.81, 0.0);
        let mut fd = TangentScratch::new(&se);
        se.force_tangents(0.0, &q, &u, &g, &mut s, a.as_mut(), a_u.as_mut(), &mut fd);
        finite_difference_tangents(&se, 0.0, &q, &u, &g, f.as_mut(), f_u.as_mut(), &mut fd);
        let (mut err, mut scale) = (0.0_f64, 0.0_f64);
        for i in 0..n {
            for j in 0..n {
                err = err.max((a[(i, j)] - f[(i, j)]).abs());
                scale = scale.max(f[(i, j)].abs());
            }
        }
        println!("{matrices:?}: {:e}", err / scale);
        assert!(err < 1e-6 * scale, "{matrices:?}: {:e}", err / scale);
    }
}

/// The round-off of the elastic forces from absolute coordinates: a rigidly placed 0.1 m segment
/// has `|q_loc| = 4e-17` at x = 0.55 m (0.55 ± 0.05 are not exact in binary), so `|h| ~ K eps |x|
/// = 3.5e-9 N`; at the origin it is exactly zero. (Documented floor: docs/decisions.md.)
#[test]
fn elastic_force_round_off_of_absolute_coordinates() {
    let se = Superelement::new(tube_segment(0.1, 0, FrameLocation::CentreOfMass)).unwrap();
    let h_at = |x: f64| {
        let (mut q, mut u) = (vec![0.0; se.nq()], vec![0.0; se.nu()]);
        se.reference_coordinates(&mut q, &mut u);
        se.set_pose(
            &mut q,
            &Vector3::new(x, 0.0, 0.0),
            &nalgebra::Matrix3::identity(),
        );
        let mut s = se.evaluated(&q, &u).unwrap();
        let mut h = vec![0.0; se.nu()];
        se.forces(0.0, &q, &u, &Vector3::zeros(), &mut s, &mut h);
        h.iter().fold(0.0_f64, |a, b| a.max(b.abs()))
    };
    assert_eq!(h_at(0.0), 0.0);
    let k_axial = se.data().k_cb.amax();
    let floor = h_at(0.55);
    println!(
        "|h| at 0.55 m: {floor:e} N, K eps |x| = {:e}",
        k_axial * f64::EPSILON * 0.55
    );
    assert!(floor > 0.0 && floor < 4.0 * k_axial * f64::EPSILON * 0.55);
}
