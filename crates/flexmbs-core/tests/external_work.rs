//! External work (`flexmbs_core::power`): drive, point-load and damper work accumulated over
//! generalized-alpha steps against analytic values, and the balance `E(t) - E(0) = W(t)`.

use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::power::{external_power, has_external_work, WorkMeter};
use flexmbs_core::system::{energy, evaluate};
use flexmbs_core::{
    Joint, Load, LoadCoordinates, Model, ModelSpec, PrescribedMotion, RigidBody, RotationParam,
    State, TimeFunction, Workspace,
};
use nalgebra::{Matrix3, Vector3};

/// Integrates `t_end` s with step `h`; returns `(E(t_end) - E(0), W(t_end))`.
fn run(model: &Model, mut s: State, h: f64, t_end: f64) -> (f64, f64) {
    let mut ws = Workspace::new(model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(model, &mut s, &mut ws).unwrap();
    let mut meter = WorkMeter::default();
    let measure = |s: &State, ws: &mut Workspace, meter: &mut WorkMeter| {
        evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
        let p = external_power(model, s.t, &ws.sys.frames, &s.lambda);
        meter.advance(s.t, p.total());
        energy(model, &s.q, &s.u, &mut ws.sys.eval, &ws.sys.frames).total()
    };
    let e0 = measure(&s, &mut ws, &mut meter);
    for _ in 0..(t_end / h).round() as usize {
        ga.step(model, &mut s, &mut ws, h).unwrap();
        measure(&s, &mut ws, &mut meter);
    }
    let e1 = measure(&s, &mut ws, &mut WorkMeter::default());
    (e1 - e0, meter.work())
}

/// A rotor (I_zz = 0.3 kg m^2) on a revolute joint whose rate is ramped from 0 to 10 rad/s in
/// 1 s: the drive does `W = 1/2 I omega^2 = 15 J` (all of it kinetic energy).
#[test]
fn drive_work_equals_kinetic_energy_gained() {
    let (i_zz, omega) = (0.3, 10.0);
    let mut spec = ModelSpec::new();
    let rotor = spec.add_body(
        "rotor",
        RigidBody::new(2.0, Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, i_zz)))
            .with_rotation(RotationParam::Quaternion),
    );
    let g = spec.add_ground_frame("axis", Vector3::zeros(), Matrix3::identity());
    let b = spec.add_frame("hub", rotor, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("drive", g, b).with_prescribed(
        PrescribedMotion::RevoluteRate {
            initial_angle: 0.0,
            rate: TimeFunction::Ramp {
                t0: 0.0,
                t1: 1.0,
                v0: 0.0,
                v1: omega,
            },
        },
    ));
    let model = spec.compile().unwrap();
    assert!(has_external_work(&model));
    let (de, w) = run(&model, model.initial_state(), 1e-3, 1.0);
    let exact = 0.5 * i_zz * omega * omega;
    println!("drive: W = {w:.12} J (exact {exact}), E - E0 = {de:.12} J");
    assert!((w - exact).abs() < 1e-9 * exact, "W = {w}");
    assert!((de - w).abs() < 1e-9 * exact, "E - E0 = {de}, W = {w}");
}

/// A free body (2 kg) pushed by a constant 3 N force for 2 s from rest: `W = (F t)^2 / (2 m)`
/// = 9 J; a second body on a spring-damper (k = 50 N/m, d = 0.8 N s/m) released from a
/// stretched spring loses energy only through the damper: `E - E0 = W` to 1e-6 of the energy
/// dissipated.
#[test]
fn load_and_damper_work_close_the_energy_balance() {
    let (m, f, t_end) = (2.0, 3.0, 2.0);
    let mut spec = ModelSpec::new();
    let pushed = spec.add_body("pushed", RigidBody::new(m, Matrix3::identity() * 0.1));
    let p = spec.add_frame("p", pushed, Vector3::zeros(), Matrix3::identity());
    spec.add_load(Load::Force {
        frame: p,
        vector: Vector3::new(f, 0.0, 0.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile().unwrap();
    let (de, w) = run(&model, model.initial_state(), 1e-3, t_end);
    let exact = (f * t_end).powi(2) / (2.0 * m);
    println!("force: W = {w:.12} J (exact {exact}), E - E0 = {de:.12} J");
    assert!((w - exact).abs() < 1e-9 * exact, "W = {w}");
    assert!((de - w).abs() < 1e-9 * exact);

    let mut spec = ModelSpec::new();
    let mass = spec.add_body("mass", RigidBody::new(m, Matrix3::identity() * 0.1));
    let anchor = spec.add_ground_frame("anchor", Vector3::zeros(), Matrix3::identity());
    let b = spec.add_frame("b", mass, Vector3::zeros(), Matrix3::identity());
    spec.add_load(Load::SpringDamper {
        frame_a: anchor,
        frame_b: b,
        stiffness: 50.0,
        damping: 0.8,
        free_length: 1.0,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        mass,
        Vector3::new(1.2, 0.0, 0.0),
        Matrix3::identity(),
    );
    let (de, w) = run(&model, s, 1e-4, t_end);
    println!("damper: W = {w:.12} J, E - E0 = {de:.12} J");
    assert!(w < -0.1 * 0.5 * 50.0 * 0.04, "too little dissipated: {w}");
    assert!((de - w).abs() < 1e-6 * w.abs(), "E - E0 = {de}, W = {w}");
}
