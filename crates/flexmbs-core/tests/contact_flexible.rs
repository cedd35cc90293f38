//! Contact on flexible contours (seed 000 §3.1-3.3): a sphere against a neutral surface, a
//! neutral curve (tube) and a flexible band of a tumbling, deforming FFR plate.
//! - kinematics: `d g_N / dt` along the motion (central differences of the gap at `q ⊕ e u`)
//!   equals `g_N_dot` (3.8), and the generalized directions reproduce the contact-point rates,
//!   `W^T u = (g_N_dot, g_T_dot)`;
//! - the normal projection: the contact point is the foot of the perpendicular (the gap vector
//!   is along the normal);
//! - dynamics: a ball dropped on a free-floating flexible plate with `C_R = 1` (Moreau) gains no
//!   energy, and the total momentum is conserved through the impacts;
//! - bad input: a contour on a rigid body or with the wrong mode count is refused at compile time;
//! - Moreau steps with a flexible contour allocate nothing (fixed and step-size controlled).

use crate::counting_alloc;
use crate::plate;

use flexmbs_core::contact::{
    Contact, ContactLaw, ContactWork, FlexibleBand, NeutralCurve, NeutralSurface, SphereContour,
};
use flexmbs_core::ffr::contour::{ContourSettings, FfrCurveContour, FfrSurfaceContour};
use flexmbs_core::ffr::FfrElement;
use flexmbs_core::integrator::{MoreauSettings, MoreauStepper, Stepper};
use flexmbs_core::rotation::rotation_vector_matrix;
use flexmbs_core::{
    system, BodyId, Joint, Model, ModelError, ModelSpec, RigidBody, State, Workspace,
};
use nalgebra::{Matrix3, Vector3};
use plate::{plate, NF, NX, NY};

#[derive(Clone, Copy, Debug)]
enum Kind {
    Surface,
    Curve,
    Band,
}

/// The plate (body 0, frame 0 its reference frame) and a ball (body 1, radius 0.02, frame 1)
/// in contact through a contour of `kind`.
fn plate_and_ball(seed: &mut u64, kind: Kind, law: ContactLaw) -> Model {
    plate_and_ball_spec(seed, kind, law, false)
        .compile()
        .unwrap()
}

/// As [`plate_and_ball`], the plate's reference frame fixed to the ground if `clamped`.
fn plate_and_ball_spec(seed: &mut u64, kind: Kind, law: ContactLaw, clamped: bool) -> ModelSpec {
    let body = plate(seed);
    let mut spec = ModelSpec::new();
    let grid: Vec<usize> = (0..NX * NY).collect();
    let surface = FfrSurfaceContour::new(&body, &grid, NX, NY, ContourSettings::default());
    // the centre line y = 0.05 (node column 1)
    let line: Vec<usize> = (0..NX).map(|i| i * NY + 1).collect();
    let curve = FfrCurveContour::new(&body, &line, ContourSettings::default()).unwrap();
    let p = spec.add_body("plate", FfrElement::new(body));
    let fp = spec.add_frame("plate", p, Vector3::zeros(), Matrix3::identity());
    let b = spec.add_body("ball", RigidBody::new(0.3, Matrix3::identity() * 1e-4));
    let fb = spec.add_frame("ball", b, Vector3::zeros(), Matrix3::identity());
    let ball = SphereContour {
        frame: fb,
        radius: 0.02,
    };
    let contact = match kind {
        Kind::Surface => Contact::new(
            "c",
            NeutralSurface::new(fp, surface.unwrap()).unwrap(),
            ball,
            law,
        ),
        Kind::Curve => Contact::new("c", NeutralCurve::new(fp, curve, 0.01).unwrap(), ball, law),
        Kind::Band => Contact::new(
            "c",
            FlexibleBand {
                curve: NeutralCurve::new(fp, curve, 0.0).unwrap(),
                width: 0.08,
                offset: 0.005,
                normal: Vector3::z(),
            },
            ball,
            law,
        ),
    };
    spec.add_contact(contact);
    if clamped {
        let g = spec.add_ground_frame("ground", Vector3::zeros(), Matrix3::identity());
        spec.add_joint(Joint::fixed("clamp", g, fp));
    }
    spec
}

/// A tumbling, deforming plate with the ball near body-axes point `(0.31, 0.06, 0.05)`.
fn random_state(seed: &mut u64, model: &Model) -> State {
    let mut s = model.initial_state();
    let a = rotation_vector_matrix(&Vector3::new(0.4, -0.9, 0.7));
    let r = Vector3::new(0.3, -0.2, 0.5);
    model.set_body_pose(&mut s, BodyId(0), r, a);
    let q = &mut s.q;
    let nq0 = model.body_dofs(BodyId(0)).q.len();
    for x in &mut q[nq0 - NF..nq0] {
        *x = 0.1 * plate::rnd(seed);
    }
    let ball = r + a * Vector3::new(0.31, 0.06, 0.05);
    model.set_body_pose(&mut s, BodyId(1), ball, Matrix3::identity());
    for x in s.u.iter_mut() {
        *x = plate::rnd(seed);
    }
    s
}

fn moved(model: &Model, s: &State, e: f64) -> State {
    let mut m = s.clone();
    let dv: Vec<f64> = s.u.iter().map(|u| e * u).collect();
    system::integrate_positions(model, &s.q, &dv, &mut m.q);
    m
}

fn geometry(
    model: &Model,
    s: &State,
    ws: &mut Workspace,
    work: &mut ContactWork,
) -> flexmbs_core::contact::ContactGeometry {
    system::evaluate(model, &s.q, &s.u, &mut ws.sys).unwrap();
    model.contacts[0].geometry(model, &ws.sys.frames, &ws.sys.eval, &mut work.sides[0])
}

#[test]
fn flexible_contact_rates_equal_finite_differences_and_w_transpose_u() {
    for kind in [Kind::Surface, Kind::Curve, Kind::Band] {
        let mut seed = 11;
        let model = plate_and_ball(&mut seed, kind, ContactLaw::unilateral(0.0));
        let s = random_state(&mut seed, &model);
        let mut ws = Workspace::new(&model);
        let mut work = ContactWork::new(&model);
        let geo = geometry(&model, &s, &mut ws, &mut work);
        assert!(geo.has_contact_point(), "{kind:?}: no contact point");
        // the contact point is the foot of the perpendicular from the ball centre
        let d = geo.point_b - geo.point_a;
        assert!(
            d.cross(&geo.normal).norm() < 1e-10,
            "{kind:?}: gap vector not along the normal"
        );
        assert!((geo.normal.dot(&d) - geo.gap).abs() < 1e-12);
        let (gn_dot, gt_dot) = geo.gap_velocities();
        let e = 1e-6;
        let mut gap = |x: f64| {
            let mut w2 = ContactWork::new(&model);
            geometry(&model, &moved(&model, &s, x), &mut ws, &mut w2).gap
        };
        let fd = (gap(e) - gap(-e)) / (2.0 * e);
        // central differences: O(e^2 |g'''|) ~ 1e-11, plus round-off 1e-16 / e
        assert!(
            (fd - gn_dot).abs() < 1e-8 * (1.0 + gn_dot.abs()),
            "{kind:?}: finite difference {fd} vs g_N_dot {gn_dot}"
        );
        let geo = geometry(&model, &s, &mut ws, &mut work);
        for (k, want) in [gn_dot, gt_dot[0], gt_dot[1]].into_iter().enumerate() {
            let mut w = vec![0.0; model.nu];
            model.contacts[0].add_direction(
                &model,
                &ws.sys.frames,
                &work.sides[0],
                &geo,
                k,
                1.0,
                &mut w,
            );
            let wu: f64 = w.iter().zip(&s.u).map(|(x, y)| x * y).sum();
            assert!(
                (wu - want).abs() < 1e-12 * (1.0 + want.abs()),
                "{kind:?} direction {k}: W^T u {wu} vs {want}"
            );
        }
    }
}

/// A ball (C_R = `restitution`, 1 m/s down) dropped on the plate, its reference frame clamped
/// to the ground (the seed's configuration: the body's frame fixed, the contour deforming), run
/// to 0.3 s with Moreau steps `h`: (impact steps, largest relative energy gain, final relative
/// energy change).
fn drop_ball_on_clamped_plate(restitution: f64, h: f64) -> (usize, f64, f64) {
    let mut seed = 3;
    let law = ContactLaw::unilateral(restitution);
    let model = plate_and_ball_spec(&mut seed, Kind::Surface, law, true)
        .compile()
        .unwrap();
    let mut s = model.initial_state();
    let ball = Vector3::new(0.31, 0.07, 0.021);
    model.set_body_pose(&mut s, BodyId(1), ball, Matrix3::identity());
    model.set_body_velocity(
        &mut s,
        BodyId(1),
        Vector3::new(0.05, 0.0, -1.0),
        Vector3::zeros(),
    );
    let mut ws = Workspace::new(&model);
    let mut st = MoreauStepper::new(MoreauSettings::default());
    st.initialize(&model, &mut s, &mut ws).unwrap();
    let energy =
        |s: &State, ws: &mut Workspace| flexmbs_core::integrator::monitor(&model, s, ws).0.total();
    let e0 = energy(&s, &mut ws);
    let (mut impacts, mut gain) = (0, f64::NEG_INFINITY);
    for _ in 0..(0.3 / h).round() as usize {
        st.step(&model, &mut s, &mut ws, h).unwrap();
        if s.contacts[0].impulse[0] > 0.0 {
            impacts += 1;
        }
        gain = gain.max((energy(&s, &mut ws) - e0) / e0);
    }
    (impacts, gain, (energy(&s, &mut ws) - e0) / e0)
}

#[test]
fn ball_bouncing_on_a_clamped_flexible_plate_gains_no_energy() {
    for h in [1e-4, 2.5e-5] {
        let (impacts, gain, end) = drop_ball_on_clamped_plate(1.0, h);
        eprintln!("C_R = 1, h {h}: {impacts} impact steps, largest gain {gain:e}, end {end:e}");
        assert!(impacts > 0, "the ball never hit the plate");
        // Moreau with C_R <= 1 never gains energy beyond round-off (seed §4.2; benchmarks:
        // 0.1 % at most)
        assert!(gain <= 1e-3, "h {h}: energy gain {gain}");
    }
    let (impacts, gain, end) = drop_ball_on_clamped_plate(0.0, 1e-4);
    eprintln!("C_R = 0: {impacts} impact steps, largest gain {gain:e}, end {end:e}");
    assert!(
        gain <= 1e-3 && end < -1e-2,
        "C_R = 0 dissipates: {gain} {end}"
    );
}

#[test]
fn flexible_contours_on_the_wrong_body_are_refused() {
    let mut seed = 7;
    let body = plate(&mut seed);
    let grid: Vec<usize> = (0..NX * NY).collect();
    let surface = FfrSurfaceContour::new(&body, &grid, NX, NY, ContourSettings::default()).unwrap();
    let mut spec = ModelSpec::new();
    let r = spec.add_body("rigid", RigidBody::new(1.0, Matrix3::identity()));
    let fr = spec.add_frame("rigid", r, Vector3::zeros(), Matrix3::identity());
    let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
    spec.add_contact(Contact::new(
        "c",
        NeutralSurface::new(fr, surface).unwrap(),
        SphereContour {
            frame: g,
            radius: 0.1,
        },
        ContactLaw::unilateral(0.0),
    ));
    match spec.compile() {
        Err(ModelError::InvalidContact { reason, .. }) => {
            assert!(reason.contains("supplies no neutral contours"), "{reason}")
        }
        other => panic!("expected InvalidContact, got {other:?}"),
    }
}

#[test]
fn moreau_steps_on_flexible_contours_allocate_nothing() {
    use flexmbs_core::integrator::{MoreauSscSettings, MoreauSscStepper};
    for kind in [Kind::Surface, Kind::Band] {
        let mut seed = 3;
        let law = ContactLaw::unilateral(0.5);
        let model = plate_and_ball_spec(&mut seed, kind, law, true)
            .compile()
            .unwrap();
        let mut s = model.initial_state();
        let ball = Vector3::new(0.31, 0.05, 0.0205);
        model.set_body_pose(&mut s, BodyId(1), ball, Matrix3::identity());
        let v = Vector3::new(0.05, 0.0, -1.0);
        model.set_body_velocity(&mut s, BodyId(1), v, Vector3::zeros());
        let mut ws = Workspace::new(&model);
        let mut fixed = MoreauStepper::new(MoreauSettings::default());
        let mut ssc = MoreauSscStepper::new(MoreauSscSettings::default());
        let mut s2 = s.clone();
        let mut ws2 = Workspace::new(&model);
        fixed.initialize(&model, &mut s, &mut ws).unwrap();
        ssc.initialize(&model, &mut s2, &mut ws2).unwrap();
        // warm-up: the first impact and the first full search happen here
        for _ in 0..20 {
            fixed.step(&model, &mut s, &mut ws, 1e-4).unwrap();
            ssc.step(&model, &mut s2, &mut ws2, 1e-4).unwrap();
        }
        let n = counting_alloc::allocations_in(|| {
            for _ in 0..200 {
                fixed.step(&model, &mut s, &mut ws, 1e-4).unwrap();
                ssc.step(&model, &mut s2, &mut ws2, 5e-5).unwrap();
            }
        });
        assert_eq!(n, 0, "{kind:?}: {n} allocations in 400 steps");
    }
}
