//! Bodies sharing nodes (coordinates shared without constraints): two point masses on one node are
//! one particle of mass m1 + m2; a chain of two-node spring elements sharing nodes equals the same
//! chain built from spring-damper loads; a frame on an element whose Jacobian spans two nodes
//! matches finite differences.

use faer::Mat;
use flexmbs_core::integrator::{GenAlpha, GenAlphaSettings, NewtonSettings};
use flexmbs_core::point_mass::PointMass;
use flexmbs_core::system::{evaluate, integrate_positions};
use flexmbs_core::{Joint, Load, ModelSpec, NodeKind, State, Workspace};
use nalgebra::{Matrix3, Vector3};

use crate::spring_element;
use spring_element::Spring;

fn tight() -> GenAlphaSettings {
    GenAlphaSettings {
        rho_inf: 0.9,
        newton: NewtonSettings {
            rtol: 1e-14,
            atol: 1e-14,
            ..NewtonSettings::default()
        },
    }
}

/// Two point masses on one node: the assembled mass is `(m1 + m2) I`, free fall is exact
/// (`z = -g t^2 / 2`), and on a spring to ground the node oscillates with
/// `omega = sqrt(k / (m1 + m2))`.
#[test]
fn two_point_masses_on_one_node_are_one_particle() {
    let (m1, m2, k, g) = (0.7, 1.8, 250.0, 9.81);
    for spring in [false, true] {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, 0.0, if spring { 0.0 } else { -g }));
        let node = spec.add_node("p", NodeKind::Vector(3));
        let a = spec.add_body_on("a", PointMass::new(m1), &[node]);
        let b = spec.add_body_on("b", PointMass::new(m2), &[node]);
        if spring {
            let fa = spec.add_frame("fa", a, Vector3::zeros(), Matrix3::identity());
            let g0 = spec.add_ground_frame("g0", Vector3::zeros(), Matrix3::identity());
            spec.add_load(Load::SpringDamper {
                frame_a: g0,
                frame_b: fa,
                stiffness: k,
                damping: 0.0,
                free_length: 0.0,
            });
        }
        let model = spec.compile().unwrap();
        assert_eq!((model.nq, model.nu), (3, 3));
        assert_eq!(model.body_dofs(a), model.body_dofs(b));
        let mut s = model.initial_state();
        let x0 = 0.05;
        if spring {
            s.q[0] = x0;
        }
        let mut ws = Workspace::new(&model);
        let ga = GenAlpha::new(tight()).unwrap();
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        let sys = &mut ws.sys;
        flexmbs_core::system::evaluate(&model, &s.q, &s.u, sys).unwrap();
        flexmbs_core::system::assemble_mass(
            &model,
            &s.q,
            &mut sys.eval,
            sys.mass.as_mut(),
            &mut sys.local,
        );
        let mut expected = Mat::<f64>::zeros(3, 3);
        for i in 0..3 {
            expected[(i, i)] = m1 + m2;
        }
        assert_eq!(ws.sys.mass, expected);
        let h = 1e-4;
        let mut samples = Vec::new();
        ga.integrate(&model, &mut s, &mut ws, h, 0.5, |st, _| {
            samples.push((st.t, st.q[0], st.q[2]))
        })
        .unwrap();
        if spring {
            // x(t) = x0 cos(omega t); generalized-alpha lengthens the period by O((omega h)^2)
            let omega = (k / (m1 + m2)).sqrt();
            for &(t, x, _) in &samples {
                assert!((x - x0 * (omega * t).cos()).abs() < 2e-4 * x0, "t {t}: {x}");
            }
        } else {
            for &(t, _, z) in &samples {
                assert!((z + 0.5 * g * t * t).abs() < 1e-10, "t {t}: {z}");
            }
        }
    }
}

/// A pendulum chain of `N` point masses hung from ground by a spherical joint, coupled by (a)
/// spring elements sharing the mass nodes, (b) spring-damper loads between frames of separate
/// bodies: the same trajectory to 1e-12.
#[test]
fn spring_element_chain_equals_spring_damper_loads() {
    const N: usize = 5;
    let (k, d, l0, m) = (400.0, 0.3, 0.1, 0.2);
    let build = |elements: bool| {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
        let mut bodies = Vec::new();
        let mut nodes = Vec::new();
        for i in 0..=N {
            let node = spec.add_node(&format!("n{i}"), NodeKind::Vector(3));
            nodes.push(node);
            bodies.push(spec.add_body_on(&format!("m{i}"), PointMass::new(m), &[node]));
        }
        let frames: Vec<_> = bodies
            .iter()
            .map(|&b| spec.add_frame("f", b, Vector3::zeros(), Matrix3::identity()))
            .collect();
        for i in 0..N {
            if elements {
                let spring = Spring {
                    stiffness: k,
                    damping: d,
                    free_length: l0,
                };
                spec.add_body_on(&format!("s{i}"), spring, &[nodes[i], nodes[i + 1]]);
            } else {
                spec.add_load(Load::SpringDamper {
                    frame_a: frames[i],
                    frame_b: frames[i + 1],
                    stiffness: k,
                    damping: d,
                    free_length: l0,
                });
            }
        }
        let g0 = spec.add_ground_frame("g0", Vector3::zeros(), Matrix3::identity());
        spec.add_joint(Joint::spherical("hang", g0, frames[0]));
        spec.compile().unwrap()
    };
    let run = |elements: bool| -> Vec<State> {
        let model = build(elements);
        let mut s = model.initial_state();
        for i in 0..=N {
            // a bent chain along x, one mass slightly out of plane
            s.q[3 * i] = 0.12 * i as f64;
            s.q[3 * i + 1] = -0.01 * (i * i) as f64;
            s.q[3 * i + 2] = if i == 3 { 0.02 } else { 0.0 };
        }
        let mut ws = Workspace::new(&model);
        let ga = GenAlpha::new(tight()).unwrap();
        ga.initialize(&model, &mut s, &mut ws).unwrap();
        let mut out = Vec::new();
        ga.integrate(&model, &mut s, &mut ws, 1e-3, 0.3, |st, _| {
            out.push(st.clone())
        })
        .unwrap();
        out
    };
    let (a, b) = (run(true), run(false));
    assert_eq!(a.len(), b.len());
    let mut worst: f64 = 0.0;
    for (sa, sb) in a.iter().zip(&b) {
        for (x, y) in sa.q.iter().zip(&sb.q).chain(sa.u.iter().zip(&sb.u)) {
            worst = worst.max((x - y).abs());
        }
    }
    let moved = (a.last().unwrap().q[3 * N] - 0.12 * N as f64).abs();
    assert!(moved > 1e-2, "the chain moves: {moved}");
    assert!(worst < 1e-12, "elements vs loads: max difference {worst:e}");
}

/// A frame at `xi = 0.3` of a spring element between two nodes: its Jacobian spans both nodes'
/// columns (`Model::frame_cols`) and equals central differences of its position along `q ⊕ dv`.
#[test]
fn frame_spanning_two_nodes_matches_finite_differences() {
    let mut spec = ModelSpec::new();
    let n: Vec<_> = (0..3)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Vector(3)))
        .collect();
    for (i, &node) in n.iter().enumerate() {
        spec.add_body_on(&format!("m{i}"), PointMass::new(1.0), &[node]);
    }
    let spring = Spring {
        stiffness: 1.0,
        damping: 0.0,
        free_length: 0.0,
    };
    let s = spec.add_body_on("s", spring, &[n[1], n[2]]);
    let f = spec.add_frame("mid", s, Vector3::new(0.3, 0.0, 0.0), Matrix3::identity());
    let model = spec.compile().unwrap();
    let cols = model.frame_cols(f);
    assert_eq!(cols.iter().collect::<Vec<_>>(), (3..9).collect::<Vec<_>>());
    let q: Vec<f64> = (0..model.nq).map(|i| (i as f64 * 0.7).sin()).collect();
    let u = vec![0.0; model.nu];
    let mut sys = Workspace::new(&model).sys;
    evaluate(&model, &q, &u, &mut sys).unwrap();
    let jac = sys.frames[f.index()].jac_t.clone();
    let (mut qp, eps) = (q.clone(), 1e-6);
    for j in 0..model.nu {
        let mut dv = vec![0.0; model.nu];
        let mut pos = [Vector3::zeros(); 2];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            dv[j] = sign * eps;
            integrate_positions(&model, &q, &dv, &mut qp);
            evaluate(&model, &qp, &u, &mut sys).unwrap();
            pos[k] = sys.frames[f.index()].position;
        }
        let fd = (pos[0] - pos[1]) / (2.0 * eps);
        let analytic = match (0..6).find(|&c| cols.global(c) == j) {
            Some(c) => Vector3::new(jac[(0, c)], jac[(1, c)], jac[(2, c)]),
            None => Vector3::zeros(),
        };
        assert!(
            (fd - analytic).norm() < 1e-9,
            "column {j}: {fd} vs {analytic}"
        );
    }
}

/// A frame owned by the node of a rigid body (`add_node_owned_frame`) is the body's frame at the
/// same offset: the same pendulum trajectory (hinge and a follower force on it), bitwise, for
/// Cardan and quaternion nodes; a modal `Vector(n)` node carries no frames.
#[test]
fn node_owned_frame_equals_body_frame() {
    use flexmbs_core::{LoadCoordinates, RigidBody, RotationParam, TimeFunction};
    for (rot, kind) in [
        (RotationParam::Cardan, NodeKind::PoseCardan),
        (RotationParam::Quaternion, NodeKind::Pose),
    ] {
        let run = |on_node: bool| {
            let mut spec = ModelSpec::new();
            spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
            let inertia = Matrix3::from_diagonal(&Vector3::new(0.02, 0.001, 0.02));
            let node = spec.add_node("rod", kind);
            let rod = spec.add_body_on(
                "rod",
                RigidBody::new(1.0, inertia).with_rotation(rot),
                &[node],
            );
            let (top, tip) = (Vector3::new(0.0, 0.5, 0.0), Vector3::new(0.0, -0.5, 0.1));
            let (ft, fp) = if on_node {
                (
                    spec.add_node_owned_frame("top", node, top, Matrix3::identity()),
                    spec.add_node_owned_frame("tip", node, tip, Matrix3::identity()),
                )
            } else {
                (
                    spec.add_frame("top", rod, top, Matrix3::identity()),
                    spec.add_frame("tip", rod, tip, Matrix3::identity()),
                )
            };
            let g = spec.add_ground_frame("g", Vector3::zeros(), Matrix3::identity());
            spec.add_joint(Joint::revolute("hinge", g, ft));
            spec.add_load(Load::Force {
                frame: fp,
                vector: Vector3::new(0.3, 0.0, 0.2),
                time: TimeFunction::Constant(1.0),
                coordinates: LoadCoordinates::Frame,
            });
            let model = spec.compile().unwrap();
            let mut s = model.initial_state();
            model.set_body_pose(
                &mut s,
                rod,
                Vector3::new(0.0, -0.5, 0.0),
                Matrix3::identity(),
            );
            let mut ws = Workspace::new(&model);
            let ga = GenAlpha::new(GenAlphaSettings::default()).unwrap();
            ga.initialize(&model, &mut s, &mut ws).unwrap();
            let mut out = Vec::new();
            ga.integrate(&model, &mut s, &mut ws, 1e-3, 0.5, |st, _| {
                out.push(st.clone())
            })
            .unwrap();
            out
        };
        let (a, b) = (run(true), run(false));
        assert!((a.last().unwrap().q[0]).abs() > 1e-3, "it swings");
        assert_eq!(a, b, "{rot:?}");
    }
    let mut spec = ModelSpec::new();
    let modal = spec.add_node("modes", NodeKind::Vector(2));
    spec.add_node_owned_frame("bad", modal, Vector3::zeros(), Matrix3::identity());
    let err = spec.compile().unwrap_err().to_string();
    assert!(err.contains("carries no frames"), "{err}");
}

/// Constraint Jacobian rows between frames whose owners share coordinates (a node-owned frame and
/// a body frame on the same node, two bodies sharing a node) equal central differences of the
/// constraint values along `q ⊕ dv`.
#[test]
fn constraint_jacobian_with_shared_owners_matches_finite_differences() {
    use flexmbs_core::system::assemble_constraints;
    use flexmbs_core::RigidBody;
    let mut spec = ModelSpec::new();
    let inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3));
    let node = spec.add_node("n", NodeKind::Pose);
    let a = spec.add_body_on(
        "a",
        RigidBody::new(1.0, inertia).with_rotation(flexmbs_core::RotationParam::Quaternion),
        &[node],
    );
    let c = spec.add_body("c", RigidBody::new(1.0, inertia));
    let fn1 =
        spec.add_node_owned_frame("n1", node, Vector3::new(0.2, 0.1, 0.0), Matrix3::identity());
    let fa = spec.add_frame("a1", a, Vector3::new(-0.1, 0.3, 0.2), Matrix3::identity());
    let fc = spec.add_frame("c1", c, Vector3::new(0.0, 0.1, -0.2), Matrix3::identity());
    spec.add_joint(Joint::revolute("node-body", fn1, fa));
    spec.add_joint(Joint::revolute("node-other", fn1, fc));
    spec.add_joint(Joint::spherical("body-other", fa, fc));
    let model = spec.compile().unwrap();
    let s0 = model.initial_state();
    let dv: Vec<f64> = (0..model.nu)
        .map(|i| 0.4 * (i as f64 * 1.3 + 0.2).sin())
        .collect();
    let mut q = s0.q.clone();
    integrate_positions(&model, &s0.q, &dv, &mut q);
    let u = vec![0.0; model.nu];
    let mut sys = Workspace::new(&model).sys;
    let eval = |q: &[f64], sys: &mut flexmbs_core::state::SystemBuffers| {
        evaluate(&model, q, &u, sys).unwrap();
        assemble_constraints(
            &model,
            0.0,
            &sys.frames,
            &mut sys.g,
            sys.g_jac.as_mut(),
            &mut sys.g_t,
            &mut sys.g_bias,
        );
    };
    eval(&q, &mut sys);
    let g_jac = sys.g_jac.clone();
    let (mut qp, eps) = (q.clone(), 1e-6);
    for j in 0..model.nu {
        let mut dvj = vec![0.0; model.nu];
        let mut g = [vec![], vec![]];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            dvj[j] = sign * eps;
            integrate_positions(&model, &q, &dvj, &mut qp);
            eval(&qp, &mut sys);
            g[k] = sys.g.clone();
        }
        for r in 0..model.nc {
            let fd = (g[0][r] - g[1][r]) / (2.0 * eps);
            assert!(
                (fd - g_jac[(r, j)]).abs() < 1e-8,
                "row {r} column {j}: {fd} vs {}",
                g_jac[(r, j)]
            );
        }
    }
}
