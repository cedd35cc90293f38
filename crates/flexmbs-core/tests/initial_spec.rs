//! The initial state belongs to the model description: poses and velocities set on the spec
//! appear in `Model::initial_state`, a spring marked unstressed gets the distance of its frames
//! there as free length at compile time (the compiled model is not changed afterwards), and a
//! mark on a load that is not a spring is refused.

use flexmbs_core::{Load, LoadCoordinates, ModelError, ModelSpec, RigidBody, TimeFunction};
use nalgebra::{Matrix3, Vector3};

fn spec() -> (
    ModelSpec,
    flexmbs_core::BodyId,
    flexmbs_core::LoadId,
    flexmbs_core::LoadId,
) {
    let mut spec = ModelSpec::new();
    let b = spec.add_body("b", RigidBody::new(1.0, Matrix3::identity() * 0.1));
    let g = spec.add_ground_frame("g", Vector3::new(0.0, 1.0, 0.0), Matrix3::identity());
    let f = spec.add_frame("f", b, Vector3::new(0.5, 0.0, 0.0), Matrix3::identity());
    let spring = spec.add_load(Load::SpringDamper {
        frame_a: g,
        frame_b: f,
        stiffness: 10.0,
        damping: 0.0,
        free_length: 99.0,
    });
    let force = spec.add_load(Load::Force {
        frame: f,
        vector: Vector3::x(),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    (spec, b, spring, force)
}

#[test]
fn unstressed_spring_takes_its_initial_length() {
    let (mut spec, b, spring, _) = spec();
    let quarter =
        nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 0.5 * std::f64::consts::PI);
    spec.set_initial_pose(b, Vector3::new(3.0, 1.0, 0.0), *quarter.matrix());
    spec.set_initial_velocity(b, Vector3::new(0.0, 2.0, 0.0), Vector3::new(0.0, 0.0, 1.5));
    spec.set_spring_unstressed_initially(spring);
    let model = spec.compile().unwrap();
    // frame f at (3, 1) + R_z(90 deg) (0.5, 0) = (3, 1.5); ground frame at (0, 1)
    let Load::SpringDamper { free_length, .. } = &model.loads[spring.0] else {
        panic!();
    };
    let expected = (3.0_f64.powi(2) + 0.5_f64.powi(2)).sqrt();
    assert!(
        (free_length - expected).abs() < 1e-14,
        "{free_length} vs {expected}"
    );
    let s = model.initial_state();
    let k = model
        .frame_kinematics(&s, flexmbs_core::FrameId(1))
        .unwrap();
    assert!((k.position - Vector3::new(3.0, 1.5, 0.0)).norm() < 1e-14);
    // v_f = v + omega x r = (0, 2, 0) + 1.5 e_z x (0, 0.5, 0) = (-0.75, 2, 0)
    assert!((k.velocity - Vector3::new(-0.75, 2.0, 0.0)).norm() < 1e-14);
    // the reference configuration is still available
    assert_eq!(model.reference_state().q[..3], [0.0, 0.0, 0.0]);
}

#[test]
fn unstressed_mark_on_a_force_is_refused() {
    let (mut spec, _, _, force) = spec();
    spec.set_spring_unstressed_initially(force);
    let err = spec.compile().unwrap_err();
    assert!(
        matches!(
            err,
            ModelError::InvalidParameter {
                name: "unstressed spring",
                ..
            }
        ),
        "{err}"
    );
}
