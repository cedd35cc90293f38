//! Adaptive generalized-alpha over regularized (penalty) contacts: the gap-based step
//! restriction (`AdaptiveSettings::max_penetration`) against the analytic restitution of the
//! penalty law and against the same runs without it (`max_penetration = inf`, the old control,
//! whose error estimate looks only at accelerations):
//! - a ball thrown at a fixed ball passed through it within one free-flight step (tunnelling);
//!   restricted, it rebounds with the restitution of the damped linear oscillator;
//! - a ball hitting a plane rebounds with that restitution, the error falling with the
//!   tolerance to below the fixed-step test's 1e-3, and smaller than without the restriction;
//! - a ball dropped under gravity reaches the analytic apex of the spring-damper with gravity
//!   (an approach step carried past its target by the acceleration is retaken);
//! - adaptive steps with penalty contact and friction allocate nothing.

use crate::counting_alloc;

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

/// A ball (1 kg, radius `r`, gravity `g` along -z) against the fixed contour
/// `obstacle(frame)` (on a ground frame at the origin), its centre at height `z0`, moving with
/// `-v0` along z.
fn ball_towards<C: Contour + 'static>(
    law: ContactLaw,
    r: f64,
    obstacle: impl FnOnce(FrameId) -> C,
    (z0, v0, g): (f64, f64, f64),
) -> (Model, State) {
    let m = 1.0;
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, 0.0, -g));
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
    let (model, s) = ball_towards(law, r, obstacle, (1.0, v0, 0.0));
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
        let (model, s) = ball_towards(ContactLaw::regularized(K, D), r, plane, (0.6, v0, 0.0));
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

/// Apex height above the plane of the lowest point of a ball (mass `m`) dropped from rest at
/// gap `h0` under gravity `g` on the spring-damper `k`, `d` that cannot pull: with the
/// penetration `x = delta + y`, `delta = m g / k`, `y'' + 2 zeta w y' + w^2 y = 0` from
/// `y(0) = -delta`, `y'(0) = sqrt(2 g h0)`; the contact ends at the first root of
/// `k x + d x' = 0` (found by bisection on a grid of 1e-4 periods), and the ball flies from
/// `-x(t*)` with `-x'(t*)` to `-x(t*) + x'(t*)^2 / (2 g)`.
fn analytic_apex(m: f64, k: f64, d: f64, g: f64, h0: f64) -> f64 {
    let w = (k / m).sqrt();
    let zeta = d / (2.0 * (k * m).sqrt());
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let delta = m * g / k;
    let (a, b) = (-delta, ((2.0 * g * h0).sqrt() - zeta * w * delta) / wd);
    let x = |t: f64| {
        let e = (-zeta * w * t).exp();
        let (c, s) = ((wd * t).cos(), (wd * t).sin());
        let y = e * (a * c + b * s);
        let yd = e * ((b * wd - zeta * w * a) * c - (a * wd + zeta * w * b) * s);
        (delta + y, yd)
    };
    let force = |t: f64| {
        let (x, xd) = x(t);
        k * x + d * xd
    };
    let dt = 1e-4 * 2.0 * std::f64::consts::PI / w;
    let mut t = dt;
    while force(t) > 0.0 {
        t += dt;
    }
    let (mut lo, mut hi) = (t - dt, t);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if force(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (xs, vs) = x(0.5 * (lo + hi));
    -xs + vs * vs / (2.0 * g)
}

/// A ball (r = 0.1 m) dropped from rest 0.5 m above the plane under gravity (the example
/// `penalty_ball.toml` without friction): each step of the free fall is longer than the last,
/// and an approach step predicted from the gap rate alone ends past its target (the
/// acceleration): it is rejected and retaken, so that the contact still closes in a short step.
/// The apex after the bounce against [`analytic_apex`] (gravity during the contact included),
/// relative, for `atol = rtol` = 1e-6, 1e-7, 1e-8: below 1.5e-2, 2e-3, 5e-4 (measured 1.2e-2,
/// 1.5e-3, 3.9e-4; the example's fixed 20 us steps: 4.0e-3), falling, and at most half the
/// error without the restriction (measured 3.3e-2, 1.3e-2, 4.5e-3).
#[test]
fn ball_dropped_under_gravity_reaches_the_analytic_apex() {
    let (r, g, h0) = (0.1, 9.81, 0.5);
    let exact = analytic_apex(1.0, K, D, g, h0);
    let mut errors = Vec::new();
    for tol in [1e-6, 1e-7, 1e-8] {
        let plane = |frame| PlaneContour { frame };
        let law = ContactLaw::regularized(K, D);
        let (spec_g, s) = ball_towards(law, r, plane, (r + h0, 0.0, g));
        let ctl = AdaptiveSettings {
            atol: tol,
            rtol: tol,
            ..Default::default()
        };
        for (label, c) in [("restricted", ctl), ("unrestricted", unrestricted(ctl))] {
            let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
            let mut s = s.clone();
            let mut ws = Workspace::new(&spec_g);
            ga.initialize(&spec_g, &mut s, &mut ws).unwrap();
            let (mut bounced, mut apex) = (false, f64::NAN);
            ga.integrate_adaptive_controlled(&spec_g, &mut s, &mut ws, &c, 1.0, |s, _| {
                bounced |= s.u[2] > 0.0 && s.contacts[0].gap > 0.0;
                if bounced && s.u[2] <= 0.0 {
                    apex = s.q[2] - r + s.u[2] * s.u[2] / (2.0 * g);
                    return ControlFlow::Break(());
                }
                ControlFlow::Continue(())
            })
            .unwrap();
            let err = (apex - exact).abs() / exact;
            println!(
                "gravity, tol {tol:e}, {label}: apex {apex:.6} (exact {exact:.6}), error {err:.2e}"
            );
            errors.push(err);
        }
    }
    for (k, bound) in [1.5e-2, 2e-3, 5e-4].into_iter().enumerate() {
        let (new, old) = (errors[2 * k], errors[2 * k + 1]);
        assert!(new < bound && new < 0.5 * old, "{errors:?}");
    }
    assert!(errors[0] > errors[2] && errors[2] > errors[4], "{errors:?}");
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
    let (model, mut s) = ball_towards(law, 0.1, plane, (0.15, 1.0, 0.0));
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
