//! Constraint Jacobian, g_t and acceleration bias vs finite differences along the motion.
use flexmbs_core::system::{assemble_constraints, evaluate, integrate_positions};
use flexmbs_core::*;
use nalgebra::{Matrix3, Rotation3, Vector3};

fn rot(a: f64, b: f64, c: f64) -> Matrix3<f64> {
    Rotation3::from_euler_angles(a, b, c).into_inner()
}

/// With `u` constant, `q(tau) = q ⊕ tau u` is the exact motion, so `d g / d tau = G u + g_t` and
/// `d^2 g / d tau^2 = g_bias` (`u_dot = 0`). Central differences (eps = 1e-4), tolerance 1e-6
/// (rate) and 1e-5 (bias) relative to max(1, |value|).
#[test]
fn jacobian_and_bias_match_finite_differences() {
    let mut spec = ModelSpec::new();
    let a = spec.add_body("a", RigidBody::new(1.0, Matrix3::identity()));
    let b = spec.add_body(
        "b",
        RigidBody::new(1.0, Matrix3::identity()).with_rotation(RotationParam::Quaternion),
    );
    let g0 = spec.add_ground_frame("g0", Vector3::new(0.1, 0.2, 0.3), rot(0.1, 0.2, 0.3));
    let fa = spec.add_frame("fa", a, Vector3::new(0.3, -0.2, 0.5), rot(-0.4, 0.1, 0.7));
    let fa2 = spec.add_frame("fa2", a, Vector3::new(-0.1, 0.4, 0.2), rot(0.2, 0.3, -0.5));
    let fb = spec.add_frame("fb", b, Vector3::new(0.2, 0.1, -0.3), rot(0.6, -0.2, 0.1));
    let harmonic = |amp, f| TimeFunction::Harmonic {
        amplitude: amp,
        frequency_hz: f,
        phase: 0.3,
        offset: 0.1,
    };
    spec.add_joint(Joint::fixed("fixed", fa, fb));
    spec.add_joint(
        Joint::revolute("rev", g0, fa)
            .with_prescribed(PrescribedMotion::RevoluteAngle(harmonic(0.7, 1.3))),
    );
    spec.add_joint(
        Joint::prismatic("pri", fa2, fb)
            .with_prescribed(PrescribedMotion::PrismaticDisplacement(harmonic(0.2, 0.8))),
    );
    spec.add_joint(Joint::new(
        "one_rot",
        fb,
        fa2,
        [false, true, false, true, false, false],
    ));
    spec.add_joint(Joint::cylindrical("cyl", g0, fb));
    spec.add_joint(Joint::spherical("sph", fa2, g0));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(&mut s, a, Vector3::new(0.5, -0.3, 0.2), rot(0.3, -0.5, 1.1));
    model.set_body_pose(&mut s, b, Vector3::new(-0.2, 0.4, 0.9), rot(-0.7, 0.4, 2.0));
    model.set_body_velocity(
        &mut s,
        a,
        Vector3::new(0.3, -1.0, 0.5),
        Vector3::new(1.2, -0.4, 0.9),
    );
    model.set_body_velocity(
        &mut s,
        b,
        Vector3::new(-0.6, 0.2, 0.8),
        Vector3::new(-0.5, 1.5, 0.3),
    );
    let t = 0.37;
    let mut ws = Workspace::new(&model);
    let nc = model.nc;
    let eval = |tau: f64, ws: &mut Workspace| -> Vec<f64> {
        let dv: Vec<f64> = s.u.iter().map(|x| x * tau).collect();
        let mut q = s.q.clone();
        integrate_positions(&model, &s.q, &dv, &mut q);
        let sys = &mut ws.sys;
        evaluate(&model, &q, &s.u, sys).unwrap();
        assemble_constraints(
            &model,
            t + tau,
            &sys.frames,
            &mut sys.g,
            sys.g_jac.as_mut(),
            &mut sys.g_t,
            &mut sys.g_bias,
        );
        sys.g.clone()
    };
    let eps = 1e-4;
    let (gp, gm) = (eval(eps, &mut ws), eval(-eps, &mut ws));
    let g0v = eval(0.0, &mut ws);
    let sys = &ws.sys;
    let mut worst: (f64, f64) = (0.0, 0.0);
    for r in 0..nc {
        let rate = sys.g_t[r]
            + (0..model.nu)
                .map(|j| sys.g_jac[(r, j)] * s.u[j])
                .sum::<f64>();
        let rate_fd = (gp[r] - gm[r]) / (2.0 * eps);
        let acc_fd = (gp[r] - 2.0 * g0v[r] + gm[r]) / (eps * eps);
        let e1 = (rate - rate_fd).abs() / rate.abs().max(1.0);
        let e2 = (sys.g_bias[r] - acc_fd).abs() / acc_fd.abs().max(1.0);
        println!(
            "row {r}: rate {rate:.9} fd {rate_fd:.9}  bias {:.7} fd {acc_fd:.7}",
            sys.g_bias[r]
        );
        worst = (worst.0.max(e1), worst.1.max(e2));
    }
    println!("worst {worst:?}");
    assert_eq!(nc, 6 + 6 + 6 + 2 + 4 + 3);
    assert!(worst.0 < 1e-6 && worst.1 < 1e-5, "{worst:?}");
}
