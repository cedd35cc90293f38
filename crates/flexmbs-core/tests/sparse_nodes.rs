//! The sparse backend on the node layer: bodies sharing pose nodes (element blocks added into the
//! same slots) and node-owned frames carrying joints, springs and forces follow the dense
//! trajectories; the block mass solver groups bodies that share nodes (DOPRI5 of a free body
//! split over two elements on one node matches free fall exactly).

use crate::common;
use flexmbs_core::algebra::{BlockMass, LinearSolver, SystemMatrix};
use flexmbs_core::integrator::{Dopri5, Dopri5Settings};
use flexmbs_core::linsolve::DenseLu;
use flexmbs_core::system;
use flexmbs_core::*;
use nalgebra::{Matrix3, Vector3};

/// Largest `|a_i - b_i|` relative to `max(1e-300, max |b|)`.
fn rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// A chain of `k` unit links, each a `PoseCardan` node carrying two rigid bodies (shared node),
/// hinged node frame to node frame (revolute joints on node-owned frames, the first to ground),
/// damped springs from a body frame of each link to a node frame of the next, a harmonic force
/// on the last node frame; horizontal at rest, under gravity.
fn node_chain(k: usize) -> (Model, State) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let id = Matrix3::identity();
    let mut prev = spec.add_ground_frame("ground", Vector3::zeros(), id);
    let mut first = Vec::new();
    let mut last_tip = prev;
    let mut spring_from: Option<FrameId> = None;
    for i in 0..k {
        let node = spec.add_node(&format!("n{i}"), NodeKind::PoseCardan);
        let ia = Matrix3::from_diagonal(&Vector3::new(0.01, 0.08, 0.08));
        let ib = Matrix3::from_diagonal(&Vector3::new(0.02, 0.05, 0.06));
        let a = spec.add_body_on(
            &format!("a{i}"),
            RigidBody::new(1.0 + 0.1 * i as f64, ia),
            &[node],
        );
        let b = spec.add_body_on(&format!("b{i}"), RigidBody::new(0.5, ib), &[node]);
        first.push(a);
        let top =
            spec.add_node_owned_frame(&format!("top{i}"), node, Vector3::new(-0.5, 0.0, 0.0), id);
        let tip =
            spec.add_node_owned_frame(&format!("tip{i}"), node, Vector3::new(0.5, 0.0, 0.0), id);
        spec.add_joint(Joint::revolute(&format!("hinge{i}"), prev, top));
        if let Some(from) = spring_from {
            spec.add_load(Load::SpringDamper {
                frame_a: from,
                frame_b: tip,
                stiffness: 50.0,
                damping: 0.5,
                free_length: 1.2,
            });
        }
        let fa = spec.add_frame(&format!("fa{i}"), a, Vector3::new(0.0, 0.2, 0.0), id);
        let fb = spec.add_frame(&format!("fb{i}"), b, Vector3::new(0.1, -0.1, 0.0), id);
        // a spring between the two bodies of one node: the same coordinates on both sides
        spec.add_load(Load::SpringDamper {
            frame_a: fa,
            frame_b: fb,
            stiffness: 20.0,
            damping: 0.2,
            free_length: 0.1,
        });
        spring_from = Some(fa);
        prev = tip;
        last_tip = tip;
    }
    spec.add_load(Load::Force {
        frame: last_tip,
        vector: Vector3::new(0.0, 0.0, 2.0),
        time: TimeFunction::Harmonic {
            amplitude: 1.0,
            frequency_hz: 2.0,
            phase: 0.0,
            offset: 0.0,
        },
        coordinates: LoadCoordinates::Frame,
    });
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    for (i, &a) in first.iter().enumerate() {
        let p = Vector3::new(i as f64 + 0.5, 0.0, 0.0);
        model.set_body_pose(&mut s, a, p, id);
    }
    (model, s)
}

/// Generalized-alpha with the sparse backend follows the dense trajectory of the shared-node
/// chain to 1e-10 (relative to the largest coordinate) on every step, full and modified Newton;
/// the chain swings (the check is not on a model at rest).
#[test]
fn sparse_trajectory_with_shared_nodes_and_node_frames_equals_dense() {
    let (model, s0) = node_chain(4);
    assert!(SystemMatrix::new(&model, LinearSolver::Sparse).is_sparse());
    for modified in [false, true] {
        let d = common::genalpha_trajectory(&model, &s0, LinearSolver::Dense, modified, 1e-3, 300);
        let sp =
            common::genalpha_trajectory(&model, &s0, LinearSolver::Sparse, modified, 1e-3, 300);
        let worst = d
            .iter()
            .zip(&sp)
            .map(|(a, b)| rel_diff(b, a))
            .fold(0.0, f64::max);
        let moved = rel_diff(d.last().unwrap(), &s0.q);
        println!("modified {modified}: worst step difference {worst:e}, motion {moved:e}");
        assert!(moved > 0.05, "the chain moves: {moved:e}");
        assert!(worst < 1e-10, "modified {modified}: {worst:e}");
    }
}

/// With shared nodes `M` is block diagonal over groups of bodies: the block Cholesky solve
/// equals a dense LU of the assembled `M` to 1e-12 relative (`cond_1(M)` of these links is
/// below 1e2).
#[test]
fn block_mass_with_shared_nodes_equals_dense_lu() {
    let (model, s) = node_chain(3);
    let nu = model.nu;
    let mut bm = BlockMass::new(&model);
    let mut ws = Workspace::new(&model);
    system::evaluate(&model, &s.q, &s.u, &mut ws.sys).unwrap();
    bm.update(&model, &s.q, &mut ws.sys.eval).unwrap();
    let mut lu = DenseLu::new(nu);
    let sys = &mut ws.sys;
    system::assemble_mass(&model, &s.q, &mut sys.eval, lu.a.as_mut(), &mut sys.local);
    assert!(lu.factor());
    let b: Vec<f64> = (0..nu).map(|i| (0.7 * i as f64).cos()).collect();
    let (mut x, mut y) = (b.clone(), b);
    bm.solve_in_place(&mut x, 1);
    lu.solve_in_place(&mut y);
    let e = rel_diff(&x, &y);
    println!("block Cholesky vs LU {e:e}");
    assert!(e < 1e-12, "{e:e}");
}

/// DOPRI5 on one free particle-like body split into two rigid elements on one pose node
/// (masses 1 and 3): free fall `x(t) = x0 + v0 t + g t^2 / 2` to 1e-10 at `t = 1` (the
/// polynomial is integrated exactly up to round-off). Solving the two elements' blocks one
/// after the other would give the acceleration `(m1 + m2) g / (m1 m2)`, 1.33 g.
#[test]
fn dopri5_with_shared_node_is_free_fall() {
    let mut spec = ModelSpec::new();
    let g = Vector3::new(0.0, -9.81, 0.0);
    spec.set_gravity(g);
    let node = spec.add_node("n", NodeKind::PoseCardan);
    let inertia = Matrix3::identity() * 0.1;
    let a = spec.add_body_on("a", RigidBody::new(1.0, inertia), &[node]);
    spec.add_body_on("b", RigidBody::new(3.0, inertia), &[node]);
    let model = spec.compile().unwrap();
    let mut s = model.initial_state();
    let v0 = Vector3::new(1.0, 2.0, -0.5);
    model.set_body_velocity(&mut s, a, v0, Vector3::zeros());
    let mut ws = Workspace::new(&model);
    let dp = Dopri5::new(Dopri5Settings::default());
    dp.integrate(&model, &mut s, &mut ws, 1.0, |_, _| {})
        .unwrap();
    let x = v0 + 0.5 * g;
    let e = (Vector3::new(s.q[0], s.q[1], s.q[2]) - x).norm();
    println!("free fall error {e:e}");
    assert!(e < 1e-10, "{e:e}");
}
