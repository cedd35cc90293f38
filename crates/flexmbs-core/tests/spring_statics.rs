//! Spring-mass oscillator frequency and static equilibria.
use crate::common;
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, Statics, StaticsSettings};
use flexmbs_core::*;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// Body on a prismatic joint (axis = x of `guide_rot`) with a spring to the ground origin.
fn spring_mass(
    m: f64,
    k: f64,
    l0: f64,
    gravity: Vector3<f64>,
    guide_rot: Matrix3<f64>,
) -> (Model, BodyId) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(gravity);
    let body = spec.add_body("mass", RigidBody::new(m, Matrix3::identity() * 0.01));
    let g = spec.add_ground_frame("guide", Vector3::zeros(), guide_rot);
    let c = spec.add_frame("c", body, Vector3::zeros(), guide_rot);
    spec.add_joint(Joint::prismatic("guide", g, c));
    spec.add_load(Load::SpringDamper {
        frame_a: g,
        frame_b: c,
        stiffness: k,
        damping: 0.0,
        free_length: l0,
    });
    (spec.compile().unwrap(), body)
}

/// Period of x(t) vs 2 pi sqrt(m / k), relative tolerance 1e-5 (rho_inf = 0.9, h = 5e-5).
#[test]
fn oscillator_frequency_matches_sqrt_k_over_m() {
    let (m, k, l0) = (2.0, 800.0, 1.0);
    let (model, body) = spring_mass(m, k, l0, Vector3::zeros(), Matrix3::identity());
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        body,
        Vector3::new(l0 + 0.1, 0.0, 0.0),
        Matrix3::identity(),
    );
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let t_exact = 2.0 * std::f64::consts::PI * (m / k).sqrt();
    let mut samples = Vec::new();
    ga.integrate(&model, &mut s, &mut ws, 5e-5, 2.6 * t_exact, |s, _| {
        samples.push((s.t, s.q[0] - l0))
    })
    .unwrap();
    let period = common::mean_period(&samples);
    let rel = (period - t_exact).abs() / t_exact;
    println!("period {period}, exact {t_exact}, rel {rel:e}");
    assert!(rel < 1e-5);
}

/// Mass hanging on a vertical spring (guide axis x pointing down): static deflection m g / k
/// to 1e-10, with 1 and 5 load steps; multiplier-free direction so lambda is the side load 0.
#[test]
fn hanging_mass_static_deflection() {
    let (m, k, l0, g) = (3.0, 500.0, 1.0, 9.81);
    let down =
        Rotation3::from_axis_angle(&Vector3::z_axis(), -std::f64::consts::FRAC_PI_2).into_inner();
    let (model, body) = spring_mass(m, k, l0, Vector3::new(0.0, -g, 0.0), down);
    for steps in [1, 5] {
        let mut s = model.initial_state();
        model.set_body_pose(
            &mut s,
            body,
            Vector3::new(0.0, -l0, 0.0),
            Matrix3::identity(),
        );
        let mut ws = Workspace::new(&model);
        let st = Statics::new(StaticsSettings {
            load_steps: steps,
            ..Default::default()
        })
        .solve(&model, &mut s, &mut ws)
        .unwrap();
        let y = model.body_q(body, &s.q)[1];
        let err = (y + l0 + m * g / k).abs();
        println!("steps {steps}: y {y}, error {err:e}, stats {st:?}");
        assert!(err < 1e-10);
        assert_eq!(st.increments, steps);
    }
}

/// The load path of [`Statics::solve_with`]: with 5 load steps the hanging mass reports the
/// equilibria at mu = 0.2, 0.4, ..., 1 with deflection mu m g / k (to 1e-10), in order.
#[test]
fn hanging_mass_load_path() {
    let (m, k, l0, g) = (3.0, 500.0, 1.0, 9.81);
    let down =
        Rotation3::from_axis_angle(&Vector3::z_axis(), -std::f64::consts::FRAC_PI_2).into_inner();
    let (model, body) = spring_mass(m, k, l0, Vector3::new(0.0, -g, 0.0), down);
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        body,
        Vector3::new(0.0, -l0, 0.0),
        Matrix3::identity(),
    );
    let mut ws = Workspace::new(&model);
    let mut path = Vec::new();
    let st = Statics::new(StaticsSettings {
        load_steps: 5,
        ..Default::default()
    })
    .solve_with(&model, &mut s, &mut ws, |s, mu, st| {
        path.push((mu, model.body_q(body, &s.q)[1], st.increments))
    })
    .unwrap();
    assert_eq!(path.len(), 5);
    for (i, &(mu, y, inc)) in path.iter().enumerate() {
        let mu_expected = (i + 1) as f64 / 5.0;
        assert!((mu - mu_expected).abs() < 1e-14, "mu {mu}");
        assert_eq!(inc, i + 1);
        let err = (y + l0 + mu * m * g / k).abs();
        assert!(err < 1e-10, "mu {mu}: y {y}, error {err:e}");
    }
    assert_eq!(path[4].1, model.body_q(body, &s.q)[1]);
    assert_eq!(st.increments, 5);
}

/// Pendulum pushed by a horizontal force F = 2 m g at its centre of mass: equilibrium angle
/// atan(F / (m g)) = atan 2 to 1e-10 (nonlinear; 4 load steps).
#[test]
fn pendulum_under_horizontal_force_static_angle() {
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
    let com = spec.add_frame("com", body, Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::revolute("hinge", pivot_g, pivot_b));
    let f = 2.0 * p.m * p.g;
    spec.add_load(Load::Force {
        frame: com,
        vector: Vector3::new(f, 0.0, 0.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        body,
        Vector3::new(0.0, -p.l, 0.0),
        Matrix3::identity(),
    );
    let mut ws = Workspace::new(&model);
    let st = Statics::new(StaticsSettings {
        load_steps: 4,
        ..Default::default()
    })
    .solve(&model, &mut s, &mut ws)
    .unwrap();
    let q = model.body_q(body, &s.q);
    let angle = q[0].atan2(-q[1]);
    println!("angle {angle}, exact {}, stats {st:?}", 2.0_f64.atan());
    assert!((angle - 2.0_f64.atan()).abs() < 1e-10);
}
