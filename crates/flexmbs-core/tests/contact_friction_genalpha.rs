//! Regularized Coulomb friction in generalized-alpha against the analytic answers of the
//! regularized law (seed 000 §3.4; issue 10's rigid references):
//! - a block sliding to rest with `mu = 0.3`: the stopping distance `v0^2 / (2 mu g)` of
//!   Coulomb's law plus the creep of the regularization, exactly `v_reg^2 / (2 mu g)` (the linear
//!   branch below `v_reg` decays exponentially with `tau = v_reg / (mu g)` and slides
//!   `v_reg tau` instead of `v_reg^2 / (2 mu g)`);
//! - the same with a steep slope (`v_reg = 1e-4` m/s, 30 times below the velocity lost in one
//!   step): full Newton cycled between sliding and sticking iterates there and the fixed step
//!   failed; the trust region on the slip velocity (`integrator::genalpha_contact`) converges, and
//!   the distance stays within the bound derived from `v_reg` and the step;
//! - a sphere on an incline: below the slip threshold `tan(alpha) < 7/2 mu` it rolls with the
//!   acceleration `5/7 g sin(alpha)` and a constant creep slip `2/7 tan(alpha) v_reg / mu`
//!   (the exact solution of the regularized law below), above it slips with
//!   `g (sin(alpha) - mu cos(alpha))`.

use flexmbs_core::contact::{Contact, ContactLaw, PlaneContour, SphereContour, TangentDirections};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, StepStats};
use flexmbs_core::point_mass::PointMass;
use flexmbs_core::{BodyId, Model, ModelSpec, RigidBody, RotationParam, State, Workspace};
use nalgebra::{Matrix3, Vector3};

const G: f64 = 9.81;
/// Normal stiffness (N/m) of every contact here, with a damping ratio of 1 on the 1 kg bodies.
const K: f64 = 1e6;

/// Damping of the normal law for a damping ratio 1 on mass `m`.
fn critical_damping(m: f64) -> f64 {
    2.0 * (K * m).sqrt()
}

/// A block (a point mass `m` on a point contour) resting on the ground plane at its static
/// penetration `m g / k`, sliding along x with `v0`, regularized friction (`mu`, `v_reg`,
/// planar: the plane's x axis).
fn block_on_plane(m: f64, mu: f64, v_reg: f64, v0: f64) -> (Model, State) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, 0.0, -G));
    let b = spec.add_body("block", PointMass::new(m));
    let point = spec.add_frame("point", b, Vector3::zeros(), Matrix3::identity());
    let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    let law = ContactLaw::regularized(K, critical_damping(m)).with_regularized_friction(
        mu,
        v_reg,
        TangentDirections::Planar,
    );
    spec.add_contact(Contact::new(
        "c",
        flexmbs_core::contact::PointContour { frame: point },
        PlaneContour { frame: ground },
        law,
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let z = -m * G / K;
    model.set_body_pose(
        &mut s,
        BodyId(0),
        Vector3::new(0.0, 0.0, z),
        Matrix3::identity(),
    );
    model.set_body_velocity(
        &mut s,
        BodyId(0),
        Vector3::new(v0, 0.0, 0.0),
        Vector3::zeros(),
    );
    (model, s)
}

/// Fixed-step generalized-alpha (`rho_inf`, step `h`) to `t_end`; `f` after every step.
/// Panics with the solver error if a step fails.
fn run_fixed(
    model: &Model,
    s: &mut State,
    rho_inf: f64,
    h: f64,
    t_end: f64,
    mut f: impl FnMut(&State, &StepStats),
) {
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf,
        ..Default::default()
    })
    .unwrap();
    let mut ws = Workspace::new(model);
    ga.initialize(model, s, &mut ws).unwrap();
    let n = (t_end / h).round() as usize;
    for _ in 0..n {
        match ga.step(model, s, &mut ws, h) {
            Ok(st) => f(s, &st),
            Err(e) => panic!("step at t = {} failed: {e}", s.t),
        }
    }
}

/// Block, `v0 = 1` m/s, `mu = 0.3`, `v_reg = 0.05` m/s resolved by the step (`h = 1e-4` s,
/// `tau = v_reg / (mu g) = 17` ms): at rest after 0.34 s + 25 tau it has slid
/// `(v0^2 + v_reg^2) / (2 mu g)`, the exact distance of the regularized law, to 1e-5 relative
/// (the second-order step error over the exponential tail; `e^-25 v_reg tau` is 1e-14 m),
/// which is `v_reg^2 / (2 mu g) = 4.2e-4` m (0.25 %) beyond Coulomb's `v0^2 / (2 mu g)`.
#[test]
fn block_slides_to_rest_at_the_regularized_stopping_distance() {
    let (m, mu, v_reg, v0) = (1.0, 0.3, 0.05, 1.0);
    let (model, mut s) = block_on_plane(m, mu, v_reg, v0);
    let tau = v_reg / (mu * G);
    let t_end = v0 / (mu * G) + 25.0 * tau;
    run_fixed(&model, &mut s, 0.9, 1e-4, t_end, |_, _| {});
    let x = s.q[0];
    let coulomb = v0 * v0 / (2.0 * mu * G);
    let regularized = (v0 * v0 + v_reg * v_reg) / (2.0 * mu * G);
    println!(
        "block: x = {x:.9} m, regularized {regularized:.9} (relative error {:.1e}), Coulomb {coulomb:.9}, v = {:.3e}",
        (x - regularized).abs() / regularized,
        s.u[0]
    );
    assert!(
        (x - regularized).abs() < 1e-5 * regularized,
        "x = {x}, regularized law {regularized}"
    );
    assert!(
        (x - coulomb - v_reg * v_reg / (2.0 * mu * G)).abs() < 1e-5 * coulomb,
        "the creep beyond Coulomb's distance"
    );
    assert!(s.u[0].abs() < 1e-9, "at rest: v = {}", s.u[0]);
}

/// Block, `mu = 0.3`, steep friction `v_reg = 1e-4` m/s at a fixed step of 1 ms: the velocity
/// lost in one step, `mu g h = 2.9e-3` m/s, is 29 `v_reg` (the linear branch, `tau = 34` us, is
/// not resolved). Full Newton cycled between sliding and sticking iterates in the step where the
/// block stops and the step failed (residual `2 mu m g` after 25 iterations); now every step
/// converges in at most 4 iterations, and for five start velocities (stops at different points
/// of a step) the block comes to rest at Coulomb's `v0^2 / (2 mu g)` within
/// `v_reg^2 / (2 mu g) + mu g h^2 / 2`: the creep of the law plus the unresolved stopping step
/// (generalized-alpha is exact for the constant deceleration before it; the exact displacement
/// within that step is between 0 and `mu g h^2 / 2`, which the scheme cannot place).
#[test]
fn block_with_steep_friction_stops_in_fixed_steps() {
    let (m, mu, v_reg, h) = (1.0, 0.3, 1e-4, 1e-3);
    for j in 0..5 {
        let v0 = 1.0 + 0.000_37 * j as f64;
        let (model, mut s) = block_on_plane(m, mu, v_reg, v0);
        let mut iterations = 0;
        run_fixed(&model, &mut s, 0.9, h, 0.6, |_, st| {
            iterations = iterations.max(st.iterations);
        });
        let x = s.q[0];
        let coulomb = v0 * v0 / (2.0 * mu * G);
        let bound = v_reg * v_reg / (2.0 * mu * G) + 0.5 * mu * G * h * h;
        println!(
            "steep block v0 = {v0}: x - Coulomb = {:.3e} m (bound {bound:.3e}), v = {:.3e}, \
             max iterations {iterations}",
            x - coulomb,
            s.u[0]
        );
        assert!((x - coulomb).abs() < bound, "x = {x}, Coulomb {coulomb}");
        assert!(s.u[0].abs() < 1e-3 * v_reg, "at rest: v = {}", s.u[0]);
        assert!(iterations <= 4, "Newton iterations {iterations}");
    }
}

/// A solid sphere (`m = 1` kg, `r = 0.1` m, `I = 2/5 m r^2`) at rest on a plane at its static
/// penetration, gravity tilted by `alpha` (`tan(alpha) = ratio 7/2 mu`: the incline), regularized
/// spatial friction `mu = 0.3`, `v_reg = 0.01` m/s.
fn sphere_on_incline(ratio: f64, mu: f64, v_reg: f64) -> (Model, State, f64) {
    let (m, r) = (1.0, 0.1);
    let alpha = (ratio * 3.5 * mu).atan();
    let mut spec = ModelSpec::new();
    spec.set_gravity(G * Vector3::new(alpha.sin(), 0.0, -alpha.cos()));
    let ball = RigidBody::new(m, Matrix3::from_diagonal_element(0.4 * m * r * r))
        .with_rotation(RotationParam::Quaternion);
    let b = spec.add_body("ball", ball);
    let centre = spec.add_frame("centre", b, Vector3::zeros(), Matrix3::identity());
    let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    let law = ContactLaw::regularized(K, critical_damping(m)).with_regularized_friction(
        mu,
        v_reg,
        TangentDirections::Spatial,
    );
    let sphere = SphereContour {
        frame: centre,
        radius: r,
    };
    spec.add_contact(Contact::new(
        "c",
        sphere,
        PlaneContour { frame: ground },
        law,
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let z = r - m * G * alpha.cos() / K;
    model.set_body_pose(
        &mut s,
        BodyId(0),
        Vector3::new(0.0, 0.0, z),
        Matrix3::identity(),
    );
    (model, s, alpha)
}

/// Below the slip threshold (`tan(alpha) = 0.8 * 7/2 mu`) the regularized law lets the contact
/// creep: the slip `v_s = v - omega r` obeys `v_s' = g sin(alpha) - 7/2 mu g cos(alpha) v_s /
/// v_reg`, so `v_s = v_ss (1 - e^(-t/tau))` with the creep `v_ss = 2/7 tan(alpha) v_reg / mu`
/// (`0.8 v_reg`) and `tau = 2 v_reg / (7 mu g cos(alpha))` (3.8 ms), and the centre moves with
/// `v(t) = 5/7 g sin(alpha) t + 2/7 g sin(alpha) tau (1 - e^(-t/tau))`: the rolling acceleration
/// `5/7 g sin(alpha)` of Coulomb's law, offset by a creep velocity of order `v_reg`
/// (`4/49 tan(alpha) v_reg / mu`). At 0.5 s with `h = 1e-4` s: the velocity and the slip to
/// 1e-6 of `v` (second-order step error over the creep transient), the acceleration over the
/// last 0.1 s to 1e-6 of `5/7 g sin(alpha)`, and the velocity differs from rolling by the creep
/// offset, not by zero.
#[test]
fn sphere_rolls_down_an_incline_below_the_slip_threshold() {
    let (mu, v_reg, h) = (0.3, 0.01, 1e-4);
    let (model, mut s, alpha) = sphere_on_incline(0.8, mu, v_reg);
    let (sa, ca) = (alpha.sin(), alpha.cos());
    let tau = 2.0 * v_reg / (7.0 * mu * G * ca);
    let v_ss = 2.0 / 7.0 * alpha.tan() * v_reg / mu;
    let v_exact =
        |t: f64| 5.0 / 7.0 * G * sa * t + 2.0 / 7.0 * G * sa * tau * (1.0 - (-t / tau).exp());
    let mut v_at_04 = f64::NAN;
    run_fixed(&model, &mut s, 0.9, h, 0.5, |s, _| {
        if (s.t - 0.4).abs() < 0.5 * h {
            v_at_04 = s.u[0];
        }
    });
    let (v, slip) = (s.u[0], s.u[0] - s.u[4] * 0.1);
    let accel = (v - v_at_04) / 0.1;
    println!(
        "incline below threshold: v = {v:.9} (exact {:.9}), slip {slip:.6e} (creep {v_ss:.6e}), \
         a = {accel:.9} (5/7 g sin = {:.9})",
        v_exact(0.5),
        5.0 / 7.0 * G * sa
    );
    assert!((v - v_exact(0.5)).abs() < 1e-6 * v, "v {v}");
    assert!((slip - v_ss).abs() < 1e-6 * v, "slip {slip}, creep {v_ss}");
    assert!(
        (accel - 5.0 / 7.0 * G * sa).abs() < 1e-6 * G * sa,
        "a = {accel}"
    );
    let offset = v - 5.0 / 7.0 * G * sa * 0.5;
    let creep_offset = 4.0 / 49.0 * alpha.tan() * v_reg / mu;
    assert!(
        (offset - creep_offset).abs() < 1e-3 * creep_offset,
        "offset {offset}"
    );
}

/// Above the slip threshold (`tan(alpha) = 1.25 * 7/2 mu`) the sphere slides: once the slip
/// exceeds `v_reg` the friction saturates at `mu m g cos(alpha)`, the centre accelerates with
/// `g (sin(alpha) - mu cos(alpha))` and the slip grows at `g (sin(alpha) - 7/2 mu cos(alpha))`;
/// over 0.3 s to 0.5 s both rates to 1e-9 relative (constant accelerations: the scheme is exact).
#[test]
fn sphere_slips_on_an_incline_above_the_slip_threshold() {
    let (mu, v_reg, h) = (0.3, 0.01, 1e-4);
    let (model, mut s, alpha) = sphere_on_incline(1.25, mu, v_reg);
    let (sa, ca) = (alpha.sin(), alpha.cos());
    let mut at_03 = (f64::NAN, f64::NAN);
    run_fixed(&model, &mut s, 0.9, h, 0.5, |s, _| {
        if (s.t - 0.3).abs() < 0.5 * h {
            at_03 = (s.u[0], s.u[0] - s.u[4] * 0.1);
        }
    });
    let (v, slip) = (s.u[0], s.u[0] - s.u[4] * 0.1);
    let (a, slip_rate) = ((v - at_03.0) / 0.2, (slip - at_03.1) / 0.2);
    let (a_exact, slip_exact) = (G * (sa - mu * ca), G * (sa - 3.5 * mu * ca));
    println!(
        "incline above threshold: a = {a:.9} ({a_exact:.9}), slip rate {slip_rate:.9} \
         ({slip_exact:.9}), slip {slip:.4} m/s"
    );
    assert!(at_03.1 > v_reg, "sliding at 0.3 s: slip {}", at_03.1);
    assert!((a - a_exact).abs() < 1e-9 * a_exact, "a = {a}");
    assert!(
        (slip_rate - slip_exact).abs() < 1e-9 * a_exact,
        "slip rate {slip_rate}"
    );
}
