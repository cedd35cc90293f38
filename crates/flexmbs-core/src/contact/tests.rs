//! Contact kinematics against finite differences: `d g_N / dt` along the motion equals
//! `g_N_dot` (3.8), and the generalized directions reproduce the relative velocities,
//! `W_N^T u = g_N_dot`, `W_T^T u = g_T_dot`.

use super::*;
use crate::ids::FrameId;
use crate::model::ModelSpec;
use crate::rigid::{RigidBody, RotationParam};
use crate::state::State;
use crate::system;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// Two tumbling rigid bodies (Cardan and quaternion) carrying one contour each of `kinds`, on
/// frames offset from the centres of mass.
fn two_bodies(a: ContourKind, b: ContourKind) -> (Model, State) {
    let mut spec = ModelSpec::new();
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.3, 0.4, 0.5));
    let b1 = spec.add_body("b1", RigidBody::new(2.0, inertia));
    let b2 = spec.add_body(
        "b2",
        RigidBody::new(1.5, inertia).with_rotation(RotationParam::Quaternion),
    );
    let r1 = Rotation3::from_euler_angles(0.2, -0.4, 0.7).into_inner();
    let r2 = Rotation3::from_euler_angles(-0.5, 0.3, 0.1).into_inner();
    let f1 = spec.add_frame("f1", b1, Vector3::new(0.1, -0.2, 0.15), r1);
    let f2 = spec.add_frame("f2", b2, Vector3::new(-0.05, 0.12, 0.2), r2);
    let contour = |k: ContourKind, f: FrameId| -> Box<dyn Contour> {
        match k {
            ContourKind::Point => Box::new(PointContour { frame: f }),
            ContourKind::Sphere => Box::new(SphereContour {
                frame: f,
                radius: 0.3,
            }),
            ContourKind::Plane => Box::new(PlaneContour { frame: f }),
            ContourKind::Circle => Box::new(CircleContour {
                frame: f,
                radius: 0.25,
            }),
            _ => unreachable!("rigid contours only"),
        }
    };
    spec.add_contact(Contact {
        name: "c".into(),
        contour_a: contour(a, f1),
        contour_b: contour(b, f2),
        law: ContactLaw::unilateral(0.0),
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let rot1 = Rotation3::from_euler_angles(0.3, 0.2, -0.1).into_inner();
    let rot2 = Rotation3::from_euler_angles(1.1, -0.6, 0.4).into_inner();
    model.set_body_pose(&mut s, crate::BodyId(0), Vector3::new(0.1, 0.2, -0.3), rot1);
    model.set_body_pose(&mut s, crate::BodyId(1), Vector3::new(0.4, 0.9, 1.2), rot2);
    let (w1, w2) = (Vector3::new(0.7, -1.3, 0.4), Vector3::new(-0.9, 0.5, 1.6));
    model.set_body_velocity(&mut s, crate::BodyId(0), Vector3::new(0.3, -0.2, 0.5), w1);
    model.set_body_velocity(&mut s, crate::BodyId(1), Vector3::new(-0.6, 0.8, 0.1), w2);
    (model, s)
}

fn frames_at(model: &Model, s: &State) -> Vec<FrameKinematics> {
    (0..model.frames.len())
        .map(|f| model.frame_kinematics(s, FrameId(f)).unwrap())
        .collect()
}

/// `q ⊕ e u` (the motion along the velocities for a time `e`, to first order exactly).
fn moved(model: &Model, s: &State, e: f64) -> State {
    let mut m = s.clone();
    let dv: Vec<f64> = s.u.iter().map(|u| e * u).collect();
    system::integrate_positions(model, &s.q, &dv, &mut m.q);
    m
}

#[test]
fn gap_rate_equals_finite_difference_and_w_transpose_u() {
    use ContourKind::*;
    for (a, b) in [
        (Plane, Point),
        (Plane, Sphere),
        (Plane, Circle),
        (Sphere, Sphere),
        (Sphere, Point),
        (Point, Plane), // swapped into (Plane, Point) at compile time
    ] {
        let (model, s) = two_bodies(a, b);
        let c = &model.contacts[0];
        let frames = frames_at(&model, &s);
        let mut work = ContactWork::new(&model);
        let w = &mut work.sides[0];
        let geo = c.geometry(&model, &frames, &[], w);
        let (gn_dot, gt_dot) = geo.gap_velocities();
        // central difference of the gap along the motion, O(e^2) = 1e-10 relative
        let e = 1e-5;
        let mut gap = |x: f64| {
            let f = frames_at(&model, &moved(&model, &s, x));
            c.geometry(&model, &f, &[], w).gap
        };
        let fd = (gap(e) - gap(-e)) / (2.0 * e);
        assert!(
            (fd - gn_dot).abs() < 1e-8 * (1.0 + gn_dot.abs()),
            "{a:?}-{b:?}: finite difference {fd} vs g_N_dot {gn_dot}"
        );
        // the directions through the frames' Jacobians reproduce the rates
        let expected = [gn_dot, gt_dot[0], gt_dot[1]];
        for (k, want) in expected.into_iter().enumerate() {
            let mut w = vec![0.0; model.nu];
            c.add_direction(&model, &frames, &work.sides[0], &geo, k, 1.0, &mut w);
            let wu: f64 = w.iter().zip(&s.u).map(|(x, y)| x * y).sum();
            assert!(
                (wu - want).abs() < 1e-13,
                "{a:?}-{b:?}: W^T u {wu} vs {want}"
            );
        }
        // contact frame orthonormal and right-handed; gap = n^T (r_Cb - r_Ca)
        let [t1, t2] = geo.tangents;
        assert!((geo.normal.cross(&t1) - t2).norm() < 1e-14, "{a:?}-{b:?}");
        assert!((geo.gap - geo.normal.dot(&(geo.point_b - geo.point_a))).abs() < 1e-14);
        assert!((geo.point_b - geo.point_a).cross(&geo.normal).norm() < 1e-13);
    }
}

/// The gap of a sphere above a plane is the analytic distance minus the radius.
#[test]
fn plane_sphere_gap_is_distance_minus_radius() {
    let (model, s) = two_bodies(ContourKind::Plane, ContourKind::Sphere);
    let frames = frames_at(&model, &s);
    let (fa, fb) = model.contacts[0].frames();
    let n = frames[fa.0].rotation.column(2).into_owned();
    let d = n.dot(&(frames[fb.0].position - frames[fa.0].position));
    let mut work = ContactWork::new(&model);
    let geo = model.contacts[0].geometry(&model, &frames, &[], &mut work.sides[0]);
    assert!((geo.gap - (d - 0.3)).abs() < 1e-15);
}

fn compile_error(a: Box<dyn Contour>, b: Box<dyn Contour>, law: ContactLaw) -> String {
    let mut spec = ModelSpec::new();
    let body = spec.add_body("b", RigidBody::new(1.0, Matrix3::identity()));
    let _ = spec.add_frame("f", body, Vector3::zeros(), Matrix3::identity());
    let _ = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    spec.add_contact(Contact {
        name: "bad".into(),
        contour_a: a,
        contour_b: b,
        law,
    });
    match spec.compile() {
        Err(ModelError::InvalidContact { contact, reason }) => {
            assert_eq!(contact, "bad");
            reason
        }
        other => panic!("expected InvalidContact, got {other:?}"),
    }
}

#[test]
fn bad_contacts_are_rejected_at_compile_time() {
    let (f, g) = (FrameId(0), FrameId(1));
    let law = ContactLaw::unilateral(0.5);
    let r = compile_error(
        Box::new(PointContour { frame: f }),
        Box::new(PointContour { frame: g }),
        law,
    );
    assert!(
        r.contains("no contact kinematics for a Point and a Point"),
        "{r}"
    );
    let r = compile_error(
        Box::new(SphereContour {
            frame: f,
            radius: -1.0,
        }),
        Box::new(PlaneContour { frame: g }),
        law,
    );
    assert!(r.contains("radius -1"), "{r}");
    let r = compile_error(
        Box::new(PlaneContour { frame: g }),
        Box::new(PointContour { frame: g }),
        law,
    );
    assert!(r.contains("both contours are on the ground"), "{r}");
    let r = compile_error(
        Box::new(PlaneContour { frame: g }),
        Box::new(PointContour { frame: FrameId(7) }),
        law,
    );
    assert!(r.contains("unknown frame"), "{r}");
    for (law, what) in [
        (ContactLaw::unilateral(1.5), "restitution"),
        (ContactLaw::regularized(-1.0, 0.0), "stiffness"),
        (law.with_coulomb(f64::NAN, TangentDirections::Planar), "mu"),
        (
            law.with_regularized_friction(0.3, 1e-3, TangentDirections::Spatial),
            "regularized normal law",
        ),
    ] {
        let r = compile_error(
            Box::new(PlaneContour { frame: g }),
            Box::new(PointContour { frame: f }),
            law,
        );
        assert!(r.contains(what), "{r}");
    }
}

#[test]
fn prox_functions() {
    assert_eq!(law::prox_nonnegative(-2.0), 0.0);
    assert_eq!(law::prox_nonnegative(3.0), 3.0);
    let mut x = [3.0, 4.0];
    law::prox_disc(&mut x, 1.0);
    assert!((x[0] - 0.6).abs() < 1e-15 && (x[1] - 0.8).abs() < 1e-15);
    let mut y = [0.3, -0.4];
    law::prox_disc(&mut y, 1.0);
    assert_eq!(y, [0.3, -0.4]);
    let mut z = [-5.0];
    law::prox_disc(&mut z, 2.0);
    assert_eq!(z, [-2.0]);
}
