//! The FFR body as an element of the engine: with zero modes it is exactly the rigid body, and a
//! free, undamped, spinning flexible body conserves energy and angular momentum under the
//! generalized-alpha scheme without numerical damping.

use faer::Mat;
use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam as FfrRot};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::{
    Element, FrameKinematics, LocalFrame, ModelSpec, RigidBody, RotationParam, Workspace,
};
use nalgebra::{Matrix3, Vector3};

/// Eight point masses at the corners of a box centred at the origin (centre of mass at 0).
fn box_nodes() -> (Vec<[f64; 3]>, Vec<f64>) {
    let mut x = Vec::new();
    let mut m = Vec::new();
    for s in [
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ] {
        x.push([0.3 * s[0], 0.1 * s[1], 0.05 * s[2]]);
        m.push(1.5); // equal masses: centre of mass at the origin (the rigid body's reference point)
    }
    (x, m)
}

fn inertia(x: &[[f64; 3]], m: &[f64]) -> Matrix3<f64> {
    let mut j = Matrix3::zeros();
    for (p, &mi) in x.iter().zip(m) {
        let r = Vector3::from(*p);
        j += mi * (r.dot(&r) * Matrix3::identity() - r * r.transpose());
    }
    j
}

fn ffr(
    nodes: &[[f64; 3]],
    masses: &[f64],
    modes: Mat<f64>,
    k: Mat<f64>,
    rot: FfrRot,
) -> FfrElement {
    let inv = FfrInvariants::from_lumped(nodes, masses, modes.as_ref()).unwrap();
    FfrElement::new(FfrBody::new(inv, rot, nodes, modes.as_ref(), None, k.as_ref()).unwrap())
}

#[test]
fn zero_modes_is_exactly_the_rigid_body() {
    let (x, m) = box_nodes();
    let mass: f64 = m.iter().sum();
    for (fr, rr) in [
        (FfrRot::Cardan, RotationParam::Cardan),
        (FfrRot::Quaternion, RotationParam::Quaternion),
    ] {
        let f = ffr(&x, &m, Mat::zeros(24, 0), Mat::zeros(0, 0), fr);
        let r = RigidBody::new(mass, inertia(&x, &m)).with_rotation(rr);
        assert_eq!((f.nq(), f.nu()), (r.nq(), r.nu()));
        let (mut q, mut u) = (vec![0.0; f.nq()], vec![0.0; f.nu()]);
        f.reference_coordinates(&mut q, &mut u);
        let rot = *nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).matrix();
        f.set_pose(&mut q, &Vector3::new(0.1, -0.2, 0.3), &rot);
        f.set_velocity(
            &q,
            &mut u,
            &Vector3::new(0.5, 0.1, -0.3),
            &Vector3::new(1.0, -2.0, 0.7),
        );
        let g = Vector3::new(0.0, 0.0, -9.81);
        let n = f.nu();
        let (mut mf, mut mr) = (Mat::<f64>::zeros(n, n), Mat::<f64>::zeros(n, n));
        let (mut ef, mut er) = (f.evaluated(&q, &u).unwrap(), r.evaluated(&q, &u).unwrap());
        f.mass_matrix(&q, &mut ef, mf.as_mut());
        r.mass_matrix(&q, &mut er, mr.as_mut());
        let scale = mr.norm_max();
        assert!(
            (&mf - &mr).norm_max() <= 1e-12 * scale,
            "{fr:?}: M differs: {mf:?} vs {mr:?}"
        );
        let (mut hf, mut hr) = (vec![0.0; n], vec![0.0; n]);
        f.forces(0.0, &q, &u, &g, &mut ef, &mut hf);
        r.forces(0.0, &q, &u, &g, &mut er, &mut hr);
        let hs = hr.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for i in 0..n {
            assert!(
                (hf[i] - hr[i]).abs() <= 1e-12 * hs,
                "{fr:?}: h[{i}] {} vs {}",
                hf[i],
                hr[i]
            );
        }
        let frame = LocalFrame {
            position: Vector3::new(0.2, 0.1, -0.05),
            rotation: Matrix3::identity(),
            mesh_node: None,
        };
        let (mut kf, mut kr) = (FrameKinematics::new(n), FrameKinematics::new(n));
        f.frame_kinematics(&q, &u, &mut ef, &frame, &mut kf);
        r.frame_kinematics(&q, &u, &mut er, &frame, &mut kr);
        assert!((kf.position - kr.position).norm() < 1e-14);
        assert!((kf.velocity - kr.velocity).norm() < 1e-13);
        assert!((kf.angular_velocity - kr.angular_velocity).norm() < 1e-13);
        assert!((kf.bias_acc - kr.bias_acc).norm() < 1e-12);
        assert!(
            (&kf.jac_t - &kr.jac_t).norm_max() < 1e-14
                && (&kf.jac_r - &kr.jac_r).norm_max() < 1e-14
        );
        assert!(
            (f.kinetic_energy(&q, &u, &mut ef) - r.kinetic_energy(&q, &u, &mut er)).abs()
                < 1e-12 * r.kinetic_energy(&q, &u, &mut er)
        );
    }
}

#[test]
fn free_spinning_flexible_body_conserves_energy_and_angular_momentum() {
    let (x, m) = box_nodes();
    // two smooth "modes": bending-like shapes, mass-normalised enough for a test
    let modes = Mat::from_fn(24, 2, |r, c| {
        let node = r / 3;
        let d = r % 3;
        let p = x[node];
        match (c, d) {
            (0, 1) => 10.0 * p[0] * p[2],
            (1, 2) => p[0] * p[1] * 3.0,
            _ => 0.0,
        }
    });
    let k = Mat::from_fn(2, 2, |i, j| if i == j { [400.0, 900.0][i] } else { 0.0 });
    let f = ffr(&x, &m, modes, k, FfrRot::Quaternion);
    let mut spec = ModelSpec::new();
    let b = spec.add_body("spinner", f);
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let body = &model.bodies[b.0];
    model.set_body_velocity(
        &mut s,
        b,
        Vector3::new(0.1, 0.0, 0.0),
        Vector3::new(0.3, 4.0, 1.0),
    );
    model.body_u_mut(b, &mut s.u)[6..8].copy_from_slice(&[0.05, -0.02]);
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 1.0,
        ..GenAlphaSettings::default()
    })
    .unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let energy = |s: &flexmbs_core::State| {
        let (q, u) = (model.body_q(b, &s.q), model.body_u(b, &s.u));
        let mut e = body.element.evaluated(q, u).unwrap();
        body.element.kinetic_energy(q, u, &mut e) + body.element.elastic_energy(q)
    };
    // angular momentum about the origin: sum_j m_j r_j x v_j from node kinematics
    let momentum = |s: &flexmbs_core::State| {
        let (q, u) = (model.body_q(b, &s.q), model.body_u(b, &s.u));
        let mut l = Vector3::zeros();
        let mut fk = FrameKinematics::for_body(&model, b);
        let mut e = body.element.evaluated(q, u).unwrap();
        for (n, (p, mi)) in x.iter().zip(&m).enumerate() {
            let fr = LocalFrame {
                position: Vector3::from(*p),
                rotation: Matrix3::identity(),
                mesh_node: Some(n),
            };
            body.element.frame_kinematics(q, u, &mut e, &fr, &mut fk);
            l += *mi * fk.position.cross(&fk.velocity);
        }
        l
    };
    let (e0, l0) = (energy(&s), momentum(&s));
    ga.integrate(&model, &mut s, &mut ws, 1e-4, 1.0, |_, _| {})
        .unwrap();
    let (e1, l1) = (energy(&s), momentum(&s));
    let de = (e1 - e0).abs() / e0;
    let dl = (l1 - l0).norm() / l0.norm();
    println!("10^4 steps: energy drift {de:e}, angular momentum drift {dl:e}");
    assert!(de < 1e-6, "energy drift {de:e}");
    assert!(dl < 1e-6, "angular momentum drift {dl:e}");
}
