//! The Moreau time-stepper on a jointed system: joint rows as velocity-level equalities with a
//! position projection against drift, checked on the physical pendulum's period (analytic) and on
//! a pendulum whose bob hits a wall (Newton impact inside a jointed system).
use flexmbs_core::contact::{Contact, ContactLaw, PlaneContour, SphereContour};
use flexmbs_core::integrator::{drive, MoreauSettings, MoreauStepper, Stepper};
use flexmbs_core::{Joint, ModelSpec, RigidBody};
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::ops::ControlFlow;

const G: f64 = 9.81;

/// Rod of mass 1 hinged about z with its centre of mass `l` below the hinge; optionally a wall
/// (plane x = `wall`, normal +x) hit by a sphere of radius `r` at the centre of mass.
fn pendulum(
    theta0: f64,
    wall: Option<(f64, f64, f64)>,
) -> (flexmbs_core::Model, flexmbs_core::State) {
    let (m, l, i_c) = (1.0, 0.5, 1.0 / 12.0);
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -G, 0.0));
    let rod = spec.add_body(
        "rod",
        RigidBody::new(m, Matrix3::from_diagonal(&Vector3::new(i_c, 1e-4, i_c))),
    );
    let hinge = spec.add_ground_frame("hinge", Vector3::zeros(), Matrix3::identity());
    let top = spec.add_frame("top", rod, Vector3::new(0.0, l, 0.0), Matrix3::identity());
    spec.add_joint(Joint::revolute("pin", hinge, top));
    if let Some((x, r, cr)) = wall {
        let centre = spec.add_frame("centre", rod, Vector3::zeros(), Matrix3::identity());
        // plane normal +x (material at x < wall): rotation taking z to +x
        let rot = Rotation3::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let w = spec.add_ground_frame("wall", Vector3::new(x, 0.0, 0.0), rot.into_inner());
        spec.add_contact(Contact::new(
            "hit",
            SphereContour {
                frame: centre,
                radius: r,
            },
            PlaneContour { frame: w },
            ContactLaw::unilateral(cr),
        ));
    }
    let model = spec.compile().unwrap();
    let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), theta0);
    let mut s = model.initial_state();
    model.set_body_pose(
        &mut s,
        flexmbs_core::BodyId(0),
        rot * Vector3::new(0.0, -l, 0.0),
        rot.into_inner(),
    );
    (model, s)
}

/// Small-amplitude period `2 pi sqrt(I_hinge / (m g l)) (1 + theta0^2 / 16)` and joint drift at
/// round-off (projection). Joint rows only: every step's velocity problem is solved directly (one
/// "sweep", residual at round-off).
#[test]
fn pendulum_period_and_drift() {
    let (model, mut s) = pendulum(0.1, None);
    let mut ws = flexmbs_core::Workspace::new(&model);
    let mut st = MoreauStepper::new(MoreauSettings::default());
    st.initialize(&model, &mut s, &mut ws).unwrap();
    let (mut crossings, mut last, mut g_max, mut e) = (Vec::new(), (0.0, 1.0), 0.0_f64, Vec::new());
    let (mut sweeps, mut residual) = (0usize, 0.0_f64);
    let control = st.control(1e-4);
    drive(
        &mut st,
        &model,
        &mut s,
        &mut ws,
        control,
        3.0,
        |s, stats| {
            let x = s.q[0];
            if last.1 < 0.0 && x >= 0.0 {
                crossings.push(last.0 + (s.t - last.0) * last.1 / (last.1 - x));
            }
            last = (s.t, x);
            g_max = g_max.max(stats.g_max);
            sweeps = sweeps.max(stats.iterations);
            residual = residual.max(stats.residual);
            e.push(stats.energy.total());
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    let (l, i_c) = (0.5_f64, 1.0 / 12.0);
    let exact = 2.0 * std::f64::consts::PI * ((i_c + l * l) / (G * l)).sqrt() * (1.0 + 0.01 / 16.0);
    let period = crossings[1] - crossings[0];
    assert!((period - exact).abs() < 1e-4 * exact, "{period} vs {exact}");
    assert!(g_max <= 1e-12, "joint drift {g_max}");
    assert_eq!(sweeps, 1, "joint rows only: one direct solve per step");
    assert!(residual <= 1e-13, "direct solve residual {residual}");
    let e_scale = G * l * (1.0 - 0.1_f64.cos());
    let e_drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e_scale;
    assert!(e_drift < 1e-3, "energy drift {e_drift} of the swing energy");
    println!(
        "Moreau pendulum: period {period} (exact {exact}), drift {g_max:.1e}, energy {e_drift:.1e}"
    );
}

/// A pendulum released at 0.3 rad hits a wall at its lowest point with `C_R`: the angular
/// velocity reverses with factor `C_R` (the joint takes the impact's reaction), so with
/// `C_R = 1` it swings back to 0.3 rad, with `C_R = 0.5` to the angle of a quarter of the energy.
#[test]
fn pendulum_hits_wall() {
    let (theta0, r, h) = (0.3_f64, 0.05, 1e-4);
    for cr in [1.0, 0.5] {
        // wall touching the sphere when the rod hangs straight down
        let (model, mut s) = pendulum(theta0, Some((-r, r, cr)));
        let mut ws = flexmbs_core::Workspace::new(&model);
        let mut st = MoreauStepper::new(MoreauSettings::default());
        st.initialize(&model, &mut s, &mut ws).unwrap();
        let mut max_angle: f64 = 0.0;
        let mut hit = false;
        let control = st.control(h);
        drive(&mut st, &model, &mut s, &mut ws, control, 1.2, |s, _| {
            hit |= s.contacts[0].impulse[0] > 0.0;
            if hit {
                max_angle = max_angle.max(s.q[5]);
            }
            ControlFlow::Continue(())
        })
        .unwrap();
        assert!(hit);
        // energy after the impact: C_R^2 of the swing energy, 1 - cos(theta) = C_R^2 (1 - cos theta0)
        let expected = (1.0 - cr * cr * (1.0 - theta0.cos())).acos();
        // impact resolved at a step's midpoint: an angle error of the order of omega h
        assert!(
            (max_angle - expected).abs() < 2e-3 * expected,
            "C_R {cr}: {max_angle} vs {expected}"
        );
        println!(
            "pendulum on wall C_R = {cr}: swings back to {max_angle:.5} rad (exact {expected:.5})"
        );
    }
}
