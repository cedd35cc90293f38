//! Bodies whose nodes are not consecutive in the global layout (scattered coordinate maps,
//! gathered and scatter-added): a ring of spring elements closed onto its first node equals the
//! same ring of spring-damper loads (generalized-alpha, DOPRI5, statics; dense and sparse); a
//! chain whose nodes were added in a shuffled order equals the ordered chain; a frame on a
//! scattered element has the Jacobian and constraint rows of finite differences.

use crate::spring_element;

use flexmbs_core::algebra::LinearSolver;
use flexmbs_core::integrator::{
    Dopri5, Dopri5Settings, GenAlpha, GenAlphaSettings, NewtonSettings, Statics, StaticsSettings,
};
use flexmbs_core::point_mass::PointMass;
use flexmbs_core::system::{assemble_constraints, evaluate, integrate_positions};
use flexmbs_core::{
    Joint, Load, LoadCoordinates, Model, ModelSpec, NodeId, NodeKind, State, TimeFunction,
    Workspace,
};
use nalgebra::{Matrix3, Vector3};
use spring_element::Spring;

const N: usize = 6;
const MASS: f64 = 0.3;
const K_RING: f64 = 300.0;
const D_RING: f64 = 0.4;
const K_GROUND: f64 = 40.0;
/// Frame position on the closing (scattered) spring element, as a fraction of its length.
const XI: f64 = 0.3;
const FORCE: [f64; 3] = [0.4, -0.2, 0.7];

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

/// Ring position of mass `i` (a tilted, slightly irregular hexagon).
fn ring_point(i: usize) -> Vector3<f64> {
    let a = 2.0 * std::f64::consts::PI * i as f64 / N as f64;
    let r = 0.5 + 0.03 * (i as f64).sin();
    Vector3::new(r * a.cos(), r * a.sin(), 0.05 * (2.0 * a).sin())
}

/// A ring of `N` point masses, each held by a zero-length spring to its ring point, coupled
/// around the ring (free length 0.9 of the chord: pre-stressed) by spring elements on the mass
/// nodes (the last one closes onto node 0: scattered) or by spring-damper loads; a constant force
/// at `XI` along the closing spring, or its two shares on the masses.
fn ring(elements: bool) -> (Model, Vec<NodeId>) {
    let mut spec = ModelSpec::new();
    spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
    let id = Matrix3::identity();
    let nodes: Vec<NodeId> = (0..N)
        .map(|i| spec.add_node(&format!("n{i}"), NodeKind::Vector(3)))
        .collect();
    let masses: Vec<_> = (0..N)
        .map(|i| spec.add_body_on(&format!("m{i}"), PointMass::new(MASS), &[nodes[i]]))
        .collect();
    let frames: Vec<_> = masses
        .iter()
        .enumerate()
        .map(|(i, &b)| spec.add_frame(&format!("f{i}"), b, Vector3::zeros(), id))
        .collect();
    for (i, &f) in frames.iter().enumerate() {
        let g = spec.add_ground_frame(&format!("g{i}"), ring_point(i), id);
        spec.add_load(Load::SpringDamper {
            frame_a: g,
            frame_b: f,
            stiffness: K_GROUND,
            damping: 0.0,
            free_length: 0.0,
        });
    }
    let force = |spec: &mut ModelSpec, frame, share: f64| {
        spec.add_load(Load::Force {
            frame,
            vector: Vector3::from(FORCE) * share,
            time: TimeFunction::Constant(1.0),
            coordinates: LoadCoordinates::Global,
        });
    };
    for i in 0..N {
        let j = (i + 1) % N;
        let free_length = 0.9 * (ring_point(j) - ring_point(i)).norm();
        if elements {
            let spring = Spring {
                stiffness: K_RING,
                damping: D_RING,
                free_length,
            };
            let s = spec.add_body_on(&format!("s{i}"), spring, &[nodes[i], nodes[j]]);
            if j == 0 {
                let f = spec.add_frame("on_closing", s, Vector3::new(XI, 0.0, 0.0), id);
                force(&mut spec, f, 1.0);
            }
        } else {
            spec.add_load(Load::SpringDamper {
                frame_a: frames[i],
                frame_b: frames[j],
                stiffness: K_RING,
                damping: D_RING,
                free_length,
            });
            if j == 0 {
                force(&mut spec, frames[i], 1.0 - XI);
                force(&mut spec, frames[j], XI);
            }
        }
    }
    (spec.compile().unwrap(), nodes)
}

/// The ring at its ring points, mass `i` displaced and moving.
fn ring_start(model: &Model, nodes: &[NodeId]) -> State {
    let mut s = model.initial_state();
    for (i, n) in nodes.iter().enumerate() {
        let r = model.nodes[n.0].q.clone();
        let p = ring_point(i) + Vector3::new(0.02, -0.01 * i as f64, 0.015 * (i % 2) as f64);
        s.q[r.clone()].copy_from_slice(p.as_slice());
        s.u[r.start] = 0.1 * (i as f64).cos();
    }
    s
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Positions and velocities of the nodes `nodes` of state `s`, in node order.
fn node_values(model: &Model, nodes: &[NodeId], s: &State) -> Vec<f64> {
    let mut out = Vec::new();
    for n in nodes {
        let node = &model.nodes[n.0];
        out.extend_from_slice(&s.q[node.q.clone()]);
        out.extend_from_slice(&s.u[node.u.clone()]);
    }
    out
}

fn genalpha_run(
    model: &Model,
    s0: &State,
    choice: LinearSolver,
    nodes: &[NodeId],
) -> Vec<Vec<f64>> {
    let mut s = s0.clone();
    let mut ws = Workspace::with_linear_solver(model, choice);
    let ga = GenAlpha::new(tight()).unwrap();
    ga.initialize(model, &mut s, &mut ws).unwrap();
    let mut out = vec![node_values(model, nodes, &s)];
    ga.integrate(model, &mut s, &mut ws, 1e-3, 0.4, |st, _| {
        out.push(node_values(model, nodes, st))
    })
    .unwrap();
    out
}

fn worst(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| max_diff(x, y))
        .fold(0.0, f64::max)
}

/// The closing spring element lives on nodes `n5`, `n0`: a scattered coordinate map.
#[test]
fn closing_element_of_a_ring_has_a_scattered_map() {
    let (model, _) = ring(true);
    let closing = model.body_id(&format!("s{}", N - 1)).unwrap();
    let dofs = model.body_dofs(closing);
    assert_eq!(dofs.u.as_range(), None);
    let cols: Vec<usize> = dofs.u.iter().collect();
    let last = 3 * (N - 1);
    assert_eq!(cols, vec![last, last + 1, last + 2, 0, 1, 2]);
    assert!(model.bodies[closing.0].is_scattered());
    let first = model.body_id("s0").unwrap();
    assert!(!model.bodies[first.0].is_scattered());
}

/// Generalized-alpha (dense and sparse backend): the ring of spring elements follows the ring of
/// spring-damper loads to 1e-12 over 0.4 s (400 steps), and the two backends agree to 1e-10.
#[test]
fn ring_of_spring_elements_equals_spring_damper_loads_generalized_alpha() {
    let (me, nodes_e) = ring(true);
    let (ml, nodes_l) = ring(false);
    let (se, sl) = (ring_start(&me, &nodes_e), ring_start(&ml, &nodes_l));
    let ref_loads = genalpha_run(&ml, &sl, LinearSolver::Dense, &nodes_l);
    let dense = genalpha_run(&me, &se, LinearSolver::Dense, &nodes_e);
    let sparse = genalpha_run(&me, &se, LinearSolver::Sparse, &nodes_e);
    let moved = max_diff(&ref_loads[0], ref_loads.last().unwrap());
    assert!(moved > 1e-2, "the ring moves: {moved}");
    let (d_loads, d_backend) = (worst(&dense, &ref_loads), worst(&sparse, &dense));
    println!("elements vs loads {d_loads:e}, sparse vs dense {d_backend:e}");
    assert!(d_loads < 1e-12, "elements vs loads: {d_loads:e}");
    assert!(d_backend < 1e-10, "sparse vs dense: {d_backend:e}");
}

/// DOPRI5 (the mass solved by block Cholesky: the zero-mass springs join all masses into one
/// block through the scattered element): the ring of elements equals the ring of loads to 1e-12
/// after 0.3 s.
#[test]
fn ring_of_spring_elements_equals_spring_damper_loads_dopri5() {
    let run = |elements: bool| {
        let (model, nodes) = ring(elements);
        let mut s = ring_start(&model, &nodes);
        let mut ws = Workspace::new(&model);
        let d = Dopri5::new(Dopri5Settings {
            rtol: 1e-10,
            atol: 1e-10,
            ..Default::default()
        });
        let mut steps = 0;
        d.integrate(&model, &mut s, &mut ws, 0.3, |_, _| steps += 1)
            .unwrap();
        (node_values(&model, &nodes, &s), steps)
    };
    let ((a, na), (b, nb)) = (run(true), run(false));
    let d = max_diff(&a, &b);
    println!("DOPRI5 elements vs loads {d:e} ({na} / {nb} outputs)");
    assert_eq!(na, nb);
    assert!(d < 1e-12, "{d:e}");
}

/// Statics under gravity and the force: the same equilibrium to 1e-12 (m).
#[test]
fn ring_of_spring_elements_equals_spring_damper_loads_statics() {
    let statics = Statics::new(StaticsSettings {
        force_tol: 1e-13,
        ..Default::default()
    });
    let solve = |elements: bool, choice: LinearSolver| {
        let (model, nodes) = ring(elements);
        let mut s = ring_start(&model, &nodes);
        s.u.fill(0.0);
        let mut ws = Workspace::with_linear_solver(&model, choice);
        statics.solve(&model, &mut s, &mut ws).unwrap();
        node_values(&model, &nodes, &s)
    };
    let loads = solve(false, LinearSolver::Dense);
    let sag = (loads[1] - ring_point(0).y).abs();
    assert!(sag > 1e-3, "gravity deflects the ring: {sag}");
    for choice in [LinearSolver::Dense, LinearSolver::Sparse] {
        let d = max_diff(&solve(true, choice), &loads);
        println!("statics {choice:?}: elements vs loads {d:e}");
        assert!(d < 1e-12, "{choice:?}: {d:e}");
    }
}

/// A pendulum chain of point masses and spring elements hanging from ground, its nodes added in
/// a shuffled order (every spring element scattered or reversed) or in chain order: the same
/// trajectory node by node to 1e-12.
#[test]
fn shuffled_chain_equals_ordered_chain() {
    const M: usize = 6;
    let build = |order: &[usize]| {
        let mut spec = ModelSpec::new();
        spec.set_gravity(Vector3::new(0.0, -9.81, 0.0));
        let mut nodes = vec![NodeId(usize::MAX); M + 1];
        for &i in order {
            nodes[i] = spec.add_node(&format!("n{i}"), NodeKind::Vector(3));
        }
        let masses: Vec<_> = (0..=M)
            .map(|i| spec.add_body_on(&format!("m{i}"), PointMass::new(0.2), &[nodes[i]]))
            .collect();
        for i in 0..M {
            let spring = Spring {
                stiffness: 400.0,
                damping: 0.3,
                free_length: 0.1,
            };
            spec.add_body_on(&format!("s{i}"), spring, &[nodes[i], nodes[i + 1]]);
        }
        let f0 = spec.add_frame("f0", masses[0], Vector3::zeros(), Matrix3::identity());
        let g0 = spec.add_ground_frame("g0", Vector3::zeros(), Matrix3::identity());
        spec.add_joint(Joint::spherical("hang", g0, f0));
        let model = spec.compile().unwrap();
        let mut s = model.initial_state();
        for (i, n) in nodes.iter().enumerate() {
            let r = model.nodes[n.0].q.clone();
            let p = [
                0.12 * i as f64,
                -0.01 * (i * i) as f64,
                if i == 3 { 0.02 } else { 0.0 },
            ];
            s.q[r].copy_from_slice(&p);
        }
        (model, s, nodes)
    };
    let (mo, so, no) = build(&(0..=M).collect::<Vec<_>>());
    let (ms, ss, ns) = build(&[3, 0, 6, 1, 5, 2, 4]);
    let scattered = ms.bodies.iter().filter(|b| b.is_scattered()).count();
    assert!(scattered >= 4, "{scattered} scattered bodies");
    assert!(mo.bodies.iter().all(|b| !b.is_scattered()));
    for choice in [LinearSolver::Dense, LinearSolver::Sparse] {
        let a = genalpha_run(&mo, &so, choice, &no);
        let b = genalpha_run(&ms, &ss, choice, &ns);
        let moved = max_diff(&a[0], a.last().unwrap());
        assert!(moved > 1e-2, "the chain moves: {moved}");
        let d = worst(&a, &b);
        println!("{choice:?}: shuffled vs ordered {d:e}");
        assert!(d < 1e-12, "{choice:?}: {d:e}");
    }
}

/// A frame at `XI` on a spring element on nodes `n2`, `n0` (node `n1` between them): its
/// Jacobian has the scattered columns and equals central differences of its position along
/// `q ⊕ dv`; the rows of a spherical joint to ground on it equal differences of `g`.
#[test]
fn frame_on_scattered_element_matches_finite_differences() {
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
    let s = spec.add_body_on("s", spring, &[n[2], n[0]]);
    let id = Matrix3::identity();
    let f = spec.add_frame("mid", s, Vector3::new(XI, 0.0, 0.0), id);
    let g = spec.add_ground_frame("g", Vector3::new(0.1, 0.2, 0.3), id);
    spec.add_joint(Joint::spherical("pin", g, f));
    let model = spec.compile().unwrap();
    let cols: Vec<usize> = model.frame_cols(f).iter().collect();
    assert_eq!(cols, vec![6, 7, 8, 0, 1, 2]);
    let q: Vec<f64> = (0..model.nq).map(|i| (i as f64 * 0.7).sin()).collect();
    let u = vec![0.0; model.nu];
    let mut sys = Workspace::new(&model).sys;
    let constraints = |q: &[f64], sys: &mut flexmbs_core::state::SystemBuffers| {
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
    constraints(&q, &mut sys);
    let (jac, g_jac) = (sys.frames[f.index()].jac_t.clone(), sys.g_jac.clone());
    let (mut qp, eps) = (q.clone(), 1e-6);
    for j in 0..model.nu {
        let mut dv = vec![0.0; model.nu];
        let mut pos = [Vector3::zeros(); 2];
        let mut g = [[0.0; 3]; 2];
        for (k, sign) in [1.0, -1.0].into_iter().enumerate() {
            dv[j] = sign * eps;
            integrate_positions(&model, &q, &dv, &mut qp);
            constraints(&qp, &mut sys);
            pos[k] = sys.frames[f.index()].position;
            g[k].copy_from_slice(&sys.g[..3]);
        }
        let fd = (pos[0] - pos[1]) / (2.0 * eps);
        let analytic = match cols.iter().position(|&c| c == j) {
            Some(c) => Vector3::new(jac[(0, c)], jac[(1, c)], jac[(2, c)]),
            None => Vector3::zeros(),
        };
        assert!(
            (fd - analytic).norm() < 1e-9,
            "column {j}: {fd} vs {analytic}"
        );
        let expected = if j < 3 {
            XI
        } else if j >= 6 {
            1.0 - XI
        } else {
            0.0
        };
        assert!((analytic.norm() - expected).abs() < 1e-14, "column {j}");
        for r in 0..3 {
            let fd_g = (g[0][r] - g[1][r]) / (2.0 * eps);
            assert!((fd_g - g_jac[(r, j)]).abs() < 1e-9, "G ({r}, {j})");
        }
    }
}

/// Initial-state setters and the element-local view of a scattered body: `set_body_pose` of a
/// point mass and `body_coordinates` of the closing spring read and write through the map.
#[test]
fn scattered_body_coordinates_read_through_the_map() {
    let (model, nodes) = ring(true);
    let s = ring_start(&model, &nodes);
    let closing = model.body_id(&format!("s{}", N - 1)).unwrap();
    let (q, u) = model.body_coordinates(closing, &s.q, &s.u);
    let (a, b) = (&model.nodes[nodes[N - 1].0], &model.nodes[nodes[0].0]);
    assert_eq!(&q[..3], &s.q[a.q.clone()]);
    assert_eq!(&q[3..], &s.q[b.q.clone()]);
    assert_eq!(&u[3..], &s.u[b.u.clone()]);
}
