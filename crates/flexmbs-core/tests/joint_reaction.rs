//! Joint reaction wrench (`joint::joint_reaction`) against Newton-Euler by hand: a clamped
//! rigid cantilever under gravity (statics) and a driven, unbalanced rotor (dynamics with the
//! consistent multipliers at exact states).
use flexmbs_core::integrator::consistent_accelerations;
use flexmbs_core::joint::joint_reaction;
use flexmbs_core::*;
use nalgebra::{Matrix3, Rotation3, Vector3};

fn rz(phi: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), phi).into_inner()
}

fn reaction(model: &Model, s: &State, ws: &mut Workspace) -> (Vector3<f64>, Vector3<f64>) {
    system::evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
    let j = &model.joints[0];
    let (ka, kb) = (&ws.sys.frames[j.frame_a.0], &ws.sys.frames[j.frame_b.0]);
    let r0 = model.joint_rows[0];
    joint_reaction(j, s.t, ka, kb, &s.lambda[r0..r0 + j.num_rows()])
}

/// Rigid cantilever (m = 3 kg, centre of mass L = 0.8 m from the clamp along x) clamped to
/// ground under gravity -g y. The clamp holds the body with F = m g (up) and the torque
/// T = m g L about +z (global). Frame `a` is turned 90 deg about z, so in its axes
/// F = (m g, 0, 0) and T = (0, 0, m g L). Tolerance 1e-12 relative.
#[test]
fn clamped_cantilever_reaction_matches_statics() {
    let (m, l, g) = (3.0, 0.8, 9.81);
    for rot in [RotationParam::Cardan, RotationParam::Quaternion] {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, -g, 0.0));
        let body = spec.add_body(
            "arm",
            RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(0.01, 0.2, 0.2)))
                .with_rotation(rot),
        );
        let a = spec.add_ground_frame("wall", Vector3::zeros(), rz(0.5 * std::f64::consts::PI));
        let b = spec.add_frame(
            "root",
            body,
            Vector3::new(-l, 0.0, 0.0),
            rz(0.5 * std::f64::consts::PI),
        );
        spec.add_joint(Joint::fixed("clamp", a, b));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        model.set_body_pose(&mut s, body, Vector3::new(l, 0.0, 0.0), Matrix3::identity());
        let mut ws = Workspace::new(&model);
        consistent_accelerations(&model, &mut s, &mut ws).unwrap();
        let (f, t) = reaction(&model, &s, &mut ws);
        let (f_ref, t_ref) = (
            Vector3::new(m * g, 0.0, 0.0),
            Vector3::new(0.0, 0.0, m * g * l),
        );
        println!("{rot:?}: F {f:?}, T {t:?}");
        assert!((f - f_ref).norm() < 1e-12 * m * g, "force {f:?}");
        assert!((t - t_ref).norm() < 1e-12 * m * g * l, "torque {t:?}");
    }
}

/// Unbalanced rotor on a revolute joint driven by `phi(t) = A sin(2 pi f t)` (no gravity): body
/// mass m, centre of mass at e from the axis, I_c about z. At exact states (phi, phi_dot) the
/// consistent multipliers must give the force m a_com (centripetal + tangential) and the drive
/// torque (I_c + m e^2) phi_ddot about z; tolerance 1e-10 relative to the largest value.
#[test]
fn driven_rotor_reaction_matches_newton_euler() {
    let (m, e, ic) = (2.0, 0.15, 0.03);
    let (amp, freq) = (0.7, 3.0);
    let w = 2.0 * std::f64::consts::PI * freq;
    let mut spec = ModelSpec::new();
    let body = spec.add_body(
        "rotor",
        RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(0.02, 0.025, ic))),
    );
    let a = spec.add_ground_frame("axis", Vector3::zeros(), Matrix3::identity());
    let b = spec.add_frame("hub", body, Vector3::new(-e, 0.0, 0.0), Matrix3::identity());
    spec.add_joint(Joint::revolute("drive", a, b).with_prescribed(
        PrescribedMotion::RevoluteAngle(TimeFunction::Harmonic {
            amplitude: amp,
            frequency_hz: freq,
            phase: 0.0,
            offset: 0.0,
        }),
    ));
    let model = spec.compile().unwrap();
    let mut ws = Workspace::new(&model);
    for t in [0.01, 0.05, 0.1, 0.13, 0.2] {
        let (phi, phi_d, phi_dd) = (
            amp * (w * t).sin(),
            amp * w * (w * t).cos(),
            -amp * w * w * (w * t).sin(),
        );
        let (er, et) = (
            Vector3::new(phi.cos(), phi.sin(), 0.0),
            Vector3::new(-phi.sin(), phi.cos(), 0.0),
        );
        let mut s = model.initial_state();
        s.t = t;
        model.set_body_pose(&mut s, body, e * er, rz(phi));
        model.set_body_velocity(&mut s, body, e * phi_d * et, Vector3::new(0.0, 0.0, phi_d));
        consistent_accelerations(&model, &mut s, &mut ws).unwrap();
        let (f, torque) = reaction(&model, &s, &mut ws);
        let f_ref = m * (-e * phi_d * phi_d * er + e * phi_dd * et);
        let t_ref = Vector3::new(0.0, 0.0, (ic + m * e * e) * phi_dd);
        let scale = f_ref.norm().max(t_ref.norm()).max(1.0);
        println!("t {t}: F {f:?} ref {f_ref:?}; T {torque:?} ref {t_ref:?}");
        assert!(
            (f - f_ref).norm() < 1e-10 * scale,
            "t {t}: force {f:?} vs {f_ref:?}"
        );
        assert!(
            (torque - t_ref).norm() < 1e-10 * scale,
            "t {t}: torque {torque:?} vs {t_ref:?}"
        );
    }
}
