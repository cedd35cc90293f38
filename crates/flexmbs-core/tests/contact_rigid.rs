//! Rigid contact with the Moreau time-stepper against analytic answers: a ball bouncing on a
//! plane (Newton impact), a block sliding to rest and sticking (Coulomb friction), a sphere rolling
//! or slipping down an incline, and a penalty (regularized) contact's artificial energy.
use flexmbs_core::contact::{
    Contact, ContactLaw, PlaneContour, PointContour, SphereContour, TangentDirections,
};
use flexmbs_core::integrator::{drive, MoreauSettings, MoreauStepper, StepStats, Stepper};
use flexmbs_core::load::LoadCoordinates;
use flexmbs_core::{
    BodyId, Load, Model, ModelSpec, RigidBody, RotationParam, State, TimeFunction, Workspace,
};
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::ops::ControlFlow;

const G: f64 = 9.81;

/// Runs a Moreau stepper with step `h` to `t_end`, calling `f` after every step.
fn run(
    model: &Model,
    s: &mut State,
    settings: MoreauSettings,
    h: f64,
    t_end: f64,
    mut f: impl FnMut(&State, &StepStats),
) {
    let mut ws = Workspace::new(model);
    let mut st = MoreauStepper::new(settings);
    st.initialize(model, s, &mut ws).unwrap();
    let control = st.control(h);
    drive(&mut st, model, s, &mut ws, control, t_end, |s, stats| {
        f(s, stats);
        ControlFlow::Continue(())
    })
    .unwrap();
}

/// A ball (mass 1, radius `r`, quaternion) above the ground plane z = 0, gravity -z.
fn ball_on_plane(law: ContactLaw, r: f64, height: f64) -> (Model, State, BodyId) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, 0.0, -G));
    let i = 0.4 * r * r;
    let ball = RigidBody::new(1.0, Matrix3::from_diagonal_element(i))
        .with_rotation(RotationParam::Quaternion);
    let b = spec.add_body("ball", ball);
    let centre = spec.add_frame("centre", b, Vector3::zeros(), Matrix3::identity());
    let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    spec.add_contact(Contact::new(
        "bounce",
        SphereContour {
            frame: centre,
            radius: r,
        },
        PlaneContour { frame: ground },
        law,
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        b,
        Vector3::new(0.0, 0.0, height + r),
        Matrix3::identity(),
    );
    (model, s, b)
}

/// Ball dropped from gap `h0`: rebound heights `C_R^2 h0` and impact times
/// `t_1 = sqrt(2 h0 / g)`, `t_2 = t_1 + 2 C_R v_1 / g`; energy never grows by more than 0.1 %
/// of `m g h0`, and `C_R = 1` conserves it to the step's accuracy.
#[test]
fn bouncing_ball_newton_impact() {
    let (h0, r, h) = (1.0, 0.1, 1e-4);
    let v1 = (2.0 * G * h0).sqrt();
    let t1 = (2.0 * h0 / G).sqrt();
    for cr in [0.0, 0.5, 1.0] {
        let (model, mut s, b) = ball_on_plane(ContactLaw::unilateral(cr), r, h0);
        let mut impacts = Vec::new(); // (time from free flight before the step)
        let mut prev = (0.0, h0, 0.0); // (t, gap, vz) at the start of the step
        let mut apex_after_first = f64::NEG_INFINITY;
        let (mut e0, mut e_end, mut gain) = (f64::NAN, 0.0, f64::NEG_INFINITY);
        run(
            &model,
            &mut s,
            MoreauSettings::default(),
            h,
            (1.1 + 2.0 * cr) * t1,
            |s, st| {
                let q = model.body_q(b, &s.q);
                let (gap, vz) = (q[2] - r, model.body_u(b, &s.u)[2]);
                let e = st.energy.total();
                if e0.is_nan() {
                    e0 = e; // free flight is exact: the first step keeps the energy
                }
                gain = gain.max(e - e0);
                e_end = e;
                if prev.2 < 0.0 && vz > prev.2 + 0.5 * G * h {
                    // free-flight root of gap + v tau - g tau^2 / 2 from the step's start
                    let (g0, v0) = (prev.1, prev.2);
                    let tau = (v0 + (v0 * v0 + 2.0 * G * g0).sqrt()) / G;
                    impacts.push(prev.0 + tau);
                }
                if !impacts.is_empty() && impacts.len() < 2 {
                    apex_after_first = apex_after_first.max(gap);
                }
                prev = (s.t, gap, vz);
            },
        );
        let scale = G * h0;
        assert!(
            (impacts[0] - t1).abs() < 1e-9,
            "C_R {cr}: t1 {} vs {t1}",
            impacts[0]
        );
        // the impact is resolved at the step's midpoint: position error <= the step's travel
        let tol_h = (1.0 + cr) * v1 * h;
        let rebound = cr * cr * h0;
        assert!(
            (apex_after_first - rebound).abs() <= tol_h,
            "C_R {cr}: rebound {apex_after_first} vs {rebound} (tol {tol_h})"
        );
        if cr > 0.0 {
            let t2 = t1 + 2.0 * cr * v1 / G;
            assert!(
                (impacts[1] - t2).abs() <= 2.0 * h,
                "C_R {cr}: t2 {} vs {t2}",
                impacts[1]
            );
        } else {
            assert_eq!(impacts.len(), 1, "C_R 0: the ball stays down");
        }
        assert!(gain <= 1e-3 * scale, "C_R {cr}: energy gain {gain}");
        if cr == 1.0 {
            let drift = (e_end - e0).abs() / scale;
            assert!(drift < 1e-3, "C_R 1: energy drift {drift}");
            println!("C_R = 1: relative energy change {drift:.2e} after two impacts");
        }
        println!(
            "C_R = {cr}: t1 = {:.6}, rebound {apex_after_first:.6} (exact {rebound})",
            impacts[0]
        );
    }
}

/// A 0.2 x 0.2 x 0.1 box (mass 1) resting on the ground on four corner points with spatial
/// Coulomb friction `mu`, pushed by a constant horizontal force `push` (N, along x).
fn block(mu: f64, push: f64) -> (Model, State, BodyId) {
    block_with(mu, push, TangentDirections::Spatial)
}

/// [`block`] with spatial or planar (along the ground's x axis) friction.
fn block_with(mu: f64, push: f64, directions: TangentDirections) -> (Model, State, BodyId) {
    let law = ContactLaw::unilateral(0.0).with_coulomb(mu, directions);
    block_law(law, push)
}

/// [`block`] with any contact law at the corners.
fn block_law(law: ContactLaw, push: f64) -> (Model, State, BodyId) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, 0.0, -G));
    let (a, c) = (0.1, 0.05);
    let i = Matrix3::from_diagonal(&Vector3::new(
        (4.0 * a * a + 4.0 * c * c) / 12.0,
        (4.0 * a * a + 4.0 * c * c) / 12.0,
        8.0 * a * a / 12.0,
    ));
    let b = spec.add_body("block", RigidBody::new(1.0, i));
    let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
    for (k, (x, y)) in [(a, a), (a, -a), (-a, a), (-a, -a)].into_iter().enumerate() {
        let f = spec.add_frame(
            &format!("corner{k}"),
            b,
            Vector3::new(x, y, -c),
            Matrix3::identity(),
        );
        spec.add_contact(Contact::new(
            &format!("c{k}"),
            PointContour { frame: f },
            PlaneContour { frame: ground },
            law,
        ));
    }
    let centre = spec.add_frame("centre", b, Vector3::zeros(), Matrix3::identity());
    if push != 0.0 {
        spec.add_load(Load::Force {
            frame: centre,
            vector: Vector3::new(push, 0.0, 0.0),
            time: TimeFunction::Constant(1.0),
            coordinates: LoadCoordinates::Global,
        });
    }
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(&mut s, b, Vector3::new(0.0, 0.0, c), Matrix3::identity());
    (model, s, b)
}

/// Sliding from `v0` to rest: stopping distance `v0^2 / (2 mu g)` at `t = v0 / (mu g)`, then at
/// rest (no tipping: the four normal impulses carry the pitching moment of friction).
#[test]
fn block_slides_to_rest() {
    block_slides_to_rest_with(TangentDirections::Spatial);
    block_slides_to_rest_with(TangentDirections::Planar);
}

fn block_slides_to_rest_with(directions: TangentDirections) {
    let (mu, v0, h) = (0.3, 2.0, 1e-4);
    let (model, mut s, b) = block_with(mu, 0.0, directions);
    model.set_body_velocity(&mut s, b, Vector3::new(v0, 0.0, 0.0), Vector3::zeros());
    let t_stop = v0 / (mu * G);
    let mut stopped_at = f64::NAN;
    let mut max_tilt: f64 = 0.0;
    run(
        &model,
        &mut s,
        MoreauSettings::default(),
        h,
        t_stop + 0.3,
        |s, _| {
            let (q, u) = (model.body_q(b, &s.q), model.body_u(b, &s.u));
            max_tilt = max_tilt.max(q[3].abs()).max(q[4].abs());
            if stopped_at.is_nan() && u[0].abs() < 1e-12 {
                stopped_at = s.t;
            }
        },
    );
    let q = model.body_q(b, &s.q);
    let d = v0 * v0 / (2.0 * mu * G);
    // constant deceleration is integrated exactly; the last step stops within mu g h^2
    assert!((q[0] - d).abs() < 1e-6 * d, "distance {} vs {d}", q[0]);
    assert!(
        (stopped_at - t_stop).abs() <= h,
        "stop at {stopped_at} vs {t_stop}"
    );
    assert!(max_tilt < 1e-9, "tilt {max_tilt}");
    assert!((q[2] - 0.05).abs() < 1e-9, "height {}", q[2]);
    println!(
        "block ({directions:?}): distance {} (exact {d}), stopped at {stopped_at} (exact {t_stop})",
        q[0]
    );
}

/// A horizontal push below `mu m g` leaves the block stuck; above it the block accelerates at
/// `F / m - mu g`.
#[test]
fn block_sticks_below_friction_limit() {
    let (mu, h, t) = (0.3, 1e-3, 1.0);
    for (ratio, moving) in [(0.5, false), (0.99, false), (1.5, true)] {
        let (model, mut s, b) = block(mu, ratio * mu * G);
        run(&model, &mut s, MoreauSettings::default(), h, t, |_, _| {});
        let x = model.body_q(b, &s.q)[0];
        let expected = if moving {
            0.5 * (ratio - 1.0) * mu * G * t * t
        } else {
            0.0
        };
        assert!(
            (x - expected).abs() < 1e-9 + 1e-9 * expected,
            "F = {ratio} mu m g: x {x} vs {expected}"
        );
    }
}

/// A solid sphere released on an incline of angle `alpha`: it rolls with `5/7 g sin(alpha)` when
/// `mu >= 2/7 tan(alpha)` (contact point at rest), and slips with `g (sin - mu cos)` otherwise.
#[test]
fn sphere_on_incline_rolls_or_slips() {
    let (alpha, r, h, t_end) = (0.35_f64, 0.1, 1e-3, 0.5);
    let mu_crit = 2.0 / 7.0 * alpha.tan();
    for (mu, rolling) in [(1.2 * mu_crit, true), (0.5 * mu_crit, false)] {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, 0.0, -G));
        let ball = RigidBody::new(1.0, Matrix3::from_diagonal_element(0.4 * r * r))
            .with_rotation(RotationParam::Quaternion);
        let b = spec.add_body("ball", ball);
        let centre = spec.add_frame("centre", b, Vector3::zeros(), Matrix3::identity());
        let rot = Rotation3::from_axis_angle(&Vector3::y_axis(), alpha).into_inner();
        let slope = spec.add_ground_frame("slope", Vector3::zeros(), rot);
        let law = ContactLaw::unilateral(0.0).with_coulomb(mu, TangentDirections::Spatial);
        let sphere = SphereContour {
            frame: centre,
            radius: r,
        };
        spec.add_contact(Contact::new(
            "c",
            sphere,
            PlaneContour { frame: slope },
            law,
        ));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        let (n, down) = (rot.column(2).into_owned(), rot.column(0).into_owned());
        // touching (1e-12 into the plane, so the first step's midpoint is closed)
        model.set_body_pose(&mut s, b, (r - 1e-12) * n, Matrix3::identity());
        let mut max_slip: f64 = 0.0;
        run(
            &model,
            &mut s,
            MoreauSettings::default(),
            h,
            t_end,
            |s, _| {
                let (u, c) = (model.body_u(b, &s.u), s.contacts[0]);
                let _ = u;
                max_slip = max_slip.max(c.gap_velocity.abs());
            },
        );
        let pos = Vector3::from_column_slice(&model.body_q(b, &s.q)[..3]);
        let vel = Vector3::from_column_slice(&model.body_u(b, &s.u)[..3]);
        let a = if rolling {
            5.0 / 7.0 * G * alpha.sin()
        } else {
            G * (alpha.sin() - mu * alpha.cos())
        };
        let (dist, speed) = (down.dot(&(pos - r * n)), down.dot(&vel));
        assert!(
            (speed - a * t_end).abs() < 1e-8 * a,
            "mu {mu}: v {speed} vs {}",
            a * t_end
        );
        assert!(
            (dist - 0.5 * a * t_end * t_end).abs() < 1e-8 * a,
            "mu {mu}: s {dist} vs {}",
            0.5 * a * t_end * t_end
        );
        assert!(max_slip < 1e-9, "normal rate {max_slip}");
        let rel = (speed / t_end - a).abs() / a;
        println!(
            "incline mu = {mu:.4}: a = {:.8} (exact {a:.8}), {rel:.1e}",
            speed / t_end
        );
    }
}

/// Penalty contact (k = 1e5 N/m, no damping): a ball dropped from about 0.1 m rebounds; the
/// energy after the bounce differs from before (the artificial energy of the regularization in
/// the time discretization). Its size depends on where the steps fall relative to the contact's
/// start and end, so the envelope over eight drop heights is taken: it shrinks with the step.
#[test]
fn penalty_contact_artificial_energy_shrinks_with_step() {
    let (r, k) = (0.05, 1e5);
    let mut envelope = Vec::new();
    for h in [4e-4, 2e-4, 1e-4, 5e-5, 2.5e-5] {
        let mut worst: f64 = 0.0;
        for j in 0..8 {
            let h0 = 0.1 * (1.0 + 0.0123 * j as f64);
            let rel = penalty_bounce_energy(r, k, h0, h) / (G * h0);
            worst = worst.max(rel.abs());
        }
        println!("penalty h = {h:.1e}: artificial energy up to {worst:.3e} of m g h0");
        envelope.push(worst);
    }
    for w in envelope.windows(2) {
        assert!(
            w[1] < w[0],
            "artificial energy must shrink with the step: {envelope:?}"
        );
    }
    assert!(envelope[envelope.len() - 1] < 1e-4, "{envelope:?}");
}

/// Energy after minus before one bounce of a ball on a penalty contact (kinetic + gravity +
/// contact spring), and a check of the dynamic penetration `sqrt(2 m g h0 / k)`.
fn penalty_bounce_energy(r: f64, k: f64, h0: f64, h: f64) -> f64 {
    let (model, mut s, b) = ball_on_plane(ContactLaw::regularized(k, 0.0), r, h0);
    let t_end = 2.0 * (2.0 * h0 / G).sqrt(); // after the bounce, before the next
    let mut ws = Workspace::new(&model);
    let energy = |s: &State, ws: &mut Workspace| {
        let (e, _, _) = flexmbs_core::integrator::monitor(&model, s, ws);
        e.total()
            + flexmbs_core::contact::regularized_energy(
                &model,
                &ws.sys.frames,
                &ws.sys.eval,
                &mut ws.contact,
            )
    };
    let e0 = energy(&s, &mut ws);
    let mut max_pen: f64 = 0.0;
    run(
        &model,
        &mut s,
        MoreauSettings::default(),
        h,
        t_end,
        |s, _| {
            max_pen = max_pen.max(r - model.body_q(b, &s.q)[2]);
        },
    );
    assert!(
        model.body_u(b, &s.u)[2] > 0.0,
        "h {h}: rising after the bounce"
    );
    // dynamic penetration (gravity during the contact neglected: m g / k = 1 % of it)
    let pen = (2.0 * G * h0 / k).sqrt();
    assert!(
        (max_pen - pen).abs() < 0.03 * pen,
        "penetration {max_pen} vs {pen}"
    );
    energy(&s, &mut ws) - e0
}

/// Step-size control (step halving, gap-based refinement): the ball's impacts are resolved to
/// the penetration bound, so the rebound heights `C_R^2 h0`, `C_R^4 h0` are met to about
/// `max_penetration` with far fewer steps than the fixed-step run needs for `(1 + C_R) v h`.
#[test]
fn bouncing_ball_with_step_size_control() {
    use flexmbs_core::integrator::{MoreauSscSettings, MoreauSscStepper};
    let (h0, r, cr) = (1.0, 0.1, 0.5);
    let (model, mut s, b) = ball_on_plane(ContactLaw::unilateral(cr), r, h0);
    let settings = MoreauSscSettings::default();
    let mut ws = Workspace::new(&model);
    let mut st = MoreauSscStepper::new(settings);
    st.initialize(&model, &mut s, &mut ws).unwrap();
    let t1 = (2.0 * h0 / G).sqrt();
    let t_end = t1 * (1.0 + 2.0 * cr + 2.0 * cr * cr) + 0.05;
    let (mut apexes, mut rising) = (Vec::new(), false);
    let control = st.control();
    drive(&mut st, &model, &mut s, &mut ws, control, t_end, |s, _| {
        let (gap, vz) = (model.body_q(b, &s.q)[2] - r, model.body_u(b, &s.u)[2]);
        if vz > 0.0 {
            rising = true;
        } else if rising {
            // the apex lies in the last step, in ballistic flight: gap + vz^2 / (2 g)
            apexes.push(gap + vz * vz / (2.0 * G));
            rising = false;
        }
        ControlFlow::Continue(())
    })
    .unwrap();
    let stats = st.statistics();
    println!(
        "SSC: {} steps, {} rejected, apexes {apexes:?}",
        stats.accepted, stats.rejected
    );
    assert!(apexes.len() >= 2, "{apexes:?}");
    for (k, apex) in apexes.iter().take(2).enumerate() {
        let exact = cr.powi(2 * (k as i32 + 1)) * h0;
        // each impact is resolved at a penetration <= max_penetration = 1e-6, which shifts the
        // rebound by at most (1 + C_R) 1e-6 per impact (flight in between is exact)
        assert!(
            (apex - exact).abs() < 2.0 * 1.5e-6,
            "apex {k}: {apex} vs {exact}"
        );
    }
    assert!(stats.accepted < 1000, "{} steps", stats.accepted);
}

/// A uniform disc (circle contour, planar friction) on a 20 degree incline rolls with
/// `a = 2/3 g sin(alpha)` (`I = m r^2 / 2`) when `mu >= tan(alpha) / 3`, and slips with
/// `g (sin - mu cos)` below.
#[test]
fn disc_on_incline_rolls_or_slips() {
    use flexmbs_core::contact::CircleContour;
    let (alpha, r, h, t_end) = (0.35_f64, 0.2, 1e-3, 0.5);
    let mu_crit = alpha.tan() / 3.0;
    for (mu, rolling) in [(1.2 * mu_crit, true), (0.5 * mu_crit, false)] {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, 0.0, -G));
        let i_axis = 0.5 * r * r;
        let disc = RigidBody::new(
            1.0,
            Matrix3::from_diagonal(&Vector3::new(0.5 * i_axis, i_axis, 0.5 * i_axis)),
        )
        .with_rotation(RotationParam::Quaternion);
        let b = spec.add_body("disc", disc);
        // circle in the x-z plane of the body (its axis, the frame's z, along the body's y)
        let axis_y = Rotation3::from_axis_angle(&Vector3::x_axis(), -std::f64::consts::FRAC_PI_2);
        let rim = spec.add_frame("rim", b, Vector3::zeros(), axis_y.into_inner());
        let rot = Rotation3::from_axis_angle(&Vector3::y_axis(), alpha).into_inner();
        let slope = spec.add_ground_frame("slope", Vector3::zeros(), rot);
        let law = ContactLaw::unilateral(0.0).with_coulomb(mu, TangentDirections::Planar);
        let circle = CircleContour {
            frame: rim,
            radius: r,
        };
        spec.add_contact(Contact::new(
            "c",
            circle,
            PlaneContour { frame: slope },
            law,
        ));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        let (n, down) = (rot.column(2).into_owned(), rot.column(0).into_owned());
        model.set_body_pose(&mut s, b, (r - 1e-12) * n, Matrix3::identity());
        run(
            &model,
            &mut s,
            MoreauSettings::default(),
            h,
            t_end,
            |_, _| {},
        );
        let vel = Vector3::from_column_slice(&model.body_u(b, &s.u)[..3]);
        let a = if rolling {
            2.0 / 3.0 * G * alpha.sin()
        } else {
            G * (alpha.sin() - mu * alpha.cos())
        };
        let speed = down.dot(&vel);
        assert!(
            (speed - a * t_end).abs() < 1e-8 * a,
            "mu {mu}: v {speed} vs {}",
            a * t_end
        );
        println!(
            "disc mu = {mu:.4}: a = {:.10} (exact {a:.10})",
            speed / t_end
        );
    }
}

/// Penalty corners (k = 1e6 N/m, near-critical damping) with regularized friction (slip
/// velocity 1e-3 m/s) or set-valued Coulomb friction bounded by the penalty force: the block
/// slides to rest within 1 % of `v0^2 / (2 mu g)` (the regularization's error: the static
/// penetration m g / k and the creep below the slip velocity).
#[test]
fn block_on_penalty_contacts_slides_to_rest() {
    let (mu, v0, h) = (0.3, 2.0, 1e-4);
    let d = v0 * v0 / (2.0 * mu * G);
    let normal = ContactLaw::regularized(1e6, 500.0);
    for law in [
        normal.with_regularized_friction(mu, 1e-3, TangentDirections::Spatial),
        normal.with_coulomb(mu, TangentDirections::Spatial),
    ] {
        let (model, mut s, b) = block_law(law, 0.0);
        // resting at the static penetration m g / (4 k) per corner
        model.set_body_pose(
            &mut s,
            b,
            Vector3::new(0.0, 0.0, 0.05 - G / 4e6),
            Matrix3::identity(),
        );
        model.set_body_velocity(&mut s, b, Vector3::new(v0, 0.0, 0.0), Vector3::zeros());
        let settings = MoreauSettings::default();
        let mut sweeps = 0;
        run(&model, &mut s, settings, h, v0 / (mu * G) + 0.3, |_, st| {
            sweeps = sweeps.max(st.iterations);
        });
        println!("largest prox sweeps per step: {sweeps}");
        let x = model.body_q(b, &s.q)[0];
        assert!(
            (x - d).abs() < 1e-2 * d,
            "{:?}: distance {x} vs {d}",
            law.friction
        );
        let rel = (x - d).abs() / d;
        println!(
            "penalty block {:?}: distance {x:.9} (exact {d:.9}), {rel:.1e}",
            law.friction
        );
    }
}

/// Bilateral contact: a ball hanging under a tilted frictionless ceiling (normal pointing down,
/// gravity pulling away from it) is held on it with a pulling (negative) normal impulse and slides
/// with `a = g sin(alpha)`; the gap rate is zero, so the gap stays at its initial value.
#[test]
fn bilateral_contact_holds_a_ball_under_a_ceiling() {
    use flexmbs_core::contact::NormalLaw;
    let (alpha, r, h, t_end) = (0.3_f64, 0.1, 1e-3, 0.5);
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, 0.0, -G));
    let ball = RigidBody::new(1.0, Matrix3::from_diagonal_element(0.4 * r * r))
        .with_rotation(RotationParam::Quaternion);
    let b = spec.add_body("ball", ball);
    let centre = spec.add_frame("centre", b, Vector3::zeros(), Matrix3::identity());
    // ceiling: normal -z turned by alpha about y
    let rot = (Rotation3::from_axis_angle(&Vector3::y_axis(), alpha)
        * Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI))
    .into_inner();
    let ceiling = spec.add_ground_frame("ceiling", Vector3::zeros(), rot);
    let law = ContactLaw {
        normal: NormalLaw::Bilateral,
        friction: flexmbs_core::contact::Friction::None,
    };
    let sphere = SphereContour {
        frame: centre,
        radius: r,
    };
    spec.add_contact(Contact::new(
        "hold",
        sphere,
        PlaneContour { frame: ceiling },
        law,
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let n = rot.column(2).into_owned();
    model.set_body_pose(&mut s, b, r * n, Matrix3::identity());
    let (mut max_gap, mut pulling) = (0.0_f64, true);
    run(
        &model,
        &mut s,
        MoreauSettings::default(),
        h,
        t_end,
        |s, _| {
            let c = s.contacts[0];
            max_gap = max_gap.max(c.gap.abs());
            pulling &= c.impulse[0] < 0.0;
        },
    );
    let vel = Vector3::from_column_slice(&model.body_u(b, &s.u)[..3]);
    let slope = rot.column(0).into_owned(); // downhill along the ceiling
    let a = G * alpha.sin();
    let along = slope.dot(&vel).abs();
    assert!(
        (along - a * t_end).abs() < 1e-9 * a,
        "v {along} vs {}",
        a * t_end
    );
    assert!(n.dot(&vel).abs() < 1e-12, "normal velocity {}", n.dot(&vel));
    assert!(max_gap < 1e-12, "gap {max_gap}");
    assert!(pulling, "the bilateral contact must pull");
}

/// DOPRI5 refuses a model with contacts (it would integrate through them as if absent), through
/// its own entry point and through the stepper contract.
#[test]
fn dopri5_refuses_contacts() {
    use flexmbs_core::integrator::{Dopri5, Dopri5Settings, Dopri5Stepper};
    use flexmbs_core::SolverError;
    let (model, mut s, _) = ball_on_plane(ContactLaw::unilateral(0.5), 0.1, 0.2);
    let mut ws = Workspace::new(&model);
    let dopri = Dopri5::new(Dopri5Settings::default());
    let e = dopri
        .integrate(&model, &mut s, &mut ws, 0.1, |_, _| {})
        .unwrap_err();
    assert!(
        matches!(
            e,
            SolverError::InvalidSetting {
                name: "contact",
                ..
            }
        ),
        "{e}"
    );
    assert!(
        e.to_string().contains("DOPRI5 does not handle contacts"),
        "{e}"
    );
    let mut st = Dopri5Stepper::new(dopri);
    let e = st.initialize(&model, &mut s, &mut ws).unwrap_err();
    assert!(matches!(e, SolverError::InvalidSetting { .. }), "{e}");
}
