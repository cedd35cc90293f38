//! Contacts and guides on a superelement's neutral curve, through the model (the contact code
//! sees the body only as a [`flexmbs_core::contour_source::NeutralContourSource`]):
//! - a sphere on the curve (a tube) of a tumbling, deforming beam superelement: `d g_N / dt`
//!   (central differences at `q ⊕ e u`) equals `g_N_dot`, and `W^T u` the contact-point rates;
//! - a ball guided on the curve: `G u` equals (Richardson-extrapolated) central differences of
//!   the guide rows `g`, off the constraint manifold, to 1e-8 (1 + |ġ|);
//! - statics: a point mass of weight `P` resting through a regularized contact on a cantilever
//!   of four beam superelements at `x = a`: the beam point under the load deflects by linear
//!   beam theory `P a³ / (3 E I)` (tolerance stated before the run: 1e-3 relative; the
//!   Craig-Bampton truncation of the load at an interior FE node of a segment with 2 internal
//!   modes and the geometric nonlinearity at `v/a ~ 1e-3` are both far below it), and the
//!   contact force balances the weight (`k_c` times the penetration equals `P` to 1e-6);
//! - Moreau steps (fixed and step-size controlled) with the sphere contact or the guide on the
//!   superelement allocate nothing.

use crate::counting_alloc;
use flexmbs_core::contact::SphereContour;

use flexmbs_core::contact::{Contact, ContactLaw, ContactWork, CurveGuide, NeutralCurve};
use flexmbs_core::ffr::contour::{ContourSettings, FfrCurveContour};
use flexmbs_core::integrator::{Statics, StaticsSettings};
use flexmbs_core::superelement::{
    beam_segment_basis, beam_segment_contour_nodes, BeamSegmentSpec, FrameLocation, Superelement,
};
use flexmbs_core::{
    system, BodyId, Joint, Load, LoadCoordinates, Model, ModelSpec, RigidBody, State, TimeFunction,
    Workspace,
};
use flexmbs_fe::element::MassKind;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{Matrix3, Rotation3, Vector3};

const E: f64 = 70e9;

fn segment(length: f64, elements: usize, internal_modes: usize) -> BeamSegmentSpec {
    BeamSegmentSpec {
        length,
        material: Material {
            e: E,
            nu: 0.3,
            rho: 2700.0,
        },
        section: BeamSection::tube(0.01, 0.001),
        theory: BeamTheory::EulerBernoulli,
        elements,
        internal_modes,
        frame: FrameLocation::CentreOfMass,
    }
}

/// A superelement of `sp` and the cubic curve through its FE nodes.
fn body_and_curve(sp: &BeamSegmentSpec) -> (Superelement, FfrCurveContour) {
    let (data, v, _) = beam_segment_basis(sp, MassKind::Consistent).unwrap();
    let nodes = beam_segment_contour_nodes(sp, &data, &v);
    let line: Vec<usize> = (0..nodes.positions.len()).collect();
    let curve = FfrCurveContour::new(&nodes, &line, ContourSettings::default()).unwrap();
    (Superelement::new(data).unwrap(), curve)
}

fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

/// A free beam superelement (body 0, frame 0 its floating frame) and a ball (body 1, frame 1):
/// a sphere contact (`guide` false) or a guide with rotations.
fn beam_and_ball(guide: bool) -> Model {
    let (se, curve) = body_and_curve(&segment(0.8, 6, 3));
    let mut spec = ModelSpec::new();
    let b = spec.add_body("beam", se);
    let fp = spec.add_frame("beam", b, Vector3::zeros(), Matrix3::identity());
    let ball = spec.add_body("ball", RigidBody::new(0.3, Matrix3::identity() * 1e-4));
    let fb = spec.add_frame("ball", ball, Vector3::zeros(), Matrix3::identity());
    if guide {
        let curve = NeutralCurve::new(fp, curve, 0.0).unwrap();
        spec.add_guide(CurveGuide::new("guide", curve, fb, Vector3::y(), true));
    } else {
        let sphere = SphereContour {
            frame: fb,
            radius: 0.02,
        };
        let curve = NeutralCurve::new(fp, curve, 0.01).unwrap();
        spec.add_contact(Contact::new(
            "c",
            curve,
            sphere,
            ContactLaw::unilateral(0.0),
        ));
    }
    spec.compile().unwrap()
}

/// The beam tumbling and deformed (a random position increment of its interfaces and modes),
/// the ball at frame-axes point `local`, random velocities.
fn random_state(seed: &mut u64, model: &Model, local: Vector3<f64>) -> State {
    let mut s = model.initial_state();
    let a = *Rotation3::from_scaled_axis(Vector3::new(0.4, -0.9, 0.7)).matrix();
    let r = Vector3::new(0.3, -0.2, 0.5);
    model.set_body_pose(&mut s, BodyId(0), r, a);
    let mut dv = vec![0.0; model.nu];
    let cols = &model.body_dofs(BodyId(0)).u;
    for j in 0..cols.len() {
        dv[cols.global(j)] = 0.01 * rnd(seed);
    }
    let q0 = s.q.clone();
    system::integrate_positions(model, &q0, &dv, &mut s.q);
    let rb = *Rotation3::from_scaled_axis(Vector3::new(rnd(seed), rnd(seed), rnd(seed))).matrix();
    model.set_body_pose(&mut s, BodyId(1), r + a * local, rb);
    for x in s.u.iter_mut() {
        *x = rnd(seed);
    }
    s
}

fn moved(model: &Model, s: &State, e: f64) -> State {
    let mut m = s.clone();
    let dv: Vec<f64> = s.u.iter().map(|u| e * u).collect();
    system::integrate_positions(model, &s.q, &dv, &mut m.q);
    m
}

#[test]
fn sphere_on_a_superelement_curve_rates_equal_finite_differences() {
    let mut seed = 11;
    let model = beam_and_ball(false);
    let s = random_state(&mut seed, &model, Vector3::new(0.13, 0.035, 0.01));
    let mut ws = Workspace::new(&model);
    let mut geometry = |s: &State, work: &mut ContactWork| {
        system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
        let g =
            model.contacts[0].geometry(&model, &ws.sys.frames, &ws.sys.eval, &mut work.sides[0]);
        (g, ws.sys.frames.clone())
    };
    let mut work = ContactWork::new(&model);
    let (geo, frames) = geometry(&s, &mut work);
    assert!(geo.has_contact_point(), "no contact point");
    let (gn_dot, gt_dot) = geo.gap_velocities();
    let e = 1e-6;
    let mut gap = |x: f64| {
        let mut w2 = ContactWork::new(&model);
        geometry(&moved(&model, &s, x), &mut w2).0.gap
    };
    let fd = (gap(e) - gap(-e)) / (2.0 * e);
    println!(
        "gap {:.4e}: g_N_dot {gn_dot:.9e}, central difference {fd:.9e}",
        geo.gap
    );
    assert!(
        (fd - gn_dot).abs() < 1e-8 * (1.0 + gn_dot.abs()),
        "finite difference {fd} vs g_N_dot {gn_dot}"
    );
    for (k, want) in [gn_dot, gt_dot[0], gt_dot[1]].into_iter().enumerate() {
        let mut w = vec![0.0; model.nu];
        model.contacts[0].add_direction(&model, &frames, &work.sides[0], &geo, k, 1.0, &mut w);
        let wu: f64 = w.iter().zip(&s.u).map(|(x, y)| x * y).sum();
        assert!(
            (wu - want).abs() < 1e-12 * (1.0 + want.abs()),
            "direction {k}: W^T u {wu} vs {want}"
        );
    }
}

#[test]
fn guide_on_a_superelement_curve_rows_equal_finite_differences() {
    let model = beam_and_ball(true);
    assert_eq!(model.nc, 5);
    for local in [
        Vector3::new(0.13, 0.004, 0.002),
        Vector3::new(-0.21, -0.003, 0.001),
    ] {
        let mut seed = 5;
        let s = random_state(&mut seed, &model, local);
        let mut ws = Workspace::new(&model);
        let mut rows = |s: &State| {
            system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
            system::update_constraints(&model, s.t, &mut ws.sys);
            let gu: Vec<f64> = (0..model.nc)
                .map(|r| (0..model.nu).map(|j| ws.sys.g_jac[(r, j)] * s.u[j]).sum())
                .collect();
            (ws.sys.g.clone(), gu)
        };
        let (g0, gu) = rows(&s);
        // Richardson-extrapolated central differences (error O(e^4)): the tumbling beam's
        // rows have large third derivatives (plain central differences at e = 1e-6 are off by
        // up to 3e-8 relative, shrinking as e^2)
        let e = 1e-6;
        let mut central = |e: f64| {
            let (gp, _) = rows(&moved(&model, &s, e));
            let (gm, _) = rows(&moved(&model, &s, -e));
            (0..model.nc)
                .map(|r| (gp[r] - gm[r]) / (2.0 * e))
                .collect::<Vec<f64>>()
        };
        let (d1, d2) = (central(e), central(2.0 * e));
        for r in 0..model.nc {
            let fd = (4.0 * d1[r] - d2[r]) / 3.0;
            println!(
                "row {r}: g {:.3e}, G u {:.9e}, central difference {fd:.9e}",
                g0[r], gu[r]
            );
            assert!(
                (fd - gu[r]).abs() < 1e-8 * (1.0 + fd.abs()),
                "row {r} at {local:?}: finite difference {fd} vs G u {}",
                gu[r]
            );
        }
    }
}

#[test]
fn point_mass_resting_on_a_superelement_cantilever_deflects_it_by_beam_theory() {
    let (length, n_seg, a) = (1.0, 4, 0.625);
    let p = 1.0;
    // penetration P / k_c = 1e-5 m: ten times the contact tangent's difference step
    let k_c = 1e5;
    let mut spec = ModelSpec::new();
    let nodes: Vec<_> = (0..=n_seg)
        .map(|i| spec.add_node(&format!("n{i}"), flexmbs_core::NodeKind::Pose))
        .collect();
    let l = length / n_seg as f64;
    let sp = segment(l, 4, 2);
    let mut bodies = Vec::new();
    let mut curve_frame = None;
    let mut curve = None;
    for i in 0..n_seg {
        let (se, c) = body_and_curve(&sp);
        let nodes_i = &nodes[i..i + 2];
        let nodes_i = if sp.internal_modes > 0 {
            let eta = spec.add_node(
                &format!("eta{i}"),
                flexmbs_core::NodeKind::Vector(sp.internal_modes),
            );
            vec![nodes_i[0], eta, nodes_i[1]]
        } else {
            nodes_i.to_vec()
        };
        let b = spec.add_body_on(&format!("b{i}"), se, &nodes_i);
        if i == 2 {
            curve_frame = Some(spec.add_frame("seg", b, Vector3::zeros(), Matrix3::identity()));
            curve = Some(c);
        }
        bodies.push(b);
    }
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
    let root = spec.add_node_owned_frame("root", nodes[0], Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", ground, root));
    // the mass: free along y only (a prismatic joint along the ground's y)
    let (r_tube, r_ball) = (0.01, 0.005);
    let ball = spec.add_body("ball", RigidBody::new(0.1, Matrix3::identity() * 1e-5));
    let fb = spec.add_frame("ball", ball, Vector3::zeros(), Matrix3::identity());
    let y_axis = Matrix3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let slide = spec.add_ground_frame("slide", Vector3::new(a, 0.0, 0.0), y_axis);
    spec.add_joint(Joint::prismatic("slide", slide, fb));
    spec.add_load(Load::Force {
        frame: fb,
        vector: Vector3::new(0.0, -p, 0.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    let curve = NeutralCurve::new(curve_frame.unwrap(), curve.unwrap(), r_tube).unwrap();
    let sphere = SphereContour {
        frame: fb,
        radius: r_ball,
    };
    spec.add_contact(Contact::new(
        "rest",
        curve,
        sphere,
        ContactLaw::regularized(k_c, 0.0),
    ));
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    for (i, b) in bodies.iter().enumerate() {
        let x = (i as f64 + 0.5) * l;
        model.set_body_pose(&mut s, *b, Vector3::new(x, 0.0, 0.0), Matrix3::identity());
    }
    // resting on the undeformed beam with the penetration of the weight
    let y0 = r_tube + r_ball - p / k_c;
    model.set_body_pose(&mut s, BodyId(n_seg), Vector3::new(a, y0, 0.0), y_axis);
    let mut ws = Workspace::new(&model);
    let statics = Statics::new(StaticsSettings {
        load_steps: 10,
        ..Default::default()
    });
    let stats = statics
        .solve_with(&model, &mut s, &mut ws, |_, _, _| {})
        .unwrap();
    println!("{stats:?}");
    system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
    let mut work = ContactWork::new(&model);
    let geo = model.contacts[0].geometry(&model, &ws.sys.frames, &ws.sys.eval, &mut work.sides[0]);
    let force = -k_c * geo.gap * geo.normal.y;
    // the beam point under the load: the curve point of the contact
    let v = -(geo.point_a.y - r_tube * geo.normal.y);
    let ei = E * BeamSection::tube(0.01, 0.001).iz;
    let want = p * a.powi(3) / (3.0 * ei);
    println!(
        "contact force {force:.9} N (weight {p}), beam point at x = {:.6}: deflection {v:.9e} m, beam theory {want:.9e} m, rel. error {:.2e}",
        geo.point_a.x,
        (v - want) / want
    );
    assert!((force - p).abs() < 1e-6 * p, "force {force}");
    assert!(((v - want) / want).abs() < 1e-3, "deflection {v} vs {want}");
}

#[test]
fn moreau_steps_on_superelement_contours_allocate_nothing() {
    use flexmbs_core::integrator::{
        MoreauSettings, MoreauSscSettings, MoreauSscStepper, MoreauStepper, Stepper,
    };
    for guide in [false, true] {
        let model = beam_and_ball(guide);
        let mut s = model.initial_state();
        let (at, v) = if guide {
            (Vector3::new(0.13, 0.0, 0.0), Vector3::new(0.5, 0.0, 0.0))
        } else {
            (
                Vector3::new(0.13, 0.0301, 0.0),
                Vector3::new(0.05, -1.0, 0.0),
            )
        };
        model.set_body_pose(&mut s, BodyId(1), at, Matrix3::identity());
        model.set_body_velocity(&mut s, BodyId(1), v, Vector3::zeros());
        let mut ws = Workspace::new(&model);
        let mut fixed = MoreauStepper::new(MoreauSettings::default());
        let mut ssc = MoreauSscStepper::new(MoreauSscSettings::default());
        let mut s2 = s.clone();
        let mut ws2 = Workspace::new(&model);
        fixed.initialize(&model, &mut s, &mut ws).unwrap();
        ssc.initialize(&model, &mut s2, &mut ws2).unwrap();
        for _ in 0..20 {
            fixed.step(&model, &mut s, &mut ws, 1e-5).unwrap();
            ssc.step(&model, &mut s2, &mut ws2, 1e-5).unwrap();
        }
        let n = counting_alloc::allocations_in(|| {
            for _ in 0..100 {
                fixed.step(&model, &mut s, &mut ws, 1e-5).unwrap();
                ssc.step(&model, &mut s2, &mut ws2, 1e-5).unwrap();
            }
        });
        assert_eq!(n, 0, "guide {guide}: {n} allocations in 200 steps");
    }
}
