//! Shared model builders and measurement helpers of the reference tests.
#![allow(dead_code)]

use flexmbs_core::*;
use nalgebra::{Matrix3, Rotation3, Vector3};

/// Physical pendulum: rigid body (mass `m`, inertia `ic` about the centre of mass) on a
/// revolute joint (axis z) at distance `l` above its centre of mass, gravity `-g y`.
pub struct Pendulum {
    pub model: Model,
    pub body: BodyId,
    pub m: f64,
    pub ic: f64,
    pub l: f64,
    pub g: f64,
}

impl Pendulum {
    pub fn new(rotation: RotationParam) -> Self {
        let (m, ic, l, g) = (1.5, 0.02, 0.8, 9.81);
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, -g, 0.0));
        let body = spec.add_body(
            "bob",
            RigidBody::new(m, Matrix3::identity() * ic).with_rotation(rotation),
        );
        let pivot_g = spec.add_ground_frame("pivot", Vector3::zeros(), Matrix3::identity());
        let pivot_b = spec.add_frame(
            "pivot_b",
            body,
            Vector3::new(0.0, l, 0.0),
            Matrix3::identity(),
        );
        spec.add_joint(Joint::revolute("hinge", pivot_g, pivot_b));
        Self {
            model: spec.compile().unwrap(),
            body,
            m,
            ic,
            l,
            g,
        }
    }

    /// State at angle `theta0` from the vertical, at rest.
    pub fn state(&self, theta0: f64) -> State {
        let mut s = self.model.initial_state();
        let r = Rotation3::from_axis_angle(&Vector3::z_axis(), theta0).into_inner();
        let com = Vector3::new(self.l * theta0.sin(), -self.l * theta0.cos(), 0.0);
        self.model.set_body_pose(&mut s, self.body, com, r);
        s
    }

    /// Angle from the vertical of the centre of mass.
    pub fn angle(&self, s: &State) -> f64 {
        let q = self.model.body_q(self.body, &s.q);
        q[0].atan2(-q[1])
    }

    /// Small-amplitude angular frequency `sqrt(m g l / (ic + m l^2))`.
    pub fn omega0(&self) -> f64 {
        (self.m * self.g * self.l / (self.ic + self.m * self.l * self.l)).sqrt()
    }
}

/// Times of upward zero crossings of a sampled signal (linear interpolation).
pub fn upward_crossings(samples: &[(f64, f64)]) -> Vec<f64> {
    samples
        .windows(2)
        .filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0)
        .map(|w| {
            let ((t0, x0), (t1, x1)) = (w[0], w[1]);
            t0 + (t1 - t0) * (-x0) / (x1 - x0)
        })
        .collect()
}

/// Mean period from successive upward crossings.
pub fn mean_period(samples: &[(f64, f64)]) -> f64 {
    let c = upward_crossings(samples);
    assert!(c.len() >= 2, "need two crossings, got {}", c.len());
    (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64
}

/// Complete elliptic integral of the first kind `K(k) = pi / (2 AGM(1, sqrt(1 - k^2)))`.
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    // quadratic convergence: 10 iterations reach machine precision for k < 0.999
    for _ in 0..10 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// Positions after each of `steps` generalized-alpha steps of size `h` (default settings, full or
/// modified Newton) with the linear-solver backend `choice`, from `s0`.
pub fn genalpha_trajectory(
    model: &Model,
    s0: &State,
    choice: algebra::LinearSolver,
    modified: bool,
    h: f64,
    steps: usize,
) -> Vec<Vec<f64>> {
    use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, NewtonSettings};
    let settings = GenAlphaSettings {
        newton: NewtonSettings {
            modified,
            ..Default::default()
        },
        ..Default::default()
    };
    let ga = GenAlpha::new(settings).unwrap();
    let mut s = s0.clone();
    let mut ws = Workspace::with_linear_solver(model, choice);
    ga.initialize(model, &mut s, &mut ws).unwrap();
    (0..steps)
        .map(|_| {
            ga.step(model, &mut s, &mut ws, h).unwrap();
            s.q.clone()
        })
        .collect()
}
