//! Cost of gathering scattered coordinates (issue 8 item 1): a clamped chain of N superelements
//! (the tube of `cantilever_static`, 2 FE beam elements and 1 internal mode each) under gravity
//! and a tip load, its nodes added root to tip (every superelement contiguous, the zero-copy
//! path) or in a shuffled order (every superelement scattered: gathered, scatter-added), the
//! same model otherwise. Generalized-alpha rho_inf 0.9, full Newton, h = 1e-4 s.
//!
//! Run: `cargo bench -p flexmbs-validate --bench scattered_chain`; environment
//! `SCATTER_BENCH_N` (chain length, default 20), `SCATTER_BENCH_STEPS` (default 200),
//! `SCATTER_BENCH_ORDER=ordered|shuffled|both` (default both), `SCATTER_BENCH_SOLVER=dense|sparse`
//! (default: automatic). Prints wall time per step and the tip deflection (equal for both
//! orders). Not a test: nothing is asserted. Under callgrind use
//! `--toggle-collect='*GenAlpha::step'` for the instructions of the steps alone.

use flexmbs_core::algebra::LinearSolver;
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings};
use flexmbs_core::superelement::{beam_segment, BeamSegmentSpec, FrameLocation, Superelement};
use flexmbs_core::*;
use flexmbs_fe::mesh::{BeamSection, BeamTheory};
use flexmbs_fe::Material;
use nalgebra::{Matrix3, Vector3};
use std::time::Instant;

fn env(name: &str) -> Option<String> {
    std::env::var(name).ok()
}

/// The chain of `n` superelements, its nodes added in the order `order` (indices 0..2n+1:
/// interface point `k` is `2k`, the internal-mode node of superelement `k` is `2k + 1`).
fn chain(n: usize, order: &[usize]) -> (Model, State, FrameId) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let mut nodes = vec![NodeId(usize::MAX); 2 * n + 1];
    for &i in order {
        let kind = if i % 2 == 0 {
            NodeKind::Pose
        } else {
            NodeKind::Vector(1)
        };
        nodes[i] = spec.add_node(&format!("n{i}"), kind);
    }
    let mut bodies = Vec::new();
    for k in 0..n {
        let data = beam_segment(&BeamSegmentSpec {
            length: 1.0 / n as f64,
            material: Material {
                e: 70e9,
                nu: 0.3,
                rho: 2700.0,
            },
            section: BeamSection::tube(0.01, 0.001),
            theory: BeamTheory::EulerBernoulli,
            elements: 2,
            internal_modes: 1,
            frame: FrameLocation::CentreOfMass,
        })
        .unwrap();
        let se = Superelement::new(data).unwrap();
        let on = [nodes[2 * k], nodes[2 * k + 1], nodes[2 * k + 2]];
        bodies.push(spec.add_body_on(&format!("s{k}"), se, &on));
    }
    let id = Matrix3::identity();
    let ground = spec.add_ground_frame("clamp", Vector3::zeros(), id);
    let root = spec.add_node_owned_frame("root", nodes[0], Vector3::zeros(), id);
    let tip = spec.add_node_owned_frame("tip", nodes[2 * n], Vector3::zeros(), id);
    spec.add_joint(Joint::fixed("clamp", ground, root));
    spec.add_load(Load::Force {
        frame: tip,
        vector: Vector3::new(0.0, -20.0, 5.0),
        time: TimeFunction::Constant(1.0),
        coordinates: LoadCoordinates::Global,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    for (k, b) in bodies.iter().enumerate() {
        let x = (k as f64 + 0.5) / n as f64;
        model.set_body_pose(&mut s, *b, Vector3::new(x, 0.0, 0.0), id);
    }
    (model, s, tip)
}

/// A fixed permutation of `0..m` that separates neighbours (stride coprime to `m`).
fn shuffled(m: usize) -> Vec<usize> {
    let stride = (2..m).find(|s| gcd(*s, m) == 1 && *s * *s > m).unwrap_or(1);
    (0..m).map(|i| (i * stride + 3) % m).collect()
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

fn main() {
    let n: usize = env("SCATTER_BENCH_N")
        .and_then(|v| v.parse().ok())
        .unwrap_or(20);
    let steps: usize = env("SCATTER_BENCH_STEPS")
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let which = env("SCATTER_BENCH_ORDER").unwrap_or_else(|| "both".into());
    let solver = match env("SCATTER_BENCH_SOLVER").as_deref() {
        Some("dense") => LinearSolver::Dense,
        Some("sparse") => LinearSolver::Sparse,
        _ => LinearSolver::Auto,
    };
    let m = 2 * n + 1;
    for (name, order) in [("ordered", (0..m).collect()), ("shuffled", shuffled(m))] {
        if which != "both" && which != name {
            continue;
        }
        let (model, mut s, tip) = chain(n, &order);
        let scattered = model.bodies.iter().filter(|b| b.is_scattered()).count();
        let mut ws = Workspace::with_linear_solver(&model, solver);
        let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        let t0 = Instant::now();
        for _ in 0..steps {
            ga.step(&model, &mut s, &mut ws, 1e-4).unwrap();
        }
        let us = t0.elapsed().as_secs_f64() * 1e6 / steps as f64;
        let y = model.frame_kinematics(&s, tip).unwrap().position.y;
        println!(
            "{name}: N = {n}, {scattered} scattered bodies, {:?}: {us:.1} us/step, tip y {y:.12e}",
            ws.saddle.is_sparse()
        );
    }
}
