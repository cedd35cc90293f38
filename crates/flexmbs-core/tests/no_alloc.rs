//! No heap allocation inside a time step (the test binary's counting global allocator).
use crate::chain;
use crate::counting_alloc;
use crate::spring_element;
use flexmbs_core::algebra::LinearSolver;
use flexmbs_core::integrator::{Dopri5, GenAlpha, GenAlphaSettings};
use flexmbs_core::*;
use nalgebra::{Matrix3, Vector3};

/// Generalized-alpha steps of an FFR body (analytic tangent, moment cache, full and modified
/// Newton, prescribed revolute joint, gravity), after the workspace exists and one warm-up step.
fn ffr_steps_allocations(modified: bool) -> usize {
    use flexmbs_core::ffr::{FfrBody, FfrElement, FfrInvariants, RotationParam as FfrRot};
    use flexmbs_core::integrator::NewtonSettings;
    let n = 6;
    let nodes: Vec<[f64; 3]> = (0..n)
        .map(|i| [0.2 * i as f64, 0.01 * (i % 2) as f64, 0.0])
        .collect();
    let masses = vec![0.5; n];
    let nf = 4;
    let modes = faer::Mat::from_fn(3 * n, nf, |r, c| {
        let (node, dir) = (r / 3, r % 3);
        if dir == 1 + c % 2 {
            (0.2 * node as f64).powi(2 + (c / 2) as i32)
        } else {
            0.0
        }
    });
    let k = faer::Mat::from_fn(
        nf,
        nf,
        |i, j| if i == j { 1e3 * (i + 1) as f64 } else { 0.0 },
    );
    let inv = FfrInvariants::from_lumped(&nodes, &masses, modes.as_ref()).unwrap();
    let body = FfrBody::new(
        inv,
        FfrRot::Cardan,
        &nodes,
        modes.as_ref(),
        None,
        k.as_ref(),
    )
    .unwrap();
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let b = spec.add_body("ffr", FfrElement::new(body));
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    let f = spec.add_frame("f", b, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("drive", g, f).with_prescribed(
        PrescribedMotion::RevoluteRate {
            initial_angle: 0.0,
            rate: TimeFunction::Constant(10.0),
        },
    ));
    // a follower tip force (the analytic load tangent) and a dead one at a floating-frame point
    let tip = spec.add_node_frame("tip", b, n - 1, Vector3::from(nodes[n - 1]));
    let mid = spec.add_frame("mid", b, Vector3::new(0.5, 0.0, 0.0), Matrix3::identity());
    for (frame, coordinates) in [
        (tip, LoadCoordinates::Frame),
        (mid, LoadCoordinates::Global),
    ] {
        spec.add_load(Load::Force {
            frame,
            vector: Vector3::new(0.0, 1.0, 0.5),
            time: TimeFunction::Constant(1.0),
            coordinates,
        });
    }
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_velocity(&mut s, b, Vector3::zeros(), Vector3::new(0.0, 0.0, 10.0));
    let mut ws = Workspace::new(&model);
    let settings = GenAlphaSettings {
        newton: NewtonSettings {
            modified,
            ..NewtonSettings::default()
        },
        ..GenAlphaSettings::default()
    };
    let ga = GenAlpha::new(settings).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    ga.step(&model, &mut s, &mut ws, 1e-3).unwrap();
    counting_alloc::allocations_in(|| {
        for _ in 0..20 {
            ga.step(&model, &mut s, &mut ws, 1e-3).unwrap();
        }
    })
}

/// Allocations in 20 generalized-alpha steps of `model` from `s0` with the given backend,
/// after the workspace exists and one warm-up step.
fn steps_allocations(model: &Model, s0: &State, choice: LinearSolver, modified: bool) -> usize {
    use flexmbs_core::integrator::NewtonSettings;
    let mut s = s0.clone();
    let mut ws = Workspace::with_linear_solver(model, choice);
    let settings = GenAlphaSettings {
        newton: NewtonSettings {
            modified,
            ..NewtonSettings::default()
        },
        ..GenAlphaSettings::default()
    };
    let ga = GenAlpha::new(settings).unwrap();
    ga.initialize(model, &mut s, &mut ws).unwrap();
    ga.step(model, &mut s, &mut ws, 1e-3).unwrap();
    counting_alloc::allocations_in(|| {
        for _ in 0..20 {
            ga.step(model, &mut s, &mut ws, 1e-3).unwrap();
        }
    })
}

/// Generalized-alpha steps of two rigid bodies sharing one pose node (accumulated element blocks,
/// node-wise position update), hinged to ground, with a damped spring to a third body and a
/// force on a node-owned frame, with the given backend.
fn shared_node_steps_allocations(choice: LinearSolver) -> usize {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let node = spec.add_node("shared", NodeKind::PoseCardan);
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3));
    let a = spec.add_body_on("a", RigidBody::new(1.0, inertia), &[node]);
    spec.add_body_on("b", RigidBody::new(2.0, inertia), &[node]);
    let c = spec.add_body("c", RigidBody::new(1.0, inertia));
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    let fa = spec.add_frame("fa", a, Vector3::new(0.0, 0.5, 0.0), Matrix3::identity());
    let fc = spec.add_frame("fc", c, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("hinge", g, fa));
    // a follower force on a node-owned frame
    let fnode = spec.add_node_owned_frame(
        "fn",
        node,
        Vector3::new(0.0, -0.3, 0.0),
        Matrix3::identity(),
    );
    spec.add_load(Load::Force {
        frame: fnode,
        vector: Vector3::x(),
        time: TimeFunction::Constant(0.5),
        coordinates: LoadCoordinates::Frame,
    });
    spec.add_load(Load::SpringDamper {
        frame_a: fa,
        frame_b: fc,
        stiffness: 100.0,
        damping: 1.0,
        free_length: 0.3,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(&mut s, a, Vector3::new(0.0, -0.5, 0.0), Matrix3::identity());
    model.set_body_pose(&mut s, c, Vector3::new(0.3, -1.0, 0.0), Matrix3::identity());
    let mut ws = Workspace::with_linear_solver(&model, choice);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    ga.step(&model, &mut s, &mut ws, 1e-3).unwrap();
    counting_alloc::allocations_in(|| {
        for _ in 0..20 {
            ga.step(&model, &mut s, &mut ws, 1e-3).unwrap();
        }
    })
}

/// A triangle of point masses and spring elements whose closing element (nodes 2, 0) is
/// scattered, with a force and a damped spring to ground on a frame of that element and,
/// with `joint`, a spherical joint on a mass: the model of [`scattered_steps_allocations`].
fn scattered_ring(joint: bool) -> (Model, State) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let id = Matrix3::identity();
    let nodes: Vec<_> = (0..3)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Vector(3)))
        .collect();
    let m0 = spec.add_body_on("m0", point_mass::PointMass::new(1.0), &[nodes[0]]);
    for (i, &node) in nodes.iter().enumerate().skip(1) {
        spec.add_body_on(&format!("m{i}"), point_mass::PointMass::new(1.0), &[node]);
    }
    let mut closing = None;
    for i in 0..3 {
        let spring = spring_element::Spring {
            stiffness: 200.0,
            damping: 0.5,
            free_length: 0.25,
        };
        closing = Some(spec.add_body_on(&format!("s{i}"), spring, &[nodes[i], nodes[(i + 1) % 3]]));
    }
    let f = spec.add_frame("f", closing.unwrap(), Vector3::new(0.4, 0.0, 0.0), id);
    let g = spec.add_ground_frame("g", Vector3::new(0.0, 0.5, 0.0), id);
    spec.add_load(Load::Force {
        frame: f,
        vector: Vector3::new(0.3, 0.0, 0.2),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    spec.add_load(Load::SpringDamper {
        frame_a: g,
        frame_b: f,
        stiffness: 50.0,
        damping: 0.3,
        free_length: 0.4,
    });
    if joint {
        let f0 = spec.add_frame("f0", m0, Vector3::zeros(), id);
        let g0 = spec.add_ground_frame("g0", Vector3::zeros(), id);
        spec.add_joint(Joint::spherical("pin", g0, f0));
    }
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    for (i, p) in [[0.0, 0.0, 0.0], [0.3, 0.05, 0.0], [0.1, -0.25, 0.05]]
        .iter()
        .enumerate()
    {
        s.q[3 * i..3 * i + 3].copy_from_slice(p);
    }
    (model, s)
}

/// Allocations of 20 generalized-alpha steps (dense and sparse, full and modified Newton) and a
/// DOPRI5 run of models with a scattered body.
fn scattered_steps_allocations() -> usize {
    let (model, s) = scattered_ring(true);
    let mut n = 0;
    for choice in [LinearSolver::Dense, LinearSolver::Sparse] {
        for modified in [false, true] {
            n += steps_allocations(&model, &s, choice, modified);
        }
    }
    let (model, mut s) = scattered_ring(false);
    let mut ws = Workspace::new(&model);
    let d = Dopri5::default();
    d.integrate(&model, &mut s, &mut ws, 0.01, |_, _| {})
        .unwrap();
    n + counting_alloc::allocations_in(|| {
        d.integrate(&model, &mut s, &mut ws, 0.2, |_, _| {})
            .unwrap();
    })
}

/// Generalized-alpha steps (joint, spring, follower force, finite-difference tangents), FFR
/// body steps (analytic tangent, full and modified Newton) and a DOPRI5 run perform zero
/// allocations after the workspace exists. One test function so that
/// no other test thread allocates concurrently.
#[test]
fn steps_do_not_allocate() {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let b = spec.add_body("b", RigidBody::new(1.0, Matrix3::identity() * 0.1));
    let q = spec.add_body(
        "q",
        RigidBody::new(1.0, Matrix3::identity() * 0.1).with_rotation(RotationParam::Quaternion),
    );
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    let fb = spec.add_frame("fb", b, Vector3::new(0.0, 0.5, 0.0), Matrix3::identity());
    let fq = spec.add_frame("fq", q, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("hinge", g, fb));
    spec.add_load(Load::SpringDamper {
        frame_a: fb,
        frame_b: fq,
        stiffness: 100.0,
        damping: 1.0,
        free_length: 0.3,
    });
    spec.add_load(Load::Force {
        frame: fq,
        vector: Vector3::x(),
        time: TimeFunction::Harmonic {
            amplitude: 1.0,
            frequency_hz: 2.0,
            phase: 0.0,
            offset: 0.0,
        },
        coordinates: LoadCoordinates::Frame,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(&mut s, b, Vector3::new(0.0, -0.5, 0.0), Matrix3::identity());
    model.set_body_pose(&mut s, q, Vector3::new(0.3, -1.0, 0.0), Matrix3::identity());
    let n_ga = steps_allocations(&model, &s, LinearSolver::Dense, false)
        + steps_allocations(&model, &s, LinearSolver::Sparse, false);

    let mut spec = ModelSpec::new();
    let body = spec.add_body(
        "free",
        RigidBody::new(1.0, Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)))
            .with_rotation(RotationParam::Quaternion),
    );
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_velocity(&mut s, body, Vector3::x(), Vector3::new(0.3, 1.0, 0.2));
    let mut ws = Workspace::new(&model);
    let n_dp = counting_alloc::allocations_in(|| {
        Dopri5::default()
            .integrate(&model, &mut s, &mut ws, 0.5, |_, _| {})
            .unwrap();
    });
    let (n_ffr_full, n_ffr_mod) = (ffr_steps_allocations(false), ffr_steps_allocations(true));
    let (chain, chain0) = chain::chain(4, chain::Link::Flexible, Some(LoadCoordinates::Frame));
    let n_sparse = steps_allocations(&chain, &chain0, LinearSolver::Sparse, false)
        + steps_allocations(&chain, &chain0, LinearSolver::Sparse, true);
    let n_shared = shared_node_steps_allocations(LinearSolver::Dense)
        + shared_node_steps_allocations(LinearSolver::Sparse);
    let n_scattered = scattered_steps_allocations();
    assert_eq!(
        (
            n_ga,
            n_dp,
            n_ffr_full,
            n_ffr_mod,
            n_sparse,
            n_shared,
            n_scattered
        ),
        (0, 0, 0, 0, 0, 0, 0),
        "allocations in 20 generalized-alpha steps (dense and sparse backend) / a DOPRI5 run / \
         20 FFR steps (full, modified Newton) / 20 steps of a flexible chain with loads (sparse \
         backend, full and modified Newton) / 20 steps of bodies sharing a node (dense and sparse \
         backend) / 20 steps (dense, sparse) and a DOPRI5 run with a scattered body"
    );
}

/// Moreau time-stepping: a hinged rod (joint rows, position projection) whose sphere rests on
/// a plane with Coulomb friction (prox iteration), plus a free ball on a penalty contact
/// with regularized friction.
#[test]
fn moreau_steps_do_not_allocate() {
    use flexmbs_core::contact::{
        Contact, ContactLaw, PlaneContour, SphereContour, TangentDirections,
    };
    use flexmbs_core::integrator::{MoreauSettings, MoreauStepper, Stepper};
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, 0.0, -9.81));
    let rod = spec.add_body(
        "rod",
        RigidBody::new(1.0, Matrix3::from_diagonal_element(0.1)),
    );
    let hinge = spec.add_ground_frame("hinge", Vector3::new(0.0, 0.0, 0.1), Matrix3::identity());
    let top = spec.add_frame(
        "top",
        rod,
        Vector3::new(-0.5, 0.0, 0.0),
        Matrix3::identity(),
    );
    spec.add_joint(Joint::new(
        "pin",
        hinge,
        top,
        [true, true, true, true, false, true],
    ));
    let tip = spec.add_frame("tip", rod, Vector3::new(0.5, 0.0, 0.0), Matrix3::identity());
    let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    let law = ContactLaw::unilateral(0.3).with_coulomb(0.4, TangentDirections::Spatial);
    let sphere = SphereContour {
        frame: tip,
        radius: 0.1,
    };
    spec.add_contact(Contact::new(
        "tip",
        sphere,
        PlaneContour { frame: ground },
        law,
    ));
    let ball = spec.add_body(
        "ball",
        RigidBody::new(1.0, Matrix3::from_diagonal_element(0.004)),
    );
    let centre = spec.add_frame("centre", ball, Vector3::zeros(), Matrix3::identity());
    let soft = ContactLaw::regularized(1e4, 10.0).with_regularized_friction(
        0.3,
        1e-3,
        TangentDirections::Planar,
    );
    let ball_sphere = SphereContour {
        frame: centre,
        radius: 0.1,
    };
    spec.add_contact(Contact::new(
        "ball",
        ball_sphere,
        PlaneContour { frame: ground },
        soft,
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        BodyId(0),
        Vector3::new(0.5, 0.0, 0.1),
        Matrix3::identity(),
    );
    model.set_body_pose(
        &mut s,
        BodyId(1),
        Vector3::new(2.0, 0.0, 0.099),
        Matrix3::identity(),
    );
    model.set_body_velocity(
        &mut s,
        BodyId(1),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::zeros(),
    );
    let mut ws = Workspace::new(&model);
    let mut st = MoreauStepper::new(MoreauSettings::default());
    st.initialize(&model, &mut s, &mut ws).unwrap();
    st.step(&model, &mut s, &mut ws, 1e-3).unwrap();
    let n = counting_alloc::allocations_in(|| {
        for _ in 0..20 {
            st.step(&model, &mut s, &mut ws, 1e-3).unwrap();
        }
    });
    assert!(
        s.contacts[0].active && s.contacts[1].impulse[0] > 0.0,
        "{:?}",
        s.contacts
    );
    assert_eq!(n, 0, "Moreau steps allocated {n} times");
    // with step-size control (saved states copied in place)
    use flexmbs_core::integrator::{MoreauSscSettings, MoreauSscStepper};
    let mut ssc = MoreauSscStepper::new(MoreauSscSettings::default());
    ssc.initialize(&model, &mut s, &mut ws).unwrap();
    ssc.step(&model, &mut s, &mut ws, 1e-3).unwrap();
    let n = counting_alloc::allocations_in(|| {
        for _ in 0..20 {
            ssc.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        }
    });
    assert_eq!(n, 0, "adaptive Moreau steps allocated {n} times");
}

/// Force elements (`Load::Element`): a PID servo with its integrator body (three frames), a
/// joint spring-damper and friction on a revolute joint, and a bushing to a second body;
/// generalized-alpha, dense and sparse backend.
#[test]
fn force_element_steps_do_not_allocate() {
    use flexmbs_core::force::*;
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let arm = spec.add_body(
        "arm",
        RigidBody::new(1.0, Matrix3::identity() * 0.1).with_rotation(RotationParam::Quaternion),
    );
    let tip = spec.add_body("tip", RigidBody::new(0.2, Matrix3::identity() * 0.01));
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    let hub = spec.add_frame(
        "hub",
        arm,
        Vector3::new(-0.5, 0.0, 0.0),
        Matrix3::identity(),
    );
    let end = spec.add_frame("end", arm, Vector3::new(0.5, 0.0, 0.0), Matrix3::identity());
    let ft = spec.add_frame("ft", tip, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("hinge", g, hub));
    let servo = JointServo {
        name: "servo".into(),
        frames: vec![g, hub],
        axis: JointAxis::Rotation,
        reference: TimeFunction::Harmonic {
            amplitude: 0.2,
            frequency_hz: 1.0,
            phase: 0.0,
            offset: 0.0,
        },
        gains: ServoGains {
            kp: 100.0,
            ki: 50.0,
            kd: 5.0,
        },
    };
    add_joint_servo(&mut spec, servo, 1e-3);
    let spring = JointSpringDamper {
        name: "spring".into(),
        frames: [g, hub],
        axis: JointAxis::Rotation,
        stiffness: 3.0,
        damping: 0.1,
        reference: 0.0,
        preload: 0.5,
    };
    spec.add_load(Load::Element(ForceElementRef::new(spring)));
    let friction = JointFriction {
        name: "friction".into(),
        frames: [g, hub],
        axis: JointAxis::Rotation,
        coulomb: 0.1,
        slip_velocity: 0.05,
    };
    spec.add_load(Load::Element(ForceElementRef::new(friction)));
    spec.add_load(Load::Element(ForceElementRef::new(Bushing::diagonal(
        "bushing", end, ft, [1e4; 6], [10.0; 6],
    ))));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        arm,
        Vector3::new(0.5, 0.0, 0.0),
        Matrix3::identity(),
    );
    model.set_body_pose(
        &mut s,
        tip,
        Vector3::new(1.0, 0.0, 0.0),
        Matrix3::identity(),
    );
    let n = steps_allocations(&model, &s, LinearSolver::Dense, false)
        + steps_allocations(&model, &s, LinearSolver::Sparse, false);
    assert_eq!(n, 0, "allocations in 20 steps with force elements");
}
