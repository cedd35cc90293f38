//! Force elements (`flexmbs_core::force`) against closed forms: joint spring-dampers (an
//! undamped one conserving energy and oscillating at sqrt(k/I), a damped one decaying as the
//! damped oscillator), the bushing (static deflection F/k; a stiff one equals a fixed joint),
//! the P and PI servo holding a pendulum against gravity, regularized joint friction
//! decelerating a wheel at Q_c/I, and the extension points (a user force, a user time function).

use flexmbs_core::force::{
    add_joint_servo, revolute_angle, Bushing, ForceElement, ForceElementRef, JointAxis,
    JointFriction, JointServo, JointSpringDamper, ServoGains, Wrench,
};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, Statics};
use flexmbs_core::user_function::{UserFunctionRef, UserTimeFunction};
use flexmbs_core::*;
use nalgebra::{Matrix3, Rotation3, Vector3};

fn rz(phi: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::z_axis(), phi).into_inner()
}

fn element(e: impl ForceElement + 'static) -> Load {
    Load::Element(ForceElementRef::new(e))
}

/// A rigid disc (inertia `izz` about z, centre on the axis) on a revolute joint to ground at
/// the origin, turned by `phi0`, with the given force elements (built from the joint frames).
fn disc_on_revolute(
    izz: f64,
    phi0: f64,
    omega0: f64,
    loads: impl Fn(FrameId, FrameId) -> Vec<Load>,
) -> (Model, State, FrameId, FrameId) {
    let mut spec = ModelSpec::new();
    let body = spec.add_body(
        "disc",
        RigidBody::new(2.0, Matrix3::from_diagonal(&Vector3::new(0.03, 0.03, izz)))
            .with_rotation(RotationParam::Quaternion),
    );
    let a = spec.add_ground_frame("axis", Vector3::zeros(), Matrix3::identity());
    let b = spec.add_frame("hub", body, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("hinge", a, b));
    for l in loads(a, b) {
        spec.add_load(l);
    }
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(&mut s, body, Vector3::zeros(), rz(phi0));
    model.set_body_velocity(
        &mut s,
        body,
        Vector3::zeros(),
        Vector3::new(0.0, 0.0, omega0),
    );
    (model, s, a, b)
}

fn angle(model: &Model, s: &State, ws: &mut Workspace, a: FrameId, b: FrameId) -> (f64, f64) {
    system::evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
    let c = revolute_angle(&ws.sys.frames[a.0], &ws.sys.frames[b.0]);
    (c.value, c.rate)
}

fn energy(model: &Model, s: &State, ws: &mut Workspace) -> system::Energy {
    system::evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
    let sys = &mut ws.sys;
    system::energy(model, &s.q, &s.u, &mut sys.eval, &sys.frames)
}

fn spring(a: FrameId, b: FrameId, k: f64, d: f64, x0: f64, preload: f64) -> JointSpringDamper {
    JointSpringDamper {
        name: "spring".into(),
        frames: [a, b],
        axis: JointAxis::Rotation,
        stiffness: k,
        damping: d,
        reference: x0,
        preload,
    }
}

/// Undamped rotational spring with preload: equilibrium `phi_e = phi0 + preload / k`, motion
/// `phi_e + A cos(w t)`, `w = sqrt(k / I)` (A = 0.17 rad, w = 50 rad/s, 8 periods, h = 1e-4:
/// phase error of the integrator ~ (w h)^2 / 12 per radian, 2e-5 rad after 8 periods), within
/// 1e-3 A; the energy (kinetic + spring) constant within 1e-6 relative.
#[test]
fn undamped_revolute_spring_conserves_energy_and_oscillates_at_sqrt_k_over_i() {
    let (izz, k, x0, preload) = (0.02, 50.0, 0.1, 1.5);
    let phi_e = x0 + preload / k;
    let amp = 0.17;
    let (model, mut s, a, b) = disc_on_revolute(izz, phi_e + amp, 0.0, |a, b| {
        vec![element(spring(a, b, k, 0.0, x0, preload))]
    });
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let e0 = energy(&model, &s, &mut ws);
    assert!(e0.springs > 0.0 && e0.kinetic == 0.0);
    let w = (k / izz).sqrt();
    let (mut worst_phi, mut worst_e) = (0.0_f64, 0.0_f64);
    let h = 1e-4;
    for _ in 0..10_000 {
        ga.step(&model, &mut s, &mut ws, h).unwrap();
        let (phi, _) = angle(&model, &s, &mut ws, a, b);
        worst_phi = worst_phi.max((phi - (phi_e + amp * (w * s.t).cos())).abs());
        worst_e = worst_e.max((energy(&model, &s, &mut ws).total() - e0.total()).abs());
    }
    println!(
        "max angle error {worst_phi:e} rad, max energy error {worst_e:e} J of {:e}",
        e0.total()
    );
    assert!(worst_phi < 1e-3 * amp, "angle error {worst_phi:e}");
    assert!(worst_e < 1e-6 * e0.total(), "energy error {worst_e:e}");
}

/// Damped rotational spring (zeta = 0.05): `phi(t) = A e^(-zeta w t) (cos(w_d t) +
/// zeta / sqrt(1 - zeta^2) sin(w_d t))`, released at rest from A = 0.2 rad; within 1e-3 A over
/// 1 s (h = 1e-4).
#[test]
fn damped_revolute_spring_decays_as_the_damped_oscillator() {
    let (izz, k, zeta): (f64, f64, f64) = (0.02, 50.0, 0.05);
    let w = (k / izz).sqrt();
    let d = 2.0 * zeta * w * izz;
    let amp = 0.2;
    let (model, mut s, a, b) = disc_on_revolute(izz, amp, 0.0, |a, b| {
        vec![element(spring(a, b, k, d, 0.0, 0.0))]
    });
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let exact = |t: f64| {
        amp * (-zeta * w * t).exp()
            * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin())
    };
    let mut worst = 0.0_f64;
    for _ in 0..10_000 {
        ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        let (phi, _) = angle(&model, &s, &mut ws, a, b);
        worst = worst.max((phi - exact(s.t)).abs());
    }
    let (phi, _) = angle(&model, &s, &mut ws, a, b);
    println!(
        "max error {worst:e} rad; phi(1 s) = {phi:e}, exact {:e}",
        exact(1.0)
    );
    assert!(worst < 1e-3 * amp, "error {worst:e}");
}

/// A block (m = 2 kg) on a prismatic joint (x free) with a translational spring-damper
/// (k = 800 N/m, d = 8 N s/m, preload 16 N): static position x0 + preload / k = 0.02 m
/// (statics, 1e-12), and the damped motion from x = 0.07 m at rest as the closed form
/// (zeta = d / (2 sqrt(k m)) = 0.1), within 1e-3 of the amplitude over 1 s.
#[test]
fn prismatic_spring_damper_matches_statics_and_damped_oscillator() {
    let (m, k, d, preload) = (2.0, 800.0, 8.0, 16.0);
    let build = |x_start: f64| {
        let mut spec = ModelSpec::new();
        let body = spec.add_body(
            "block",
            RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(0.1, 0.1, 0.1))),
        );
        let a = spec.add_ground_frame("rail", Vector3::zeros(), Matrix3::identity());
        let b = spec.add_frame("slider", body, Vector3::zeros(), Matrix3::identity());
        spec.add_joint(Joint::prismatic("slide", a, b));
        spec.add_load(element(JointSpringDamper {
            name: "spring".into(),
            frames: [a, b],
            axis: JointAxis::Translation,
            stiffness: k,
            damping: d,
            reference: 0.0,
            preload,
        }));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        model.set_body_pose(
            &mut s,
            body,
            Vector3::new(x_start, 0.0, 0.0),
            Matrix3::identity(),
        );
        (model, s)
    };
    let x_e = preload / k;
    let (model, mut s) = build(0.0);
    let mut ws = Workspace::new(&model);
    Statics::default().solve(&model, &mut s, &mut ws).unwrap();
    println!("static x = {:e}, expected {x_e:e}", s.q[0]);
    assert!((s.q[0] - x_e).abs() < 1e-12, "static x {}", s.q[0]);

    let amp = 0.05;
    let (model, mut s) = build(x_e + amp);
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let w = (k / m).sqrt();
    let zeta = d / (2.0 * (k * m).sqrt());
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let exact = |t: f64| {
        x_e + amp
            * (-zeta * w * t).exp()
            * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin())
    };
    let mut worst = 0.0_f64;
    for _ in 0..10_000 {
        ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        worst = worst.max((s.q[0] - exact(s.t)).abs());
    }
    println!("max error {worst:e} m");
    assert!(worst < 1e-3 * amp, "error {worst:e}");
}

/// A body (m = 2 kg) hanging from ground under gravity (-9.81 y), attached at a point 0.5 m
/// above its centre of mass, by a bushing (`Some((k_t, d_t))`, rotational stiffness and damping
/// 0.1 of them) or by a fixed joint; a lateral force F = 30 N x at the attachment point.
/// Returns the centre of mass: at static equilibrium (statics) or, with `t_end`, after a
/// dynamic run from rest (generalized-alpha, h = 1 ms).
fn hanging_body(bushing: Option<(f64, f64)>, t_end: Option<f64>) -> Vector3<f64> {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let body = spec.add_body(
        "body",
        RigidBody::new(2.0, Matrix3::from_diagonal(&Vector3::new(0.05, 0.02, 0.05)))
            .with_rotation(RotationParam::Quaternion),
    );
    let a = spec.add_ground_frame("mount", Vector3::new(0.0, 0.5, 0.0), Matrix3::identity());
    let b = spec.add_frame(
        "eye",
        body,
        Vector3::new(0.0, 0.5, 0.0),
        Matrix3::identity(),
    );
    match bushing {
        Some((kt, dt)) => {
            let (kr, dr) = (0.1 * kt, 0.1 * dt);
            spec.add_load(element(Bushing::diagonal(
                "bushing",
                a,
                b,
                [kt, kt, kt, kr, kr, kr],
                [dt, dt, dt, dr, dr, dr],
            )));
        }
        None => {
            spec.add_joint(Joint::fixed("clamp", a, b));
        }
    }
    spec.add_load(Load::Force {
        frame: b,
        vector: Vector3::new(30.0, 0.0, 0.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let mut ws = Workspace::new(&model);
    match t_end {
        None => {
            Statics::default().solve(&model, &mut s, &mut ws).unwrap();
        }
        Some(t_end) => {
            let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
            ga.initialize(&model, &mut s, &mut ws).unwrap();
            ga.integrate(&model, &mut s, &mut ws, 1e-3, t_end, |_, _| {})
                .unwrap();
        }
    }
    Vector3::new(s.q[0], s.q[1], s.q[2])
}

/// Bushing statics: the attachment point moves by `K^-1 F` = (30, -19.62, 0) / k_t and the body
/// does not turn (the loads pass through the attachment point and the centre of mass below it),
/// to 1e-9 relative. Stiff limit: after 0.5 s from rest, a bushing with k_t = 1e6 N/m
/// (critically damped translation, d_t = 2 sqrt(k_t m)) holds the body where the fixed joint
/// does, within 1.01 |F| / k_t (its static deflection).
#[test]
fn bushing_deflects_by_f_over_k_and_equals_a_fixed_joint_when_stiff() {
    let f = Vector3::new(30.0, -2.0 * 9.81, 0.0);
    let kt = 1e4;
    let p = hanging_body(Some((kt, 0.0)), None);
    let expected = f / kt;
    println!("bushing centre {p:?}, expected {expected:?}");
    assert!((p - expected).norm() < 1e-9 * expected.norm(), "{p:?}");
    let kt = 1e6;
    let fixed = hanging_body(None, Some(0.5));
    let stiff = hanging_body(Some((kt, 2.0 * (kt * 2.0).sqrt())), Some(0.5));
    println!(
        "fixed joint {fixed:?}; stiff bushing - fixed joint: {:e} (|F|/k {:e})",
        (stiff - fixed).norm(),
        f.norm() / kt
    );
    assert!((stiff - fixed).norm() < 1.01 * f.norm() / kt);
}

/// A pendulum (m = 1.5 kg, centre of mass l = 0.4 m from the pivot, I_c,zz = 0.02) held
/// horizontal (phi_ref = 0) against gravity by a servo (K_p = 200 N m/rad, K_d = 5). The P
/// servo settles at the error e solving `K_p e + m g l cos(e) = 0` (to first order
/// -m g l / K_p = -0.0294 rad), to 1e-8 rad after 4 s; the PI servo (K_i = 400) at e = 0 to 1e-7
/// rad after 10 s, with the drive torque m g l (the signal) to 1e-6 relative.
#[test]
fn servo_holds_a_pendulum_with_p_error_mgl_over_kp_and_none_with_pi() {
    let (m, l, g, kp, kd) = (1.5, 0.4, 9.81, 200.0, 5.0);
    let run = |ki: f64, t_end: f64| {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, -g, 0.0));
        let body = spec.add_body(
            "arm",
            RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(0.002, 0.02, 0.02)))
                .with_rotation(RotationParam::Quaternion),
        );
        let a = spec.add_ground_frame("pivot", Vector3::zeros(), Matrix3::identity());
        let b = spec.add_frame("hub", body, Vector3::new(-l, 0.0, 0.0), Matrix3::identity());
        spec.add_joint(Joint::revolute("shoulder", a, b));
        let servo = JointServo {
            name: "servo".into(),
            frames: vec![a, b],
            axis: JointAxis::Rotation,
            reference: TimeFunction::Constant(0.0),
            gains: ServoGains { kp, ki, kd },
        };
        let id = add_joint_servo(&mut spec, servo, 1e-3);
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        model.set_body_pose(&mut s, body, Vector3::new(l, 0.0, 0.0), Matrix3::identity());
        let mut ws = Workspace::new(&model);
        let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        ga.integrate(&model, &mut s, &mut ws, 1e-3, t_end, |_, _| {})
            .unwrap();
        let (e, _) = angle(&model, &s, &mut ws, a, b);
        let Load::Element(servo) = &model.loads[id.0] else {
            unreachable!()
        };
        let torque = servo.output(s.t, &ws.sys.frames).unwrap();
        (e, torque)
    };
    // independent reference: fixed point of K_p e = -m g l cos(e)
    let mut e_ref = 0.0_f64;
    for _ in 0..100 {
        e_ref = -m * g * l * e_ref.cos() / kp;
    }
    let (e_p, _) = run(0.0, 4.0);
    println!(
        "P: e = {e_p:e}, expected {e_ref:e} (first order {:e})",
        -m * g * l / kp
    );
    assert!((e_p - e_ref).abs() < 1e-8, "P error {e_p:e}");
    let (e_pi, torque) = run(400.0, 10.0);
    println!(
        "PI: e = {e_pi:e}, drive torque {torque:e} (m g l = {:e})",
        m * g * l
    );
    assert!(e_pi.abs() < 1e-7, "PI error {e_pi:e}");
    assert!(
        (torque - m * g * l).abs() < 1e-6 * m * g * l,
        "torque {torque}"
    );
}

/// A wheel (I_zz = 0.05) spinning at 20 rad/s with joint friction Q_c = 0.5 N m (slip velocity
/// 0.05 rad/s) decelerates at Q_c / I = 10 rad/s^2: omega(1 s) = 10 rad/s to 1e-8, and it is at
/// rest at 2.5 s (below the slip velocity it creeps to rest at the rate Q_c / (v_s I) = 200/s),
/// |omega| < 1e-6 rad/s.
#[test]
fn joint_friction_decelerates_a_wheel_at_friction_torque_over_inertia() {
    let (izz, qc, w0) = (0.05, 0.5, 20.0);
    let (model, mut s, a, b) = disc_on_revolute(izz, 0.0, w0, |a, b| {
        vec![element(JointFriction {
            name: "bearing".into(),
            frames: [a, b],
            axis: JointAxis::Rotation,
            coulomb: qc,
            slip_velocity: 0.05,
        })]
    });
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    ga.integrate(&model, &mut s, &mut ws, 1e-3, 1.0, |_, _| {})
        .unwrap();
    let (_, w1) = angle(&model, &s, &mut ws, a, b);
    println!("omega(1 s) = {w1}, expected {}", w0 - qc / izz);
    assert!((w1 - (w0 - qc / izz)).abs() < 1e-8, "omega {w1}");
    ga.integrate(&model, &mut s, &mut ws, 1e-3, 2.5, |_, _| {})
        .unwrap();
    let (_, w2) = angle(&model, &s, &mut ws, a, b);
    println!("omega(2.5 s) = {w2:e}");
    assert!(w2.abs() < 1e-6, "omega {w2}");
}

/// A user force through the extension point: linear drag `-c v` on one frame (default
/// numerical tangent, no potential).
#[derive(Debug)]
struct Drag {
    frames: [FrameId; 1],
    c: f64,
}

impl ForceElement for Drag {
    fn name(&self) -> &str {
        "drag"
    }
    fn frames(&self) -> &[FrameId] {
        &self.frames
    }
    fn wrenches(&self, _t: f64, frames: &[FrameKinematics], out: &mut [Wrench]) {
        out[0] = Wrench {
            force: -frames[self.frames[0].0].velocity * self.c,
            moment: Vector3::zeros(),
        };
    }
}

/// A user time function: `f(t) = t^2` with only `value` given (defaults for the rest).
#[derive(Debug)]
struct Square;

impl UserTimeFunction for Square {
    fn value(&self, t: f64) -> f64 {
        t * t
    }
}

/// The extension points: a free body (m = 2 kg) with a user drag force (c = 4 N s/m) and a
/// user time function pushing it (F = 3 t^2 N, along y) moves as
/// `v_x = v0 e^(-c t / m)` and `m v_y' = 3 t^2 - c v_y` (solved here in closed form), to 1e-6
/// relative at t = 1 s; the defaults of the user time function (derivatives, integral) match
/// the closed forms 2t, 2, t^3/3 to 1e-6.
#[test]
fn user_force_and_user_time_function_extend_the_engine() {
    let (m, c, v0) = (2.0, 4.0, 1.5);
    let mut spec = ModelSpec::new();
    let body = spec.add_body(
        "puck",
        RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(0.1, 0.1, 0.1)))
            .with_rotation(RotationParam::Quaternion),
    );
    let f = spec.add_frame("centre", body, Vector3::zeros(), Matrix3::identity());
    spec.add_load(element(Drag { frames: [f], c }));
    let square = TimeFunction::User(UserFunctionRef::new(Square));
    for t in [0.3, 1.7] {
        assert!((square.value(t) - t * t).abs() < 1e-15);
        assert!((square.derivative(t) - 2.0 * t).abs() < 1e-6);
        assert!((square.second_derivative(t) - 2.0).abs() < 1e-6);
        assert!((square.integral(t) - t * t * t / 3.0).abs() < 1e-6);
    }
    spec.add_load(Load::Force {
        frame: f,
        vector: Vector3::new(0.0, 3.0, 0.0),
        time: square,
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_velocity(&mut s, body, Vector3::new(v0, 0.0, 0.0), Vector3::zeros());
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    ga.integrate(&model, &mut s, &mut ws, 1e-4, 1.0, |_, _| {})
        .unwrap();
    let vx = v0 * (-c / m).exp();
    // m v' + c v = 3 t^2, v(0) = 0: v = (3/c)(t^2 - 2 a t + 2 a^2 (1 - e^(-t/a))), a = m / c
    let a = m / c;
    let vy = 3.0 / c * (1.0 - 2.0 * a + 2.0 * a * a * (1.0 - (-1.0 / a).exp()));
    println!("v = ({}, {}), expected ({vx}, {vy})", s.u[0], s.u[1]);
    assert!((s.u[0] - vx).abs() < 1e-6 * vx);
    assert!((s.u[1] - vy).abs() < 1e-6 * vy);
}

/// Bad parameters are refused by `compile` with the element's name.
#[test]
fn bad_force_element_parameters_are_refused() {
    let mut spec = ModelSpec::new();
    let body = spec.add_body(
        "disc",
        RigidBody::new(1.0, Matrix3::from_diagonal(&Vector3::new(0.1, 0.1, 0.1))),
    );
    let a = spec.add_ground_frame("axis", Vector3::zeros(), Matrix3::identity());
    let b = spec.add_frame("hub", body, Vector3::zeros(), Matrix3::identity());
    spec.add_load(element(spring(a, b, -1.0, 0.0, 0.0, 0.0)));
    let err = spec.compile().unwrap_err();
    assert!(
        matches!(&err, ModelError::InvalidForceElement { element, reason }
            if element == "spring" && reason.contains("stiffness")),
        "{err}"
    );
}

/// The local load tangents of force elements (per element, only its frames' owners perturbed;
/// a servo with its integrator body has three owners) equal central differences of the
/// assembled load forces over all coordinates (along `q ⊕ dv` and `u`), at a general moving
/// state, to 1e-8 of the largest entry (the same differences: round-off only).
#[test]
fn force_element_tangents_equal_global_differences() {
    use flexmbs_core::system::{add_load_forces, add_load_tangents, evaluate, integrate_positions};
    let mut spec = ModelSpec::new();
    let arm = spec.add_body(
        "arm",
        RigidBody::new(1.0, Matrix3::from_diagonal(&Vector3::new(0.01, 0.1, 0.1)))
            .with_rotation(RotationParam::Quaternion),
    );
    let tip = spec.add_body(
        "tip",
        RigidBody::new(0.2, Matrix3::identity() * 0.01).with_rotation(RotationParam::Quaternion),
    );
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    let hub = spec.add_frame("hub", arm, Vector3::new(-0.5, 0.0, 0.0), rz(0.3));
    let end = spec.add_frame("end", arm, Vector3::new(0.5, 0.1, 0.0), Matrix3::identity());
    let ft = spec.add_frame("ft", tip, Vector3::new(0.0, 0.05, 0.0), rz(-0.2));
    let servo = JointServo {
        name: "servo".into(),
        frames: vec![g, hub],
        axis: JointAxis::Rotation,
        reference: TimeFunction::Constant(0.4),
        gains: ServoGains {
            kp: 100.0,
            ki: 50.0,
            kd: 5.0,
        },
    };
    add_joint_servo(&mut spec, servo, 1e-3);
    spec.add_load(element(spring(g, hub, 30.0, 2.0, 0.1, 0.5)));
    spec.add_load(element(JointSpringDamper {
        axis: JointAxis::Translation,
        ..spring(end, ft, 300.0, 4.0, 0.2, 1.0)
    }));
    spec.add_load(element(JointFriction {
        name: "friction".into(),
        frames: [g, hub],
        axis: JointAxis::Rotation,
        coulomb: 0.5,
        slip_velocity: 2.0,
    }));
    let mut bushing = Bushing::diagonal(
        "bushing",
        end,
        ft,
        [1e3, 2e3, 3e3, 40.0, 50.0, 60.0],
        [1.0, 2.0, 3.0, 0.1, 0.2, 0.3],
    );
    bushing.stiffness[(0, 4)] = 100.0;
    bushing.stiffness[(4, 0)] = 100.0;
    spec.add_load(element(bushing));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let turn = Rotation3::from_euler_angles(0.2, -0.3, 0.5).into_inner();
    model.set_body_pose(&mut s, arm, Vector3::new(0.5, 0.1, -0.05), turn);
    model.set_body_pose(&mut s, tip, Vector3::new(1.1, 0.2, 0.03), rz(0.4) * turn);
    model.set_body_velocity(
        &mut s,
        arm,
        Vector3::new(0.3, -0.2, 0.1),
        Vector3::new(0.5, -1.0, 2.0),
    );
    model.set_body_velocity(
        &mut s,
        tip,
        Vector3::new(-0.1, 0.4, 0.2),
        Vector3::new(1.0, 0.3, -0.7),
    );
    let (mut q, mut u) = (s.q.clone(), s.u.clone());
    let nu = model.nu;
    q[model.nq - 1] = 0.02; // the servo's integral state
    u[nu - 1] = -0.3;
    let mut ws = Workspace::new(&model);
    let mut forces = |q: &[f64], u: &[f64], h: &mut Vec<f64>| {
        evaluate(&model, q, u, &mut ws.sys).unwrap();
        h.iter_mut().for_each(|x| *x = 0.0);
        add_load_forces(&model, 0.7, 1.0, &ws.sys.frames, h);
    };
    let (mut hp, mut hm) = (vec![0.0; nu], vec![0.0; nu]);
    let (mut ref_q, mut ref_u) = (vec![vec![0.0; nu]; nu], vec![vec![0.0; nu]; nu]);
    let mut qp = q.clone();
    for j in 0..nu {
        let eps = 1e-6;
        let mut dv = vec![0.0; nu];
        dv[j] = eps;
        integrate_positions(&model, &q, &dv, &mut qp);
        forces(&qp, &u, &mut hp);
        dv[j] = -eps;
        integrate_positions(&model, &q, &dv, &mut qp);
        forces(&qp, &u, &mut hm);
        for i in 0..nu {
            ref_q[i][j] = (hp[i] - hm[i]) / (2.0 * eps);
        }
        let eps = 1e-6 * u[j].abs().max(1.0);
        let mut up = u.clone();
        up[j] = u[j] + eps;
        forces(&q, &up, &mut hp);
        up[j] = u[j] - eps;
        forces(&q, &up, &mut hm);
        for i in 0..nu {
            ref_u[i][j] = (hp[i] - hm[i]) / (2.0 * eps);
        }
    }
    evaluate(&model, &q, &u, &mut ws.sys).unwrap();
    ws.sys.dh_dq.fill(0.0);
    ws.sys.dh_du.fill(0.0);
    add_load_tangents(&model, 0.7, &q, &u, 1.0, &mut ws.sys);
    for (what, m, r) in [
        ("dh/dq", &ws.sys.dh_dq, &ref_q),
        ("dh/du", &ws.sys.dh_du, &ref_u),
    ] {
        let scale = r.iter().flatten().fold(0.0_f64, |a, x| a.max(x.abs()));
        let mut diff = 0.0_f64;
        for i in 0..nu {
            for j in 0..nu {
                diff = diff.max((m[(i, j)] - r[i][j]).abs());
            }
        }
        println!("{what}: max difference {diff:e} of {scale:e}");
        assert!(
            scale > 1.0 && diff <= 1e-8 * scale,
            "{what}: {diff:e} of {scale:e}"
        );
    }
}
