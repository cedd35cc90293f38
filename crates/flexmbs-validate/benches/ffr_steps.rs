//! Steps per second of one FFR body on the rotating-beam model (tube hinged at one end, driven at
//! 100 rad/s by a prescribed revolute joint), for 6 ... 100 modes. Run:
//! `cargo bench -p flexmbs-validate --bench ffr_steps`. Not a test: nothing is asserted.

use flexmbs_core::ffr::{FfrBody, FfrElement, RotationParam};
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::{Joint, ModelSpec, PrescribedMotion, TimeFunction, Workspace};
use flexmbs_fe::constraint::BoundaryConditions;
use flexmbs_fe::eigen::EigenOptions;
use flexmbs_fe::element::MassKind;
use flexmbs_fe::reduction::{modal_analysis, reduce_modal, Provenance};
use flexmbs_fe::system::FeSystem;
use flexmbs_fe::{Material, UnitSystem};
use nalgebra::{Matrix3, Vector3};
use std::time::Instant;

fn main() {
    let start = Instant::now();
    let material = Material {
        e: 70e9,
        nu: 0.3,
        rho: 2700.0,
    };
    // solid square aluminium bar 1 m x 20 mm x 20 mm, 100 x 2 x 2 hex8i (a beam-element model has no
    // node rotary inertia in the FFR body: torsion modes would make its mass matrix singular)
    let mesh = flexmbs_fe::mesh::generate::box_mesh(
        [1.0, 0.02, 0.02],
        [100, 2, 2],
        flexmbs_fe::ElementKind::Hex8I,
        material,
        UnitSystem::Si,
    )
    .expect("mesh");
    let bc = BoundaryConditions {
        fixed: mesh.node_set("xmin").expect("set").to_vec(),
        rigid: vec![],
    };
    let sys = FeSystem::assemble(&mesh, &bc, MassKind::Lumped, &mut |_, _| {}).expect("assembly");
    let opts = EigenOptions {
        method: flexmbs_fe::eigen::EigenMethod::Dense, // 2700 DOFs, 150 modes
        ..EigenOptions::default()
    };
    let modal = modal_analysis(&sys, 150, &opts, &mut |_| {}).expect("modes");
    println!(
        "FE model: {} nodes, {} DOFs; modal analysis of 150 modes + set-up {:.2} s",
        mesh.num_nodes(),
        sys.len(),
        start.elapsed().as_secs_f64()
    );
    println!("| modes | steps | wall [s] | steps/s | us/step |");
    println!("|---|---|---|---|---|");
    for n in [6usize, 12, 24, 50, 100] {
        let body =
            reduce_modal(&mesh, &sys, &modal, n, "tube", Provenance::default()).expect("reduce");
        let ffr = FfrBody::from_reduced(&body, RotationParam::Cardan).expect("ffr");
        let mut spec = ModelSpec::new();
        let b = spec.add_body("tube", FfrElement::new(ffr));
        let g = spec.add_ground_frame("hinge", Vector3::zeros(), Matrix3::identity());
        let f = spec.add_frame("hinge", b, Vector3::zeros(), Matrix3::identity());
        spec.add_joint(Joint::revolute("drive", g, f).with_prescribed(
            PrescribedMotion::RevoluteRate {
                initial_angle: 0.0,
                rate: TimeFunction::Constant(100.0),
            },
        ));
        let model = spec.compile().expect("model");
        let mut s = model.initial_state();
        model.set_body_velocity(&mut s, b, Vector3::zeros(), Vector3::new(0.0, 0.0, 100.0));
        let mut ws = Workspace::new(&model);
        let ga = GenAlpha::new(GenAlphaSettings::default()).expect("integrator");
        ga.initialize(&model, &mut s, &mut ws).expect("init");
        let steps = if n <= 24 { 2000 } else { 400 };
        let t0 = Instant::now();
        ga.integrate(
            &model,
            &mut s,
            &mut ws,
            1e-4,
            steps as f64 * 1e-4,
            |_, _| {},
        )
        .expect("run");
        let wall = t0.elapsed().as_secs_f64();
        println!(
            "| {n} | {steps} | {wall:.3} | {:.0} | {:.1} |",
            steps as f64 / wall,
            1e6 * wall / steps as f64
        );
    }
}
