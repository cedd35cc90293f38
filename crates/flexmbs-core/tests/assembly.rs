//! `GenAlpha::initialize` refuses a state that violates a joint (position or velocity) or does
//! not fit the model, instead of letting the first step pull the bodies together.
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, Statics};
use flexmbs_core::*;
use nalgebra::{Matrix3, Vector3};

/// Rigid arm (centre of mass 0.5 m below the hinge) on a revolute joint about z.
fn pendulum() -> (Model, BodyId) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let arm = spec.add_body(
        "arm",
        RigidBody::new(1.0, Matrix3::from_diagonal(&Vector3::new(0.02, 1e-4, 0.02))),
    );
    let hinge = spec.add_ground_frame("hinge", Vector3::zeros(), Matrix3::identity());
    let top = spec.add_frame("top", arm, Vector3::new(0.0, 0.5, 0.0), Matrix3::identity());
    spec.add_joint(Joint::revolute("pin", hinge, top));
    (spec.compile().unwrap(), arm)
}

#[test]
fn initialize_refuses_unassembled_states() {
    let (model, arm) = pendulum();
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    let mut ws = Workspace::new(&model);

    // 1 cm gap along y
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        arm,
        Vector3::new(0.0, -0.49, 0.0),
        Matrix3::identity(),
    );
    match ga.initialize(&model, &mut s, &mut ws) {
        Err(SolverError::NotAssembled {
            joint,
            row,
            level,
            violation,
            ..
        }) => {
            assert_eq!((joint.as_str(), row, level), ("pin", "ty", "position"));
            assert!((violation.abs() - 0.01).abs() < 1e-12, "{violation}");
        }
        other => panic!("expected NotAssembled, got {other:?}"),
    }

    // assembled, but the centre of mass moves along y (the joint allows only rotation about z)
    model.set_body_pose(
        &mut s,
        arm,
        Vector3::new(0.0, -0.5, 0.0),
        Matrix3::identity(),
    );
    model.set_body_velocity(&mut s, arm, Vector3::new(0.0, 0.3, 0.0), Vector3::zeros());
    match ga.initialize(&model, &mut s, &mut ws) {
        Err(SolverError::NotAssembled { row, level, .. }) => {
            assert_eq!((row, level), ("ty", "velocity"))
        }
        other => panic!("expected NotAssembled, got {other:?}"),
    }

    // consistent: swinging about the hinge, v = omega x r
    let w = 2.0;
    model.set_body_velocity(
        &mut s,
        arm,
        Vector3::new(w * 0.5, 0.0, 0.0),
        Vector3::new(0.0, 0.0, w),
    );
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    ga.step(&model, &mut s, &mut ws, 1e-3).unwrap();
}

#[test]
fn foreign_state_is_an_error_not_a_panic() {
    let (model, _) = pendulum();
    let mut other = ModelSpec::new();
    other.add_body("b", RigidBody::new(1.0, Matrix3::identity()));
    let other = other.compile().unwrap();
    let mut s = other.initial_state();
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    for r in [
        ga.initialize(&model, &mut s, &mut ws),
        ga.step(&model, &mut s, &mut ws, 1e-3).map(|_| ()),
        Statics::default()
            .solve(&model, &mut s, &mut ws)
            .map(|_| ()),
    ] {
        assert!(
            matches!(
                r,
                Err(SolverError::StateSize {
                    what: "lambda",
                    got: 0,
                    expected: 5
                })
            ),
            "{r:?}"
        );
    }
}

/// `ModelSpec::compile` validates rigid bodies: mass > 0, inertia positive definite and
/// physically possible (triangle inequality of the principal moments).
#[test]
fn unphysical_rigid_bodies_are_refused() {
    let cases = [
        (-1.0, Matrix3::identity(), "mass must be finite and > 0"),
        (f64::NAN, Matrix3::identity(), "mass must be finite and > 0"),
        (1.0, -Matrix3::identity(), "positive definite"),
        (
            1.0,
            Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 3.0)),
            "triangle inequality",
        ),
    ];
    for (m, i, needle) in cases {
        let mut spec = ModelSpec::new();
        spec.add_body("b", RigidBody::new(m, i));
        match spec.compile() {
            Err(e @ ModelError::InvalidBody { .. }) => {
                assert!(e.to_string().contains(needle), "{e}");
                assert!(e.to_string().starts_with("body `b`: "), "{e}");
            }
            other => panic!("mass {m}, inertia {i:?}: expected InvalidBody, got {other:?}"),
        }
    }
    // a thin plate (I_z = I_x + I_y) is fine
    let mut spec = ModelSpec::new();
    spec.add_body(
        "plate",
        RigidBody::new(1.0, Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))),
    );
    spec.compile().unwrap();
}

/// Post-processing lookups: names to ids, and one frame's kinematics equal to the frame the
/// integrators compute (`system::update_frames`), bitwise; foreign ids give `None`.
#[test]
fn frame_kinematics_and_name_lookups() {
    let (model, arm) = pendulum();
    assert_eq!(model.body_id("arm"), Some(arm));
    assert_eq!(model.body_id("nope"), None);
    let top = model.frame_id("top").unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        arm,
        Vector3::new(0.0, -0.5, 0.0),
        Matrix3::identity(),
    );
    model.set_body_velocity(
        &mut s,
        arm,
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 0.0, 2.0),
    );
    let k = model.frame_kinematics(&s, top).unwrap();
    let mut ws = Workspace::new(&model);
    system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
    let all = &ws.sys.frames[top.index()];
    assert_eq!(k.position, all.position);
    assert_eq!(k.velocity, all.velocity);
    assert!(k.position.norm() < 1e-15, "hinge point at the origin");
    assert!(
        k.velocity.norm() < 1e-15,
        "hinge point at rest: {:?}",
        k.velocity
    );
    assert_eq!(
        model.frame_kinematics(&s, FrameId(99)).map(|k| k.position),
        None
    );
    let hinge = model
        .frame_kinematics(&s, model.frame_id("hinge").unwrap())
        .unwrap();
    assert_eq!(hinge.position, Vector3::zeros());
}
