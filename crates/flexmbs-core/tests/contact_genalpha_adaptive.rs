//! Adaptive generalized-alpha over regularized (penalty) contacts: the gap-based step
//! restriction (`AdaptiveSettings::max_penetration`) against the analytic restitution of the
//! penalty law and against the same runs without it (`max_penetration = inf`, the old control,
//! whose error estimate looks only at accelerations):
//! - a ball thrown at a fixed ball passed through it within one free-flight step (tunnelling);
//!   restricted, it rebounds with the restitution of the damped linear oscillator;
//! - a ball hitting a plane rebounds with that restitution, the error falling with the
//!   tolerance to below the fixed-step test's 1e-3, and smaller than without the restriction;
//! - adaptive steps with penalty contact and friction allocate nothing.

#[path = "support/counting_alloc.rs"]
mod counting_alloc;

use flexmbs_core::contact::{
    Contact, ContactLaw, Contour, PlaneContour, SphereContour, TangentDirections,
};
use flexmbs_core::integrator::{AdaptiveSettings, GenAlpha, GenAlphaSettings};
use flexmbs_core::{BodyId, FrameId, Model, ModelSpec, RigidBody, RotationParam, State, Workspace};
use nalgebra::{Matrix3, Vector3};
use std::ops::ControlFlow;

/// Contact stiffness (N/m) and damping (N s/m): damping ratio 0.1 on the 1 kg ball.
const K: f64 = 1e6;
const D: f64 = 200.0;

/// Coefficient of restitution of a mass on a linear spring-damper that cannot pull (damping
/// ratio `zeta`): contact ends when `k x + d x_dot = 0`, at `w_d t* = pi - atan(2 zeta
/// sqrt(1 - zeta^2) / (1 - 2 zeta^2))`, and `e = e^(-zeta w t*) |sqrt(1 - zeta^2) cos(w_d t*) -
/// zeta sin(w_d t*)| / sqrt(1 - zeta^2)` (the analytic solution of the damped oscillator).
fn no_tension_restitution(zeta: f64) -> f64 {
    let c = (1.0 - zeta * zeta).sqrt();
    let phi = std::f64::consts::PI - (2.0 * zeta * c / (1.0 - 2.0 * zeta * zeta)).atan();
    (-zeta * phi / c).exp() * (c * phi.cos() - zeta * phi.sin()).abs() / c
}

/// Largest penetration of the damped oscillator hit at `v0` (`x = v0 / w_d e^(-zeta w t)
/// sin(w_d t)`, largest where `tan(w_d t) = sqrt(1 - zeta^2) / zeta`).
fn largest_penetration(v0: f64, w: f64, zeta: f64) -> f64 {
    let c = (1.0 - zeta * zeta).sqrt();
    let phi = (c / zeta).atan();
    v0 / (w * c) * (-zeta * phi / c).exp() * phi.sin()
}

/// A ball (1 kg, radius `r`, no gravity) against the fixed contour `obstacle(frame)` (on a
/// ground frame at the origin), its centre at height `z0`, moving with `-v0` along z.
fn ball_towards<C: Contour + 'static>(
    law: ContactLaw,
    r: f64,
    obstacle: impl FnOnce(FrameId) -> C,
    z0: f64,
    v0: f64,
) -> (Model, State) {
    let m = 1.0;
    let mut spec = ModelSpec::new();
    let ball = RigidBody::new(m, Matrix3::from_diagonal_element(0.4 * m * r * r))
        .with_rotation(RotationParam::Quaternion);
    let b = spec.add_body("ball", ball);
    let centre = spec.add_frame("centre", b, Vector3::zeros(), Matrix3::identity());
    let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    let sphere = SphereContour {
        frame: centre,
        radius: r,
    };
    spec.add_contact(Contact::new("c", sphere, obstacle(ground), law));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(&mut s, BodyId(0), z0 * Vector3::z(), Matrix3::identity());
    model.set_body_velocity(&mut s, BodyId(0), -v0 * Vector3::z(), Vector3::zeros());
    (model, s)
}

/// Adaptive generalized-alpha (defaults, `rho_inf = 0.9`) with `ctl` to `t_end`: the state at
/// the end, the rejected steps, the accepted steps and the deepest gap of the run.
fn run_adaptive(model: &Model, mut s: State, ctl: &AdaptiveSettings, t_end: f64) -> Run {
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    let mut ws = Workspace::new(model);
    ga.initialize(model, &mut s, &mut ws).unwrap();
    let (mut steps, mut deepest) = (0, f64::INFINITY);
    let run = ga
        .integrate_adaptive_controlled(model, &mut s, &mut ws, ctl, t_end, |s, _| {
            steps += 1;
            deepest = deepest.min(s.contacts[0].gap);
            ControlFlow::Continue(())
        })
        .unwrap();
    Run {
        s,
        rejected: run.rejected,
        steps,
        deepest,
    }
}

/// Outcome of [`run_adaptive`].
struct Run {
    s: State,
    rejected: usize,
    steps: usize,
    deepest: f64,
}

fn unrestricted(ctl: AdaptiveSettings) -> AdaptiveSettings {
    AdaptiveSettings {
        max_penetration: f64::INFINITY,
        ..ctl
    }
}

/// A ball (r = 5 cm) thrown at 5 m/s at a fixed ball (r = 5 cm) 0.9 m away, default adaptive
/// settings (`h_max = 0.1` s): without the gap restriction the free flight's steps grow to
/// 0.1 s (0.5 m, more than the 0.2 m both balls span), no step ends in contact, and the ball
/// passes through unchanged; with it the ball rebounds with the restitution `e = 0.74408` of the
/// damped oscillator (damping ratio 0.1) to 5e-3 relative (the default tolerances, 1e-6 m: the
/// plane test below shows the error falling with them), and no step ends deeper than the
/// oscillator's largest penetration ([`largest_penetration`], 4.31 mm) plus 1e-3 of it.
#[test]
fn ball_thrown_at_a_ball_rebounds_instead_of_passing_through() {
    let (r, v0) = (0.05, 5.0);
    let law = ContactLaw::regularized(K, D);
    let obstacle = |frame| SphereContour { frame, radius: r };
    let (model, s) = ball_towards(law, r, obstacle, 1.0, v0);
    let e = no_tension_restitution(D / (2.0 * (K * 1.0_f64).sqrt()));
    let ctl = AdaptiveSettings::default();
    let old = run_adaptive(&model, s.clone(), &unrestricted(ctl), 0.5);
    let new = run_adaptive(&model, s, &ctl, 0.5);
    println!(
        "ball at ball: unrestricted z = {:.3} vz = {:.4} ({} steps); restricted z = {:.3}, \
         ratio {:.5} (e = {e:.5}), {} steps, {} rejected, deepest {:.3e}",
        old.s.q[2],
        old.s.u[2],
        old.steps,
        new.s.q[2],
        new.s.u[2] / v0,
        new.steps,
        new.rejected,
        new.deepest
    );
    assert!(
        old.s.u[2] == -v0 && old.s.q[2] < 0.0,
        "the old control tunnels"
    );
    assert!(
        (new.s.u[2] / v0 - e).abs() < 5e-3 * e,
        "rebound {}",
        new.s.u[2]
    );
    let x_max = largest_penetration(v0, (K / 1.0_f64).sqrt(), D / (2.0 * (K * 1.0_f64).sqrt()));
    assert!(
        new.deepest > -x_max * (1.0 + 1e-3),
        "deepest {} (x_max {x_max})",
        new.deepest
    );
}

/// A ball (r = 0.1 m) hitting the plane at 3 m/s from 0.5 m (no gravity), adaptive with
/// `atol = rtol` = 1e-6, 1e-7, 1e-8: the rebound ratio approaches the damped oscillator's
/// `e = 0.74408`, below 1e-3 relative at 1e-8 (the fixed-step restitution test's tolerance), and
/// at every tolerance at most half the error of the unrestricted control (which lets the closing
/// step end millimetres deep, where the damping is faded in over a long step) with fewer
/// rejected steps.
#[test]
fn ball_hitting_a_plane_rebounds_with_the_penalty_restitution() {
    let (r, v0) = (0.1, 3.0);
    let e = no_tension_restitution(D / (2.0 * (K * 1.0_f64).sqrt()));
    let mut errors = Vec::new();
    for tol in [1e-6, 1e-7, 1e-8] {
        let plane = |frame| PlaneContour { frame };
        let (model, s) = ball_towards(ContactLaw::regularized(K, D), r, plane, 0.6, v0);
        let ctl = AdaptiveSettings {
            atol: tol,
            rtol: tol,
            ..Default::default()
        };
        let old = run_adaptive(&model, s.clone(), &unrestricted(ctl), 0.4);
        let new = run_adaptive(&model, s, &ctl, 0.4);
        let (err_old, err_new) = (
            (old.s.u[2] / v0 - e).abs() / e,
            (new.s.u[2] / v0 - e).abs() / e,
        );
        println!(
            "plane, tol {tol:e}: rebound error {err_new:.2e} ({} steps, {} rejected), \
             unrestricted {err_old:.2e} ({} steps, {} rejected)",
            new.steps, new.rejected, old.steps, old.rejected
        );
        assert!(err_new < 0.5 * err_old, "tol {tol}: {err_new} vs {err_old}");
        assert!(new.rejected < old.rejected, "tol {tol}: rejections");
        errors.push(err_new);
    }
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "{errors:?}");
    assert!(errors[2] < 1e-3, "{errors:?}");
}

/// Adaptive steps (including rejections by the gap restriction and the error estimate) of a
/// ball with penalty contact and regularized friction bouncing on a plane allocate nothing.
#[test]
fn adaptive_contact_steps_allocate_nothing() {
    let law = ContactLaw::regularized(K, D).with_regularized_friction(
        0.3,
        1e-3,
        TangentDirections::Spatial,
    );
    let plane = |frame| PlaneContour { frame };
    let (model, mut s) = ball_towards(law, 0.1, plane, 0.15, 1.0);
    model.set_body_velocity(
        &mut s,
        BodyId(0),
        Vector3::new(0.5, 0.0, -1.0),
        Vector3::zeros(),
    );
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    let mut ws = Workspace::new(&model);
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let ctl = AdaptiveSettings::default();
    // first steps outside the count (lazily sized buffers)
    ga.integrate_adaptive(&model, &mut s, &mut ws, &ctl, 0.01, |_, _| {})
        .unwrap();
    let mut contact_steps = 0;
    let n = counting_alloc::allocations_in(|| {
        ga.integrate_adaptive(&model, &mut s, &mut ws, &ctl, 0.2, |s, _| {
            contact_steps += usize::from(s.contacts[0].active);
        })
        .unwrap();
    });
    assert!(contact_steps > 10, "steps in contact: {contact_steps}");
    assert_eq!(n, 0, "{n} allocations");
}
