//! Torque-free rigid body: conservation of energy and angular momentum.
use flexmbs_core::integrator::{Dopri5, Dopri5Settings, GenAlpha, GenAlphaSettings};
use flexmbs_core::*;
use nalgebra::{Matrix3, Vector3};

fn free_body(rotation: RotationParam, omega: Vector3<f64>) -> (Model, State, BodyId) {
    let mut spec = ModelSpec::new();
    let inertia = Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0));
    let body = spec.add_body("body", RigidBody::new(2.0, inertia).with_rotation(rotation));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let r0 = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 0.5).into_inner();
    model.set_body_pose(&mut s, body, Vector3::new(1.0, 2.0, 3.0), r0);
    model.set_body_velocity(&mut s, body, Vector3::new(0.1, 0.0, -0.2), r0 * omega);
    (model, s, body)
}

fn momentum(model: &Model, s: &State, body: BodyId) -> Vector3<f64> {
    let rb = RigidBody::new(2.0, Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)))
        .with_rotation(if model.nq == 7 {
            RotationParam::Quaternion
        } else {
            RotationParam::Cardan
        });
    rb.angular_momentum(model.body_q(body, &s.q), model.body_u(body, &s.u))
}

/// DOPRI5 at rtol = atol = 1e-12 over 20 s: energy and |L - L0| / |L0| below 1e-8.
#[test]
fn dopri5_conserves_energy_and_angular_momentum() {
    for rot in [RotationParam::Quaternion, RotationParam::Cardan] {
        let (model, mut s, body) = free_body(rot, Vector3::new(0.4, 0.3, 0.6));
        let mut ws = Workspace::new(&model);
        let e0 = flexmbs_core::integrator::monitor(&model, &s, &mut ws)
            .0
            .total();
        let l0 = momentum(&model, &s, body);
        let d = Dopri5::new(Dopri5Settings {
            rtol: 1e-12,
            atol: 1e-12,
            ..Default::default()
        });
        let (mut de, mut dl): (f64, f64) = (0.0, 0.0);
        d.integrate(&model, &mut s, &mut ws, 20.0, |s, st| {
            de = de.max((st.energy.total() - e0).abs() / e0);
            dl = dl.max((momentum(&model, s, body) - l0).norm() / l0.norm());
        })
        .unwrap();
        println!("{rot:?}: energy {de:e}, momentum {dl:e}");
        assert!(de < 1e-8 && dl < 1e-8, "{rot:?}: {de} {dl}");
    }
}

/// Generalized-alpha with rho_inf = 1 (h = 1e-3, 20 s, quaternion/exponential map): energy and
/// angular-momentum errors stay below 1e-4 and do not grow (second half <= 2 x first half + 1e-9).
#[test]
fn generalized_alpha_drift_is_bounded() {
    let (model, mut s, body) = free_body(RotationParam::Quaternion, Vector3::new(0.4, 0.3, 0.6));
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf: 1.0,
        ..Default::default()
    })
    .unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let e0 = flexmbs_core::integrator::monitor(&model, &s, &mut ws)
        .0
        .total();
    let l0 = momentum(&model, &s, body);
    let mut errs = Vec::new();
    ga.integrate(&model, &mut s, &mut ws, 1e-3, 20.0, |s, st| {
        errs.push((
            (st.energy.total() - e0).abs() / e0,
            (momentum(&model, s, body) - l0).norm() / l0.norm(),
        ));
    })
    .unwrap();
    let half = errs.len() / 2;
    let max = |v: &[(f64, f64)]| {
        v.iter()
            .fold((0.0_f64, 0.0_f64), |m, e| (m.0.max(e.0), m.1.max(e.1)))
    };
    let (a, b) = (max(&errs[..half]), max(&errs[half..]));
    println!("first half {a:?}, second half {b:?}");
    assert!(b.0 < 1e-4 && b.1 < 1e-4);
    assert!(b.0 <= 2.0 * a.0 + 1e-9 && b.1 <= 2.0 * a.1 + 1e-9);
}

/// Dzhanibekov effect: spin about the intermediate axis (I = 2) with a 1e-3 perturbation
/// flips (body-frame omega_y changes sign) within 30 s; spin about the major axis does not.
#[test]
fn intermediate_axis_is_unstable() {
    for (omega, flips) in [
        (Vector3::new(1e-3, 1.0, 1e-3), true),
        (Vector3::new(1e-3, 1e-3, 1.0), false),
    ] {
        let (model, mut s, _) = free_body(RotationParam::Quaternion, omega);
        let mut ws = Workspace::new(&model);
        let (axis, w0) = if flips { (4, 1.0_f64) } else { (5, 1.0_f64) };
        let mut min_w = w0;
        Dopri5::new(Dopri5Settings {
            rtol: 1e-10,
            atol: 1e-12,
            ..Default::default()
        })
        .integrate(&model, &mut s, &mut ws, 30.0, |s, _| {
            min_w = min_w.min(s.u[axis])
        })
        .unwrap();
        assert_eq!(min_w < 0.0, flips, "omega {omega:?}: min {min_w}");
    }
}
