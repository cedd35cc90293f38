//! Cost of superelement chains (seed 001; issue 9 "Must show": benchmarks).
//!
//! 1. Dynamics: the `rotating_beam` tube (L = 1 m, hinged, 100 rad/s prescribed, 50 N tip pulse
//!    during 0.01 s) as chains of 10 and 50 superelements (2 FE beam elements each, static modes,
//!    floating frames at the centres of mass), generalized-alpha rho_inf 0.9, full Newton, sparse
//!    and dense backends: wall time per step and Newton iterations per step over 0.3 s (or
//!    `SE_BENCH_STEPS` steps), at h = 1e-4 s and 2e-5 s (the validation case's step).
//! 2. Statics: the `cantilever_static` tube clamped at x = 0 as chains of 10 and 50 superelements
//!    under a vertical tip force of 2500 N in 50 equal load steps (Newton-Raphson on the analytic
//!    tangent), sparse and dense: wall time and Newton iterations per load step.
//!
//! Run: `cargo bench -p flexmbs-validate --bench superelement_chains`. Not a test: nothing is
//! asserted. `SE_BENCH_STEPS=n` caps the dynamic steps (e.g. under callgrind);
//! `SE_BENCH_BODIES=10` restricts the chain lengths; `SE_BENCH_ONLY=sparse-1e-4` runs only the
//! dynamics with that backend and step (no statics), e.g. under `/usr/bin/time` for the CPU time;
//! `SE_BENCH_ACCURACY=1e-4,2e-5` (untimed) prints the first tip peak and the post-pulse frequency of
//! the 10-body chain at those steps (reference: 0.090666 m, 127.728 rad/s).

use flexmbs_core::algebra::LinearSolver;
use flexmbs_core::integrator::{Statics, StaticsSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::{Joint, Load, LoadCoordinates, ModelSpec, NodeKind, TimeFunction, Workspace};
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use flexmbs_validate::rotating_beam_superelement::rotating_chain;
use nalgebra::{Matrix3, Vector3};
use std::time::Instant;

fn env_list(name: &str) -> Option<Vec<usize>> {
    std::env::var(name)
        .ok()
        .map(|v| v.split(',').filter_map(|s| s.trim().parse().ok()).collect())
}

fn dynamics(n: usize, solver: LinearSolver, h: f64, steps_cap: Option<usize>) {
    let mut c = rotating_chain(n, FrameLocation::CentreOfMass, solver).expect("model");
    let steps = steps_cap.unwrap_or((0.3 / h).round() as usize);
    let t_end = steps as f64 * h;
    let (mut iterations, mut taken) = (0usize, 0usize);
    let start = Instant::now();
    c.stepper
        .integrate(
            &c.model,
            &mut c.state,
            &mut c.workspace,
            h,
            t_end,
            |_, stats| {
                iterations += stats.iterations;
                taken += 1;
            },
        )
        .expect("integration");
    let wall = start.elapsed().as_secs_f64();
    println!(
        "dynamics  N = {n:2} {solver:?}: h = {h:.0e} s, {taken} steps ({t_end:.3} s): {wall:.3} s, {:.1} us/step, {:.2} Newton iterations/step",
        1e6 * wall / taken as f64,
        iterations as f64 / taken as f64
    );
}

fn statics(n: usize, solver: LinearSolver) {
    let mut spec = ModelSpec::new();
    let i3 = Matrix3::identity();
    let nodes: Vec<_> = (0..=n)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Pose))
        .collect();
    let l = 1.0 / n as f64;
    let mut bodies = Vec::new();
    for i in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: l,
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
        .expect("segment");
        let se = Superelement::new(data).expect("superelement");
        bodies.push(spec.add_body_on(&format!("b{i}"), se, &nodes[i..i + 2]));
    }
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), i3);
    let root = spec.add_node_owned_frame("root", nodes[0], Vector3::zeros(), i3);
    let tip = spec.add_node_owned_frame("tip", nodes[n], Vector3::zeros(), i3);
    spec.add_joint(Joint::fixed("clamp", ground, root));
    spec.add_load(Load::Force {
        frame: tip,
        vector: Vector3::new(0.0, -2500.0, 0.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile().expect("model");
    let mut s = model.initial_state();
    for (i, b) in bodies.iter().enumerate() {
        let x = (i as f64 + 0.5) * l;
        model.set_body_pose(&mut s, *b, Vector3::new(x, 0.0, 0.0), i3);
    }
    let mut ws = Workspace::with_linear_solver(&model, solver);
    let load_steps = 50;
    let st = Statics::new(StaticsSettings {
        load_steps,
        ..Default::default()
    });
    let start = Instant::now();
    let stats = st.solve(&model, &mut s, &mut ws).expect("statics");
    let wall = start.elapsed().as_secs_f64();
    let tip_y = model
        .frame_kinematics(&s, tip)
        .map_or(f64::NAN, |k| k.position.y);
    println!(
        "statics   N = {n:2} {solver:?}: {} load increments to 2500 N: {wall:.4} s, {:.1} us/increment, {:.2} Newton iterations/increment (tip y {tip_y:.5} m)",
        stats.increments,
        1e6 * wall / stats.increments as f64,
        stats.iterations as f64 / stats.increments as f64
    );
}

fn main() {
    let bodies = env_list("SE_BENCH_BODIES").unwrap_or(vec![10, 50]);
    let cap = env_list("SE_BENCH_STEPS").and_then(|v| v.first().copied());
    if let Ok(steps) = std::env::var("SE_BENCH_ACCURACY") {
        for h in steps
            .split(',')
            .filter_map(|x| x.trim().parse::<f64>().ok())
        {
            let (t, w) = flexmbs_validate::rotating_beam_superelement::simulate(
                10,
                FrameLocation::CentreOfMass,
                h,
                0.3,
            )
            .expect("run");
            let peak = flexmbs_validate::rotating_beam::first_peak(&w);
            let omega = flexmbs_validate::rotating_beam::omega_after_pulse(&t, &w);
            println!(
                "accuracy  N = 10: h = {h:.0e} s: first peak {peak:.6} m, omega {omega:?} rad/s"
            );
        }
        return;
    }
    if let Ok(only) = std::env::var("SE_BENCH_ONLY") {
        let (solver, h) = only.split_once('-').expect("SE_BENCH_ONLY=sparse-1e-4");
        let solver = if solver == "dense" {
            LinearSolver::Dense
        } else {
            LinearSolver::Sparse
        };
        for &n in &bodies {
            dynamics(n, solver, h.parse().expect("step"), cap);
        }
        return;
    }
    for &n in &bodies {
        for solver in [LinearSolver::Sparse, LinearSolver::Dense] {
            statics(n, solver);
        }
    }
    for &n in &bodies {
        for solver in [LinearSolver::Sparse, LinearSolver::Dense] {
            for h in [1e-4, 2e-5] {
                dynamics(n, solver, h, cap);
            }
        }
    }
}
