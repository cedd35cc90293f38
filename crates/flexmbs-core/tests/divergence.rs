//! Failures produce typed errors, not panics.
use crate::common;
use flexmbs_core::integrator::{Dopri5, GenAlpha, GenAlphaSettings, Statics};
use flexmbs_core::*;
use nalgebra::{Matrix3, Vector3};

fn pendulum_with_force(force: f64) -> (Model, State) {
    let p = common::Pendulum::new(RotationParam::Cardan);
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -p.g, 0.0));
    let body = spec.add_body("bob", RigidBody::new(p.m, Matrix3::identity() * p.ic));
    let pivot_g = spec.add_ground_frame("pivot", Vector3::zeros(), Matrix3::identity());
    let pivot_b = spec.add_frame(
        "pivot_b",
        body,
        Vector3::new(0.0, p.l, 0.0),
        Matrix3::identity(),
    );
    spec.add_joint(Joint::revolute("hinge", pivot_g, pivot_b));
    spec.add_load(Load::Force {
        frame: pivot_b,
        vector: Vector3::new(1.0, 0.0, 0.0),
        time: TimeFunction::Step {
            t0: 0.01,
            before: 0.0,
            after: force,
        },
        coordinates: LoadCoordinates::Frame,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        body,
        Vector3::new(p.l, 0.0, 0.0),
        nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2)
            .into_inner(),
    );
    (model, s)
}

#[test]
fn nan_force_gives_non_finite_error_with_time_and_step() {
    let (model, mut s) = pendulum_with_force(f64::NAN);
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let err = ga
        .integrate(&model, &mut s, &mut ws, 1e-3, 0.1, |_, _| {})
        .unwrap_err();
    println!("{err}");
    match err {
        SolverError::NonFinite { t, h, .. } => assert!((t - 0.009).abs() < 1e-9 && h == 1e-3),
        e => panic!("unexpected {e:?}"),
    }
    assert!(
        (s.t - 0.009).abs() < 1e-9,
        "state stays at the last good step"
    );
}

/// A step of 50 s with only 3 Newton iterations on a large-amplitude pendulum fails with
/// NewtonFailed (time, step, residual reported); a negative step is an invalid setting.
#[test]
fn absurd_step_gives_newton_failure() {
    let (model, mut s) = pendulum_with_force(0.0);
    let mut ws = Workspace::new(&model);
    let mut settings = GenAlphaSettings::default();
    settings.newton.max_iterations = 3;
    let ga = GenAlpha::new(settings).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let err = ga.step(&model, &mut s, &mut ws, 50.0).unwrap_err();
    println!("{err}");
    assert!(
        matches!(err, SolverError::NewtonFailed { h, iterations: 3, .. } if h == 50.0),
        "{err:?}"
    );
    assert!(matches!(
        ga.step(&model, &mut s, &mut ws, -1.0),
        Err(SolverError::InvalidSetting { .. })
    ));
    assert!(matches!(
        GenAlpha::new(GenAlphaSettings {
            rho_inf: 1.5,
            ..Default::default()
        }),
        Err(SolverError::InvalidSetting { .. })
    ));
}

#[test]
fn dopri_rejects_constraints_and_statics_reports_nan() {
    let (model, mut s) = pendulum_with_force(f64::NAN);
    let mut ws = Workspace::new(&model);
    let e = Dopri5::default()
        .integrate(&model, &mut s, &mut ws, 1.0, |_, _| {})
        .unwrap_err();
    assert!(matches!(
        e,
        SolverError::ConstraintsUnsupported { nc: 5, .. }
    ));
    s.t = 1.0; // the NaN step force is active
    let e = Statics::default()
        .solve(&model, &mut s, &mut ws)
        .unwrap_err();
    assert!(matches!(e, SolverError::NonFinite { .. }), "{e:?}");
}

#[test]
fn invalid_models_are_rejected() {
    let mut spec = ModelSpec::new();
    let b = spec.add_body("b", RigidBody::new(1.0, Matrix3::identity()));
    let f = spec.add_frame("f", b, Vector3::zeros(), Matrix3::identity());
    let f2 = spec.add_frame("f2", b, Vector3::x(), Matrix3::identity());
    spec.add_joint(Joint::revolute("self", f, f2));
    assert!(matches!(spec.compile(), Err(ModelError::SameOwner { .. })));
    let mut spec = ModelSpec::new();
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("dangling", g, FrameId(7)));
    assert!(matches!(
        spec.compile(),
        Err(ModelError::UnknownFrame {
            frame: FrameId(7),
            ..
        })
    ));
    let mut spec = ModelSpec::new();
    let b = spec.add_body("b", RigidBody::new(1.0, Matrix3::identity()));
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    let f = spec.add_frame("f", b, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(
        Joint::fixed("j", g, f)
            .with_prescribed(PrescribedMotion::RevoluteAngle(TimeFunction::Constant(0.0))),
    );
    assert!(matches!(
        spec.compile(),
        Err(ModelError::PrescribedOnLockedDof { dof: "rz", .. })
    ));
}
