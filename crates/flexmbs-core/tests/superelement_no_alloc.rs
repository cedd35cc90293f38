//! No heap allocation inside a time step of superelements (counting global allocator; own test
//! binary): a clamped chain of three superelements with internal modes under gravity and a tip
//! load, dense and sparse backends, fictitious forces neglected (analytic tangent) and from
//! `M_CB` (finite-difference tangent).
use crate::counting_alloc;
use flexmbs_core::algebra::LinearSolver;
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::superelement::{
    beam_segment, BeamSegmentSpec, FictitiousForces, FrameLocation, Superelement,
};
use flexmbs_core::*;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{Matrix3, Vector3};

fn chain_steps_allocations(choice: LinearSolver, fictitious: FictitiousForces) -> usize {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let n = 3;
    let mut nodes = vec![spec.add_node("n0", NodeKind::Pose)];
    let mut bodies = Vec::new();
    for i in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: 1.0 / n as f64,
            material: Material {
                e: 70e9,
                nu: 0.3,
                rho: 2700.0,
            },
            section: BeamSection::tube(0.01, 0.001),
            theory: BeamTheory::EulerBernoulli,
            elements: 4,
            internal_modes: 1,
            frame: FrameLocation::CentreOfMass,
        })
        .unwrap();
        let eta = spec.add_node(&format!("eta{i}"), NodeKind::Vector(1));
        let next = spec.add_node(&format!("n{}", i + 1), NodeKind::Pose);
        let se = Superelement::new(data)
            .unwrap()
            .with_fictitious_forces(fictitious);
        bodies.push(spec.add_body_on(&format!("b{i}"), se, &[nodes[i], eta, next]));
        nodes.push(next);
    }
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), Matrix3::identity());
    let root = spec.add_node_owned_frame("root", nodes[0], Vector3::zeros(), Matrix3::identity());
    let tip = spec.add_node_owned_frame("tip", nodes[n], Vector3::zeros(), Matrix3::identity());
    spec.add_joint(Joint::fixed("clamp", ground, root));
    spec.add_load(Load::Force {
        frame: tip,
        vector: Vector3::new(0.0, -20.0, 5.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Frame,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    for (i, b) in bodies.iter().enumerate() {
        let x = (i as f64 + 0.5) / n as f64;
        model.set_body_pose(&mut s, *b, Vector3::new(x, 0.0, 0.0), Matrix3::identity());
    }
    let mut ws = Workspace::with_linear_solver(&model, choice);
    let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
    ga.initialize(&model, &mut s, &mut ws).unwrap();
    ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
    counting_alloc::allocations_in(|| {
        for _ in 0..20 {
            ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        }
    })
}

#[test]
fn superelement_steps_do_not_allocate() {
    for choice in [LinearSolver::Dense, LinearSolver::Sparse] {
        for fictitious in [FictitiousForces::Neglected, FictitiousForces::FromMcb] {
            let n = chain_steps_allocations(choice, fictitious);
            assert_eq!(
                n, 0,
                "{choice:?} {fictitious:?}: {n} allocations in 20 steps"
            );
        }
    }
}
