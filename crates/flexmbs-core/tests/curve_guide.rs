//! The bilateral guide of a frame on a 1D neutral contour ([`flexmbs_core::contact::guide`]):
//! - rows: `G u` equals the rate of `g` along the motion (central differences of `g` at
//!   `q ⊕ e u`) for a tumbling, deforming plate and a rotating ball, on and off the constraint
//!   manifold (the Jacobian is exact at any state, not only where `g = 0`);
//! - the contour frame is orthonormal with `t` along the deformed curve and `n_1` in the plane of
//!   `t` and the reference direction;
//! - dynamics: a ball guided along a clamped plate's centre line by the Moreau stepper with
//!   step-size control stays on it (`|g|` at round-off after the projection), conserves
//!   the energy of the smooth motion, and allocates nothing per step;
//! - bad input: a curve on a rigid body, a slider on the curve's own body, a zero normal.

use crate::counting_alloc;
use crate::plate;

use flexmbs_core::contact::{CurveGuide, NeutralCurve};
use flexmbs_core::ffr::contour::{ContourSettings, FfrCurveContour};
use flexmbs_core::ffr::FfrElement;
use flexmbs_core::integrator::{MoreauSscSettings, MoreauSscStepper, Stepper};
use flexmbs_core::rotation::rotation_vector_matrix;
use flexmbs_core::{
    system, BodyId, Joint, Model, ModelError, ModelSpec, RigidBody, State, Workspace,
};
use nalgebra::{Matrix3, Vector3};
use plate::{plate, NF, NX, NY};

/// The plate (body 0) with its centre line y = 0.05 as the curve, a ball (body 1, frame 1) guided
/// on it with `rotations`; the plate clamped to the ground if `clamped`.
fn guided_ball_spec(seed: &mut u64, rotations: bool, clamped: bool) -> ModelSpec {
    let body = plate(seed);
    let mut spec = ModelSpec::new();
    let line: Vec<usize> = (0..NX).map(|i| i * NY + 1).collect();
    let curve = FfrCurveContour::new(&body, &line, ContourSettings::default()).unwrap();
    let p = spec.add_body("plate", FfrElement::new(body));
    let fp = spec.add_frame("plate", p, Vector3::zeros(), Matrix3::identity());
    let b = spec.add_body(
        "ball",
        RigidBody::new(0.3, Matrix3::from_diagonal(&Vector3::new(1e-3, 2e-3, 3e-3))),
    );
    let fb = spec.add_frame("ball", b, Vector3::zeros(), Matrix3::identity());
    let curve = NeutralCurve::new(fp, curve, 0.0).unwrap();
    spec.add_guide(CurveGuide::new("guide", curve, fb, Vector3::y(), rotations));
    if clamped {
        let g = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
        spec.add_joint(Joint::fixed("clamp", g, fp));
    }
    spec
}

/// A tumbling, deforming plate, the ball at body-axes point `local` with a random rotation.
fn random_state(seed: &mut u64, model: &Model, local: Vector3<f64>) -> State {
    let mut s = model.initial_state();
    let a = rotation_vector_matrix(&Vector3::new(0.4, -0.9, 0.7));
    let r = Vector3::new(0.3, -0.2, 0.5);
    model.set_body_pose(&mut s, BodyId(0), r, a);
    let nq0 = model.body_dofs(BodyId(0)).q.len();
    for x in &mut s.q[nq0 - NF..nq0] {
        *x = 0.1 * plate::rnd(seed);
    }
    let rb = rotation_vector_matrix(&Vector3::new(
        plate::rnd(seed),
        plate::rnd(seed),
        plate::rnd(seed),
    ));
    model.set_body_pose(&mut s, BodyId(1), r + a * local, rb);
    for x in s.u.iter_mut() {
        *x = plate::rnd(seed);
    }
    s
}

/// `g` and `G u` at `s`.
fn rows(model: &Model, s: &State, ws: &mut Workspace) -> (Vec<f64>, Vec<f64>) {
    system::evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
    system::update_constraints(model, s.t, &mut ws.sys);
    let gu = (0..model.nc)
        .map(|r| (0..model.nu).map(|j| ws.sys.g_jac[(r, j)] * s.u[j]).sum())
        .collect();
    (ws.sys.g.clone(), gu)
}

fn moved(model: &Model, s: &State, e: f64) -> State {
    let mut m = s.clone();
    let dv: Vec<f64> = s.u.iter().map(|u| e * u).collect();
    system::integrate_positions(model, &s.q, &dv, &mut m.q);
    m
}

#[test]
fn guide_rows_equal_finite_differences_on_and_off_the_manifold() {
    // off the manifold: the ball 4 mm and 2 mm off the line, rotated; near it: 1e-9
    for (local, rotations) in [
        (Vector3::new(0.31, 0.054, 0.002), true),
        (Vector3::new(0.47, 0.0500, 1e-9), true),
        (Vector3::new(0.12, 0.047, -0.003), false),
    ] {
        let mut seed = 5;
        let model = guided_ball_spec(&mut seed, rotations, false)
            .compile()
            .unwrap();
        assert_eq!(model.nc, if rotations { 5 } else { 2 });
        let s = random_state(&mut seed, &model, local);
        let mut ws = Workspace::new(&model);
        let (g0, gu) = rows(&model, &s, &mut ws);
        let w = &ws.sys.guides[0];
        assert!(!w.beyond_end);
        // the contour frame (t, n_1, n_2): orthonormal, right-handed
        let [t, n1, n2] = w.frame;
        assert!((t.cross(&n1) - n2).norm() < 1e-14);
        assert!(t.dot(&n1).abs() < 1e-14 && (n1.norm() - 1.0).abs() < 1e-14);
        // the projection: the offset c - r_C is perpendicular to t
        let c = ws.sys.frames[1].position;
        assert!(t.dot(&(c - w.point)).abs() < 1e-12);
        let e = 1e-6;
        let mut ws2 = Workspace::new(&model);
        let (gp, _) = rows(&model, &moved(&model, &s, e), &mut ws2);
        let (gm, _) = rows(&model, &moved(&model, &s, -e), &mut ws2);
        for r in 0..model.nc {
            let fd = (gp[r] - gm[r]) / (2.0 * e);
            // central differences: O(e^2 g''') ~ 1e-11 and round-off 1e-16 / e
            assert!(
                (fd - gu[r]).abs() < 1e-8 * (1.0 + fd.abs()),
                "row {r} at {local:?}: finite difference {fd} vs G u {} (g = {})",
                gu[r],
                g0[r]
            );
        }
    }
}

/// The rows' values alone (`update_constraint_values`, the Moreau projection's iterates) equal
/// those of the full update bit for bit, with and without rotations, clamped (joint rows first),
/// off the manifold, and at a second state searched from the first one's warm start.
#[test]
fn guide_values_alone_equal_the_full_update_bitwise() {
    for (local, rotations) in [
        (Vector3::new(0.31, 0.054, 0.002), true),
        (Vector3::new(0.12, 0.047, -0.003), false),
    ] {
        let mut seed = 7;
        let model = guided_ball_spec(&mut seed, rotations, true)
            .compile()
            .unwrap();
        let s = random_state(&mut seed, &model, local);
        let (mut full, mut values) = (Workspace::new(&model), Workspace::new(&model));
        for state in [s.clone(), moved(&model, &s, 1e-3)] {
            let (g, _) = rows(&model, &state, &mut full);
            system::evaluate(&model, &state.q, &state.u, &mut values.sys).unwrap();
            system::update_constraint_values(&model, state.t, &mut values.sys);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&g), bits(&values.sys.g), "rotations {rotations}");
            let (a, b) = (&full.sys.guides[0], &values.sys.guides[0]);
            assert_eq!(a.eta.to_bits(), b.eta.to_bits());
            assert_eq!(a.point, b.point);
            assert_eq!(a.frame, b.frame);
        }
    }
}

#[test]
fn guided_ball_stays_on_the_line_and_conserves_energy() {
    let mut seed = 3;
    let model = guided_ball_spec(&mut seed, true, true).compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        BodyId(1),
        Vector3::new(0.1, 0.05, 0.0),
        Matrix3::identity(),
    );
    // sliding along the line with a transverse velocity: an initial impact makes the velocities
    // consistent, then the motion is smooth
    model.set_body_velocity(
        &mut s,
        BodyId(1),
        Vector3::new(1.0, 0.0, -0.2),
        Vector3::zeros(),
    );
    let mut ws = Workspace::new(&model);
    let mut st = MoreauSscStepper::new(MoreauSscSettings {
        h_max: 1e-3,
        ..MoreauSscSettings::default()
    });
    st.initialize(&model, &mut s, &mut ws).unwrap();
    let energy =
        |s: &State, ws: &mut Workspace| flexmbs_core::integrator::monitor(&model, s, ws).0.total();
    let mut h = 1e-4;
    // the first step resolves the inconsistent initial velocity
    while s.t == 0.0 {
        h = st.step(&model, &mut s, &mut ws, h).unwrap().h_next;
    }
    let mut ws_e = Workspace::new(&model);
    let e1 = energy(&s, &mut ws_e);
    let (mut g_max, mut e_dev, mut steps) = (0.0_f64, 0.0_f64, 0);
    let mut allocations = 0;
    while s.t < 0.15 {
        let hh = h.min(0.15 - s.t).max(1e-9);
        allocations += counting_alloc::allocations_in(|| {
            let a = st.step(&model, &mut s, &mut ws, hh).unwrap();
            h = a.h_next;
        });
        steps += 1;
        let (_, g, _) = flexmbs_core::integrator::monitor(&model, &s, &mut ws_e);
        g_max = g_max.max(g);
        e_dev = e_dev.max((energy(&s, &mut ws_e) - e1).abs() / e1);
    }
    let x = model.body_q(BodyId(1), &s.q)[0];
    // the ball moved along the plate's line (at about 1 m/s, 0.15 m) and stayed on it
    assert!((x - 0.25).abs() < 0.01, "x = {x}");
    assert!(!ws.sys.guides[0].beyond_end);
    assert!(g_max < 1e-10, "constraint drift {g_max}");
    // after the initial impact no work is done: measured 5e-9 over 0.3 s
    assert!(e_dev < 1e-7, "energy deviation {e_dev} in {steps} steps");
    assert_eq!(allocations, 0, "allocations in {steps} steps");
}

#[test]
fn bad_guides_are_refused_at_compile_time() {
    let mut seed = 1;
    // a slider on the curve's own body
    let body = plate(&mut seed);
    let line: Vec<usize> = (0..NX).map(|i| i * NY + 1).collect();
    let curve = FfrCurveContour::new(&body, &line, ContourSettings::default()).unwrap();
    let mut spec = ModelSpec::new();
    let p = spec.add_body("plate", FfrElement::new(body));
    let fp = spec.add_frame("plate", p, Vector3::zeros(), Matrix3::identity());
    let f2 = spec.add_frame("other", p, Vector3::x(), Matrix3::identity());
    let nc = NeutralCurve::new(fp, curve.clone(), 0.0).unwrap();
    spec.add_guide(CurveGuide::new("g", nc.clone(), f2, Vector3::z(), true));
    let err = spec.compile().unwrap_err();
    assert!(
        matches!(&err, ModelError::InvalidContact { reason, .. } if reason.contains("own body")),
        "{err}"
    );
    // a curve on a rigid body's frame
    let mut spec = ModelSpec::new();
    let r = spec.add_body("rigid", RigidBody::new(1.0, Matrix3::identity()));
    let fr = spec.add_frame("rigid", r, Vector3::zeros(), Matrix3::identity());
    let b = spec.add_body("ball", RigidBody::new(1.0, Matrix3::identity()));
    let fb = spec.add_frame("ball", b, Vector3::zeros(), Matrix3::identity());
    let mut on_rigid = nc.clone();
    on_rigid.frame = fr;
    spec.add_guide(CurveGuide::new("g", on_rigid, fb, Vector3::z(), false));
    let err = spec.compile().unwrap_err();
    assert!(
        matches!(&err, ModelError::InvalidContact { reason, .. } if reason.contains("supplies no neutral contours")),
        "{err}"
    );
    // a zero normal direction
    let mut seed = 1;
    let body = plate(&mut seed);
    let curve = FfrCurveContour::new(&body, &line, ContourSettings::default()).unwrap();
    let mut spec2 = ModelSpec::new();
    let p = spec2.add_body("plate", FfrElement::new(body));
    let fp = spec2.add_frame("plate", p, Vector3::zeros(), Matrix3::identity());
    let b = spec2.add_body("ball", RigidBody::new(1.0, Matrix3::identity()));
    let fb = spec2.add_frame("ball", b, Vector3::zeros(), Matrix3::identity());
    let nc = NeutralCurve::new(fp, curve, 0.0).unwrap();
    spec2.add_guide(CurveGuide::new("g", nc, fb, Vector3::zeros(), false));
    let err = spec2.compile().unwrap_err();
    assert!(
        matches!(&err, ModelError::InvalidContact { reason, .. } if reason.contains("normal")),
        "{err}"
    );
}

/// Generalized-alpha takes the guide's rows too (`g`, `G`; the acceleration bias is zero and
/// the tangent of `G^T lambda` is neglected): a ball sliding along the clamped plate's line at
/// 1 m/s (consistent start: along the line, plate at rest) for 0.1 s stays on it and keeps its
/// energy within the scheme's numerical damping (rho_inf = 0.9).
#[test]
fn generalized_alpha_integrates_a_guided_ball() {
    use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
    let mut seed = 3;
    let model = guided_ball_spec(&mut seed, true, true).compile().unwrap();
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        BodyId(1),
        Vector3::new(0.1, 0.05, 0.0),
        Matrix3::identity(),
    );
    model.set_body_velocity(&mut s, BodyId(1), Vector3::x(), Vector3::zeros());
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    let mut ws = Workspace::new(&model);
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let mut ws_e = Workspace::new(&model);
    let e0 = flexmbs_core::integrator::monitor(&model, &s, &mut ws_e)
        .0
        .total();
    let (mut g_max, mut e_dev) = (0.0_f64, 0.0_f64);
    ga.integrate(&model, &mut s, &mut ws, 2e-4, 0.1, |s, st| {
        g_max = g_max.max(st.g_max);
        let e = flexmbs_core::integrator::monitor(&model, s, &mut ws_e)
            .0
            .total();
        e_dev = e_dev.max((e - e0).abs() / e0);
    })
    .unwrap();
    let x = model.body_q(BodyId(1), &s.q)[0];
    assert!((x - 0.2).abs() < 5e-3, "x = {x}");
    assert!(g_max < 1e-8, "constraint drift {g_max}");
    assert!(e_dev < 1e-3, "energy deviation {e_dev}");
}
