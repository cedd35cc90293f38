//! Regularized (penalty) contact in generalized-alpha (seed 000 §3.1, §3.4): the contact forces
//! `W_N F_N + W_T F_T` enter `h`, their local tangent the iteration matrix.
//! - the tangent equals a fourth-order finite-difference Jacobian of the assembled contact
//!   forces (global perturbation, full evaluation: an independent path) on a rigid sphere vs a
//!   plane and a point vs a tumbling FFR plate's neutral surface; frictionless and undamped, the
//!   sphere's normal stiffness is `-k` exactly;
//! - a ball resting on a plane settles at the static penetration `m g / k`;
//! - a ball hitting a plane under a linear spring-damper law rebounds with the analytic
//!   restitution of the damped oscillator (no-tension law: contact ends when the force is 0);
//! - the same penalty model under Moreau and generalized-alpha agrees better as `h` falls, and
//!   the penalty energy `1/2 k g_N^2` is reported with the springs' energy;
//! - set-valued laws are refused; steps allocate nothing (dense and sparse backends).

use crate::counting_alloc;
use crate::plate;

use flexmbs_core::algebra::LinearSolver;
use flexmbs_core::contact::{
    regularized, Contact, ContactLaw, ContactWork, NeutralSurface, PlaneContour, PointContour,
    SphereContour, TangentDirections,
};
use flexmbs_core::ffr::contour::{ContourSettings, FfrSurfaceContour};
use flexmbs_core::ffr::FfrElement;
use flexmbs_core::integrator::{
    GenAlpha, GenAlphaSettings, MoreauSettings, MoreauStepper, StepStats, Stepper,
};
use flexmbs_core::rotation::rotation_vector_matrix;
use flexmbs_core::{
    system, BodyId, Model, ModelSpec, RigidBody, RotationParam, SolverError, State, Workspace,
};
use nalgebra::{Matrix3, Vector3};

const G: f64 = 9.81;

/// A ball (mass `m`, radius `r`, quaternion) with its lowest point `gap` above the ground plane
/// z = 0, gravity `g` along -z.
fn ball_on_plane(law: ContactLaw, m: f64, r: f64, gap: f64, g: f64) -> (Model, State) {
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
    spec.add_contact(Contact::new(
        "c",
        sphere,
        PlaneContour { frame: ground },
        law,
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let p = Vector3::new(0.0, 0.0, gap + r);
    model.set_body_pose(&mut s, BodyId(0), p, Matrix3::identity());
    (model, s)
}

/// The generalized contact forces of `model` at `(q, u)` by a full evaluation.
fn contact_forces(model: &Model, q: &[f64], u: &[f64], ws: &mut Workspace) -> Vec<f64> {
    system::evaluate(model, q, u, &mut ws.sys).unwrap();
    let mut h = vec![0.0; model.nu];
    let (frames, eval) = (&ws.sys.frames, &ws.sys.eval);
    regularized::add_regularized_forces(model, frames, eval, &mut ws.contact, &mut h);
    h
}

/// Fourth-order central differences `(8 (f(e) - f(-e)) - (f(2e) - f(-2e))) / (12 e)` of the
/// contact forces along `q ⊕ e_j` (positions) or `u + e_j` (velocities), column `j`.
fn reference_column(model: &Model, s: &State, j: usize, position: bool, e: f64) -> Vec<f64> {
    let mut ws = Workspace::new(model);
    let mut at = |x: f64| {
        let (mut q, mut u) = (s.q.clone(), s.u.clone());
        if position {
            let mut dv = vec![0.0; model.nu];
            dv[j] = x;
            system::integrate_positions(model, &s.q, &dv, &mut q);
        } else {
            u[j] += x;
        }
        contact_forces(model, &q, &u, &mut ws)
    };
    let (p1, m1, p2, m2) = (at(e), at(-e), at(2.0 * e), at(-2.0 * e));
    (0..model.nu)
        .map(|i| (8.0 * (p1[i] - m1[i]) - (p2[i] - m2[i])) / (12.0 * e))
        .collect()
}

/// The contact tangents of the engine (`system::add_contact_tangents`) against
/// [`reference_column`]: the largest difference relative to the largest entry, for `dh/dq`
/// and `dh/du`.
fn tangent_errors(model: &Model, s: &State) -> (f64, f64, f64) {
    let mut ws = Workspace::new(model);
    let mut work = ContactWork::new(model);
    system::evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
    ws.sys.dh_dq.fill(0.0);
    ws.sys.dh_du.fill(0.0);
    system::add_contact_tangents(model, &s.q, &s.u, &mut ws.sys, &mut work);
    let mut err = [0.0_f64; 2];
    let mut scale = [0.0_f64; 2];
    for (k, position) in [true, false].into_iter().enumerate() {
        let m = if position {
            &ws.sys.dh_dq
        } else {
            &ws.sys.dh_du
        };
        for j in 0..model.nu {
            let r = reference_column(model, s, j, position, 1e-5);
            for (i, ri) in r.iter().enumerate() {
                err[k] = err[k].max((m[(i, j)] - ri).abs());
                scale[k] = scale[k].max(ri.abs());
            }
        }
    }
    (err[0] / scale[0], err[1] / scale[1], scale[0])
}

/// Rigid sphere vs plane: penetrating, sliding and spinning, damped, with regularized spatial
/// friction (slipping): the tangent equals the finite differences to 1e-6 relative; without
/// friction and damping the normal stiffness is `-k` (and nothing else but the moment arm).
#[test]
fn contact_tangent_equals_finite_differences_sphere_plane() {
    let k = 1e5;
    let law = ContactLaw::regularized(k, 80.0).with_regularized_friction(
        0.4,
        0.05,
        TangentDirections::Spatial,
    );
    let (model, mut s) = ball_on_plane(law, 1.2, 0.1, -2e-3, G);
    let b = BodyId(0);
    let a = rotation_vector_matrix(&Vector3::new(0.3, -0.2, 0.5));
    model.set_body_pose(&mut s, b, Vector3::new(0.1, 0.2, 0.098), a);
    let (v, w) = (Vector3::new(0.3, -0.2, -0.4), Vector3::new(1.0, 2.0, -0.5));
    model.set_body_velocity(&mut s, b, v, w);
    let (eq, eu, _) = tangent_errors(&model, &s);
    println!("sphere-plane tangent: dh/dq {eq:.2e}, dh/du {eu:.2e} relative");
    assert!(eq < 1e-6 && eu < 1e-6, "dh/dq {eq:e}, dh/du {eu:e}");
    // frictionless, undamped: d F_z / d z = -k on the ball's z translation
    let (model, mut s) = ball_on_plane(ContactLaw::regularized(k, 0.0), 1.2, 0.1, -2e-3, G);
    model.set_body_velocity(&mut s, b, v, w);
    let mut ws = Workspace::new(&model);
    let mut work = ContactWork::new(&model);
    system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
    ws.sys.dh_dq.fill(0.0);
    system::add_contact_tangents(&model, &s.q, &s.u, &mut ws.sys, &mut work);
    let kzz = ws.sys.dh_dq[(2, 2)];
    assert!(
        (kzz + k).abs() < 1e-6 * k,
        "dF_z/dz = {kzz}, expected {}",
        -k
    );
}

/// A free FFR plate (3 modes), tumbling and deforming, and a point (a rigid body's frame)
/// pressed 3 mm into its neutral surface: the tangent on both bodies' coordinates, including the
/// modal columns and the moving contact point, equals the finite differences to 1e-6 relative.
#[test]
fn contact_tangent_equals_finite_differences_point_on_ffr_surface() {
    let mut seed = 5;
    let body = plate::plate(&mut seed);
    let mut spec = ModelSpec::new();
    let grid: Vec<usize> = (0..plate::NX * plate::NY).collect();
    let surface = FfrSurfaceContour::new(
        &body,
        &grid,
        plate::NX,
        plate::NY,
        ContourSettings::default(),
    )
    .unwrap();
    let p = spec.add_body("plate", FfrElement::new(body));
    let fp = spec.add_frame("plate", p, Vector3::zeros(), Matrix3::identity());
    let b = spec.add_body("mass", RigidBody::new(0.3, Matrix3::identity() * 1e-4));
    let fb = spec.add_frame("mass", b, Vector3::zeros(), Matrix3::identity());
    let law = ContactLaw::regularized(2e4, 15.0).with_regularized_friction(
        0.3,
        0.02,
        TangentDirections::Spatial,
    );
    let surface = NeutralSurface::new(fp, surface).unwrap();
    spec.add_contact(Contact::new("c", surface, PointContour { frame: fb }, law));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let (a, r) = (
        rotation_vector_matrix(&Vector3::new(0.4, -0.9, 0.7)),
        Vector3::new(0.3, -0.2, 0.5),
    );
    model.set_body_pose(&mut s, BodyId(0), r, a);
    let nq0 = model.body_dofs(BodyId(0)).q.len();
    for x in &mut s.q[nq0 - plate::NF..nq0] {
        *x = 0.1 * plate::rnd(&mut seed);
    }
    for x in s.u.iter_mut() {
        *x = plate::rnd(&mut seed);
    }
    // the point 3 mm below the deformed surface along its normal
    let point = r + a * Vector3::new(0.31, 0.06, 0.0);
    model.set_body_pose(&mut s, BodyId(1), point, Matrix3::identity());
    let mut ws = Workspace::new(&model);
    let mut work = ContactWork::new(&model);
    system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
    let geo = model.contacts[0].geometry(&model, &ws.sys.frames, &ws.sys.eval, &mut work.sides[0]);
    assert!(geo.has_contact_point());
    let point = point - (geo.gap + 3e-3) * geo.normal;
    model.set_body_pose(&mut s, BodyId(1), point, Matrix3::identity());
    let (eq, eu, kq) = tangent_errors(&model, &s);
    println!("point-FFR surface tangent: dh/dq {eq:.2e}, dh/du {eu:.2e} relative (|K| {kq:.3e})");
    assert!(eq < 1e-6 && eu < 1e-6, "dh/dq {eq:e}, dh/du {eu:e}");
}

/// Runs generalized-alpha (`rho_inf`) with step `h` to `t_end` on a workspace with `solver`,
/// calling `f` after every step.
fn run_genalpha(
    model: &Model,
    s: &mut State,
    rho_inf: f64,
    solver: LinearSolver,
    h: f64,
    t_end: f64,
    mut f: impl FnMut(&State, &StepStats),
) {
    let ga = GenAlpha::new(GenAlphaSettings {
        rho_inf,
        ..Default::default()
    })
    .unwrap();
    let mut ws = Workspace::with_linear_solver(model, solver);
    ga.initialize(model, s, &mut ws).unwrap();
    let n = (t_end / h).round() as usize;
    for _ in 0..n {
        let st = ga.step(model, s, &mut ws, h).unwrap();
        f(s, &st);
    }
}

/// A ball (m = 2 kg) released at zero gap on a plane with k = 1e5 N/m and damping ratio 0.5
/// settles at the static penetration `m g / k` (1e-9 relative), with the contact force `m g`
/// reported as impulse / h, on the dense and the sparse backend.
#[test]
fn ball_resting_on_plane_settles_at_static_penetration() {
    let (m, k): (f64, f64) = (2.0, 1e5);
    let d = 2.0 * 0.5 * (k * m).sqrt();
    for solver in [LinearSolver::Dense, LinearSolver::Sparse] {
        let (model, mut s) = ball_on_plane(ContactLaw::regularized(k, d), m, 0.1, 0.0, G);
        let h = 1e-3;
        let mut last = None;
        run_genalpha(&model, &mut s, 0.9, solver, h, 0.4, |s, _| {
            last = Some(s.contacts[0]);
        });
        let pen = 0.1 - s.q[2];
        let exact = m * G / k;
        println!("{solver:?}: penetration {pen:.12e}, m g / k = {exact:.12e}");
        assert!((pen - exact).abs() < 1e-9 * exact, "{pen} vs {exact}");
        let c = last.unwrap();
        assert!(c.active && (c.gap + exact).abs() < 1e-9 * exact, "{c:?}");
        assert!((c.impulse[0] / h - m * G).abs() < 1e-6 * m * G, "{c:?}");
    }
}

/// Coefficient of restitution of a mass on a linear spring-damper that cannot pull (damping
/// ratio `zeta`): the penetration `x = v0/w_d e^(-zeta w t) sin(w_d t)`; contact ends when
/// `k x + d x_dot = 0`, `tan(w_d t*) = -2 zeta sqrt(1 - zeta^2) / (1 - 2 zeta^2)`, and
/// `e = -x_dot(t*) / v0 = e^(-zeta w t*) (sqrt(1 - zeta^2) cos(w_d t*) - zeta sin(w_d t*)) /
/// sqrt(1 - zeta^2)` (reduces to `e^(-zeta pi / sqrt(1 - zeta^2))` when the force may pull).
fn no_tension_restitution(zeta: f64) -> f64 {
    let c = (1.0 - zeta * zeta).sqrt();
    let phi = std::f64::consts::PI - (2.0 * zeta * c / (1.0 - 2.0 * zeta * zeta)).atan();
    // zeta w t* = zeta phi / sqrt(1 - zeta^2)
    (-zeta * phi / c).exp() * (c * phi.cos() - zeta * phi.sin()).abs() / c
}

/// Rebound velocity ratio of a ball (no gravity, 1 m/s towards the plane from 0.12345 mm: contact does not start at a step boundary) under
/// `k = 1e5`, damping ratio `zeta`, with generalized-alpha (`rho_inf = 1`) and step `h`.
fn rebound_ratio(zeta: f64, h: f64) -> f64 {
    let (m, k): (f64, f64) = (1.0, 1e5);
    let d = 2.0 * zeta * (k * m).sqrt();
    let (model, mut s) = ball_on_plane(ContactLaw::regularized(k, d), m, 0.1, 1.2345e-4, 0.0);
    model.set_body_velocity(&mut s, BodyId(0), -Vector3::z(), Vector3::zeros());
    // contact lasts under half a period, pi / w = 9.9 ms
    run_genalpha(
        &model,
        &mut s,
        1.0,
        LinearSolver::Dense,
        h,
        0.015,
        |_, _| {},
    );
    assert!(s.q[2] > 0.1, "ball separated");
    s.u[2]
}

/// The restitution of the damped linear oscillator (no-tension law, [`no_tension_restitution`])
/// for damping ratios 0.05, 0.2 and 0.5: the error falls with the step at first order (the
/// force jumps by `d v0` where the contact closes; the closing step fades the damping in,
/// `regularized::damping_factor`), by a factor 1.8 to 2.2 per halving, and is below 1e-3
/// relative at h = 5e-6 s.
#[test]
fn dropped_ball_rebounds_with_damped_oscillator_restitution() {
    for zeta in [0.05, 0.2, 0.5] {
        let e = no_tension_restitution(zeta);
        let e_pull = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
        let mut errors = Vec::new();
        for h in [4e-5, 2e-5, 1e-5, 5e-6] {
            errors.push((rebound_ratio(zeta, h) - e).abs());
        }
        println!("zeta {zeta}: e = {e:.6} (pulling law {e_pull:.6}), errors {errors:?}");
        for w in errors.windows(2) {
            let ratio = w[0] / w[1];
            assert!(
                (1.8..2.2).contains(&ratio),
                "zeta {zeta}: first-order convergence: {errors:?}"
            );
        }
        assert!(errors[3] < 1e-3 * e, "zeta {zeta}: {errors:?}");
    }
}

/// A ball dropped about 5 cm on a penalty contact (k = 1e5, d = 20) under Moreau and
/// generalized-alpha: the difference of the rebound velocities at 0.2 s (after the bounce),
/// the envelope over five drop heights (each integrator's error depends on where the steps
/// fall relative to the contact's start), falls with the step (first order), to below 6e-4 of the drop speed
/// at h = 2.5e-5 s.
#[test]
fn moreau_and_genalpha_agree_as_h_falls() {
    let mut diffs = Vec::new();
    for h in [2e-4, 1e-4, 5e-5, 2.5e-5] {
        let worst = (0..5)
            .map(|j| moreau_genalpha_difference(0.05 * (1.0 + 0.0123 * j as f64), h))
            .fold(0.0, f64::max);
        diffs.push(worst);
    }
    println!("Moreau vs generalized-alpha, |du_z| / v0: {diffs:?}");
    for w in diffs.windows(2) {
        assert!(w[1] < w[0], "{diffs:?}");
    }
    assert!(diffs[3] < 6e-4, "{diffs:?}");
}

/// `|u_z(Moreau) - u_z(generalized-alpha)| / v0` at 0.2 s of a ball dropped from gap `h0` on a
/// penalty contact (k = 1e5, d = 20), step `h`.
fn moreau_genalpha_difference(h0: f64, h: f64) -> f64 {
    let t_end = 0.2;
    let (model, s0) = ball_on_plane(ContactLaw::regularized(1e5, 20.0), 1.0, 0.05, h0, G);
    let mut ga = s0.clone();
    run_genalpha(
        &model,
        &mut ga,
        1.0,
        LinearSolver::Dense,
        h,
        t_end,
        |_, _| {},
    );
    let mut mo = s0.clone();
    let mut ws = Workspace::new(&model);
    let mut st = MoreauStepper::new(MoreauSettings::default());
    st.initialize(&model, &mut mo, &mut ws).unwrap();
    for _ in 0..(t_end / h).round() as usize {
        st.step(&model, &mut mo, &mut ws, h).unwrap();
    }
    assert!(
        ga.u[2] > 0.0 && mo.u[2] > 0.0,
        "both rising after the bounce"
    );
    (ga.u[2] - mo.u[2]).abs() / (2.0 * G * h0).sqrt()
}

/// Undamped penalty bounce with generalized-alpha (`rho_inf = 1`): the step statistics report
/// the penalty energy `1/2 k g_N^2` with the springs' energy (checked against the state's gap),
/// and the artificial energy (largest change of the total) shrinks with the step.
#[test]
fn penalty_energy_is_reported_and_artificial_energy_shrinks() {
    let k = 1e5;
    let mut worst = Vec::new();
    for h in [1e-4, 5e-5, 2.5e-5] {
        let (model, mut s) = ball_on_plane(ContactLaw::regularized(k, 0.0), 1.0, 0.05, 0.05, G);
        let mut ws = Workspace::new(&model);
        let (e0, _, _) = flexmbs_core::integrator::monitor(&model, &s, &mut ws);
        let e0 = e0.total();
        let (mut change, mut checked): (f64, usize) = (0.0, 0);
        run_genalpha(&model, &mut s, 1.0, LinearSolver::Dense, h, 0.2, |s, st| {
            let g = s.contacts[0].gap;
            if g < 0.0 {
                let pen = 0.5 * k * g * g;
                assert!((st.energy.springs - pen).abs() <= 1e-12 * pen.max(1e-300));
                checked += 1;
            }
            change = change.max((st.energy.total() - e0).abs());
        });
        assert!(checked > 10, "steps in contact: {checked}");
        worst.push(change / (G * 0.05));
    }
    println!("generalized-alpha penalty: artificial energy up to {worst:?} of m g h0");
    for w in worst.windows(2) {
        assert!(w[1] < w[0], "{worst:?}");
    }
    assert!(worst[2] < 1e-3, "{worst:?}");
}

/// Set-valued laws need the Moreau stepper: generalized-alpha refuses them when initialized.
#[test]
fn genalpha_refuses_set_valued_contact_laws() {
    for law in [
        ContactLaw::unilateral(0.5),
        ContactLaw::regularized(1e5, 0.0).with_coulomb(0.3, TangentDirections::Planar),
    ] {
        let (model, mut s) = ball_on_plane(law, 1.0, 0.1, 0.1, G);
        let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
        let mut ws = Workspace::new(&model);
        let err = ga.initialize(&model, &mut s, &mut ws).unwrap_err();
        assert!(
            matches!(
                err,
                SolverError::InvalidSetting {
                    name: "contact",
                    ..
                }
            ),
            "{err}"
        );
    }
}

/// Generalized-alpha steps with a penalty contact (in contact, with friction) allocate nothing,
/// dense and sparse.
#[test]
fn genalpha_contact_steps_allocate_nothing() {
    let law = ContactLaw::regularized(1e5, 50.0).with_regularized_friction(
        0.3,
        0.01,
        TangentDirections::Spatial,
    );
    for solver in [LinearSolver::Dense, LinearSolver::Sparse] {
        let (model, mut s) = ball_on_plane(law, 1.0, 0.1, 1e-4, G);
        model.set_body_velocity(
            &mut s,
            BodyId(0),
            Vector3::new(0.5, 0.0, -0.3),
            Vector3::zeros(),
        );
        let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
        let mut ws = Workspace::with_linear_solver(&model, solver);
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        for _ in 0..5 {
            ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        }
        let n = counting_alloc::allocations_in(|| {
            for _ in 0..50 {
                ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
            }
        });
        assert!(s.contacts[0].active, "in contact");
        assert_eq!(n, 0, "{solver:?}: {n} allocations in 50 steps");
    }
}

/// Statics with a penalty contact: a ball (m = 2 kg) guided along z by a joint (x, y and the
/// rotations locked), started at zero gap under gravity, comes to rest at the penetration
/// `m g / k` (1e-10 relative), dense and sparse; the contact tangent makes Newton converge.
#[test]
fn statics_with_penalty_contact_finds_m_g_over_k() {
    use flexmbs_core::integrator::{Statics, StaticsSettings};
    use flexmbs_core::Joint;
    let (m, k, r) = (2.0, 1e5, 0.1);
    for solver in [LinearSolver::Dense, LinearSolver::Sparse] {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, 0.0, -G));
        let ball = RigidBody::new(m, Matrix3::from_diagonal_element(0.4 * m * r * r))
            .with_rotation(RotationParam::Quaternion);
        let b = spec.add_body("ball", ball);
        let centre = spec.add_frame("centre", b, Vector3::zeros(), Matrix3::identity());
        let ground = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
        let axis = spec.add_ground_frame("axis", Vector3::new(0.0, 0.0, r), Matrix3::identity());
        let sphere = SphereContour {
            frame: centre,
            radius: r,
        };
        let law = ContactLaw::regularized(k, 10.0);
        spec.add_contact(Contact::new(
            "c",
            sphere,
            PlaneContour { frame: ground },
            law,
        ));
        let locks = [true, true, false, true, true, true];
        spec.add_joint(Joint::new("slide", axis, centre, locks));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        model.set_body_pose(&mut s, b, Vector3::new(0.0, 0.0, r), Matrix3::identity());
        let mut ws = Workspace::with_linear_solver(&model, solver);
        let st = Statics::new(StaticsSettings {
            load_steps: 2,
            ..Default::default()
        });
        st.solve(&model, &mut s, &mut ws).unwrap();
        let (pen, exact) = (r - s.q[2], m * G / k);
        println!("statics {solver:?}: penetration {pen:.12e}, m g / k = {exact:.12e}");
        assert!((pen - exact).abs() < 1e-10 * exact, "{pen} vs {exact}");
    }
}
