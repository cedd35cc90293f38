//! Newton's round-off floor with absolute interface coordinates: a chain of superelements
//! starting from rest under a ramped tip load converges with the default tolerances (before the
//! element force scale entered the floor, the first step failed: the elastic forces of absolute
//! coordinates carry round-off ~ K eps |x| that a tolerance relative to the (zero) net force at
//! rest cannot meet).

use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, NewtonSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::{Joint, Load, LoadCoordinates, ModelSpec, NodeKind, TimeFunction, Workspace};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{Matrix3, Vector3};

/// The tip's vertical position after `t_end` of the ramped load, with Newton `rtol`.
fn tip_after(t_end: f64, rtol: f64) -> (f64, usize) {
    let (n, l) = (10, 1.0);
    let mut spec = ModelSpec::new();
    let nodes: Vec<_> = (0..=n)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Pose))
        .collect();
    let mut bodies = vec![];
    for i in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: l / n as f64,
            material: Material {
                e: 70e9,
                nu: 0.3,
                rho: 2700.0,
            },
            section: BeamSection::tube(0.01, 0.001),
            theory: BeamTheory::EulerBernoulli,
            elements: 2,
            internal_modes: 0,
            frame: FrameLocation::CentreOfMass,
        })
        .unwrap();
        let se = Superelement::new(data).unwrap();
        bodies.push(spec.add_body_on(&format!("b{i}"), se, &nodes[i..i + 2]));
    }
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
    let root = spec.add_node_owned_frame("root", nodes[0], Vector3::zeros(), Matrix3::identity());
    let tip = spec.add_node_owned_frame("tip", nodes[n], Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", ground, root));
    spec.add_load(Load::Force {
        frame: tip,
        vector: Vector3::new(0.0, -2500.0, 0.0),
        time: TimeFunction::Ramp {
            t0: 0.0,
            t1: 0.05,
            v0: 0.0,
            v1: 1.0,
        },
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    for (i, b) in bodies.iter().enumerate() {
        let x = (i as f64 + 0.5) * l / n as f64;
        model.set_body_pose(&mut s, *b, Vector3::new(x, 0.0, 0.0), Matrix3::identity());
    }
    let mut ws = Workspace::new(&model);
    let ga = GenAlpha::new(GenAlphaSettings {
        newton: NewtonSettings {
            rtol,
            ..NewtonSettings::default()
        },
        ..GenAlphaSettings::default()
    })
    .unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    let mut iterations = 0;
    ga.integrate(&model, &mut s, &mut ws, 1e-4, t_end, |_, st| {
        iterations += st.iterations
    })
    .unwrap();
    (
        model.frame_kinematics(&s, tip).unwrap().position.y,
        iterations,
    )
}

/// With the default `rtol = 1e-10` the run converges (2 iterations per step) and agrees with the
/// run at `rtol = 1e-7` (which worked before, and whose tolerance bounds the difference).
#[test]
fn superelement_chain_from_rest_converges_with_default_tolerances() {
    let default_rtol = NewtonSettings::default().rtol;
    let (y, iterations) = tip_after(0.01, default_rtol);
    let (y_loose, _) = tip_after(0.01, 1e-7);
    eprintln!(
        "tip y at 0.01 s: {y:e} m (rtol 1e-7: {y_loose:e}), {iterations} iterations / 100 steps"
    );
    assert!(y < -0.01, "the tip moved down: {y}");
    assert!((y - y_loose).abs() < 1e-6 * y.abs(), "{y} vs {y_loose}");
    assert!(iterations <= 300, "{iterations} iterations");
}
